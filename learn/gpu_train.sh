#!/usr/bin/env bash
# The learned parts' training runs on the GPU host (the `device` tool): the depth prior
# (learn/train_depth.py) or, with TRAINER=train_world_model.py, the world model. One call carries
# at most 64 MiB and runs at most 10 minutes, so the shards travel in parts and the
# training outlives a call: each call stages the shards it carries under $VDATA
# (outside the working tree; kept while the machine stays warm), `start` launches a
# named run in the background and returns (several runs may share the GPU, each with
# its own options: an ablation trained side by side for the same minutes), `wait`
# calls keep the machine warm while they run, and `collect` waits for their end and
# packs each run's files into $OUT/NAME.tgz (the device tool returns at most 8 files).
#   learn/gpu_train.sh stage             copy the carried $DATA/train_*/*.zip and $DATA/eval/*.zip to $VDATA
#   learn/gpu_train.sh start NAME MINUTES [OPTION...]
#                                        stage, then train run NAME for MINUTES (in the background)
#                                        into $RUNS/NAME; OPTIONs go to $TRAINER after the
#                                        defaults below, so they override them (e.g. --loss decoupled)
#   learn/gpu_train.sh wait SECONDS      wait that long (or to the end of every run), print the logs' tails
#   learn/gpu_train.sh collect           wait for every run (at most 540 s), pack each into $OUT/NAME.tgz
# Make the calls back to back and keep each but the last short (`wait 60`): the machine
# goes back when idle for 30 s, and once that happened after a 574 s call, taking the
# training with it. Call `collect` when the training has less than 540 s to go.
# DATA (default data) may name several folders, space-separated, relative to the folder
# above learn/: each call may carry other parts (a folder train_X of one call and one of
# the same name in another call must not hold shards of the same name).
set -euo pipefail
cd "$(dirname "$0")/.."
VDATA=${VDATA:-/root/vdata}
export TRAINER=${TRAINER:-train_depth.py}
RUNS=${RUNS:-/root/depth_runs}
mode=${1:-stage}
case $mode in stage | start | wait | collect) ;; *) echo "gpu_train.sh: unknown mode '$mode' (stage, start, wait or collect)" >&2; exit 2 ;; esac
runs() { ls -d "$RUNS"/*/ 2> /dev/null | xargs -r -n1 basename; }
running() {  # a run without its .done file whose training process lives
  local name
  for name in $(runs); do
    [ -f "$RUNS/$name.done" ] || ! pgrep -f "out $RUNS/$name " > /dev/null || return 0
  done
  return 1
}
wait_for_training() {  # at most $1 seconds
  local deadline=$((SECONDS + $1)) name
  while running && [ $SECONDS -lt $deadline ]; do sleep 5; done
  for name in $(runs); do echo "== $name"; tail -n 4 "$RUNS/$name.log"; done
}
if [ "$mode" = wait ]; then
  [[ ${2:-} =~ ^[0-9]+$ ]] || { echo "gpu_train.sh wait: SECONDS must be a whole number, got '${2:-}'" >&2; exit 2; }
  wait_for_training "$2"
  exit 0
fi
if [ "$mode" = collect ]; then
  wait_for_training 540
  ! running || { echo "training still running"; exit 3; }
  status=0
  for name in $(runs); do
    [ -f "$RUNS/$name.done" ] || { echo "$name: no exit status (the process died)"; status=1; continue; }
    [ "$(cat "$RUNS/$name.done")" = 0 ] || { echo "$name: exit status $(cat "$RUNS/$name.done")"; status=1; }
    cp "$RUNS/$name.log" "$RUNS/$name/train.log"
    # The world model's weights (world_model.pt, ~5 MB) come back: a later machine continues from them (--init).
    if [ "$TRAINER" = train_world_model.py ]; then keep=(); else keep=(--exclude '*.pt'); fi
    tar -czf "$OUT/$name.tgz" -C "$RUNS" "${keep[@]}" "$name"
  done
  exit $status
fi
# Each `start` stages its call's parts again while earlier runs may still be reading
# them: a shard already there is left alone, a changed one arrives by rename (a run that
# opened the old file keeps reading it; an overwrite in place once broke a run's load).
stage_file() {
  cmp -s "$1" "$2" || { cp "$1" "$2.part" && mv "$2.part" "$2"; }
}
mkdir -p "$VDATA/train" "$VDATA/eval"
for root in ${DATA:-data}; do
  for f in "$root"/train_*/*.zip; do [ -f "$f" ] && stage_file "$f" "$VDATA/train/$(basename "$(dirname "$f")")_$(basename "$f")"; done
  for f in "$root"/eval/*.zip; do [ -f "$f" ] && stage_file "$f" "$VDATA/eval/$(basename "$f")"; done
done
echo "staged: $(ls "$VDATA/train" | wc -l) training shards, $(ls "$VDATA/eval" | wc -l) evaluation shards"
du -sh "$VDATA/train" "$VDATA/eval"
[ "$mode" = start ] || exit 0
name=${2:-}
case $TRAINER in train_depth.py | train_world_model.py) ;; *) echo "gpu_train.sh: TRAINER must be train_depth.py or train_world_model.py, got '$TRAINER'" >&2; exit 2 ;; esac
[[ $name =~ ^[A-Za-z0-9_-]+$ ]] || { echo "gpu_train.sh start: NAME must be letters, digits, _ or -, got '$name'" >&2; exit 2; }
[[ ${3:-} =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "gpu_train.sh start: MINUTES must be a number, got '${3:-}'" >&2; exit 2; }
python3 -c 'import torch, cv2, onnx; print("torch", torch.__version__, "cuda", torch.cuda.is_available(), torch.cuda.get_device_name(0) if torch.cuda.is_available() else "-", "cv2", cv2.__version__, "onnx", onnx.__version__)'
rm -rf "${RUNS:?}/$name" "$RUNS/$name.done"
mkdir -p "$RUNS/$name"
# setsid: the training must outlive this call's process group.
setsid bash -c 'PYTHONUNBUFFERED=1 python3 "learn/$TRAINER" --train "$2/train/*.zip" --val "$2/eval/*.zip" --out "$1" \
   --minutes "$0" --batch 256 --workers 16 --seed 0 --device cuda "${@:3}" > "$1.log" 2>&1; echo $? > "$1.done"' \
  "$3" "$RUNS/$name" "$VDATA" "${@:4}" < /dev/null &
sleep 5
tail -n 5 "$RUNS/$name.log"
