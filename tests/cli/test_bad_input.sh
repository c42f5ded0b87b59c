#!/usr/bin/env bash
# Bad input across the commands: each line of the table is a command line, the exit status it
# must end with (2 for a usage error, 1 for a runtime failure; never a signal) and a word its
# message must hold, the option, field or file at fault. After it, the cases a line cannot hold:
# memory that runs out, outputs that must survive or be written through, damaged files.
# Usage: test_bad_input.sh PATH_TO_INFOCUS
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

# STATUS | PATTERN | ARGS (split on spaces)
table=(
	"2|'--bogus'.*not an option|--bogus"
	"2|'-x'.*not an option|-x"
	"2|'--bogus'.*not an option|--bogus analyze sim:"
	"2|seed=18446744073709551616|analyze sim:seed=18446744073709551616 --frames 1"
	"2|seed=-1|analyze sim:seed=-1 --frames 1"
	"2|seed=1.5|analyze sim:seed=1.5 --frames 1"
	"2|size=30x20|analyze sim:size=30x20 --frames 1"
	"2|size=99999999999x20|analyze sim:size=99999999999x20 --frames 1"
	"2|angle=nan|analyze sim:angle=nan --frames 1"
	"2|angle=inf|analyze sim:angle=inf --frames 1"
	"2|angle=1e300|analyze sim:angle=1e300 --frames 1"
	"2|tilt=nan|analyze sim:scene=tilted,tilt=nan --frames 1"
	"2|tilt=-inf|analyze sim:scene=tilted,tilt=-inf --frames 1"
	"2|tilt=85|analyze sim:scene=tilted,tilt=85 --frames 1"
	"2|fnumber=1e300|analyze sim:fnumber=1e300 --frames 1"
	"2|pitch=1e-300m|analyze sim:pitch=1e-300m --frames 1"
	"2|sensor=1x1|analyze sim:sensor=1x1 --frames 1"
	"2|focus=1e300dpt|analyze sim:focus=1e300dpt --frames 1"
	"2|noise=nan|analyze sim:noise=nan --frames 1"
)
for row in "${table[@]}"; do
	IFS='|' read -r want pat args <<<"$row"
	read -ra argv <<<"$args"
	# A hang is a failure too: no bad input may keep a command running.
	out=$(timeout 60 "$bin" "${argv[@]}" 2>&1 >/dev/null)
	st=$?
	if [[ $st -eq $want ]] && grep -qE -- "$pat" <<<"$out"; then
		ok
	else
		bad "infocus $args -> status $st (want $want), stderr: $(head -3 <<<"$out")"
	fi
done

# Memory that runs out is a runtime failure with a message, not an abort. Not under
# AddressSanitizer (scripts/test.sh --sanitize), which reserves terabytes of address space and
# reports a failed allocation itself.
if [[ -z ${ASAN_OPTIONS:-} ]]; then
	out=$(
		ulimit -v 400000
		"$bin" analyze sim:size=8192x8192 --frames 1 2>&1 >/dev/null
	)
	st=$?
	[[ $st -eq 1 ]] && grep -q 'memory' <<<"$out" && ok || bad "out of memory -> status $st: $out"
fi

# An existing -o file survives a failure before output starts: a source that does not open, an
# option it refuses.
keep() { # keep STATUS FILE -- ARGS...: ARGS exits with STATUS and FILE holds what it held
	local want=$1 file=$2
	shift 3
	echo 'yesterday' >"$file"
	"$bin" "$@" >/dev/null 2>&1
	local st=$?
	if [[ $st -eq $want && $(cat "$file") == yesterday ]]; then
		ok
	else
		bad "infocus $* -> status $st (want $want), $file now: $(head -c 80 "$file")"
	fi
}
keep 1 "$tmp/out.jsonl" -- analyze "$tmp/no-such.y4m" -o "$tmp/out.jsonl"
keep 2 "$tmp/out.jsonl" -- analyze sim:bogus=1 -o "$tmp/out.jsonl"
keep 2 "$tmp/out.jsonl" -- analyze sim:size=64x48 --roi 0,0,500,500 -o "$tmp/out.jsonl"
"$bin" analyze sim:size=64x48,pace=fast --frames 2 -o "$tmp/out.jsonl" 2>/dev/null &&
	[[ $(wc -l <"$tmp/out.jsonl") -eq 2 ]] && ok || bad "analyze -o did not write 2 lines"
# A sweep that fails to start leaves no empty sweep.jsonl that would make the next run refuse
# the directory as a sweep's.
"$bin" sweep sim:bogus=1 -o "$tmp/sweep" >/dev/null 2>&1
[[ $? -eq 2 && ! -e $tmp/sweep/sweep.jsonl ]] && ok || bad "sweep with a bad source left sweep.jsonl"
"$bin" sweep sim:pace=fast --from nonsense -o "$tmp/sweep" >/dev/null 2>&1
[[ $? -ne 0 && ! -e $tmp/sweep/sweep.jsonl ]] && ok || bad "sweep with a bad --from left sweep.jsonl"
"$bin" sweep sim:pace=fast,size=64x48 --steps 3 -o "$tmp/sweep" >/dev/null 2>&1 &&
	[[ -s $tmp/sweep/summary.json ]] && ok || bad "sweep -o after the failures"
# report -o writes through a symlink (the target gets the report, the link stays), writes
# devices and FIFOs directly and never replaces them with a regular file.
rep=(report sim:size=64x48,pace=fast --frames 1 --grid 2x2)
mkdir "$tmp/r" && echo old >"$tmp/r/target.html" && ln -s target.html "$tmp/r/link.html"
"$bin" "${rep[@]}" -o "$tmp/r/link.html" >/dev/null 2>&1
[[ $? -eq 0 && -L $tmp/r/link.html ]] && grep -q '<html' "$tmp/r/target.html" && ok ||
	bad "report -o through a symlink: $(ls -l "$tmp/r")"
