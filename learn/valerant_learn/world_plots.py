"""The world model run's figures: learning curves and generated-against-true rollouts."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)
import numpy as np  # noqa: E402

from .world_metrics import HORIZONS  # noqa: E402


def plot_world_curves(rows, path):
    """rows: log.csv's rows (step, train_loss, val_l1, val_psnr_<h>)."""
    steps = [row["step"] for row in rows]
    figure, (loss_axes, psnr_axes) = plt.subplots(1, 2, figsize=(11, 4))
    loss_axes.plot(steps, [row["train_loss"] for row in rows], marker=".", label="train loss (L1 + 0.2 (1 - SSIM))")
    loss_axes.plot(steps, [row["val_l1"] for row in rows], marker=".", label="val L1 (same windows each time)")
    loss_axes.set_xlabel("step")
    loss_axes.set_yscale("log")
    loss_axes.legend()
    for h in HORIZONS:
        values = [row["val_psnr_%d" % h] for row in rows]
        if np.isfinite(values).any():
            psnr_axes.plot(steps, values, marker=".", label="frame %d" % h)
    psnr_axes.set_xlabel("step")
    psnr_axes.set_ylabel("val PSNR of whole rollouts (dB)")
    psnr_axes.legend()
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)


def plot_rollouts(samples, path):
    """samples: (title, generated [T,3,H,W], true [T,3,H,W]) in [0,1]; per sample two
    rows (true above generated), one column per horizon the rollout reaches."""
    figure, axes = plt.subplots(2 * len(samples), len(HORIZONS), figsize=(2.2 * len(HORIZONS), 1.8 * 2 * len(samples)),
                                squeeze=False)
    for s, (title, generated, true) in enumerate(samples):
        for column, h in enumerate(HORIZONS):
            for row, (name, images) in enumerate((("true", true), ("model", generated))):
                axis = axes[2 * s + row, column]
                axis.set_xticks([])
                axis.set_yticks([])
                if len(images) >= h:
                    axis.imshow(images[h - 1].permute(1, 2, 0).clamp(0, 1).numpy())
                if column == 0:
                    axis.set_ylabel("%s\n%s" % (title, name), fontsize=7)
                if s == 0 and row == 0:
                    axis.set_title("frame %d" % h, fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)
