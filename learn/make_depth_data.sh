#!/usr/bin/env bash
# Renders the depth prior's data set (models/depth_prior.md) into data/ (git-ignored):
# the training maps in two halves (odd and even lines of the sorted list), four times
# (other places and views each time): once as the maps look (seed 1) and three times
# with their textures randomised (seed 4 at p 0.9, seeds 5 and 6 at p 1.0); then turns in
# place near walls only, twice (seed 7 as the maps look, seed 8 randomised at p 1.0);
# and the evaluation maps' shard (seed 2). Then it packs them into data/depth_parts/pNN, one
# folder per call to the GPU host (learn/pack_parts.py: each part leaves room for the
# tracked working tree, and 4 MiB more, in a call's 64 MiB).
#   learn/make_depth_data.sh            (about 2 minutes a rendering on 2 cores)
# Then, on the GPU host, one call per folder, back to back:
#   DATA=data/depth_parts/pNN learn/gpu_train.sh stage
# and with the last folder `start NAME MINUTES` instead of `stage` (options: models/depth_prior.md).
set -euo pipefail
source "$(dirname "$0")/../scripts/env.sh"
valerant_source_workspace  # the tool finds its default config through the sourced workspace
tool="$VALERANT_BUILD/devel/lib/valerant/valerant_dataset"
cd "$VALERANT_ROOT"
mkdir -p data
maps=$("$tool" --list-maps --split train)
a=$(echo "$maps" | awk 'NR % 2 == 1' | paste -sd,)
b=$(echo "$maps" | awk 'NR % 2 == 0' | paste -sd,)
render() {  # render NAME SEED [OPTION...]: both halves side by side
  local name=$1 seed=$2
  shift 2
  "$tool" --out "data/${name}_a" --maps "$a" --seed "$seed" "$@" > "data/${name}_a.json" &
  local first=$!
  "$tool" --out "data/${name}_b" --maps "$b" --seed "$seed" "$@" > "data/${name}_b.json" &
  wait $first
  wait $!
}
render train 1
render train_rand 4 --texture-shuffle 0.9
render train_rand5 5 --texture-shuffle 1.0
render train_rand6 6 --texture-shuffle 1.0
walls=(--spawns 0 --rotations 0 --walks 0 --wall-rotations 24)
render train_wall7 7 "${walls[@]}"
render train_wall8 8 "${walls[@]}" --texture-shuffle 1.0
"$tool" --out data/eval --split evaluation --seed 2 > data/eval.json
/usr/bin/python3 learn/pack_parts.py --out data/depth_parts \
  data/train_{,rand_,rand5_,rand6_,wall7_,wall8_}{a,b} data/eval
