#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer run: configures ./build-asan
# (RelWithDebInfo, -fsanitize=address,undefined, frame pointers kept, every
# UB finding fatal), builds it and runs the `unit` and `fuzz` CTest labels.
# Prints the number of tests run and failed and the number of sanitizer
# findings (reports of AddressSanitizer, LeakSanitizer and UBSan's
# "runtime error:" lines) in the test logs; exits non-zero on any failure or
# finding.
#
# Usage: scripts/sanitize.sh [TARGET...]: with targets (e.g. core_tests
# fuzz_tests furnace), only those are built and only the tests of their areas
# run (CTest names start with the area, the binary's name up to its first
# underscore: core_tests -> core., cli_tests -> cli.). The binaries
# of the two labels are core_tests analytic_tests renderer_tests export_tests
# verify_check_tests cli_tests (unit) and fuzz_tests (fuzz, with the
# furnace binary it runs): naming them skips building the statistical, report
# and slow test binaries, which these labels do not run.
#
# Slow: every translation unit is rebuilt with instrumentation (the CGAL one
# alone takes minutes) and the tests run ~10x slower (the analytic unit
# tests: 35 s of test time in Release, 473 s instrumented). Jobs: FURNACE_JOBS
# (default 2). The fuzz test detects the AddressSanitizer build from the
# compiler's __SANITIZE_ADDRESS__ and allows each case 10x its Release time
# limit (kCaseTimeLimit), so a slow instrumented case is not taken for a hang.
# Embree, TBB, OpenEXR and the C++ runtime are not instrumented:
# the findings are in furnace's code and the headers it instantiates (CGAL,
# Boost, nlohmann, fmt). CGAL's interval arithmetic changes the rounding mode,
# which runs natively under the sanitizers (unlike valgrind, see
# TOOLCHAIN.md), so CGAL_ALWAYS_ROUND_TO_NEAREST is not needed here.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="${FURNACE_JOBS:-2}"
build=build-asan
flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"

# halt_on_error: a finding ends the process with exit code 86, which no
# furnace command uses (the fuzz test's subprocesses then fail its exit-code
# check rather than pass for exit 1); the log keeps the report.
# Leaks are findings too; the uninstrumented libraries' own allocations that
# live until exit (TBB's and Embree's thread-local pools) are suppressed by
# library name only. Set before the build: test discovery runs the binaries.
mkdir -p "$build"
suppressions="$PWD/$build/lsan.supp"
printf 'leak:libtbb\nleak:libembree3\n' >"$suppressions"
# UBSan's vptr check reports CGAL 5.5's arrangement iterators
# (Arrangement_2_iterators.h:458 downcasts a DCEL base pointer to its Face
# type before the object is used as one): a pattern inside CGAL's headers,
# not furnace's code. Suppressed by CGAL's type names only, so a bad downcast
# in furnace's own types is still a finding.
ubsan_suppressions="$PWD/$build/ubsan.supp"
printf 'vptr_check:*Arr_*\nvptr_check:*Face*\nvptr_check:*CGAL*\n' >"$ubsan_suppressions"
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:exitcode=86:strict_string_checks=1"
export LSAN_OPTIONS="suppressions=$suppressions"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:exitcode=86:suppressions=$ubsan_suppressions"

launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DFURNACE_BUILD_BENCHMARKS=OFF
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build "$build" -j "$jobs" "${targets[@]}"

# The areas of the built test binaries (cli_tests -> ^cli\.), or
# all. A binary of an area that was not built registers one unlabelled
# *_NOT_BUILT test, which the label selection leaves out.
selection=()
if [ "$#" -gt 0 ]; then
  areas=$(printf '%s\n' "$@" | sed -n 's/^\([^_]*\)_.*tests$/\1/p' | sort -u | paste -sd '|')
  selection=(-R "^(${areas})\\.")
fi

log="$build/sanitize.log"
status=0
ctest --test-dir "$build" -L 'unit|fuzz' "${selection[@]}" -j "$jobs" --output-on-failure --timeout 1800 \
  >"$log" 2>&1 || status=$?
tail -n 4 "$log"
# Every test's full output is in LastTest.log (the summary log repeats the failures').
findings=$(grep -cE 'ERROR: (Address|Leak)Sanitizer|runtime error:' "$build/Testing/Temporary/LastTest.log" || true)
echo "sanitizer findings: $findings (log: $build/Testing/Temporary/LastTest.log)"
if [ "$findings" -ne 0 ]; then status=1; fi
exit "$status"
