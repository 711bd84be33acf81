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
#   learn/make_depth_data.sh --x2       the data of a net that reads frames at twice its output
#                                       size (train_depth.py --input-scale 2, docs/depth_prior.md v12):
#                                       frames at 256 x 192, four renderings (seeds 1, 5, 7 and 8),
#                                       into data/x2 and data/x2/depth_parts (about 5 minutes a
#                                       rendering; about 11 KB a frame, 2.4 times the 128 x 96 frame)
# Then, on the GPU host, one call per folder, back to back:
#   DATA=data/depth_parts/pNN learn/gpu_train.sh stage
# and with the last folder `start NAME MINUTES` instead of `stage` (options: models/depth_prior.md).
set -euo pipefail
source "$(dirname "$0")/../scripts/env.sh"
valerant_source_workspace  # the tool finds its default config through the sourced workspace
tool="$VALERANT_BUILD/devel/lib/valerant/valerant_dataset"
cd "$VALERANT_ROOT"
case ${1:-} in
  "") root=data size=() ;;
  --x2) root=data/x2 size=(--width 256 --height 192) ;;
  *) echo "make_depth_data.sh: unknown option '$1' (none or --x2)" >&2; exit 2 ;;
esac
mkdir -p "$root"
maps=$("$tool" --list-maps --split train)
a=$(echo "$maps" | awk 'NR % 2 == 1' | paste -sd,)
b=$(echo "$maps" | awk 'NR % 2 == 0' | paste -sd,)
renderings=()  # the rendered folders, in order, for pack_parts.py
render() {  # render NAME SEED [OPTION...]: both halves side by side
  local name=$1 seed=$2
  shift 2
  "$tool" --out "$root/${name}_a" --maps "$a" --seed "$seed" "${size[@]}" "$@" > "$root/${name}_a.json" &
  local first=$!
  "$tool" --out "$root/${name}_b" --maps "$b" --seed "$seed" "${size[@]}" "$@" > "$root/${name}_b.json" &
  wait $first
  wait $!
  renderings+=("$root/${name}_a" "$root/${name}_b")
}
all=$([ ${#size[@]} -eq 0 ] && echo yes || true)  # --x2 leaves out seeds 4 and 6
walls=(--spawns 0 --rotations 0 --walks 0 --wall-rotations 24)
render train 1
[ -z "$all" ] || render train_rand 4 --texture-shuffle 0.9
render train_rand5 5 --texture-shuffle 1.0
[ -z "$all" ] || render train_rand6 6 --texture-shuffle 1.0
render train_wall7 7 "${walls[@]}"
render train_wall8 8 "${walls[@]}" --texture-shuffle 1.0
"$tool" --out "$root/eval" --split evaluation --seed 2 "${size[@]}" > "$root/eval.json"
/usr/bin/python3 learn/pack_parts.py --out "$root/depth_parts" "${renderings[@]}" "$root/eval"
