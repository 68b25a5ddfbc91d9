#!/usr/bin/env bash
# README command 2: install dependencies, build, and run the whole test suite through ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh -DBUILD_TESTING=ON
cd build
ctest --output-on-failure -j"$(nproc)" --timeout 600
