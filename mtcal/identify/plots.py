"""Plots of identified errors (thesis figs. 4.1-4.10 and 3.7): PNG via matplotlib's Agg backend.

Per axis: translational errors (um) and angular errors (urad) over the axis position, mean over rounds with its
95 % interval drawn as a band (the estimates at neighbouring positions are correlated: the three-point values
share each round's reference reading, the joint fit's share the reflectors and alignments; a band does not invite
reading the positions as independent) - Student's t for the rounds' Type A (AxisResult.k95), and the fitted
continuous function; per linear axis: the raw straightness errors with their reference straight lines (the slope
goes into squareness).
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
    band = _band_label(ar)
    for panel, (names, scale, yl) in zip(axs, ((ar.names[:3], 1e3, "error (um)"), (ar.names[3:], 1e6, "error (urad)"))):
        for nm in names:
            i = ar.names.index(nm)
            v = ar.values(nm) * scale
            u = np.nan_to_num(ar.u95[:, i]) * scale
            dots = panel.plot(x, v, "o", ms=3.5, label=f"{nm} (mean)")[0]
            panel.fill_between(x, v - u, v + u, color=dots.get_color(), alpha=0.18, lw=0)
            f: ErrorFunction | None = model.functions.get(nm)
            if f is not None and f.fit:
                lab = (f"degree {f.fit.degree}" if isinstance(f.fit, Polynomial) else f"{f.fit.harmonics} harmonics")
                panel.plot(xs, f(xs) * scale, "-", color=dots.get_color(), lw=1.2, label=f"{nm} fit ({lab})")
        panel.axhline(0, color="0.6", lw=0.6)
        panel.set_xlabel(f"{ar.axis} ({unit})")
        panel.set_ylabel(yl)
        panel.grid(alpha=0.3)
        panel.legend(fontsize=7)
    sl = " (straightness without the squareness slope)" if ar.lines else ""
    fig.suptitle(f"Axis {ar.axis}: identified error motions, {int(ar.n.max())} rounds{sl}\nbands: {band}", fontsize=10)
    fig.tight_layout()
    paths = [out / f"identify_{ar.axis}.png"]
    save_figure(fig, paths[0], dpi=120)
    plt.close(fig)
    if ar.lines:
        fig, axs = plt.subplots(1, len(ar.lines), figsize=(5.5 * len(ar.lines), 4))
        for panel, (nm, line) in zip(np.atleast_1d(axs), sorted(ar.lines.items())):
            i = ar.names.index(nm)
            raw, u = ar.mean[:, i] * 1e3, np.nan_to_num(ar.u95[:, i]) * 1e3
            panel.plot(x, raw, "o", ms=3.5, color="C0", label=f"{nm} measured (mean; band: {band})")
            panel.fill_between(x, raw - u, raw + u, color="C0", alpha=0.18, lw=0)
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


def _band_label(ar) -> str:
    """What the bands are: the 95 % interval of the mean and its coverage factor."""
    if ar.covariance is not None:
        return "95 % interval of the estimate (joint fit's covariance, k = 1.96)"
    k = ar.k95[np.isfinite(ar.k95)]
    ks = f"k = {k.min():.2f}" if len(k) and np.ptp(k) < 1e-9 else (f"k = {k.min():.2f}-{k.max():.2f}" if len(k)
                                                                      else "one round: none")
    return f"95 % interval of the mean (Student t, {int(np.nanmax(ar.dof)) if len(k) else 0} dof, {ks})"


def plot_all(result, out_dir: str | Path) -> list[Path]:
    """All plots of an IdentifyResult."""
    paths = []
    for ar in result.axes.values():
        paths += plot_axis(ar, result.model, out_dir)
    return paths
