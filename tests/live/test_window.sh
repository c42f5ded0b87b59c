#!/usr/bin/env bash
# The window view as a person sees it: `infocus live --ui window` on the simulated camera under
# Xvfb (1600×1000), screenshots of the X screen taken while it runs. The newest screenshot must
# show the picture (a grey texture: luma standard deviation ≥ 20 and ≥ 64 grey levels left of the
# panel), peaking (≥ 100 pixels of its tint, (255, 32, 32) ± 12), the heat map (≥ 300 pixels of
# its reddish, orange, yellow or green outlines) and the panel's text (≥ 300 bright pixels). The
# view exits 0 by itself after --seconds 5 (within 25 s of starting: the first frame of the sim can
# take seconds on a loaded machine). With no display it exits 2 naming --ui tui and --ui web. The
# q key (sent through XTest) closes it with exit 0.
# Usage: test_window.sh PATH_TO_INFOCUS HAVE_WINDOW(true|false) SCREENSHOT.png
set -u
bin=${1:?path to infocus}
shot=${3:?path of the screenshot to write}
if [[ ${2:-true} != true ]]; then
	echo "SKIP: this build has no window view (SDL2 or Dear ImGui not found)"
	exit 77
fi
for tool in Xvfb xwd convert python3; do
	if ! command -v "$tool" >/dev/null; then
		echo "SKIP: $tool is missing (apt install xvfb x11-apps imagemagick python3)"
		exit 77
	fi
done
tmp=$(mktemp -d)
xvfb_pid=
cleanup() {
	[[ -n $xvfb_pid ]] && kill "$xvfb_pid" 2>/dev/null
	rm -rf "$tmp"
}
trap cleanup EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*"; fail=$((fail + 1)); }
source_string='sim:focal=16mm,fnumber=1.4,distance=1m,focus=0.5m'

# No display: a clear message naming the other faces, exit 2, before the camera opens.
env -u DISPLAY -u WAYLAND_DISPLAY "$bin" live "$source_string" --ui window --seconds 1 \
	>"$tmp/nodisplay.out" 2>&1
rc=$?
[[ $rc -eq 2 ]] && ok || bad "without a display the exit status is $rc, not 2"
grep -q -- '--ui tui' "$tmp/nodisplay.out" && grep -q -- '--ui web' "$tmp/nodisplay.out" && ok ||
	bad "without a display the message names no other face: $(cat "$tmp/nodisplay.out")"

# Xvfb on a free display number it picks itself (-displayfd).
Xvfb -displayfd 3 -screen 0 1600x1000x24 -nolisten tcp 3>"$tmp/display" 2>"$tmp/xvfb.log" &
xvfb_pid=$!
for ((i = 0; i < 50; i++)); do
	[[ -s $tmp/display ]] && break
	sleep 0.1
done
if [[ ! -s $tmp/display ]]; then
	echo "SKIP: Xvfb did not start: $(tail -3 "$tmp/xvfb.log")"
	exit 77
fi
export DISPLAY=:$(head -1 "$tmp/display")
unset WAYLAND_DISPLAY

ms() { echo $(($(date +%s%N) / 1000000)); }
start=$(ms)
"$bin" live "$source_string" --ui window --seconds 5 --peaking percentile >"$tmp/live.out" 2>&1 &
live_pid=$!
# Screenshots every half second while the view runs; the newest that has the picture is kept.
n=0
while kill -0 "$live_pid" 2>/dev/null; do
	sleep 0.5
	if (($(ms) - start > 25000)); then
		bad "the view still runs after 25 s; killing it"
		kill "$live_pid"
		break
	fi
	kill -0 "$live_pid" 2>/dev/null || break
	xwd -root -display "$DISPLAY" 2>/dev/null | convert xwd:- -depth 8 rgb:"$tmp/shot$n.rgb" 2>/dev/null && n=$((n + 1))
done
wait "$live_pid"
rc=$?
end=$(ms)
[[ $rc -eq 0 ]] && ok || bad "the view exited $rc: $(cat "$tmp/live.out")"
(((end - start) >= 5000)) && ok || bad "the view returned after $((end - start)) ms, before 5 s"
echo "the view ran $((end - start)) ms for --seconds 5; $n screenshots"

