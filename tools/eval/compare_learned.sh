#!/usr/bin/env bash
# The learned methods' evaluation (docs/methods/tnnd.md, docs/methods/rae.md): `rtdenoise
# compare` on every held-out test scene of a data set, tnnd and rae beside accumulate, svgf and
# bmfr, plus tnnd with its temporal accumulation in front; then the Table 3.1-style summary
# (SSIM per scene, ms per frame).
#
#   bash tools/eval/compare_learned.sh [DATA=build/data/tnnd-v1] [OUT=build/eval/learned]
set -euo pipefail
cd "$(dirname "$0")/../.."
data="${1:-build/data/tnnd-v1}"
out="${2:-build/eval/learned}"
cli=build/release/apps/rtdenoise
mkdir -p "$out"
for dir in "$data"/test/*/; do
  scene=$(basename "$dir")
  "$cli" compare --input "$dir" --reference "$dir/reference" --methods accumulate,svgf,bmfr,tnnd,rae \
    --output "$out/$scene" --overwrite --threads 2 > "$out-$scene.log" 2>&1 || { cat "$out-$scene.log"; exit 1; }
  "$cli" compare --input "$dir" --reference "$dir/reference" --methods tnnd --set tnnd.accumulate=true \
    --output "$out/$scene-tnnd-accumulate" --overwrite --threads 2 > "$out-$scene-acc.log" 2>&1 || { cat "$out-$scene-acc.log"; exit 1; }
done
/usr/bin/python3 tools/eval/learned_table.py "$out"
