#!/usr/bin/env bash
# The blur engine's accuracy tables as a user runs them (`infocus bench --accuracy`): they must run
# to the end; every edge row inside the target ranges (disc 2–60 px ±5 %, Gaussian σ 0.7–20 px
# ±3 %, edge angles 0–45°, noise 0–2 %) must meet its tolerance; the 200 random slanted squares
# must each print a line and the summary.
# Usage: test_accuracy.sh PATH_TO_INFOCUS
set -u
bin=${1:?path to infocus}
out=$("$bin" bench --accuracy 2>&1)
st=$?
rows=$(grep -cE '^(disc|gauss) ' <<<"$out")
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
grep -qE "^squares: targets" <<<"$out" || fail=1
exit $fail
