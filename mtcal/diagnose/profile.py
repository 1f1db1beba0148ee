"""A finding's uncertainty over its nuisance parameters: profile likelihood over a grid.

A side's drift A (1 - exp(-(t - t0)/tau)) is linear in A but not in its onset t0 and time constant tau (the air's
drift, e (1 - exp(-(t - t0)/tau)) ppm, in its time constant).  The
standard uncertainty of A at the best (t0, tau) alone is conditional on them and too small when the record does
not pin them down.  Here every member of the family on a grid of (t0, tau) is fitted with the other selected
effects; the members whose residual sum of squares is within chi^2_1(0.95) = 3.84 (in units of the fit's
sigma^2) of the best form the 95 % confidence region of the nuisance parameters, and the interval of A is the
union of their 95 % intervals (profile likelihood over the nuisance parameters, on the conservative side).  The
same for the change the record observes, A (1 - exp(-(t_end - t0)/tau)), which stays bounded when tau does not.
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np

from mtcal.diagnose import effects as fx
from mtcal.diagnose.engine import Engine

CHI2_95 = 3.841   # chi^2 with 1 degree of freedom at 95 %
Z95 = 1.960
TAU_GRID_S = np.geomspace(300.0, 14400.0, 13)


def members(prep, c: fx.Candidate) -> list[fx.Candidate]:
    """``c``'s family on the grid of its nuisance parameters: a side's drift at every onset it may have
    (mtcal.diagnose.candidates.onsets) and time constants of 5 min to 4 h, finer (25 values over a factor of 3
    either way) about the finding's own; the air's drift (a lag) at those time constants; empty for other
    findings."""
    from mtcal.diagnose.candidates import onsets

    if c.name == "air_index_drift" and c.extra["law"] == "lag":  # its onset is the first reading: tau only
        taus = sorted(set(TAU_GRID_S.tolist()) | set((c.extra["tau_s"] * np.geomspace(1 / 3, 3, 25)).tolist()))
        return [c.refine(tau) for tau in taus]
    if c.name != "thermal_drift" or c.extra.get("target") not in ("spindle", "table"):
        return []
    g = prep.geometry
    seen = g.side == fx.SIDE[c.extra["target"]]
    taus = sorted(set(TAU_GRID_S.tolist()) | set((c.extra["tau_s"] * np.geomspace(1 / 3, 3, 25)).tolist()))
    return [fx.thermal_drift(g, c.extra["target"], tau, t0) for t0 in onsets(prep.rec, seen) for tau in taus]


def profile(eng: Engine, others: list[np.ndarray], grid: list[fx.Candidate], w: Callable, k: int,
            t_end: float) -> dict | None:
    """95 % profile intervals (module docstring) of parameter ``k`` of the members (a drift vector's component, mm;
    the air's final scale change, ppm) and of its change over the record, signed; ``others`` the other selected
    effects' whitened columns; None without a grid."""
    if not grid:
        return None
    fit = eng.copy_base()
    for G in others:
        fit.add(G)
    rows = []
    for c in grid:
        G = w(c)
        sc = fit.score(G)
        if not sc.separable:
            continue
        theta, cov = fit.estimate(others + [G])
        j = k - G.shape[1]  # the member's own parameters come last
        a, u = float(theta[j]), float(math.sqrt(max(cov[j, j], 0.0)))
        frac = 1.0 - math.exp(-max(t_end - c.extra["t0_s"], 0.0) / c.extra["tau_s"])
        rows.append((fit.rss - sc.delta, a, u, frac, c.extra["t0_s"], c.extra["tau_s"]))
    if not rows:
        return None
    rss = np.array([r[0] for r in rows])
    s2 = float(rss.min()) / max(fit.dof - grid[0].G.shape[-1], 1)
    keep = [r for r, v in zip(rows, rss) if v <= rss.min() + CHI2_95 * s2]
    return {"interval_95": [min(r[1] - Z95 * r[2] for r in keep), max(r[1] + Z95 * r[2] for r in keep)],
            "change_interval_95": [min((r[1] - Z95 * r[2]) * r[3] for r in keep),
                                   max((r[1] + Z95 * r[2]) * r[3] for r in keep)],
            "onsets_s": sorted({round(r[4], 3) for r in keep}),
            "tau_s": [min(r[5] for r in keep), max(r[5] for r in keep)],
            "members_within": len(keep), "members": len(rows),
            "how": "profile likelihood over the onset and the time constant: the members within chi^2_1(0.95) of "
                   "the best fit, each with its own 95 % interval (mtcal.diagnose.profile)"}
