"""What the training scripts share: shard globs, the device, the learning-rate
schedule, file checksums."""
import glob
import hashlib
import math
import platform

import torch

WARMUP_FRACTION = 0.03
FINAL_LR_FRACTION = 0.01


def expand_globs(patterns, option):
    paths = []
    for pattern in patterns:
        matches = sorted(glob.glob(pattern))
        if not matches:
            raise ValueError("%s %s: no such shard" % (option, pattern))
        paths.extend(path for path in matches if path not in paths)
    return paths


def pick_device(choice):
    if choice == "auto":
        choice = "cuda" if torch.cuda.is_available() else "cpu"
    if choice == "cuda" and not torch.cuda.is_available():
        raise ValueError("--device cuda, but torch sees no CUDA device")
    return torch.device(choice)


def device_name(device):
    if device.type == "cuda":
        return torch.cuda.get_device_name(device)
    return "cpu (%s, %d threads)" % (platform.machine(), torch.get_num_threads())


def learning_rate(base, progress):
    """One cycle over progress in [0,1]: linear warm-up from base/10, then cosine
    decay to FINAL_LR_FRACTION * base."""
    if progress < WARMUP_FRACTION:
        return base * (0.1 + 0.9 * progress / WARMUP_FRACTION)
    t = min(1.0, (progress - WARMUP_FRACTION) / (1 - WARMUP_FRACTION))
    return base * (FINAL_LR_FRACTION + (1 - FINAL_LR_FRACTION) * 0.5 * (1 + math.cos(math.pi * t)))


def sha256(path):
    with open(path, "rb") as handle:
        return hashlib.sha256(handle.read()).hexdigest()
