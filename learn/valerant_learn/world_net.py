"""The world model network: one step of an action-conditioned next-frame predictor,
run autoregressively (the C++ backend feeds each output back as the newest context
frame).

Predicting pixels directly blurs within a few steps; most of what the camera sees
next is what it saw last, moved. So the net predicts a warp of the newest frame (a
flow field in pixels), a mask, and a fill colour for what the warp cannot show
(disocclusions, the image border a turn reveals):

  next = m * last(x + dx, y + dy) + (1 - m) * fill

The warp is done outside the net (apply_warp here in training, cv::remap in C++),
because OpenCV 4.6's ONNX importer has no GridSample.

Input "frames_and_motion" ("frames_motion_and_pose_warp" with the pose_anchor warp, so
that a backend configured for another warp cannot run the model by mistake): float32
[N, 3K+4+E, H, W]: K RGB frames in [0,1], oldest first, then four constant planes of
the commanded motion (forward_units, strafe_units, yaw_deg, pitch_deg; raw MotionStep
values, scaled inside the net), then E extra planes of the warp interface
(world_warp.py: none for last_frame; for rotation_anchor the newest frame turned by the
commanded rotation, RGB, and that rotation's in-view mask; for pose_anchor the newest
frame sampled where the commanded turn and translation send each pixel, and its in-view
mask).
Output "warp_and_fill": float32 [N, 6, H, W]: dx, dy (pixels), m in [0,1], fill RGB
in [0,1]; with the anchor warps the flow is added to the geometry's sampling positions.

A U-Net of plain 3x3 conv + BatchNorm + ReLU (ConvBN, folded for export) from half
resolution down to 1/16 and back to half, whose head is upsampled to full
resolution; the motion planes, average-pooled, join every encoder stage, and
row/column coordinate channels join the input (a turn moves the image's edge columns
differently from its centre)."""
import torch
from torch import nn
import torch.nn.functional as F

from .depth_net import AppendCoordinates, ConvBN
from .world_warp import ANCHOR_WARPS, EXTRA_INPUT_CHANNELS, VALID_MIN, AnchorState, anchor_step, pixel_grid, \
    rotation_sampling, sample

INPUT_NAME = "frames_and_motion"
POSE_ANCHOR_INPUT_NAME = "frames_motion_and_pose_warp"
OUTPUT_NAME = "warp_and_fill"
MOTION_CHANNELS = 4
# Typical per-frame magnitudes: w moves 256/57 = 4.5 units, j/l in place turn
# 90/57 = 1.6 deg; dividing by them puts the motion planes near 1.
MOTION_SCALE = (1 / 4.5, 1 / 4.5, 1 / 1.6, 1 / 1.6)
ENCODER_CHANNELS = (32, 64, 96, 160)
# The flow head's output is multiplied by this many pixels, so that its weights
# stay in the usual range for the largest flows of a frame (a 1.6 deg turn moves the
# image by about 1.8 px at 128 px and 90 deg field of view; a step forward, less).
FLOW_SCALE_PX = 4.0
# Channels of the full-resolution head (full_res_head).
FULL_RES_CHANNELS = 16
# The mask starts on the warp (sigmoid(4) = 0.98): the untrained net repeats the last frame.
MASK_INITIAL_LOGIT = 4.0


class ScaleMotion(nn.Module):
    """Multiplies each motion plane by its MOTION_SCALE factor: a fixed depthwise 1x1
    conv (a Mul by a [1,4,1,1] constant would need a broadcast OpenCV 4.6 may not fuse)."""

    def __init__(self):
        super().__init__()
        self.conv = nn.Conv2d(MOTION_CHANNELS, MOTION_CHANNELS, 1, groups=MOTION_CHANNELS, bias=False)
        with torch.no_grad():
            self.conv.weight.copy_(torch.tensor(MOTION_SCALE).view(MOTION_CHANNELS, 1, 1, 1))
        self.conv.weight.requires_grad_(False)

    def forward(self, motion):
        return self.conv(motion)


