#!/usr/bin/env bash
# Builds the product and its tests with AddressSanitizer + UndefinedBehaviorSanitizer into
# build-asan/ (-O1, line tables only, to keep the build short) and runs the tests there. Any
# sanitizer report fails the test that triggered it (-fno-sanitize-recover, LSan at exit).
#
# Usage: scripts/sanitize.sh [--all]
# By default (the test command) the unit, command-line and hardening tests run (the executables
# quadplan and quadplan_tests with the plugins); left out, to bound the time, are the per-cage
# limit checks (72 runs of one code path that the unit tests cover on small cages), the
# benchmark smoke tests and the Xvfb window tests. --all builds and runs those too (about four
# times longer). Never here: the Python tests, whose interpreter is not instrumented.
set -euo pipefail
cd "$(dirname "$0")/.."
targets=(--target quadplan quadplan_tests)
exclude='check_limit\.|^cli\.bench_|^window\.|^scene_|^tutorial\.|_NOT_BUILT'
if [[ "${1:-}" == "--all" ]]; then
  targets=()
  exclude='check_limit\.catmark_(nonman_quad)?pole360$|^scene_|^tutorial\.'
fi

launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" \
      -DQUADPLAN_SANITIZE=ON -DBUILD_TESTING=ON "${launcher[@]}" >/dev/null
cmake --build build-asan -j"$(nproc)" "${targets[@]}"

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/sanitize/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="suppressions=$PWD/tests/fuzz/ubsan.supp:print_stacktrace=1:halt_on_error=1"
export QUADPLAN_VALIDATE=1
cd build-asan
ctest --output-on-failure -j"$(nproc)" --timeout 900 -E "$exclude"
