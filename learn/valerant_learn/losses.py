"""Training loss: Laplace negative log-likelihood of ln depth."""
import torch

# Sky has no depth; it is trained as this far away, beyond the arenas' extent, so
# the net learns "far" there rather than nothing.
SKY_DEPTH_M = 80.0


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
