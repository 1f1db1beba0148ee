"""The noise model of the diagnosis: the covariance of every reading, given or estimated from the data.

A laser tracker's reading covariance is a small radial part along the beam and a much larger transverse part across
it (angle encoders; AT960, mtcal.measurement.tracker). With the tracker position given (``--tracker``), the AT960
covariance
about it weights the readings. Without it, the position is estimated from the scatter of the repeated rounds: the
residuals of the quasi-static base family (unweighted) at every reflector have their smallest spread along the beam;
each reading's residual is taken about the mean of its cell (axis, position, point, direction) over the rounds, so a
misfit that repeats every round stays out of the noise model; (1) each reflector's residual scatter (3x3, pooled
over its readings) gives a beam line through the reflector along its least-spread direction, (2) the point closest
to all beam lines starts (3) a maximum-likelihood fit of the tracker position under the AT960 covariance times a
scale c near 1 (prior log c ~ N(0, 0.3^2): the distance comes from the size of the transverse scatter as well as
from the convergence of the beams; Nelder-Mead from that start and from 1.5 m along the mean beam on either side),
(4) twice: the base refitted with the weights of the estimate, and the fit of (3) repeated on its residuals (the
unweighted fit leaks the large transverse noise into the radial residuals of other readings). The estimate is used
when it beats the isotropic model by a likelihood-ratio test (chi^2 with 3 dof, p < 1e-3); else (or with one round)
the readings are weighted equally, sigma from the residuals. The estimation itself (starts, likelihood, test) is
mtcal.measurement.tracker_position, shared with identify. Units: mm."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from scipy import stats

from mtcal.measurement.tracker import covariance
from mtcal.measurement.tracker_position import LR_LEVEL, beam_starts, isotropic_nll, refine

if TYPE_CHECKING:
    from mtcal.diagnose.prepare import Prepared

ITERATIONS = 2          # refits of the base with the estimated weights


@dataclass
class NoiseModel:
    """Whitening W (n, 3, 3) with W^T W = covariance^-1 (1/mm), and how it was obtained."""

    W: np.ndarray
    kind: str                          # "AT960 (given tracker)", "AT960 (estimated tracker)", "isotropic"
    how: str
    tracker: list[float] | None = None  # mm, machine frame
    details: dict = field(default_factory=dict)

    @property
    def weighted(self) -> bool:
        return self.kind != "isotropic"

    @classmethod
    def isotropic(cls, n: int, how: str = "") -> "NoiseModel":
        return cls(np.broadcast_to(np.eye(3), (n, 3, 3)).copy(), "isotropic", how)

    @classmethod
    def at960(cls, xyz: np.ndarray, tracker: np.ndarray, kind: str, how: str, **details) -> "NoiseModel":
        return cls(_whitening(xyz, tracker), kind, how, [float(v) for v in tracker], dict(details))

    @classmethod
    def stations(cls, xyz: np.ndarray, station: np.ndarray, trackers: dict[str, np.ndarray]) -> "NoiseModel":
        """The AT960 covariance of every reading about its own station's tracker (several stations)."""
        W = np.empty((len(xyz), 3, 3))
        for label, t in trackers.items():
            on = station == label
            W[on] = _whitening(xyz[on], t)
        return cls(W, "AT960 (given trackers, per station)",
                   "each reading weighted by the AT960 covariance about its own station's tracker (the recording's "
                   "station and tracker_x,y,z columns)", None,
                   {"trackers": {k: [float(v) for v in t] for k, t in trackers.items()}})

    def to_dict(self) -> dict:
        return {"kind": self.kind, "how": self.how, "tracker": self.tracker, **self.details}


def _whitening(xyz: np.ndarray, tracker: np.ndarray) -> np.ndarray:
    """W (n, 3, 3), W^T W = the inverse AT960 covariance of the readings xyz (n, 3) mm about ``tracker`` (3,)."""
    return np.linalg.inv(np.linalg.cholesky(covariance(xyz, tracker)))


