#!/usr/bin/env bash
# Renders the world model's data set (models/world_model.md) into data/wm (git-ignored):
# consecutive frames (--every 1) of the five candidates from one spawn, one full turn
# in place and five 64-frame random walks per training map (data/wm/train_wm), and the
# same from two spawns and two walks per evaluation map (data/wm/eval); then packs them
# into data/wm_parts/pNN, one folder per call to the GPU host (learn/pack_parts.py: each
# part leaves room for the tracked working tree, and 4 MiB more, in a call's 64 MiB). The pose_anchor warp's
# depth prior runs at load on the GPU host (valerant_learn/prior_depth.py), not here.
#   learn/make_world_data.sh            (about 12 minutes on 2 cores)
# Then, on the GPU host, one call per folder, back to back:
#   DATA=data/wm_parts/pNN VDATA=/root/wmdata RUNS=/root/wm_runs TRAINER=train_world_model.py learn/gpu_train.sh stage
# and with the last folder `start NAME MINUTES` instead of `stage` (options: docs/world_model.md).
set -euo pipefail
source "$(dirname "$0")/../scripts/env.sh"
valerant_source_workspace  # the tool finds its default config through the sourced workspace
tool="$VALERANT_BUILD/devel/lib/valerant/valerant_dataset"
cd "$VALERANT_ROOT"
sampling=(--walk-frames 64 --every 1 --shard-mib 58)
mkdir -p data/wm
"$tool" --split train --spawns 1 --rotations 1 --walks 5 --seed 11 "${sampling[@]}" --out data/wm/train_wm \
  > data/wm/train_wm.json
"$tool" --split evaluation --spawns 2 --walks 2 --seed 12 --rotations 0 "${sampling[@]}" --out data/wm/eval \
  > data/wm/eval.json
/usr/bin/python3 learn/pack_parts.py --out data/wm_parts data/wm/train_wm data/wm/eval
