"""Training losses of ln depth, sky trained as 80 m.

laplace_nll: the Laplace negative log-likelihood of runs v1-v5. The learnt scale b
divides each pixel's depth gradient, so the net can give up on hard pixels (a large
b) and learn them slowest.

decoupled_loss: the depth and its confidence trained apart (run v6). The depth
learns from |ln error| plus the pixel's AbsRel, which punishes a surface placed too
far without bound as the benchmark does; the scale head learns the same Laplace NLL
on the detached error, so ln b keeps its meaning (the scale of the ln-depth error)
without weighting the depth's gradient.

gradient_matching_loss: an extra term for the depth (train_depth.py --gradient-weight):
the ln-depth error's differences between neighbouring pixels, at several scales, as in
MiDaS's gradient-matching term. A blurred wall edge costs little in the per-pixel
terms (few pixels) but a whole edge here, so it asks for sharp edges and for a wall to
stand out of the floor it meets."""
import torch

# Sky has no depth; it is trained as this far away, beyond the arenas' extent, so
# the net learns "far" there rather than nothing.
SKY_DEPTH_M = 80.0
# The AbsRel term's ln error is capped here (exp(3) - 1 = 19 times too far): beyond
# it the L1 term alone pulls, so a wild first step cannot overflow the loss.
ABS_REL_MAX_LOG_ERROR = 3.0
LOSSES = ("laplace", "decoupled")


def log_depth_target(depth, sky_depth_m=SKY_DEPTH_M):
    """ln of the depth in metres, sky (NaN) replaced by sky_depth_m."""
    return torch.log(torch.where(torch.isnan(depth), torch.full_like(depth, sky_depth_m), depth))


def laplace_nll(output, depth, sky_depth_m=SKY_DEPTH_M):
    """Mean over pixels of |mu - ln d| * exp(-s) + s (the Laplace NLL without its
    constant ln 2). output: [N,2,H,W] (mu = ln depth, s = ln b); depth: [N,H,W]
    metres with NaN for sky. Computed in float32 whatever the output's dtype."""
    output = output.float()
    mu, log_scale = output[:, 0], output[:, 1]
    error = (mu - log_depth_target(depth.float(), sky_depth_m)).abs()
    return (error * torch.exp(-log_scale) + log_scale).mean()


def decoupled_loss(output, depth, sky_depth_m=SKY_DEPTH_M):
    """Mean over pixels of |e| + |exp(e) - 1| (the latter, the pixel's AbsRel, on
    pixels with a depth only: the benchmark leaves sky out) plus the Laplace NLL
    |e| * exp(-s) + s with e detached, e = mu - ln d. Same arguments as laplace_nll."""
    output = output.float()
    mu, log_scale = output[:, 0], output[:, 1]
    depth = depth.float()
    error = mu - log_depth_target(depth, sky_depth_m)
    has_depth = ~torch.isnan(depth)
    abs_rel = (torch.exp(error.clamp(max=ABS_REL_MAX_LOG_ERROR)) - 1).abs()
    depth_term = error.abs() + torch.where(has_depth, abs_rel, torch.zeros_like(abs_rel))
    scale_term = error.detach().abs() * torch.exp(-log_scale) + log_scale
    return (depth_term + scale_term).mean()


# Scales of gradient_matching_loss: every pixel, then every 2nd, 4th and 8th.
GRADIENT_SCALES = 4


def gradient_matching_loss(output, depth, scales=GRADIENT_SCALES, sky_depth_m=SKY_DEPTH_M):
    """Mean over scales k = 0..scales-1 of the mean |difference| of the ln-depth error
    e = mu - ln d between horizontal neighbours plus that between vertical neighbours,
    on the image subsampled to every 2^k-th row and column (sky as sky_depth_m, as in
    the other losses). 0 where the prediction is the truth up to a constant ln factor
    (a global scale error): this term judges the shape alone. Same arguments as
    laplace_nll; computed in float32."""
    error = output.float()[:, 0] - log_depth_target(depth.float(), sky_depth_m)
    total = error.new_zeros(())
    for scale in range(scales):
        step = 2 ** scale
        sampled = error[:, ::step, ::step]
        across = (sampled[:, :, 1:] - sampled[:, :, :-1]).abs().mean() if sampled.shape[2] > 1 else 0.0
        down = (sampled[:, 1:, :] - sampled[:, :-1, :]).abs().mean() if sampled.shape[1] > 1 else 0.0
        total = total + across + down
    return total / scales


def training_loss(name):
    """The loss function called name (one of LOSSES)."""
    if name not in LOSSES:
        raise ValueError("unknown loss %r (expected one of %s)" % (name, ", ".join(LOSSES)))
    return laplace_nll if name == "laplace" else decoupled_loss
