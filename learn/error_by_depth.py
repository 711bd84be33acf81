#!/usr/bin/env python3
"""Where a depth prior's error is: runs an exported model in cv2.dnn (as the
explorer does) on the frames of shards and splits AbsRel by kind of pixel,
pixels pooled over frames. Prints one JSON object.

Pixel groups: "floor" (true depth within FLOOR_TOLERANCE of the floor plane of its
row, which the fixed eye height gives) and the other pixels by true depth: below
3 m, 3-8 m, 8-20 m, 20 m and beyond. For each: its share of the pixels, its AbsRel,
its share of the summed AbsRel, the fraction placed over twice too far, and the
median predicted ln b. Both depths are clipped to the metrics' 0.1-80 m; sky is
left out.

  error_by_depth.py MODEL.onnx SHARD.zip [SHARD.zip ...]"""
import argparse
import json
import sys

import cv2
import numpy as np

from valerant_learn.floor_prior import floor_log_depth
from valerant_learn.losses import SKY_DEPTH_M
from valerant_learn.metrics import METRIC_MAX_M, METRIC_MIN_M
from valerant_learn.shards import load_shards

FLOOR_TOLERANCE = 0.02
DEPTH_BINS_M = (3.0, 8.0, 20.0)
BATCH = 64


def group_names():
    edges = ("0",) + tuple("%g" % edge for edge in DEPTH_BINS_M) + ("inf",)
    return ["floor"] + ["other %s-%s m" % (low, high) for low, high in zip(edges[:-1], edges[1:])]


def pixel_groups(depth, floor_depth):
    """int [N,H,W]: 0 floor, 1.. the depth bins of the other pixels, -1 sky.
    floor_depth: the floor plane's depth of each pixel, SKY_DEPTH_M at and above
    the horizon (no floor there)."""
    floor = (np.abs(depth / floor_depth - 1) < FLOOR_TOLERANCE) & (floor_depth < SKY_DEPTH_M)
    groups = 1 + np.digitize(depth, DEPTH_BINS_M)
    groups = np.where(floor, 0, groups)
    return np.where(np.isnan(depth), -1, groups)


def summarize_groups(pred, log_scale, depth, groups):
    """The figures of the module docstring for each group (None for an empty one)."""
    gt = np.clip(np.where(np.isnan(depth), 1.0, depth), METRIC_MIN_M, METRIC_MAX_M)
    pred = np.clip(pred, METRIC_MIN_M, METRIC_MAX_M)
    abs_rel = np.abs(pred - gt) / gt
    valid = groups >= 0
    total_pixels, total_abs_rel = valid.sum(), abs_rel[valid].sum()
    result = {"pixels": int(total_pixels), "abs_rel": float(abs_rel[valid].mean()), "groups": {}}
    for index, name in enumerate(group_names()):
        member = groups == index
        if not member.any():
            result["groups"][name] = None
            continue
        result["groups"][name] = {
            "pixel_share": float(member.sum() / total_pixels),
            "abs_rel": float(abs_rel[member].mean()),
            "abs_rel_share": float(abs_rel[member].sum() / total_abs_rel),
            "over_twice_too_far": float((pred[member] > 2 * gt[member]).mean()),
            "median_log_scale": float(np.median(log_scale[member])),
        }
    return result


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("model", help="an ONNX depth prior (train_depth.py's depth_prior.onnx)")
    parser.add_argument("shards", nargs="+", help="valerant_dataset shards")
    args = parser.parse_args(argv)
    try:
        data = load_shards(args.shards)
        net = cv2.dnn.readNetFromONNX(args.model)
    except (ValueError, cv2.error) as error:
        sys.exit("error_by_depth: error: %s" % error)
    meta = data["meta"]
    cv2.setNumThreads(1)
    outputs = []
    for start in range(0, len(data["rgb"]), BATCH):
        rgb = data["rgb"][start:start + BATCH].transpose(0, 3, 1, 2).astype(np.float32) / 255
        net.setInput(np.ascontiguousarray(rgb))
        outputs.append(net.forward())
    output = np.concatenate(outputs)
    if output.shape[1:] != (2, meta["height"], meta["width"]):
        sys.exit("error_by_depth: error: %s gives %s, expected [N,2,%d,%d]"
                 % (args.model, list(output.shape), meta["height"], meta["width"]))
    floor_depth = np.exp(floor_log_depth(meta["height"], meta["width"], meta, SKY_DEPTH_M).numpy())
    groups = pixel_groups(data["depth"], floor_depth[None])
    result = summarize_groups(np.exp(output[:, 0]), output[:, 1], data["depth"], groups)
    result.update(model=args.model, shards=args.shards, frames=len(data["rgb"]))
    print(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
