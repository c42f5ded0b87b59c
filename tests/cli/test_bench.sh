#!/usr/bin/env bash
# `infocus bench` as a user runs it: the JSON contract (DESIGN.md "bench --json"), every operator
# and the blur engine timed beside their baselines, and the blur engine's scalar and AVX2 kernels
# finding edges in the same regions. Timings are printed, never judged.
# Usage: test_bench.sh PATH_TO_INFOCUS
set -u
bin=${1:?path to infocus}
out=$("$bin" bench --json --seconds 0.01)
st=$?
[[ $st -eq 0 ]] || {
	echo "FAIL: infocus bench --json exited $st"
	exit 1
}
echo "$out"
python3 - "$out" <<'PY'
import json, sys
rows = [json.loads(line) for line in sys.argv[1].strip().split("\n")]
for r in rows:
    for k in ("what", "width", "height", "ms"):
        assert k in r, (k, r)
    assert r["ms"] > 0, r
    # A baseline comes with its speed-up, and the speed-up is the ratio of the two times.
    assert ("baseline_ms" in r) == ("speedup" in r), r
    if "baseline_ms" in r:
        assert r["baseline_ms"] > 0 and r.get("baseline"), r
        assert abs(r["speedup"] - r["baseline_ms"] / r["ms"]) <= 1e-9 * r["speedup"], r
full = [r for r in rows if r["what"] == "sharpness" and (r["width"], r["height"]) == (1920, 1080)]
ops = sorted(r["operator"] for r in full)
assert ops == sorted(["teng", "lapv", "lapm", "tenv", "brenner", "glvn", "dctr"]), ops
assert all("baseline_ms" in r for r in full)
blur = [r for r in rows if r["what"] == "blur"]
assert len(blur) == 1, blur
b = blur[0]
assert (b["width"], b["height"]) == (1920, 1080) and "baseline_ms" in b, b
# The bench frame is textured all over: every one of the 144 regions but a handful has an edge,
# and the scalar run (the same sums) agrees.
assert "kernel bug" not in b["note"], b["note"]
measured = int(b["note"].split(",")[1].split()[0])
assert 120 <= measured <= 144, b["note"]
PY
st=$?
[[ $st -eq 0 ]] && echo "ok" || echo "FAIL: bench JSON contract"
exit $st
