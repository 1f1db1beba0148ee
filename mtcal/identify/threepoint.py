"""The three-point method (Zhang & Hu): for every pass (axis, round, position, direction) the readings of >= 3
non-collinear reflectors (P, Q, K) are compared with where the nominal motion takes each point's reference
reading; the differences, in the axis' own frame (derive/threepoint.py: B's stator frame is tilted 45 deg), give
the six error motions E_XJ, E_YJ, E_ZJ (mm) and E_AJ, E_BJ, E_CJ (rad) by least squares over all 3 n equations
(weighted by the tracker covariance when its position is known).  Passes of one round at one position are
averaged; rounds give the Type A statistics (thesis eqs. 2.45-2.49)."""
from __future__ import annotations

import warnings as _warnings
from typing import Iterable

import numpy as np

from mtcal.errors import InputError
from mtcal.generated import threepoint_numpy as tp
from mtcal.identify.results import AxisResult, PositionResult
from mtcal.kinematics.machine import DEFAULT_MACHINE, Machine, load_machine
from mtcal.measurement import tracker as trk
from mtcal.measurement.passes import first_readings, group_passes, position_key, reading_order, reference_position
from mtcal.measurement.recordings import Recording
from mtcal.measurement.slips import MAX_DEVIATION_MM  # noqa: F401 (re-exported: the slip screen's one bound)

PARTS = ("X", "Y", "Z", "A", "B", "C")  # E_<part><axis>


MIN_SHAPE = 1e-3  # point_shape below this: points (nearly) collinear, rotation about their line unobservable




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
    at = np.unique(position_key(rec.position[idx]))
    if len(at) < 2:
        raise InputError(f"{rec.source}: axis {axis} is measured at one position only ({at[0]:g}"
                         f", lines {_lines(rec, idx)}): its errors are relative to the reference position, so an "
                         f"axis needs two or more positions")
    order_key = reading_order(rec, idx)
    groups = group_passes(rec, idx, rec.direction[idx], axis)
    rounds = np.array(sorted({k[0] for k in groups}))
    refs = {}
    for r in rounds:
        ri = idx[rec.round[idx] == r]
        q0 = reference_position(rec.position[ri])
        first = first_readings(rec, ri, q0, order_key)
        missing = [pt for pt in points if (pt,) not in first]
        if missing:
            raise InputError(f"{rec.source}: axis {axis}, round {r}: point {missing[0]} has no reading at the "
                             f"reference position {q0:g} (lines {_lines(rec, ri)})")
        refs[int(r)] = (q0, {pt: first[(pt,)] for pt in points})
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


def _identify_axis(rec: Recording, axis: str, m: Machine, t, warnings: list[str], outlier_k: float,
                   spec: trk.TrackerSpec = trk.AT960) -> AxisResult:
    """One axis by the three-point method: every pass solved (weighted by the tracker law ``spec`` when ``t`` is
    given, else isotropic from the residuals), passes of one round at one position averaged, Type A over rounds."""
    ps = _passes(rec, axis)
    rows, ref_rows = ps["rows"], ps["ref_rows"]
    readings, refs = rec.xyz[rows], rec.xyz[ref_rows]
    pts, dls, rf, d_m, rrel = frame_data(m, axis, _axes_vector(m, axis, ps["position"]),
                                         _axes_vector(m, axis, ps["q0"]), readings, refs)
    _check_shape(rec, axis, ps)
    cov = c_ref = None
    if t is not None:
        c_read, c_ref = delta_covariance(readings, refs, rrel, rf, t, parts=True, spec=spec)
        cov = c_read + c_ref
    e, resid, ce = solve_frame(pts, dls, cov)
    var, var_ref = _pass_variances(pts, resid, ce, cov, c_ref, (rows == ref_rows).all(axis=1))
    positions, rounds = np.unique(ps["position"]), ps["rounds"]
    ri, pi = np.searchsorted(rounds, ps["round"]), np.searchsorted(positions, ps["position"])
    per_round, var_round = _per_round(e, var, var_ref, ri, pi, len(rounds), len(positions))
    rss, cnt = np.zeros(len(positions)), np.zeros(len(positions))
    np.add.at(rss, pi, np.sum(resid**2, axis=-1))
    np.add.at(cnt, pi, resid.shape[-1])
    direction = np.array([k[2] for k in ps["keys"]])
    reversal = _reversal(e, direction, ri, pi, len(rounds), len(positions))
    q0s = np.unique(ps["q0"])
    _notes(axis, q0s, rounds, positions, per_round, warnings)
    if t is None and len(rounds) >= 3:
        var_round = _floor_at_scatter(per_round, var_round)
    names = m.error_motions(axis)
    if len(rounds) >= 2 and outlier_k > 0:
        _check_rounds(rec, axis, names, positions, rounds, per_round, var_round, outlier_k, warnings, ps)
    return AxisResult(axis, positions, rounds, ps["points"], per_round, np.sqrt(rss / np.maximum(cnt, 1)),
                      np.sqrt(np.nanmean(var_round, axis=0)), names, float(q0s[0]), t is not None,
                      reversal=reversal)


