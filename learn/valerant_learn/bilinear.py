"""Bilinear sampling in pixel-index coordinates (pixel i's centre at i), the one
interpolation of the world model's warps (world_warp.py, pose_warp.py): torch's
grid_sample with align_corners=True, as sampleBilinear in
include/valerant/world/learned/anchor_warp.h."""
import torch
import torch.nn.functional as F


def pixel_grid(height, width, device, dtype=torch.float32):
    """[2,H,W]: x (column) and y (row) of each pixel, pixel-index coordinates."""
    ys, xs = torch.meshgrid(torch.arange(height, device=device, dtype=dtype),
                            torch.arange(width, device=device, dtype=dtype), indexing="ij")
    return torch.stack([xs, ys])


def sample(image, positions, padding="border"):
    """image [N,C,H,W] sampled bilinearly at positions [N,2,H,W] (pixel-index x, y);
    padding "border" replicates the border, "zeros" counts taps outside as 0."""
    _, _, h, w = image.shape
    gx = positions[:, 0] * (2.0 / (w - 1)) - 1.0
    gy = positions[:, 1] * (2.0 / (h - 1)) - 1.0
    return F.grid_sample(image, torch.stack([gx, gy], -1), mode="bilinear", padding_mode=padding,
                         align_corners=True)
