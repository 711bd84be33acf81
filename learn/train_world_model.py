#!/usr/bin/env python3
"""Trains the world model (valerant_learn/world_net.py) on valerant_dataset shards
rendered with `--every 1`, and exports it for OpenCV's DNN module. Runs the same on
CPU and CUDA (bf16 autocast there).

  train_world_model.py --train 'data/wm_train/*.zip' --val 'data/wm_eval/*.zip' --out runs/wm --minutes 12

Each step draws windows of K context frames and --unroll frames to come, and runs
the net autoregressively over them, feeding its own frames back as the backend does,
so that it learns to live with its own errors; the loss is the mean L1 of every
predicted frame plus a structure term (1 - SSIM). The kept weights are the last
ones: --val is measured, never used to choose.

--init starts from the weights of an earlier run's world_model.pt (same context, head,
warp and frame size; a fresh optimiser and schedule). --adversarial-weight W adds W times
the hinge term of a PatchGAN discriminator (valerant_learn/world_discriminator.py),
trained beside the net from --adversarial-start on and shown where the predicted frames
show what no context frame held, so that the fill there gets texture rather than a
smooth mean colour. --discriminator-lead lets the discriminator learn alone for a while
before its term joins the net's loss, --discriminator-steps gives it several updates a
step, and --invented-weight lowers the reconstruction terms' pull towards the mean colour
on the invented pixels while the term runs.

Validation (and the figures of the model card) runs every candidate rollout of the
--val shards from its first frame, the context that frame repeated, and reports PSNR
and SSIM at frames 8, 16, 32, 57 and 97 against the true frames, next to two
baselines: `repeat` (the context frame) and `flat` (the true frame's mean colour).

Writes to --out: log.csv, world_model.pt, world_model.onnx (verified in cv2.dnn),
metrics.json, curves.png, rollouts.png."""
import argparse
import csv
import json
import os
import random
import shlex
import sys
import time

import numpy as np
import torch

from valerant_learn.prior_depth import prior_depths
from valerant_learn.shards import check_same_camera, load_shards
from valerant_learn.training import device_name, expand_globs, learning_rate, pick_device, sha256
from valerant_learn.world_data import WorldWindows
from valerant_learn.world_discriminator import Adversary
from valerant_learn.world_export import export_world_onnx
from valerant_learn.world_metrics import HORIZONS, SSIM_WINDOW, horizon_table, ssim, ssim_map
from valerant_learn.world_net import WorldNet, net_input, rollout, start_state
from valerant_learn.world_warp import WARPS
from valerant_learn.world_plots import plot_world_curves, plot_rollouts

