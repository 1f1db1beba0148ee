"""Where the tracker stood, estimated from the scatter of repeated readings (mm, machine frame).

A laser tracker's reading covariance (mtcal.measurement.tracker) is small along the beam and large across it, so the
scatter of repeated readings of one reflector is flattest along the line to the tracker. ``estimate_position`` turns
the scatter ``r`` (n, 3) of readings ``xyz`` (n, 3) into the station: (1) each group's (a reflector's) least-spread
direction gives a beam line through it, (2) the point closest to all beam lines, and 1.5 m either side along the
mean beam, start (3) a maximum-likelihood fit of the position together with the radial and transverse scales of the
prior law (the AT960's unless another is named, mtcal.measurement.tracker.tracker_model), the transverse one near 1
(prior log c_t ~ N(0, 0.3^2): the distance comes from the size of the transverse scatter as well as from the
convergence of the beams, which converge only under the right shape), under a Student-t law (NU dof: what an effect
does to a few readings weighs little; Nelder-Mead).  The estimate is accepted when it beats isotropic noise of the
best scale by a likelihood-ratio test (chi^2 with 4 dof, p < 1e-3); its
covariance is the inverse of the negative log-likelihood's Hessian. Used by the diagnosis (scatter = residuals of
its base family) and by identify (scatter = readings about their mean over the rounds, no model needed).
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
from scipy import interpolate, optimize

from mtcal import _tails
from mtcal.measurement.passes import position_key
from mtcal.measurement.recordings import Recording
from mtcal.measurement.tracker import AT960, TrackerSpec, law_report

LR_LEVEL = 1e-3       # likelihood-ratio test level: anisotropic (a tracker) vs isotropic noise
START_DISTANCE = 1500.0  # mm: the start along the mean beam direction (a usual tracker stand-off)
MAX_DISTANCE = 30000.0   # mm: the search stays within this distance of every reading
SCALE_PRIOR = 0.3        # sd of the log of the tracker's transverse noise relative to its specification (the prior)
HESSIAN_STEP = (5.0, 5.0, 5.0, 0.01, 0.01)  # mm, mm, mm, log c_r, log c_t: central differences of the likelihood
NU = 4.0                 # Student-t dof of the scatter: the readings an effect moves (an outlier and the other
# readings of its cell, a bumped nest) weigh less than under a normal law (gen2, 1 : 70 trackers: the station of an
# outlier's campaign 10.8 m off under a normal law, 21 mm under this one)
WARM = 0.1              # a warm start's simplex over the cold starts' (refine)
LOG_SHAPE_START = 1.5    # the radial scale starts at the prior's and exp(+-1.5) (variance) times it
SHAPE_HIGH, SHAPE_LOW = 4.0, 0.6  # the base law's shape gives way when the data's radial : transverse ratio over
# the base's is above SHAPE_HIGH (both with and without each round's mean removed: effects the scatter holds raise
# it by up to 2-3, never lower it) or below SHAPE_LOW (without: a round's mean carries the large transverse noise of
# its readings into the small radial direction of each, so removing it raises the ratio of a tracker more
# anisotropic than the base's, gen2 seed 19 campaign 29: 0.35 -> 0.63, truth 0.37; no effect lowers the ratio);
# other trackers differ by 0.4 (1 : 70) to 30 (isotropic) ...
MIN_LABEL_READINGS = 20  # readings with scatter a reflector needs for its own ratio in shape_ratio
SHAPE_NEAR, SHAPE_AGREE = 1.4, 1.25  # ... and already above 1.4 where the ratio with and without the round means
# agree within 1.25, or below 1 / 1.4 (the ratio without them, as for SHAPE_LOW): an effect in the scatter (a
# drift, a bump, a re-seated nest) moves the two apart (tests/test_noise_shape.py: 1.3-1.8 against 1.3-2.7), the
# instrument's own shape does not (gen2: an AT960-like tracker's ratio is 0.66-2.3 times the AT960's, its
# estimates agree within 1.1)
SHAPE_NEAR_FIT = 1.15  # the near band where the station and the shape, estimated together, prefer the data's
# shape by a likelihood-ratio test (mtcal.diagnose.noise._estimated_shape)


@dataclass(frozen=True)
class PositionEstimate:
    """The estimated station (mm), its covariance (mm^2; None when the Hessian is not positive definite), the
    transverse noise variance relative to the prior law's specification (AT960 by default), the likelihood-ratio
    test against isotropic noise, and ``shape``: the radial : transverse sigma ratio over the prior's."""

    position: np.ndarray
    covariance: np.ndarray | None
    scale: float
    likelihood_ratio: float
    p_isotropic: float
    shape: float = 1.0
    logs: np.ndarray | None = None  # the fit's log scales (log c_r, log c_t) and negative log-likelihood
    nll: float | None = None
    interval: dict | None = None  # how far the data fix its distance (station_interval), where asked

    @property
    def accepted(self) -> bool:
        """Whether the scatter shows a tracker's shape (p < ``LR_LEVEL``) and the position is determined."""
        return self.p_isotropic < LR_LEVEL and self.covariance is not None

    @property
    def sigma_mm(self) -> np.ndarray:
        return np.sqrt(np.diagonal(self.covariance)) if self.covariance is not None else np.full(3, np.inf)


def least_spread(r: np.ndarray) -> np.ndarray:
    """The unit direction in which the scatter r (n, 3) is smallest (the beam)."""
    return np.linalg.eigh(r.T @ r)[1][:, 0]


def beam_starts(xyz: np.ndarray, r: np.ndarray, groups: list[np.ndarray], spec: TrackerSpec = AT960
                ) -> list[np.ndarray]:
    """Starting positions (mm): the point closest (least squares) to every group's beam line (unless they are
    parallel), and START_DISTANCE either side of the readings' centre along the mean beam."""
    A, b = np.zeros((3, 3)), np.zeros(3)
    us = []
    for sel in groups:
        u = least_spread(r[sel])
        us.append(u)
        P = np.eye(3) - np.outer(u, u)
        A += P
        b += P @ xyz[sel].mean(axis=0)
    lam = np.linalg.eigvalsh(A)
    starts = [] if lam[-1] <= 0 or lam[0] < 1e-3 * lam[-1] else [np.linalg.solve(A, b)]
    M = sum(np.outer(u, u) for u in (us or [least_spread(r)]))
    u = np.linalg.eigh(M)[1][:, -1]
    c = xyz.mean(axis=0)
    starts += [c + START_DISTANCE * u, c - START_DISTANCE * u]
    lik = Likelihood(xyz, r, spec)
    starts = [s for s in starts if math.isfinite(lik(np.append(s, 0.0)))]
    return starts or [c + START_DISTANCE * e for e in np.vstack([np.eye(3), -np.eye(3)])]


class Likelihood:
    """The scatter's negative log-likelihood about a trial tracker (``nll``), with what does not depend on the trial
    (the live rows, their squared scatter, the law's coefficients) computed once and the coordinates held as
    contiguous columns: the optimizers below call it thousands of times (about 0.1 ms a call for 1700 readings)."""

    def __init__(self, xyz: np.ndarray, r: np.ndarray, spec: TrackerSpec = AT960):
        live = np.any(r != 0, axis=1)
        self.xyz, self.spec, self.all_live = np.asarray(xyz, float), spec, bool(live.all())
        self.X, self.R = (np.ascontiguousarray(a.T) for a in (self.xyz[live], r[live]))  # (3, m) each
        self.R2, self.m = np.sum(r[live] ** 2, axis=1), int(live.sum())
        # the law's sigmas a + b L (mm, L in mm): spec.sigmas' numbers, held to evaluate without its calls
        self.law = [(a / spec.k * 1e-3, b / spec.k * 1e-6) for a, b in (
            (spec.radial_um, spec.radial_um_per_m), (spec.transverse_um, spec.transverse_um_per_m))]

    def __call__(self, v: np.ndarray) -> float:
        if not np.all(np.isfinite(v)):
            return math.inf
        lr, lt = (float(v[3]), float(v[4])) if len(v) == 5 else (float(v[3]),) * 2
        (x, y, z), (rx, ry, rz) = self.X, self.R
        dx, dy, dz = x - v[0], y - v[1], z - v[2]
        dist = np.sqrt(dx * dx + dy * dy + dz * dz)
        near, far = (dist.min(), dist.max()) if self.all_live else self._extremes(np.asarray(v[:3], float))
        if near < 100.0 or far > MAX_DISTANCE:
            return math.inf
        (ar, br), (at, bt) = self.law
        s_r, s_t = ar + br * dist, at + bt * dist
        along2 = ((rx * dx + ry * dy + rz * dz) / dist) ** 2
        across = np.maximum(self.R2 - along2, 0.0)
        st2 = s_t * s_t
        q = along2 * (math.exp(-lr) / NU) / (s_r * s_r) + across * (math.exp(-lt) / NU) / st2
        logdet = 2.0 * float(np.sum(np.log(s_r * st2))) + self.m * (lr + 2 * lt)
        return 0.5 * ((NU + 3) * float(np.sum(np.log1p(q))) + logdet + (lt / SCALE_PRIOR) ** 2)

    def _extremes(self, t: np.ndarray) -> tuple[float, float]:
        dist = np.linalg.norm(self.xyz - t, axis=1)  # every reading, those without scatter too
        return float(dist.min()), float(dist.max())


