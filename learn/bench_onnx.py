#!/usr/bin/env python3
"""Times an exported depth prior in OpenCV's DNN module on one thread (as the
explorer runs it) and prints one JSON line with the median time a frame."""
import argparse
import json
import statistics
import time

import cv2
import numpy as np
import onnx


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("model", help="depth_prior.onnx written by train_depth.py")
    parser.add_argument("--runs", type=int, default=50)
    parser.add_argument("--warmup", type=int, default=5)
    parser.add_argument("--batch", type=int, default=1, help="frames a forward pass")
    args = parser.parse_args()
    properties = {entry.key: entry.value for entry in onnx.load(args.model).metadata_props}
    width, height = int(properties["input_width"]), int(properties["input_height"])
    cv2.setNumThreads(1)
    net = cv2.dnn.readNetFromONNX(args.model)
    blob = np.random.default_rng(0).random((args.batch, 3, height, width), dtype=np.float32)
    seconds = []
    for run in range(args.warmup + args.runs):
        start = time.perf_counter()
        net.setInput(blob)
        net.forward()
        if run >= args.warmup:
            seconds.append(time.perf_counter() - start)
    print(json.dumps({
        "model": args.model, "backend": "cv2.dnn", "opencv": cv2.__version__, "threads": cv2.getNumThreads(),
        "width": width, "height": height, "batch": args.batch, "runs": args.runs,
        "median_ms_per_frame": round(statistics.median(seconds) * 1000 / args.batch, 3),
        "min_ms_per_frame": round(min(seconds) * 1000 / args.batch, 3),
    }), flush=True)


if __name__ == "__main__":
    main()
