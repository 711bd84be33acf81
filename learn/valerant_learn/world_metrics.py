"""Image similarity of generated frames against the engine's: PSNR and SSIM, and
the horizon table the world model's card and valerant_bench wm report.

PSNR = 10 log10(1 / MSE) over the three channels of images in [0,1] (peak 1, the
same as 255 on 8-bit images). SSIM is Wang et al. (2004): an 11 x 11 Gaussian
window of sigma 1.5, C1 = 0.01^2, C2 = 0.03^2, over the window positions that lie
inside the image, per channel, then averaged over channels and positions."""
import math

import torch
import torch.nn.functional as F

HORIZONS = (8, 16, 32, 57, 97)
SSIM_WINDOW = 11
SSIM_SIGMA = 1.5
SSIM_C1 = 0.01 ** 2
SSIM_C2 = 0.03 ** 2
# PSNR of identical images is infinite; report this cap instead.
PSNR_CAP_DB = 100.0


def psnr(predicted, true):
    """float [N] in dB of images float [N,3,H,W] in [0,1]."""
    mse = (predicted.float() - true.float()).pow(2).flatten(1).mean(1)
    return (10 * torch.log10(1.0 / mse.clamp_min(10 ** (-PSNR_CAP_DB / 10))))


def _gaussian_window(channels, device):
    x = torch.arange(SSIM_WINDOW, dtype=torch.float32, device=device) - (SSIM_WINDOW - 1) / 2
    g = torch.exp(-x ** 2 / (2 * SSIM_SIGMA ** 2))
    g = g / g.sum()
    return (g[:, None] * g[None, :]).expand(channels, 1, SSIM_WINDOW, SSIM_WINDOW).contiguous()


def ssim(predicted, true):
    """float [N] of images float [N,C,H,W] in [0,1] (differentiable: the training loss uses it)."""
    return ssim_map(predicted, true).flatten(1).mean(1)


def ssim_map(predicted, true):
    """The SSIM index of every window of images float [N,C,H,W] in [0,1]: float
    [N,C,H-SSIM_WINDOW+1,W-SSIM_WINDOW+1], position (y, x) the window whose top left pixel
    is (y, x) (its centre pixel (y + r, x + r), r = SSIM_WINDOW // 2)."""
    predicted, true = predicted.float(), true.float()
    channels = predicted.shape[1]
    window = _gaussian_window(channels, predicted.device)

    def blur(image):
        return F.conv2d(image, window, groups=channels)

    mu_p, mu_t = blur(predicted), blur(true)
    var_p = blur(predicted * predicted) - mu_p ** 2
    var_t = blur(true * true) - mu_t ** 2
    cov = blur(predicted * true) - mu_p * mu_t
    return ((2 * mu_p * mu_t + SSIM_C1) * (2 * cov + SSIM_C2)) / (
        (mu_p ** 2 + mu_t ** 2 + SSIM_C1) * (var_p + var_t + SSIM_C2))


def flat_like(true):
    """Every pixel of each image its own mean colour: the `flat` baseline."""
    return true.mean((-2, -1), keepdim=True).expand_as(true)


def horizon_table(entries):
    """entries: (generated [T,3,H,W], truth [T,3,H,W], context frame [3,H,W]) per
    rollout, frame i of generated/truth being the one after i+1 actions. Returns
    {str(h): {"rollouts": n, "model"|"repeat"|"flat": {"psnr", "ssim"}}}, the means over
    the rollouts at least h frames long (None where none is)."""
    table = {}
    for h in HORIZONS:
        chosen = [(g[h - 1], t[h - 1], c) for g, t, c in entries if len(t) >= h]
        row = {"rollouts": len(chosen)}
        if chosen:
            generated = torch.stack([g for g, _, _ in chosen])
            truth = torch.stack([t for _, t, _ in chosen])
            context = torch.stack([c for _, _, c in chosen])
            for name, image in (("model", generated), ("repeat", context), ("flat", flat_like(truth))):
                row[name] = {"psnr": float(psnr(image, truth).mean()), "ssim": float(ssim(image, truth).mean())}
        else:
            for name in ("model", "repeat", "flat"):
                row[name] = {"psnr": math.nan, "ssim": math.nan}
        table[str(h)] = row
    return table