WEIGHT_DECAY = 0.01
GRAD_CLIP_NORM = 1.0
SSIM_WEIGHT = 0.2
VAL_WINDOWS = 256
# A frame shows the discriminator something when at least this share of its pixels was
# invented (a one-pixel column of a 128-pixel-wide frame is 0.8 %).
MIN_INVENTED_SHARE = 0.01
DEFAULT_DEPTH_PRIOR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "models", "depth_prior.onnx")
# What train() saves in world_model.pt; --init reads it back.
CHECKPOINT_KEYS = ("state_dict", "context", "full_res_head", "warp", "camera", "height", "width", "step")
LOG_COLUMNS = ["step", "seconds", "unroll", "train_loss", "val_l1"] + [
    "val_psnr_%d" % h for h in HORIZONS]


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--train", nargs="+", required=True, metavar="GLOB", help="training shards (zip)")
    parser.add_argument("--val", nargs="+", required=True, metavar="GLOB",
                        help="validation shards; their maps must not appear in --train")
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder (created)")
    budget = parser.add_mutually_exclusive_group(required=True)
    budget.add_argument("--minutes", type=float, help="wall-clock training budget")
    budget.add_argument("--steps", type=int, help="number of optimiser steps")
    parser.add_argument("--context", type=int, default=4, help="context frames K")
    parser.add_argument("--unroll", type=int, default=8, help="frames each window predicts autoregressively")
    parser.add_argument("--late-unroll", type=int, default=16,
                        help="frames a window predicts in the last --late-fraction of the training")
    parser.add_argument("--late-fraction", type=float, default=0.4)
    parser.add_argument("--batch", type=int, default=32, help="windows a step")
    parser.add_argument("--lr", type=float, default=1e-3, help="peak AdamW learning rate")
    parser.add_argument("--full-res-head", action="store_true",
                        help="the net's head at full resolution, seeing the newest frame (world_net.py)")
    parser.add_argument("--warp", choices=WARPS, default="last_frame",
                        help="how a frame is made from the net's output (valerant_learn/world_warp.py): "
                             "last_frame (models v1, v2), rotation_anchor (the commanded rotation exact, "
                             "pixels sampled once from an anchor frame) or pose_anchor (the commanded turn and "
                             "translation exact through each pixel's depth, the anchors' first depth the "
                             "--depth-prior's)")
    parser.add_argument("--depth-prior", default=DEFAULT_DEPTH_PRIOR, metavar="ONNX",
                        help="pose_anchor: the depth prior whose depth of each window's newest context frame "
                             "starts its anchor, as the C++ backend's world.learned.depth_prior_model does "
                             "(default: the shipped models/depth_prior.onnx)")
    parser.add_argument("--gradient-weight", type=float, default=0.0,
                        help="weight of the image-gradient difference term of the loss (against blur)")
    parser.add_argument("--init", metavar="PT",
                        help="start from the weights of this world_model.pt of an earlier run (same --context, "
                             "--full-res-head, --warp and frame size), with a fresh optimiser and schedule")
    parser.add_argument("--adversarial-weight", type=float, default=0.0, metavar="W",
                        help="weight of the hinge term of a PatchGAN discriminator on the predicted frames "
                             "(valerant_learn/world_discriminator.py); 0: none")
    parser.add_argument("--adversarial-frames", type=int, default=64, metavar="N",
                        help="predicted and true frames a step shows the discriminator (a random subset of "
                             "the unroll's when it has more)")
    parser.add_argument("--adversarial-lr", type=float, default=2e-4,
                        help="the discriminator's Adam learning rate (constant)")
    parser.add_argument("--adversarial-start", type=float, default=0.0, metavar="F",
                        help="the share of the training (steps or minutes) before the adversarial term and the "
                             "discriminator start: the reconstruction is learnt first")
    parser.add_argument("--discriminator-lead", type=float, default=0.0, metavar="F",
                        help="the share of the training from --adversarial-start in which the discriminator "
                             "learns alone, before the generator's term joins the loss")
    parser.add_argument("--discriminator-steps", type=int, default=1, metavar="N",
                        help="discriminator updates on each batch of frames a step shows it")
    parser.add_argument("--invented-weight", type=float, default=1.0, metavar="W",
                        help="while the generator's adversarial term runs, the weight of an invented pixel "
                             "(world_net.carry_seen) in the L1, SSIM and gradient terms; 1: as any other")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--device", choices=["auto", "cpu", "cuda"], default="auto")
    parser.add_argument("--eval-every", type=int, default=500, metavar="N", help="validate every N steps")
    parser.add_argument("--log-every", type=int, default=100, metavar="N",
                        help="every N steps, print the mean training loss since the last validation")
    parser.add_argument("--precision", choices=["bf16", "fp32"], default="fp32",
                        help="on CUDA: fp32, or bf16 autocast, which diverged here within 100 steps "
                             "(models/world_model.md); the CPU always runs fp32")
    parser.add_argument("--workers", type=int, default=min(8, os.cpu_count() or 1),
                        help="threads decoding the shards' images (and, for pose_anchor, running the depth prior)")
    parser.add_argument("--max-val-rollouts", type=int, default=50,
                        help="candidate rollouts of --val measured at the horizons")
    args = parser.parse_args(argv)
    for name in ("steps", "batch", "eval_every", "log_every", "workers", "context", "unroll", "late_unroll",
                 "max_val_rollouts", "adversarial_frames", "discriminator_steps"):
        value = getattr(args, name)
        if value is not None and value < 1:
            parser.error("--%s must be at least 1" % name.replace("_", "-"))
    if args.minutes is not None and not args.minutes > 0:
        parser.error("--minutes must be positive")
    if not args.lr > 0:
        parser.error("--lr must be positive")
    if not args.gradient_weight >= 0:
        parser.error("--gradient-weight must be at least 0")
    if not args.adversarial_weight >= 0:
        parser.error("--adversarial-weight must be at least 0")
    if not args.adversarial_lr > 0:
        parser.error("--adversarial-lr must be positive")
    if not 0 <= args.adversarial_start < 1:
        parser.error("--adversarial-start must be in [0, 1)")
    if not (0 <= args.discriminator_lead and args.adversarial_start + args.discriminator_lead < 1):
        parser.error("--discriminator-lead must be at least 0, and --adversarial-start + --discriminator-lead below 1")
    if not 0 <= args.invented_weight <= 1:
        parser.error("--invented-weight must be in [0, 1]")
    if not 0 <= args.late_fraction < 1:
        parser.error("--late-fraction must be in [0, 1)")
    return args


