#!/usr/bin/env bash
# The GPU benchmark in one command: every Vulkan method (SVGF, BMFR, A-SVGF, TNND, RAE; $METHODS
# to choose) at 1920x1080 (per-pass GPU timestamp medians, "gpu filter" = everything between
# import and export), with the device name; then Gersthofer's stereo pipeline, both eyes at
# 1440x1600 (thesis Table 5.3; $STEREO_SIZE for another). Targets on an H100: SVGF <= 1.0 ms, BMFR <= 1.5 ms (gpu filter).
# Usage: scripts/bench-gpu.sh [WIDTHxHEIGHT] [extra rtdenoise bench options, e.g. --device h100]
# Environment: FRAMES (default 50) and WARMUP (default 10) frames per method; RTD_CLI the CLI to
# run (default build/release/apps/rtdenoise, built first if missing).
# On lavapipe (no GPU) use a small size: it is a CPU emulation.
set -euo pipefail
cd "$(dirname "$0")/.."
size="${1:-1920x1080}"
shift || true
cli=${RTD_CLI:-build/release/apps/rtdenoise}  # RTD_CLI: another build's CLI (scripts/gpu-bundle.sh)
if [ ! -x "$cli" ] && [ -z "${RTD_CLI:-}" ]; then
  cmake --preset release >/dev/null
  cmake --build build/release -j"$(nproc)" --target rtdenoise_cli
fi
$cli devices
command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,clocks.max.sm --format=csv || true
for m in ${METHODS:-svgf bmfr asvgf tnnd rae}; do
  # The progress bar goes to stderr; errors still show (set -e stops on them).
  $cli bench --backend vulkan --method "$m" --size "$size" --frames "${FRAMES:-50}" --warmup "${WARMUP:-10}" "$@"
done
$cli bench --backend vulkan --method svgf --stereo --set variant=gersthofer --size "${STEREO_SIZE:-1440x1600}" \
  --frames "${FRAMES:-50}" --warmup "${WARMUP:-10}" "$@"
