#!/usr/bin/env bash
# Builds the core with clang, AddressSanitizer + UndefinedBehaviorSanitizer and libFuzzer's
# coverage into build-fuzz/ (-O2, line tables): the fuzz targets and the unit tests that need only
# the core (quadplan_core_tests). scripts/sanitize.sh runs the tests, scripts/fuzz.sh the
# targets; both call this first, and the second call finds everything built.
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" \
      -DCMAKE_CXX_COMPILER=clang++ -DQUADPLAN_FUZZ=ON -DBUILD_TESTING=ON "${launcher[@]}" >/dev/null
cmake --build build-fuzz -j"$(nproc)"
