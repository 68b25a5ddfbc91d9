#!/usr/bin/env bash
# Installs every Debian 12 package Quadplan needs to build, run and test. Idempotent: when all
# packages are present it touches nothing (and needs no network).
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libosd-dev libglm-dev libtbb-dev nlohmann-json3-dev libcli11-dev libfmt-dev
  libglfw3-dev libimgui-dev libstb-dev
  libvulkan-dev mesa-vulkan-drivers vulkan-tools vulkan-validationlayers vulkan-validationlayers-dev glslc spirv-tools
  libgtest-dev libgmock-dev libbenchmark-dev
  libeigen3-dev libxxhash-dev
  libtinygltf-dev libmeshoptimizer-dev libopenmesh-dev libopenexr-dev  # exports (export/) and reading them back in tests
  python3-dev pybind11-dev python3-numpy python3-pytest python3-matplotlib
  xvfb xauth xdotool imagemagick
  clang libclang-rt-14-dev  # the test command's fuzzing (libFuzzer) and sanitizer runs
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  exit 0
fi

echo "Installing: ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
