#!/usr/bin/env bash
# Fails when any C++ source or header in the project is not formatted per .clang-format.
# Usage: check_format.sh SOURCE_ROOT [CLANG_FORMAT]
set -u
root=${1:?source root}
cf=${2:-clang-format}
cd "$root" || exit 1
mapfile -t files < <(git ls-files --cached --others --exclude-standard -- '*.cpp' '*.h' 2>/dev/null ||
	find include src drivers replay tests bench -name '*.cpp' -o -name '*.h')
bad=0
for f in "${files[@]}"; do
	[ -f "$f" ] || continue
	if ! "$cf" --style=file --dry-run -Werror "$f" >/dev/null 2>&1; then
		echo "not formatted: $f (fix with: clang-format -i $f)"
		bad=$((bad + 1))
	fi
done
echo "checked ${#files[@]} files, $bad not formatted"
[ "$bad" -eq 0 ]
