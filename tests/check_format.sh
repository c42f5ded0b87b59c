#!/usr/bin/env bash
# Fails when any C++ source or header in the project is not formatted per .clang-format.
# Usage: check_format.sh SOURCE_ROOT [CLANG_FORMAT]
# One clang-format process checks every file: one process per file took 19 s of CPU, close to
# meson's time limit on a loaded machine.
set -u
root=${1:?source root}
cf=${2:-clang-format}
cd "$root" || exit 1
mapfile -t files < <(git ls-files --cached --others --exclude-standard -- '*.cpp' '*.h' 2>/dev/null ||
	find include src drivers replay tests bench -name '*.cpp' -o -name '*.h')
present=()
for f in "${files[@]}"; do
	[ -f "$f" ] && present+=("$f")
done
if [ ${#present[@]} -eq 0 ]; then
	echo "no C++ files found under $root: nothing to check" >&2
	exit 1
fi
log=$(mktemp)
trap 'rm -f "$log"' EXIT
"$cf" --style=file --dry-run -Werror "${present[@]}" >/dev/null 2>"$log"
status=$?
# clang-format names each unformatted place as "FILE:LINE:COL: error: code should be ...".
mapfile -t bad < <(sed -nE 's/^([^:]+):[0-9]+:[0-9]+: error: code should be clang-formatted.*/\1/p' "$log" | sort -u)
for f in "${bad[@]}"; do
	echo "not formatted: $f (fix with: clang-format -i $f)"
done
if [ "$status" -ne 0 ] && [ ${#bad[@]} -eq 0 ]; then
	echo "clang-format failed:" >&2
	head -20 "$log" >&2
fi
echo "checked ${#present[@]} files, ${#bad[@]} not formatted"
[ "$status" -eq 0 ] && [ ${#bad[@]} -eq 0 ]
