#!/usr/bin/env python3
"""Trains the monocular depth prior on valerant_dataset shards and exports it for
OpenCV's DNN module. Runs the same on CPU and CUDA (bf16 autocast there).

  train_depth.py --train 'data/train/*.zip' --val 'data/val/*.zip' --out runs/depth --minutes 20

The weights kept are those of the best validation by AbsRel: on --select-maps (training
maps held out of training) where given, else on --val, which is then no longer an
unbiased measure. With --keep last they are the weights at the end instead (with --ema,
the averaged ones): no selection set picks them, so none can pick them badly.

Writes to --out: log.csv, depth_prior.pt (the kept weights),
depth_prior.onnx (verified in cv2.dnn), metrics.json, curves.png, samples.png."""
import argparse
import csv
import json
import math
import os
import random
import shlex
import sys
import time

import numpy as np
import torch

from valerant_learn.augment import augment
from valerant_learn.depth_net import INPUT_SCALES, DepthNet, count_macs, count_parameters
from valerant_learn.frame_size import parse_size, resize_frames
from valerant_learn.losses import LOSSES, SKY_DEPTH_M, gradient_matching_loss, training_loss
from valerant_learn.metrics import METRIC_MAX_M, METRIC_MIN_M, average, frame_calibration, frame_metrics, summarize
from valerant_learn.onnx_export import FORMAT_VERSION, export_onnx
from valerant_learn.plots import plot_curves, plot_samples
from valerant_learn.shards import check_same_camera, load_shards
from valerant_learn.training import device_name, expand_globs, learning_rate, pick_device, sha256
from valerant_learn.weight_average import WeightAverage