def load_data(args):
    """The train and val shards. For pose_anchor their "depth" becomes the depth prior's
    (the shards' true depth is never read): the C++ backend starts its anchors from the
    prior's depth of the start frame, so the training does too."""
    train = load_shards(expand_globs(args.train, "--train"), args.workers)
    val = load_shards(expand_globs(args.val, "--val"), args.workers)
    if args.warp == "pose_anchor":
        if not os.path.isfile(args.depth_prior):
            raise ValueError("--depth-prior %s: no such file" % args.depth_prior)
        start = time.time()
        for data in (train, val):
            data["depth"] = prior_depths(args.depth_prior, data["rgb"], args.workers)
        print("depth prior %s on %d frames: %.0f s" % (args.depth_prior, len(train["rgb"]) + len(val["rgb"]),
                                                      time.time() - start), flush=True)
    shared = sorted(set(train["meta"]["maps"]) & set(val["meta"]["maps"]))
    if shared:
        raise ValueError("val maps overlap train maps: %s (val must measure maps the net never saw)"
                         % ", ".join(shared))
    check_same_camera("the train shards", train["meta"], "the val shards", val["meta"])
    return train, val


def read_init(args):
    """The checkpoint of --init, checked against this run's options (before the data's
    long load); ValueError naming the file when it is missing, unreadable or made for
    other options."""
    path = args.init
    if not os.path.isfile(path):
        raise ValueError("--init %s: no such file" % path)
    try:
        # Not weights_only: torch 1.13's weights-only unpickler cannot read the camera's
        # floats. The file is an earlier run's own output.
        checkpoint = torch.load(path, map_location="cpu", weights_only=False)
    except Exception as error:  # torch.load fails in many ways: pickle, zip, EOF, OS errors
        raise ValueError("--init %s: unreadable (%s)" % (path, error))
    if not isinstance(checkpoint, dict) or not all(key in checkpoint for key in CHECKPOINT_KEYS):
        raise ValueError("--init %s: not a world_model.pt (its keys are not %s)" % (path, ", ".join(CHECKPOINT_KEYS)))
    for key, value in (("context", args.context), ("full_res_head", args.full_res_head), ("warp", args.warp)):
        if checkpoint[key] != value:
            option = "--" + key.replace("_", "-")
            raise ValueError("--init %s: made with %s %s, this run has %s %s" % (path, option, checkpoint[key],
                                                                                 option, value))
    return checkpoint


def load_init(model, checkpoint, path):
    """Loads read_init()'s weights into the model built for this run's data."""
    if (checkpoint["height"], checkpoint["width"]) != (model.height, model.width):
        raise ValueError("--init %s: made for %dx%d frames, this data's are %dx%d" % (
            path, checkpoint["width"], checkpoint["height"], model.width, model.height))
    try:
        model.load_state_dict(checkpoint["state_dict"])
    except RuntimeError as error:
        raise ValueError("--init %s: its weights do not fit the net (%s)" % (path, error))


