#!/usr/bin/env bash
# `analyze --jobs`: frames measured at once give the bytes one job gives, in order, on the real
# photographs and a recording; the progress line shows on a terminal (script(1)) and never in a
# file or with --quiet.
# Usage: test_jobs.sh PATH_TO_INFOCUS DATA_DIR
set -u
bin=${1:?path to infocus}
data=${2:?path to the shared data}
[[ -d "$data" ]] || {
	echo "skipped: no data at $data"
	exit 77
}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
check() { # what, command...
	local what=$1
	shift
	if ! "$@"; then
		echo "FAIL: $what"
		fail=1
	fi
}

for src in focus-sweep-pi focus-stack/depthmap focus-stack/pcb; do
	"$bin" analyze "$data/$src" --jobs 1 -o "$tmp/one.jsonl" 2>/dev/null || fail=1
	for jobs in 2 3; do
		"$bin" analyze "$data/$src" --jobs $jobs -o "$tmp/many.jsonl" 2>/dev/null || fail=1
		check "$src: --jobs $jobs differs from --jobs 1" cmp -s "$tmp/one.jsonl" "$tmp/many.jsonl"
	done
	echo "$src: $(wc -l <"$tmp/one.jsonl") frames, --jobs 2 and 3 identical to --jobs 1"
done
# CSV and --frames through the same engine.
"$bin" analyze "$data/focus-sweep-pi" --jobs 1 --format csv --frames 40 >"$tmp/one.csv" 2>/dev/null
"$bin" analyze "$data/focus-sweep-pi" --jobs 2 --format csv --frames 40 >"$tmp/two.csv" 2>/dev/null
check "csv --frames 40: --jobs 2 differs" cmp -s "$tmp/one.csv" "$tmp/two.csv"
check "csv --frames 40: not 40 frames" test "$(cut -d, -f1 "$tmp/one.csv" | sort -u | wc -l)" -eq 41

# A recording with lens positions, and the report over it.
"$bin" record "sim:size=320x240,focus=1m,pace=fast" -o "$tmp/rec" --frames 40 >/dev/null 2>&1 ||
	fail=1
"$bin" analyze "$tmp/rec" --jobs 1 -o "$tmp/rec1.jsonl" 2>"$tmp/err1"
"$bin" analyze "$tmp/rec" --jobs 2 -o "$tmp/rec2.jsonl" 2>"$tmp/err2"
check "recording: --jobs 2 differs" cmp -s "$tmp/rec1.jsonl" "$tmp/rec2.jsonl"
check "progress written into a file" test ! -s "$tmp/err2"
"$bin" report "$tmp/rec" --frames 0 --jobs 1 -o "$tmp/r1.html" 2>/dev/null
"$bin" report "$tmp/rec" --frames 0 --jobs 2 -o "$tmp/r2.html" 2>/dev/null
check "report: --jobs 2 differs" cmp -s "$tmp/r1.html" "$tmp/r2.html"

# On a terminal: one line redrawn in place, with done of total, frames a second and time left.
script -qfec "'$bin' analyze '$tmp/rec' --jobs 2 -o '$tmp/tty.jsonl'" /dev/null >"$tmp/tty" 2>&1
check "no progress line on a terminal" grep -q "infocus analyze: 40/40 frames (100%) .* fps .* left" "$tmp/tty"
script -qfec "'$bin' analyze '$tmp/rec' --quiet -o '$tmp/tty.jsonl'" /dev/null >"$tmp/quiet" 2>&1
check "--quiet still shows progress" test ! -s "$tmp/quiet"
script -qfec "'$bin' record '$tmp/rec' -o '$tmp/rec2'" /dev/null >"$tmp/rtty" 2>&1
check "no progress line for record" grep -q "infocus record: 40/40 frames" "$tmp/rtty"
script -qfec "'$bin' stack '$data/focus-stack/pcb' --json" /dev/null >"$tmp/stty" 2>&1
check "no progress line for stack" grep -qE "infocus stack: ([0-9]+)/\1 frames" "$tmp/stty"
[[ $fail -eq 0 ]] && echo ok
exit $fail
