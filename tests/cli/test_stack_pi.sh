#!/usr/bin/env bash
# `infocus stack` on the Raspberry Pi camera's focus sweep (../shared/data/focus-sweep-pi), its
# positions read from the file names (zNNN_Z±ZZZ.jpg: frame, machine Z in mm) into a CSV: every
# textured region must peak near Z = -50 mm, where the sweep's own analysis found best focus, and
# the nearly black last frames must read dark and not count. Tolerance: within 10 mm (10 frames)
# of -50.
# Usage: test_stack_pi.sh PATH_TO_INFOCUS SHARED_DATA_DIR
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
pi="$data/focus-sweep-pi"
[[ -f "$pi/z070_Z-050.jpg" ]] || { echo "SKIP: no test data at $pi"; exit 77; }

{
	echo frame,position,unit
	for f in "$pi"/z*_Z*.jpg; do
		name=$(basename "$f" .jpg)
		frame=$((10#${name:1:3}))
		z=${name#*_Z}
		echo "$frame,${z:0:1}$((10#${z:1})),mm" # "+20" is read as 20
	done
} >"$tmp/pi.csv"
# 4x4 regions of 100x100 px (they peak at Z = -57 to -42): on the 400x400 crops an 8x6 grid leaves
# 50x66 px regions, 4 of 48 of which peak beyond 10 mm of -50.
"$bin" stack "$pi/z*.jpg" --positions "$tmp/pi.csv" --grid 4x4 --json >"$tmp/pi.json" 2>"$tmp/err"
st=$?
[[ $st -eq 0 ]] || { echo "FAIL: stack exited $st: $(cat "$tmp/err")"; exit 1; }

python3 - "$tmp/pi.json" <<'PY'
import json, sys
o = json.load(open(sys.argv[1]))
assert len(o["frames"]) == 131 and o["position_unit"] == "mm"
assert o["frames"][70]["position"] == -50
regions = o["regions"]
# z130 (Z = -110) is nearly black but for a few hot pixels, which would score as the sharpest
# of the sweep: every one of its regions must read dark (null in the curves).
lit = [f"{r['col']},{r['row']}" for r in regions if r["curve"]["sharpness"][130] is not None]
if lit:
    print(f"FAIL: regions {' '.join(lit)} of the black frame z130_Z-110.jpg are not read dark")
    sys.exit(1)
ok = [r for r in regions if r["status"] == "ok"]
near = [r for r in ok if r["peak_position"] is not None and abs(r["peak_position"] + 50) <= 10]
for r in ok:
    if r not in near:
        print(f"region {r['col']},{r['row']} peaks at {r['peak_position']} mm")
a = o["agreement"]
print(f"pi: {len(near)} of {len(ok)} textured regions peak within 10 mm of Z = -50; "
      f"peak and vertex agree in {a['agree']} of {a['both']}")
sys.exit(0 if ok and len(near) == len(ok) else 1)
PY
