#!/usr/bin/env bash
# Configures and builds Quadplan into build/ (executable: build/bin/quadplan).
# Debug information is line tables only (-g1): backtraces, sanitizers and profilers still name
# file and line, and the build takes about two thirds of the time full -g takes (the code
# generated is the same). Pass -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g -DNDEBUG" for a build to
# step through in a debugger, or -DCMAKE_BUILD_TYPE=Debug.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" "$@"
cmake --build build -j"$(nproc)"
