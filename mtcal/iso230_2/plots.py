"""Plot of an ISO 230-2 evaluation in the layout of the standard's figures: the
mean unidirectional positional deviations up and down over the target positions with their +-2 s bands and the
individual runs; PNG via matplotlib's Agg backend."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from mtcal.io import atomic_open
from mtcal.iso230_2.evaluation import AxisEvaluation


def plot_evaluation(ev: AxisEvaluation, path: str | Path) -> Path:
    """Write the PNG of one axis' evaluation; returns its path."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 4.8))
    x, t = ev.positions, ev.targets
    for sgn, tag, colour, label in ((1, "up", "tab:blue", "up (+)"), (-1, "down", "tab:red", "down (-)")):
        sel = ev.runs.direction == sgn
        if not sel.any():
            continue
        ax.plot(ev.runs.position[sel], ev.runs.deviation[sel], ".", color=colour, alpha=0.35, ms=4)
        mean, s = t[f"mean_{tag}"], np.nan_to_num(t[f"s_{tag}"])
        ax.plot(x, mean, "-o", color=colour, ms=4, label=f"mean {label}")
        ax.fill_between(x, mean - 2 * s, mean + 2 * s, color=colour, alpha=0.15, label=f"mean {label} +- 2s")
    p = ev.parameters
    ax.set_title(f"ISO 230-2 axis {ev.axis}: A = {p['A']:.2f}, E = {p['E']:.2f}, M = {p['M']:.2f}, "
                 f"R = {p['R']:.2f}, B = {p['B']:.2f} {ev.unit}", fontsize=10)
    ax.set_xlabel(f"target position ({ev.position_unit})")
    ax.set_ylabel(f"positional deviation ({ev.unit})")
    ax.axhline(0, color="0.6", lw=0.8)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    with atomic_open(path, "wb") as fh:
        fig.savefig(fh, format="png", dpi=120)
    plt.close(fig)
    return Path(path)
