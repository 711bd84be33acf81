"""The world model's warps: where each pixel of the next frame is sampled from.

Three interfaces (world.learned.warp in the C++ config, `--warp` of train_world_model.py):

last_frame (models v1, v2): the net's flow moves the newest frame,
  next = m * newest(p + flow) + (1 - m) * fill.
  A turn's flow must be learnt, and it came out short (docs/world_model.md: the turns
  lag), and each frame resamples the one before, so detail blurs away within 30 frames.

rotation_anchor (v3): the camera's own rotation is applied exactly and the net
  predicts only what it cannot know (the parallax of a translation, disocclusions):
    p_rot = rotation_sampling(yaw, pitch)(p)    where p looks in the newest frame for
                                                the commanded rotation alone
    s     = p_rot + flow(p)                     the net's residual flow on top
  and pixels are sampled from a sharp *anchor* frame through a coordinate map instead
  of from the newest frame, so a pixel is interpolated once however many frames it
  survives. The state beside the context frames:
    anchor [3,H,W]  the frame the coordinates point into
    coords [2,H,W]  for each pixel of the newest frame, where its colour lies in anchor
    valid  [1,H,W]  1 where the newest frame's pixel is anchor(coords), 0 where it was
                    made by the fill (or sampled from a fill pixel)
  One step:
    coords' = coords(s), valid' = valid(s) (bilinear; outside the image valid is 0)
    warped  = anchor(coords')  where valid' >= VALID_MIN, else newest(s)
    next    = m * warped + (1 - m) * fill
    valid   = (valid' >= VALID_MIN) and (m >= 0.5)
  and when less than REANCHOR_FRACTION of the pixels stay valid, the new frame becomes
  the anchor (coords the identity, valid 1), so the fill's content is also sampled
  from one frame from then on. The net also reads newest(p_rot) and the rotation's
  in-view mask (4 more input planes): it sees the picture already turned.

pose_anchor: as rotation_anchor, but the geometry is the whole commanded camera motion,
  the turn and the translation, through each pixel's depth (pose_warp.py): p_rot is
  replaced by pose_warp.pose_sampling's position, so the translation's parallax is
  geometry and the net's flow only its residual; the net reads the newest frame at those
  positions and their in-view mask (the same 4 planes). The state also holds the anchor's
  depth (the depth prior's prediction on the first anchor, a real frame), the anchor's
  pose and the newest frame's pose (pose_warp.PoseGeometry); the newest frame's depth is
  that of the anchor pixels its coordinates point to, seen from the newest pose. When a
  generated frame becomes the anchor, its depth is that depth, carried over, never a new
  prediction: so training (which cannot run the ONNX prior inside the unroll) and the
  C++ backend do the same.

Sampling is bilinear with the border replicated in pixel-index coordinates (pixel i's
centre at i): torch.grid_sample(align_corners=True) here, cv::remap(INTER_LINEAR,
BORDER_REPLICATE) in C++ (include/valerant/world/learned/anchor_warp.h); valid is
sampled with zeros outside (BORDER_CONSTANT 0)."""
import torch

from .bilinear import pixel_grid, sample
from .pose_warp import PoseGeometry

WARPS = ("last_frame", "rotation_anchor", "pose_anchor")
# The warps that sample through an anchor's coordinate map.
ANCHOR_WARPS = ("rotation_anchor", "pose_anchor")
# Extra input planes of each interface after the K frames and 4 motion planes.
EXTRA_INPUT_CHANNELS = {"last_frame": 0, "rotation_anchor": 4, "pose_anchor": 4}
# A sampled validity at least this is a pixel of the anchor (1 - a rounding margin:
# bilinear weights of four valid pixels sum to 1 up to float error).
VALID_MIN = 0.999
# Below this share of valid pixels the new frame becomes the anchor.
REANCHOR_FRACTION = 0.6


