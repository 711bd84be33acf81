"""Batched photometric augmentation on the training device.

Only changes that keep the metric geometry valid: a horizontal flip (the
principal point is at the image centre, so a mirrored frame is a frame the same
camera could take) and changes of colour, noise and sharpness. No crops or
scaling: metric depth from one image depends on the focal length in pixels."""
import torch
import torch.nn.functional as F

FLIP_PROBABILITY = 0.5
BLUR_PROBABILITY = 0.2
LOG_GAMMA_RANGE = 0.25
CONTRAST_RANGE = (0.7, 1.3)
BRIGHTNESS_RANGE = (0.7, 1.3)
CHANNEL_GAIN_RANGE = (0.9, 1.1)
MAX_NOISE_SIGMA = 0.03


def augment(rgb, depth):
    """rgb: float [N,3,H,W] in [0,1]; depth: [N,H,W]. Returns new (rgb, depth).
    Draws from torch's global generator, so it follows torch.manual_seed."""
    count, device = rgb.shape[0], rgb.device

    def uniform(low, high, *shape):
        return torch.empty((count,) + shape, device=device).uniform_(low, high)

    flip = torch.rand(count, device=device) < FLIP_PROBABILITY
    rgb = torch.where(flip[:, None, None, None], rgb.flip(-1), rgb)
    depth = torch.where(flip[:, None, None], depth.flip(-1), depth)

    rgb = rgb.clamp(0, 1) ** torch.exp(uniform(-LOG_GAMMA_RANGE, LOG_GAMMA_RANGE, 1, 1, 1))
    mean = rgb.mean(dim=(1, 2, 3), keepdim=True)
    rgb = (rgb - mean) * uniform(*CONTRAST_RANGE, 1, 1, 1) + mean
    rgb = rgb * uniform(*BRIGHTNESS_RANGE, 1, 1, 1) * uniform(*CHANNEL_GAIN_RANGE, 3, 1, 1)

    # A 3x3 binomial blur, as from a slightly soft render or a video model's output.
    kernel = torch.tensor([1.0, 2.0, 1.0], device=device)
    kernel = (kernel[:, None] * kernel[None, :] / 16).expand(3, 1, 3, 3).to(rgb.dtype)
    blurred = F.conv2d(F.pad(rgb, (1, 1, 1, 1), mode="replicate"), kernel, groups=3)
    rgb = torch.where(torch.rand(count, 1, 1, 1, device=device) < BLUR_PROBABILITY, blurred, rgb)

    rgb = rgb + torch.randn_like(rgb) * uniform(0, MAX_NOISE_SIGMA, 1, 1, 1)
    return rgb.clamp(0, 1), depth