def nll(xyz: np.ndarray, r: np.ndarray, v: np.ndarray, spec: TrackerSpec = AT960) -> float:
    """Negative log-likelihood (up to a constant) of the scatter about the tracker t = v[:3] (mm): Student-t (NU
    dof) with the scale matrix c_r * ``spec``'s radial part + c_t * its transverse part, (log c_r, log c_t) = v[3:5]
    (the data's shape), or c_r = c_t = exp(v[3]) for a 4-vector (``spec``'s shape); prior log c_t ~ N(0,
    SCALE_PRIOR^2) (a tracker near its specification: with the convergence of the beams it fixes the distance).
    Rows of zeros of ``r`` carry no scatter (cells of one reading); the distance bounds hold for every reading."""
    return Likelihood(xyz, r, spec)(np.asarray(v, float))


def refine(xyz: np.ndarray, r: np.ndarray, start: np.ndarray, spec: TrackerSpec = AT960, shape: bool = True,
           logs: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, float]:
    """Maximum likelihood from ``start`` (nll): (position mm, log scales (log c_r, log c_t), negative
    log-likelihood); ``shape``: the radial and transverse scales free (the data's shape; Nelder-Mead from three
    radial starts, the beams converge only under the right shape), else ``spec``'s shape times one scale.
    ``logs``: a previous optimum's log scales (with ``start`` its position, on a scatter that changed little since):
    one start from there, the simplex a tenth of the cold starts' (WARM)."""
    best, lik = None, Likelihood(xyz, r, spec)
    warm = logs is not None and shape
    for lr0 in ((None,) if not shape else (tuple(logs),) if warm else (0.0, -LOG_SHAPE_START, LOG_SHAPE_START)):
        x0 = np.append(np.asarray(start, float), [0.0] if lr0 is None else lr0 if warm else [lr0, 0.0])
        step = np.array([300.0, 300.0, 300.0] + [0.3] * (len(x0) - 3)) * (WARM if warm else 1.0)
        simplex = x0 + np.vstack([np.zeros(len(x0)), np.diag(step)])
        res = optimize.minimize(lik, x0, method="Nelder-Mead",
                                options={"xatol": 1e-3, "fatol": 1e-3, "initial_simplex": simplex, "maxiter": 4000})
        if best is None or res.fun < best.fun:
            best = res
    logs = best.x[3:5] if shape else np.repeat(best.x[3], 2)
    return best.x[:3], logs, float(best.fun)


def isotropic_nll(r: np.ndarray) -> float:
    """The negative log-likelihood of the scatter under isotropic noise (Student-t, NU dof, of the best scale)."""
    live = np.any(r != 0, axis=1)
    r2 = np.sum(r[live] ** 2, axis=1)
    m = int(live.sum())

    def f(ls: float) -> float:
        return 0.5 * ((NU + 3) * float(np.sum(np.log1p(r2 * math.exp(-ls) / NU))) + 3 * m * ls)

    ls0 = math.log(max(float(np.median(r2)), 1e-30) / 3)
    return float(optimize.minimize_scalar(f, bounds=(ls0 - 10, ls0 + 10), method="bounded").fun)


def _covariance(xyz: np.ndarray, r: np.ndarray, v: np.ndarray, spec: TrackerSpec = AT960) -> np.ndarray | None:
    h = np.asarray(HESSIAN_STEP)

    f = Likelihood(xyz, r, spec)

    f0 = f(v)
    k = len(v)
    H = np.zeros((k, k))
    for i in range(k):
        for j in range(i, k):
            ei, ej = np.eye(k)[i] * h[i], np.eye(k)[j] * h[j]
            H[i, j] = H[j, i] = (f(v + ei + ej) - f(v + ei - ej) - f(v - ei + ej) + f(v - ei - ej)) / (
                4 * h[i] * h[j]) if i != j else (f(v + ei) - 2 * f0 + f(v - ei)) / h[i] ** 2
    if not np.all(np.isfinite(H)) or np.linalg.eigvalsh(H)[0] <= 0:
        return None
    return np.linalg.inv(H)[:3, :3]


def best_start(xyz: np.ndarray, r: np.ndarray, groups: list[np.ndarray], spec: TrackerSpec = AT960
               ) -> tuple[np.ndarray, np.ndarray, float]:
    """refine from every beam_starts start; the best: (position mm, log scales, negative log-likelihood)."""
    return min((refine(xyz, r, s, spec) for s in beam_starts(xyz, r, groups, spec)), key=lambda v: v[2])


def against_isotropic(r: np.ndarray, nll_fit: float) -> tuple[float, float]:
    """(likelihood ratio, p) of a fit (``nll_fit``: position and shape, refine) against isotropic noise of the best
    scale on the scatter ``r``: chi^2 with 4 dof (the position and the shape)."""
    lr = 2.0 * (isotropic_nll(r) - nll_fit)
    return lr, float(_tails.chi2_sf(max(lr, 0.0), 4))


def estimate_position(xyz: np.ndarray, r: np.ndarray, groups: list[np.ndarray], spec: TrackerSpec = AT960
                      ) -> PositionEstimate:
    """The station (see module docstring) from readings ``xyz`` (n, 3) mm, their scatter ``r`` (n, 3) mm (rows of
    zeros carry none) and the groups (boolean masks) of readings of one reflector, under ``spec``'s law."""
    t, logs, f = best_start(xyz, r, groups, spec)
    lr, p = against_isotropic(r, f)
    return PositionEstimate(t, _covariance(xyz, r, np.append(t, logs), spec), math.exp(logs[1]), lr, p,
                            math.exp(0.5 * (logs[0] - logs[1])), np.asarray(logs, float), f)


def round_scatter(rec: Recording, values: np.ndarray | None = None) -> np.ndarray:
    """(n, 3) mm: each reading (or its row of ``values``, e.g. a model's residuals) minus the mean of its cell
    (station, axis, position, point, direction) over the rounds, scaled by sqrt(m / (m - 1)) for a cell of m
    readings (unbiased); 0 for cells of one reading.  What the tracker's noise (and any drift) does between repeated
    rounds: with the readings themselves, no model needed; with residuals, a misfit that repeats every round stays
    out."""
    v = rec.xyz if values is None else values
    keys = list(zip(rec.stations().tolist(), rec.axis.tolist(), position_key(rec.position).tolist(),
                    rec.point.tolist(), rec.direction.tolist()))
    index = {k: i for i, k in enumerate(dict.fromkeys(keys))}
    cell = np.array([index[k] for k in keys])
    m = np.bincount(cell)[cell].astype(float)
    mean = np.stack([np.bincount(cell, v[:, k]) for k in range(3)], axis=1)[cell] / m[:, None]
    return np.where(m[:, None] > 1, (v - mean) * np.sqrt(m / np.maximum(m - 1, 1))[:, None], 0.0)


def _round_centred(rec: Recording, r: np.ndarray) -> np.ndarray:
    """The scatter ``r`` with each (station, axis, round)'s mean removed (a drift moves a round as a whole),
    scaled by sqrt(k / (k - 1)) for a round of k readings with scatter (unbiased)."""
    out = r.copy()
    live = np.any(r != 0, axis=1)
    keys = list(zip(rec.stations().tolist(), rec.axis.tolist(), rec.round.tolist()))
    index = {k: i for i, k in enumerate(dict.fromkeys(keys))}
    block = np.array([index[k] for k in keys])
    for b in np.unique(block[live]):
        sel = (block == b) & live
        k = int(sel.sum())
        if k > 1:
            out[sel] = (r[sel] - r[sel].mean(axis=0)) * math.sqrt(k / (k - 1))
    return out


