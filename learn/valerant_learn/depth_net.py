"""The depth prior network: a small encoder-decoder sized for one CPU core.

Encoder: MobileNetV2-style inverted residuals down to stride 32. Decoder: a light
U-Net (bilinear upsampling, skip concatenation, depthwise-separable convs) back to
full resolution. Every conv but the two 1x1 heads is followed by BatchNorm (+ReLU),
which fold_batchnorm() folds away for export, so the exported graph holds only ops
OpenCV 4.6's ONNX importer runs: Conv, Relu, Add, Sub, Mul, Slice, Concat, Resize.

Input "rgb": float32 [N,3,H,W] RGB in [0,1]. Output "depth_and_scale": float32
[N,2,H,W]; channel 0 is ln(depth in metres), channel 1 is ln(b), b the Laplace
scale of the ln-depth error, clamped to [LOG_SCALE_MIN, LOG_SCALE_MAX].

With a floor prior (floor_prior.py) the depth head predicts ln depth relative to
the floor-plane depth of each row, added inside the net: the output is the same.
With global context (GlobalContext) the stride-32 features also see a summary of
the whole frame before decoding; with column context (ColumnContext) the stride-8
decoder features see a summary of their image column. With deep_blocks N, each of the
two coarsest encoder stages (strides 16 and 32) ends with N more stride-1 blocks: depth
where a frame is 48 and 12 positions, which costs parameters but few multiply-adds.
With input_scale 2 the net reads a frame of twice its output size (InputStem): one
stride-2 conv brings it to the output size, where the net goes on as at scale 1 and
its last decoder stage gets those features as a skip. A 128 x 96 frame blurs a wall's
texels within a few metres; the texel size is a metric cue (a level's textures are
mapped at one scale), so the net sees them at 256 x 192 and still costs about what it
did: the extra conv runs once, at the output size."""
import copy
import math

import torch
from torch import nn
import torch.nn.functional as F
from torch.nn.utils.fusion import fuse_conv_bn_eval

from .floor_prior import floor_log_depth
from .losses import SKY_DEPTH_M

INPUT_NAME = "rgb"
OUTPUT_NAME = "depth_and_scale"
LOG_SCALE_MIN = -6.0
LOG_SCALE_MAX = 3.0
# Start the depth head at 4 m, a typical arena range, so the first steps need not
# learn the offset.
INITIAL_DEPTH_M = 4.0

# (output channels, stride, expansion) of each inverted residual; a stride-2 block
# starts each stage, and the encoder keeps the output of each stage as a skip.
ENCODER_STAGES = [
    [(16, 1, 1)],                                        # stride 2
    [(24, 2, 6), (24, 1, 6)],                            # stride 4
    [(32, 2, 6), (32, 1, 6), (32, 1, 6)],                # stride 8
    [(64, 2, 6), (64, 1, 6), (64, 1, 6), (96, 1, 6), (96, 1, 6)],  # stride 16
    [(160, 2, 6), (160, 1, 6), (160, 1, 6)],             # stride 32
]
STEM_CHANNELS = 16
# Decoder output channels from stride 16 up to full resolution.
DECODER_CHANNELS = [96, 64, 32, 24, 16]
# Width of GlobalContext's summary of the frame.
GLOBAL_CONTEXT_CHANNELS = 256
# Width of ColumnContext's summary of a column, and the decoder stage it follows
# (stage 1 outputs stride 8: 16 columns of 8 pixels at 128 x 96).
COLUMN_CONTEXT_CHANNELS = 64
COLUMN_CONTEXT_STAGE = 1
# Input size over output size: 1, or 2 through an InputStem of this many features (not
# widened by the width multiplier: each of them costs about 1.2 M multiply-adds a frame).
INPUT_SCALES = (1, 2)
INPUT_STEM_CHANNELS = 8
# Channel counts are multiples of this after a width multiplier (the usual MobileNet
# rounding, which keeps the convolutions' vector loops full).
CHANNEL_DIVISOR = 8


