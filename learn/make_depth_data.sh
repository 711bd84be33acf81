#!/usr/bin/env bash
# Renders the depth prior's data set (models/depth_prior.md) into data/ (git-ignored):
# the training maps in two halves (odd and even lines of the sorted list), each small
# enough to travel to the GPU host in parts, once as the maps look and once with their
# textures randomised (the same maps, other places and views), and the evaluation maps'
# shard.
#   learn/make_depth_data.sh            (about 2 minutes a half on 2 cores)
set -euo pipefail
source "$(dirname "$0")/../scripts/env.sh"
tool="$VALERANT_BUILD/devel/lib/valerant/valerant_dataset"
cd "$VALERANT_ROOT"
maps=$("$tool" --list-maps --split train)
a=$(echo "$maps" | awk 'NR % 2 == 1' | paste -sd,)
b=$(echo "$maps" | awk 'NR % 2 == 0' | paste -sd,)
"$tool" --out data/train_a --maps "$a" --seed 1 > data/train_a.json &
"$tool" --out data/train_b --maps "$b" --seed 1 > data/train_b.json &
wait
"$tool" --out data/train_rand_a --maps "$a" --seed 4 --texture-shuffle 0.9 > data/train_rand_a.json &
"$tool" --out data/train_rand_b --maps "$b" --seed 4 --texture-shuffle 0.9 > data/train_rand_b.json &
wait
"$tool" --out data/eval --split evaluation --seed 2 > data/eval.json
