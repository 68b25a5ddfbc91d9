#!/usr/bin/env bash
# README command 1: install dependencies, build, and open Quadplan on the default scene.
# Extra arguments go to quadplan (e.g. `scripts/run.sh info scenes/default.json`).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh -DBUILD_TESTING=OFF
if (($# == 0)); then set -- edit scenes/default.json; fi
exec build/bin/quadplan "$@"