class WorldNet(nn.Module):
    """full_res_head: the head works at full resolution on the upsampled features and
    the newest frame (with the anchor warps: the newest frame moved by the geometry,
    which lines up with the output), so that the fill can carry detail (v2); without it the head works
    at half resolution and is upsampled (v1). warp: world_warp.WARPS."""

    def __init__(self, context, height, width, full_res_head=False, warp="last_frame"):
        super().__init__()
        if height % 16 or width % 16:
            raise ValueError("WorldNet: %dx%d is not a multiple of 16 in both sides" % (width, height))
        if warp not in EXTRA_INPUT_CHANNELS:
            raise ValueError("WorldNet: unknown warp %r (one of %s)" % (warp, ", ".join(EXTRA_INPUT_CHANNELS)))
        self.context, self.height, self.width, self.warp = context, height, width, warp
        self.extra_inputs = EXTRA_INPUT_CHANNELS[warp]
        self.scale_motion = ScaleMotion()
        self.coordinates = AppendCoordinates(height, width)
        c = ENCODER_CHANNELS
        inputs = 3 * context + MOTION_CHANNELS + self.extra_inputs + 2
        self.encoder = nn.ModuleList([nn.Sequential(ConvBN(inputs, c[0], 3, stride=2), ConvBN(c[0], c[0], 3))])
        for i in range(1, len(c)):
            self.encoder.append(nn.Sequential(ConvBN(c[i - 1] + MOTION_CHANNELS, c[i], 3, stride=2),
                                              ConvBN(c[i], c[i], 3)))
        self.bottleneck = ConvBN(c[-1], c[-1], 3)
        self.decoder = nn.ModuleList([ConvBN(c[i] + c[i - 1], c[i - 1], 3) for i in range(len(c) - 1, 0, -1)])
        self.full_res = ConvBN(c[0] + 3, FULL_RES_CHANNELS, 3) if full_res_head else None
        self.head = nn.Conv2d(FULL_RES_CHANNELS if full_res_head else c[0], 6, 3, padding=1)
        with torch.no_grad():
            self.head.weight.mul_(0.1)
            self.head.bias.zero_()
            self.head.bias[2] = MASK_INITIAL_LOGIT

    def forward(self, frames_and_motion):
        frames = frames_and_motion[:, :3 * self.context]
        motion_end = 3 * self.context + MOTION_CHANNELS
        motion = self.scale_motion(frames_and_motion[:, 3 * self.context:motion_end])
        # (An empty slice would export as a Slice OpenCV 4.6 gives one channel.)
        extra = [frames_and_motion[:, motion_end:]] if self.extra_inputs else []
        x = self.coordinates(torch.cat([frames, motion] + extra, 1))
        skips = []
        for i, stage in enumerate(self.encoder):
            if i > 0:
                x = torch.cat([x, motion], 1)
            x = stage(x)
            # The motion at the resolution the next stage's stride-2 conv reads.
            motion = F.avg_pool2d(motion, 2)
            skips.append(x)
        x = self.bottleneck(x)
        for stage, skip in zip(self.decoder, reversed(skips[:-1])):
            x = F.interpolate(x, scale_factor=2.0, mode="bilinear", align_corners=False)
            x = stage(torch.cat([x, skip], 1))
        if self.full_res is not None:
            x = F.interpolate(x, scale_factor=2.0, mode="bilinear", align_corners=False)
            guide = (frames_and_motion[:, motion_end:motion_end + 3] if self.warp in ANCHOR_WARPS
                     else frames[:, -3:])
            out = self.head(self.full_res(torch.cat([x, guide], 1)))
        else:
            # Flow, mask and fill are smooth, and the warp carries the detail.
            out = F.interpolate(self.head(x), scale_factor=2.0, mode="bilinear", align_corners=False)
        flow = out[:, 0:2] * FLOW_SCALE_PX
        mask = torch.sigmoid(out[:, 2:3])
        fill = torch.sigmoid(out[:, 3:6])
        return torch.cat([flow, mask, fill], 1)


def apply_warp(last, warp_and_fill):
    """The next frame from the newest context frame `last` (float [N,3,H,W] in [0,1])
    and the net's output: bilinear sampling at (x+dx, y+dy) with the border
    replicated, blended with the fill by the mask, clamped to [0,1]. The same
    arithmetic as the C++ backend's cv::remap(INTER_LINEAR, BORDER_REPLICATE)."""
    _, _, h, w = last.shape
    flow, mask, fill = warp_and_fill[:, 0:2], warp_and_fill[:, 2:3], warp_and_fill[:, 3:6]
    warped = sample(last, pixel_grid(h, w, last.device, last.dtype)[None] + flow)
    return (mask * warped + (1.0 - mask) * fill).clamp(0.0, 1.0)


def motion_planes(motion, height, width):
    """float [N,4] motions as [N,4,H,W] constant planes."""
    return motion[:, :, None, None].expand(-1, -1, height, width)


