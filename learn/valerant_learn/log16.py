"""The dataset's 'log16' depth encoding, in one place.

Code 0 means no depth (sky). Codes 1..65535 map linearly in log depth onto
[depth_min_m, depth_max_m], so the relative step is the same at every range
(about 1.3e-4 for 0.05..200 m)."""
import numpy as np

MAX_CODE = 65535


def decode_log16(code, depth_min_m, depth_max_m):
    """uint16 codes -> float32 metres, NaN where code == 0."""
    code = np.asarray(code)
    lo, hi = np.log(depth_min_m), np.log(depth_max_m)
    depth = np.exp(lo + (code.astype(np.float64) - 1.0) / (MAX_CODE - 1) * (hi - lo))
    return np.where(code == 0, np.nan, depth).astype(np.float32)


def encode_log16(depth_m, depth_min_m, depth_max_m):
    """Metres -> uint16 codes; NaN, inf and non-positive depths become 0 (sky),
    finite depths are clipped into [depth_min_m, depth_max_m]."""
    depth = np.asarray(depth_m, dtype=np.float64)
    valid = np.isfinite(depth) & (depth > 0)
    lo, hi = np.log(depth_min_m), np.log(depth_max_m)
    clipped = np.clip(np.where(valid, depth, depth_min_m), depth_min_m, depth_max_m)
    code = np.rint(1.0 + (np.log(clipped) - lo) / (hi - lo) * (MAX_CODE - 1))
    return np.where(valid, code, 0).astype(np.uint16)
