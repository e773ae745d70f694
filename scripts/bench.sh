#!/usr/bin/env bash
# Per-pass medians of every method at 1280x720 on the CPU (and on Vulkan when a device is
# present), one method after another in one run, so the figures are comparable.
# Usage: scripts/bench.sh [WIDTHxHEIGHT] [extra rtdenoise bench options]
# RTD_CPU_PATH=sse2|avx2|avx512 forces a CPU path; --threads 1 gives per-pass CPU times that a
# shared machine barely moves (docs/performance.md).
set -euo pipefail
cd "$(dirname "$0")/.."
size="${1:-1280x720}"
shift || true
cli=build/release/apps/rtdenoise
lscpu | grep -E 'Model name' || true
for m in $($cli methods --json - | python3 -c 'import json,sys; print(" ".join(m["name"] for m in json.load(sys.stdin)))'); do
  $cli bench --method "$m" --size "$size" --frames 20 --warmup 5 "$@" 2>/dev/null
done
