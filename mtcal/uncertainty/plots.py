"""Pictures of a Monte Carlo: each axis' error functions with their 95 % coverage band (the trials' errors are
correlated across positions - they share reference readings, reflectors and alignments - so a band, not
independent bars) and, for an adaptive run, the convergence of the stages."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from mtcal.io import save_figure


def plot_bands(res, folder: str | Path) -> list[Path]:
    """uncertainty_AXIS.png per axis (translations um, angles urad); returns the paths."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    d = res.to_dict()
    out, folder = [], Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    axes = sorted({e["axis"] for e in d["errors"].values()})
    for ax in axes:
        names = [n for n, e in d["errors"].items() if e["axis"] == ax]
        fig, panels = plt.subplots(1, 2, figsize=(11, 4.2))
        for panel, kind, scale, unit in ((panels[0], "XYZ", 1e3, "um"), (panels[1], "ABC", 1e6, "urad")):
            for n in (n for n in names if n[2] in kind):
                e = d["errors"][n]
                x = np.asarray(e["positions"])
                line, = panel.plot(x, np.asarray(e["mean"]) * scale, label=n)
                panel.fill_between(x, np.asarray(e["lo95"]) * scale, np.asarray(e["hi95"]) * scale,
                                   color=line.get_color(), alpha=0.2)
            panel.set_xlabel(f"{ax} position")
            panel.set_ylabel(f"error ({unit})")
            panel.grid(alpha=0.3)
            panel.legend(fontsize=8)
        fig.suptitle(f"axis {ax}: Monte Carlo mean and 95 % coverage band ({d['trials']} trials, GUM-S1)", fontsize=10)
        fig.tight_layout()
        p = folder / f"uncertainty_{ax}.png"
        save_figure(fig, p, dpi=110)
        plt.close(fig)
        out.append(p)
    return out


def plot_convergence(res, path: str | Path) -> Path | None:
    """The adaptive run's stages (GUM-S1 7.9): twice the standard deviation of the stages' interval limits against
    the number of trials (um; angles in urad), with the tolerance reached; None for a run of fixed length."""
    if not res.convergence:
        return None
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = [c["trials"] for c in res.convergence]
    v = [c["twice_sd_of_limits_mm"] * 1e3 for c in res.convergence]
    fig, ax = plt.subplots(figsize=(6.5, 3.8))
    ax.plot(n, v, "o-")
    ax.set_xlabel("trials")
    ax.set_ylabel("2 sd of the interval limits (um, urad)")
    ax.set_yscale("log")
    ax.grid(alpha=0.3)
    ax.set_title("Monte Carlo convergence (GUM-S1 7.9)", fontsize=10)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)
    return Path(path)
