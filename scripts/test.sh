#!/usr/bin/env bash
# Installs what is missing, builds (Release) and runs the whole test suite. RTD_SANITIZERS=1 adds
# the sanitizer stage: the library, CLI and tests built with ASan + UBSan + LeakSanitizer (clang
# 14, the `asan` preset) run the whole suite again (Vulkan on lavapipe included), and each
# libFuzzer target runs for a fixed time (scripts/fuzz.sh). It is off by default until it has
# run green and within CI's time on the current tree (docs/input-validation.md).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake --preset release
cmake --build build/release -j"$(nproc)"
ctest --preset release -j"$(nproc)"
if [ "${RTD_SANITIZERS:-0}" = 1 ]; then
  cmake --preset asan
  cmake --build build/asan -j"$(nproc)"
  ctest --preset asan -j"$(nproc)"
  scripts/fuzz.sh build/asan
fi