def input_channels(model):
    """Channels of the net's input: K frames, the motion, the warp's extra planes."""
    return 3 * model.context + MOTION_CHANNELS + model.extra_inputs


def input_name(warp):
    """The name of the net's input for a warp (the module text)."""
    return POSE_ANCHOR_INPUT_NAME if warp == "pose_anchor" else INPUT_NAME


def net_input(model, context, motion, camera, state=None):
    """The net's input for one step, the geometry's sampling positions (None for
    last_frame) and, for pose_anchor, the state's geometry moved to the next frame
    (else None). context [N,K,3,H,W], motion [N,4]; state: the AnchorState of pose_anchor."""
    n, k, _, h, w = context.shape
    parts = [context.reshape(n, 3 * k, h, w), motion_planes(motion, h, w)]
    positions = geometry = None
    if model.warp == "rotation_anchor":
        positions, in_view = rotation_sampling(motion, camera, h, w)
    elif model.warp == "pose_anchor":
        positions, in_view, geometry = state.geometry.sampling(state.coords, motion)
    if positions is not None:
        parts += [sample(context[:, -1], positions), in_view]
    return torch.cat(parts, 1), positions, geometry


def carry_seen(seen, positions, mask):
    """Where the next frame still shows what the context showed: its pixels whose
    sampling positions in the newest frame (positions [N,2,H,W]: the geometry's plus the
    flow) fall wholly on pixels that showed it (all four bilinear taps; none outside the
    image) and whose mask [N,1,H,W] keeps the warp rather than the fill. seen: float
    [N,1,H,W] of 0 and 1 for the newest frame; the same for the next. The training's
    adversarial term looks where this is 0, at what the model invented; unlike the anchor
    state's validity it is not reset when a generated frame becomes the anchor."""
    return ((sample(seen, positions, padding="zeros") >= VALID_MIN) & (mask >= 0.5)).to(seen.dtype)


def step(model, context, motion, camera=None, state=None, seen=None):
    """One autoregressive step. context: float [N,K,3,H,W] in [0,1], oldest first;
    motion: float [N,4]; camera (fx, fy, cx, cy) and the AnchorState for the anchor
    warps; seen: carry_seen()'s map of the newest frame, or None. Returns (next frame
    [N,3,H,W], context for the step after, state after, seen map of the next frame or
    None)."""
    x, positions, geometry = net_input(model, context, motion, camera, state)
    out = model(x)
    last = context[:, -1]
    if model.warp in ANCHOR_WARPS:
        positions = positions + out[:, 0:2]
        frame, state = anchor_step(state, last, positions, out[:, 2:3], out[:, 3:6], geometry)
    else:
        frame = apply_warp(last, out)
        if seen is not None:  # apply_warp's sampling positions
            positions = pixel_grid(last.shape[2], last.shape[3], last.device, last.dtype)[None] + out[:, 0:2]
    if seen is not None:
        seen = carry_seen(seen, positions, out[:, 2:3])
    return frame, torch.cat([context[:, 1:], frame[:, None]], 1), state, seen


def start_state(model, context, camera=None, depth=None):
    """The anchor warps' state at the start of a rollout from context [N,K,3,H,W]: the
    newest context frame is the anchor; pose_anchor needs its depth [N,1,H,W] (metres,
    the depth prior's). None for last_frame."""
    if model.warp not in ANCHOR_WARPS:
        return None
    if model.warp == "pose_anchor" and depth is None:
        raise ValueError("the pose_anchor warp needs the depth of the newest context frame")
    return AnchorState.start(context[:, -1], depth if model.warp == "pose_anchor" else None, camera)


def rollout(model, context, motions, camera=None, depth=None, with_invented=False):
    """Autoregressive frames for motions float [N,T,4] from context [N,K,3,H,W]:
    float [N,T,3,H,W]. The anchor warps' anchor starts at the newest context frame, whose
    depth [N,1,H,W] pose_anchor needs. with_invented: also returns, as a second value,
    float [N,T,1,H,W], 1 where a frame's pixel shows what no context frame held (1 -
    carry_seen()'s map, which starts at 1 on the newest context frame)."""
    state = start_state(model, context, camera, depth)
    seen = torch.ones_like(context[:, -1, :1]) if with_invented else None
    frames, invented = [], []
    for t in range(motions.shape[1]):
        frame, context, state, seen = step(model, context, motions[:, t], camera, state, seen)
        frames.append(frame)
        if with_invented:
            invented.append(1.0 - seen)
    frames = torch.stack(frames, 1)
    return (frames, torch.stack(invented, 1)) if with_invented else frames