WEIGHT_DECAY = 0.01
# The NLL's exp(-s) factor (and the AbsRel term's exp(e)) can make rare, very large gradients.
GRAD_CLIP_NORM = 1.0
EVAL_BATCH = 256
TRAIN_EVAL_FRAMES = 1000
SAMPLE_FRAMES = 4
VERIFY_FRAMES = 8
KEEP_CHOICES = ("best", "last")
LOG_COLUMNS = ["step", "seconds", "train_loss", "val_abs_rel", "val_delta1", "select_abs_rel", "select_delta1"]


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--train", nargs="+", required=True, metavar="GLOB", help="training shards (zip)")
    parser.add_argument("--val", nargs="+", required=True, metavar="GLOB",
                        help="validation shards; their maps must not appear in --train")
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder (created)")
    budget = parser.add_mutually_exclusive_group(required=True)
    budget.add_argument("--minutes", type=float, help="wall-clock training budget")
    budget.add_argument("--steps", type=int, help="number of optimiser steps")
    parser.add_argument("--batch", type=int, default=512,
                        help="frames a step (an H100 runs 512 about as fast as 128)")
    parser.add_argument("--lr", type=float, default=2e-3, help="peak AdamW learning rate")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--device", choices=["auto", "cpu", "cuda"], default="auto")
    parser.add_argument("--eval-every", type=int, default=500, metavar="N", help="validate every N steps")
    parser.add_argument("--workers", type=int, default=min(8, os.cpu_count() or 1),
                        help="threads decoding the shards' images")
    parser.add_argument("--select-maps", metavar="MAP,...",
                        help="training maps held out of training to pick the kept weights by "
                             "(without it --val picks them)")
    parser.add_argument("--loss", choices=LOSSES, default="laplace",
                        help="laplace: the Laplace NLL of ln depth; decoupled: |ln error| + AbsRel for the "
                             "depth, the NLL on the detached error for ln b (valerant_learn/losses.py)")
    parser.add_argument("--global-context", action="store_true",
                        help="add a summary of the whole frame to the encoder's output "
                             "(valerant_learn/depth_net.py, GlobalContext)")
    parser.add_argument("--column-context", action="store_true",
                        help="add a summary of each image column to the stride-8 decoder features "
                             "(valerant_learn/depth_net.py, ColumnContext)")
    parser.add_argument("--width-multiplier", type=float, default=1.0, metavar="M",
                        help="every encoder and decoder width times M, rounded to a multiple of 8 "
                             "(valerant_learn/depth_net.py, scaled_channels); the time a frame grows about "
                             "as M squared")
    parser.add_argument("--deep-blocks", type=int, default=0, metavar="N",
                        help="N more stride-1 blocks at the end of the stride-16 and of the stride-32 encoder "
                             "stage each (valerant_learn/depth_net.py)")
    parser.add_argument("--gradient-weight", type=float, default=0.0, metavar="W",
                        help="add W times the multi-scale gradient-matching term of the ln-depth error "
                             "(valerant_learn/losses.py, gradient_matching_loss); 0: none")
    parser.add_argument("--ema", type=float, metavar="DECAY",
                        help="validate and keep an exponential moving average of the weights "
                             "(valerant_learn/weight_average.py), e.g. 0.999")
    parser.add_argument("--keep", choices=KEEP_CHOICES, default="best",
                        help="best: the weights of the best validation (above); last: the weights at "
                             "the end of training (with --ema, the averaged ones)")
    parser.add_argument("--input-scale", type=int, choices=INPUT_SCALES, default=1,
                        help="the net reads frames of this many times its output size "
                             "(valerant_learn/depth_net.py, InputStem)")
    parser.add_argument("--output-size", metavar="WxH",
                        help="the net's output size (default: the shards' size over --input-scale); the "
                             "shards' colour and depth are resized to the net's sizes "
                             "(valerant_learn/frame_size.py)")
    parser.add_argument("--floor-prior", action="store_true",
                        help="predict ln depth relative to the floor-plane depth of each image row "
                             "(valerant_learn/floor_prior.py) instead of outright")
    args = parser.parse_args(argv)
    for name in ("steps", "batch", "eval_every", "workers"):
        value = getattr(args, name)
        if value is not None and value < 1:
            parser.error("--%s must be at least 1" % name.replace("_", "-"))
    if args.minutes is not None and not args.minutes > 0:
        parser.error("--minutes must be positive")
    if not args.lr > 0:
        parser.error("--lr must be positive")
    if args.deep_blocks < 0:
        parser.error("--deep-blocks must be at least 0")
    if not args.gradient_weight >= 0:
        parser.error("--gradient-weight must be at least 0, got %r" % args.gradient_weight)
    if args.ema is not None and not 0 < args.ema < 1:
        parser.error("--ema must be between 0 and 1, got %r" % args.ema)
    if args.output_size is not None:
        try:
            args.output_size = parse_size(args.output_size)
        except ValueError as error:
            parser.error("--output-size: %s" % error)
    if args.select_maps is not None:
        args.select_maps = [name for name in args.select_maps.split(",") if name]
        if not args.select_maps:
            parser.error("--select-maps names no map")
    return args


def take_frames(data, keep):
    """The frames of a load_shards() result where keep (bool [N]) holds, its
    meta's maps narrowed to theirs."""
    part = {name: value[keep] for name, value in data.items() if name != "meta"}
    part["meta"] = dict(data["meta"], maps=sorted(set(part["map"].tolist())))
    return part


def split_selection(train, select_maps):
    """(training frames, selection frames): the frames of select_maps go to the
    selection set. Raises ValueError naming a map the training shards lack, or when
    nothing would be left to train on."""
    missing = [name for name in select_maps if name not in train["meta"]["maps"]]
    if missing:
        raise ValueError("--select-maps %s: not in the training shards" % ", ".join(missing))
    chosen = np.isin(train["map"], select_maps)
    if chosen.all():
        raise ValueError("--select-maps takes every training map: nothing is left to train on")
    return take_frames(train, ~chosen), take_frames(train, chosen)


