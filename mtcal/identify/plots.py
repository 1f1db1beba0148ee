"""Plots of identified errors (thesis figs. 4.1-4.10 and 3.7): PNG via matplotlib's Agg backend.

Per axis: translational errors (um) and angular errors (urad) over the axis position, mean over rounds with
+-2 sigma bars (experimental standard deviation over rounds) and the fitted continuous function; per linear
axis: the raw straightness errors with their reference straight lines (the slope goes into squareness).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from mtcal.io import save_figure
from mtcal.model.errormodel import ErrorFunction
from mtcal.model.fits import Polynomial


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_axis(result, model, out_dir: str | Path) -> list[Path]:
    """PNG files for one AxisResult; returns the paths written."""
    plt = _plt()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    ar = result
    unit = model.kinematics.unit(ar.axis)
    x = ar.positions
    xs = np.linspace(x.min(), x.max(), 300)
    fig, axs = plt.subplots(1, 2, figsize=(11, 4.2))
    for panel, (names, scale, yl) in zip(axs, ((ar.names[:3], 1e3, "error (um)"), (ar.names[3:], 1e6, "error (urad)"))):
        for nm in names:
            i = ar.names.index(nm)
            v = ar.values(nm) * scale
            s = ar.std[:, i] * scale
            eb = panel.errorbar(x, v, yerr=2 * np.nan_to_num(s), fmt="o", ms=3.5, capsize=3, label=f"{nm} (mean, +-2s)")
            f: ErrorFunction | None = model.functions.get(nm)
            if f is not None and f.fit:
                lab = (f"degree {f.fit.degree}" if isinstance(f.fit, Polynomial) else f"{f.fit.harmonics} harmonics")
                panel.plot(xs, f(xs) * scale, "-", color=eb[0].get_color(), lw=1.2, label=f"{nm} fit ({lab})")
        panel.axhline(0, color="0.6", lw=0.6)
        panel.set_xlabel(f"{ar.axis} ({unit})")
        panel.set_ylabel(yl)
        panel.grid(alpha=0.3)
        panel.legend(fontsize=7)
    sl = " (straightness without the squareness slope)" if ar.lines else ""
    fig.suptitle(f"Axis {ar.axis}: identified error motions, {int(ar.n.max())} rounds{sl}")
    fig.tight_layout()
    paths = [out / f"identify_{ar.axis}.png"]
    save_figure(fig, paths[0], dpi=120)
    plt.close(fig)
    if ar.lines:
        fig, axs = plt.subplots(1, len(ar.lines), figsize=(5.5 * len(ar.lines), 4))
        for panel, (nm, line) in zip(np.atleast_1d(axs), sorted(ar.lines.items())):
            i = ar.names.index(nm)
            raw = ar.mean[:, i] * 1e3
            panel.errorbar(x, raw, yerr=2 * np.nan_to_num(ar.std[:, i]) * 1e3, fmt="o", ms=3.5, capsize=3,
                           label=f"{nm} measured (mean, +-2s)")
            panel.plot(x, (line["intercept"] + line["slope"] * x) * 1e3, "k--", lw=1,
                       label=f"{line['method']} reference line, slope {line['slope'] * 1e6:.2f} urad")
            panel.plot(x, ar.values(nm) * 1e3, "s-", ms=3, lw=0.8, label=f"{nm} without the slope")
            panel.set_xlabel(f"{ar.axis} (mm)")
            panel.set_ylabel("straightness (um)")
            panel.grid(alpha=0.3)
            panel.legend(fontsize=7)
        fig.suptitle(f"Axis {ar.axis}: straightness and reference straight lines (thesis fig. 3.7)")
        fig.tight_layout()
        p = out / f"identify_{ar.axis}_straightness.png"
        save_figure(fig, p, dpi=120)
        plt.close(fig)
        paths.append(p)
    return paths


def plot_all(result, out_dir: str | Path) -> list[Path]:
    """All plots of an IdentifyResult."""
    paths = []
    for ar in result.axes.values():
        paths += plot_axis(ar, result.model, out_dir)
    return paths
