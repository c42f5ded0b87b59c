#!/usr/bin/env bash
# `infocus record` end to end: sim: → recording → re-record is bit-exact; a recording killed with
# SIGKILL mid-stream replays every completed frame; SIGINT stops cleanly; bad input fails clearly.
# Usage: test_record.sh PATH_TO_INFOCUS
set -u
bin=${1:?path to infocus}
work=$(mktemp -d /tmp/infocus-test-record-XXXXXX)
trap 'rm -rf "$work"' EXIT
pass=0 fail=0
check() { # check DESCRIPTION CONDITION...
	local what=$1
	shift
	if "$@"; then pass=$((pass + 1)); else
		echo "FAIL: $what"
		fail=$((fail + 1))
	fi
}
size() { stat -c %s "$1"; }
# One GREY 320x240 record: 128-byte header + 76800 bytes of pixels (replay/recording_format.h).
rec=$((128 + 320 * 240))

# 1. Record and replay: re-recording a recording reproduces its frame file byte for byte.
out=$("$bin" record sim:scene=tilted,size=320x240,pace=fast,noise=0.01 -o "$work/a" --frames 12 2>&1)
check "record sim: exits 0 ($out)" test $? -eq 0
check "summary names 12 frames ($out)" grep -q "recorded 12 frames" <<<"$out"
check "frame file holds 12 records" test "$(size "$work/a/frames.bin")" -eq $((12 * rec))
"$bin" record "$work/a" -o "$work/b" >/dev/null 2>&1
check "re-record exits 0" test $? -eq 0
check "re-recorded frames are bit-exact" cmp -s "$work/a/frames.bin" "$work/b/frames.bin"

# 2. SIGKILL mid-stream: every completed frame replays, the torn one is reported.
"$bin" record sim:size=320x240,fps=200 -o "$work/k" --frames 100000 >/dev/null 2>&1 &
pid=$!
for _ in $(seq 1 400); do
	[ -f "$work/k/frames.bin" ] && [ "$(size "$work/k/frames.bin")" -gt $((20 * rec)) ] && break
	sleep 0.05
done
kill -KILL $pid
wait $pid 2>/dev/null
total=$(size "$work/k/frames.bin")
complete=$((total / rec))
check "killed recording wrote frames ($complete)" test "$complete" -ge 20
out=$("$bin" record "$work/k" -o "$work/k2" 2>&1)
st=$?
if [ $((total % rec)) -ne 0 ]; then
	check "torn last frame is reported, exit 1 ($st: $out)" test $st -eq 1
	check "report names the frame file" grep -q "frames.bin: frame $complete .*incomplete" <<<"$out"
else
	check "kill fell between frames: clean replay ($st)" test $st -eq 0
fi
check "all $complete complete frames replayed" test "$(size "$work/k2/frames.bin")" -eq $((complete * rec))
check "replayed frames equal the recorded ones" cmp -s -n $((complete * rec)) "$work/k/frames.bin" "$work/k2/frames.bin"

# 3. SIGINT finishes the recording cleanly with a summary.
# --seconds bounds the run should the signal be lost; the signal is sent once a frame is written,
# i.e. after the handler is installed (a background job starts with SIGINT ignored).
"$bin" record sim:size=320x240,fps=100 -o "$work/i" --seconds 30 >"$work/i.out" 2>&1 &
pid=$!
for _ in $(seq 1 200); do
	[ -f "$work/i/frames.bin" ] && [ "$(size "$work/i/frames.bin")" -ge $rec ] && break
	sleep 0.05
done
kill -INT $pid
wait $pid
st=$?
check "SIGINT exits 0 ($st)" test $st -eq 0
check "SIGINT summary, before the 30 s bound" grep -q "stopped by signal" "$work/i.out"
check "SIGINT leaves whole frames only" test $(($(size "$work/i/frames.bin") % rec)) -eq 0

# 3b. SIGTERM while the source opens (a 4000x3000 sim: scene takes about 0.7 s to open): a clean
# stop with exit 0, nothing recorded or a recording of whole frames; never the default action.
for delay in 0.1 0.3 0.5; do
	"$bin" record sim:size=4000x3000,pace=fast -o "$work/o$delay" --frames 1 >"$work/o.out" 2>&1 &
	pid=$!
	sleep $delay
	kill -TERM $pid
	wait $pid
	st=$?
	check "SIGTERM after ${delay} s of opening exits 0 ($st: $(cat "$work/o.out"))" test $st -eq 0
	check "SIGTERM after ${delay} s leaves whole frames only" \
		test ! -e "$work/o$delay/frames.bin" -o $(($(size "$work/o$delay/frames.bin" 2>/dev/null || echo 0) % (128 + 4000 * 3000))) -eq 0