class WindowTable:
    """Every window of one unroll length as index tensors on the device, so a batch is
    a gather: context rows [S,K], target rows [S,T], motions [S,T,4]."""

    def __init__(self, windows, unroll, device):
        starts = windows.starts(unroll)
        if not starts:
            raise ValueError("no sequence is longer than %d frames: nothing to train on" % unroll)
        context, targets, motions = [], [], []
        for r, t in starts:
            run = windows.runs[r]
            context.append(run[[max(0, t - windows.context + 1 + k) for k in range(windows.context)]])
            targets.append(run[t + 1:t + 1 + unroll])
            motions.append(windows.motions[r][t + 1:t + 1 + unroll])
        self.context = torch.from_numpy(np.stack(context)).to(device)
        self.targets = torch.from_numpy(np.stack(targets)).to(device)
        self.motions = torch.from_numpy(np.stack(motions)).to(device)
        self.count = len(starts)


def as_frames(rgb):
    """uint8 [..., H, W, 3] -> float [..., 3, H, W] in [0,1]."""
    return rgb.movedim(-1, -3).float().div(255)


def mirror(context, targets, motions):
    """The same windows seen in a mirror: images flipped left-right, strafe and yaw
    negated (forward and pitch keep their sign)."""
    sign = torch.tensor([1.0, -1.0, -1.0, 1.0], device=motions.device)
    return context.flip(-1), targets.flip(-1), motions * sign


def gradient_difference(predicted, true, weights=None):
    """Mean |horizontal and vertical differences of predicted - those of true|: zero for
    a perfect frame, large for a blurred one whose edges are flattened. weights [N,1,H,W]
    (reconstruction_weights): each difference weighs the smaller weight of its two pixels."""
    dx = (predicted[..., :, 1:] - predicted[..., :, :-1]) - (true[..., :, 1:] - true[..., :, :-1])
    dy = (predicted[..., 1:, :] - predicted[..., :-1, :]) - (true[..., 1:, :] - true[..., :-1, :])
    if weights is None:
        return dx.abs().mean() + dy.abs().mean()
    wx = torch.minimum(weights[..., :, 1:], weights[..., :, :-1])
    wy = torch.minimum(weights[..., 1:, :], weights[..., :-1, :])
    return pixel_weighted_mean(dx.abs(), wx) + pixel_weighted_mean(dy.abs(), wy)


def pixel_weighted_mean(values, weights):
    """sum(weights * values) / sum(weights) over every pixel and channel of values
    [N,C,H,W], weights [N,1,H,W] (the same for each channel)."""
    return (weights * values).sum() / (weights.sum() * values.shape[1])


def reconstruction_weights(invented, invented_weight):
    """Each predicted pixel's weight in the reconstruction terms: 1, and invented_weight
    where the invented map [N,1,H,W] is 1 (between the two where it is between)."""
    return 1.0 - (1.0 - invented_weight) * invented


def reconstruction_loss(predicted, true, gradient_weight, weights=None):
    """L1 + SSIM_WEIGHT (1 - SSIM) + gradient_weight x gradient_difference of frames
    [N,3,H,W]; returns (loss, L1). weights [N,1,H,W] (reconstruction_weights) make each
    term a weighted mean: L1 and the gradient term by pixel, SSIM by the weight of each
    window's centre pixel. None: plain means."""
    if weights is None:
        l1 = (predicted - true).abs().mean()
        structure = ssim(predicted, true).mean()
    else:
        l1 = pixel_weighted_mean((predicted - true).abs(), weights)
        r = SSIM_WINDOW // 2
        centres = weights[..., r:weights.shape[-2] - r, r:weights.shape[-1] - r]
        structure = pixel_weighted_mean(ssim_map(predicted, true), centres)
    loss = l1 + SSIM_WEIGHT * (1 - structure)
    if gradient_weight > 0:
        loss = loss + gradient_weight * gradient_difference(predicted, true, weights)
    return loss, l1


