"""The world model's adversarial term (train_world_model.py --adversarial-weight): a
small PatchGAN discriminator trained against the predicted frames with the hinge loss.

Under L1 and SSIM the fill of what no context frame held comes out as a smooth mean
colour, on which visual SLAM finds no features; a discriminator that tells real from
predicted patches rewards the fill for carrying texture instead.

The discriminator sees RGB frames in [0,1], float [N,3,H,W], and gives a logit for each
patch, [N,1,H/8,W/8] (each logit sees a 38 x 38 pixel patch). Its convolutions are
spectral-normalised, which keeps its gradients to the generator bounded. It is only used
in training: the exported world model is the generator alone."""
import torch
from torch import nn
import torch.nn.functional as F
from torch.nn.utils.parametrizations import spectral_norm

CHANNELS = (32, 64, 128)
# Adam's betas of GAN training: a short momentum follows the moving target.
BETAS = (0.5, 0.999)


class PatchDiscriminator(nn.Module):
    def __init__(self):
        super().__init__()
        layers, inputs = [], 3
        for channels in CHANNELS:
            layers += [spectral_norm(nn.Conv2d(inputs, channels, 4, stride=2, padding=1)), nn.LeakyReLU(0.2)]
            inputs = channels
        layers.append(spectral_norm(nn.Conv2d(inputs, 1, 3, padding=1)))
        self.layers = nn.Sequential(*layers)

    def forward(self, frames):
        return self.layers(frames)


def discriminator_loss(real_logits, fake_logits):
    """Hinge loss: real patches pushed to logits of at least 1, fake ones to at most -1."""
    return F.relu(1 - real_logits).mean() + F.relu(1 + fake_logits).mean()


def generator_loss(fake_logits):
    """The generator's hinge term: the mean logit of its frames, negated."""
    return -fake_logits.mean()


class Adversary:
    """The discriminator and its Adam optimiser (constant rate), one step per generator
    step. Call it outside autocast: it runs in fp32."""

    def __init__(self, lr, device):
        self.net = PatchDiscriminator().to(device)
        self.optimizer = torch.optim.Adam(self.net.parameters(), lr=lr, betas=BETAS)

    def generator_term(self, fake):
        """generator_loss of fake frames, differentiable with respect to them."""
        return generator_loss(self.net(fake))

    def step(self, real, fake):
        """One discriminator step on real and fake frames (detached here): returns its
        loss, or None when that is not finite and the step was skipped."""
        loss = discriminator_loss(self.net(real), self.net(fake.detach()))
        if not torch.isfinite(loss):
            return None
        # Also drops the gradients the generator's backward left in the discriminator.
        self.optimizer.zero_grad(set_to_none=True)
        loss.backward()
        self.optimizer.step()
        return loss.detach()