ln -s new.html "$tmp/r/dangling.html"
"$bin" "${rep[@]}" -o "$tmp/r/dangling.html" >/dev/null 2>&1
[[ $? -eq 0 && -L $tmp/r/dangling.html ]] && grep -q '<html' "$tmp/r/new.html" && ok ||
	bad "report -o through a dangling symlink: $(ls -l "$tmp/r")"
mkfifo "$tmp/r/fifo"
timeout 60 cat "$tmp/r/fifo" >"$tmp/r/from-fifo" &
reader=$!
timeout 60 "$bin" "${rep[@]}" -o "$tmp/r/fifo" >/dev/null 2>&1
st=$?
wait $reader
[[ $st -eq 0 && -p $tmp/r/fifo ]] && grep -q '<html' "$tmp/r/from-fifo" && ok ||
	bad "report -o FIFO -> status $st: $(ls -l "$tmp/r")"
if [[ $(id -u) -eq 0 ]]; then # device nodes of our own: /dev/null's and /dev/full's numbers
	mknod "$tmp/r/null" c 1 3 && mknod "$tmp/r/full" c 1 7
	"$bin" "${rep[@]}" -o "$tmp/r/null" >/dev/null 2>&1
	[[ $? -eq 0 && -c $tmp/r/null ]] && ok || bad "report -o a null device replaced it"
	out=$("$bin" "${rep[@]}" -o "$tmp/r/full" 2>&1 >/dev/null)
	[[ $? -eq 1 && -c $tmp/r/full ]] && grep -q "$tmp/r/full" <<<"$out" && ok ||
		bad "report -o a full device: $out; $(ls -l "$tmp/r/full")"
fi
# A recording whose header.json is there but cannot be read is not called one without it.
"$bin" record sim:size=64x48,pace=fast --frames 2 -o "$tmp/rec" >/dev/null 2>&1
mv "$tmp/rec/header.json" "$tmp/header.json" && ln -s "$tmp/gone.json" "$tmp/rec/header.json"
expect 1 'header.json.*(missing|cannot read)' -- analyze "$tmp/rec"
if [[ $(id -u) -ne 0 ]]; then # root reads any file
	rm "$tmp/rec/header.json" && cp "$tmp/header.json" "$tmp/rec/" && chmod 000 "$tmp/rec/header.json"
	expect 1 'cannot read.*header.json' -- analyze "$tmp/rec"
	chmod 000 "$tmp/rec"
	expect 1 'cannot read directory' -- analyze "$tmp/rec"
	chmod 755 "$tmp/rec"
fi
# An image too large for a frame is named, a runtime failure (the file, not the command line).
python3 - "$tmp/big.png" <<'PY'
import struct, sys, zlib
def chunk(t, d):
    return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
w = h = 17000
rows = zlib.compress(b"\0" * ((w + 1) * h), 9)
with open(sys.argv[1], "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0)))
    f.write(chunk(b"IDAT", rows) + chunk(b"IEND", b""))
PY
expect 1 'big.png is 17000x17000' -- analyze "$tmp/big.png"
# depth's JSONL input: a field of the wrong type is named with its line, not "cannot use at()".
"$bin" analyze sim:size=64x48,pace=fast --frames 2 --grid 2x2 >"$tmp/a.jsonl" 2>/dev/null
jsonl() { # jsonl NAME PYTHON: a.jsonl with its second record changed by PYTHON (on r)
	python3 - "$tmp/a.jsonl" "$tmp/$1.jsonl" "$2" <<'PY'
import json, sys
lines = [json.loads(x) for x in open(sys.argv[1])]
r = lines[1]
exec(sys.argv[3])
open(sys.argv[2], "w").write("".join(json.dumps(x) + "\n" for x in lines))
PY
}
jsonl regions-number 'r["regions"] = 5'
expect 1 'line 2.*"regions" must be an array' -- depth "$tmp/regions-number.jsonl" --lens rpi-cam3
jsonl region-number 'r["regions"][1] = 5'
expect 1 'line 2.*region 2: the region must be an object' -- depth "$tmp/region-number.jsonl" --lens rpi-cam3
jsonl lens-null 'r["lens_position"]["value"] = None'
expect 1 'line 2.*"lens_position".*"value"' -- depth "$tmp/lens-null.jsonl" --lens rpi-cam3
jsonl metric-number 'r["metric"] = 5'
expect 1 'line 2.*"metric" must be a string' -- depth "$tmp/metric-number.jsonl" --lens rpi-cam3
jsonl sharpness-string 'r["regions"][0]["sharpness"] = "high"'
expect 1 'line 2.*region 1: "sharpness" must be a number' -- depth "$tmp/sharpness-string.jsonl" --lens rpi-cam3
# A Y4M header line longer than the reader takes is said to be too long, not another format.
{ printf 'YUV4MPEG2 W16 H16 F30:1 C420jpeg X'; head -c 5000 /dev/zero | tr '\0' a; printf '\n'; } >"$tmp/long.y4m"
expect 1 'long.y4m: its YUV4MPEG2 header line does not end within 4096 bytes' -- analyze "$tmp/long.y4m"
: >"$tmp/empty.y4m"
expect 1 'empty.y4m: is empty' -- analyze "$tmp/empty.y4m"

echo "bad input: $pass passed, $fail failed"
[[ $fail -eq 0 ]]
