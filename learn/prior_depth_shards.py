#!/usr/bin/env python3
"""Copies valerant_dataset shards with their depth replaced by the depth prior's
prediction (models/depth_prior.onnx in cv2.dnn on the CPU, as DepthPrior runs it in
C++: the RGB frame in [0,1], the output's first channel exp'd), for the world model's
pose_anchor warp, whose backend has only the prior's depth of the frames it starts
from (docs/world_model.md). meta.json gains depth_source "depth_prior:<sha256 of the
model>", so that load_shards() never hands these depths to a caller that expects the
engine's. The images and frames.csv are copied byte for byte.

  prior_depth_shards.py --model models/depth_prior.onnx --out-dir data/wm_prior/train_a data/wm_train/*.zip

One CPU thread a process (about 11 ms a 128 x 96 frame); --jobs N runs N shards at once."""
import argparse
import concurrent.futures
import json
import os
import sys
import zipfile

import cv2
import numpy as np

from valerant_learn.log16 import encode_log16
from valerant_learn.shards import DEPTH_PRIOR_SOURCE, depth_name, load_shards, rgb_name
from valerant_learn.training import sha256

INPUT_NAME, OUTPUT_NAME = "rgb", "depth_and_scale"


def predict_depth(net, rgb):
    """The prior's depth (metres, float32 H x W) of one RGB uint8 H x W x 3 frame at the
    net's size."""
    net.setInput(cv2.dnn.blobFromImage(rgb, 1.0 / 255.0, swapRB=False, crop=False, ddepth=cv2.CV_32F), INPUT_NAME)
    return np.exp(net.forward(OUTPUT_NAME)[0, 0])


def convert(shard, model, out_dir):
    """Writes out_dir/<shard's name> with the prior's depth; returns (path, frames)."""
    cv2.setNumThreads(1)
    data = load_shards([shard])
    meta = data["meta"]
    net = cv2.dnn.readNetFromONNX(model)
    path = os.path.join(out_dir, os.path.basename(shard))
    temporary = path + ".partial"
    with zipfile.ZipFile(shard) as source, zipfile.ZipFile(temporary, "w", zipfile.ZIP_DEFLATED) as target:
        shard_meta = json.loads(source.read("meta.json"))
        shard_meta["depth_source"] = DEPTH_PRIOR_SOURCE + sha256(model)
        target.writestr("meta.json", json.dumps(shard_meta, indent=1))
        target.writestr("frames.csv", source.read("frames.csv"))
        for i, rgb in enumerate(data["rgb"]):
            depth = predict_depth(net, rgb)
            if depth.shape != rgb.shape[:2]:
                raise ValueError("%s: the prior predicts %s for %s frames (another input size?)"
                                 % (model, depth.shape, rgb.shape[:2]))
            code = encode_log16(depth, meta["depth_min_m"], meta["depth_max_m"])
            target.writestr(rgb_name(i), source.read(rgb_name(i)), zipfile.ZIP_STORED)
            target.writestr(depth_name(i), cv2.imencode(".png", code)[1].tobytes(), zipfile.ZIP_STORED)
    os.replace(temporary, path)
    return path, len(data["rgb"])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("shards", nargs="+", help="shards with the engine's depth")
    parser.add_argument("--model", required=True, help="the depth prior (ONNX)")
    parser.add_argument("--out-dir", required=True)
    parser.add_argument("--jobs", type=int, default=1, help="shards converted at once")
    args = parser.parse_args(argv)
    if args.jobs < 1:
        parser.error("--jobs must be at least 1")
    if not os.path.isfile(args.model):
        sys.exit("prior_depth_shards: error: %s: no such model file" % args.model)
    os.makedirs(args.out_dir, exist_ok=True)
    try:
        with concurrent.futures.ProcessPoolExecutor(args.jobs) as pool:
            for path, frames in pool.map(convert, args.shards, [args.model] * len(args.shards),
                                         [args.out_dir] * len(args.shards)):
                print("%s: %d frames" % (path, frames), flush=True)
    except (ValueError, cv2.error) as error:
        sys.exit("prior_depth_shards: error: %s" % error)
    return 0


if __name__ == "__main__":
    sys.exit(main())
