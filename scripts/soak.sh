#!/usr/bin/env bash
# The soak (bench/soak/soak.h): 1000 renderer-made frames (64x48 and 48x32, shots of 100 frames,
# each a camera cut, a resize every two shots, bad pixels in one frame of each shot) through
# every method on each backend, with the resident memory sampled every 25 frames. Fails when an
# output is not finite, a frame from the 70th of a shot on is not within a factor 2 of its
# input's mean, or the resident memory grows by more than 24 MiB after the first 300 frames.
# Not part of the test suite (minutes); tests/reliability/soak_test.cpp runs a short version.
# Usage: scripts/soak.sh [rtd_soak options: --frames N --method M --backend cpu|vulkan]
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -x build/release/bench/rtd_soak ]; then
  cmake --preset release
  cmake --build build/release -j"$(nproc)" --target rtd_soak
fi
exec build/release/bench/rtd_soak "$@"
