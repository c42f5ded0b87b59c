#!/usr/bin/env bash
# `infocus analyze` end to end: the JSONL contract, CSV and table output, a damaged image in a
# sequence (skipped, reported, the rest analysed, non-zero exit), and usage errors (exit 2).
# Usage: test_analyze.sh PATH_TO_INFOCUS SHARED_DATA_DIR
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

# Three frames in name order: two real photographs around a truncated copy of one.
src="$data/focus-stack/depthmap"
cp "$src/pcb_000.JPG" "$tmp/a.jpg"
head -c 200000 "$src/pcb_004.JPG" >"$tmp/b.jpg"
cp "$src/pcb_009.JPG" "$tmp/c.jpg"
mkdir "$tmp/good" && cp "$src/pcb_003.JPG" "$src/pcb_006.JPG" "$tmp/good/"

out=$("$bin" analyze "$tmp/good" --grid 4x3 2>"$tmp/err")
st=$?
[[ $st -eq 0 ]] && ok || bad "analyze good dir exited $st: $(cat "$tmp/err")"
# Every contract field, on every frame and region (docs/design.md, analyze JSONL).
if python3 - "$out" <<'PY'; then ok; else bad "JSONL contract"; fi
import json, sys
lines = sys.argv[1].strip().split("\n")
assert len(lines) == 2, len(lines)
for i, line in enumerate(lines):
    o = json.loads(line)
    for k in ("frame", "timestamp_ns", "lens_position", "width", "height", "regions"):
        assert k in o, k
    assert o["frame"] == i and o["width"] == 2048 and o["height"] == 1536
    assert len(o["regions"]) == 12
    for r in o["regions"]:
        for k in ("col", "row", "x", "y", "w", "h", "sharpness", "edge_width_px",
                  "blur_sigma_px", "blur_width_px", "confidence"):
            assert k in r, k
        assert 0 <= r["confidence"] <= 1
        assert (r["blur_width_px"] is None) == (r["confidence"] == 0)
    assert sum(r["w"] * r["h"] for r in o["regions"]) == 2048 * 1536
PY

csv=$("$bin" analyze "$tmp/good" --grid 2x2 --format csv --no-blur)
[[ $(head -1 <<<"$csv") == frame,timestamp_ns,lens_value,lens_unit,width,height,col,row,x,y,w,h,sharpness,* ]] && ok || bad "csv header"
[[ $(wc -l <<<"$csv") -eq 9 ]] && ok || bad "csv rows: $(wc -l <<<"$csv")"

"$bin" analyze "$tmp/good" --grid 3x2 --format table --no-blur --frames 1 | grep -q "sharpness (teng" && ok || bad "table"

# The table's blur grid: each region's width as the JSONL gives it to 0.1 px, in parentheses where
# its confidence is under 0.25 (kLowBlurConfidence), "-" where it has none. The simulated steps
# scene has regions of both kinds.
"$bin" analyze sim:scene=steps --frames 1 --grid 8x4 --format table >"$tmp/steps.txt" &&
	"$bin" analyze sim:scene=steps --frames 1 --grid 8x4 >"$tmp/steps.jsonl" && ok ||
	bad "analyze steps table and JSONL"
if python3 - "$tmp/steps.txt" "$tmp/steps.jsonl" <<'PY'; then ok; else bad "table blur cells"; fi
import json, sys
lines = open(sys.argv[1]).read().splitlines()
assert "(w) confidence under 0.25" in lines[1], lines[1]
regions = json.loads(open(sys.argv[2]).readline())["regions"]
low = high = 0
for r in regions:
    cell = lines[2 + r["row"]].split()[8 + r["col"]]
    w, c = r["blur_width_px"], r["confidence"]
    if w is None:
        assert cell == "-", (r, cell)
    elif c < 0.25:
        assert cell == "(%.1f)" % w, (r, cell)
        low += 1
    else:
        assert cell == "%.1f" % w, (r, cell)
        high += 1
assert low > 0 and high > 0, (low, high)
PY

# A damaged frame: skipped and named, the intact ones still written, exit 1.
"$bin" analyze "$tmp" --grid 2x2 --no-blur -o "$tmp/out.jsonl" 2>"$tmp/err"
st=$?
[[ $st -eq 1 ]] && ok || bad "damaged sequence exited $st"
[[ $(wc -l <"$tmp/out.jsonl") -eq 2 ]] && ok || bad "intact frames written: $(wc -l <"$tmp/out.jsonl")"
grep -q "b.jpg" "$tmp/err" && grep -q "damaged" "$tmp/err" && ok || bad "damage report: $(cat "$tmp/err")"

# A tracked stream (--blur-search N) measures each frame's edges again where the first frame's
# search found them and searches N regions afresh: on a repeated frame every blur field equals
# the full search's, frame after frame.
mkdir "$tmp/same" && for n in 1 2 3; do cp "$src/pcb_003.JPG" "$tmp/same/f$n.jpg"; done
"$bin" analyze "$tmp/same" --grid 4x3 --blur-search all >"$tmp/all.jsonl" &&
	"$bin" analyze "$tmp/same" --grid 4x3 --blur-search 2 >"$tmp/tracked.jsonl" && ok ||
	bad "analyze --blur-search"