def window_loss(model, rgb, table, picks, flip, camera, depth=None, gradient_weight=0.0, with_invented=False,
                invented_weight=None):
    """depth: float [N,H,W] metres of every frame (pose_anchor), else None. Returns the
    loss, its L1 part, the predicted and true frames of the unroll [N*T,3,H,W] and, with
    with_invented, the predicted frames' invented maps [N*T,1,H,W] (world_net.rollout;
    else None). invented_weight (with with_invented): the weight of an invented pixel in
    the reconstruction terms (reconstruction_weights); None: every pixel weighs 1."""
    context = as_frames(rgb[table.context[picks]])
    targets = as_frames(rgb[table.targets[picks]])
    motions = table.motions[picks]
    anchor_depth = None if depth is None else depth[table.context[picks, -1]][:, None]
    if flip is not None:
        flipped = mirror(context[flip], targets[flip], motions[flip])
        context, targets, motions = context.clone(), targets.clone(), motions.clone()
        context[flip], targets[flip], motions[flip] = flipped
        if anchor_depth is not None:
            anchor_depth = anchor_depth.clone()
            anchor_depth[flip] = anchor_depth[flip].flip(-1)
    predicted, invented = rollout(model, context, motions, camera, anchor_depth, with_invented=True) \
        if with_invented else (rollout(model, context, motions, camera, anchor_depth), None)
    predicted = predicted.float()
    n, t = predicted.shape[:2]
    flat_pred, flat_true = predicted.reshape(n * t, *predicted.shape[2:]), targets.reshape(n * t, *targets.shape[2:])
    if invented is not None:
        invented = invented.reshape(n * t, *invented.shape[2:]).float()
    weights = None if invented_weight is None else reconstruction_weights(invented, invented_weight)
    loss, l1 = reconstruction_loss(flat_pred, flat_true, gradient_weight, weights)
    return loss, l1, flat_pred, flat_true, invented


def adversarial_sample(predicted, true, invented, limit, generator):
    """The frames the discriminator sees: the unroll's predicted and true frames
    [F,3,H,W] and the predicted ones' invented maps [F,1,H,W], of the frames whose
    invented share is at least MIN_INVENTED_SHARE; at most `limit` of them, drawn with the
    training generator (seeded). None when no frame has that much invented."""
    chosen = torch.nonzero(invented.mean((1, 2, 3)) >= MIN_INVENTED_SHARE).flatten()
    if len(chosen) == 0:
        return None
    if len(chosen) > limit:
        chosen = chosen[torch.randperm(len(chosen), generator=generator, device=chosen.device)[:limit]]
    return predicted[chosen], true[chosen], invented[chosen]


def val_rollouts(windows, limit):
    """The candidate rollouts of the val windows that start at their first frame
    (kind 'rollout'), at most `limit`, spread over the list."""
    chosen = [r for r, kind in enumerate(windows.kinds) if kind == "rollout"]
    if len(chosen) > limit:
        chosen = [chosen[i] for i in np.linspace(0, len(chosen) - 1, limit).astype(int)]
    return chosen


def generate(model, windows, run_index, device, camera, depth=None):
    """The model's frames for a whole run from its first frame (context: that frame
    repeated; depth: pose_anchor's tensor [N,H,W] of every frame's depth on the device):
    float [T,3,H,W] on the CPU, T = run length - 1."""
    run = windows.runs[run_index]
    first = as_frames(torch.from_numpy(windows.rgb[run[0]]).to(device))
    context = first[None, None].expand(1, windows.context, *first.shape).contiguous()
    motions = torch.from_numpy(windows.motions[run_index][1:]).to(device)[None]
    first_depth = None if depth is None else depth[int(run[0])][None, None]
    with torch.no_grad():
        return rollout(model, context, motions, camera, first_depth)[0].float().cpu()


def measure_horizons(model, windows, runs, device, camera, depth=None):
    """horizon_table() of the model and both baselines over `runs`."""
    model.eval()
    entries = []
    for r in runs:
        run = windows.runs[r]
        truth = as_frames(torch.from_numpy(windows.rgb[run[1:]]))
        entries.append((generate(model, windows, r, device, camera, depth), truth,
                        as_frames(torch.from_numpy(windows.rgb[run[0]]))))
    model.train()
    return horizon_table(entries)


class RunningMean:
    """The mean of the values added since the last take() (0 when none were)."""

    def __init__(self):
        self.total, self.count = 0.0, 0

    def add(self, value):
        self.total, self.count = self.total + value, self.count + 1

    def take(self):
        mean = float(self.total) / max(self.count, 1)
        self.total, self.count = 0.0, 0
        return mean


