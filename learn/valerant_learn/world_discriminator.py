"""The world model's adversarial term (train_world_model.py --adversarial-weight): a
small PatchGAN discriminator trained against the predicted frames with the hinge loss,
looking at what the model invented.

Under L1 and SSIM the fill of what no context frame held comes out as a smooth mean
colour, on which visual SLAM finds no features; a discriminator that tells real from
predicted patches there rewards the fill for carrying texture instead. Most of a
predicted frame is the context moved by the warp, which looks real whatever the fill
does, so a discriminator of whole frames barely sees the fill (an unconditioned one, in
a 10-minute trial, stayed near a coin flip and changed nothing visible:
docs/world_model.md). This one is told where the invented pixels are, and only its
patches over them count:

- input: RGB in [0,1] and the frame's invented map (world_net.rollout's, 1 where a pixel
  shows what no context frame held), float [N,4,H,W]; a true frame is shown with the
  invented map of the predicted frame it pairs, so the map says nothing of which is which;
- output: a logit for each patch, [N,1,H/8,W/8] (each logit sees a 38 x 38 pixel patch);
- each logit's weight in the losses is the share of invented pixels in the 8 x 8 cell
  under it (patch_weights).

Its convolutions are spectral-normalised, which keeps its gradients to the generator
bounded. It is only used in training: the exported world model is the generator alone."""
import torch
from torch import nn
import torch.nn.functional as F
from torch.nn.utils.parametrizations import spectral_norm

CHANNELS = (32, 64, 128)
INPUT_CHANNELS = 4  # RGB and the invented map
STRIDE = 8          # input pixels per logit along each side
# Adam's betas of GAN training: a short momentum follows the moving target.
BETAS = (0.5, 0.999)


class PatchDiscriminator(nn.Module):
    def __init__(self):
        super().__init__()
        layers, inputs = [], INPUT_CHANNELS
        for channels in CHANNELS:
            layers += [spectral_norm(nn.Conv2d(inputs, channels, 4, stride=2, padding=1)), nn.LeakyReLU(0.2)]
            inputs = channels
        layers.append(spectral_norm(nn.Conv2d(inputs, 1, 3, padding=1)))
        self.layers = nn.Sequential(*layers)

    def forward(self, frames, invented):
        return self.layers(torch.cat([frames, invented], 1))


def patch_weights(invented):
    """The share of invented pixels in each logit's STRIDE x STRIDE cell: [N,1,H/8,W/8]."""
    return F.avg_pool2d(invented, STRIDE)


def weighted_mean(values, weights):
    """sum(weights * values) / sum(weights); the caller keeps sum(weights) above 0."""
    return (weights * values).sum() / weights.sum()


def discriminator_loss(real_logits, fake_logits, weights):
    """Hinge loss, each patch weighted: real patches pushed to logits of at least 1, fake
    ones to at most -1."""
    return weighted_mean(F.relu(1 - real_logits), weights) + weighted_mean(F.relu(1 + fake_logits), weights)


def generator_loss(fake_logits, weights):
    """The generator's hinge term: the weighted mean logit of its frames, negated."""
    return -weighted_mean(fake_logits, weights)


class Adversary:
    """The discriminator and its Adam optimiser (constant rate), `steps` updates on each
    batch the generator's step shows it (more than one lets it keep ahead of a generator
    that learns faster). Call it outside autocast: it runs in fp32. Frames come with
    their invented maps; a batch whose maps are all 0 has nothing to judge (the caller
    skips it)."""

    def __init__(self, lr, device, steps=1):
        self.net = PatchDiscriminator().to(device)
        self.optimizer = torch.optim.Adam(self.net.parameters(), lr=lr, betas=BETAS)
        self.steps = steps

    def generator_term(self, fake, invented):
        """generator_loss of fake frames, differentiable with respect to them."""
        return generator_loss(self.net(fake, invented), patch_weights(invented))

    def step(self, real, fake, invented):
        """`steps` discriminator updates on real and fake frames (detached here) shown
        with the fake ones' invented maps: returns the loss before the first, or None
        when a loss was not finite (that update and the rest are skipped)."""
        weights, fake = patch_weights(invented), fake.detach()
        first = None
        for _ in range(self.steps):
            loss = discriminator_loss(self.net(real, invented), self.net(fake, invented), weights)
            if not torch.isfinite(loss):
                return None
            first = loss.detach() if first is None else first
            # Also drops the gradients the generator's backward left in the discriminator.
            self.optimizer.zero_grad(set_to_none=True)
            loss.backward()
            self.optimizer.step()
        return first