def noise_model(prep: "Prepared", tracker: np.ndarray | None, max_degree: int) -> NoiseModel:
    """The noise model of ``prep``'s readings (see module docstring)."""
    xyz = prep.rec.xyz
    n = len(xyz)
    if tracker is not None:
        return NoiseModel.at960(xyz, tracker, "AT960 (given tracker)",
                                   "tracker position given (--tracker or the recording's tracker_x,y,z columns)")
    if len(set(prep.rec.round.tolist())) < 2:
        return NoiseModel.isotropic(n, "one round: no repeated readings to estimate the beam directions from")
    r = _base_residuals(prep, max_degree)
    groups = list(_groups(prep))
    t, _, nll = min((refine(xyz, r, s) for s in beam_starts(xyz, r, groups)), key=lambda v: v[2])
    for _ in range(ITERATIONS):  # refit the base with the weights of the estimate: the unweighted fit leaks the
        # large transverse noise into the radial residuals of other readings
        r = _base_residuals(prep, max_degree, NoiseModel.at960(xyz, t, "", "").W)
        t, _, nll = refine(xyz, r, t)
    c = xyz.mean(axis=0)
    lr = 2.0 * (isotropic_nll(r) - nll)
    p = float(stats.chi2.sf(max(lr, 0.0), 3))
    details = {"likelihood_ratio": lr, "p_isotropic": p,
               "distance_mm": float(np.linalg.norm(t - c))}
    if p >= LR_LEVEL:
        return NoiseModel.isotropic(n, f"the scatter of the repeated rounds shows no tracker shape (likelihood "
                                       f"ratio {lr:.1f}, p = {p:.2g}): equal weights, sigma from the residuals")
    return NoiseModel.at960(xyz, t, "AT960 (estimated tracker)",
                            "tracker position estimated from the shape of the scatter of the repeated rounds "
                            "(beam lines of the least spread, then maximum likelihood under the AT960 shape)",
                            **details)


def _base_residuals(prep: "Prepared", max_degree: int, W: np.ndarray | None = None) -> np.ndarray:
    """(n, 3) residuals (mm) of the quasi-static base family (or the given model), fitted with the whitening W
    (None: unweighted)."""
    from dataclasses import replace

    from mtcal.diagnose.design import base_design, engine_for, whiten
    n = len(prep.rec)
    if W is not None:
        prep = replace(prep, noise=NoiseModel(W, "AT960", ""))
    degrees = {a: 0 if prep.given_model else max_degree for a in prep.axes}
    eng = engine_for(prep, base_design(prep, degrees), whiten(prep.W, prep.y))
    raw = np.linalg.solve(prep.W, eng.r.reshape(n, 3)[..., None])[..., 0]
    return _round_scatter(prep, raw)


def _round_scatter(prep: "Prepared", raw: np.ndarray) -> np.ndarray:
    """The scatter of the repeated rounds: each reading's residual minus the mean of its cell (axis, position,
    point, direction) over the rounds, scaled by sqrt(m / (m - 1)) for a cell of m readings (unbiased), so that a
    misfit that repeats in every round (an effect the base lacks) does not enter the noise model; cells of one
    reading get 0 (they carry no scatter)."""
    rec = prep.rec
    keys = list(zip(rec.axis.tolist(), rec.position.tolist(), rec.point.tolist(), rec.direction.tolist()))
    index = {k: i for i, k in enumerate(dict.fromkeys(keys))}
    cell = np.array([index[k] for k in keys])
    m = np.bincount(cell)[cell].astype(float)
    mean = np.stack([np.bincount(cell, raw[:, k]) for k in range(3)], axis=1)[cell] / m[:, None]
    return np.where(m[:, None] > 1, (raw - mean) * np.sqrt(m / np.maximum(m - 1, 1))[:, None], 0.0)


def _groups(prep: "Prepared"):
    rec = prep.rec
    for a in prep.axes:
        for lab in np.unique(rec.point[rec.axis == a]):
            sel = (rec.axis == a) & (rec.point == lab)
            if sel.sum() >= 6:
                yield sel
