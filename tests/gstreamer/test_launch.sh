#!/usr/bin/env bash
# focusmeter from the command line: gst-inspect-1.0 lists every property with its range or
# choices, gst-launch-1.0 -m posts one `infocus` message per frame (skip-frames=false), the
# newest-frame rule accounts for every frame (analysed + skipped = offered), and out-of-range
# properties are refused with a warning. Skips (77) without the GStreamer tools.
# Usage: test_launch.sh PLUGIN_DIR
set -u
plugin_dir=$1
for tool in gst-inspect-1.0 gst-launch-1.0; do
    command -v "$tool" >/dev/null || { echo "SKIP: $tool not installed (gstreamer1.0-tools)"; exit 77; }
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export GST_PLUGIN_PATH=$plugin_dir
export GST_REGISTRY=$tmp/registry.bin  # the build tree's plugin, never a stale cache
gst-inspect-1.0 videotestsrc >/dev/null 2>&1 || { echo "SKIP: videotestsrc missing (gstreamer1.0-plugins-base)"; exit 77; }
fails=0
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }

# ---- gst-inspect-1.0: every property, its type and its range as docs/gstreamer.md gives them
gst-inspect-1.0 focusmeter >"$tmp/inspect" 2>&1 || bad "gst-inspect-1.0 focusmeter failed: $(cat "$tmp/inspect")"
grep -q 'Filter/Analyzer/Video' "$tmp/inspect" || bad "klass missing"
for caps in GRAY8 GRAY16_LE I420 NV12 YUY2 UYVY RGB BGR RGBx BGRx; do
    grep -Eq "(\{ |, )\(string\)$caps(,| \})" "$tmp/inspect" || bad "caps lack $caps"