class ConvBN(nn.Sequential):
    """Conv2d -> BatchNorm2d (-> ReLU)."""

    def __init__(self, cin, cout, kernel=1, stride=1, groups=1, relu=True):
        layers = [nn.Conv2d(cin, cout, kernel, stride, kernel // 2, groups=groups, bias=False),
                  nn.BatchNorm2d(cout)]
        if relu:
            layers.append(nn.ReLU(inplace=True))
        super().__init__(*layers)

    def fold(self):
        self[0] = fuse_conv_bn_eval(self[0], self[1])
        self[1] = nn.Identity()


def scaled_channels(channels, multiplier):
    """channels x multiplier, rounded to the nearest multiple of CHANNEL_DIVISOR and
    never below one of them: the stage widths of a net widened or narrowed by
    `multiplier` (1 leaves every listed width as it is, all being multiples of 8)."""
    return max(CHANNEL_DIVISOR, int(channels * multiplier / CHANNEL_DIVISOR + 0.5) * CHANNEL_DIVISOR)


def coordinate_channels(height, width):
    """[2,H,W]: row and column of each pixel centre, scaled to [-1,1]."""
    rows = (torch.arange(height, dtype=torch.float32) + 0.5) / height * 2 - 1
    cols = (torch.arange(width, dtype=torch.float32) + 0.5) / width * 2 - 1
    return torch.stack([rows[:, None].expand(height, width), cols[None, :].expand(height, width)])


class AppendCoordinates(nn.Module):
    """Appends row/column coordinate channels to the image.

    The camera height is fixed, so an image row says how far the floor seen there
    is: the net needs to know where it is in the image. The constant is made
    batch-sized as rgb[:, :2] * 0 + coords (a [2,H,W] constant broadcasts over the
    batch in an Add), because ONNX Concat does not broadcast. (Adding the first
    conv's coordinate term as a constant after that conv would be cheaper, but
    OpenCV 4.6 fails an assertion when it fuses such an Add into the conv.)"""

    def __init__(self, height, width):
        super().__init__()
        self.register_buffer("coords", coordinate_channels(height, width))

    def forward(self, rgb):
        return torch.cat([rgb, rgb[:, :2] * 0 + self.coords], 1)


class AddFloorPrior(nn.Module):
    """Adds the floor prior's ln depth (floor_prior.floor_log_depth, far at the sky
    depth) to the depth head's [N,1,H,W] output. The constant is made batch-sized
    as rgb[:, :1] * 0 + prior for the reason AppendCoordinates gives: OpenCV 4.6
    fails when it fuses an Add of a spatial constant into the conv before it."""

    def __init__(self, height, width, camera):
        super().__init__()
        self.camera = {key: float(camera[key]) for key in ("fy", "cy", "eye_height_m")}
        self.register_buffer("log_depth", floor_log_depth(height, width, camera, SKY_DEPTH_M)[None])

    def forward(self, residual, rgb):
        return residual + (rgb[:, :1] * 0 + self.log_depth)


class GlobalContext(nn.Module):
    """Concatenates a summary of the whole frame (the mean of the features, through
    two 1x1 layers) to every position, then mixes back to the input width.

    How far a wall is depends on the room's size, which a 3x3 stack sees only in
    part; the mean over the frame is a cheap view of all of it. The summary is
    spread by a nearest Resize of fixed scales (a broadcasting Add of two tensors
    is not in OpenCV 4.6's importer)."""

    def __init__(self, channels, grid_height, grid_width):
        super().__init__()
        self.grid = (float(grid_height), float(grid_width))
        self.summary = nn.Sequential(nn.Conv2d(channels, GLOBAL_CONTEXT_CHANNELS, 1), nn.ReLU(inplace=True),
                                     nn.Conv2d(GLOBAL_CONTEXT_CHANNELS, GLOBAL_CONTEXT_CHANNELS, 1),
                                     nn.ReLU(inplace=True))
        self.mix = ConvBN(channels + GLOBAL_CONTEXT_CHANNELS, channels)

    def forward(self, x):
        summary = self.summary(F.adaptive_avg_pool2d(x, 1))
        spread = F.interpolate(summary, scale_factor=self.grid, mode="nearest")
        return self.mix(torch.cat([x, spread], 1))


class ColumnContext(nn.Module):
    """Concatenates a summary of each image column (the mean of the features over
    its rows, through a 1x1 layer) to every position of that column, then mixes
    back to the input width.

    The eye is always at the same height over a level floor, so a wall stands as
    far away as the floor straight below it in the same image column: the column
    holds the answer, but a 3x3 stack at stride 8 sees only a few of its rows.
    The mean is an AveragePool over the whole grid height, spread back over the
    rows by a nearest Resize of fixed scales (both in OpenCV 4.6's importer; a
    broadcasting Add of two tensors is not)."""

    def __init__(self, channels, grid_height, summary_channels=COLUMN_CONTEXT_CHANNELS):
        super().__init__()
        self.rows = grid_height
        self.summary = nn.Sequential(nn.Conv2d(channels, summary_channels, 1), nn.ReLU(inplace=True))
        self.mix = ConvBN(channels + summary_channels, channels)

    def forward(self, x):
        summary = self.summary(F.avg_pool2d(x, (self.rows, 1)))
        spread = F.interpolate(summary, scale_factor=(float(self.rows), 1.0), mode="nearest")
        return self.mix(torch.cat([x, spread], 1))


class InvertedResidual(nn.Module):
    """MobileNetV2 block: 1x1 expand, 3x3 depthwise, linear 1x1 project."""

    def __init__(self, cin, cout, stride, expansion):
        super().__init__()
        hidden = cin * expansion
        layers = [ConvBN(cin, hidden)] if expansion != 1 else []
        layers += [ConvBN(hidden, hidden, 3, stride, groups=hidden), ConvBN(hidden, cout, relu=False)]
        self.body = nn.Sequential(*layers)
        self.residual = stride == 1 and cin == cout

    def forward(self, x):
        return x + self.body(x) if self.residual else self.body(x)


def separable(cin, cout):
    """Depthwise 3x3 then pointwise 1x1, each with BN+ReLU."""
    return nn.Sequential(ConvBN(cin, cin, 3, groups=cin), ConvBN(cin, cout))


class DecoderStage(nn.Module):
    """Upsample x2, concatenate the encoder skip (if any), separable conv."""

    def __init__(self, cin, skip, cout):
        super().__init__()
        self.conv = separable(cin + skip, cout)

    def forward(self, x, skip=None):
        x = F.interpolate(x, scale_factor=2.0, mode="bilinear", align_corners=False)
        return self.conv(x if skip is None else torch.cat([x, skip], 1))


def clamp_by_relu(x, low, high):
    """torch.clamp(x, low, high) written as low + relu(x - low) - relu(x - high):
    opset 11 exports clamp as a Clip with min/max inputs, which OpenCV 4.6 rejects."""
    return low + F.relu(x - low) - F.relu(x - high)


class InputStem(nn.Module):
    """A frame of twice the output size to `channels` features at the output size:
    coordinates appended at the input size, one 3x3 stride-2 conv."""

    def __init__(self, height, width, channels):
        super().__init__()
        self.coordinates = AppendCoordinates(2 * height, 2 * width)
        self.conv = ConvBN(5, channels, 3, 2)

    def forward(self, rgb):
        return self.conv(self.coordinates(rgb))


class DepthNet(nn.Module):
    """floor_prior: None (the depth head predicts ln depth itself) or the camera
    (fy, cy, eye_height_m) whose floor-plane depth the head predicts ln depth
    relative to. global_context: a GlobalContext after the encoder. column_context:
    a ColumnContext after decoder stage COLUMN_CONTEXT_STAGE. width_multiplier:
    every encoder and decoder width times this (scaled_channels); the contexts'
    summaries keep theirs. deep_blocks: stride-1 blocks added at the end of the
    stride-16 and the stride-32 stage each (0: ENCODER_STAGES as listed).
    input_scale: 1 (the net reads height x width) or 2 (it reads twice that, through
    an InputStem); the output is height x width either way."""

    def __init__(self, height=96, width=128, floor_prior=None, global_context=False, column_context=False,
                 width_multiplier=1.0, deep_blocks=0, input_scale=1):
        super().__init__()
        if height % 32 or width % 32:
            raise ValueError("DepthNet needs a size divisible by 32, got %dx%d" % (width, height))
        if not width_multiplier > 0:
            raise ValueError("DepthNet needs a positive width multiplier, got %r" % (width_multiplier,))
        if not (isinstance(deep_blocks, int) and deep_blocks >= 0):
            raise ValueError("DepthNet needs a whole number of deep blocks, at least 0, got %r" % (deep_blocks,))
        if input_scale not in INPUT_SCALES:
            raise ValueError("DepthNet needs an input scale among %s, got %r" % (INPUT_SCALES, input_scale))
        self.height, self.width = height, width
        self.input_scale = input_scale
        self.input_height, self.input_width = height * input_scale, width * input_scale
        self.width_multiplier = float(width_multiplier)
        self.deep_blocks = deep_blocks

        def widen(channels):
            return scaled_channels(channels, self.width_multiplier)

        decoder_channels = [widen(channels) for channels in DECODER_CHANNELS]
        self.floor_prior = None if floor_prior is None else AddFloorPrior(height, width, floor_prior)
        self.input_stem = InputStem(height, width, INPUT_STEM_CHANNELS) if input_scale == 2 else None
        image_channels = 3 if self.input_stem is None else INPUT_STEM_CHANNELS
        self.coordinates = AppendCoordinates(height, width)
        self.stem = ConvBN(image_channels + 2, widen(STEM_CHANNELS), 3, 2)
        self.stages = nn.ModuleList()
        channels, skips = widen(STEM_CHANNELS), []
        for index, stage in enumerate(ENCODER_STAGES):
            if index >= len(ENCODER_STAGES) - 2:  # the stride-16 and stride-32 stages
                last_channels, _, last_expansion = stage[-1]
                stage = stage + [(last_channels, 1, last_expansion)] * deep_blocks
            blocks = []
            for cout, stride, expansion in stage:
                blocks.append(InvertedResidual(channels, widen(cout), stride, expansion))
                channels = widen(cout)
            self.stages.append(nn.Sequential(*blocks))
            skips.append(channels)
        self.global_context = GlobalContext(channels, height // 32, width // 32) if global_context else None
        # Skips at strides 16, 8, 4, 2, then at full resolution the input stem's (if any).
        self.decoder = nn.ModuleList()
        full_resolution_skip = 0 if self.input_stem is None else INPUT_STEM_CHANNELS
        for cout, skip in zip(decoder_channels, skips[-2::-1] + [full_resolution_skip]):
            self.decoder.append(DecoderStage(channels, skip, cout))
            channels = cout
        column_stride = 16 // 2 ** COLUMN_CONTEXT_STAGE
        self.column_context = (ColumnContext(decoder_channels[COLUMN_CONTEXT_STAGE], height // column_stride)
                               if column_context else None)
        self.depth_head = nn.Conv2d(channels, 1, 1)
        self.scale_head = nn.Conv2d(channels, 1, 1)
        nn.init.zeros_(self.depth_head.weight)
        # With the prior the net starts at the floor-plane depth (under the sky's).
        nn.init.constant_(self.depth_head.bias, 0.0 if self.floor_prior is not None else math.log(INITIAL_DEPTH_M))
        nn.init.zeros_(self.scale_head.bias)

    def forward(self, rgb):
        image = rgb if self.input_stem is None else self.input_stem(rgb)
        x = self.stem(self.coordinates(image))
        skips = [] if self.input_stem is None else [image]
        for stage in self.stages:
            x = stage(x)
            skips.append(x)
        x = skips.pop()
        if self.global_context is not None:
            x = self.global_context(x)
        for index, stage in enumerate(self.decoder):
            x = stage(x, skips.pop() if skips else None)
            if index == COLUMN_CONTEXT_STAGE and self.column_context is not None:
                x = self.column_context(x)
        log_depth = self.depth_head(x)
        if self.floor_prior is not None:
            log_depth = self.floor_prior(log_depth, rgb)
        log_scale = clamp_by_relu(self.scale_head(x), LOG_SCALE_MIN, LOG_SCALE_MAX)
        if log_scale.dtype != log_depth.dtype:  # under autocast the float32 prior promotes log_depth
            log_scale = log_scale.to(log_depth.dtype)
        return torch.cat([log_depth, log_scale], 1)


def fold_batchnorm(model):
    """An eval-mode copy of the model with every BatchNorm folded into its conv."""
    model = copy.deepcopy(model).cpu().float().eval()
    with torch.no_grad():
        for module in list(model.modules()):
            if isinstance(module, ConvBN):
                module.fold()
    return model


def count_parameters(model):
    return sum(parameter.numel() for parameter in model.parameters())


def count_macs(model):
    """Multiply-accumulates of the convolutions for one frame of the model's input
    size (the rest of the graph is a rounding error). One FLOP-count convention is 2
    x this."""
    total = [0]

    def hook(module, _inputs, output):
        kh, kw = module.kernel_size
        total[0] += output[0].numel() * (module.in_channels // module.groups) * kh * kw

    handles = [module.register_forward_hook(hook) for module in model.modules()
               if isinstance(module, nn.Conv2d)]
    was_training = model.training
    model.eval()
    try:
        with torch.no_grad():
            model(torch.zeros(1, 3, model.input_height, model.input_width, device=next(model.parameters()).device))
    finally:
        model.train(was_training)
        for handle in handles:
            handle.remove()
    return total[0]
