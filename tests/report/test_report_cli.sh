#!/usr/bin/env bash
# `infocus report` end to end: a report of the simulated camera with a lens, a stack without
# one, and refusals with their exit status (nothing written, an older report kept).
# Usage: test_report_cli.sh PATH_TO_INFOCUS
source "$(dirname "${BASH_SOURCE[0]}")/../cli/harness.sh"
sim='sim:scene=tilted,tilt=60,axis=x,distance=1m,focus=1m,focal=16mm,fnumber=1.4,size=640x360'

# With the lens: distances, the depth of field and the tilt; the file is named on stderr.
expect 0 'wrote .*one\.html \(1 frame, [0-9]+ KiB\)' -- report "$sim" -o "$tmp/one.html" \
	--focal 16mm --fnumber 1.4 --pixel-pitch 10.08um
if grep -q 'Depth of field</b>' "$tmp/one.html" && grep -q 'meets the plane of focus at' "$tmp/one.html" &&
	grep -q '1\.000 m from the lens (lens position of the frame)' "$tmp/one.html"; then ok; else bad "one.html lacks the optics"; fi

# Several frames without a lens: a table of frames, in pixels, saying what the lens would add.
expect 0 'wrote .*stack\.html \(3 frames' -- report "sim:size=320x180,pace=fast" --frames 3 --grid 4x3 \
	-o "$tmp/stack.html"
if grep -q '<h2>Frames</h2>' "$tmp/stack.html" && grep -q 'This report is in pixels' "$tmp/stack.html"; then
	ok
else
	bad "stack.html lacks the frame table or the note"
fi

# Refusals: usage errors exit 2 and write nothing; an older report survives a failed run.
cp "$tmp/one.html" "$tmp/keep.html"
expect 2 'output is required|--output' -- report "$sim"
expect 2 'folder .*nowhere does not exist' -- report "$sim" -o "$tmp/nowhere/r.html"
expect 2 'is a folder' -- report "$sim" -o "$tmp"
expect 2 'needs the pixel size' -- report "$sim" -o "$tmp/keep.html" --coc 0.03mm
expect 2 'grid' -- report "$sim" -o "$tmp/keep.html" --grid 0x3
expect 2 'inside the focal length' -- report "$sim" -o "$tmp/keep.html" --focal 50mm --fnumber 2 --focus 40mm
expect 1 'no-such-file' -- report "$tmp/no-such-file.y4m" -o "$tmp/keep.html"
if cmp -s "$tmp/one.html" "$tmp/keep.html" && [[ ! -e "$tmp/nowhere" ]]; then ok; else bad "a refused run touched a file"; fi
# Half a lens is most likely a slip: said, and the report stays in pixels.
expect 0 '--focal without --fnumber' -- report "$sim" -o "$tmp/half.html" --focal 16mm

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