def station_scatter(rec: Recording, values: np.ndarray | None = None) -> np.ndarray:
    """(n, 3) mm: the scatter that places an unknown station -- round_scatter (of the readings, or of ``values``),
    less the mean of each (station, axis, round) (_round_centred).  A motion that moves a whole round alike (the
    tracker knocked or re-levelled between rounds, a drift, a robot's pose moving the base) is no noise of the
    tracker: left in, its one direction is shared by every reading of the round and pulls the beam lines.  A
    re-levelled tracker (gen2 3611/34: a 28 um shift before X round 3) put the station 6.6 m away on the far side
    of the machine instead of 4.2 m on its own (the beam lines are the same lines either way; their directions
    through the work zone are not), and the weights about it named a noise reading an outlier; the round means
    removed, it is found 0.2 m from the truth.  Used by identify and the diagnosis alike."""
    return _round_centred(rec, round_scatter(rec, values))


def shape_ratio(xyz: np.ndarray, r: np.ndarray, t: np.ndarray, base: TrackerSpec,
                labels: np.ndarray | None = None) -> tuple[float, float]:
    """(rho, transverse variance scale): the scatter along the beam over the base law's radial sigma (normal:
    1.4826 x median |z|) against the scatter across it over the transverse sigma (chi^2, 2 dof: median / 2 ln 2).
    ``labels`` (n,): each reflector's own, then the median over the reflectors with MIN_LABEL_READINGS (an effect
    of one nest -- a knock, a creep -- moves one reflector's scatter, not the median's)."""
    live = np.any(r != 0, axis=1)
    d = xyz[live] - np.broadcast_to(np.asarray(t, float), xyz.shape)[live]
    dist = np.linalg.norm(d, axis=1)
    u = d / dist[:, None]
    s_r, s_t = base.sigmas(dist)
    z_r = np.abs(np.einsum("ni,ni->n", r[live], u)) / s_r
    z_t2 = np.maximum(np.sum(r[live] ** 2, axis=1) - (z_r * s_r) ** 2, 0.0) / s_t**2
    groups = [np.ones(len(z_r), bool)] if labels is None else [
        m for m in (labels[live] == lab for lab in np.unique(labels[live])) if m.sum() >= MIN_LABEL_READINGS]
    if not groups:
        groups = [np.ones(len(z_r), bool)]
    sr = 1.4826 * float(np.median([np.median(z_r[m]) for m in groups]))
    st2 = float(np.median([np.median(z_t2[m]) for m in groups])) / (2 * math.log(2))
    return sr / math.sqrt(st2), st2


@dataclass(frozen=True)
class ShapeEstimate:
    """The noise law the repeated rounds show about a tracker position, against a base law (the prior: the
    AT960's unless another is named, ``base``):
    ``rho`` = the data's radial : transverse ratio over the base's (from the model-free round scatter; ``rho_centred``
    the same with each round's mean removed), ``scale`` = the transverse variance over the base's, and ``spec``,
    the base law with both sigmas scaled to the data's.  ``replaces_base``: the shapes differ beyond what effects
    in the scatter can make (SHAPE_HIGH, SHAPE_LOW; SHAPE_NEAR where the two ratios agree, SHAPE_AGREE)."""

    spec: TrackerSpec
    rho: float
    rho_centred: float
    scale: float
    base: TrackerSpec = AT960
    known: bool = True   # the tracker position given, not estimated (an estimate's error raises both ratios alike)
    near_band: float = SHAPE_NEAR  # the near band's edge (SHAPE_NEAR_FIT where the likelihood prefers the data's shape)
    rigid: dict | None = None  # the law from the mutual distances (rigid_law) and the cross-check (_cross_check)

    @property
    def replaces_base(self) -> bool:
        lo, hi = sorted((self.rho, self.rho_centred))
        b = self.near_band
        near = self.known and (hi / lo < SHAPE_AGREE and lo > b or self.rho < 1 / b)
        return lo > SHAPE_HIGH or self.rho < SHAPE_LOW or near

    def law(self) -> dict:
        """One-sigma law a + b L of each direction (um, um/m)."""
        k = self.spec.k
        return {"radial_um": self.spec.radial_um / k, "radial_um_per_m": self.spec.radial_um_per_m / k,
                "transverse_um": self.spec.transverse_um / k,
                "transverse_um_per_m": self.spec.transverse_um_per_m / k}

    def law_text(self) -> str:
        """The law in words (one sigma, um and um/m) and its shape against the base law's."""
        law = self.law()
        return (f"1 sigma along the beam {law['radial_um']:.2f} um + {law['radial_um_per_m']:.2f} um/m, across "
                f"{law['transverse_um']:.1f} um + {law['transverse_um_per_m']:.1f} um/m (radial : transverse "
                f"{self.rho:.2g} times {self.base.whose})")

    def report(self) -> dict:
        """The law to weight by, as the JSON answers report it (tracker.law_report): the data's where the rounds
        reject the base's shape, else the base's; the ratio said either way."""
        ratio = f"the data's radial : transverse ratio is {self.rho:.3g} times {self.base.whose}"
        if self.replaces_base:
            return law_report(self.spec, self.base, "data", f"{ratio}, outside {self._band()}", self.source)
        return law_report(self.base, self.base, "prior", f"{self.source} agree with its shape ({ratio})")

    @property
    def source(self) -> str:
        """Where the law's sigmas come from, in words: the one statement every field that reports the law uses."""
        used = (self.rigid or {}).get("used", "round scatter")
        return {"mutual distances": "the reflectors' mutual distances within each pass",
                ACROSS: "the reflectors' mutual distances across the beams and the repeated rounds along them",
                ALONG: "the reflectors' mutual distances along the beams and the repeated rounds across them"}.get(
            used, "the repeated rounds")

    @property
    def note(self) -> str | None:
        """Where the round scatter and the mutual distances disagree: what differs and which law was used (the
        distances', or the base's where their shape is the base's: replaces_base)."""
        text = None if self.rigid is None else self.rigid.get("disagreement")
        return text and text + (f": the law from {self.source} is used" if self.replaces_base else
                                f": their shape is {self.base.whose}, whose law is used")

    def to_dict(self) -> dict:
        return {**({"mutual_distances": self.rigid} if self.rigid is not None else {}),
                "law_1sigma": {k: round(v, 4) for k, v in self.law().items()},
                "radial_to_transverse_over_base": round(self.rho, 3),
                "same_with_round_means_removed": round(self.rho_centred, 3),
                "used": "estimated law" if self.replaces_base else f"base law ({self.base.label})",
                "rule": f"the base law's shape gives way outside {self._band()} (mtcal.measurement.tracker_position)"}

    @staticmethod
    def _band() -> str:
        return (f"[{SHAPE_LOW:g}, {SHAPE_HIGH:g}], or (the tracker position given) [{1 / SHAPE_NEAR:.3g}, "
                f"{SHAPE_NEAR:g}] (above it where the ratios with and without the round means agree within "
                f"{SHAPE_AGREE:g}) "
                f"(estimated with it: [{1 / SHAPE_NEAR_FIT:.3g}, {SHAPE_NEAR_FIT:g}] where the likelihood also "
                "prefers the data's shape)")


def estimate_shape(rec: Recording, t: np.ndarray, base: TrackerSpec = AT960, r: np.ndarray | None = None,
                   known: bool = True) -> ShapeEstimate:
    """The tracker's noise law about ``t`` (mm: (3,), or (n, 3) every reading's own station's tracker: several
    stations of one instrument share the law) from the scatter of the repeated rounds of ``rec`` (model-free, so no
    misfit of a model passes for noise).  Medians (per reflector, then over the reflectors: shape_ratio) make it
    robust to outliers and to an effect of one nest; the distance law (a : b of each
    direction) stays the base's: one machine's readings span too short a range of distances to separate a and b.
    ``r``: (n, 3) mm scatter to use instead (a model's residuals where no reading is repeated at one station);
    ``known``: ``t`` is given (False: estimated from the same scatter; only the wide band applies).  The scale
    across the beams is the mutual distances' wherever they determine it (_cross_check), with the rounds' own
    scatter: a model's residuals (``r``) are shrunk by the fit in both directions alike, so their ratio is kept."""
    unbiased = r is None
    r = round_scatter(rec) if r is None else r
    rho, scale = shape_ratio(rec.xyz, r, t, base, rec.point)
    rho_c, scale_c = shape_ratio(rec.xyz, _round_centred(rec, r), t, base, rec.point)
    c = math.sqrt(scale)
    rigid = rigid_law(rec, t, base)
    fr, ft, rigid = _cross_check(c * rho, c, rigid, base, across=unbiased, known=known)
    if rigid is not None and rigid["used"] in ("mutual distances", ALONG):
        rho = rho_c = fr / ft   # immune to a round's mean: both ratios are the distances'
        scale, c = ft**2, ft
    elif rigid is not None and rigid["used"] == ACROSS:
        rho, rho_c = fr / ft, math.sqrt(scale_c) * rho_c / ft   # the rounds' radial over the distances' transverse
        scale, c = ft**2, ft
    return ShapeEstimate(base.scaled(c * rho, c), rho, rho_c, scale, base, known, rigid=rigid)


