#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test. Ends with "N passed, N failed".
#   scripts/test.sh              unit, integration, CLI and style tests (build/)
#   scripts/test.sh --sanitize   the same under AddressSanitizer + UBSan (build-asan/)
#   scripts/test.sh --sanitize=clang   the same built by clang (build-asan-clang/), whose UBSan
#                                also checks float-to-integer casts that GCC's lets pass
# Without --sanitize, a brief run of every fuzzer (scripts/fuzz.sh 30, two at once) follows the
# unit tests when clang and libclang-rt-dev are there; it counts as one test in the closing line.
# After the unit tests it runs the real-driver tier (tests/vm/run.sh: vivid and vimc in qemu) and
# counts its parts in the closing line; INFOCUS_NO_VM=1 leaves it out (it is left out under
# --sanitize and when a camera backend is disabled).
# Environment: INFOCUS_MESON_OPTS adds meson options (e.g. "-Dv4l2=disabled -Dlibcamera=disabled").
set -uo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here" || exit 1

builddir=build
opts=(${INFOCUS_MESON_OPTS:-})
vm=${INFOCUS_NO_VM:+no}
[[ "${INFOCUS_MESON_OPTS:-}" == *disabled* ]] && vm=no
fuzz=yes
if [[ "${1:-}" == --sanitize* ]]; then
	vm=no
	fuzz=no
	builddir=build-asan
	# lundef=false: the sanitizer runtimes resolve symbols at load time.
	opts+=(-Db_sanitize=address,undefined -Db_lundef=false -Dbuildtype=debugoptimized)
	if [[ "$1" == --sanitize=clang ]]; then
		builddir=build-asan-clang
		export CC=clang CXX=clang++
		# werror off: clang warns where GCC, the compiler of every other build, does not.
		opts+=(-Dcpp_args=-fsanitize=float-cast-overflow -Dwerror=false)
	else
		# GCC 12 reports a false maybe-uninitialized inside libstdc++'s std::regex (used by
		# Catch2) once the sanitizers change inlining: that one warning is not an error there.
		opts+=(-Dcpp_args=-Wno-maybe-uninitialized)
	fi
	export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
	# Full stacks, so that leaks inside third-party libraries match tests/lsan.supp.
	export LSAN_OPTIONS=suppressions=$here/tests/lsan.supp:fast_unwind_on_malloc=0:print_suppressions=0
	export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
fi

scripts/install-deps.sh --test || exit 1
if [[ ! -f "$builddir/build.ninja" ]]; then
	meson setup "$builddir" "${opts[@]}" >/dev/null || { echo "meson setup failed" >&2; exit 1; }
elif [[ ${#opts[@]} -gt 0 ]]; then
	meson configure "$builddir" "${opts[@]}" >/dev/null || exit 1
fi
ninja -C "$builddir" || { echo "0 passed, 1 failed"; exit 1; }

meson test -C "$builddir" --num-processes 2 --print-errorlogs
status=$?

# One closing line from meson's machine-readable log.
read -r passed failed skipped < <(python3 - "$builddir/meson-logs/testlog.json" <<'PY'
import json, sys
p = f = s = 0
for line in open(sys.argv[1]):
    r = json.loads(line)["result"]
    if r in ("OK", "EXPECTEDFAIL"):
        p += 1
    elif r == "SKIP":
        s += 1
    else:
        f += 1
print(p, f, s)
PY
)
passed=${passed:-0}
failed=${failed:-1}
if [[ $fuzz == yes ]]; then
	echo "== fuzzers, 30 s each (scripts/fuzz.sh) =="
	FUZZ_JOBS=2 scripts/fuzz.sh 30
	case $? in
	0) passed=$((passed + 1)) ;;
	77) skipped=$((${skipped:-0} + 1)) ;;
	*) failed=$((failed + 1)) status=1 ;;
	esac
fi
if [[ "$vm" != no ]]; then
	echo "== real-driver tier (tests/vm/run.sh) =="
	# Through a file, not tee: stdout may itself be a file that a reopen would truncate.
	vmlog=$(mktemp)
	tests/vm/run.sh "$builddir" >"$vmlog" 2>&1
	vmstatus=$?
	cat "$vmlog"
	read -r vp vf < <(grep -E '^[0-9]+ passed, [0-9]+ failed$' "$vmlog" | tail -1 |
		sed -E 's/([0-9]+) passed, ([0-9]+) failed/\1 \2/')
	passed=$((passed + ${vp:-0}))
	failed=$((failed + ${vf:-1}))
	[[ $vmstatus -eq 0 ]] || status=1
	rm -f "$vmlog"
fi
if [[ "${skipped:-0}" -gt 0 ]]; then
	echo "${passed:-0} passed, ${failed:-1} failed, ${skipped} skipped"
else
	echo "${passed:-0} passed, ${failed:-1} failed"
fi
exit $status