def _pass_variances(pts, resid, ce, cov, c_ref, at_ref) -> tuple[np.ndarray, np.ndarray | None]:
    """(variance (passes, 6) of every pass' solution, the reference reading's share of it or None): from the
    tracker law, or isotropic from the residuals of all passes (3 n - 6 dof each); the reference passes
    themselves are zero by construction."""
    var_ref = None
    if ce is None:
        dof = resid.shape[-1] - 6
        s2 = float(np.sum(resid[~at_ref] ** 2) / max(1, dof * int((~at_ref).sum())))
        a = tp.point_rows(pts).reshape(len(pts), -1, 6)
        ce = s2 * np.linalg.inv(np.swapaxes(a, -1, -2) @ a)
    else:  # the reference reading's share, common to all passes of a round at one position (no averaging down)
        var_ref = np.diagonal(_propagate(pts, cov, c_ref), axis1=-2, axis2=-1).copy()
        var_ref[at_ref] = 0.0
    var = np.diagonal(ce, axis1=-2, axis2=-1).copy()
    var[at_ref] = 0.0
    return var, var_ref


def _per_round(e, var, var_ref, ri, pi, n_rounds: int, n_pos: int) -> tuple[np.ndarray, np.ndarray]:
    """(values, variances) (rounds, positions, 6): passes of one round at one position averaged (NaN where none)."""
    per_round = np.full((n_rounds, n_pos, 6), np.nan)
    var_round = np.full((n_rounds, n_pos, 6), np.nan)
    for r in range(n_rounds):
        for p in range(n_pos):
            sel = (ri == r) & (pi == p)
            if sel.any():
                per_round[r, p] = e[sel].mean(axis=0)
                k = sel.sum()
                if var_ref is None:
                    var_round[r, p] = var[sel].sum(axis=0) / k**2
                else:
                    vr = var_ref[sel].mean(axis=0)
                    var_round[r, p] = (var[sel] - var_ref[sel]).sum(axis=0) / k**2 + vr
    return per_round, var_round


def _reversal(e, direction, ri, pi, n_rounds: int, n_pos: int) -> np.ndarray | None:
    """Mean over rounds of (+ pass) - (- pass) per position (positions, 6), None when not bidirectional."""
    if not ((direction > 0).any() and (direction < 0).any()):
        return None
    diffs = np.full((n_rounds, n_pos, 6), np.nan)
    for r in range(n_rounds):
        for p in range(n_pos):
            up = (ri == r) & (pi == p) & (direction > 0)
            dn = (ri == r) & (pi == p) & (direction < 0)
            if up.any() and dn.any():
                diffs[r, p] = e[up].mean(axis=0) - e[dn].mean(axis=0)
    with _warnings.catch_warnings():  # positions without both directions stay NaN
        _warnings.simplefilter("ignore", RuntimeWarning)
        return np.nanmean(diffs, axis=0)


def _notes(axis: str, q0s, rounds, positions, per_round, warnings: list[str]) -> None:
    """Warnings on the layout: several reference positions, (round, position) pairs not measured, one round."""
    if len(q0s) > 1:
        warnings.append(f"axis {axis}: rounds use different reference positions "
                        f"({', '.join(format(q, 'g') for q in q0s.tolist())})")
    missing = [(int(rounds[r]), float(positions[p])) for r in range(len(rounds)) for p in range(len(positions))
               if np.isnan(per_round[r, p, 0])]
    if missing:
        eg = "; ".join(f"round {r} at {axis} = {q:g}" for r, q in missing[:4])
        warnings.append(f"axis {axis}: {len(missing)} (round, position) pair(s) not measured, e.g. {eg}; "
                        f"their statistics use fewer rounds")
    if len(rounds) < 2:
        warnings.append(f"axis {axis}: only one round ({int(rounds[0])}): no Type A uncertainty (std is NaN)")


def _floor_at_scatter(per_round: np.ndarray, var_round: np.ndarray) -> np.ndarray:
    """Without a noise model the isotropic residual estimate can miss anisotropic tracker noise: each error's
    variance floored at the median (over positions) of its round-to-round variance (exact data: no floor)."""
    with _warnings.catch_warnings():
        _warnings.simplefilter("ignore", RuntimeWarning)
        s2 = np.nanvar(per_round, axis=0, ddof=1)
        floor = np.nanmedian(np.where(s2 > 0, s2, np.nan), axis=0)
    if np.isfinite(floor).all():
        return np.where(np.isfinite(var_round), np.maximum(var_round, floor), var_round)
    return var_round


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
