"""Polar plot of circular tests as ballbar software draws it: the deviation (um) magnified on a reference circle,
counter-clockwise and clockwise paths in two colours, several traces (predicted before and after compensation,
measured) on one plot; PNG via matplotlib's Agg backend."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from mtcal.io import atomic_open

COLOURS = ("tab:blue", "tab:red", "tab:green", "tab:purple", "tab:orange")


def plot_circular(traces: list[tuple[str, np.ndarray, np.ndarray, np.ndarray]], title: str,
                  path: str | Path) -> Path:
    """Write the polar plot of ``traces`` [(label, theta_deg, deltaR_mm, direction), ...]; returns the path.  The
    radial scale is in um about a reference circle (the zero of the deviation), the same for every trace."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    span = max(float(np.abs(t[2]).max()) * 1e3 for t in traces) if traces else 1.0
    span = max(span, 0.5)
    base = 2.0 * span  # the zero deviation's circle
    fig = plt.figure(figsize=(6.2, 6.2))
    ax = fig.add_subplot(projection="polar")
    for k, (label, th, dr, d) in enumerate(traces):
        for sgn, style in ((1, "-"), (-1, "--")):
            on = d == sgn
            if not on.any():
                continue
            order = np.argsort(th[on])
            t, r = np.radians(th[on][order]), base + dr[on][order] * 1e3
            ax.plot(np.append(t, t[:1]), np.append(r, r[:1]), style, color=COLOURS[k % len(COLOURS)], lw=1.2,
                    label=f"{label} ({'ccw' if sgn > 0 else 'cw'})")
    ax.plot(np.linspace(0, 2 * np.pi, 361), np.full(361, base), color="0.5", lw=0.8)
    ticks = np.linspace(0, 3 * span, 4)
    ax.set_rticks(ticks)
    ax.set_yticklabels([f"{v - base:+.2g}" for v in ticks], fontsize=7)
    ax.set_rlim(0, 3 * span)
    ax.set_title(title + "\n(deviation in um about the grey circle)", fontsize=9)
    ax.legend(fontsize=7, loc="lower left", bbox_to_anchor=(-0.12, -0.14))
    fig.tight_layout()
    with atomic_open(path, "wb") as fh:
        fig.savefig(fh, format="png", dpi=110)
    plt.close(fig)
    return Path(path)