done

# 4. Bad input: clear errors, non-zero exits, no crash.
out=$("$bin" record "$work/missing" -o "$work/m" 2>&1)
check "missing recording exits 1 ($out)" test $? -eq 1
check "missing recording is named" grep -q "$work/missing" <<<"$out"
sed -i 's/"format_version": 1/"format_version": 9/' "$work/b/header.json"
out=$("$bin" record "$work/b" -o "$work/n" 2>&1)
check "newer format version exits 1 ($out)" test $? -eq 1
check "newer format version is explained" grep -q "version 9.*newer infocus" <<<"$out"
printf 'not a picture' >"$work/bad.png"
out=$("$bin" record "$work/bad.png" -o "$work/p" 2>&1)
check "unreadable image exits 1 ($out)" test $? -eq 1
check "unreadable image is named" grep -q "bad.png" <<<"$out"
out=$("$bin" record sim:scene=cube -o "$work/s" 2>&1)
check "bad sim option exits 2 ($out)" test $? -eq 2
out=$("$bin" record sim: -o "$work/a" --frames 1 2>&1)
check "non-empty output directory exits 2 ($out)" test $? -eq 2
out=$("$bin" record sim: -o "$work/x" --frames 3 --seconds 1 2>&1)
check "--frames with --seconds exits 2" test $? -eq 2

# 5. A crafted record length near 2^64 (header CRC recomputed): the frames before it are kept,
# the record is named with its byte offset, exit 1; it neither loops nor aborts.
cp -r "$work/a" "$work/big"
python3 - "$work/big/frames.bin" $rec <<'PY'
import struct, sys, zlib
path, offset = sys.argv[1], int(sys.argv[2])
with open(path, "r+b") as f:
    f.seek(offset)
    h = bytearray(f.read(128))
    struct.pack_into("<IQ", h, 4, 512, 2**64 - 256)
    struct.pack_into("<I", h, 124, zlib.crc32(bytes(h[:124])))
    f.seek(offset)
    f.write(h)
PY
out=$(timeout 20 "$bin" record "$work/big" -o "$work/big2" 2>&1)
st=$?
check "crafted record length exits 1 ($st: $out)" test $st -eq 1
check "crafted record length is named ($out)" grep -q "frames.bin: frame 1 at byte $rec" <<<"$out"
check "the frame before it is kept" test "$(size "$work/big2/frames.bin")" -eq $rec

# 6. A disk that fills up mid-frame (a 200 KiB file size limit with SIGXFSZ ignored gives EFBIG,
# as ENOSPC would): the torn frame is cut off, so the two whole frames replay with exit 0.
out=$( (
	ulimit -f 200
	trap '' XFSZ
	exec "$bin" record sim:size=320x240,pace=fast -o "$work/full" --frames 10
) 2>&1)
st=$?
check "full disk exits 1 ($st: $out)" test $st -eq 1
check "full disk says what is kept ($out)" grep -q "the 2 frames before it are kept and replay" <<<"$out"
check "full disk leaves whole frames only" test "$(size "$work/full/frames.bin")" -eq $((2 * rec))
out=$("$bin" record "$work/full" -o "$work/full2" 2>&1)
st=$?
check "the cut recording replays with exit 0 ($st: $out)" test $st -eq 0
check "the cut recording replays its 2 frames ($out)" grep -q "recorded 2 frames" <<<"$out"

# 7. Two recorders on one new directory: one wins and its header names its own source, the
# other says another recording is being written there. Each records half a second, so that the
# second still finds the first writing when its start (loading the simulated camera) is slower.
race_ok=0
for t in $(seq 1 20); do
	d="$work/race$t"
	"$bin" record sim:size=32x24,fps=50,seed=1 -o "$d" --frames 25 >"$d.1" 2>&1 &
	p1=$!
	"$bin" record sim:size=32x24,fps=50,seed=2 -o "$d" --frames 25 >"$d.2" 2>&1 &
	p2=$!
	wait $p1
	s1=$?
	wait $p2
	s2=$?
	if [ $s1 -eq 0 ] && [ $s2 -eq 1 ]; then win=1 lose=2; elif [ $s1 -eq 1 ] && [ $s2 -eq 0 ]; then win=2 lose=1; else
		echo "race $t: exits $s1 $s2"
		continue
	fi
	grep -q "another recording is being written there" "$d.$lose" &&
		grep -q "\"source\": \"sim:size=32x24,fps=50,seed=$win\"" "$d/header.json" &&
		race_ok=$((race_ok + 1))
done
check "20 of 20 recorder races: one wins, the other says why ($race_ok)" test $race_ok -eq 20

echo "record: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
