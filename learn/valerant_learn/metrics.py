"""Depth accuracy metrics, computed per frame and then averaged over frames, so a
frame counts the same whatever its share of sky."""
import math

import numpy as np
import torch

# Both depths are clipped into this range before comparing (the usual protocol:
# the very near and very far are not what the prior is for).
METRIC_MIN_M = 0.1
METRIC_MAX_M = 80.0
METRIC_NAMES = ("abs_rel", "delta1", "rmse_log")
# frame_calibration's figures; for a calibrated Laplace scale b of the ln-depth
# error, E|e|/b = 1 and P(|e| < b) = 1 - 1/e = 0.632.
CALIBRATION_NAMES = ("scaled_error", "within_scale")


def frame_metrics(pred, gt):
    """pred, gt: [N,H,W] depth in metres (tensors or arrays); gt is NaN for sky,
    which is left out. Returns {name: float64 numpy [N]}: abs_rel = mean |p-g|/g,
    delta1 = fraction with max(p/g, g/p) < 1.25, rmse_log = sqrt(mean (ln p - ln g)^2),
    and 'pixels', the count compared; a frame with no pixel gets NaN."""
    pred = torch.as_tensor(pred, dtype=torch.float64)
    gt = torch.as_tensor(gt, dtype=torch.float64, device=pred.device)
    valid = ~torch.isnan(gt)
    pred = pred.clamp(METRIC_MIN_M, METRIC_MAX_M)
    gt = torch.where(valid, gt, torch.ones_like(gt)).clamp(METRIC_MIN_M, METRIC_MAX_M)
    weight = valid.double()
    pixels = weight.sum(dim=(1, 2))
    count = pixels.clamp(min=1)
    ratio = torch.maximum(pred / gt, gt / pred)
    values = {
        "abs_rel": ((pred - gt).abs() / gt * weight).sum(dim=(1, 2)) / count,
        "delta1": ((ratio < 1.25).double() * weight).sum(dim=(1, 2)) / count,
        "rmse_log": torch.sqrt(((pred.log() - gt.log()) ** 2 * weight).sum(dim=(1, 2)) / count),
    }
    result = {name: torch.where(pixels > 0, value, torch.full_like(value, math.nan)).cpu().numpy()
              for name, value in values.items()}
    result["pixels"] = pixels.cpu().numpy()
    return result


def frame_calibration(log_depth, log_scale, gt):
    """How well the predicted ln b describes the ln-depth error e = ln p - ln g.
    log_depth, log_scale, gt: [N,H,W] (gt metres, NaN for sky, left out; no
    clipping: b describes the raw error). Returns {name: float64 numpy [N]}:
    scaled_error = mean |e| / b and within_scale = fraction with |e| < b; NaN for a
    frame with no pixel."""
    log_depth = torch.as_tensor(log_depth, dtype=torch.float64)
    log_scale = torch.as_tensor(log_scale, dtype=torch.float64, device=log_depth.device)
    gt = torch.as_tensor(gt, dtype=torch.float64, device=log_depth.device)
    valid = ~torch.isnan(gt)
    error = (log_depth - torch.where(valid, gt, torch.ones_like(gt)).log()).abs()
    weight = valid.double()
    pixels = weight.sum(dim=(1, 2))
    count = pixels.clamp(min=1)
    values = {
        "scaled_error": (error * torch.exp(-log_scale) * weight).sum(dim=(1, 2)) / count,
        "within_scale": ((error < torch.exp(log_scale)).double() * weight).sum(dim=(1, 2)) / count,
    }
    return {name: torch.where(pixels > 0, value, torch.full_like(value, math.nan)).cpu().numpy()
            for name, value in values.items()}


def average(per_frame, mask=None):
    """Means over the frames selected by mask (all if None) that have pixels of
    METRIC_NAMES and of those CALIBRATION_NAMES per_frame holds; None for a
    metric when no frame qualifies."""
    keep = per_frame["pixels"] > 0
    if mask is not None:
        keep = keep & np.asarray(mask, dtype=bool)
    summary = {"frames": int(keep.sum())}
    for name in METRIC_NAMES + CALIBRATION_NAMES:
        if name not in per_frame:
            continue
        summary[name] = float(per_frame[name][keep].mean()) if keep.any() else None
    return summary


def summarize(per_frame, kinds, maps):
    """Figures for all frames, for 'rotate' frames, and per map."""
    kinds, maps = np.asarray(kinds), np.asarray(maps)
    return {
        "all": average(per_frame),
        "rotate": average(per_frame, kinds == "rotate"),
        "per_map": {name: average(per_frame, maps == name) for name in sorted(set(maps.tolist()))},
    }