def rotation_sampling(motion, camera, height, width):
    """Where each pixel of the next frame looks in the newest frame when the camera
    only rotates by the motion's yaw (left positive) and pitch (down positive):
    (positions [N,2,H,W] in pixel-index coordinates, in_view [N,1,H,W] 1.0 where the
    ray lies in front of the newest camera and inside its image).

    camera: fx, fy, cx, cy of the frames, cx, cy measured from the image's corner
    (pixel i spans [i, i+1), its centre i + 0.5: the dataset's convention, cx = W/2).
    The ray of next-frame pixel p, d = ((x + 0.5 - cx)/fx, (y + 0.5 - cy)/fy, 1) in its
    optical frame (x right, y down, z forward), is carried into the newest camera's
    frame by the pitch, about x, then the yaw, about the vertical y:
      pitch b: (x, y cos b + z sin b, -y sin b + z cos b)
      yaw a:   (x cos a - z sin a, y, x sin a + z cos a)
    and projected back. Exact when the newest frame's own pitch is zero (the yaw then
    turns about the camera's y axis), as in every training sequence."""
    n = motion.shape[0]
    grid = pixel_grid(height, width, motion.device, motion.dtype)
    x = ((grid[0] + 0.5 - camera["cx"]) / camera["fx"]).expand(n, height, width)
    y = ((grid[1] + 0.5 - camera["cy"]) / camera["fy"]).expand(n, height, width)
    yaw = torch.deg2rad(motion[:, 2])[:, None, None]
    pitch = torch.deg2rad(motion[:, 3])[:, None, None]
    y1 = y * torch.cos(pitch) + torch.sin(pitch)
    z1 = -y * torch.sin(pitch) + torch.cos(pitch)
    x2 = x * torch.cos(yaw) - z1 * torch.sin(yaw)
    z2 = x * torch.sin(yaw) + z1 * torch.cos(yaw)
    ahead = z2 > 1e-6
    safe_z = torch.where(ahead, z2, torch.ones_like(z2))
    u = camera["fx"] * x2 / safe_z + camera["cx"] - 0.5
    v = camera["fy"] * y1 / safe_z + camera["cy"] - 0.5
    inside = ahead & (u >= 0) & (u <= width - 1) & (v >= 0) & (v <= height - 1)
    # Rays behind the camera sample nothing: park them at the image centre.
    u = torch.where(ahead, u, torch.full_like(u, (width - 1) / 2))
    v = torch.where(ahead, v, torch.full_like(v, (height - 1) / 2))
    return torch.stack([u, v], 1), inside[:, None].to(motion.dtype)


class AnchorState:
    """The anchor warps' state of a batch (see the module text); geometry: the
    pose_anchor warp's pose_warp.PoseGeometry, None for rotation_anchor."""

    def __init__(self, anchor, coords, valid, geometry=None):
        self.anchor, self.coords, self.valid, self.geometry = anchor, coords, valid, geometry

    @staticmethod
    def start(frame, depth=None, camera=None):
        """The state whose anchor is `frame` [N,3,H,W] itself; for pose_anchor also its
        depth [N,1,H,W] (metres) and the camera (fx, fy, cx, cy)."""
        n, _, h, w = frame.shape
        coords = pixel_grid(h, w, frame.device, frame.dtype).expand(n, -1, -1, -1).contiguous()
        geometry = None if depth is None else PoseGeometry.start(depth, camera)
        return AnchorState(frame, coords, torch.ones_like(frame[:, :1]), geometry)


def anchor_step(state, newest, positions, mask, fill, geometry=None):
    """The next frame [N,3,H,W] and the state after it. newest: the newest frame;
    positions [N,2,H,W]: s = p_rot + flow (pose_anchor: the pose's positions + flow);
    mask [N,1,H,W], fill [N,3,H,W]; geometry: for pose_anchor, the state's geometry
    moved to the next frame (PoseGeometry.sampling)."""
    coords = sample(state.coords, positions)
    sampled_valid = sample(state.valid, positions, padding="zeros")
    from_anchor = sampled_valid >= VALID_MIN
    warped = torch.where(from_anchor, sample(state.anchor, coords), sample(newest, positions))
    frame = (mask * warped + (1.0 - mask) * fill).clamp(0.0, 1.0)
    valid = (from_anchor & (mask >= 0.5)).to(frame.dtype)
    reanchor = valid.mean((1, 2, 3)) < REANCHOR_FRACTION
    if bool(reanchor.any()):
        fresh = AnchorState.start(frame)
        pick = reanchor[:, None, None, None]
        return frame, AnchorState(torch.where(pick, frame, state.anchor), torch.where(pick, fresh.coords, coords),
                                  torch.where(pick, fresh.valid, valid),
                                  None if geometry is None else geometry.reanchored(coords, reanchor))
    return frame, AnchorState(state.anchor, coords, valid, geometry)
