#!/usr/bin/env bash
# Installs what is missing, builds (Release) and runs the whole test suite, then the sanitizer
# stage: the library, CLI and tests built with ASan + UBSan + LeakSanitizer (clang 14, the `asan`
# preset) run the whole suite again (Vulkan on lavapipe included), and each libFuzzer target runs
# a fixed number of mutations from its seeds and regression inputs (scripts/fuzz.sh, ~15-20 s
# each). RTD_SANITIZERS=0 skips the stage; CI (.ci/run) runs both. docs/input-validation.md has
# what each stage covers and costs.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
start=$SECONDS
cmake --preset release
cmake --build build/release -j"$(nproc)"
ctest --preset release -j"$(nproc)"
echo "release stage: $((SECONDS - start)) s"
if [ "${RTD_SANITIZERS:-1}" != 0 ]; then
  start=$SECONDS
  cmake --preset asan
  cmake --build build/asan -j"$(nproc)"
  ctest --preset asan -j"$(nproc)"
  scripts/fuzz.sh build/asan
  echo "sanitizer stage: $((SECONDS - start)) s"
fi
