"""Three-point identification of the error motions of each axis from laser-tracker recordings (Zhang & Hu).

For every pass (axis, round, position, direction) the readings of the points P, Q, K (>= 3 non-collinear
reflectors; on the spindle for X, Y, Z, on the table for B, C) are compared with where the nominal machine
motion takes each point's reference reading (the round's reading at the position closest to zero, the first
time it is approached); the differences, expressed in the axis' own frame (derive/threepoint.py: B's stator
frame is tilted 45 deg), give the six error motions E_XJ, E_YJ, E_ZJ (mm) and E_AJ, E_BJ, E_CJ (rad) by least
squares over all 3 n equations (weighted by the AT960 covariance when the tracker position is known).  Passes of
one round at one position are averaged; rounds give the Type A statistics (thesis eqs. 2.45-2.49); reference
straight lines give squareness (mtcal.identify.fitting); continuous functions make the error model
(mtcal.model.errormodel).

Assumptions: readings are in the machine frame (mm); the axes not measured stand at zero (only matters for the
rotary axes: B is measured at C = 0, C at B = 0); errors are zero at the reference position.
"""
from __future__ import annotations

import logging
import warnings as _warnings
from dataclasses import dataclass, field, replace
from typing import Iterable

import numpy as np

from mtcal.identify import fitting
from mtcal.measurement import tracker as trk
from mtcal.identify.compare import split_half_worth
from mtcal.errors import InputError
from mtcal.generated import threepoint_numpy as tp
from mtcal.io import read_text
from mtcal.kinematics.machine import DEFAULT_MACHINE, Machine, load_machine
from mtcal.model.errormodel import ErrorFunction, ErrorModel
from mtcal.measurement.recordings import Recording
from mtcal.measurement.tracker_position import LR_LEVEL, PositionEstimate, estimate_position

PARTS = ("X", "Y", "Z", "A", "B", "C")  # E_<part><axis>
log = logging.getLogger(__name__)
MIN_SHAPE = 1e-3  # point_shape below this: points (nearly) collinear, rotation about their line unobservable
MAX_DEVIATION_MM = 1.0  # a reading this far from the nominal motion is a unit / frame / axis mix-up, not an error
METHODS = ("auto", "three-point", "joint")
METHOD_TEXT = {"three-point": "three-point (Zhang & Hu), least squares over all equations",
               "joint": "joint weighted fit of all readings and stations (error motions, reflectors, station "
                        "alignments; mtcal.identify.joint)"}


def error_names(axis: str) -> tuple[str, ...]:
    """ISO 230-1 names of the six error motions of an axis, in solution order."""
    return tuple(f"E_{p}{axis}" for p in PARTS)


