#!/usr/bin/env bash
# Trains a learned method end to end (docs/training.md):
#
#   bash scripts/train.sh <model> [--install]
#
# 1. builds rtdenoise (build/release) if needed;
# 2. renders the data set with `rtdenoise dataset` into $DATA (default build/data/<model>-v1)
#    unless a complete one is there ($DATASET_ARGS, default the configuration the committed
#    weights were trained on);
# 3. trains with python/rtdenoise_train (Debian's /usr/bin/python3 with python3-torch) into
#    $RUN (default build/train/<model>), resuming from its checkpoint if one exists
#    ($TRAIN_ARGS: the model's configuration of the committed weights);
# 4. with --install, copies the weights where the library embeds them
#    (src/methods/<model>/<model>_weights.json) and the loss curve beside docs/methods/.
set -euo pipefail
cd "$(dirname "$0")/.."
model="${1:?usage: scripts/train.sh <model> [--install]}"
install="${2:-}"
case "$model" in
  tnnd)
    : "${DATASET_ARGS:=--seed 1 --procedural 10 --scene data/scenes/props.json --test glossy,dynamic,props --frames 4 --test-frames 6 --size 256x256 --reference-spp 64 --max-reference-spp 256 --tolerance 0.02 --threads 2}"
    : "${TRAIN_ARGS:=--steps 2000 --batch 2 --patch 128 --lr 0.005 --losses mse=1,gradient=0.5 --val-every 25 --checkpoint-every 25 --threads 1}"
    weights_target=src/methods/tnnd/tnnd_weights.json ;;
  rae)
    # The RAE trains on TNND's data set (docs/methods/rae.md "Training").
    : "${DATA:=build/data/tnnd-v1}"
    : "${DATASET_ARGS:=--seed 1 --procedural 10 --scene data/scenes/props.json --test glossy,dynamic,props --frames 4 --test-frames 6 --size 256x256 --reference-spp 64 --max-reference-spp 256 --tolerance 0.02 --threads 2}"
    : "${TRAIN_ARGS:=--steps 3000 --batch 8 --patch 64 --lr 0.002 --val-every 25 --checkpoint-every 25 --val-patches 16 --threads 1 --time-limit 48}"
    weights_target=src/methods/rae/rae_weights.json ;;
  *) echo "unknown model '$model' (expected: tnnd, rae)" >&2; exit 2 ;;
esac
DATA="${DATA:-build/data/$model-v1}"
RUN="${RUN:-build/train/$model}"

if [ ! -x build/release/apps/rtdenoise ]; then
  cmake --preset release >/dev/null
  cmake --build build/release -j2 --target rtdenoise_cli
fi
if ! grep -q '"complete": true' "$DATA/dataset.json" 2>/dev/null; then
  # shellcheck disable=SC2086
  build/release/apps/rtdenoise dataset --output "$DATA" $DATASET_ARGS
fi
# shellcheck disable=SC2086
PYTHONPATH=python /usr/bin/python3 -m rtdenoise_train.train --model "$model" --data "$DATA" --out "$RUN" --resume $TRAIN_ARGS
if [ "$install" = "--install" ]; then
  cp "$RUN/weights.json" "$weights_target"
  cp "$RUN/loss.png" "docs/methods/$model-loss.png"
  cp "$RUN/loss.json" "docs/methods/$model-loss.json"
  echo "installed $weights_target and docs/methods/$model-loss.{png,json}"
fi