done
# name, then a pattern its block must hold (ranges in the units the property names)
expect=(
    'grid|String.*Default: "16x9"'
    'roi|String.*Default: ""'
    'metric|Enum "GstFocusMeterMetric" Default: 2, "teng"'
    'blur|Boolean.*Default: true'
    'blur-search|Integer. Range: 0 - 65536 Default: 16'
    'transfer|Enum "GstFocusMeterTransfer" Default: 0, "linear"'
    'focal-length|Double. Range: 0 - 10000 Default: 0'
    'f-number|Double. Range: 0 - 1024 Default: 0'
    'pixel-pitch|Double. Range: 0 - 1000 Default: 0'
    'focus-distance|Double. Range: 0 - inf Default: 0'
    'interval|Unsigned Integer64. Range: 0 - 18446744073709551615 Default: 100000000'
    'post-messages|Boolean.*Default: true'
    'attach-meta|Boolean.*Default: false'
    'skip-frames|Boolean.*Default: true'
)
for e in "${expect[@]}"; do
    name=${e%%|*}
    want=${e#*|}
    # A property's block: its line and the indented lines up to the next property.
    block=$(awk -v p="$name" '
        $1 == p && $2 == ":" { on = 1; print; next }
        on && /^  [a-z-]+ +:/ { exit }
        on { print }' "$tmp/inspect" | tr -s ' \n' ' ')
    [[ -n $block ]] || { bad "property $name not listed"; continue; }
    grep -Eq "$want" <<<"$block" || bad "property $name: want /$want/ in: $block"
done
for m in lapv lapm teng tenv brenner glvn dctr; do
    grep -Eq "\([0-9]+\): $m +- " "$tmp/inspect" || bad "metric $m not listed"
done
for t in linear srgb rec709; do
    grep -Eq "\([0-9]+\): $t +- " "$tmp/inspect" || bad "transfer $t not listed"
done

# ---- gst-launch-1.0 -m: one message per frame, frames 0..59 in order, the fields present
gst-launch-1.0 -m videotestsrc num-buffers=60 ! focusmeter interval=0 skip-frames=false ! fakesink \
    >"$tmp/launch" 2>&1 || bad "gst-launch-1.0 failed: $(tail -5 "$tmp/launch")"
n=$(grep -c 'element): infocus, ' "$tmp/launch")
[[ $n -eq 60 ]] || bad "skip-frames=false posted $n messages for 60 frames"
frames=$(grep -o 'element): infocus, .*' "$tmp/launch" | grep -o ' frame=(guint64)[0-9]*' |
    grep -o '[0-9]*$' | tr '\n' ' ')
[[ $frames == "$(seq -s ' ' 0 59) " ]] || bad "frames out of order: $frames"
first=$(grep -m1 'element): infocus, ' "$tmp/launch")
for f in timestamp stream-time running-time duration frame skipped score percent-of-peak cols \
    rows sharpness blur-width-px confidence status; do
    grep -q " $f=" <<<"$first" || bad "message lacks $f: $first"
done
grep -q ' cols=(int)16, rows=(int)9,' <<<"$first" || bad "default grid is not 16x9: $first"
grep -q 'in-focus-distance' <<<"$first" && bad "in-focus-distance without a lens"
# The 2nd frame of videotestsrc at 30/1 starts at 1/30 s and lasts as long.
second=$(grep 'element): infocus, ' "$tmp/launch" | sed -n 2p)
grep -q 'timestamp=(guint64)33333333,' <<<"$second" || bad "2nd timestamp: $second"
grep -q 'duration=(guint64)33333333,' <<<"$second" || bad "2nd duration: $second"
grep -q 'Got EOS from element' "$tmp/launch" || bad "no EOS"

# The default rule: a stream faster than the analysis is skipped, never queued. Every frame is
# either analysed or counted as skipped, and the last one is analysed.
gst-launch-1.0 -m videotestsrc num-buffers=60 ! video/x-raw,width=1280,height=720 ! \
    focusmeter interval=0 blur-search=0 ! fakesink >"$tmp/skip" 2>&1 || bad "skipping run failed"
n=$(grep -c 'element): infocus, ' "$tmp/skip")
last=$(grep 'element): infocus, ' "$tmp/skip" | tail -1)
skipped=$(grep -o ' skipped=(guint64)[0-9]*' <<<"$last" | grep -o '[0-9]*$')
lastframe=$(grep -o ' frame=(guint64)[0-9]*' <<<"$last" | grep -o '[0-9]*$')
echo "default rule: $n analysed, ${skipped:-?} skipped of 60"
[[ $((n + ${skipped:-1000})) -eq 60 ]] || bad "analysed $n + skipped $skipped != 60"
[[ ${lastframe:-} == 59 ]] || bad "last analysed frame is ${lastframe:-none}, not 59"

# interval, 100 ms by default: at 30 fps every 3rd frame (by timestamps), none skipped
gst-launch-1.0 -m videotestsrc num-buffers=30 ! focusmeter skip-frames=false ! \
    fakesink >"$tmp/interval" 2>&1 || bad "interval run failed"
frames=$(grep -o 'element): infocus, .*' "$tmp/interval" | grep -o ' frame=(guint64)[0-9]*' |
    grep -o '[0-9]*$' | tr '\n' ' ')
[[ $frames == "0 3 6 9 12 15 18 21 24 27 " ]] || bad "interval=100 ms analysed frames $frames"

# post-messages=false: none
gst-launch-1.0 -m videotestsrc num-buffers=10 ! focusmeter post-messages=false ! fakesink \
    >"$tmp/quiet" 2>&1 || bad "post-messages=false run failed"
[[ $(grep -c 'element): infocus, ' "$tmp/quiet") -eq 0 ]] || bad "post-messages=false posted"

# Out-of-range values: refused with a warning naming them, the default kept.
gst-launch-1.0 -m videotestsrc num-buffers=2 ! focusmeter interval=0 grid=0x3 blur-search=70000 \
    f-number=-2 ! fakesink >"$tmp/range" 2>&1 || bad "out-of-range run failed"
grep -q "grid '0x3' refused" "$tmp/range" || bad "grid=0x3 not refused: $(cat "$tmp/range")"
grep -q "blur-search" "$tmp/range" || bad "blur-search=70000 not warned"
grep -q "f-number" "$tmp/range" || bad "f-number=-2 not warned"
grep -q ' cols=(int)16, rows=(int)9,' "$tmp/range" || bad "old grid not kept"

if [[ $fails -ne 0 ]]; then
    echo "$fails check(s) failed"
    exit 1
fi
echo "all focusmeter launch checks passed"
