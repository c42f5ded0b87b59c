#!/usr/bin/env bash
# The command line's contract: help and version succeed, usage errors exit 2 with a message.
# Usage: test_cli.sh PATH_TO_INFOCUS
set -u
bin=${1:?path to infocus}
pass=0 fail=0
expect() { # expect STATUS PATTERN -- ARGS...
	local want=$1 pat=$2
	shift 3
	local out st
	out=$("$bin" "$@" 2>&1)
	st=$?
	if [[ $st -eq $want ]] && grep -qE -- "$pat" <<<"$out"; then
		pass=$((pass + 1))
	else
		echo "FAIL: infocus $* -> status $st (want $want), output:"
		echo "$out" | head -5
		fail=$((fail + 1))
	fi
}
expect 0 'Usage|usage' -- --help
expect 0 '^infocus [0-9]+\.[0-9]+' -- --version
expect 2 'subcommand' --
expect 2 'nonsense' -- nonsense
expect 2 'not expected|--bogus' -- bench --bogus
expect 2 'seconds' -- bench --seconds -1
# An empty value is refused, not read as an option left out (a default CoC) or as 0.
expect 2 'empty argument follows --coc' -- dof --focal 50mm -N 8 --focus 2m --coc ''
expect 2 'value of --focal is empty' -- dof --focal= -N 8 --focus 2m --coc 0.03mm
expect 2 'empty argument follows --blur-floor' -- depth - --blur-floor ''
expect 2 'argument is empty' -- analyze ''
# Output that cannot be written (/dev/full takes nothing) fails with the reason; it exited 0
# with the report lost.
full() { # full PATTERN -- ARGS...
	local pat=$1
	shift 2
	local err st
	err=$("$bin" "$@" 2>&1 >/dev/full)
	st=$?
	if [[ $st -eq 1 ]] && grep -qE -- "$pat" <<<"$err"; then
		pass=$((pass + 1))
	else
		echo "FAIL: infocus $* >/dev/full -> status $st (want 1): $err"
		fail=$((fail + 1))
	fi
}
full 'infocus dof: writing to standard output failed' -- dof --lens rpi-cam3 --focus 1m
full 'infocus dof: writing to standard output failed' -- dof --lens rpi-cam3 --focus 1m --json
full 'infocus devices: writing to standard output failed' -- devices
echo "cli: $pass passed, $fail failed"
[[ $fail -eq 0 ]]
