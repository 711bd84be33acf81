#!/usr/bin/python3
"""Draws an evaluation report's plots with matplotlib from the data valerant_eval wrote
(eval_plots.h: plots.json) into the same folder: each figure as PNG and SVG.

    plot_eval.py FOLDER/plots.json

plots.json: {"configs": [names, in the report's order],
             "curves": [{"name", "title", "xlabel", "ylabel",
                         "series": {config: [value at step 1, 2, ...]},
                         "x": {config: [x of each value]} (optional: steps 1, 2, ...)}],
             "bars":   [{"name", "title", "ylabel", "values": {config: value or null}}]}
A null value is a figure no run recorded: its bar is absent and labelled n/a.
Exit status 1 with a message naming this script when matplotlib is missing."""
import json
import os
import sys

try:
    import matplotlib

    matplotlib.use("Agg")  # files only, no display
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator, MultipleLocator, NullLocator
except ImportError as error:
    sys.exit("%s: matplotlib is missing (%s): apt-get install python3-matplotlib" % (sys.argv[0], error))

# Reproducible files: the same data gives the same bytes (no dates, fixed SVG ids).
matplotlib.rcParams["svg.hashsalt"] = "valerant"
METADATA = {"png": {"Software": None}, "svg": {"Date": None, "Creator": None}}


def colours(configs):
    """One colour per configuration, the same in every figure."""
    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    return {c: cycle[i % len(cycle)] for i, c in enumerate(configs)}


def legend(axes):
    """Right of the plot, where it never hides a line or bar."""
    axes.legend(title="configuration", fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1))


def save(figure, folder, name):
    figure.tight_layout()
    for extension in ("png", "svg"):
        # Under a temporary name, then renamed: a reader never sees a cut file.
        path = os.path.join(folder, "%s.%s" % (name, extension))
        figure.savefig(path + ".tmp", format=extension, dpi=110, metadata=METADATA[extension])
        os.replace(path + ".tmp", path)
    plt.close(figure)


def plot_curves(spec, colour, folder):
    figure, axes = plt.subplots(figsize=(8.4, 4.2))
    x = spec.get("x")
    for config, values in spec["series"].items():
        # A configuration without the curve (runs written before it existed) draws nothing.
        if not values:
            continue
        xs = x[config] if x is not None else list(range(1, len(values) + 1))
        # Long runs: markers only while they stay apart.
        marker = "o" if len(values) <= 40 else None
        axes.plot(xs, values, marker=marker, markersize=3, linewidth=1.8, color=colour[config], label=config)
    axes.set_title(spec["title"])
    axes.set_xlabel(spec["xlabel"])
    axes.set_ylabel(spec["ylabel"])
    if x is None:
        # Steps are whole numbers: a tick per step up to 20 steps, fewer whole ones beyond.
        steps = max([len(values) for values in spec["series"].values()] + [1])
        axes.xaxis.set_major_locator(MultipleLocator(1) if steps <= 20 else MaxNLocator(integer=True))
        axes.xaxis.set_minor_locator(MultipleLocator(1) if steps <= 100 else NullLocator())
        axes.set_xlim(left=0.5)
    else:
        axes.set_xlim(left=0)
    axes.set_ylim(bottom=0)
    axes.grid(True, alpha=0.3)
    if axes.get_legend_handles_labels()[0]:
        legend(axes)
    save(figure, folder, spec["name"])


def plot_bars(spec, configs, colour, folder):
    figure, axes = plt.subplots(figsize=(max(6.0, 1.1 * len(configs) + 3.4), 4.0))
    recorded = [v for v in spec["values"].values() if v is not None]
    for i, config in enumerate(configs):
        value = spec["values"].get(config)
        if value is None:
            axes.annotate("n/a", (i, 0), ha="center", va="bottom")
            continue
        axes.bar(i, value, width=0.7, color=colour[config], label=config)
        axes.annotate("%.2f" % value if value < 10 else "%.0f" % value, (i, value), ha="center", va="bottom",
                      xytext=(0, 2), textcoords="offset points", fontsize="small")
    axes.set_xticks(range(len(configs)))
    axes.set_xticklabels(configs, rotation=30 if len(configs) > 4 else 0, ha="right" if len(configs) > 4 else "center")
    axes.set_title(spec["title"])
    axes.set_xlabel("configuration")
    axes.set_ylabel(spec["ylabel"])
    # Head room for the value labels; a plot of zeros still gets a visible axis.
    axes.set_ylim(0, max(recorded + [0]) * 1.15 or 1)
    axes.grid(True, axis="y", alpha=0.3)
    if recorded:
        legend(axes)
    save(figure, folder, spec["name"])


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: %s FOLDER/plots.json" % sys.argv[0])
    path = sys.argv[1]
    try:
        with open(path) as f:
            data = json.load(f)
        configs = data["configs"]
        curves, bars = data["curves"], data["bars"]
    except (OSError, ValueError, KeyError, TypeError) as error:
        sys.exit("%s: %s: not a plot data file (%s)" % (sys.argv[0], path, error))
    folder = os.path.dirname(os.path.abspath(path))
    colour = colours(configs)
    for spec in curves:
        plot_curves(spec, colour, folder)
    for spec in bars:
        plot_bars(spec, configs, colour, folder)


if __name__ == "__main__":
    main()
