#!/usr/bin/env bash
# Bad input across the commands: each line of the table is a command line, the exit status it
# must end with (2 for a usage error, 1 for a runtime failure; never a signal) and a word its
# message must hold, the option, field or file at fault.
# Usage: test_bad_input.sh PATH_TO_INFOCUS
source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"

# STATUS | PATTERN | ARGS (split on spaces)
table=(
	"2|'--bogus'.*not an option|--bogus"
	"2|'-x'.*not an option|-x"
	"2|'--bogus'.*not an option|--bogus analyze sim:"
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

# Memory that runs out is a runtime failure with a message, not an abort.
out=$(
	ulimit -v 400000
	"$bin" analyze sim:size=8192x8192 --frames 1 2>&1 >/dev/null
)
st=$?
if [[ $st -eq 1 ]] && grep -q 'memory' <<<"$out"; then ok; else bad "out of memory -> status $st: $out"; fi

echo "bad input: $pass passed, $fail failed"
[[ $fail -eq 0 ]]
