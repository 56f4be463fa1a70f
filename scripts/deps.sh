#!/usr/bin/env bash
# Installs the Debian 12 packages cumulo needs, if any are missing. Idempotent and quiet when all is there.
set -euo pipefail
PKGS=(
  build-essential cmake ninja-build pkg-config git
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools spirv-tools
  glslang-dev glslang-tools libglm-dev libtinygltf-dev nlohmann-json3-dev libstb-dev
  libimgui-dev libglfw3-dev libgtest-dev libgmock-dev libbenchmark-dev libmeshoptimizer-dev
  libopenvdb-dev libtbb-dev libzstd-dev libboost-dev libopenexr-dev
  clang-14 libclang-rt-14-dev libfuzzer-14-dev
  xvfb xauth xdotool
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "cumulo: installing ${#missing[@]} missing Debian packages: ${missing[*]}"
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "cumulo: packages installed."
