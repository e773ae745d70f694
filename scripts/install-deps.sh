#!/usr/bin/env bash
# Installs every Debian 12 package rtdenoise needs to build, test and run (as root, or with
# sudo). Does nothing for packages already installed, so it is cheap to run again.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  libopenexr-dev libimath-dev libtbb-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libembree-dev libtinygltf-dev libstb-dev
  glslc libvulkan-dev mesa-vulkan-drivers vulkan-tools
  # The sanitizer stage of scripts/test.sh: ASan/UBSan/LSan and libFuzzer (llvm-14 for symbolized reports).
  clang-14 libclang-rt-14-dev llvm-14
  chromium help2man libwebp-dev
  # Per-buffer input files other than EXR (PFM, HDR, PNG, TIFF; src/io/oiio) and their tests (oiiotool).
  libopenimageio-dev openimageio-tools
  # Training of the learned methods and its tests only (python/rtdenoise_train, /usr/bin/python3).
  python3-torch python3-numpy python3-matplotlib
  # Python bindings (bindings/python: pybind11 module for /usr/bin/python3) and their tests.
  python3-dev pybind11-dev python3-pybind11 python3-pytest
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO=sudo
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
