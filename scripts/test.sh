#!/usr/bin/env bash
# README command 2: install dependencies, build, and run the whole test suite through ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh -DBUILD_TESTING=ON
cd build
# Every Vulkan context in every test process runs with the validation layers; any message fails
# that process (render/vk_context.h).
export QUADPLAN_VALIDATE=1
ctest --output-on-failure -j"$(nproc)" --timeout 600
