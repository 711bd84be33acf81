#!/usr/bin/env bash
# The depth prior's training run on the GPU host (the `device` tool). One call carries
# at most 64 MiB and runs at most 10 minutes, so the shards travel in parts and the
# training outlives a call: each call stages the shards it carries under $VDATA
# (outside the working tree; kept while the machine stays warm), `start` launches the
# training in the background and returns, `wait` calls keep the machine warm while it
# runs, and `collect` waits for the end and copies the results to $OUT/run.
#   learn/gpu_train.sh stage             copy the carried $DATA/train_*/*.zip and $DATA/eval/*.zip to $VDATA
#   learn/gpu_train.sh start MINUTES [OPTION...]
#                                        stage, then train for MINUTES (in the background);
#                                        OPTIONs go to train_depth.py (e.g. --floor-prior)
#   learn/gpu_train.sh wait SECONDS      wait that long (or to the end), print the log's tail
#   learn/gpu_train.sh collect           wait for the training (at most 540 s), copy its files to $OUT/run
# Make the calls back to back and keep each but the last short (`wait 60`): the machine
# goes back when idle for 30 s, and once that happened after a 574 s call, taking the
# training with it. Call `collect` when the training has less than 540 s to go.
# DATA (default data) may name several folders, space-separated, relative to the folder
# above learn/: each call may carry other parts (a folder train_X of one call and one of
# the same name in another call must not hold shards of the same name).
set -euo pipefail
cd "$(dirname "$0")/.."
VDATA=${VDATA:-/root/vdata}
RUN=${RUN:-/root/depth_run}
mode=${1:-stage}
case $mode in stage | start | wait | collect) ;; *) echo "gpu_train.sh: unknown mode '$mode' (stage, start, wait or collect)" >&2; exit 2 ;; esac
wait_for_training() {  # at most $1 seconds
  local deadline=$((SECONDS + $1))
  while [ ! -f "$RUN.done" ] && [ $SECONDS -lt $deadline ] && pgrep -f learn/train_depth.py > /dev/null; do sleep 5; done
  tail -n 30 "$RUN.log"
}
if [ "$mode" = wait ]; then
  [[ ${2:-} =~ ^[0-9]+$ ]] || { echo "gpu_train.sh wait: SECONDS must be a whole number, got '${2:-}'" >&2; exit 2; }
  wait_for_training "$2"
  exit 0
fi
if [ "$mode" = collect ]; then
  wait_for_training 540
  [ -f "$RUN.done" ] || { echo "training still running"; exit 3; }
  mkdir -p "$OUT/run"
  cp "$RUN"/log.csv "$RUN"/metrics.json "$RUN"/curves.png "$RUN"/samples.png "$RUN"/depth_prior.onnx "$OUT/run/"
  cp "$RUN.log" "$OUT/train.log"
  exit "$(cat "$RUN.done")"
fi
mkdir -p "$VDATA/train" "$VDATA/eval"
for root in ${DATA:-data}; do
  for f in "$root"/train_*/*.zip; do [ -f "$f" ] && cp "$f" "$VDATA/train/$(basename "$(dirname "$f")")_$(basename "$f")"; done
  for f in "$root"/eval/*.zip; do [ -f "$f" ] && cp "$f" "$VDATA/eval/"; done
done
echo "staged: $(ls "$VDATA/train" | wc -l) training shards, $(ls "$VDATA/eval" | wc -l) evaluation shards"
du -sh "$VDATA/train" "$VDATA/eval"
python3 -c 'import torch, cv2, onnx; print("torch", torch.__version__, "cuda", torch.cuda.is_available(), torch.cuda.get_device_name(0) if torch.cuda.is_available() else "-", "cv2", cv2.__version__, "onnx", onnx.__version__)'
[ "$mode" = start ] || exit 0
rm -rf "$RUN" "$RUN.done"
# setsid: the training must outlive this call's process group.
setsid bash -c 'PYTHONUNBUFFERED=1 python3 learn/train_depth.py --train "$2/train/*.zip" --val "$2/eval/*.zip" --out "$1" \
   --minutes "$0" --batch 256 --workers 16 --seed 0 --device cuda "${@:3}" > "$1.log" 2>&1; echo $? > "$1.done"' \
  "${2:-12}" "$RUN" "$VDATA" "${@:3}" < /dev/null &
sleep 5
wait_for_training 20