# ----------------------------------------------------------------------------- one position
def solve_frame(points, deltas, cov=None) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Least-squares three-point solution in the axis frame F, vectorised over leading dimensions.

    points (..., n, 3) mm: nominal reflector positions in F; deltas (..., n, 3) mm: measured minus nominal in F;
    cov (..., n, 3, 3) mm^2: covariance of each delta (None: unweighted).  Returns (errors (..., 6) as
    (E_X, E_Y, E_Z mm, E_A, E_B, E_C rad), residuals (..., 3 n) mm (unweighted, measured - fitted),
    covariance of the errors (..., 6, 6) when ``cov`` is given, else None).  Three points unweighted use the
    generated centred closed form; otherwise the whitened system from the generated rows is solved by QR.
    """
    p = np.asarray(points, dtype=float)
    d = np.asarray(deltas, dtype=float)
    n = p.shape[-2]
    if n < 3:
        raise InputError(f"three-point identification needs >= 3 points, got {n}")
    lead = np.broadcast_shapes(p.shape[:-2], d.shape[:-2])
    if cov is None and n == 3:
        pf, df = p.reshape(*p.shape[:-2], 9), d.reshape(*d.shape[:-2], 9)
        return tp.ls_solve(pf, df), tp.ls_residuals(pf, df), None
    a = tp.point_rows(p)  # (..., n, 3, 6)
    a = np.broadcast_to(a, lead + a.shape[-3:])
    d = np.broadcast_to(d, lead + d.shape[-2:])
    if cov is None:
        aw, bw = a, d
    else:
        chol = np.linalg.cholesky(np.asarray(cov, dtype=float))
        aw = np.linalg.solve(chol, a)
        bw = np.linalg.solve(chol, d[..., None])[..., 0]
    aw = aw.reshape(*lead, 3 * n, 6)
    bw = bw.reshape(*lead, 3 * n)
    q, r = np.linalg.qr(aw)
    e = np.linalg.solve(r, np.einsum("...ki,...k->...i", q, bw)[..., None])[..., 0]
    resid = (d - np.einsum("...kij,...j->...ki", a, e)).reshape(*lead, 3 * n)
    ce = None
    if cov is not None:
        rinv = np.linalg.inv(r)
        ce = rinv @ np.swapaxes(rinv, -1, -2)
    return e, resid, ce


def _axes_vector(machine: Machine, axis: str, position) -> np.ndarray:
    """Axis positions (..., n_axes) with ``axis`` at ``position`` and the others at zero."""
    return machine.axis_vector({axis: position})


def frame_data(machine: Machine, axis: str, axes, axes0, readings, reference):
    """Nominal points and deltas in the axis frame F (see ``identify_position``); axes, axes0 (..., n_axes): all
    axis positions at the reading and at the reference reading.  Returns (points_F (..., n, 3), deltas_F
    (..., n, 3), R_F (..., 3, 3), deltas in the machine frame (..., n, 3), R_rel (..., 3, 3): how the part turned
    from the reference position, which carries the reference reading's noise into the nominal point)."""
    q, q0 = np.asarray(axes, dtype=float), np.asarray(axes0, dtype=float)
    t0, r0 = machine.rigid_motion(axis, q0)
    tq, rq = machine.rigid_motion(axis, q)
    m = np.asarray(readings, dtype=float)
    m0 = np.asarray(reference, dtype=float)
    w = np.einsum("...ji,...nj->...ni", r0, m0 - t0[..., None, :])  # R0^T (m0 - t0): point in its own part
    nominal = np.einsum("...ij,...nj->...ni", rq, w) + tq[..., None, :]
    rf, of = machine.axis_frame(axis, q)
    d_m = m - nominal
    pts = np.einsum("...ji,...nj->...ni", rf, nominal - of[..., None, :])
    dls = np.einsum("...ji,...nj->...ni", rf, d_m)
    return pts, dls, rf, d_m, rq @ np.swapaxes(r0, -1, -2)


def delta_covariance(readings, reference, r_rel, r_f, tracker, parts: bool = False, spec: trk.TrackerSpec = trk.AT960):
    """Covariance (..., n, 3, 3) mm^2 in F of delta = reading - (R_rel (reference - t0) + t), tracker noise model
    ``spec`` (AT960); with ``parts`` the pair (reading's share, reference reading's share)."""
    c0 = np.einsum("...ij,...njk,...lk->...nil", r_rel, trk.covariance(reference, tracker, spec), r_rel)
    c1 = trk.covariance(readings, tracker, spec)
    to_f = lambda c: np.einsum("...ki,...nkl,...lj->...nij", r_f, c, r_f)  # noqa: E731
    return (to_f(c1), to_f(c0)) if parts else to_f(c1 + c0)


def estimate(machine: Machine, axis: str, axes, axes0, readings, reference, tracker=None,
             spec: trk.TrackerSpec = trk.AT960) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """The three-point estimator (used by identify and plan): the six error motions of ``axis`` (..., 6) from
    readings (..., n, 3) at axis positions ``axes`` (..., n_axes) and their reference readings (..., n, 3) at
    ``axes0``; weighted by the tracker covariance when ``tracker`` (3,) mm is given.  Returns (errors,
    residuals (..., 3 n), covariance (..., 6, 6) or None), as ``solve_frame``."""
    pts, dls, rf, _, rrel = frame_data(machine, axis, axes, axes0, readings, reference)
    cov = None
    if tracker is not None:
        cov = delta_covariance(readings, reference, rrel, rf, np.asarray(tracker, dtype=float).reshape(3), spec=spec)
    return solve_frame(pts, dls, cov)


@dataclass
class PositionResult:
    errors: np.ndarray  # (..., 6) E_X, E_Y, E_Z mm; E_A, E_B, E_C rad
    residuals: np.ndarray  # (..., 3 n) mm
    covariance: np.ndarray | None  # (..., 6, 6) with a tracker position
    names: tuple[str, ...]

    @property
    def residual_rms(self) -> np.ndarray:
        return np.sqrt(np.mean(self.residuals**2, axis=-1))

    def as_dict(self) -> dict[str, np.ndarray]:
        return {n: self.errors[..., i] for i, n in enumerate(self.names)}


def identify_position(axis: str, position, readings, reference, reference_position=0.0, tracker=None,
                      machine: str | Machine = DEFAULT_MACHINE) -> PositionResult:
    """The six error motions of ``axis`` at ``position`` (mm or deg; vectorised over leading dimensions).

    readings (..., n, 3) mm: the n points measured at ``position``; reference (..., n, 3) mm: the same points
    measured at ``reference_position`` (where the errors are zero by definition); machine frame.  tracker (3,)
    mm: tracker position in the machine frame; when given, the least squares is weighted by the AT960
    covariance of reading and reference reading, and the errors' covariance is returned.
    """
    m = machine if isinstance(machine, Machine) else load_machine(machine)
    e, r, ce = estimate(m, axis, _axes_vector(m, axis, position), _axes_vector(m, axis, reference_position),
                        readings, reference, tracker)
    return PositionResult(e, r, ce, m.error_motions(axis))


# ----------------------------------------------------------------------------- a recording
@dataclass
class AxisResult:
    """Identified errors of one axis.  ``per_round`` (n_rounds, n_positions, 6), NaN where a round lacks a
    position; statistics over rounds (Type A): mean, std (experimental, eq. 2.47), std_mean (eq. 2.49)."""

    axis: str
    positions: np.ndarray
    rounds: np.ndarray
    points: tuple[str, ...]
    per_round: np.ndarray
    residual_rms: np.ndarray  # (n_positions,) mm, over all passes
    sigma_pred: np.ndarray  # (n_positions, 6): predicted std of one round's value (noise model or residuals)
    names: tuple[str, ...]
    reference_position: float
    weighted: bool
    lines: dict[str, dict] = field(default_factory=dict)  # reference straight lines of straightness errors
    reversal: np.ndarray | None = None  # (n_positions, 6): mean over rounds of (+ pass) - (- pass), if bidirectional
    fits: dict[str, dict] = field(default_factory=dict)
    covariance: np.ndarray | None = None  # (n_positions * 6, n_positions * 6) of the joint fit's estimate, else None
    # the data's precision relative to ``covariance`` (joint fit: min(1, Birge ratio^2)): the functions are sized by
    # the scatter the readings show, not by the noise law assumed (noise-free readings give the truth back)
    fit_variance_factor: float = 1.0

    @property
    def n(self) -> np.ndarray:
        return np.isfinite(self.per_round[..., 0]).sum(axis=0)

    @property
    def mean(self) -> np.ndarray:
        return np.nanmean(self.per_round, axis=0)

    @property
    def std(self) -> np.ndarray:
        n = self.n[:, None]
        dev = np.where(np.isfinite(self.per_round), self.per_round - self.mean, 0.0)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(n >= 2, np.sqrt((dev**2).sum(axis=0) / (n - 1)), np.nan)

    @property
    def std_mean(self) -> np.ndarray:
        """Type A over rounds (eq. 2.49); for the joint fit its covariance (Birge-scaled), since its rounds may come
        from stations of different precision and share the reflectors' and alignments' estimate."""
        if self.covariance is not None:
            return np.sqrt(np.diagonal(self.covariance).reshape(len(self.positions), 6))
        return self.std / np.sqrt(self.n[:, None])

    def values(self, name: str, corrected: bool = True) -> np.ndarray:
        """Mean per position of one error; straightness with its reference-line slope removed if ``corrected``."""
        v = self.mean[:, self.names.index(name)]
        if corrected and name in self.lines:
            v = v - self.lines[name]["slope"] * self.positions
        return v

    def to_json(self) -> dict:
        mean, std, sm = self.mean, self.std, self.std_mean
        return {"positions": self.positions.tolist(), "rounds": self.rounds.tolist(), "points": list(self.points),
                "reference_position": self.reference_position, "n": self.n.tolist(),
                "errors": {nm: {"mean": mean[:, i].tolist(), "std": std[:, i].tolist(), "std_mean": sm[:, i].tolist()}
                           for i, nm in enumerate(self.names)},
                "residual_rms": self.residual_rms.tolist(),
                "reference_lines": self.lines, "fits": self.fits,
                **({} if self.reversal is None else
                   {"reversal": {nm: self.reversal[:, i].tolist() for i, nm in enumerate(self.names)}})}


@dataclass
class IdentifyResult:
    axes: dict[str, AxisResult]
    squareness: dict[str, float]
    model: ErrorModel
    warnings: list[str]
    reference: str
    weighted: bool
    source: str
    squareness_stats: dict = field(default_factory=dict)  # Type A over rounds: {name: {rounds, std, std_mean}}
    method: str = "three-point"
    joint: dict | None = None  # joint fit: stations (tracker, alignment), reflectors, chi2, dof (JointResult.summary)

    def to_json(self) -> dict:
        return {"source": self.source, "method": self.method, **({"joint": self.joint} if self.joint else {}),
                "units": {"length": "mm", "angle": "rad", "position": "mm or deg"},
                "weighted": self.weighted, "reference": self.reference,
                "axes": {a: r.to_json() for a, r in self.axes.items()},
                "squareness": self.squareness, "squareness_type_a": self.squareness_stats,
                "squareness_convention": fitting.SQUARENESS_CONVENTION,
                **{k: self.model.meta[k] for k in ("tracker_estimated",) if k in self.model.meta},
                "warnings": self.warnings}


def _lines(rec: Recording, idx: Iterable[int]) -> str:
    ls = sorted(int(rec.line[i]) for i in idx)
    return ", ".join(map(str, ls[:6])) + (" ..." if len(ls) > 6 else "")


def _order_points(labels: Iterable[str]) -> tuple[str, ...]:
    labels = sorted(set(labels))
    if set(labels) == {"P", "Q", "K"}:
        return ("P", "Q", "K")
    return tuple(labels)


def _passes(rec: Recording, axis: str):
    """Group one axis' rows into passes; check completeness.  Returns dict with arrays per pass."""
    idx = np.flatnonzero(rec.axis == axis)
    points = _order_points(rec.point[idx])
    if len(points) < 3:
        raise InputError(f"{rec.source}: axis {axis} has only {len(points)} point label(s) {[str(p) for p in points]} "
                         f"(lines {_lines(rec, idx)}); the three-point method needs >= 3 (P, Q, K)")
    at = np.unique(np.round(rec.position[idx], 6))
    if len(at) < 2:
        raise InputError(f"{rec.source}: axis {axis} is measured at one position only ({at[0]:g}"
                         f", lines {_lines(rec, idx)}): its errors are relative to the reference position, so an "
                         f"axis needs two or more positions")
    has_time = np.isfinite(rec.time_s[idx]).all()
    order_key = rec.time_s if has_time else rec.line.astype(float)
    pos_key = np.round(rec.position[idx], 6)
    groups: dict[tuple, dict[str, int]] = {}
    for i, pk in zip(idx, pos_key):
        key = (int(rec.round[i]), float(pk), int(rec.direction[i]))
        g = groups.setdefault(key, {})
        pt = str(rec.point[i])
        if pt in g:
            j = g[pt]
            raise InputError(f"{rec.where(i)}: point {pt} measured again at axis {axis}, round {key[0]}, position "
                             f"{key[1]:g}, direction {key[2]:+d} (first at line {int(rec.line[j])}); repeated readings "
                             f"of one pass are not averaged silently: remove one or give it its own round")
        g[pt] = i
    rounds = np.array(sorted({k[0] for k in groups}))
    refs = {}
    for r in rounds:
        ri = idx[rec.round[idx] == r]
        q0 = float(np.round(rec.position[ri][np.argmin(np.abs(rec.position[ri]))], 6))
        cand = [k for k in groups if k[0] == r and k[1] == q0]
        first = {}
        for pt in points:
            rows = [groups[k][pt] for k in cand if pt in groups[k]]
            if not rows:
                raise InputError(f"{rec.source}: axis {axis}, round {r}: point {pt} has no reading at the reference "
                                 f"position {q0:g} (lines {_lines(rec, ri)})")
            first[pt] = min(rows, key=lambda i: order_key[i])
        refs[int(r)] = (q0, first)
    keys = sorted(groups)
    for k in keys:
        g = groups[k]
        missing = [pt for pt in points if pt not in g]
        if missing:
            raise InputError(f"{rec.source}: axis {axis}, round {k[0]}, position {k[1]:g}"
                             f"{'' if k[2] == 0 else f', direction {k[2]:+d}'}: point(s) {missing} missing "
                             f"(present: lines {_lines(rec, g.values())}); every pass needs all of {list(points)}")
    rows = np.array([[groups[k][pt] for pt in points] for k in keys])  # (n_pass, n_pts)
    ref_rows = np.array([[refs[k[0]][1][pt] for pt in points] for k in keys])
    return {"points": points, "keys": keys, "rows": rows, "ref_rows": ref_rows, "rounds": rounds,
            "round": np.array([k[0] for k in keys]), "position": np.array([k[1] for k in keys]),
            "q0": np.array([refs[k[0]][0] for k in keys])}


def identify(rec: Recording, tracker=None, machine: str | Machine = DEFAULT_MACHINE, reference: str = "least-squares",
             outlier_k: float = 5.0, max_degree: int = 7, max_harmonics: int = 6,
             max_deviation_mm: float = MAX_DEVIATION_MM, method: str = "auto", worth: bool = True) -> IdentifyResult:
    """Identify every axis in a recording; see the module docstring.  tracker: (3,) mm or None (unweighted);
    reference: reference straight line method (mtcal.identify.fitting.REFERENCE_METHODS); outlier_k: a round whose value
    differs from the mean of the other rounds by more than k predicted sigma is reported in ``warnings``;
    method: "three-point" (per position, this module), "joint" (one weighted fit of all readings of all
    stations, mtcal.identify.joint) or "auto" (joint when the tracker position is known or can be estimated from
    the scatter of the rounds, ``estimate_station``; else three-point, with a warning); worth: also run the
    estimator on two halves of the rounds to state the model's predicted error against what it corrects
    (``model.meta["worth"]``, mtcal.identify.compare.split_half_worth) and warn when compensating may make the machine
    worse."""
    m = machine if isinstance(machine, Machine) else load_machine(machine)
    if method not in METHODS:
        raise InputError(f"--method must be one of {METHODS}, got {method!r}")
    warnings: list[str] = []
    estimated = None
    if method == "auto":
        method, tracker, estimated = _auto_method(rec, tracker, warnings)
    if reference not in fitting.REFERENCE_METHODS:
        raise InputError(f"--reference must be one of {fitting.REFERENCE_METHODS}, got {reference!r}")
    t = None if tracker is None else np.asarray(tracker, dtype=float).reshape(3)
    results: dict[str, AxisResult] = {}
    for axis in rec.axes():
        if axis not in m.axes:
            raise InputError(f"{rec.source}: axis {axis} is not an axis of machine {m.name} ({', '.join(m.axes)})")
    joint = None
    if method == "joint" or len(set(rec.stations().tolist())) > 1:
        if method != "joint":
            raise InputError(f"{rec.source}: several tracker stations need the joint fit (--method joint)")
        from mtcal.identify import joint as identify_joint
        log.info("joint weighted fit of %d readings from %d station(s)", len(rec), len(set(rec.stations().tolist())))
        for axis in rec.axes():  # the same input checks as the per-position method (gross errors, collinearity)
            sub = rec.select(rec.axis == axis)
            _check_shape(sub, axis, _passes(sub, axis))
        joint = identify_joint.joint_fit(rec, m, t)
        warnings += joint.warnings
        results = {axis: identify_joint.axis_result(joint, rec, m, axis) for axis in rec.axes()}
    linear = [a for a in rec.axes() if m.kind(a) == "linear"]
    for axis in ([] if joint is not None else linear):
        log.info("identifying axis %s", axis)
        results[axis] = _identify_axis(rec, axis, m, t, warnings, outlier_k, max_deviation_mm)
    slopes = _reference_lines(results, m, reference)
    if joint is None and len(linear) < len(rec.axes()):
        iso, t_iso = _in_iso_frame(rec, t, m, slopes)
        for axis in rec.axes():
            if axis not in linear:
                log.info("identifying axis %s (readings turned into the ISO frame of the linear axes)", axis)
                results[axis] = _identify_axis(iso, axis, m, t_iso, warnings, outlier_k, max_deviation_mm)
        results = {a: results[a] for a in rec.axes()}
    sq = fitting.squareness(slopes)
    sq_stats = _squareness_type_a(results, m, reference, sq)
    lin = [a for a, k in zip(m.axes, m.axis_kinds) if k == "linear"]
    if set(lin) <= set(results) and len(sq) < 3:
        warnings.append("squareness: some straightness records are missing; only " + ", ".join(sorted(sq)) + " found")
    model = _model(results, sq, m, max_degree, max_harmonics, rec.source, reference, t is not None or joint is not None,
                   warnings)
    model.meta["method"] = METHOD_TEXT[method]
    if estimated is not None:
        model.meta["tracker_estimated"] = {"position_mm": estimated.position.tolist(),
                                           "sigma_mm": estimated.sigma_mm.tolist(),
                                           "noise_scale_vs_at960": estimated.scale,
                                           "how": "estimated from the scatter of the repeated rounds "
                                                  "(mtcal.measurement.tracker_position)"}
    if worth:
        _state_worth(rec, m, model, warnings, dict(tracker=t, reference=reference, max_degree=max_degree,
                                                     max_harmonics=max_harmonics, method=method))
    model.meta["warnings"] = list(warnings)
    if sq_stats:
        model.meta["squareness_type_a"] = sq_stats
    res = IdentifyResult(results, sq, model, warnings, reference, t is not None or joint is not None, rec.source,
                         sq_stats, method)
    if joint is not None:
        res.joint = joint.summary()
        res.joint["squareness_sigma"] = squareness_sigma(results, reference)
        model.meta["squareness_sigma"] = res.joint["squareness_sigma"]
    return res


def _state_worth(rec: Recording, m: Machine, model: ErrorModel, warnings: list[str], kw: dict) -> None:
    """model.meta["worth"] from the same estimator on the even and the odd rounds (``split_half_worth``), and a
    warning when compensating with the model may leave the machine worse than without it."""
    rounds = np.unique(rec.round)
    if len(rounds) < 2:
        warnings.append("one round: the model's error cannot be predicted from the data (measure two or more rounds)")
        return
    halves = (rounds[::2], rounds[1::2])
    short = [a for a in rec.axes() for h in halves if not np.isin(rec.round[rec.axis == a], h).any()]
    if short:
        warnings.append(f"the model's error was not predicted: axis {short[0]} is not measured in both halves of the "
                        f"rounds (even and odd)")
        return
    quiet = logging.getLogger("mtcal")
    level = quiet.level
    quiet.setLevel(max(level, logging.WARNING))  # the halves' progress is not the user's
    try:
        a, b = [identify(rec.select(np.isin(rec.round, h)), machine=m, worth=False, **kw).model for h in halves]
    except InputError as e:  # a half lacks what the whole has (a position measured in one round only)
        warnings.append(f"the model's error was not predicted: a half of the rounds cannot be identified ({e})")
        return
    finally:
        quiet.setLevel(level)
    w = split_half_worth(m, model, a, b, len(halves[0]), len(halves[1]))
    model.meta["worth"] = w.to_dict()
    log.info("model: corrects %.1f um RMS over the measured volume; predicted error %.1f um RMS (%s)",
             w.corrects_rms_um, w.predicted_error_rms_um, w.how)
    if w.may_worsen:
        warnings.append(f"compensating with this model may make the machine worse: it corrects {w.corrects_rms_um:.1f} "
                        f"um RMS and is itself uncertain by {w.predicted_error_rms_um:.1f} um RMS over the measured "
                        f"volume; measure more rounds or from more tracker stations (mtcal plan shows the gain)")


def _auto_method(rec: Recording, tracker, warnings: list[str]):
    """identify's default estimator: (method, tracker position or None, the estimate or None).  The joint fit
    when the tracker position is given or estimated from the rounds' scatter; else three-point, with a warning
    naming what is lost."""
    estimated = None
    if tracker is None and rec.tracker_xyz is None:
        estimated, why = estimate_station(rec)
        if estimated is None and len(np.unique(rec.round)) > 1 and not np.any(round_scatter(rec)):  # noise-free
            log.info("tracker position not estimated (%s): three-point method", why)
        elif estimated is None:
            warnings.append(f"{rec.source}: tracker position not given and not estimated ({why}): three-point "
                            f"method, readings weighted equally; lost: the weighting by the tracker's anisotropic "
                            f"noise and the joint fit (about twice the model error, benchmarks/identify_truth.py); "
                            f"give --tracker x,y,z")
        else:
            tracker = estimated.position
            log.info("tracker position estimated from the scatter: %s mm", station_text(estimated))
    method = "joint" if tracker is not None or rec.tracker_xyz is not None else "three-point"
    return method, tracker, estimated


def round_scatter(rec: Recording) -> np.ndarray:
    """(n, 3) mm: each reading minus the mean of its cell (station, axis, position, point, direction) over the
    rounds, scaled by sqrt(m / (m - 1)) for a cell of m readings (unbiased); 0 for cells of one reading.  What the
    tracker's noise (and any drift) does between repeated rounds, no model needed."""
    keys = list(zip(rec.stations().tolist(), rec.axis.tolist(), np.round(rec.position, 6).tolist(),
                    rec.point.tolist(), rec.direction.tolist()))
    index = {k: i for i, k in enumerate(dict.fromkeys(keys))}
    cell = np.array([index[k] for k in keys])
    m = np.bincount(cell)[cell].astype(float)
    mean = np.stack([np.bincount(cell, rec.xyz[:, k]) for k in range(3)], axis=1)[cell] / m[:, None]
    return np.where(m[:, None] > 1, (rec.xyz - mean) * np.sqrt(m / np.maximum(m - 1, 1))[:, None], 0.0)


def estimate_station(rec: Recording) -> tuple[PositionEstimate | None,
str]:
    """Where the tracker stood, from the scatter of the repeated rounds (mtcal.measurement.tracker_position):
    (estimate, "")
    or (None, why not).  One station only (a multi-station recording carries its trackers' positions)."""
    if len(set(rec.stations().tolist())) > 1:
        return None, "several stations without tracker_x,y,z columns"
    if len(set(rec.round.tolist())) < 2:
        return None, "one round: no repeated readings to show the beam directions"
    r = round_scatter(rec)
    if not np.any(r):
        return None, "the rounds repeat exactly: no scatter (noise-free readings?)"
    groups = [sel for a in rec.axes() for p in np.unique(rec.point[rec.axis == a])
              if (sel := (rec.axis == a) & (rec.point == p)).sum() >= 6]
    est = estimate_position(rec.xyz, r, groups)
    if not est.accepted:
        return None, (f"the scatter shows no tracker shape (likelihood ratio {est.likelihood_ratio:.1f}, "
                      f"p = {est.p_isotropic:.2g})" if est.p_isotropic >= LR_LEVEL else
                      "the scatter does not pin the position down")
    return est, ""


def station_text(est: PositionEstimate) -> str:
    """'x, y, z +- sx, sy, sz' (mm)."""
    return (", ".join(f"{v:.0f}" for v in est.position) + " +- " + ", ".join(f"{v:.0f}" for v in est.sigma_mm))


def _reference_lines(results: dict[str, AxisResult], m: Machine, reference: str) -> dict[str, float]:
    """Fit the reference straight line of every straightness of the linear axes (stored in ``AxisResult.lines``)
    and return their slopes {E_IJ: mm/mm}: they define the ISO frame (design.md gauge) and the squareness."""
    slopes = {}
    for axis, ar in results.items():
        if m.kind(axis) != "linear":
            continue
        for nm in ar.names[:3]:
            if nm == m.positioning_errors[axis]:
                continue  # positioning error: no reference line
            a, b = fitting.reference_line(ar.positions, ar.mean[:, ar.names.index(nm)], reference)
            ar.lines[nm] = {"method": reference, "intercept": a, "slope": b}
            slopes[nm] = b
    return slopes


def iso_frame_rotation(m: Machine, slopes: dict[str, float]) -> np.ndarray:
    """Small rotation (rx, ry, rz) rad that turns the measuring frame into the ISO frame of the linear axes
    (design.md gauge: x along the motion of the linear axis that moves along x, y in the plane of the x and y
    motions), from the straightness reference-line slopes ``slopes`` (mm/mm).  A linear axis moving along
    (1, s_y, s_z) is turned onto x by rz = -s_y, ry = +s_z; the y-moving axis' z slope s_z' by rx = -s_z'.
    Slopes that are missing count as zero (that part of the frame stays the measuring frame's)."""
    along = {m.error_motions(a).index(m.positioning_errors[a]): m.error_motions(a)
             for a in m.axes if m.kind(a) == "linear"}
    phi = np.zeros(3)
    if 0 in along:
        phi[2] = -slopes.get(along[0][1], 0.0)
        phi[1] = slopes.get(along[0][2], 0.0)
    if 1 in along:
        phi[0] = -slopes.get(along[1][2], 0.0)
    return phi


def _in_iso_frame(rec: Recording, tracker, m: Machine, slopes: dict[str, float]):
    """The recording (and the tracker position) with every reading turned about the machine origin into the ISO
    frame of the linear axes, so that the rotary axes' errors are identified in the frame the linear axes'
    reference lines put those in (three-point path; the joint fit holds that frame by its gauge)."""
    phi = np.concatenate([np.zeros(3), iso_frame_rotation(m, slopes)])
    def turn(v):
        return None if v is None else tp.rigid_point(np.asarray(v, dtype=float).reshape(-1, 3), phi)
    turned = replace(rec, xyz=turn(rec.xyz), tracker_xyz=turn(rec.tracker_xyz))
    return turned, (None if tracker is None else turn(tracker)[0])


def _squareness_type_a(results: dict[str, AxisResult], m: Machine, reference: str, sq: dict) -> dict:
    """Squareness of each round (rounds matched by number across axes) -> {name: {"rounds", "std", "std_mean"}}."""
    out = {}
    common = None
    for axis, ar in results.items():
        if m.axis_kinds[m.axes.index(axis)] == "linear":
            common = set(ar.rounds.tolist()) if common is None else common & set(ar.rounds.tolist())
    if not sq or not common or len(common) < 2:
        return out
    per = []
    for r in sorted(common):
        slopes = {}
        for axis, ar in results.items():
            if m.axis_kinds[m.axes.index(axis)] != "linear":
                continue
            k = int(np.flatnonzero(ar.rounds == r)[0])
            for nm in ar.lines:
                v = ar.per_round[k, :, ar.names.index(nm)]
                ok = np.isfinite(v)
                if ok.sum() >= 2:
                    slopes[nm] = fitting.reference_line(ar.positions[ok], v[ok], reference)[1]
        per.append(fitting.squareness(slopes))
    for name in sq:
        v = np.array([p[name] for p in per if name in p])
        if len(v) >= 2:
            s = float(v.std(ddof=1))
            out[name] = {"rounds": v.tolist(), "std": s, "std_mean": s / np.sqrt(len(v))}
    return out


def _identify_axis(rec: Recording, axis: str, m: Machine, t, warnings: list[str], outlier_k: float,
                   max_dev: float) -> AxisResult:
    ps = _passes(rec, axis)
    rows, ref_rows = ps["rows"], ps["ref_rows"]
    readings, refs = rec.xyz[rows], rec.xyz[ref_rows]
    pts, dls, rf, d_m, rrel = frame_data(m, axis, _axes_vector(m, axis, ps["position"]),
                                         _axes_vector(m, axis, ps["q0"]), readings, refs)
    worst = np.unravel_index(int(np.argmax(np.linalg.norm(d_m, axis=-1))), rows.shape)
    dev = float(np.linalg.norm(d_m[worst]))
    if not dev <= max_dev:
        i, j = rows[worst], ref_rows[worst]
        unit = "mm" if m.axis_kinds[m.axes.index(axis)] == "linear" else "deg"
        raise InputError(f"{rec.where(i)}: point {rec.point[i]} at {axis} = {rec.position[i]:g} {unit} is {dev:.3g} mm "
                         f"from where the commanded motion takes its reference reading (line {int(rec.line[j])}); "
                         f"geometric errors are far smaller: positions must be in {unit} and readings in mm in the "
                         f"machine frame (positions in metres or radians? another axis moving?)")
    _check_shape(rec, axis, ps)
    cov = var_ref = None
    if t is not None:
        c_read, c_ref = delta_covariance(readings, refs, rrel, rf, t, parts=True)
        cov = c_read + c_ref
    e, resid, ce = solve_frame(pts, dls, cov)
    at_ref = (rows == ref_rows).all(axis=1)  # the reference passes themselves: zero by construction
    if ce is None:  # isotropic noise estimated from the residuals of all passes (3 n - 6 dof each)
        dof = resid.shape[-1] - 6
        s2 = float(np.sum(resid[~at_ref] ** 2) / max(1, dof * int((~at_ref).sum())))
        a = tp.point_rows(pts).reshape(len(pts), -1, 6)
        ce = s2 * np.linalg.inv(np.swapaxes(a, -1, -2) @ a)
    else:  # the reference reading's share, common to all passes of a round at one position (no averaging down)
        var_ref = np.diagonal(_propagate(pts, cov, c_ref), axis1=-2, axis2=-1).copy()
        var_ref[at_ref] = 0.0
    var = np.diagonal(ce, axis1=-2, axis2=-1).copy()
    var[at_ref] = 0.0
    positions = np.unique(ps["position"])
    rounds = ps["rounds"]
    per_round = np.full((len(rounds), len(positions), 6), np.nan)
    var_round = np.full((len(rounds), len(positions), 6), np.nan)
    rss = np.zeros(len(positions))
    cnt = np.zeros(len(positions))
    ri = np.searchsorted(rounds, ps["round"])
    pi = np.searchsorted(positions, ps["position"])
    for r in range(len(rounds)):
        for p in range(len(positions)):
            sel = (ri == r) & (pi == p)
            if sel.any():
                per_round[r, p] = e[sel].mean(axis=0)
                k = sel.sum()
                if var_ref is None:
                    var_round[r, p] = var[sel].sum(axis=0) / k**2
                else:
                    vr = var_ref[sel].mean(axis=0)
                    var_round[r, p] = (var[sel] - var_ref[sel]).sum(axis=0) / k**2 + vr
    np.add.at(rss, pi, np.sum(resid**2, axis=-1))
    np.add.at(cnt, pi, resid.shape[-1])
    direction = np.array([k[2] for k in ps["keys"]])
    reversal = None
    if (direction > 0).any() and (direction < 0).any():  # bidirectional: + minus - per (round, position)
        diffs = np.full((len(rounds), len(positions), 6), np.nan)
        for r in range(len(rounds)):
            for p in range(len(positions)):
                up = (ri == r) & (pi == p) & (direction > 0)
                dn = (ri == r) & (pi == p) & (direction < 0)
                if up.any() and dn.any():
                    diffs[r, p] = e[up].mean(axis=0) - e[dn].mean(axis=0)
        with _warnings.catch_warnings():  # positions without both directions stay NaN
            _warnings.simplefilter("ignore", RuntimeWarning)
            reversal = np.nanmean(diffs, axis=0)
    q0s = np.unique(ps["q0"])
    if len(q0s) > 1:
        warnings.append(f"axis {axis}: rounds use different reference positions {q0s.tolist()}")
    missing = [(int(rounds[r]), float(positions[p])) for r in range(len(rounds)) for p in range(len(positions))
               if np.isnan(per_round[r, p, 0])]
    if missing:
        warnings.append(f"axis {axis}: {len(missing)} (round, position) pair(s) not measured, e.g. {missing[:4]}; "
                        f"their statistics use fewer rounds")
    if len(rounds) < 2:
        warnings.append(f"axis {axis}: only one round ({int(rounds[0])}): no Type A uncertainty (std is NaN)")
    if t is None and len(rounds) >= 3:
        # without a noise model the isotropic residual estimate can miss anisotropic tracker noise: floor each
        # error's variance at the median (over positions) of its round-to-round variance
        with _warnings.catch_warnings():  # exact data: no spread at all, then no floor
            _warnings.simplefilter("ignore", RuntimeWarning)
            s2 = np.nanvar(per_round, axis=0, ddof=1)
            floor = np.nanmedian(np.where(s2 > 0, s2, np.nan), axis=0)
        if np.isfinite(floor).all():
            var_round = np.where(np.isfinite(var_round), np.maximum(var_round, floor), var_round)
    names = m.error_motions(axis)
    if len(rounds) >= 2 and outlier_k > 0:
        _check_rounds(rec, axis, names, positions, rounds, per_round, var_round, outlier_k, warnings, ps)
    return AxisResult(axis, positions, rounds, ps["points"], per_round, np.sqrt(rss / np.maximum(cnt, 1)),
                      np.sqrt(np.nanmean(var_round, axis=0)), names, float(q0s[0]), t is not None,
                      reversal=reversal)


def _propagate(pts: np.ndarray, cov: np.ndarray, part: np.ndarray) -> np.ndarray:
    """Covariance (..., 6, 6) of the weighted solution due to one part (..., n, 3, 3) of the deltas' covariance
    (blocks per point, mutually independent): G part G^T with the gain G = (A^T W A)^-1 A^T W."""
    a = tp.point_rows(pts)  # (..., n, 3, 6)
    wa = np.linalg.solve(cov, a)  # W_i A_i
    info = np.einsum("...nki,...nkj->...ij", a, wa)
    mid = np.einsum("...nki,...nkl,...nlj->...ij", wa, part, wa)
    inv = np.linalg.inv(info)
    return inv @ mid @ inv


def _check_shape(rec: Recording, axis: str, ps: dict) -> None:
    """Refuse reflectors that are (nearly) collinear at the reference readings (a rigid motion keeps the shape, so
    the machine-frame readings serve every path)."""
    ref = ps["position"] == ps["q0"]
    ref_pts = rec.xyz[ps["ref_rows"][ref]]
    shape = tp.point_shape(ref_pts.reshape(-1, 9))[..., 0] if ref_pts.shape[-2] == 3 else _shape(ref_pts)
    if np.any(shape < MIN_SHAPE):
        k = int(np.flatnonzero(ref)[int(np.argmin(shape))])
        raise InputError(f"{rec.source}, lines {_lines(rec, ps['ref_rows'][k])}: the points "
                         f"{[str(p) for p in ps['points']]} of axis {axis} are (nearly) collinear (shape measure "
                         f"{float(shape.min()):.2e}, 1 = equilateral, minimum {MIN_SHAPE:g}): the rotation about "
                         f"their line cannot be identified")


def _shape(pts: np.ndarray) -> np.ndarray:
    r = pts - pts.mean(axis=-2, keepdims=True)
    j = np.einsum("...ni,...ni->...", r, r)[..., None, None] * np.eye(3) - np.einsum("...ni,...nj->...ij", r, r)
    return 32 * np.linalg.det(j) / np.trace(j, axis1=-2, axis2=-1) ** 3


def _check_rounds(rec, axis, names, positions, rounds, per_round, var_round, k, warnings, ps) -> None:
    """Each round against the mean of the others, in units of the predicted sigma of their difference."""
    for r in range(len(rounds)):
        others = np.delete(per_round, r, axis=0)
        n_o = np.isfinite(others[..., 0]).sum(axis=0)[:, None]
        with np.errstate(invalid="ignore", divide="ignore"), _warnings.catch_warnings():
            _warnings.simplefilter("ignore", RuntimeWarning)  # a position no other round has: NaN, said elsewhere
            mo = np.nanmean(others, axis=0)
            vo = np.nansum(np.delete(var_round, r, axis=0), axis=0) / n_o**2
            z = np.abs(per_round[r] - mo) / np.sqrt(var_round[r] + vo)
        z = np.where(np.isfinite(z), z, 0.0)
        if z.max() > k:
            p, i = np.unravel_index(int(np.argmax(z)), z.shape)
            nbad = int((z > k).any(axis=1).sum())
            sel = np.flatnonzero((ps["round"] == rounds[r]) & (ps["position"] == positions[p]))
            msg = (f"axis {axis}, round {int(rounds[r])} disagrees with the other rounds: {names[i]} at "
                   f"{positions[p]:g} is {z[p, i]:.1f} sigma from their mean ({nbad} of {len(positions)} positions "
                   f"beyond {k:g} sigma; {rec.source}, lines {_lines(rec, ps['rows'][sel].ravel())}); it is kept in "
                   f"the mean: check it (thermal drift, a moved reflector, an outlier)")
            warnings.append(msg)


def _model(results: dict[str, AxisResult], sq: dict[str, float], m: Machine, max_degree: int, max_harmonics: int,
           source: str, reference: str, weighted: bool, warnings: list[str]) -> ErrorModel:
    """The error model: every error's table (mean over rounds) and its fitted function; a fit that leaves a
    significant part of its table adds a warning to ``warnings``."""
    funcs = {}
    for axis, ar in results.items():
        rotary = m.axis_kinds[m.axes.index(axis)] == "rotary"
        periodic = rotary and fitting.is_periodic(ar.positions)
        std, sm = ar.std, ar.std_mean
        for i, nm in enumerate(ar.names):
            vals = ar.values(nm)
            pr = ar.per_round[..., i]
            if nm in ar.lines:
                pr = pr - ar.lines[nm]["slope"] * ar.positions
            if len(ar.positions) < 2:
                continue
            cov = _value_covariance(ar, i, nm, reference)
            fit = (fitting.fit_harmonic(ar.positions, pr, 360.0, max_harmonics, ar.reference_position, cov) if periodic
                   else fitting.fit_polynomial(ar.positions, pr, max_degree, ar.reference_position, cov))
            if "covariance" in fit:  # reported at the noise law's level (the factor only sized the function)
                fit["covariance"] = (np.asarray(fit["covariance"]) / ar.fit_variance_factor).tolist()
            warnings += _fit_leaves(nm, i >= 3, ar, pr, cov, ErrorFunction(axis, ar.positions, vals, fit))
            extra = {"std": std[:, i].tolist(), "std_mean": sm[:, i].tolist(), "n": ar.n.tolist()}
            if nm in ar.lines:
                extra["reference_line"] = ar.lines[nm]
            funcs[nm] = ErrorFunction(axis, ar.positions.copy(), vals, fit, extra)
            ar.fits[nm] = fit
    meta = {"identified_from": source, "method": "three-point (Zhang & Hu), least squares over all equations",
            "weighted": weighted, "reference_line": reference,
            "squareness_convention": fitting.SQUARENESS_CONVENTION}
    return ErrorModel(m.name, dict(sq), funcs, meta)


FIT_LEAVES_K = 4.0  # a fit that misses a table value by more than this many of its standard deviations is said


def _fit_leaves(name: str, angular: bool, ar: AxisResult, per_round: np.ndarray, cov, f: ErrorFunction) -> list[str]:
    """A warning where the fitted function misses a significant part of the table (compensation and every
    exporter evaluate the fit, so what it leaves is not corrected): the largest |table - fit| beyond
    ``FIT_LEAVES_K`` standard deviations of the table value (the rounds' scatter, or the joint covariance)."""
    if cov is None:
        cov = fitting.rounds_covariance(per_round)
    var = np.zeros(per_round.shape[1]) if cov is None else np.diagonal(cov)
    table = np.nanmean(per_round, axis=0)
    miss = np.abs(table - f(ar.positions))
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(var > 0, miss / np.sqrt(var), 0.0)
    if not np.nanmax(z, initial=0.0) > FIT_LEAVES_K:
        return []
    k = int(np.nanargmax(z))
    scale, unit = (1e6, "urad") if angular else (1e3, "um")
    return [f"{name}: the fitted function misses the table by {miss[k] * scale:.2f} {unit} ({z[k]:.1f} sigma) at "
            f"{ar.axis} = {ar.positions[k]:g}: compensation evaluates the fit, so that part is not corrected "
            f"(more rounds, or --max-degree / --max-harmonics)"]


def _value_covariance(ar: AxisResult, i: int, name: str, reference: str) -> np.ndarray | None:
    """Covariance (n_pos, n_pos) of error ``i``'s values as fitted (reference-line slope removed) from the
    joint fit's covariance; None for the per-position method."""
    if ar.covariance is None:
        return None
    c = ar.covariance[i::6, i::6] * ar.fit_variance_factor
    if name in ar.lines:
        t = np.eye(len(ar.positions)) - np.outer(ar.positions, fitting.slope_weights(ar.positions, reference))
        c = t @ c @ t.T
    return c


def squareness_sigma(results: dict[str, AxisResult], reference: str) -> dict[str, float]:
    """Standard deviation (rad) of each squareness from the joint covariance of the straightness slopes it sums
    (in the ISO frame the slopes it pairs with are zero by the gauge, so the axes' slopes are independent)."""
    var: dict[str, float] = {}
    for ar in results.values():
        if ar.covariance is None:
            return {}
        g = fitting.slope_weights(ar.positions, reference)
        for nm in ar.lines:
            i = ar.names.index(nm)
            var[nm] = float(g @ ar.covariance[i::6, i::6] @ g)
    return {k: float(np.sqrt(var[a] + var[b])) for k, ((a, b), _) in fitting.SQUARENESS_PAIRS.items()
            if a in var and b in var}


# ----------------------------------------------------------------------------- Inspire export layout
INSPIRE_ORDER = ("K", "P", "Q")  # thesis appendices C, D: blocks of K, then P, then Q rows


def parse_positions(text: str) -> np.ndarray:
    """'start:stop:count' (inclusive, evenly spaced) or 'a,b,c,...' -> positions (mm or deg)."""
    try:
        if ":" in text:
            a, b, n = text.split(":")
            p = np.linspace(float(a), float(b), int(n))
        else:
            p = np.array([float(v) for v in text.split(",")])
    except ValueError:
        p = np.array([])
    if len(p) < 2 or not np.isfinite(p).all():
        raise InputError(f"--positions must be start:stop:count (count >= 2) or a comma list of >= 2 finite numbers, "
                         f"got {text!r}")
    return p


def read_inspire(paths, axis: str, positions=None, machine: str | Machine = DEFAULT_MACHINE) -> Recording:
    """Recording from Inspire exports as the thesis used them: one CSV per round (file order = round 1, 2, ...),
    rows 'label, x, y, z' (mm, machine frame), in blocks of K, P, Q readings over the same positions (one
    direction).  ``positions`` (mm or deg) default to the thesis plan of the axis when the block length matches.
    A first line that is not numeric is taken as a header; any other bad line is an error naming file and line."""
    from mtcal.measurement.recordings import make_recording
    from mtcal.campaign.simulate import default_positions
    m = machine if isinstance(machine, Machine) else load_machine(machine)
    axis = axis.upper()
    if axis not in m.axes:
        raise InputError(f"--axis {axis}: not an axis of machine {m.name} ({', '.join(m.axes)})")
    rows: dict[str, list] = {k: [] for k in ("round", "position", "point", "xyz", "line", "file")}
    for r, path in enumerate(paths, start=1):
        text = read_text(path, "Inspire export")
        data = []
        for ln, line in enumerate(text.splitlines(), start=1):
            if not line.strip():
                continue
            f = [c.strip() for c in line.split(",")]
            try:
                xyz = [float(v) for v in f[1:4]] if len(f) >= 4 else None
            except ValueError:
                xyz = None
            if xyz is None:
                if not data and ln == 1:
                    continue  # header
                raise InputError(f"{path}:{ln}: expected 'label, x, y, z' in mm, got {line.strip()!r}") from None
            if not np.isfinite(xyz).all():
                raise InputError(f"{path}:{ln}: NaN/inf is not a measurement")
            data.append((ln, xyz))
        if len(data) % 3 or not data:
            raise InputError(f"{path}: {len(data)} readings is not three equal blocks (K, P, Q) of one per position")
        n = len(data) // 3
        pos = (np.asarray(positions, dtype=float) if positions is not None
               else default_positions(m).get(axis))
        if pos is None or len(pos) != n:
            raise InputError(f"{path}: blocks of {n} readings; give the {n} positions of axis {axis} "
                             f"(--positions start:stop:count)")
        for k, (ln, xyz) in enumerate(data):
            for key, v in zip(rows, (r, pos[k % n], INSPIRE_ORDER[k // n], xyz, ln, str(path))):
                rows[key].append(v)
    rec = make_recording([axis] * len(rows["round"]), rows["round"], rows["position"], rows["point"],
                         np.array(rows["xyz"]), source=" + ".join(map(str, paths)))
    rec.line = np.array(rows["line"])
    return rec

