"""Predicted uncertainty of identify's joint fit, the estimator ``identify`` uses when the tracker position is known
(mtcal.identify.joint): every reading of every station in one weighted fit of the error motions, the reflectors'
positions and the stations' alignments.

Linear propagation: the fit's covariance at the plan's nominal readings under the tracker law - one noise-free
campaign of the plan through the physical simulator (no errors, stations aligned exactly), fitted once: the
covariance of a weighted least-squares fit depends on the design and the weights, not on the data.  Monte Carlo:
N noisy campaigns of the plan (zero true errors, the tracker law's noise, seeds seed..seed+N-1), each fitted by the
same joint fit; the standard deviation of the N estimates.  Per position of every axis, (n_positions, 6), mm and
rad, of the estimate from all rounds."""
from __future__ import annotations

import logging

import numpy as np

from mtcal.campaign.plans import Plan
from mtcal.campaign.simulate import simulate
from mtcal.campaign.stations import simulate_stations
from mtcal.identify.joint import axis_result, joint_fit
from mtcal.kinematics.machine import Machine
from mtcal.measurement import tracker as trk

log = logging.getLogger(__name__)
PROGRESS_STEPS = 10  # the Monte Carlo says how far it is this many times (each tenth of its campaigns)


def _campaign(m: Machine, pl: Plan, noise: bool, seed: int, spec: trk.TrackerSpec = trk.AT960):
    """One simulated campaign of the plan (zero errors, the tracker law ``spec``): several stations when the plan
    names them."""
    if pl.stations:
        rec, _ = simulate_stations(None, list(pl.stations.items()), machine=m, rounds=pl.rounds, seed=seed,
                                   noise=noise, plan=pl, alignment_um=0.0, alignment_urad=0.0, spec=spec)
        return rec, None
    rec, _ = simulate(None, machine=m, plan=pl, rounds=None, seed=seed, noise=noise, spec=spec)
    return rec, np.asarray(pl.tracker, dtype=float)


def joint_sigma(m: Machine, pl: Plan, spec: trk.TrackerSpec = trk.AT960) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """{axis: (positions, standard uncertainty (n_positions, 6))} of the joint fit's estimate from all rounds, by
    linear propagation (module docstring)."""
    rec, t = _campaign(m, pl, noise=False, seed=0, spec=spec)
    res = joint_fit(rec, m, t, spec)
    out = {}
    for axis in rec.axes():
        ar = axis_result(res, rec, m, axis)
        out[axis] = (ar.positions, np.sqrt(np.maximum(np.diagonal(ar.covariance), 0.0)).reshape(-1, 6))
    return out


def joint_monte_carlo(m: Machine, pl: Plan, n: int, seed: int = 0,
                      spec: trk.TrackerSpec = trk.AT960) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """{axis: (positions, standard deviation (n_positions, 6))} of the joint fit's estimates over ``n`` noisy
    campaigns of the plan (module docstring); logs how many are done at each tenth."""
    est: dict[str, list[np.ndarray]] = {}
    pos: dict[str, np.ndarray] = {}
    every = max(1, n // PROGRESS_STEPS)
    for k in range(n):
        if k and k % every == 0:
            log.info("Monte Carlo of the joint fit: %d of %d campaigns done", k, n)
        rec, t = _campaign(m, pl, noise=True, seed=seed + k, spec=spec)
        res = joint_fit(rec, m, t, spec)
        for axis in rec.axes():
            ar = axis_result(res, rec, m, axis)
            pos[axis] = ar.positions
            est.setdefault(axis, []).append(ar.mean)
    return {a: (pos[a], np.std(np.array(v), axis=0, ddof=1)) for a, v in est.items()}
