#!/usr/bin/env bash
# README command 1: install dependencies, build, and open Quadplan on the default scene.
# Extra arguments go to quadplan (e.g. `scripts/run.sh info scenes/default.json`).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh -DBUILD_TESTING=OFF
# No arguments: the editor on the bundled default scene, untitled (Save asks for a name instead
# of overwriting scenes/default.json).
if (($# == 0)); then set -- edit; fi
exec build/bin/quadplan "$@"