def _cross_check(fr: float, ft: float, rigid: dict | None, base: TrackerSpec, across: bool = True,
                 known: bool = True) -> tuple[float, float, dict | None]:
    """The round scatter's factors (radial ``fr``, transverse ``ft`` against ``base``) checked against the mutual
    distances' (rigid_law): where the round scatter's sigma exceeds a determined sigma of the distances by more than
    RIGID_DISAGREE, the round scatter counts a motion shared by a side (a drift, the machine's own motion) as noise:
    the distances' sigmas are used and the disagreement said; so too their upper bound where they do not determine
    the scale but see it (an interval with a lower end: the detrend changes it, or it spans 4x or more) and the
    rounds' exceeds the bound by as much.  About an estimated station (not ``known``), where the interval has no
    lower end (the distances' best is nil: no distance needs that noise about the estimate's beams), the bound says
    only how little they see of it there, not how large it is: that is said
    ("bounded") and the rounds' sigma kept (icelinker's replica with a nest wandering, about a station the
    distances reject: radial 0-3.9 of the law's; the bound as the weight took the along-beam sigma from 14 to 1.7
    um and named a false knock of the wandering nest; about a given tracker the beams are the tracker's and the
    bound is kept: icelinker about its origin, radial 0-0.71 um, the rounds' 17.4 um named a side expanding).
    Where they agree, the scale across the beams is still the distances' wherever they determine it (the tighter of
    the two, blind to what moves a side; on 43 gen2 campaigns within 25 % of the generator's law in all, the rounds'
    in 93 %) and the radial one the rounds' (the distances' is poorly conditioned where the pairs lie across the
    beams); not with ``across`` False (a model's residuals, shrunk by the fit in both directions alike: their ratio
    is kept). Returns the factors used and ``rigid`` with "used" ("mutual distances", ACROSS, ALONG or "round
    scatter": where each scale used comes from), "bounded" where said, and "disagreement" or "cross_check"."""
    if rigid is None:
        return fr, ft, None
    out, say, bounds, theirs = [fr, ft], [], [], [False, False]
    for k, (name, f0) in enumerate((("radial", fr), ("transverse", ft))):
        g = rigid[name]
        hi = g["interval_95"][1]
        sig0 = float(base.sigmas(rigid["at_distance_m"] * 1e3)[k]) * 1e3  # um: the base law's at that distance
        if g["determined"] and f0 > RIGID_DISAGREE * g["factor"]:  # a shared motion only adds to the rounds'
            out[k], theirs[k] = g["factor"], True
        elif not (known or g["determined"]) and hi is not None and f0 > RIGID_DISAGREE * hi and \
                g["interval_95"][0] is None:
            bounds.append(f"{name} {f0 * sig0:.3g} um from the rounds, at most {hi * sig0:.3g} um from the "
                          "distances, whose best is nil (the rounds' is kept)")
            continue
        elif not g["determined"] and hi is not None and f0 > RIGID_DISAGREE * hi:
            out[k], theirs[k] = hi, True   # the distances see this noise, not closely: the largest they allow
        else:
            if name == "transverse" and g["determined"] and across:
                out[k], theirs[k] = g["factor"], True  # the distances determine the scale across the beams best
            continue
        say.append(f"{name} {f0 * sig0:.3g} um from the rounds against {out[k] * sig0:.3g} um from the distances"
                   + ("" if g["determined"] else " (their upper bound)"))
    text = (f"the tracker's noise (1 sigma at {rigid['at_distance_m']:.3g} m) from the scatter of the rounds and "
            f"from the reflectors' mutual distances within each pass differ: {'; '.join(say)} -- the rounds count "
            "a motion shared by a side (a drift, the machine's motion) as noise, the distances do not") if say else None
    used = ("mutual distances" if all(theirs) else ACROSS if theirs[1] else ALONG if theirs[0] else
            "round scatter")  # where each scale used comes from
    return out[0], out[1], {**rigid, "used": used,
                            "round_scatter_factors": {"radial": round(fr, 4), "transverse": round(ft, 4)},
                            **({"bounded": "; ".join(bounds)} if bounds else {}),
                            **({"disagreement": text} if text else
                               {"cross_check": f"the round scatter agrees with the mutual distances within "
                                               f"{RIGID_DISAGREE:g}x"
                                               + (" where they determine a scale" if bounds else "") + ": " + (
                                                   "the distances' scale across the beams and the rounds' along "
                                                   "them are used" if theirs[1] else "its law is used")})}


ACROSS = "mutual distances across the beams, round scatter along them"  # _cross_check's "used": the scales' sources
ALONG = "mutual distances along the beams, round scatter across them"


RIGID_DISAGREE = 2.0    # the round scatter's sigma exceeds the mutual distances' by more than this: say so and weight
# by the mutual distances' (a drift shared by a side, or the machine's motion, counts as noise in the rounds; nothing
# makes the rounds scatter less than the noise, and on clean AT960 campaigns the distances' radial factor reads 2-7x
# high on some designs, so a round scatter below the distances' is kept)
RIGID_DETERMINED = 4.0  # a scale is determined by the mutual distances when its 95 % profile interval spans < 4x
RIGID_MIN_PAIRS = 20    # mutual distances (beyond the pairs' own means) the law needs
def _t_consistency(nu: float) -> float:
    """The Student-t (``nu`` dof) maximum-likelihood variance of unit normal data: E[(nu + 1) z^2 / (nu s^2 + z^2)]
    = 1 (Gauss-Hermite), so that a t-fitted scale divided by its root is a normal sigma (0.69 for nu = 4)."""
    x, w = np.polynomial.hermite_e.hermegauss(80)
    w = w / w.sum()
    return float(optimize.brentq(lambda s2: float(np.sum(w * (nu + 1) * x**2 / (nu * s2 + x**2))) - 1.0, 1e-3, 10.0))


T_CONSISTENCY = math.sqrt(_t_consistency(NU))  # a t-fitted sigma over the normal sigma of the same readings
PROFILE_SPAN = 9.0      # log variance factor searched either side of the best for the profile intervals
PROFILE_STEPS = np.r_[np.arange(0.5, PROFILE_SPAN + 0.01, 0.5), np.arange(11.0, 41.0, 2.0)]  # beyond the span
# in coarser steps: a scale whose best is 0 (log -> -inf) still has an upper end
LOG_FLOOR = -30.0       # log variance factor below which a scale counts as nil (its sigma 3e-7 of the law's)
DETRENDS = ("line", "bending")  # what each mutual distance is taken about over the passes (_detrend_design)
BEND_KNOTS = 4          # interior knots of the bending detrend: a cubic regression spline in time


