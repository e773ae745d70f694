#!/usr/bin/env bash
# Installs what is missing, builds (Release) and runs the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake --preset release
cmake --build build/release -j"$(nproc)"
ctest --preset release -j"$(nproc)"
