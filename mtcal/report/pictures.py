"""The report's pictures, drawn from stored results (JSON documents and history quantities, mm and rad inside,
µm and µrad shown) and returned as PNG bytes, so that the report inlines them as data: URIs."""
from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np

from mtcal.history.compare import SHOWN, Trend
from mtcal.history.results import Quantity


def _figure(w: float = 7.0, h: float = 3.2):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(w, h))
    return plt, fig, ax


def _png(plt, fig) -> bytes:
    buf = io.BytesIO()
    fig.tight_layout()
    fig.savefig(buf, format="png", dpi=96)
    plt.close(fig)
    return buf.getvalue()


def error_functions(axis: str, qs: list[Quantity], position_unit: str = "mm") -> bytes:
    """One axis' identified error functions with their 95 % bands: translations (µm) left, angles (µrad) right,
    over the axis' position (``position_unit``).  No title: the report captions the picture."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(7.2, 2.8))
    for ax, unit in zip(axes, ("mm", "rad")):
        shown, f = SHOWN[unit]
        for name in sorted({q.name for q in qs if q.unit == unit}):
            pts = sorted((q.position, q.value * f, (q.u95 or 0.0) * f) for q in qs if q.name == name)
            x, v, u = (np.array(c) for c in zip(*pts))
            line, = ax.plot(x, v, marker=".", label=name)
            ax.fill_between(x, v - u, v + u, color=line.get_color(), alpha=0.2)
        ax.set_xlabel(f"{axis} position ({position_unit})")
        ax.set_ylabel(f"{'translation' if unit == 'mm' else 'angular'} error ({shown})")
        ax.grid(alpha=0.3)
        if ax.lines:
            ax.legend(fontsize=7, ncol=3)
    return _png(plt, fig)


def iso230_2_axis(ev: dict) -> bytes:
    """ISO 230-2 mean deviations per target, up and down, with ±2s (the ISO 230-2 band)."""
    plt, fig, ax = _figure(7.0, 2.8)
    x = np.asarray(ev["positions"], dtype=float)
    t = ev["targets"]
    for tag, label in (("up", "approached +"), ("down", "approached −")):
        m = np.asarray([np.nan if v is None else v for v in t[f"mean_{tag}"]], dtype=float)
        s = np.asarray([np.nan if v is None else v for v in t[f"s_{tag}"]], dtype=float)
        line, = ax.plot(x, m, marker="o", label=label)
        ax.fill_between(x, m - 2 * s, m + 2 * s, color=line.get_color(), alpha=0.2)
    ax.set_xlabel(f"target position ({_unit(ev.get('position_unit', 'mm'))})")
    ax.set_ylabel(f"mean positional deviation ({_unit(ev.get('unit', 'um'))})")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    return _png(plt, fig)


def circular_trace(doc: dict) -> bytes:
    """A circular test: measured and predicted radial deviation (µm) over the angle, the prediction's band."""
    plt, fig, ax = _figure(7.0, 2.8)
    tr = np.asarray(doc["trace"], dtype=float)
    order = np.lexsort((tr[:, 0], tr[:, 4]))
    tr = tr[order]
    for d, name in ((1, "ccw"), (-1, "cw")):
        k = tr[:, 4] == d
        if k.any():
            ax.plot(tr[k, 0], tr[k, 1] * 1e3, label=f"measured {name}")
            ax.plot(tr[k, 0], tr[k, 2] * 1e3, ls="--", label=f"predicted {name}")
            ax.fill_between(tr[k, 0], (tr[k, 2] - 2 * tr[k, 3]) * 1e3, (tr[k, 2] + 2 * tr[k, 3]) * 1e3, alpha=0.15)
    ax.set_xlabel("angle (deg)")
    ax.set_ylabel("radial deviation (µm)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    return _png(plt, fig)


def rtest_trace(doc: dict) -> bytes:
    """An R-test: measured and predicted deviations dx, dy, dz (µm) over the rotary position."""
    plt, fig, ax = _figure(7.0, 2.8)
    tr = np.asarray(doc["trace"], dtype=float)
    for i, c in enumerate("xyz"):
        line, = ax.plot(tr[:, 0], tr[:, 1 + i] * 1e3, label=f"measured d{c}")
        ax.plot(tr[:, 0], tr[:, 4 + i] * 1e3, ls="--", color=line.get_color(), label=f"predicted d{c}")
    ax.set_xlabel(f"{doc.get('axis') or 'rotary axis'} position (deg)")
    ax.set_ylabel("deviation (µm)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=3)
    return _png(plt, fig)


def findings(effects: list[dict]) -> bytes:
    """The diagnosis' findings: each estimate's size with its 95 % interval where one is given (µm or µrad)."""
    plt, fig, ax = _figure(7.0, max(1.8, 0.6 + 0.35 * len(effects)))
    labels, sizes, lo, hi = [], [], [], []
    for e in effects:
        est = e.get("estimate")
        if not isinstance(est, (int, float)) or not math.isfinite(est):
            continue
        iv = e.get("interval_95")
        labels.append(f"{e['name']} {e.get('axis') or ''}".strip())
        sizes.append(est * 1e3)
        lo.append(iv[0] * 1e3 if iv else est * 1e3)
        hi.append(iv[1] * 1e3 if iv else est * 1e3)
    y = np.arange(len(sizes))
    ax.barh(y, sizes, color="#4477aa")
    ax.errorbar(sizes, y, xerr=[np.subtract(sizes, lo), np.subtract(hi, sizes)], fmt="none", ecolor="k")
    ax.set_yticks(y, labels, fontsize=8)
    ax.set_ylabel("finding")
    ax.set_xlabel("estimate (µm, or µrad for an angle) with its 95 % interval")
    ax.grid(alpha=0.3, axis="x")
    return _png(plt, fig)


def trend_png(t: Trend) -> bytes:
    """An error's values over the calibrations with their 95 % intervals."""
    import datetime as dt
    plt, fig, ax = _figure(7.0, 2.6)
    x = [dt.date.fromisoformat(p["date"]) for p in t.points]
    v = [p["value"] for p in t.points]
    u = [p["u95"] or 0.0 for p in t.points]
    ax.errorbar(x, v, yerr=u, marker="o", capsize=3)
    ax.set_xticks(x, [d.isoformat() for d in x])
    ax.set_ylabel(f"{t.name} ({t.unit})")
    ax.set_xlabel("calibration date")
    ax.grid(alpha=0.3)
    return _png(plt, fig)


def ranked(effects: list[tuple[str, float]]) -> bytes:
    """The largest errors' tool-tip error over the work volume, each alone (µm RMS), largest on top."""
    plt, fig, ax = _figure(7.0, max(1.8, 0.7 + 0.3 * len(effects)))
    names = [n for n, _ in effects][::-1]
    ax.barh(np.arange(len(names)), [v for _, v in effects][::-1], color="#4477aa")
    ax.set_yticks(np.arange(len(names)), names, fontsize=8)
    ax.set_ylabel("ISO 230-1 error")
    ax.set_xlabel("tool-tip error over the work volume, the error alone (µm RMS)")
    ax.grid(alpha=0.3, axis="x")
    return _png(plt, fig)


def _unit(u: str) -> str:
    """A stored unit as printed: um as µm, urad as µrad."""
    return {"um": "µm", "urad": "µrad"}.get(u, u)


def save_trend(t: Trend, path: str | Path) -> None:
    """The trend picture written atomically (mtcal.io)."""
    from mtcal.io import atomic_open
    with atomic_open(path, "wb") as fh:
        fh.write(trend_png(t))