def _detrend_design(tm: np.ndarray, kind: str) -> np.ndarray:
    """Columns (n, p) a pair's distances over its passes (times ``tm``) are taken about: a line in time ("line":
    a side that expands steadily is not noise) or a curve that bends ("bending": a cubic spline with BEND_KNOTS
    evenly spaced interior knots, fewer where the passes are few -- eight passes a column beyond the line's, a
    parabola below that); a constant where the times are not known."""
    n = len(tm)
    if n < 4 or not np.isfinite(tm).all() or np.ptp(tm) <= 0:
        return np.ones((n, 1))
    s = (tm - tm.min()) / np.ptp(tm)
    if kind == "line":
        return np.column_stack([np.ones(n), s])
    knots = min(BEND_KNOTS, (n - 4) // 8)
    if knots < 1:
        return np.column_stack([np.ones(n), s, s * s][:3 if n >= 6 else 2])
    return interpolate.BSpline.design_matrix(s, np.r_[[0.0] * 3, np.linspace(0, 1, knots + 2), [1.0] * 3],
                                             3).toarray()


FRAMEWORK_RANK = 1e-3  # a distance whose derivative (by the readings) lies within this of the others' span adds
# nothing a reading can move independently: it is left out of the pass's set (_framework)


def _framework(X: np.ndarray) -> list[tuple[int, int]]:
    """The pairs of an independent set of distances among the reflectors at ``X`` ((k, 3) mm, their mean
    readings): pair by pair, each kept only where its derivative by the readings (the rigidity matrix's row, +-w on
    its two reflectors) is not within FRAMEWORK_RANK of the span of those kept.  Every distance of the pass then
    follows from these to first order and their covariance is not singular: 3 k - 6 for k >= 3 in general position,
    2 k - 3 where the reflectors lie in a plane, k - 1 on a line (a collinear set, which identify refuses later)."""
    k = len(X)
    rows, pairs = np.zeros((0, 3 * k)), []
    for a, b in itertools.combinations(range(k), 2):
        w = X[a] - X[b]
        row = np.zeros(3 * k)
        row[3 * a:3 * a + 3], row[3 * b:3 * b + 3] = w, -w
        row /= max(float(np.linalg.norm(row)), 1e-300)
        trial = np.vstack([rows, row])
        if np.linalg.svd(trial, compute_uv=False)[-1] > FRAMEWORK_RANK:
            rows, pairs = trial, pairs + [(a, b)]
    return pairs


@dataclass(frozen=True)
class _PassGroup:
    """The passes of one (station, axis) that read the same reflectors: ``idx`` (P, k) reading rows, ``S`` (P, m,
    k, 3) each distance's derivative by each reflector's reading (+-w, w the pair's unit vector), ``D`` (P, m) mm
    the distances, ``F`` {detrend: (P, p)} the columns each distance is taken about (_detrend_design)."""

    idx: np.ndarray
    S: np.ndarray
    D: np.ndarray
    F: dict

    @property
    def count(self) -> int:
        """The distances beyond their detrends' columns."""
        return self.D.size - self.D.shape[1] * max(f.shape[1] for f in self.F.values())


def _pass_groups(rec: Recording) -> list[_PassGroup]:
    """Every pass (station, axis, round, position, direction) of two or more reflectors, grouped by (station, axis,
    reflectors read), groups of three or more passes (the first reading of each reflector in a pass)."""
    keys = list(zip(rec.stations().tolist(), rec.axis.tolist(), rec.round.tolist(),
                    position_key(rec.position).tolist(), rec.direction.tolist()))
    passes: dict = {}
    for i, k in enumerate(keys):
        passes.setdefault(k, {}).setdefault(str(rec.point[i]), i)
    groups: dict = {}
    for (st, ax, *_), pts in passes.items():
        if len(pts) >= 2:
            labels = tuple(sorted(pts))
            groups.setdefault((st, ax, labels), []).append([pts[p] for p in labels])
    out = []
    for rows in groups.values():
        if len(rows) < 3:
            continue
        idx = np.array(rows)
        X = rec.xyz[idx]
        pairs = _framework(X.mean(axis=0))
        S = np.zeros((len(idx), len(pairs), idx.shape[1], 3))
        D = np.empty((len(idx), len(pairs)))
        for j, (a, b) in enumerate(pairs):
            v = X[:, a] - X[:, b]
            D[:, j] = np.linalg.norm(v, axis=1)
            S[:, j, a], S[:, j, b] = v / np.maximum(D[:, j], 1e-12)[:, None], -v / np.maximum(D[:, j], 1e-12)[:, None]
        tm = rec.time_s[idx].mean(axis=1)
        F = {kind: _detrend_design(tm, kind) for kind in DETRENDS}
        if len(idx) > max(f.shape[1] for f in F.values()):
            out.append(_PassGroup(idx, S, D, F))
    return out


class RigidLikelihood:
    """The restricted (REML) negative log-likelihood of the mutual distances within the passes, all of a pass's
    distances jointly: a pass's reflectors are read with independent normal errors e_i of covariance c_r s_r(L_i)^2
    u_i u_i^T + c_t s_t(L_i)^2 (I - u_i u_i^T) (``base``'s sigmas at the reading's distance L_i from the tracker t,
    u_i its beam), so the pass's distances d_p (one minimally rigid set, _framework), d_ab = w_ab . (e_a - e_b) to
    first order about their mean, have the covariance Sigma_p = c_r R_p(t) + c_t T_p(t), R_p = sum_i s_r,i^2 (S_i
    u_i)(S_i u_i)^T, T_p = sum_i s_t,i^2 (S_i S_i^T - (S_i u_i)(S_i u_i)^T) (S_i the distances' derivatives by e_i):
    each distance's variance and the covariance of two sharing a reflector.  The mean of d_p is B^T f_p (each
    distance's detrend, _detrend_design), B estimated by generalised least squares, and the likelihood is the
    restricted one, 1/2 [sum_p log det Sigma_p + sum_p r_p^T Sigma_p^-1 r_p + log det sum_p (f_p f_p^T (x)
    Sigma_p^-1)] (r_p the GLS residual): exact for the detrend's degrees of freedom, whatever the passes' leverage.
    ``v`` = (t (3,) mm, log c_r - log c_t), the common scale at its best (__call__)."""

    def __init__(self, groups: list[_PassGroup], xyz: np.ndarray, kind: str, spec: TrackerSpec = AT960):
        self.groups, self.xyz, self.spec, self.kind = groups, xyz, spec, kind

    def parts(self, t: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]] | None:
        """(R, T) of every group about the tracker ``t`` ((3,) or (n, 3) every reading's own), or None where a
        reading is nearer than 100 mm or farther than MAX_DISTANCE."""
        tt = np.broadcast_to(np.asarray(t, float), self.xyz.shape)
        out = []
        for g in self.groups:
            v = self.xyz[g.idx] - tt[g.idx]
            L = np.linalg.norm(v, axis=2)
            if L.min() < 100.0 or L.max() > MAX_DISTANCE:
                return None
            s_r, s_t = self.spec.sigmas(L)
            A = np.einsum("pmki,pki->pmk", g.S, v / L[..., None])
            AA = np.einsum("pmk,pnk->pmnk", A, A)
            out.append((np.einsum("pmnk,pk->pmn", AA, s_r**2),
                        np.einsum("pmki,pnki,pk->pmn", g.S, g.S, s_t**2) - np.einsum("pmnk,pk->pmn", AA, s_t**2)))
        return out

    @property
    def count(self) -> int:
        """N: the distances beyond their detrends' columns (the restricted likelihood's degrees of freedom)."""
        return sum((len(g.F[self.kind]) - g.F[self.kind].shape[1]) * g.D.shape[1] for g in self.groups)

    def forms(self, parts, w_r: float, w_t: float) -> tuple[float, float] | None:
        """(sum_p r_p^T Sigma_p^-1 r_p, sum_p log det Sigma_p + log det A) at Sigma_p = w_r R_p + w_t T_p (the
        beams' ``parts``), or None where a Sigma_p or A is not positive definite."""
        quad = rest = 0.0
        for (R, T), g in zip(parts, self.groups):
            S = R * w_r + T * w_t
            sign, logdet = np.linalg.slogdet(S)
            if np.any(sign <= 0):
                return None
            Si = np.linalg.inv(S)
            F, D = g.F[self.kind], g.D
            p, m = F.shape[1], D.shape[1]
            FF = (F[:, :, None] * F[:, None, :]).reshape(len(F), p * p)
            A = (FF.T @ Si.reshape(len(F), m * m)).reshape(p, p, m, m).transpose(0, 2, 1, 3).reshape(p * m, p * m)
            b = (F.T @ np.einsum("pab,pb->pa", Si, D)).reshape(-1)
            sa, la = np.linalg.slogdet(A)
            if sa <= 0:
                return None
            r = D - F @ np.linalg.solve(A, b).reshape(p, m)
            quad += float(np.einsum("pa,pab,pb->", r, Si, r))
            rest += float(np.sum(logdet)) + la
        return quad, rest

    def given(self, parts, logs) -> float:
        """The likelihood with the beams' parts (``parts``) fixed and the log scales ``logs``."""
        if parts is None or not np.all(np.isfinite(logs)):
            return math.inf
        qr = self.forms(parts, math.exp(logs[0]), math.exp(logs[1]))
        return math.inf if qr is None else 0.5 * (qr[0] + qr[1])

    def __call__(self, v: np.ndarray) -> float:
        """The likelihood at the station ``v[:3]`` (mm) and the log ratio of the scales ``v[3]``, their common
        scale at its best (_concentrate)."""
        parts = self.parts(v[:3]) if np.all(np.isfinite(v)) else None
        if parts is None:
            return math.inf
        lw = _ratio_weights(float(v[3]))
        return _concentrate(self.forms(parts, *np.exp(lw)), lw, self.count)[0]

    def outlying(self, parts, logs) -> list[np.ndarray]:
        """Per group, the passes whose distances lie beyond the joint law: r_p^T Sigma_p^-1 r_p (r_p about the
        detrend by ordinary least squares) beyond chi^2_m's 1 - OUTLIER_LEVEL / (all passes) quantile."""
        n = sum(len(g.idx) for g in self.groups)
        out = []
        for (R, T), g in zip(parts, self.groups):
            F, D = g.F[self.kind], g.D
            r = D - F @ np.linalg.lstsq(F, D, rcond=None)[0]
            q = np.einsum("pa,pab,pb->p", r, np.linalg.inv(R * math.exp(logs[0]) + T * math.exp(logs[1])), r)
            out.append(q > _tails.chi2_ppf(1.0 - OUTLIER_LEVEL / n, D.shape[1]))
        return out