if python3 - "$tmp/all.jsonl" "$tmp/tracked.jsonl" <<'PY'; then ok; else bad "tracked frames differ from searched ones"; fi
import json, sys
a = [json.loads(l) for l in open(sys.argv[1])]
t = [json.loads(l) for l in open(sys.argv[2])]
assert len(a) == len(t) == 3
measured = 0
for fa, ft in zip(a, t):
    for ra, rt in zip(fa["regions"], ft["regions"]):
        for k in ("edge_width_px", "blur_sigma_px", "blur_width_px", "confidence"):
            assert ra[k] == rt[k], (fa["frame"], ra["col"], ra["row"], k, ra[k], rt[k])
        measured += ra["blur_width_px"] is not None
assert measured >= 15, measured  # most regions have an edge: the comparison is not empty
PY

# Usage errors exit 2 and say what to type; a missing file exits 1 and names it.
expect_usage() {
	local pat=$1
	shift
	local e
	e=$("$bin" analyze "$@" 2>&1 >/dev/null)
	local s=$?
	[[ $s -eq 2 ]] && grep -qE -- "$pat" <<<"$e" && ok || bad "analyze $* -> $s: $e"
}
expect_usage "e.g. 16x9" "$tmp/good" --grid 16by9
# A grid past the limit names the limit, however far past it (a 2000x2000 grid once only heard
# "give columns x rows").
expect_usage "use 1x1 to 256x256" "$tmp/good" --grid 257x1
expect_usage "use 1x1 to 256x256" "$tmp/good" --grid 2000x2000
expect_usage "lapv" "$tmp/good" --metric sharpest
expect_usage "jsonl, csv or table" "$tmp/good" --format xml
expect_usage "x,y,w,h" "$tmp/good" --roi 1,2,3
expect_usage "all, auto or a number of regions" "$tmp/good" --blur-search some
expect_usage "all, auto or a number of regions" "$tmp/good" --blur-search 0
expect_usage "drop one of them" "$tmp/good" --no-blur --blur-search 4
expect_usage "use linear, srgb, rec709 .* or auto" "$tmp/good" --transfer gamma
# --transfer auto on a source that names no transfer function: measured as it is, and said why.
{ printf 'YUV4MPEG2 W64 H48 F25:1 Ip A1:1 Cmono\nFRAME\n'; head -c 3072 /dev/urandom; } >"$tmp/plain.y4m"
e=$("$bin" analyze "$tmp/plain.y4m" --grid 1x1 --transfer auto 2>&1 >/dev/null)
s=$?
[[ $s -eq 0 ]] && grep -q "transfer auto: a Y4M header names no transfer function; grey levels measured as they are" <<<"$e" &&
	ok || bad "transfer auto on y4m -> $s: $e"
# A negative frame count is refused, not wrapped to 2^64 − 1 (it ran without end on a camera).
expect_usage "not a frame count" "$tmp/good" --frames -1
# A region whose far edge passes INT_MAX: outside the frame, not wrapped around (it crashed).
expect_usage "reaches outside the 2048x1536 frame" "$tmp/good" --roi 2147483640,0,100,100
expect_usage "reaches outside the 2048x1536 frame" "$tmp/good" --roi 10,10,2147483640,100
e=$("$bin" analyze "$tmp/nothing-here.jpg" 2>&1)
s=$?
[[ $s -eq 1 ]] && grep -q "nothing-here.jpg" <<<"$e" && ok || bad "missing file -> $s: $e"

# A disk that fills up mid-frame (a file size limit of 40 kB stands in for it; the signal it
# raises is ignored, as a full disk raises none): exit 1, the frame and the file named, and the
# file cut back to the frames written whole, so that every line of it reads.
e=$( (trap '' XFSZ; ulimit -f 40; "$bin" analyze "sim:size=320x240,pace=fast" --frames 20 \
	--grid 16x9 --no-blur -o "$tmp/full.jsonl") 2>&1)
s=$?
[[ $s -eq 1 ]] && grep -q "writing frame [1-9] to $tmp/full.jsonl failed" <<<"$e" &&
	grep -q "frame(s) before it are complete there" <<<"$e" && ok || bad "full disk -> $s: $e"
if python3 - "$tmp/full.jsonl" <<'PY'; then ok; else bad "full disk: torn last line kept"; fi
import json, sys
lines = open(sys.argv[1]).read().split("\n")
assert lines[-1] == "", "the file does not end with a whole line"
assert len(lines) > 1
for line in lines[:-1]:
    json.loads(line)
PY
# Standard output that takes nothing (/dev/full): the same error, not a crash.
e=$("$bin" analyze "sim:size=64x48,pace=fast" --frames 2 --grid 2x2 --no-blur 2>&1 >/dev/full)
s=$?
[[ $s -eq 1 ]] && grep -q "writing frame 0 to standard output failed" <<<"$e" && ok ||
	bad "/dev/full -> $s: $e"

echo "analyze: $pass passed, $fail failed"
[[ $fail -eq 0 ]]
