#!/usr/bin/env bash
# `infocus bench --images`: the blur engine timed on a user's own frames. The rows' contract, the
# regions measured agreeing with `infocus analyze` on the same frames and between the two rows,
# a damaged frame (skipped, reported, the rest timed, non-zero exit), and usage errors (exit 2).
# Timings are printed, never judged.
# Usage: test_bench_images.sh PATH_TO_INFOCUS SHARED_DATA_DIR
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

# The pcb stack's seven photographs (2048x1536, scaled to 1920x1080 for the timing).
out=$("$bin" bench --images "$data/focus-stack/pcb/pcb_*.jpg" --seconds 0.01 --json 2>"$tmp/err")
st=$?
[[ $st -eq 0 ]] && ok || bad "bench --images exited $st: $(cat "$tmp/err")"
echo "$out"
if python3 - "$out" "$data/focus-stack/pcb/pcb_*.jpg" <<'PY'; then ok; else bad "rows"; fi
import json, re, sys
rows = [json.loads(line) for line in sys.argv[1].strip().split("\n")]
source = sys.argv[2]
images = [r for r in rows if r["what"] == "blur_image"]
stream = [r for r in rows if r["what"] == "blur_image_stream"]
assert len(images) == 7 and len(stream) == 1 and len(rows) == 8, [r["what"] for r in rows]
assert [r["input_frame"] for r in images] == list(range(7)), images
for r in rows:
    assert r["input"] == source and (r["width"], r["height"]) == (1920, 1080), r
    assert r["ms"] > 0 and r["baseline_ms"] > 0 and r.get("baseline"), r
    assert abs(r["speedup"] - r["baseline_ms"] / r["ms"]) <= 1e-9 * r["speedup"], r
for r in images:
    # The scalar reference kernels give the same sums: the same regions measured.
    assert "kernel bug" not in r["note"], r["note"]
    assert "2048x1536 scaled to 1920x1080" in r["note"], r["note"]
    n = r["regions_with_edge"]
    assert 0 <= n <= 144 and f"{n} with an edge" in r["note"], r
# The stream row's full search reads the same frames, each held 10 frames, the first left out:
# its mean count of regions is the image rows' counts so weighted.
m = re.search(r"searching every frame: ([\d.]+)", stream[0]["note"])
assert m, stream[0]["note"]
counts = [r["regions_with_edge"] for r in images]
expected = (10 * sum(counts) - counts[0]) / (10 * len(counts) - 1)
assert abs(float(m.group(1)) - expected) <= 0.05, (m.group(1), expected)
t = re.search(r"90 % of frames within ([\d.]+) ms, slowest ([\d.]+) ms", stream[0]["note"])
assert t and stream[0]["ms"] <= float(t.group(1)) <= float(t.group(2)), stream[0]["note"]
PY

# On 1080p frames nothing is scaled, and the bench measures the regions `infocus analyze` does
# (the same 16x9 grid of the same frames): the simulated camera, focused short of its scene.
# Far enough short (a disc of about 20 px) that a tenth of the regions find no edge: at 0.3 m (9 px)
# all but one or two do, and whether those do turns on the last digits of a render.
sim="sim:size=1920x1080,focus=0.15m"
b=$("$bin" bench --images "$sim" --frames 2 --seconds 0.01 --json 2>"$tmp/err")
st=$?
[[ $st -eq 0 ]] && ok || bad "bench --images sim exited $st: $(cat "$tmp/err")"
a=$("$bin" analyze "$sim" --frames 2 2>"$tmp/err")
[[ $? -eq 0 ]] && ok || bad "analyze sim: $(cat "$tmp/err")"
if python3 - "$b" "$a" <<'PY'; then ok; else bad "bench and analyze disagree"; fi
import json, sys
bench = [json.loads(l) for l in sys.argv[1].strip().split("\n")]
bench = [r for r in bench if r["what"] == "blur_image"]
analyze = [json.loads(l) for l in sys.argv[2].strip().split("\n")]
assert len(bench) == 2 and len(analyze) == 2, (len(bench), len(analyze))
for r, f in zip(bench, analyze):
    assert "scaled" not in r["note"], r["note"]
    measured = sum(g["blur_width_px"] is not None for g in f["regions"])
    assert r["regions_with_edge"] == measured, (r["regions_with_edge"], measured)
    assert 0 < measured < 144, measured  # the frame is not trivially all edges or none
PY

# A damaged frame among good ones: skipped with a message, the others timed, exit non-zero.
src="$data/focus-stack/depthmap"
cp "$src/pcb_003.JPG" "$tmp/a.jpg"
head -c 200000 "$src/pcb_004.JPG" >"$tmp/b.jpg"
cp "$src/pcb_006.JPG" "$tmp/c.jpg"
out=$("$bin" bench --images "$tmp" --seconds 0.01 --json 2>"$tmp/err")
st=$?
[[ $st -ne 0 && $st -ne 2 ]] && ok || bad "damaged frame: exit $st"
grep -q "skipped a damaged frame" "$tmp/err" && grep -q "1 damaged frame(s) skipped, 2 timed" \
	"$tmp/err" && ok || bad "damaged frame message: $(cat "$tmp/err")"
[[ $(grep -c '"what":"blur_image"' <<<"$out") -eq 2 ]] && grep -q blur_image_stream <<<"$out" &&
	ok || bad "damaged frame: the good frames' rows: $out"

# Usage errors: exit 2 and a message naming the option.
expect_usage() {
	local want=$1
	shift
	"$bin" "$@" >/dev/null 2>"$tmp/err"
	local st=$?
	[[ $st -eq 2 ]] && grep -q -- "$want" "$tmp/err" && ok || bad "$* : exit $st, $(cat "$tmp/err")"
}
expect_usage "--accuracy and --images" bench --images "$tmp" --accuracy
expect_usage "--frames" bench --frames 3
expect_usage "not a frame count" bench --images "$tmp" --frames -1
# A source that does not exist is a runtime failure that names it.
"$bin" bench --images "$tmp/none.jpg" >/dev/null 2>"$tmp/err"
st=$?
[[ $st -ne 0 && $st -ne 2 ]] && grep -q "none.jpg" "$tmp/err" && ok ||
	bad "missing source: exit $st, $(cat "$tmp/err")"

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
