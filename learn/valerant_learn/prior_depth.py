"""The depth prior's depth of frames (models/depth_prior.onnx in cv2.dnn on the CPU, as
DepthPrior runs it in C++: the RGB frame in [0,1], the first output channel exp'd), which
the world model's pose_anchor warp starts its anchors from. The training computes it at
load, one cv2.dnn net a thread (OpenCV's Python calls release the GIL), rather than
shipping it in the shards: its 16-bit PNGs are 15 KB a frame against the engine's 2 KB
(the prior's low bits are noise to PNG), which would triple the data a GPU call carries."""
import concurrent.futures
import threading

import cv2
import numpy as np

INPUT_NAME, OUTPUT_NAME = "rgb", "depth_and_scale"
CHUNK = 256  # frames a task


def predict_depth(net, rgb):
    """The prior's depth (metres, float32 H x W) of one RGB uint8 H x W x 3 frame at the
    net's size (a ValueError naming the model size otherwise)."""
    net.setInput(cv2.dnn.blobFromImage(rgb, 1.0 / 255.0, swapRB=False, crop=False, ddepth=cv2.CV_32F), INPUT_NAME)
    depth = np.exp(net.forward(OUTPUT_NAME)[0, 0])
    if depth.shape != rgb.shape[:2]:
        raise ValueError("the depth prior predicts %s for frames of %s (made for another size?)"
                         % (depth.shape, rgb.shape[:2]))
    return depth


def prior_depths(model_path, rgb, workers):
    """float32 [N,H,W]: the prior's depth of every frame of rgb uint8 [N,H,W,3], on
    `workers` threads of one OpenCV thread each."""
    cv2.setNumThreads(1)
    local = threading.local()

    def chunk(start):
        if not hasattr(local, "net"):
            local.net = cv2.dnn.readNetFromONNX(model_path)
        return np.stack([predict_depth(local.net, frame) for frame in rgb[start:start + CHUNK]])

    with concurrent.futures.ThreadPoolExecutor(max(1, workers)) as pool:
        parts = list(pool.map(chunk, range(0, len(rgb), CHUNK)))
    return np.concatenate(parts) if parts else np.zeros((0,) + rgb.shape[1:3], np.float32)
