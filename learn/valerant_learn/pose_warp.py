"""The pose_anchor warp's geometry: the camera's commanded motion (turn and translation)
and where each pixel of the next frame lies in the newest frame through its depth.
world_warp.py carries it from frame to frame; include/valerant/world/learned/pose_warp.h
is the same arithmetic in C++.

A camera pose is [x, y, yaw_deg, pitch_deg]: x, y in metres on the floor plane of the
rollout's first anchor (that camera at 0, 0 with heading 0: x ahead, y to its left), yaw
left positive, pitch down positive. The first anchor is taken as level (a screenshot's
pitch is unknown; every training sequence is level), and the height never changes: a
MotionStep has no vertical part (stairs are left to the net's residual flow).

advance_pose applies a MotionStep as the engine does (camera_kinematics.cpp): turn first,
then move forward and strafe along the new heading, 32 units a metre.

The camera's optical axes (x right, y down, z ahead) in the floor frame, as
CameraKinematics::cameraToWorld:
  forward = (cos p cos a, cos p sin a, -sin p),  right = (sin a, -cos a, 0),
  down = forward x right = (-sin p cos a, -sin p sin a, -cos p)
so with R = [right | down | forward] and c the position (x, y, 0), a point X in camera
B's optical frame is R_A^T R_B X + R_A^T (c_B - c_A) in camera A's (relative_transform).

pose_sampling: pixel p of the next camera M has the ray d = ((x + 0.5 - cx) / fx,
(y + 0.5 - cy) / fy, 1); its point at depth z' is a z' + t in the newest camera N, with
a = R d and (R, t) = relative_transform(N, M). Its depth there, a_z z' + t_z, must be the
newest frame's depth Z_N where it projects: a fixed point, found from the rotation's
position (the point at infinity), s_0 = proj(a), by
  Z       = Z_N(s_k)                      (bilinear, the border replicated)
  z'      = (Z - t_z) / a_z
  s_k+1   = proj(a z' + t) = (fx (a_x z' + t_x) / Z + cx - 0.5, fy (a_y z' + t_y) / Z + cy - 0.5)
FIXED_POINT_ITERATIONS times. On a surface of constant depth one iteration is exact; on
the floor the error shrinks by |dZ_N/ds| |ds/dZ|, about 0.07 an iteration for the
bottom row and a 4.5-unit step (docs/world_model.md). Where a surface edge lies between
s_k and the answer (a disocclusion) there is no fixed point and the last iterate stands:
the net's residual flow and fill are for those pixels. in_view: a_z > 0 (the ray is
ahead of the newest camera), z' > 0 (the surface is ahead of the next one) and the
position inside the image; rays behind the newest camera are parked at its centre.

depth_in_camera: a pixel's depth in a camera of the anchor's rollout, from the anchor's
depth at the pixel's anchor coordinates and the two poses."""
import torch

from .bilinear import pixel_grid, sample

UNITS_PER_METRE = 32.0
FIXED_POINT_ITERATIONS = 3
# Depths are clamped to at least this (the dataset's nearest depth), so that a point
# always projects; the prior calls the sky 80 m, and so does a missing true depth here.
MIN_DEPTH_M = 0.05
SKY_DEPTH_M = 80.0


def advance_pose(pose, motion):
    """The poses [N,4] after the MotionSteps motion [N,4] (forward_units, strafe_units,
    yaw_deg, pitch_deg)."""
    yaw = pose[:, 2] + motion[:, 2]
    heading = torch.deg2rad(yaw)
    forward, strafe = motion[:, 0] / UNITS_PER_METRE, motion[:, 1] / UNITS_PER_METRE
    x = pose[:, 0] + forward * torch.cos(heading) + strafe * torch.sin(heading)
    y = pose[:, 1] + forward * torch.sin(heading) - strafe * torch.cos(heading)
    return torch.stack([x, y, yaw, pose[:, 3] + motion[:, 3]], 1)


def camera_axes(pose):
    """[N,3,3]: columns right, down, forward of the cameras at `pose` in the floor frame."""
    a, p = torch.deg2rad(pose[:, 2]), torch.deg2rad(pose[:, 3])
    zero = torch.zeros_like(a)
    right = torch.stack([torch.sin(a), -torch.cos(a), zero], 1)
    down = torch.stack([-torch.sin(p) * torch.cos(a), -torch.sin(p) * torch.sin(a), -torch.cos(p)], 1)
    forward = torch.stack([torch.cos(p) * torch.cos(a), torch.cos(p) * torch.sin(a), -torch.sin(p)], 1)
    return torch.stack([right, down, forward], 2)


def relative_transform(to_pose, from_pose):
    """(R [N,3,3], t [N,3]): a point X in the optical frame of the camera at from_pose is
    R X + t in that of the camera at to_pose."""
    r_to, r_from = camera_axes(to_pose), camera_axes(from_pose)
    offset = torch.stack([from_pose[:, 0] - to_pose[:, 0], from_pose[:, 1] - to_pose[:, 1],
                          torch.zeros_like(from_pose[:, 0])], 1)
    r_to_t = r_to.transpose(1, 2)
    return r_to_t @ r_from, (r_to_t @ offset[:, :, None])[:, :, 0]


def pixel_rays(camera, positions):
    """[N,3,H,W]: the rays (x, y, 1) of pixel-index positions [N,2,H,W]."""
    x = (positions[:, 0] + 0.5 - camera["cx"]) / camera["fx"]
    y = (positions[:, 1] + 0.5 - camera["cy"]) / camera["fy"]
    return torch.stack([x, y, torch.ones_like(x)], 1)