class FixedBeams:
    """RigidLikelihood.given at fixed beams, each pass's R_p and T_p diagonalised jointly once (W_p^T T_p W_p = I,
    W_p^T R_p W_p = diag(lam_p): Cholesky of T_p, then the eigenvectors of L^-1 R_p L^-T), so that for any scales
    Sigma_p^-1 = W_p diag(1 / (c_r lam_p + c_t)) W_p^T and log det Sigma_p = sum log(c_r lam_p + c_t) + log det T_p:
    the restricted likelihood costs a few products per group.  With z = W^T d and V the rows f_p (x) W_p e_j,
    b = V^T (z / q), A = V^T diag(1 / q) V (q = c_r lam + c_t) and the GLS residual's quadratic form is
    sum z^2 / q - b^T A^-1 b.  ``concentrated``: the common scale c in Sigma = c (w_r R + w_t T) in closed form,
    c = Q / N (Q the quadratic form at c = 1, N the distances beyond the detrends' columns).  ``ok`` is False where
    some T_p is not positive definite (RigidLikelihood.given is then the one to use)."""

    def __init__(self, lik: RigidLikelihood, parts):
        self.lik, self.parts, self.ok, self.terms, self.count = lik, parts, parts is not None, [], lik.count
        if parts is None:
            return
        for (R, T), g in zip(parts, lik.groups):
            try:
                L = np.linalg.cholesky(T)
            except np.linalg.LinAlgError:
                self.ok = False
                return
            Li = np.linalg.inv(L)
            lam, U = np.linalg.eigh(Li @ R @ np.swapaxes(Li, 1, 2))
            W = np.swapaxes(Li, 1, 2) @ U                       # (P, m, m): columns W_p e_j
            F, D = g.F[lik.kind], g.D
            D = D - F @ np.linalg.lstsq(F, D, rcond=None)[0]  # the GLS residual is the same about any fit in F's
            # span; about this one the quadratic forms below hold no large cancelling parts
            z = np.einsum("paj,pa->pj", W, D).reshape(-1)
            V = np.einsum("pi,paj->pjia", F, W).reshape(len(z), -1)  # row (p, j): f_p (x) W_p e_j
            logdet_t = 2.0 * float(np.sum(np.log(np.diagonal(L, axis1=1, axis2=2))))
            self.terms.append((np.maximum(lam.reshape(-1), 0.0), z, V, logdet_t))

    def forms(self, w_r: float, w_t: float) -> tuple[float, float] | None:
        """RigidLikelihood.forms at Sigma = w_r R + w_t T, or None where A is singular."""
        quad = rest = 0.0
        for lam, z, V, logdet_t in self.terms:
            d = 1.0 / (w_r * lam + w_t)
            b = V.T @ (d * z)
            A = (V.T * d) @ V
            sa, la = np.linalg.slogdet(A)
            if sa <= 0:
                return None
            quad += float(np.dot(d, z * z) - b @ np.linalg.solve(A, b))
            rest += float(-np.sum(np.log(d))) + logdet_t + la
        return quad, rest

    def value(self, logs) -> float:
        """The negative log-likelihood at the log scales ``logs`` (log c_r, log c_t), as RigidLikelihood.given."""
        if not self.ok:
            return self.lik.given(self.parts, logs)
        if not np.all(np.isfinite(logs)):
            return math.inf
        qr = self.forms(math.exp(logs[0]), math.exp(logs[1]))
        return math.inf if qr is None else 0.5 * (qr[0] + qr[1])

    def concentrated(self, theta: float) -> tuple[float, np.ndarray]:
        """The likelihood at log c_r - log c_t = ``theta`` with the common scale at its best: (value, log scales)."""
        lw = _ratio_weights(theta)
        if self.ok:
            return _concentrate(self.forms(*np.exp(lw)), lw, self.count)
        return _concentrate(None if self.parts is None else self.lik.forms(self.parts, *np.exp(lw)), lw, self.count)


def _ratio_weights(theta: float) -> np.ndarray:
    """log (w_r, w_t) of the log ratio ``theta`` = log c_r - log c_t, the larger weight 1 (well scaled both ways)."""
    return np.array([min(theta, 0.0), min(-theta, 0.0)])


def _concentrate(forms: tuple[float, float] | None, lw: np.ndarray, count: int) -> tuple[float, np.ndarray]:
    """The restricted likelihood at Sigma = c (w_r R + w_t T) with the common scale c at its best: with Q, K the
    quadratic form and the log determinants at c = 1 (``forms``) and N = ``count``, the likelihood is 1/2 (N log c
    + Q / c + K), least at c = Q / N.  Returns (value, log scales (log c_r, log c_t)); infinite where ``forms`` is
    None or Q is nil."""
    if forms is None or forms[0] <= 0:
        return math.inf, lw
    c = forms[0] / count
    return 0.5 * (count * math.log(c) + count + forms[1]), lw + math.log(c)


OUTLIER_LEVEL = 1e-3  # a pass whose distances the joint law puts beyond this level (Bonferroni over the passes) is
# left out of the law and the station from what is rigid (a reading an effect moved: the replica's 40 um one read
# the radial sigma 1.2-1.5 um where 0.68 was planted)


def _trimmed(groups: list[_PassGroup], xyz: np.ndarray, t: np.ndarray, base: TrackerSpec) -> list[_PassGroup]:
    """``groups`` less their outlying passes (RigidLikelihood.outlying about ``t``, the scales fitted under the
    line), fitted again until none is left out (at most three times)."""
    for _ in range(3):
        lik = RigidLikelihood(groups, xyz, "line", base)
        parts = lik.parts(t)
        if parts is None:
            return groups
        law = _scale_intervals(FixedBeams(lik, parts), intervals=False)
        logs = [max(2 * math.log(max(law[k]["factor"], 1e-300)), LOG_FLOOR) for k in ("radial", "transverse")]
        drop = lik.outlying(parts, logs)
        if not any(d.any() for d in drop):
            return groups
        groups = [_PassGroup(g.idx[~d], g.S[~d], g.D[~d], {k: f[~d] for k, f in g.F.items()})
                  for g, d in zip(groups, drop) if (~d).sum() > max(f.shape[1] for f in g.F.values())]
    return groups


THETA_GRID = np.arange(-40.0, 40.01, 2.0)  # log c_r - log c_t searched for the law's best (_scale_best)


def _scale_best(fb: FixedBeams) -> tuple[np.ndarray, float]:
    """The law's two log scales by maximum likelihood on fixed beams: the common scale in closed form
    (FixedBeams.concentrated), their log ratio over THETA_GRID and refined about the grid's best (bounded Brent);
    a scale below LOG_FLOOR is nil.  Returns (log scales, negative log-likelihood there)."""
    theta = THETA_GRID[int(np.argmin([fb.concentrated(x)[0] for x in THETA_GRID]))]
    o = optimize.minimize_scalar(lambda x: fb.concentrated(x)[0], bounds=(theta - 2.0, theta + 2.0),
                                 method="bounded", options={"xatol": 1e-5})
    logs = np.maximum(fb.concentrated(float(o.x))[1], LOG_FLOOR)
    return logs, fb.value(logs)


