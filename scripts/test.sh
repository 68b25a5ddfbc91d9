#!/usr/bin/env bash
# README command 2: install dependencies, build, and run the whole test suite: the ctest suite
# (every Vulkan context validated), then the sanitizer build's tests, then each fuzz target for a
# bounded time. Any failure stops the run with a non-zero status.
set -euo pipefail
cd "$(dirname "$0")/.."
stage() { echo; echo "==== $1 (at ${SECONDS}s)"; }

stage "dependencies"
scripts/install-deps.sh
stage "build"
scripts/build.sh -DBUILD_TESTING=ON
stage "ctest"
# Every Vulkan context in every test process runs with the validation layers; any message fails
# that process (render/vk_context.h).
(cd build && QUADPLAN_VALIDATE=1 ctest --output-on-failure -j"$(nproc)" --timeout 600)
stage "AddressSanitizer + UndefinedBehaviorSanitizer"
scripts/sanitize.sh
stage "fuzzing"
scripts/fuzz.sh 30
stage "all passed"
