#!/usr/bin/env bash
# Installs what is missing, builds (Release) and runs the main job.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake --preset release
cmake --build build/release -j"$(nproc)"
if build/release/apps/rtdenoise demo --help >/dev/null 2>&1; then
  exec build/release/apps/rtdenoise demo --output out/demo --overwrite
fi
# Until the demo exists: denoise the bundled Blender Cycles fixture.
build/release/apps/rtdenoise denoise --method accumulate --input tests/fixtures/blender --output out/fixture-accumulate
echo "result: $(pwd)/out/fixture-accumulate"
