#!/usr/bin/env bash
# The blur engine's accuracy tables as a user runs them (`infocus bench --accuracy`): they must run
# to the end; every edge row inside the target ranges (disc 2–60 px ±5 %, Gaussian σ 0.7–20 px
# ±3 %, edge angles 0–45°, noise 0–2 %) must meet its tolerance; and on the 200 random slanted
# squares at least 95 % must read with confidence ≥ 0.25 and those must read d or σ with p95 ≤ 2 %
# and worst ≤ 5 %; the near-axis cases and the wide discs alike must meet the share and the worst
# (a subset of 16 cases has its worst case for a 95th percentile).
# Usage: test_accuracy.sh PATH_TO_INFOCUS
set -u
bin=${1:?path to infocus}
out=$("$bin" bench --accuracy 2>&1)
st=$?
# The blur table's rows: those before the MTF50 table, whose rows start alike.
rows=$(awk '/^MTF50 accuracy/ { exit } /^(disc|gauss) / { n++ } END { print n + 0 }' <<<"$out")
edges=$(grep -E 'row\(s\) inside the target ranges' <<<"$out")
squares=$(grep -cE '^ *[0-9]+ (disc d|gauss s) ' <<<"$out")
echo "$out" | grep -E 'MISS' || true
echo "accuracy: exit $st, $rows edge rows; $edges; $squares square cases"
grep -E '^squares' <<<"$out"
fail=0
# 14 disc diameters (1–60 px) and 11 Gaussian σ (0.5–20 px), each at three noise levels.
[[ $st -eq 0 && $rows -eq 75 && $edges == "0 row(s) inside the target ranges missed their tolerance" ]] ||
    fail=1
[[ $squares -eq 200 ]] || fail=1
# Each summary line: "squares NAME N cases, confidence >= 0.25: K ( S %), error p95 P %, worst W %".
for set in all near-axis wide-disc; do
    line=$(grep -E "^squares $set " <<<"$out")
    read -r share p95 worst < <(sed -E 's/.*\( *([0-9.]+) %\), error p95 +([0-9.]+) %, worst +([0-9.]+) %.*/\1 \2 \3/' <<<"$line")
    maxp95=2
    [[ $set == all ]] || maxp95=100
    if [[ -z $line ]] || ! awk -v s="$share" -v p="$p95" -v w="$worst" -v m="$maxp95" \
        'BEGIN { exit !(s >= 95 && p <= m && w <= 5) }'; then
        echo "squares $set: confident ${share:-?} % (>= 95), p95 ${p95:-?} % (<= $maxp95), worst ${worst:-?} % (<= 5): missed"
        fail=1
    fi
done
exit $fail
