"""The pictures of a thermal test a metrologist expects: the drift of each direction against time over the spindle
speed profile, the drift against a temperature (its hysteresis shows the lag), and a model's prediction against
the measurement with the training / hold-out split. PNG via matplotlib's Agg backend, written atomically."""
from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np

from mtcal.io import save_figure
from mtcal.thermal.features import temperature_rise
from mtcal.thermal.iso230_3 import Iso230_3Result
from mtcal.thermal.readings import ThermalTest


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_drift(res: Iso230_3Result, test: ThermalTest, path: str | Path) -> Path:
    """Drift (um) and tilts (urad) against time (h), the spindle speed beneath."""
    plt = _plt()
    h = (res.time_s - res.time_s[0]) / 3600.0
    rows = 3 if res.tilt_urad else 2
    fig, ax = plt.subplots(rows, 1, figsize=(10, 2.6 * rows + 1), sharex=True,
                           height_ratios=[3] + ([2] if res.tilt_urad else []) + [1.3])
    for k, v in res.drift_um.items():
        ax[0].plot(h, v, lw=1, label=f"{k}: range {np.ptp(v):.1f} um")
    ax[0].set_ylabel("drift from the start (um)")
    ax[0].set_title(f"{Path(res.source).name}: {res.clause}", fontsize=9)
    if res.tilt_urad:
        for k, v in res.tilt_urad.items():
            ax[1].plot(h, v, lw=1, label=f"tilt {k}: range {np.ptp(v):.1f} urad")
        ax[1].set_ylabel("tilt (urad)")
    low = ax[-1]
    if test.spindle_rpm is not None:
        low.step(h, test.spindle_rpm, "k", lw=0.8, where="post")
    low.set_ylabel("spindle (rpm)")
    low.set_xlabel("time (h)")
    for a in ax:
        a.grid(alpha=0.3)
        if a.get_legend_handles_labels()[0]:
            a.legend(fontsize=7, loc="best")
    fig.tight_layout()
    save_figure(fig, path, dpi=90)
    plt.close(fig)
    return Path(path)


def plot_drift_temperature(res: Iso230_3Result, test: ThermalTest, sensor: str, path: str | Path) -> Path:
    """Each direction's drift against the rise of one temperature, coloured by time."""
    plt = _plt()
    dT = temperature_rise(test.time_s, test.temperatures[sensor])
    n = len(res.drift_um)
    fig, ax = plt.subplots(1, n, figsize=(3.2 * n + 1, 3.8), squeeze=False, layout="constrained")
    h = (res.time_s - res.time_s[0]) / 3600.0
    for a, (k, v) in zip(ax[0], res.drift_um.items()):
        sc = a.scatter(dT, v, c=h, s=3, cmap="viridis")
        a.set_xlabel(f"rise of {sensor} (K)")
        a.set_title(k, fontsize=9)
        a.grid(alpha=0.3)
    ax[0][0].set_ylabel("drift from the start (um)")
    fig.colorbar(sc, ax=ax[0].tolist(), label="time (h)")
    fig.suptitle(f"{Path(res.source).name}: drift against temperature {sensor}", fontsize=9)
    save_figure(fig, path, dpi=90)
    plt.close(fig)
    return Path(path)


def plot_model(model, test: ThermalTest, path: str | Path) -> Path:
    """Each channel measured, the model and the two baselines, the split marked."""
    plt = _plt()
    h = (test.time_s - test.time_s[0]) / 3600.0
    split = (model.split_s - test.time_s[0]) / 3600.0
    n = len(model.channels)
    fig, ax = plt.subplots(n, 1, figsize=(10, 2.2 * n + 0.6), sharex=True, squeeze=False)
    for a, c in zip(ax[:, 0], model.channels):
        a.plot(h, test.channels[c.channel], "k", lw=1.1, label="measured")
        for name, v in (c.baselines_um or {}).items():
            a.plot(h, v, lw=0.8, ls=":", label=name)
        a.plot(h, c.fitted_um, lw=1, label=f"model: RMSE {c.rmse_um:.1f} um out of sample")
        a.axvline(split, color="grey", ls="--", lw=0.8)
        a.set_ylabel(f"{c.channel} (um)")
        a.set_title(textwrap.shorten(f"{'predictable' if c.predictable else 'NOT predictable'} -- {c.channel}: "
                                     f"{c.model}", 150), fontsize=7)
        a.legend(fontsize=6, loc="best")
        a.grid(alpha=0.3)
    ax[-1, 0].set_xlabel("time (h); fitted left of the dashed line, judged right of it")
    fig.tight_layout()
    save_figure(fig, path, dpi=90)
    plt.close(fig)
    return Path(path)
