#!/usr/bin/env bash
# Configures and builds Quadplan into build/ (executable: build/bin/quadplan).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@"
cmake --build build -j"$(nproc)"
