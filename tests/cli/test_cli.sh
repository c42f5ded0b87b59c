#!/usr/bin/env bash
# The command line's contract: help and version succeed, usage errors exit 2 with a message.
# Usage: test_cli.sh PATH_TO_INFOCUS
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
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
		ok
	else
		bad "infocus $* >/dev/full -> status $st (want 1): $err"
	fi
}
full 'infocus dof: writing to standard output failed' -- dof --lens rpi-cam3 --focus 1m
full 'infocus dof: writing to standard output failed' -- dof --lens rpi-cam3 --focus 1m --json
full 'infocus devices: writing to standard output failed' -- devices
echo "cli: $pass passed, $fail failed"
[[ $fail -eq 0 ]]
