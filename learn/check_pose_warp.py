#!/usr/bin/env python3
"""Checks the world model's warp geometry on the engine's own frames, with no net: each
translating candidate rollout of a shard (uw, jw, lw) is predicted from its first frame
by the warp alone (flow 0, mask 1: every pixel sampled from the anchor, or from the
newest frame where it leaves the anchor's view) and scored against the engine's frames
by PSNR, for the rotation_anchor warp (the commanded turn only) and the pose_anchor
warp (turn and translation through a depth) with the shard's true depth and, given
--prior, with the depth prior's on the first frame (what the C++ backend has). A warp
whose geometry is right predicts the walk better than one that ignores the translation;
docs/world_model.md has the figures.

  check_pose_warp.py data/wm_eval/evaluation-000.zip --prior models/depth_prior.onnx --frames 20 \\
      --sheet docs/world_model/pose_warp_check.png

Prints one line per candidate kind and one JSON line with every figure."""
import argparse
import json
import sys

import cv2
import numpy as np
import torch

from valerant_learn.prior_depth import predict_depth
from valerant_learn.shards import load_shards
from valerant_learn.world_data import WorldWindows
from valerant_learn.world_metrics import psnr
from valerant_learn.world_warp import AnchorState, anchor_step, rotation_sampling

def warp_only(frames, motions, camera, depth=None):
    """Frames 1..T predicted from frames[0] (float [T+1,3,H,W]) by the warp alone:
    rotation_anchor when depth is None, else pose_anchor from depth [H,W]."""
    _, _, h, w = frames.shape
    first = frames[:1]
    state = AnchorState.start(first, None if depth is None else depth[None, None], camera)
    newest, predicted = first, []
    for motion in motions:
        motion = motion[None]
        geometry = None
        if depth is None:
            positions, _ = rotation_sampling(motion, camera, h, w)
        else:
            positions, _, geometry = state.geometry.sampling(state.coords, motion)
        newest, state = anchor_step(state, newest, positions, torch.ones_like(first[:, :1]), first, geometry)
        predicted.append(newest[0])
    return torch.stack(predicted)


def candidate_kind(motions):
    """uw, jw or lw from a rollout's motions float [T,4] (forward with no turn, with a left
    or a right turn), None for one that does not translate."""
    if not np.any(motions[:, 0] != 0):
        return None
    yaw = float(np.sum(motions[:, 2]))
    return "uw" if yaw == 0 else "jw" if yaw > 0 else "lw"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("shard", help="a shard of consecutive frames (valerant_dataset --every 1) with true depth")
    parser.add_argument("--prior", help="the depth prior (ONNX): also pose_anchor from its depth of the first frame")
    parser.add_argument("--frames", type=int, default=20, help="frames predicted from each rollout's first")
    parser.add_argument("--sheet", help="a PNG of one uw rollout's last predicted frame by each warp")
    args = parser.parse_args(argv)
    try:
        data = load_shards([args.shard])
    except ValueError as error:
        sys.exit("check_pose_warp: error: %s" % error)
    meta = data["meta"]
    camera = {key: float(meta[key]) for key in ("fx", "fy", "cx", "cy")}
    windows = WorldWindows(data["rgb"], data, context=1)
    net = cv2.dnn.readNetFromONNX(args.prior) if args.prior else None
    warps = ["rotation_anchor", "pose_anchor_true_depth"] + (["pose_anchor_prior_depth"] if net else [])
    scores = {}  # kind -> warp -> [PSNR of each predicted frame of each rollout]
    sheet = None
    for r, run in enumerate(windows.runs):
        kind = candidate_kind(windows.motions[r]) if windows.kinds[r] == "rollout" else None
        if kind is None or len(run) <= args.frames or bool(np.any(data["in_solid"][run[:args.frames + 1]])):
            continue
        rgb = data["rgb"][run[:args.frames + 1]]
        frames = torch.from_numpy(rgb).permute(0, 3, 1, 2).double() / 255
        motions = torch.from_numpy(windows.motions[r][1:args.frames + 1]).double()
        depths = {"rotation_anchor": None, "pose_anchor_true_depth": torch.from_numpy(data["depth"][run[0]]).double()}
        if net:
            depths["pose_anchor_prior_depth"] = torch.from_numpy(predict_depth(net, rgb[0])).double()
        predicted = {warp: warp_only(frames, motions, camera, depths[warp]) for warp in warps}
        for warp in warps:
            scores.setdefault(kind, {}).setdefault(warp, []).extend(psnr(predicted[warp], frames[1:]).tolist())
        if sheet is None and kind == "uw":
            sheet = [frames[-1]] + [predicted[warp][-1] for warp in warps]
    if not scores:
        sys.exit("check_pose_warp: error: %s has no translating candidate rollout of %d frames out of solid"
                 % (args.shard, args.frames + 1))
    summary = {kind: {warp: {"mean_psnr_db": round(float(np.mean(values)), 2),
                             "frames": len(values)} for warp, values in by_warp.items()}
               for kind, by_warp in sorted(scores.items())}
    for kind, by_warp in summary.items():
        print("%s: %s" % (kind, "  ".join("%s %.2f dB (%d frames)" % (warp, v["mean_psnr_db"], v["frames"])
                                          for warp, v in by_warp.items())))
    if args.sheet and sheet is not None:
        row = np.concatenate([(frame.permute(1, 2, 0).numpy() * 255).round().astype(np.uint8) for frame in sheet], 1)
        cv2.imwrite(args.sheet, cv2.cvtColor(cv2.resize(row, None, fx=2, fy=2, interpolation=cv2.INTER_NEAREST),
                                             cv2.COLOR_RGB2BGR))
        print("sheet: %s (the engine's frame %d, then %s)" % (args.sheet, args.frames, ", ".join(warps)))
    print(json.dumps({"shard": args.shard, "frames": args.frames, "prior": args.prior, "psnr": summary}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
