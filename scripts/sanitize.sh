#!/usr/bin/env bash
# Runs tests under AddressSanitizer + UndefinedBehaviorSanitizer. Any sanitizer report fails the
# test that triggered it (-fno-sanitize-recover, LSan at exit).
#
# Usage: scripts/sanitize.sh [--all]
# By default (the test command) it runs the unit tests that need only the core — the readers of
# untrusted files, topology, plans, edits, history, displacement, animation — as
# quadplan_core_tests (tests named sanitized.*), built with clang beside the fuzz targets in
# build-fuzz/ (scripts/build-sanitized-core.sh), so the test command compiles the core twice, not
# three times. --all builds the whole product and its tests with gcc into build-asan/ (-O1, line
# tables only) and runs every test except the two largest pole cages' limit checks and the
# Python tests (their interpreter is not instrumented); it takes about four times longer and was
# clean when last run (docs/hardening.md).
set -euo pipefail
cd "$(dirname "$0")/.."
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/sanitize/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="suppressions=$PWD/tests/fuzz/ubsan.supp:print_stacktrace=1:halt_on_error=1"
export QUADPLAN_VALIDATE=1

if [[ "${1:-}" != "--all" ]]; then
  scripts/build-sanitized-core.sh
  cd build-fuzz
  exec ctest --output-on-failure -j"$(nproc)" --timeout 900 -R '^sanitized\.'
fi

launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" \
      -DQUADPLAN_SANITIZE=ON -DBUILD_TESTING=ON "${launcher[@]}" >/dev/null
cmake --build build-asan -j"$(nproc)"
cd build-asan
ctest --output-on-failure -j"$(nproc)" --timeout 900 -E 'check_limit\.catmark_(nonman_quad)?pole360$|^scene_|^tutorial\.'
