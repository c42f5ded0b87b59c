#!/usr/bin/env bash
# The blur engine's accuracy table as a user runs it (`infocus bench --accuracy`): it must run to
# the end and every row inside the target ranges (disc 2–60 px ±5 %, Gaussian σ 0.7–20 px ±3 %,
# edge angles 0–45°, noise 0–2 %) must meet its tolerance.
# Usage: test_accuracy.sh PATH_TO_INFOCUS
set -u
bin=${1:?path to infocus}
out=$("$bin" bench --accuracy 2>&1)
st=$?
rows=$(grep -cE '^(disc|gauss) ' <<<"$out")
last=$(tail -n 1 <<<"$out")
echo "$out" | grep -E 'MISS' || true
echo "accuracy: exit $st, $rows rows; $last"
# 14 disc diameters (1–60 px) and 11 Gaussian σ (0.5–20 px), each at three noise levels.
[[ $st -eq 0 && $rows -eq 75 && $last == "0 row(s) inside the target ranges missed their tolerance" ]]
