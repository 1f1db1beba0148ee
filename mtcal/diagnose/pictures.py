"""A picture per finding of the diagnosis, drawn so that a person sees the effect in the readings.

For each significant finding: the partial residual (the residual after every selected effect, plus what this one
adds beyond the base) and the effect's fit, both projected on the direction the effect moves the readings most
(the first principal direction of its fitted displacements, machine frame), against what shows it:
* a reversal (backlash, angular, straightness, free-form): the axis position, + and - approach apart, with the mean
  per position and direction;
* a periodic, scale, second-order or constant error: the axis position;
* a drift, knock, creep, settling or temperature effect: the time (h);
* an outlier or a re-seated nest: the reading's place in time order, the readings concerned marked.
Units: um, machine frame (the fit is made on the whitened readings; the picture shows them unwhitened).
"""
from __future__ import annotations

import os
import re

import numpy as np

from mtcal.diagnose.report import Diagnosis, Finding
from mtcal.io import save_figure

REVERSAL = ("backlash", "reversal_angular", "reversal_straightness", "backlash_travel")
TIME = ("thermal_drift", "thermal_temperature", "nest_creep", "nest_knock", "tracker_settling", "tracker_scale")


def _series(diag: Diagnosis, f: Finding) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(partial residual, the effect's fit, the readings it moves) per reading, um, along the effect's main direction:
    the first
    principal direction of the displacements it fits in the machine frame (unwhitened, so that one direction means
    the same for every reading)."""
    n = len(diag.prep.rec)
    W = diag.prep.W
    fit = np.linalg.solve(W, f.fitted.reshape(n, 3, 1))[..., 0]
    part = np.linalg.solve(W, diag.residuals_after.reshape(n, 3, 1))[..., 0] + fit
    d = np.linalg.svd(fit, full_matrices=False)[2][0]
    if np.sum(fit @ d) < 0:
        d = -d
    return part @ d * 1e3, fit @ d * 1e3, f.touched


def _kind(f: Finding) -> str:
    if f.name in REVERSAL:
        return "reversal"
    if f.name in TIME or f.get("variant") == "tracker knock":
        return "time"
    if f.name in ("outlier", "offset"):
        return "reading"
    return "position" if f.axis else "time"


def _draw(ax, diag: Diagnosis, f: Finding, kind: str) -> str:
    """One panel; returns the x label."""
    rec = diag.prep.rec
    y, m, on = _series(diag, f)
    sel = on & (rec.axis == f.axis) if f.axis and kind in ("reversal", "position") else on
    if kind == "reversal":
        for d, col, lab in ((1, "C0", "+ approach"), (-1, "C3", "- approach")):
            k = sel & (rec.direction == d)
            x = rec.position[k]
            ax.plot(x, y[k], ".", ms=3, color=col, alpha=0.4)
            xs = np.unique(x)
            ax.plot(xs, [y[k][x == v].mean() for v in xs], "o-", ms=4, color=col, label=f"{lab}: mean")
            ax.plot(xs, [m[k][x == v].mean() for v in xs], "--", color=col, lw=1, label=f"{lab}: fit")
        return f"{f.axis} position ({diag.prep.machine.unit(f.axis)})"
    if kind == "position":
        x = rec.position[sel]
        o = np.argsort(x)
        ax.plot(x, y[sel], ".", ms=3, alpha=0.5, label="partial residual")
        ax.plot(x[o], m[sel][o], "-", color="k", lw=1.2, label="fit")
        return f"{f.axis} position ({diag.prep.machine.unit(f.axis)})"
    if kind == "time":
        t = rec.time_s / 3600.0
        o = np.argsort(t)
        ax.plot(t[~on], y[~on], ".", ms=2, color="0.75", label="readings it does not move")
        ax.plot(t[on], y[on], ".", ms=3, alpha=0.6, label="partial residual")
        ax.plot(t[o][on[o]], m[o][on[o]], "-", color="k", lw=1.2, label="fit")
        return "time (h)"
    r = np.argsort(diag.prep.order)
    idx = np.arange(len(r))
    ax.plot(idx, y[r], ".", ms=2, color="0.6", label="readings")
    ax.plot(idx[on[r]], y[r][on[r]], "o", ms=4, color="C3", label="the readings concerned")
    return "reading (time order)"


def _size(v: float, unit: str) -> str:
    """A finding's size in the unit people read it in (um, urad, um/h)."""
    scale = {"mm": (1e3, "um"), "rad": (1e6, "urad"), "mm/s": (3.6e6, "um/h"), "mm/K": (1e3, "um/K")}
    f, u = scale.get(unit, (1.0, unit))
    return f"{v * f:.3g} {u}"


def plot_findings(diag: Diagnosis, directory) -> list[str]:
    """PNG per significant finding (module docstring) in ``directory``; returns the paths written."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(directory, exist_ok=True)
    unit = "residual (um)"
    paths = []
    for i, f in enumerate(e for e in diag.effects if e.significant and e.fitted is not None):
        fig, ax = plt.subplots(figsize=(8, 3.4))
        ax.set_xlabel(_draw(ax, diag, f, _kind(f)))
        ax.set_ylabel(unit + ", along the effect")
        ax.axhline(0, color="0.6", lw=0.6)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="best")
        size = "" if f.estimate is None else ": " + _size(f.estimate, f.get("unit", ""))
        ax.set_title(f"{f.name} {f.axis or ''} {f.get('where', '')}{size}"[:120], fontsize=9)
        fig.tight_layout()
        name = re.sub(r"[^A-Za-z0-9_]+", "_", f"finding_{i + 1}_{f.name}_{f.axis or ''}").strip("_")
        p = os.path.join(str(directory), f"{name}.png")
        save_figure(fig, p, dpi=110)
        plt.close(fig)
        paths.append(p)
    return paths
