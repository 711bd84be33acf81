#!/usr/bin/env bash
# Renders the world model's data set (models/world_model.md) into data/ (git-ignored):
# consecutive frames (--every 1) of the five candidates from one spawn, one full turn
# in place and five 64-frame random walks per training map, and the same from two
# spawns and two walks per evaluation map; then cuts the training shards into parts
# and packs them into data/wmc1 .. data/wmc7, one folder per call to the GPU host
# (each under 52 MiB, which leaves room for the working tree in a call's 64 MiB).
#   learn/make_world_data.sh            (about 10 minutes on 2 cores)
# Then, on the GPU host, one call per folder, back to back:
#   DATA=data/wmcN VDATA=/root/wmdata RUNS=/root/wm_runs TRAINER=train_world_model.py learn/gpu_train.sh stage
# and with the last folder `start NAME MINUTES` instead of `stage` (options: see models/world_model.md).
set -euo pipefail
source "$(dirname "$0")/../scripts/env.sh"
valerant_source_workspace  # the tool finds its default config through the sourced workspace
tool="$VALERANT_BUILD/devel/lib/valerant/valerant_dataset"
cd "$VALERANT_ROOT"
sampling=(--walk-frames 64 --every 1 --shard-mib 58)
"$tool" --split train --spawns 1 --rotations 1 --walks 5 --seed 11 "${sampling[@]}" --out data/wm_train > data/wm_train.json
"$tool" --split evaluation --spawns 2 --walks 2 --seed 12 --rotations 0 "${sampling[@]}" --out data/wm_eval \
  > data/wm_eval.json
parts=data/wm_parts
for shard in data/wm_train/train-00[0-3].zip; do /usr/bin/python3 learn/split_shard.py "$shard" --parts 3 --out-dir $parts; done
pack() {  # pack FOLDER FILE...: hard links, so the parts are stored once
  mkdir -p "data/$1"
  local folder=$1
  shift
  ln -f "$@" "data/$folder/"
}
rm -rf data/wmc[0-9]
pack wmc1/eval data/wm_eval/evaluation-000.zip
pack wmc1/train_a $parts/train-000-0.zip
pack wmc2/train_b $parts/train-002-1.zip $parts/train-002-2.zip
pack wmc3/train_c $parts/train-000-1.zip $parts/train-003-2.zip
pack wmc4/train_d $parts/train-000-2.zip $parts/train-001-2.zip
pack wmc5/train_e $parts/train-001-0.zip $parts/train-002-0.zip
pack wmc6/train_f $parts/train-001-1.zip $parts/train-003-0.zip
pack wmc7/train_g $parts/train-003-1.zip data/wm_train/train-004.zip
du -sh data/wmc[0-9]