def load_split(args):
    """Loads --train and --val, and splits --select-maps off the training frames
    (None without them); raises ValueError on anything that makes the split
    unusable."""
    train = load_shards(expand_globs(args.train, "--train"), args.workers)
    val = load_shards(expand_globs(args.val, "--val"), args.workers)
    select = None
    if args.select_maps is not None:
        train, select = split_selection(train, args.select_maps)
    shared = sorted(set(train["meta"]["maps"]) & set(val["meta"]["maps"]))
    if shared:
        raise ValueError("val maps overlap train maps: %s (val must measure maps the net never saw)"
                         % ", ".join(shared))
    check_same_camera("the train shards", train["meta"], "the val shards", val["meta"])
    for option, data in (("--train", train), ("--val", val)):
        if not np.isfinite(data["depth"]).any():
            raise ValueError("%s shards hold no depth at all (every pixel is sky)" % option)
    meta = train["meta"]
    output_size = args.output_size or (meta["width"] // args.input_scale, meta["height"] // args.input_scale)
    train, val = (resize_frames(data, output_size, args.input_scale, "the %s shards" % option)
                  for option, data in (("--train", train), ("--val", val)))
    if select is not None:
        select = resize_frames(select, output_size, args.input_scale, "the --select-maps frames")
    return train, val, select


class Frames:
    """One split on the training device: uint8 RGB and float depth, loaded once."""

    def __init__(self, data, device):
        self.rgb = torch.from_numpy(data["rgb"]).to(device)
        self.depth = torch.from_numpy(data["depth"]).to(device)
        self.kind, self.map, self.key = data["kind"], data["map"], data["key"]
        self.meta = data["meta"]
        self.count = len(self.kind)


def as_input(rgb):
    """uint8 [N,H,W,3] -> float [N,3,H,W] in [0,1]. The permuted view is already
    channels_last in memory, which the convolutions prefer."""
    return rgb.permute(0, 3, 1, 2).float().div(255).contiguous(memory_format=torch.channels_last)


def batch_indices(count, batch, generator):
    """Endless training batches: every frame once an epoch, a fresh order each epoch.
    Drawn on the generator's device, so a CUDA run never waits for a host copy."""
    device = generator.device
    pending = torch.empty(0, dtype=torch.long, device=device)
    while True:
        while len(pending) < batch:
            pending = torch.cat([pending, torch.randperm(count, generator=generator, device=device)])
        yield pending[:batch]
        pending = pending[batch:]


def predict(model, rgb):
    """(ln depth, ln b) as float32 [N,H,W], in eval mode and full precision (the
    deployed model runs in float32 too)."""
    model.eval()
    with torch.no_grad():
        output = model(as_input(rgb)).float()
    model.train()
    return output[:, 0], output[:, 1]


def evaluate(model, frames, indices):
    """Per-frame metrics (metrics.frame_metrics and frame_calibration) of the
    frames indices."""
    parts = []
    for start in range(0, len(indices), EVAL_BATCH):
        chunk = indices[start:start + EVAL_BATCH]
        log_depth, log_scale = predict(model, frames.rgb[chunk])
        part = frame_metrics(torch.exp(log_depth), frames.depth[chunk])
        part.update(frame_calibration(log_depth, log_scale, frames.depth[chunk]))
        parts.append(part)
    return {name: np.concatenate([part[name] for part in parts]) for name in parts[0]}


def save_checkpoint(model, state, step, keep, path):
    """The kept weights with what it takes to rebuild the net and how they were kept."""
    torch.save({"state_dict": {k: v.cpu() for k, v in state.items()},
                "height": model.height, "width": model.width, "step": step, "keep": keep,
                "floor_prior": floor_prior_camera(model),
                "global_context": model.global_context is not None,
                "column_context": model.column_context is not None,
                "width_multiplier": model.width_multiplier, "deep_blocks": model.deep_blocks,
                "input_scale": model.input_scale}, path)


def train(model, train_frames, val_frames, select_frames, args, device, out_dir):
    """The training loop. Returns (log rows, best step, kept step, steps, seconds)
    and leaves the kept weights (with --ema, of the averaged net) loaded in model
    and saved to depth_prior.pt: with --keep best those of the best AbsRel on
    select_frames (on val_frames where that is None), with --keep last those at the
    end. The best step is reported either way."""
    loss_function = training_loss(args.loss)
    weight_average = None if args.ema is None else WeightAverage(model, args.ema)
    judged = model if weight_average is None else weight_average.model
    decay = [p for p in model.parameters() if p.ndim > 1]
    no_decay = [p for p in model.parameters() if p.ndim <= 1]  # BatchNorm and biases
    optimizer = torch.optim.AdamW([{"params": decay, "weight_decay": WEIGHT_DECAY},
                                   {"params": no_decay, "weight_decay": 0.0}], lr=args.lr)
    batches = batch_indices(train_frames.count, args.batch, torch.Generator(device).manual_seed(args.seed))
    val_indices = torch.arange(val_frames.count, device=device)
    select_indices = None if select_frames is None else torch.arange(select_frames.count, device=device)
    budget_s = args.minutes * 60 if args.minutes is not None else None
    rows, best = [], {"abs_rel": math.inf, "step": 0, "state": None}
    checkpoint_path = os.path.join(out_dir, "depth_prior.pt")
    loss_sum, loss_steps, step = torch.zeros((), device=device), 0, 0
    start = time.time()
    with open(os.path.join(out_dir, "log.csv"), "w", newline="") as log_file:
        log = csv.DictWriter(log_file, LOG_COLUMNS)
        log.writeheader()

        def validate():
            nonlocal loss_sum, loss_steps
            figures = average(evaluate(judged, val_frames, val_indices))
            row = {"step": step, "seconds": round(time.time() - start, 2),
                   "train_loss": float(loss_sum) / loss_steps,
                   "val_abs_rel": figures["abs_rel"], "val_delta1": figures["delta1"],
                   "select_abs_rel": "", "select_delta1": ""}
            if select_frames is not None:
                selection = average(evaluate(judged, select_frames, select_indices))
                row.update(select_abs_rel=selection["abs_rel"], select_delta1=selection["delta1"])
            else:
                selection = figures
            loss_sum, loss_steps = torch.zeros((), device=device), 0
            rows.append(row)
            log.writerow(row)
            log_file.flush()
            improved = selection["abs_rel"] < best["abs_rel"]
            if improved:
                best.update(abs_rel=selection["abs_rel"], step=step)
                if args.keep == "best":
                    best["state"] = {k: v.detach().clone() for k, v in judged.state_dict().items()}
                    save_checkpoint(model, best["state"], step, args.keep, checkpoint_path)
            print("step %d  %.1f s  lr %.2e  train loss %.4f  val AbsRel %.4f  delta1 %.4f%s%s"
                  % (step, row["seconds"], optimizer.param_groups[0]["lr"], row["train_loss"],
                     figures["abs_rel"], figures["delta1"],
                     "" if select_frames is None else "  select AbsRel %.4f  delta1 %.4f"
                     % (selection["abs_rel"], selection["delta1"]),
                     "  (best)" if improved else ""), flush=True)

        model.train()
        while True:
            progress = step / args.steps if budget_s is None else (time.time() - start) / budget_s
            if step > 0 and progress >= 1:
                break
            for group in optimizer.param_groups:
                group["lr"] = learning_rate(args.lr, progress)
            indices = next(batches)
            rgb, depth = augment(as_input(train_frames.rgb[indices]), train_frames.depth[indices])
            with torch.autocast(device_type=device.type, dtype=torch.bfloat16, enabled=device.type == "cuda"):
                output = model(rgb.contiguous(memory_format=torch.channels_last))
            loss = loss_function(output, depth)
            if args.gradient_weight > 0:
                loss = loss + args.gradient_weight * gradient_matching_loss(output, depth)
            optimizer.zero_grad(set_to_none=True)
            loss.backward()
            torch.nn.utils.clip_grad_norm_(model.parameters(), GRAD_CLIP_NORM)
            optimizer.step()
            if weight_average is not None:
                weight_average.update(model)
            loss_sum += loss.detach()
            loss_steps += 1
            step += 1
            if step % args.eval_every == 0:
                validate()
        if loss_steps:
            validate()
    seconds = time.time() - start
    if not math.isfinite(best["abs_rel"]):
        raise RuntimeError("validation never gave a finite AbsRel: training diverged")
    if args.keep == "best":
        model.load_state_dict(best["state"])
        return rows, best["step"], best["step"], step, seconds
    if judged is not model:
        model.load_state_dict(judged.state_dict())
    save_checkpoint(model, model.state_dict(), step, args.keep, checkpoint_path)
    return rows, best["step"], step, step, seconds


def floor_prior_camera(model):
    """The camera the model's floor prior was built for (DepthNet's floor_prior
    argument), None without one."""
    return None if model.floor_prior is None else dict(model.floor_prior.camera)


def write_samples(model, frames, path):
    chosen = np.unique(np.linspace(0, frames.count - 1, min(SAMPLE_FRAMES, frames.count)).astype(int))
    indices = torch.from_numpy(chosen).to(frames.rgb.device)
    log_depth, log_scale = predict(model, frames.rgb[indices])
    titles = ["%s, %s, key '%s', frame %d" % (frames.map[i], frames.kind[i], frames.key[i], i) for i in chosen]
    plot_samples(frames.rgb[indices].cpu().numpy(), frames.depth[indices].cpu().numpy(),
                 torch.exp(log_depth).cpu().numpy(), log_scale.cpu().numpy(), titles, path,
                 (METRIC_MIN_M, METRIC_MAX_M))


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    args = parse_args(argv)
    random.seed(args.seed)
    np.random.seed(args.seed)
    torch.manual_seed(args.seed)
    try:
        device = pick_device(args.device)
        train_data, val_data, select_data = load_split(args)
        meta = train_data["meta"]
        model = DepthNet(meta["height"], meta["width"], meta if args.floor_prior else None, args.global_context,
                         args.column_context, args.width_multiplier, args.deep_blocks, args.input_scale)
    except ValueError as error:
        sys.exit("train_depth: error: %s" % error)
    os.makedirs(args.out, exist_ok=True)
    for name, data in (("train", train_data), ("val", val_data), ("select", select_data)):
        if data is None:
            continue
        print("%s: %d frames from %d shards, maps %s" % (name, len(data["kind"]), len(data["meta"]["shards"]),
                                                         ", ".join(data["meta"]["maps"])), flush=True)
    parameters = count_parameters(model)
    macs = count_macs(model)
    print("model: %d parameters, %.1f M multiply-adds a frame; device %s"
          % (parameters, macs / 1e6, device_name(device)), flush=True)
    train_frames, val_frames = Frames(train_data, device), Frames(val_data, device)
    select_frames = None if select_data is None else Frames(select_data, device)
    model = model.to(device).to(memory_format=torch.channels_last)

    rows, best_step, kept_step, steps, seconds = train(model, train_frames, val_frames, select_frames, args,
                                                       device, args.out)

    val_summary = summarize(evaluate(model, val_frames, torch.arange(val_frames.count, device=device)),
                            val_frames.kind, val_frames.map)
    subset = torch.randperm(train_frames.count, generator=torch.Generator().manual_seed(args.seed))
    subset = subset[:TRAIN_EVAL_FRAMES].sort().values
    chosen = subset.numpy()
    train_summary = summarize(evaluate(model, train_frames, subset.to(device)),
                              train_frames.kind[chosen], train_frames.map[chosen])
    select_summary = None if select_frames is None else summarize(
        evaluate(model, select_frames, torch.arange(select_frames.count, device=device)),
        select_frames.kind, select_frames.map)

    onnx_path = os.path.join(args.out, "depth_prior.onnx")
    verify_rgb = as_input(val_frames.rgb[:VERIFY_FRAMES]).cpu().contiguous().numpy()
    onnx_report = export_onnx(model, onnx_path, verify_rgb, {
        "sky_depth_m": SKY_DEPTH_M, "fx": meta["fx"], "fy": meta["fy"], "cx": meta["cx"], "cy": meta["cy"],
        "eye_height_m": meta["eye_height_m"], "floor_prior": "yes" if args.floor_prior else "no",
        "global_context": "yes" if args.global_context else "no",
        "column_context": "yes" if args.column_context else "no", "loss": args.loss,
        "width_multiplier": args.width_multiplier, "deep_blocks": args.deep_blocks,
        "gradient_weight": args.gradient_weight, "input_scale": args.input_scale,
        "keep": args.keep, "kept_step": kept_step,
        "train_maps": ",".join(meta["maps"]), "val_abs_rel": val_summary["all"]["abs_rel"]})
    print("exported %s; cv2.dnn vs torch max |diff| ln depth %.2e, ln b %.2e"
          % (onnx_path, onnx_report["max_abs_diff_log_depth"], onnx_report["max_abs_diff_log_scale"]), flush=True)

    metrics = {
        "format": FORMAT_VERSION,
        "val": val_summary,
        "train_subset": train_summary,
        "select": select_summary,
        "keep": args.keep,
        "picked_by": "select" if select_frames is not None else "val",
        "loss": args.loss,
        "global_context": args.global_context,
        "column_context": args.column_context,
        "width_multiplier": args.width_multiplier,
        "deep_blocks": args.deep_blocks,
        "gradient_weight": args.gradient_weight,
        "ema": args.ema,
        "sky_depth_m": SKY_DEPTH_M,
        "metric_depth_range_m": [METRIC_MIN_M, METRIC_MAX_M],
        "floor_prior": floor_prior_camera(model),
        "parameters": parameters,
        "macs_per_frame": macs,
        "flops_per_frame": 2 * macs,
        "input_scale": args.input_scale,
        "input_width": model.input_width,
        "input_height": model.input_height,
        "output_width": model.width,
        "output_height": model.height,
        "steps": steps,
        "best_step": best_step,
        "kept_step": kept_step,
        "train_seconds": round(seconds, 2),
        "batch": args.batch,
        "lr": args.lr,
        "seed": args.seed,
        "device": device_name(device),
        "torch_version": torch.__version__,
        "command_line": shlex.join([sys.argv[0]] + argv),
        "train_frames": train_frames.count,
        "val_frames": val_frames.count,
        "select_frames": 0 if select_frames is None else select_frames.count,
        "select_maps": [] if select_frames is None else select_frames.meta["maps"],
        "train_maps": meta["maps"],
        "val_maps": val_frames.meta["maps"],
        "train_shards": meta["shards"],
        "val_shards": val_frames.meta["shards"],
        "onnx_sha256": sha256(onnx_path),
        "onnx_check": onnx_report,
    }
    with open(os.path.join(args.out, "metrics.json"), "w") as handle:
        json.dump(metrics, handle, indent=1)
    plot_curves(rows, os.path.join(args.out, "curves.png"))
    write_samples(model, val_frames, os.path.join(args.out, "samples.png"))
    rotation = val_summary["rotate"]["abs_rel"]
    print("done: kept step %d (%s; best step %d) of %d in %.0f s; val AbsRel %.4f delta1 %.4f, "
          "rotation frames' AbsRel %s; wrote %s"
          % (kept_step, args.keep, best_step, steps, seconds, val_summary["all"]["abs_rel"],
             val_summary["all"]["delta1"], "none" if rotation is None else "%.4f" % rotation, args.out), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
