"""The training run's figures: learning curves and sample predictions."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)
import numpy as np  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402
from matplotlib.ticker import NullFormatter  # noqa: E402

DEPTH_TICKS_M = (0.1, 0.2, 0.5, 1, 2, 3, 5, 10, 20, 30, 50, 80)


def plot_curves(rows, path):
    """rows: dicts with step, train_loss, val_abs_rel, val_delta1 and, where a
    selection set picked the weights, select_abs_rel and select_delta1 (log.csv's
    rows; the select columns are "" without one)."""
    steps = [row["step"] for row in rows]
    figure, (loss_axes, val_axes) = plt.subplots(1, 2, figsize=(11, 4))
    loss_axes.plot(steps, [row["train_loss"] for row in rows], marker=".", label="train loss")
    loss_axes.set_xlabel("step")
    loss_axes.set_ylabel("loss (mean since the previous evaluation)")
    loss_axes.legend()
    val_axes.plot(steps, [row["val_abs_rel"] for row in rows], marker=".", label="val AbsRel")
    val_axes.plot(steps, [row["val_delta1"] for row in rows], marker=".", label="val delta<1.25")
    if rows and rows[0].get("select_abs_rel", "") != "":
        val_axes.plot(steps, [row["select_abs_rel"] for row in rows], marker=".", linestyle="--",
                      label="selection maps AbsRel")
        val_axes.plot(steps, [row["select_delta1"] for row in rows], marker=".", linestyle="--",
                      label="selection maps delta<1.25")
    val_axes.set_xlabel("step")
    val_axes.set_ylabel("value")
    val_axes.set_ylim(0, 1)
    val_axes.legend()
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)


def plot_samples(rgb, true_depth, pred_depth, log_scale, titles, path, depth_range_m=(0.1, 80.0)):
    """One row a frame: RGB | true depth | predicted depth | confidence exp(-s).
    The two depth panels of a row share one logarithmic colour scale; sky (NaN) is
    drawn white."""
    rows = len(rgb)
    figure, axes = plt.subplots(rows, 4, figsize=(14, 2.6 * rows), squeeze=False)
    colours = matplotlib.colormaps["turbo_r"].copy()
    colours.set_bad("white")
    for row in range(rows):
        known = true_depth[row][np.isfinite(true_depth[row])]
        both = np.concatenate([known, pred_depth[row].ravel()])
        low = max(depth_range_m[0], float(both.min()))
        high = min(depth_range_m[1], float(both.max()))
        norm = LogNorm(vmin=low, vmax=max(high, low * 1.01))
        axes[row, 0].imshow(rgb[row])
        axes[row, 0].set_title(titles[row], fontsize=8)
        axes[row, 1].imshow(np.ma.masked_invalid(true_depth[row]), cmap=colours, norm=norm)
        axes[row, 1].set_title("true depth (m)", fontsize=8)
        image = axes[row, 2].imshow(pred_depth[row], cmap=colours, norm=norm)
        axes[row, 2].set_title("predicted depth (m)", fontsize=8)
        ticks = [t for t in DEPTH_TICKS_M if norm.vmin <= t <= norm.vmax]
        bar = figure.colorbar(image, ax=axes[row, 1:3], fraction=0.03, ticks=ticks, format="%g")
        bar.ax.yaxis.set_minor_formatter(NullFormatter())
        confidence = axes[row, 3].imshow(np.exp(-log_scale[row]), cmap="viridis")
        axes[row, 3].set_title("confidence exp(-s) = 1/b", fontsize=8)
        figure.colorbar(confidence, ax=axes[row, 3], fraction=0.05)
        for axis in axes[row]:
            axis.set_xticks([])
            axis.set_yticks([])
    figure.savefig(path, dpi=90)
    plt.close(figure)
