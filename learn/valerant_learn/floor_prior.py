"""The floor-plane depth prior: the depth each image row would have if the world
were an endless floor under a sky at a fixed distance.

The camera is level and always the same height over the floor it stands on, so a
floor pixel's z-depth follows from its row alone: a ray through row v falls by
(v - cy) / fy per metre forward, so it meets the floor eye_height_m below at
z = eye_height_m * fy / (v - cy) (rows counted from 0, as valerant_dataset renders:
row v's floor depth is exactly this). Rows at or above the horizon, and the floor
beyond far_m, get far_m (the depth sky is trained as). A net that predicts depth
relative to this prior gets the floor right by default, to the row, and only has
to learn where and by how much the scene stands in front of it."""
import math

import torch

# The keys of the camera dict floor_log_depth reads (valerant_dataset's meta.json).
CAMERA_KEYS = ("fy", "cy", "eye_height_m")


def floor_log_depth(height, width, camera, far_m):
    """float32 [H,W]: ln of min(floor depth of the row, far_m); camera holds fy,
    cy (pixels) and eye_height_m. Raises ValueError on a camera it cannot use."""
    missing = [key for key in CAMERA_KEYS if key not in camera]
    if missing:
        raise ValueError("floor prior: the camera lacks %s" % ", ".join(missing))
    fy, cy, eye_height_m = (float(camera[key]) for key in CAMERA_KEYS)
    if not (fy > 0 and eye_height_m > 0 and far_m > 0 and math.isfinite(cy)):
        raise ValueError("floor prior: needs fy, eye_height_m and far_m > 0 and a finite cy, got "
                         "fy %r, cy %r, eye_height_m %r, far_m %r" % (fy, cy, eye_height_m, far_m))
    below_horizon = torch.arange(height, dtype=torch.float64) - cy
    # A row whose floor lies beyond far_m drops below eye_height_m * fy / far_m.
    floor = eye_height_m * fy / below_horizon.clamp(min=eye_height_m * fy / far_m)
    return torch.log(floor).float()[:, None].expand(height, width).contiguous()