def rotate(r, vectors):
    """R [N,3,3] applied to every vector of [N,3,H,W]."""
    return torch.einsum("nij,njhw->nihw", r, vectors)


def pose_sampling(newest_depth, newest_pose, next_pose, camera):
    """Where each pixel of the camera at next_pose looks in the newest frame, whose depth
    (metres along its optical axis) is newest_depth [N,1,H,W] and pose newest_pose [N,4]:
    (positions [N,2,H,W] in pixel-index coordinates, in_view [N,1,H,W]). See the module
    text."""
    n, _, height, width = newest_depth.shape
    r, t = relative_transform(newest_pose, next_pose)
    t = t[:, :, None, None]
    grid = pixel_grid(height, width, newest_depth.device, newest_depth.dtype)[None].expand(n, -1, -1, -1)
    a = rotate(r, pixel_rays(camera, grid))
    ahead = a[:, 2:3] > 1e-6
    a_z = torch.where(ahead, a[:, 2:3], torch.ones_like(a[:, 2:3]))
    centre = torch.tensor([(width - 1) / 2, (height - 1) / 2], device=a.device, dtype=a.dtype).view(1, 2, 1, 1)
    focal = torch.tensor([camera["fx"], camera["fy"]], device=a.device, dtype=a.dtype).view(1, 2, 1, 1)
    principal = torch.tensor([camera["cx"] - 0.5, camera["cy"] - 0.5], device=a.device,
                             dtype=a.dtype).view(1, 2, 1, 1)
    positions = torch.where(ahead, focal * a[:, :2] / a_z + principal, centre)
    depth_ahead = torch.zeros_like(a_z)
    for _ in range(FIXED_POINT_ITERATIONS):
        depth = sample(newest_depth, positions).clamp(min=MIN_DEPTH_M)
        depth_ahead = (depth - t[:, 2:3]) / a_z
        point = a[:, :2] * depth_ahead + t[:, :2]
        positions = torch.where(ahead, focal * point / depth + principal, centre)
    u, v = positions[:, 0:1], positions[:, 1:2]
    inside = (u >= 0) & (u <= width - 1) & (v >= 0) & (v <= height - 1)
    return positions, (ahead & (depth_ahead > 0) & inside).to(newest_depth.dtype)


def depth_in_camera(anchor_depth, coords, anchor_pose, pose, camera):
    """[N,1,H,W]: the depth in the camera at `pose` of each pixel's point, the anchor's
    pixel at coords [N,2,H,W] at its depth anchor_depth [N,1,H,W] (sampled bilinearly),
    clamped to at least MIN_DEPTH_M."""
    r, t = relative_transform(pose, anchor_pose)
    points = pixel_rays(camera, coords) * sample(anchor_depth, coords)
    return (rotate(r, points)[:, 2:3] + t[:, 2, None, None, None]).clamp(min=MIN_DEPTH_M)


class PoseGeometry:
    """The pose_anchor warp's part of world_warp.AnchorState: the anchor frame's depth
    [N,1,H,W] (metres, in its own camera) and pose [N,4], and the newest frame's pose
    [N,4], for cameras `camera` (fx, fy, cx, cy)."""

    def __init__(self, depth, anchor_pose, pose, camera):
        self.depth, self.anchor_pose, self.pose, self.camera = depth, anchor_pose, pose, camera

    @staticmethod
    def start(depth, camera):
        """The geometry of an anchor seen at `depth` [N,1,H,W] (not finite, as a missing
        true depth's NaN: the sky; at least MIN_DEPTH_M), both poses the first anchor's (zeros)."""
        depth = torch.nan_to_num(depth, nan=SKY_DEPTH_M, posinf=SKY_DEPTH_M, neginf=SKY_DEPTH_M).clamp(min=MIN_DEPTH_M)
        zero = torch.zeros(depth.shape[0], 4, device=depth.device, dtype=depth.dtype)
        return PoseGeometry(depth, zero, zero, camera)

    def depth_of(self, coords):
        """The newest frame's depth of pixels whose anchor coordinates are coords [N,2,H,W]."""
        return depth_in_camera(self.depth, coords, self.anchor_pose, self.pose, self.camera)

    def moved(self, motion):
        """The geometry after the MotionSteps motion [N,4]: the newest pose advanced."""
        return PoseGeometry(self.depth, self.anchor_pose, advance_pose(self.pose, motion), self.camera)

    def sampling(self, coords, motion):
        """pose_sampling() of the step by motion [N,4] from the newest frame (anchor
        coordinates coords [N,2,H,W]): (positions, in_view, the geometry moved)."""
        moved = self.moved(motion)
        # The geometry is an input, not learnt through: a gradient through the depth's
        # fixed point is divided by the ray's a_z and the depth each iteration, and
        # overflowed to NaN in the first GPU run's 24-frame unrolls.
        positions, in_view = pose_sampling(self.depth_of(coords).detach(), self.pose, moved.pose, self.camera)
        return positions, in_view, moved

    def reanchored(self, coords, pick):
        """Where pick [N] (bool) is set, the geometry whose anchor is the newest frame, whose
        pixels lie at anchor coordinates coords: its depth carried over, its pose the newest."""
        where = pick[:, None, None, None]
        return PoseGeometry(torch.where(where, self.depth_of(coords).detach(), self.depth),
                            torch.where(pick[:, None], self.pose, self.anchor_pose), self.pose, self.camera)