def train(model, rgb, depth, tables, val_table, windows_val, val_runs, args, device, out_dir, camera):
    """depth: {"train", "val"}: tensors [N,H,W] of every frame's depth on the device for
    pose_anchor, else None."""
    decay = [p for p in model.parameters() if p.ndim > 1 and p.requires_grad]
    no_decay = [p for p in model.parameters() if p.ndim <= 1]
    optimizer = torch.optim.AdamW([{"params": decay, "weight_decay": WEIGHT_DECAY},
                                   {"params": no_decay, "weight_decay": 0.0}], lr=args.lr)
    generator = torch.Generator(device).manual_seed(args.seed)
    val_picks = torch.linspace(0, val_table.count - 1, min(VAL_WINDOWS, val_table.count), device=device).long()
    budget_s = args.minutes * 60 if args.minutes is not None else None
    rows, step, loss_sum, loss_steps, skipped_steps = [], 0, torch.zeros((), device=device), 0, 0
    adversary = Adversary(args.adversarial_lr, device, args.discriminator_steps) if args.adversarial_weight > 0 \
        else None
    adversarial_mean, discriminator_mean, discriminator_skipped = RunningMean(), RunningMean(), 0
    adversarial_steps = 0  # steps whose frames showed the discriminator something (adversarial_sample)
    generator_steps = 0    # of them, steps whose loss held the generator's term
    start = time.time()
    with open(os.path.join(out_dir, "log.csv"), "w", newline="") as log_file:
        log = csv.DictWriter(log_file, LOG_COLUMNS)
        log.writeheader()

        def validate(unroll):
            nonlocal loss_sum, loss_steps
            model.eval()
            with torch.no_grad():
                _, val_l1, _, _, _ = window_loss(model, rgb["val"], val_table, val_picks, None, camera, depth["val"])
            model.train()
            table = measure_horizons(model, windows_val, val_runs, device, camera, depth["val"])
            row = {"step": step, "seconds": round(time.time() - start, 2), "unroll": unroll,
                   "train_loss": float(loss_sum) / max(1, loss_steps), "val_l1": float(val_l1)}
            row.update({"val_psnr_%d" % h: table[str(h)]["model"]["psnr"] for h in HORIZONS})
            loss_sum, loss_steps = torch.zeros((), device=device), 0
            rows.append(row)
            log.writerow(row)
            log_file.flush()
            print("step %d  %.0f s  unroll %d  lr %.2e  train loss %.4f  val L1 %.4f  PSNR %s" % (
                step, row["seconds"], unroll, optimizer.param_groups[0]["lr"], row["train_loss"], row["val_l1"],
                " ".join("%d:%.2f/%.2f/%.2f" % (h, table[str(h)]["model"]["psnr"], table[str(h)]["repeat"]["psnr"],
                                                table[str(h)]["flat"]["psnr"]) for h in HORIZONS
                         if table[str(h)]["rollouts"])), flush=True)

        model.train()
        unroll = args.unroll
        while True:
            progress = step / args.steps if budget_s is None else (time.time() - start) / budget_s
            if step > 0 and progress >= 1:
                break
            unroll = args.late_unroll if progress >= 1 - args.late_fraction else args.unroll
            table = tables[unroll]
            for group in optimizer.param_groups:
                group["lr"] = learning_rate(args.lr, progress)
            picks = torch.randint(table.count, (args.batch,), generator=generator, device=device)
            flip = torch.rand(args.batch, generator=generator, device=device) < 0.5
            adversarial_on = adversary is not None and progress >= args.adversarial_start
            generator_on = adversarial_on and progress >= args.adversarial_start + args.discriminator_lead
            with torch.autocast(device_type=device.type, dtype=torch.bfloat16,
                                enabled=device.type == "cuda" and args.precision == "bf16"):
                loss, _, predicted, true, invented = window_loss(
                    model, rgb["train"], table, picks, flip, camera, depth["train"], args.gradient_weight,
                    adversarial_on, args.invented_weight if generator_on and args.invented_weight != 1 else None)
            shown, adversarial = None, None  # adversarial: the generator's term, when it joins the loss
            if adversarial_on:  # in fp32, outside autocast
                shown = adversarial_sample(predicted, true, invented, args.adversarial_frames, generator)
            if shown is not None and generator_on:
                fake, _, fake_invented = shown
                adversarial = adversary.generator_term(fake, fake_invented)
                loss = loss + args.adversarial_weight * adversarial
            optimizer.zero_grad(set_to_none=True)
            loss.backward()
            grad_norm = torch.nn.utils.clip_grad_norm_(model.parameters(), GRAD_CLIP_NORM)
            if torch.isfinite(grad_norm):
                optimizer.step()
                loss_sum += loss.detach()
                loss_steps += 1
                if adversarial is not None:
                    adversarial_mean.add(adversarial.detach())
            else:  # one bad window must not turn every weight into NaN
                skipped_steps += 1
            if shown is not None:
                fake, real, fake_invented = shown
                adversarial_steps += 1
                generator_steps += adversarial is not None
                d_loss = adversary.step(real, fake, fake_invented)
                if d_loss is None:
                    discriminator_skipped += 1
                else:
                    discriminator_mean.add(d_loss)
            step += 1
            if step % args.log_every == 0:
                adversarial_log = "" if adversary is None else (
                    "  adversarial steps %d (generator %d)  discriminator loss %.4f  adversarial term %.4f  "
                    "skipped (discriminator) %d" % (adversarial_steps, generator_steps, discriminator_mean.take(),
                                                    adversarial_mean.take(), discriminator_skipped))
                print("step %d  %.0f s  train loss %.4f  skipped (non-finite gradient) %d%s"
                      % (step, time.time() - start, float(loss_sum) / max(loss_steps, 1), skipped_steps,
                         adversarial_log), flush=True)
            if step % args.eval_every == 0:
                validate(unroll)
        if loss_steps:
            validate(unroll)
    # The keys of CHECKPOINT_KEYS, which --init reads back.
    torch.save({"state_dict": {k: v.cpu() for k, v in model.state_dict().items()}, "context": model.context,
                "full_res_head": model.full_res is not None, "warp": model.warp, "camera": camera,
                "height": model.height, "width": model.width, "step": step},
               os.path.join(out_dir, "world_model.pt"))
    return rows, step, time.time() - start


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    args = parse_args(argv)
    random.seed(args.seed)
    np.random.seed(args.seed)
    torch.manual_seed(args.seed)
    try:
        device = pick_device(args.device)
        checkpoint = None if args.init is None else read_init(args)
        init = None if checkpoint is None else {"path": args.init, "sha256": sha256(args.init),
                                                "step": checkpoint["step"]}
        train_data, val_data = load_data(args)
        meta = train_data["meta"]
        model = WorldNet(args.context, meta["height"], meta["width"], args.full_res_head, args.warp)
        if checkpoint is not None:
            load_init(model, checkpoint, args.init)
        camera = {key: float(meta[key]) for key in ("fx", "fy", "cx", "cy")}
        windows = {"train": WorldWindows(train_data["rgb"], train_data, args.context),
                   "val": WorldWindows(val_data["rgb"], val_data, args.context)}
        unrolls = sorted({args.unroll, args.late_unroll})
        tables = {u: WindowTable(windows["train"], u, device) for u in unrolls}
        val_table = WindowTable(windows["val"], args.unroll, device)
    except ValueError as error:
        sys.exit("train_world_model: error: %s" % error)
    os.makedirs(args.out, exist_ok=True)
    for name, data in (("train", train_data), ("val", val_data)):
        print("%s: %d frames in %d sequences from %d shards, maps %s" % (
            name, len(data["kind"]), len(windows[name].runs), len(data["meta"]["shards"]),
            ", ".join(data["meta"]["maps"])), flush=True)
    parameters = sum(p.numel() for p in model.parameters())
    print("model: %d parameters; device %s" % (parameters, device_name(device)), flush=True)
    if init is not None:
        print("init: the weights of %s, step %d of its run (sha256 %s)" % (init["path"], init["step"], init["sha256"]),
              flush=True)
    model = model.to(device)
    rgb = {"train": torch.from_numpy(train_data["rgb"]).to(device), "val": torch.from_numpy(val_data["rgb"]).to(device)}
    # Only pose_anchor reads depth: its anchors start at the newest context frame's.
    depth = {name: torch.from_numpy(data["depth"]).to(device) if args.warp == "pose_anchor" else None
             for name, data in (("train", train_data), ("val", val_data))}
    val_runs = val_rollouts(windows["val"], args.max_val_rollouts)

    rows, steps, seconds = train(model, rgb, depth, tables, val_table, windows["val"], val_runs, args, device,
                                 args.out, camera)

    horizons = measure_horizons(model, windows["val"], val_runs, device, camera, depth["val"])
    onnx_path = os.path.join(args.out, "world_model.onnx")
    model.eval()
    with torch.no_grad():
        context = as_frames(rgb["val"][val_table.context[:2]])
        verify_depth = None if depth["val"] is None else depth["val"][val_table.context[:2, -1]][:, None]
        verify, _, _ = net_input(model, context, val_table.motions[:2, 0], camera,
                                 start_state(model, context, camera, verify_depth))
    onnx_report = export_world_onnx(model, onnx_path, verify.cpu().numpy(), {
        "train_maps": ",".join(meta["maps"]), "fx": meta["fx"], "fy": meta["fy"], "cx": meta["cx"], "cy": meta["cy"]})
    print("exported %s; cv2.dnn vs torch max |diff| %.2e" % (onnx_path, onnx_report["max_abs_diff"]), flush=True)
    metrics = {
        "format": "valerant-world-model-1",
        "horizons": horizons,
        "val_rollouts": len(val_runs),
        "parameters": parameters,
        "context": args.context,
        "unroll": args.unroll,
        "late_unroll": args.late_unroll,
        "full_res_head": args.full_res_head,
        "warp": args.warp,
        "depth_prior_sha256": sha256(args.depth_prior) if args.warp == "pose_anchor" else None,
        "gradient_weight": args.gradient_weight,
        "adversarial_weight": args.adversarial_weight,
        "adversarial_frames": args.adversarial_frames,
        "adversarial_lr": args.adversarial_lr,
        "adversarial_start": args.adversarial_start,
        "discriminator_lead": args.discriminator_lead,
        "discriminator_steps": args.discriminator_steps,
        "invented_weight": args.invented_weight,
        "init": init,
        "input_width": meta["width"],
        "input_height": meta["height"],
        "steps": steps,
        "train_seconds": round(seconds, 2),
        "batch": args.batch,
        "precision": args.precision if device.type == "cuda" else "fp32",
        "lr": args.lr,
        "seed": args.seed,
        "device": device_name(device),
        "torch_version": torch.__version__,
        "command_line": shlex.join([sys.argv[0]] + argv),
        "train_frames": len(train_data["kind"]),
        "train_sequences": len(windows["train"].runs),
        "val_frames": len(val_data["kind"]),
        "train_maps": meta["maps"],
        "val_maps": val_data["meta"]["maps"],
        "train_shards": meta["shards"],
        "val_shards": val_data["meta"]["shards"],
        "onnx_sha256": sha256(onnx_path),
        "onnx_check": onnx_report,
    }
    with open(os.path.join(args.out, "metrics.json"), "w") as handle:
        json.dump(metrics, handle, indent=1)
    plot_world_curves(rows, os.path.join(args.out, "curves.png"))
    samples = val_runs[:: max(1, len(val_runs) // 4)][:4]
    model.eval()
    plot_rollouts([(windows["val"].maps[r], generate(model, windows["val"], r, device, camera, depth["val"]),
                    as_frames(torch.from_numpy(windows["val"].rgb[windows["val"].runs[r][1:]]))) for r in samples],
                  os.path.join(args.out, "rollouts.png"))
    print("done: %d steps in %.0f s; PSNR model/repeat/flat %s; wrote %s" % (
        steps, seconds, " ".join("%s:%.2f/%.2f/%.2f" % (h, v["model"]["psnr"], v["repeat"]["psnr"], v["flat"]["psnr"])
                                 for h, v in horizons.items() if v["rollouts"]), args.out), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