def _scale_intervals(fb: FixedBeams, intervals: bool = True) -> dict:
    """The law's two scales by maximum likelihood on the fixed beams ``fb`` (_scale_best), each with its 95 %
    profile interval (chi^2, 1 dof; the other scale at its best), as sigma factors: {"radial", "transverse":
    {"factor", "interval_95", "determined"}}."""
    def f(v):  # a scale below exp(LOG_FLOOR) is nil: the likelihood is flat there
        return fb.value(np.maximum(np.asarray(v, float), LOG_FLOOR))
    best, f_best = _scale_best(fb)
    if not intervals:
        return {name: {"factor": math.exp(0.5 * best[k])} for k, name in enumerate(("radial", "transverse"))}
    out = {}
    for k, name in enumerate(("radial", "transverse")):
        def prof(g, k=k):  # 2 x the profile negative log-likelihood over its best, the other scale at its best
            o = optimize.minimize_scalar(lambda x: f([g, x] if k == 0 else [x, g]),
                                         bounds=(best[1 - k] - PROFILE_SPAN, best[1 - k] + PROFILE_SPAN),
                                         method="bounded", options={"xatol": 1e-4})
            return 2.0 * (o.fun - f_best) - _tails.chi2_ppf(0.95, 1)
        ends = []
        for sign in (-1.0, 1.0):
            inside, g, at = best[k], None, [-_tails.chi2_ppf(0.95, 1), None]  # prof's values at inside and g
            for h in PROFILE_STEPS:
                v = prof(best[k] + sign * h)
                if v > 0:
                    g, at[1] = best[k] + sign * h, v
                    break
                inside, at[0] = best[k] + sign * h, v
            ends.append(None if g is None else _profile_end(prof, inside, g, *at))
        lo, hi = ends
        out[name] = {"factor": math.exp(0.5 * best[k]), "interval_95": [lo, hi],
                     "determined": bool(lo is not None and hi is not None and hi / lo < RIGID_DETERMINED)}
    return out


def _profile_end(prof, inside: float, outside: float, a: float, b: float) -> float | None:
    """The sigma factor where the profile ``prof`` (of a log scale) crosses zero between ``inside`` and
    ``outside`` (``a``, ``b``: its values there), or None (that end not known) where it cannot be bracketed there:
    the restricted likelihood's A is indefinite by rounding at scales here and there when the pass's transverse
    covariance is singular, and its profile is then infinite or not a number beside finite values (gen2 3690/3
    stopped the diagnosis with a ValueError).  An end not known leaves the scale not determined."""
    if not (math.isfinite(a) and math.isfinite(b) and a <= 0 < b):
        return None
    try:
        return math.exp(0.5 * optimize.brentq(prof, inside, outside, xtol=1e-3))
    except (ValueError, RuntimeError):  # a value not a number met inside the bracket
        return None


def _within(x: float, interval: list) -> bool:
    lo, hi = interval
    return (lo is None or x >= lo) and (hi is None or x <= hi)


def rigid_law(rec: Recording, t: np.ndarray, base: TrackerSpec = AT960) -> dict | None:
    """The tracker's noise law from what is rigid: within one pass (one pose of one axis) the reflectors sit on one
    rigid side, so their mutual distances are the same in every pass up to the tracker's noise -- blind to any
    motion of the side (a drift shared by it, the machine's own motion), unlike the scatter of the rounds.  All the
    distances of a pass jointly (RigidLikelihood: each one's variance and the covariance of two sharing a
    reflector, from the law and the beams from ``t`` (mm, (3,) or (n, 3))), each pair's distances taken about a
    line in time and, separately, about a curve that bends (_detrend_design); c_r, c_t by maximum likelihood, each
    with its 95 % profile-likelihood interval (chi^2, 1 dof).  A scale is determined where, under both detrends,
    its interval spans less than RIGID_DETERMINED and each detrend's estimate lies in the other's interval: a scale
    the detrend changes is what the detrend leaves, not the tracker's noise.  The interval stated is the hull of
    the two.  None when there are fewer than RIGID_MIN_PAIRS distances.  Returns {"radial", "transverse":
    {"factor" (the line's), "interval_95", "determined", "sigma_um", "upper_um", "by_detrend"}, "distances",
    "at_distance_m"} (factors against ``base``, sigmas um at the median distance)."""
    tt = np.broadcast_to(np.asarray(t, float), rec.xyz.shape)
    groups = _trimmed(_pass_groups(rec), rec.xyz, tt, base)
    n = sum(g.count for g in groups)
    if n < RIGID_MIN_PAIRS:
        return None
    fits = {}
    for kind in DETRENDS:
        lik = RigidLikelihood(groups, rec.xyz, kind, base)
        parts = lik.parts(tt)
        if parts is None:
            return None
        fits[kind] = _scale_intervals(FixedBeams(lik, parts))
    dist_m = float(np.median(np.linalg.norm(rec.xyz - tt, axis=1))) / 1e3
    s_r0, s_t0 = (float(s) * 1e3 for s in base.sigmas(dist_m * 1e3))
    out = {"distances": int(n), "at_distance_m": round(dist_m, 3),
           "detrends": "each distance about a line in time and about a cubic spline that bends; determined where "
                       "they agree (rigid_law)"}
    for name, s0 in (("radial", s_r0), ("transverse", s_t0)):
        a, b = fits["line"][name], fits["bending"][name]
        los, his = [a["interval_95"][0], b["interval_95"][0]], [a["interval_95"][1], b["interval_95"][1]]
        lo = None if None in los else min(los)
        hi = None if None in his else max(his)
        det = a["determined"] and b["determined"] and _within(a["factor"], b["interval_95"]) and \
            _within(b["factor"], a["interval_95"])
        out[name] = {"factor": a["factor"], "interval_95": [lo, hi], "determined": bool(det),
                     "sigma_um": round(a["factor"] * s0, 3), "upper_um": None if hi is None else round(hi * s0, 3),
                     "by_detrend": {k: {"factor": round(v[name]["factor"], 4),
                                        "interval_95": [None if x is None else round(x, 4)
                                                        for x in v[name]["interval_95"]]}
                                    for k, v in fits.items()}}
    return out


def _profile_point(f, x: np.ndarray) -> optimize.OptimizeResult:
    """The minimum of ``f`` (a profile's negative log-likelihood: two tilts and the log scales) from ``x``: BFGS on
    finite differences (smooth there, about a fifth of Nelder-Mead's evaluations for the same values on the demo
    campaign), Nelder-Mead where BFGS ends on no finite value from a finite start (a step into the region too near
    the readings or too far from them, where the likelihood is infinite); an infinite start stays infinite."""
    with np.errstate(invalid="ignore", over="ignore"):  # steps into the infinite region are no fault
        res = optimize.minimize(f, x, method="BFGS", options={"gtol": 1e-3})
        if not (math.isfinite(res.fun) and np.all(np.isfinite(res.x))) and math.isfinite(f(x)):
            res = optimize.minimize(f, x, method="Nelder-Mead", options={"xatol": 1e-3, "fatol": 1e-2,
                                                                          "maxiter": 300})
    return res


STATION_GRID = np.geomspace(300.0, MAX_DISTANCE, 17)  # mm from the readings' centre: the profile's distances
STATION_DETERMINED = 2.0  # the station is determined when its distance's 95 % interval spans less than 2x


def _distance_profile(f, c: np.ndarray, t: np.ndarray, x0: np.ndarray, f_best: float) -> list[tuple[float, float]]:
    """2 (nll - best) of ``f`` (of a trial station (3,) mm and the rest of its parameters) at every distance s of
    STATION_GRID from ``c`` (mm), the direction tilted from c -> ``t`` and the rest re-fitted (_profile_point; from
    the estimate outwards both ways, each distance from the previous one's optimum), and at ``t`` itself (``x0``
    the rest's start there, ``f_best`` f's value there), sorted by distance; the best over them all is 0."""
    d0 = np.asarray(t, float) - c
    s0 = float(np.linalg.norm(d0))
    u0 = d0 / s0
    a, b = np.linalg.svd(u0[None])[2][1:]  # two unit vectors across u0 (their signs do not matter here)

    def at(s, v):  # position at distance s along the direction tilted by v[:2] (across u0)
        u = u0 + v[0] * a + v[1] * b
        return c + s * u / np.linalg.norm(u)

    prof, best = [], f_best
    for way in (STATION_GRID[STATION_GRID < s0][::-1], STATION_GRID[STATION_GRID >= s0]):
        x = np.array([0.0, 0.0, *x0])  # from the estimate outwards, each distance from the previous one's
        for s in way:  # optimum (the profile is continuous; from the grid's near end a chain strays into
            # another basin of the tilts and scales and reads the profile thousands too high)
            res = _profile_point(lambda v, s=s: f(at(s, v[:2]), v[2:]), x)
            prof.append((float(s), float(res.fun)))
            best = min(best, float(res.fun))
            if math.isfinite(res.fun):
                x = res.x
    return sorted((s, 2.0 * (v - best)) for s, v in prof + [(s0, f_best)])


