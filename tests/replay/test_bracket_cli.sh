#!/usr/bin/env bash
# `infocus live` on focus brackets end to end: the Raspberry Pi camera's sweep
# (../shared/data/focus-sweep-pi, Z in mm from the names zNNN_Z±ZZZ.jpg) opened as a lens runs in
# the JSON face with a focus control over the sweep's range, and bad positions files stop it with
# exit 2 and a message naming the file and the line.
# Usage: test_bracket_cli.sh PATH_TO_INFOCUS SHARED_DATA_DIR
source "$(dirname "${BASH_SOURCE[0]}")/../cli/harness.sh"
pi="$data/focus-sweep-pi"
[[ -f "$pi/z070_Z-050.jpg" ]] || { echo "SKIP: no test data at $pi"; exit 77; }

{
	echo frame,position,unit
	for f in "$pi"/z*_Z*.jpg; do
		name=$(basename "$f" .jpg)
		z=${name#*_Z}
		echo "$((10#${name:1:3})),${z:0:1}$((10#${z:1})),mm"
	done
} >"$tmp/pi.csv"

out=$("$bin" live "$pi,bracket=$tmp/pi.csv,pace=fast" --ui json --frames 30 2>"$tmp/err")
st=$?
[[ $st -eq 0 ]] && ok || bad "live on the bracket exited $st: $(cat "$tmp/err")"
if python3 - "$out" <<'PY'; then ok; else bad "live's JSON on the bracket: $out"; fi
import json, sys
rows = [json.loads(l) for l in sys.argv[1].strip().split("\n")]
last = rows[-1]
assert last["has_focus_control"], last
assert last["focus_range"]["min"] == -110 and last["focus_range"]["max"] == 20, last["focus_range"]
assert last["focus_range"]["unit"] == "mm" and last["lens_position"]["value"] == 20, last
assert last["frame"] >= 29, last["frame"]
PY
# Starting elsewhere: the frame at Z = -100.
out=$("$bin" live "$pi/z*.jpg,bracket=$tmp/pi.csv,pace=fast,focus=-100" --ui json --frames 3 2>&1)
grep -q '"lens_position":{"value":-100.0' <<<"$out" && ok || bad "focus=-100: $(head -c 300 <<<"$out")"

# Bad positions files: exit 2 (1 for a missing file), naming the file and the line.
sed '52s/.*/50,-29,mm/' "$tmp/pi.csv" >"$tmp/order.csv"
sed '20s/.*/18;x/' "$tmp/pi.csv" >"$tmp/malformed.csv"
head -n 100 "$tmp/pi.csv" >"$tmp/short.csv"
expect 2 "order.csv line 52: .*must run one way" -- live "$pi,bracket=$tmp/order.csv" --frames 1
expect 2 "malformed.csv line 20: " -- live "$pi,bracket=$tmp/malformed.csv" --frames 1
expect 2 "short.csv gives positions for 99 frames, but the bracket has 131" -- \
	live "$pi,bracket=$tmp/short.csv" --frames 1
expect 1 "none.csv" -- live "$pi,bracket=$tmp/none.csv" --frames 1
expect 2 "no lens position" -- live "$pi,bracket=recorded" --frames 1
expect 2 "unknown option 'loop'" -- live "$pi,bracket=$tmp/pi.csv,loop=1" --frames 1

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