# check RGB: prints what it found, exits 0 when the picture and its overlays are there.
check() {
	python3 - "$1" <<'PY'
import sys
px = open(sys.argv[1], 'rb').read()
w, h = 1600, 1000  # the Xvfb screen, 8-bit RGB
if len(px) != w * h * 3:
    sys.exit(f"{sys.argv[1]}: {len(px)} bytes, not a {w}x{h} RGB screenshot")
panel_x = w - 390
levels, lumas, tint, heat, text = set(), [], 0, 0, 0
for y in range(0, h, 2):
    row = px[y * w * 3:(y + 1) * w * 3]
    for x in range(0, w, 2):
        r, g, b = row[3 * x], row[3 * x + 1], row[3 * x + 2]
        if x >= panel_x:
            text += r > 200 and g > 200 and b > 200
            continue
        if abs(r - g) < 10 and abs(g - b) < 10:
            l = (r + g + b) // 3
            levels.add(l)
            lumas.append(l)
        if abs(r - 255) <= 12 and abs(g - 32) <= 12 and abs(b - 32) <= 12:
            tint += 1
        elif r - b > 60 or g - b > 60:
            heat += 1
n = max(len(lumas), 1)
mean = sum(lumas) / n
sd = (sum((l - mean) ** 2 for l in lumas) / n) ** 0.5
# Counts are of every other pixel in each direction: a quarter of the screen's.
print(f"picture: {len(lumas)} grey samples, sd {sd:.1f}, {len(levels)} levels; "
      f"peaking {tint}, heat map {heat}, panel text {text} samples")
sys.exit(0 if sd >= 20 and len(levels) >= 64 and tint >= 25 and heat >= 75 and text >= 75 else 1)
PY
}
found=
for ((i = n - 1; i >= 0; i--)); do
	if check "$tmp/shot$i.rgb"; then
		found=$i
		break
	fi
done
if [[ -n $found ]]; then
	ok
	convert -size 1600x1000 -depth 8 "rgb:$tmp/shot$found.rgb" "png:$shot"
	echo "screenshot $((found + 1)) of $n: $shot"
else
	bad "no screenshot shows the picture with peaking, the heat map and the panel"
	((n > 0)) && convert -size 1600x1000 -depth 8 "rgb:$tmp/shot$((n - 1)).rgb" "png:$shot" && echo "the last screenshot: $shot"
fi

# q quits: the key pressed through XTest (libXtst, by ctypes) once the window is up.
xtest_key() {
	python3 - "$1" <<'PY'
import ctypes, sys, time
x11, xt = ctypes.CDLL('libX11.so.6'), ctypes.CDLL('libXtst.so.6')
x11.XOpenDisplay.restype = ctypes.c_void_p
d = ctypes.c_void_p(x11.XOpenDisplay(None))
code = x11.XKeysymToKeycode(d, ctypes.c_ulong(x11.XStringToKeysym(sys.argv[1].encode())))
for down in (1, 0):
    xt.XTestFakeKeyEvent(d, code, down, 0)
    x11.XFlush(d)
    time.sleep(0.1)
PY
}
if python3 -c "import ctypes; ctypes.CDLL('libXtst.so.6')" 2>/dev/null; then
	"$bin" live "$source_string" --ui window --seconds 60 >"$tmp/quit.out" 2>&1 &
	live_pid=$!
	sleep 4
	xtest_key q
	for ((i = 0; i < 100; i++)); do
		kill -0 "$live_pid" 2>/dev/null || break
		sleep 0.2
	done
	if kill -0 "$live_pid" 2>/dev/null; then
		bad "q did not close the window within 20 s"
		kill "$live_pid"
		wait "$live_pid"
	else
		wait "$live_pid"
		rc=$?
		[[ $rc -eq 0 ]] && ok || bad "after q the view exited $rc: $(cat "$tmp/quit.out")"
	fi
else
	echo "note: libXtst is missing, the q key is not tried"
fi

echo "$pass passed, $fail failed"
((fail == 0))
