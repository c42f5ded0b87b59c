#!/usr/bin/env bash
# `infocus sweep` end to end on the simulated camera: the best focus of a plane at a known
# distance, the files of -o, the lens left at best focus, and refusals with their exit status.
# Usage: test_sweep_cli.sh PATH_TO_INFOCUS
source "$(dirname "${BASH_SOURCE[0]}")/../cli/harness.sh"
# An 8 mm f/2 lens at 640 px blurs 3.2 px a dioptre; the plane is at 1.25 m (0.8 dpt).
sim='sim:distance=1.25m,size=640x360,focal=8mm,fnumber=2,pace=fast'

# The summary as JSON: best focus within 0.05 dpt of 0.8, in focus at 1.25 m within 7 %.
out=$("$bin" sweep "$sim" --steps 11 --no-blur --json 2>"$tmp/err")
st=$?
if [[ $st -eq 0 ]] && python3 - "$out" <<'PY'; then ok; else bad "sweep --json: status $st: $out $(cat "$tmp/err")"; fi
import json, sys
j = json.loads(sys.argv[1])
b = j["best"]
assert j["unit"] == "dioptre" and b["unit"] == "dioptre", j
assert abs(b["dioptres"] - 0.8) <= 0.05, b
assert abs(b["in_focus_distance_m"] - 1.25) <= 0.07 * 1.25, b
assert not b["at_end"], b
assert len(j["steps"]) == 20 and len(j["regions"]) == 48, (len(j["steps"]), len(j["regions"]))
assert abs(j["lens_left_at"]["value"] - b["position"]) < 1e-9, j["lens_left_at"]
for r in j["regions"]:
    assert abs(r["best"]["dioptres"] - 0.8) <= 0.1, r
PY

# The table for people, and -o DIR with each frame as analyze writes it.
out=$("$bin" sweep "$sim" --steps 6 --refine 3 --grid 4x3 -o "$tmp/run" 2>"$tmp/err")
st=$?
if [[ $st -eq 0 ]] && grep -q '^best focus: 0\.[78][0-9]* dpt (in focus at 1\.[0-9]* m from the lens)' <<<"$out" &&
	grep -q 'the lens is left there' <<<"$out"; then ok; else bad "sweep table: status $st: $out"; fi
if [[ $(wc -l <"$tmp/run/sweep.jsonl") -eq 9 ]] && python3 - "$tmp/run" <<'PY'; then ok; else bad "sweep -o files"; fi
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1] + "/sweep.jsonl")]
assert all(l["lens_position"]["unit"] == "dioptre" and len(l["regions"]) == 12 for l in lines)
assert all(r["blur_width_px"] is None or r["blur_width_px"] >= 0 for l in lines for r in l["regions"])
s = json.load(open(sys.argv[1] + "/summary.json"))
assert [st["frame"] for st in s["steps"]] == [l["frame"] for l in lines], "steps and lines differ"
fits = [r["blur_fit"] for r in s["regions"]]
assert len(fits) == 12 and any(fits), fits
assert all(f is None or (f["slope_px_per_unit"] > 0 and f["points"] >= 4) for f in fits), fits
PY
# A second sweep into the same directory would overwrite the first: refused.
out=$("$bin" sweep "$sim" --steps 3 -o "$tmp/run" 2>&1)
st=$?
if [[ $st -eq 2 ]] && grep -q 'already holds a sweep' <<<"$out"; then ok; else bad "reused -o: $st $out"; fi

# A bare number is ambiguous for a lens in dioptres (metres or dioptres?).
expect 2 'give a unit|unit' -- sweep "$sim" --from 2
expect 2 'outside the lens range.*0 to 10 dioptre' -- sweep "$sim" --from 20dpt
expect 2 'starts and ends at' -- sweep "$sim" --from 1m --to 1m
expect 2 'steps' -- sweep "$sim" --steps 1
expect 2 'grid' -- sweep "$sim" --grid 0x3
expect 2 'metric|operator' -- sweep "$sim" --metric sharpest
# A source whose lens cannot move.
"$bin" record "sim:size=64x48,pace=fast" -o "$tmp/rec" --frames 2 >/dev/null 2>&1
expect 1 'has no focus control' -- sweep "$tmp/rec"
# Rising to the end of the sweep: said on stderr, the best stays the last position.
expect 0 'sweep.s last one.*wider range' -- sweep "$sim" --from inf --to 0.5dpt --steps 4 --refine 0 --no-blur

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
