#!/usr/bin/env bash
# Sourced by the CLI test scripts that take PATH_TO_INFOCUS [SHARED_DATA_DIR]: sets $bin and $data
# from the arguments, a scratch directory $tmp removed on exit, the pass/fail counters that ok and
# bad keep (the script ends by reporting them), and expect, which checks one command's exit
# status and output.
set -u
bin=${1:?path to infocus}
data=${2:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*"; fail=$((fail + 1)); }
# expect STATUS PATTERN -- ARGS...: infocus ARGS exits with STATUS and its output (stdout and
# stderr) matches the extended regular expression PATTERN.
expect() {
	local want=$1 pat=$2
	shift 3
	local out st
	out=$("$bin" "$@" 2>&1)
	st=$?
	if [[ $st -eq $want ]] && grep -qE -- "$pat" <<<"$out"; then
		ok
	else
		bad "infocus $* -> status $st (want $want), output: $(head -5 <<<"$out")"
	fi
}