def _profile_set(prof: list[tuple[float, float]]) -> tuple[list[float] | None, bool]:
    """The 95 % set of a distance profile (_distance_profile): every s within chi^2_1(0.95) of the best, to the
    grid's distances either side of them (the grid is coarser than a sharp profile); (interval or None where it
    is not one piece, determined: one piece inside the grid and the search's bounds, spanning less than
    STATION_DETERMINED)."""
    ok = np.array([v <= _tails.chi2_ppf(0.95, 1) for _, v in prof])
    idx = np.flatnonzero(ok)
    piece = bool(idx.size and np.all(np.diff(idx) == 1))
    if not piece:
        return None, False
    ends = (max(idx[0] - 1, 0), min(idx[-1] + 1, len(prof) - 1))
    lo, hi = prof[ends[0]][0], prof[ends[1]][0]
    # an end where the likelihood is infinite is the search's bound (MAX_DISTANCE, 100 mm of a reading), not the
    # data's: the set may go on beyond it
    det = idx[0] > 0 and idx[-1] < len(prof) - 1 and hi / lo < STATION_DETERMINED and all(
        math.isfinite(prof[i][1]) for i in ends)
    return [lo, hi], bool(det)


RIGID_STARTS = np.array([v for v in itertools.product((-1.0, 0.0, 1.0), repeat=3) if sum(map(abs, v)) in (1, 3)])
RIGID_STARTS = RIGID_STARTS / np.linalg.norm(RIGID_STARTS, axis=1)[:, None]  # the 14 directions of a cube's faces
# and corners (none more than 55 deg from the tracker's): where the station from what is rigid is looked for beside
# the rounds' estimate (_rigid_best)


def _rigid_best(lik: RigidLikelihood, c: np.ndarray, v: np.ndarray, f_v: float, scale: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, float]:
    """The best station of the mutual distances' likelihood ``lik``: the local best ``v`` (position mm, the log
    ratio of the scales; ``f_v`` its value) found from the rounds' estimate, against local searches from
    START_DISTANCE (or v's distance, if farther) from the readings' centre ``c`` along each of RIGID_STARTS (the
    ratio from v's).
    The profile of the distance is then taken about it: about the rounds' estimate, its direction held near theirs,
    it reads the distance in a direction the distances reject (the icelinker replica: the rounds' station 86 deg
    from the tracker's as seen from the readings, the profile 4-30 m where the tracker stood 2.84 m away).
    Returns (position, log ratio, value)."""
    best, f_best = v, f_v
    d = max(START_DISTANCE, float(np.linalg.norm(v[:3] - c)))
    for u in RIGID_STARTS:
        start = np.append(c + d * u, v[3:])
        res = _profile_point(lambda w, s=start: lik(s + w * scale), np.zeros(len(start)))
        if math.isfinite(res.fun) and res.fun < f_best:
            best, f_best = start + res.x * scale, float(res.fun)
    return best[:3], best[3:], f_best


def rigid_station(rec: Recording, t: np.ndarray, base: TrackerSpec = AT960) -> dict | None:
    """Whether the reflectors' mutual distances allow the station ``t`` (mm), and where they put it: under
    RigidLikelihood with the bending detrend (a spline holds a line: valid whether or not the distances bend; under
    a line, icelinker's bend pushed the station out to 12.7-30 m), the likelihood-ratio test of the station t
    (chi^2, 3 dof) against the best the distances reach from it (t and both scales free; a local best, so the
    test leans to agreement); where it rejects at LR_LEVEL, the profile likelihood of the station's distance from
    the readings' centre (_distance_profile: the direction and both scales re-fitted) and its 95 % set
    (_profile_set).  No rigid motion of a side moves a mutual distance, so a shared motion that the rounds'
    scatter counts as noise places nothing here.  None where there are fewer than RIGID_MIN_PAIRS distances.
    Returns {"likelihood_ratio", "p", and where it rejects "interval_95_mm", "determined", "profile"} (mm)."""
    t = np.asarray(t, float)
    groups = _trimmed(_pass_groups(rec), rec.xyz, t, base)
    if sum(g.count for g in groups) < RIGID_MIN_PAIRS:
        return None
    lik = RigidLikelihood(groups, rec.xyz, "bending", base)
    parts = lik.parts(t)
    if parts is None:
        return None
    x0, f_t = _scale_best(FixedBeams(lik, parts))
    theta = np.array([x0[0] - x0[1]])
    scale = np.array([100.0, 100.0, 100.0, 1.0])  # mm, log: the local search in comparable steps
    res = _profile_point(lambda v: lik(np.append(t, theta) + v * scale), np.zeros(4))
    lr = max(2.0 * (f_t - min(float(res.fun), f_t)), 0.0)
    out = {"likelihood_ratio": round(float(lr), 2), "p": float(_tails.chi2_sf(lr, 3))}
    if out["p"] >= LR_LEVEL:
        return out
    c = rec.xyz.mean(axis=0)
    q, x, f_q = _rigid_best(lik, c, np.append(t, theta) + res.x * scale, float(res.fun), scale)
    prof = _distance_profile(lambda q, v: lik(np.append(q, v)), c, q, x, f_q)
    interval, det = _profile_set(prof)
    return {**out, "interval_95_mm": interval, "determined": det,
            "profile": [[round(s, 1), round(v, 2)] for s, v in prof]}


def station_interval(xyz: np.ndarray, r: np.ndarray, t: np.ndarray, logs: np.ndarray, nll_best: float,
                     spec: TrackerSpec = AT960, rec: Recording | None = None) -> dict:
    """How far the data fix the station's distance from the readings' centre.  The scatter ``r``: its profile
    likelihood (nll, the data's shape free; _distance_profile about the estimate ``t``) and the 95 % set of it
    (_profile_set); it is "not determined" when that set reaches the grid's ends or the search's bounds, spans
    STATION_DETERMINED or more, or is not one piece (no interval then): the station found is one of several the
    data allow.  A curvature sigma (the Hessian) says nothing of either.  With ``rec`` (the readings' recording),
    the mutual distances as well (rigid_station): where they reject the estimate (their test), the scatter that
    placed it holds what is not the tracker's noise (a motion shared by a side) -- the interval stated is the
    distances' (none where their profile is not one piece), not determined, and said; where they allow it,
    nothing changes.
    Returns {"distance_mm", "interval_95_mm", "determined", "profile": [[s mm, 2 (nll -
    best)], ...], "note", "mutual_distances", "scatter"} (mm)."""
    c = xyz.mean(axis=0)
    s0 = float(np.linalg.norm(np.asarray(t, float) - c))
    lik = Likelihood(xyz, r, spec)
    prof = _distance_profile(lambda q, v: lik(np.append(q, v)), c, np.asarray(t, float), np.asarray(logs, float),
                             nll_best)
    interval, det = _profile_set(prof)
    lo, hi = interval if interval else (s0, s0)
    out = {"distance_mm": s0, "interval_95_mm": interval, "determined": det,
           "profile": [[round(s, 1), round(v, 2)] for s, v in prof]}
    if not det:
        out["note"] = (f"the station is not determined by the scatter: its distance's profile likelihood is "
                       f"{'flat' if interval else 'many-moded'} over {lo / 1e3:.3g}-{hi / 1e3:.3g} m from the "
                       f"readings (the estimate, {s0 / 1e3:.3g} m, is one of the stations the data allow); the "
                       "weights, and the findings that depend on them, are conditional on it: give the tracker's "
                       "position (--tracker or the tracker_x,y,z columns)")
    rigid = None if rec is None else rigid_station(rec, np.asarray(t, float), spec)
    if rigid is None:
        return out
    out["mutual_distances"] = {k: v for k, v in rigid.items() if k != "profile"}
    if rigid["p"] >= LR_LEVEL:
        return out
    iv = rigid.get("interval_95_mm")
    where = (f"put it {iv[0] / 1e3:.3g}-{iv[1] / 1e3:.3g} m from the readings" if iv else
             "leave its distance many-moded")
    out.update(scatter={"interval_95_mm": interval, "determined": det}, interval_95_mm=iv, determined=False,
               note=f"the station is not determined: the reflectors' mutual distances, which no motion of a side "
                    f"moves, reject the estimate {s0 / 1e3:.3g} m from the readings (likelihood ratio "
                    f"{rigid['likelihood_ratio']:.1f}, p = {rigid['p']:.2g}) and {where}, the scatter of the "
                    f"rounds {'-'.join(f'{v / 1e3:.3g}' for v in (interval or [lo, hi]))} m: the rounds hold a "
                    "motion shared by a side, not only the tracker's noise; the weights, and the findings that "
                    "depend on them, are conditional on it: give the tracker's position (--tracker or the "
                    "tracker_x,y,z columns)")
    return out
