"""An exponential moving average of a model's weights (--ema).

The kept weights are picked by a noisy validation figure; at the one-cycle
schedule's high rates a single step's weights wander, so run v6's first try kept a
snapshot from mid-run (step 7,500 of 19,463) that was worse on the other figures
than the weights around it. The average over about 1 / (1 - decay) steps is the
smoother net to validate and keep."""
import copy

import torch


class WeightAverage:
    """average = decay' * average + (1 - decay') * current after every step, over
    every floating-point entry of the state dict (weights and BatchNorm's running
    statistics); integer entries (BatchNorm's batch count) are copied. decay' =
    min(decay, (1 + step) / (10 + step)): the early steps, far from the start,
    count more while there is little to average."""

    def __init__(self, model, decay):
        if not 0 < decay < 1:
            raise ValueError("--ema must be between 0 and 1, got %r" % decay)
        self.decay = decay
        self.model = copy.deepcopy(model).eval()
        for parameter in self.model.parameters():
            parameter.requires_grad_(False)
        self.steps = 0

    def update(self, model):
        decay = min(self.decay, (1 + self.steps) / (10 + self.steps))
        self.steps += 1
        averaged, current = self.model.state_dict(), model.state_dict()
        floats = [name for name, value in averaged.items() if value.is_floating_point()]
        with torch.no_grad():
            if floats:
                targets = [averaged[name] for name in floats]
                torch._foreach_mul_(targets, decay)
                torch._foreach_add_(targets, [current[name].detach() for name in floats], alpha=1 - decay)
            for name, value in averaged.items():
                if not value.is_floating_point():
                    value.copy_(current[name])
