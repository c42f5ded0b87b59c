#!/usr/bin/env bash
# Builds the libFuzzer harnesses of tests/fuzz with clang (build-fuzz/, ASan + UBSan) and runs
# each for SECONDS (default 60), starting from the seeds the harnesses write and the corpus of
# earlier runs (build-fuzz/fuzz-corpus/<harness>). Ends with a table of executions, coverage and
# findings, and "N passed, N failed" (a harness fails when it finds a crash, a leak or a hang).
#   scripts/fuzz.sh [SECONDS] [HARNESS...]
# Environment: FUZZ_JOBS=2 runs two harnesses at once, each started as soon as the previous
# build step is done; FUZZ_NICE=19 runs them at that niceness (a shared machine).
# A finding is left in build-fuzz/fuzz-artifacts/<harness>/; once fixed, copy it to
# tests/fuzz/regressions/<harness>/, which every build replays.
set -uo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here" || exit 1
seconds=${1:-60}
shift $(($# > 0 ? 1 : 0))
harnesses=("$@")
if [[ ${#harnesses[@]} -eq 0 ]]; then
	harnesses=(y4m recording jsonl options image luma)
	# The web view's harness exists only where the web face is built (cpp-httplib).
	pkg-config --exists cpp-httplib 2>/dev/null && harnesses+=(http)
fi
jobs=${FUZZ_JOBS:-1}
niceness=${FUZZ_NICE:-0}
builddir=build-fuzz

if ! command -v clang++ >/dev/null || ! compgen -G "/usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a" >/dev/null; then
	echo "fuzz.sh: needs clang and libclang-rt-dev (scripts/install-deps.sh --test)" >&2
	exit 77
fi
if [[ ! -f "$builddir/build.ninja" ]]; then
	# werror off: clang warns where GCC, the compiler of the normal build, does not.
	CC=clang CXX=clang++ meson setup "$builddir" -Dfuzz=true -Db_sanitize=address,undefined \
		-Db_lundef=false -Dbuildtype=debugoptimized -Dwerror=false >/dev/null ||
		{ echo "meson setup $builddir failed" >&2; exit 1; }
fi
export ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1
export LSAN_OPTIONS=suppressions=$here/tests/lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

results=$(mktemp -d)
trap 'rm -rf "$results"' EXIT
run() {  # run HARNESS: one harness, its summary line to $results/HARNESS
	local h=$1 corpus=$builddir/fuzz-corpus/$1 artifacts=$builddir/fuzz-artifacts/$1
	mkdir -p "$corpus" "$artifacts"
	"$builddir/tests/fuzz/fuzz_${h}_replay" --write-seeds "$builddir/fuzz-seeds/$h" >/dev/null
	nice -n "$niceness" "$builddir/tests/fuzz/fuzz_$h" -max_total_time="$seconds" -timeout=20 \
		-rss_limit_mb=2560 -print_final_stats=1 -artifact_prefix="$artifacts/" \
		"$corpus" "$builddir/fuzz-seeds/$h" >"$builddir/fuzz-$h.log" 2>&1
	local rc=$?
	local stats execs cov ft
	stats=$(grep -E '^#[0-9]+' "$builddir/fuzz-$h.log" | tail -1)
	execs=$(grep -E '^stat::number_of_executed_units' "$builddir/fuzz-$h.log" | tail -1 | awk '{print $2}')
	cov=$(sed -nE 's/.* cov: ([0-9]+).*/\1/p' <<<"$stats")
	ft=$(sed -nE 's/.* ft: ([0-9]+).*/\1/p' <<<"$stats")
	local finding=none
	[[ $rc -eq 0 ]] || finding=$(ls "$artifacts" | head -1)
	echo "$h ${execs:-0} ${cov:-?} ${ft:-?} $(ls "$corpus" | wc -l) ${finding:-exit-$rc} $rc" >"$results/$h"
	echo "fuzz_$h: ${execs:-0} executions (up to ${seconds} s), cov ${cov:-?}, ft ${ft:-?}, findings: ${finding:-exit $rc} ($builddir/fuzz-$h.log)"
}

# The modules a harness loads at run time, which building the harness alone leaves out: the
# web view's harness streams from the simulated camera and encodes pictures.
declare -A modules=([http]="replay/infocus-sim.so src/imaging/infocus-imaging.so")
running=0
for h in "${harnesses[@]}"; do
	# shellcheck disable=SC2086 # the module list splits into targets
	ninja -C "$builddir" "tests/fuzz/fuzz_$h" "tests/fuzz/fuzz_${h}_replay" ${modules[$h]:-} >/dev/null ||
		{ echo "$h 0 - - 0 build-failed 1" >"$results/$h"; continue; }
	run "$h" &
	running=$((running + 1))
	if [[ $running -ge $jobs ]]; then
		wait -n
		running=$((running - 1))
	fi
done
wait

passed=0
failed=0
printf '%-10s %12s %6s %7s %7s  %s\n' harness executions cov ft corpus findings
for h in "${harnesses[@]}"; do
	read -r name execs cov ft corpus finding rc <"$results/$h"
	printf '%-10s %12s %6s %7s %7s  %s\n' "$name" "$execs" "$cov" "$ft" "$corpus" "$finding"
	if [[ $rc -eq 0 ]]; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
done
echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
