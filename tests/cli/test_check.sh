#!/usr/bin/env bash
# `infocus check` end to end: simulated frames in focus and 0.3 dpt off against a spec that
# separates them (exit 0 and 3), the JSON and the JUnit XML parsed, and bad specs (exit 2 naming
# the key and its line).
# Usage: test_check.sh PATH_TO_INFOCUS
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

# The edges scene at 1 m, the lens focused at 1 m (1 dpt) and at 1.3 dpt: a 0.3 dpt miss blurs
# the simulated camera's frame, rendered 2560 wide (2.52 µm pixels, f 4.74 mm at f/1.8), by a
# disc of A·z_s·0.3 dpt = 2.63 mm · 4.76 mm · 0.3 /m ≈ 3.8 µm, 1.5 px. In focus only the pixel
# and diffraction blur: MTF50 near the pixel's own 0.6 cy/px; the 1.5 px disc's MTF times the
# pixel's falls to 0.5 near 0.33 cy/px. The spec's 0.45 lies between them.
sharp="sim:scene=edges,distance=1m,focus=1dpt,size=2560x1440"
soft="sim:scene=edges,distance=1m,focus=1.3dpt,size=2560x1440"
cat >"$tmp/spec.json" <<'JSON'
{
  "grid": "8x6",
  "zones": {
    "centre": {"min_mtf50_cy_px": 0.45},
    "middle": {"min_mtf50_cy_px": 0.45}
  },
  "min_weighted_mtf50_cy_px": 0.45,
  "min_confident_regions": 10
}
JSON
"$bin" check "$sharp" --spec "$tmp/spec.json" --junit "$tmp/sharp.xml" >"$tmp/sharp.txt" 2>"$tmp/err"
st=$?
[[ $st -eq 0 ]] && ok || bad "in focus: exit $st: $(cat "$tmp/sharp.txt" "$tmp/err")"
grep -q "PASS" "$tmp/sharp.txt" && ok || bad "in focus: no PASS in $(cat "$tmp/sharp.txt")"
"$bin" check "$soft" --spec "$tmp/spec.json" --junit "$tmp/soft.xml" --json >"$tmp/soft.json" 2>"$tmp/err"
st=$?
[[ $st -eq 3 ]] && ok || bad "0.3 dpt off: exit $st: $(cat "$tmp/soft.json" "$tmp/err")"
if python3 - "$tmp/sharp.xml" "$tmp/soft.xml" "$tmp/soft.json" <<'PY'; then ok; else bad "JUnit and JSON"; fi
import json, sys
import xml.etree.ElementTree as ET
def suite(path):
    root = ET.parse(path).getroot()
    assert root.tag == "testsuites", root.tag
    s = root.find("testsuite")
    cases = s.findall("testcase")
    assert int(s.get("tests")) == len(cases) >= 4, (s.get("tests"), len(cases))
    failed = [c.get("name") for c in cases if c.find("failure") is not None]
    assert int(s.get("failures")) == len(failed)
    return [c.get("name") for c in cases], failed
names, failed = suite(sys.argv[1])
assert failed == [], failed
assert "centre_mtf50 (cy/px)" in names and "weighted_mtf50 (cy/px)" in names, names
names, failed = suite(sys.argv[2])
assert "centre_mtf50 (cy/px)" in failed, failed
o = json.load(open(sys.argv[3]))
assert o["pass"] == 0 and o["frames_failed"] == 1
c = {x["name"]: x for x in o["frames"][0]["criteria"]}
assert c["centre_mtf50"]["pass"] == 0 and c["centre_mtf50"]["measured"] < 0.45
assert c["centre_mtf50"]["unit"] == "cy/px" and c["centre_mtf50"]["kind"] == "min"
assert len(o["frames"][0]["regions"]) == 48
assert {r["zone"] for r in o["frames"][0]["regions"]} == {"centre", "middle", "corners"}
PY

# A black frame has no edge: a failure with its reason, never a pass.
python3 -c 'import sys; sys.stdout.buffer.write(b"P5\n320 240\n255\n" + bytes(320 * 240))' >"$tmp/black.pgm"
expect 3 'FAIL \(no region could be measured: the frame is too dark' -- check "$tmp/black.pgm" --spec "$tmp/spec.json"
# Bad specs: exit 2 naming the key and the line.
printf '{\n  "grid": "8x6",\n  "zones": {"centre": {"min_mtf50_cy_px": 0.2}},\n  "max_blurr_px": 3\n}\n' >"$tmp/unknown.json"
expect 2 'unknown.json line 4: "max_blurr_px" is not a spec key' -- check "$sharp" --spec "$tmp/unknown.json"
printf '{\n  "zones": {\n    "corners": {"min_mtf50_cy_px": 80}\n  }\n}\n' >"$tmp/unit.json"
expect 2 'line 3: "min_mtf50_cy_px" is 80, more than 1 cycle per pixel.*_lp_mm' -- check "$sharp" --spec "$tmp/unit.json"
printf '{\n  "max_blur_width_px": -2\n}\n' >"$tmp/sign.json"
expect 2 'line 2: "max_blur_width_px" is -2' -- check "$sharp" --spec "$tmp/sign.json"
printf '{\n  "zones": {"centre": {"min_mtf50_cy_px": 0.2}\n}\n' >"$tmp/json.json"
expect 2 'json.json line [34]: not valid JSON' -- check "$sharp" --spec "$tmp/json.json"
printf '{"zones": {"centre": {"min_mtf50_lp_mm": 60}}}\n' >"$tmp/lpmm.json"
expect 2 'min_mtf50_lp_mm needs the pixel pitch; give --pixel-pitch' -- check "$sharp" --spec "$tmp/lpmm.json"
printf '{"max_tilt_deg": 1}\n' >"$tmp/tilt.json"
expect 2 'needs the f-number.*--fnumber' -- check "$sharp" --spec "$tmp/tilt.json"
expect 2 'cannot read the spec' -- check "$sharp" --spec "$tmp/missing.json"
# lp/mm with the pitch: 2.52 µm pixels turn 0.45 cy/px into 178.6 lp/mm.
printf '{"zones": {"centre": {"min_mtf50_lp_mm": 178.6}}}\n' >"$tmp/lpmm.json"
expect 0 'centre_mtf50 .* lp/mm .*pass' -- check "$sharp" --spec "$tmp/lpmm.json" --pixel-pitch 2.52um
expect 3 'centre_mtf50 .* lp/mm .*FAIL' -- check "$soft" --spec "$tmp/lpmm.json" --pixel-pitch 2.52um

echo "check: $pass passed, $fail failed"
[[ $fail -eq 0 ]]
