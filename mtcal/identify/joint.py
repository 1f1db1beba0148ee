"""Joint weighted identification from one or several laser-tracker stations (issue 14).

One least-squares fit of all readings of a recording, instead of one three-point solution per position:

* unknowns: the six error motions (E_X, E_Y, E_Z mm; E_A, E_B, E_C rad) of each measured axis at each measured
  position and, where the data has both, direction; the reflector positions in their carrier frames (mm: the
  spindle side relative to the spindle gauge point, the table side in workpiece coordinates; a point label is one
  nest throughout the file, shared by rounds and stations); one rigid alignment correction per tracker station
  (tx, ty, tz mm, rotations about x, y, z rad: the station's readings are ``rigid_point(true point, alignment)``,
  generated from derive/threepoint.py);
* reading model (machine frame, mm): ``rigid_point(Machine.points(side, axes, w, e), a_s)``, linearised by
  ``Machine.point_jacobian_errors`` (errors), ``Machine.rigid_motion`` (reflector position: d x / d w = R) and
  ``point_rows`` (alignment), solved by Gauss-Newton (the model is nearly linear: two steps);
* weights: each reading's AT960 covariance (mtcal.measurement.tracker) from its station's tracker position;
* gauge (what the data cannot tell, docs/design.md): errors are zero at each axis' reference (the position closest to
  zero, in the direction first approached there); the station translations sum to zero (one station: zero);
  the rotation of the frame is fixed by the ISO frame of the linear axes: the least-squares slopes (over the
  measured positions) of the first linear axis' two straightness motions and of the second linear axis'
  straightness out of the plane of the two are zero (X along the X motion, Y in the X-Y motion plane).  Without
  two linear axes in the data the station rotations sum to zero instead (stated in the warnings);
* solution: the whitened Jacobian is assembled sparse (scipy.sparse), the normal equations N = J^T J (column
  scaled) with the gauge rows C are solved as one KKT system; the covariance of the estimate is the matching block
  of the KKT inverse (the constrained covariance, mm^2 / rad^2);
* Type A: chi^2 / dof of the whitened residuals (Birge ratio; the covariance is scaled up by it when > 1) and the
  error motions of each round, re-solved position by position with the jointly estimated reflectors and alignments
  held (their spread over rounds is the experimental standard deviation).

Other axes' positions (``pos_<AXIS>`` columns) move the carrier; those axes' own errors there are not unknowns.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sps

from mtcal.errors import InputError
from mtcal.generated import threepoint_numpy as tp
from mtcal.identify.results import AxisResult
from mtcal.kinematics.machine import Machine
from mtcal.measurement import tracker as trk
from mtcal.measurement.passes import first_readings, position_key, reading_order, reference_position
from mtcal.measurement.recordings import Recording

FIT_VARIANCE_FLOOR = 1e-12  # noise-free readings: the fits are sized as if the data were this precise (not exactly 0)
GN_STEPS = 2  # Gauss-Newton steps (errors are um and urad: the second step changes nothing measurable)


@dataclass
class Layout:
    """Where each unknown sits in the parameter vector and which rows belong to which unknowns."""

    axes: dict[str, list[tuple[float, int]]]  # axis -> unknown keys (position, direction); the reference excluded
    reference: dict[str, tuple[float, int]]  # axis -> (reference position, direction first approached)
    err_index: dict[tuple[str, float, int], int]  # (axis, position, direction) -> first of 6 columns
    reflectors: dict[tuple[str, str], int]  # (side, label) -> first of 3 columns
    stations: dict[str, int]  # station label -> first of 6 columns
    n: int


@dataclass
class JointResult:
    """The joint estimate.  ``x`` and ``covariance`` are ordered by ``layout``; ``per_round`` maps (axis, round)
    to the error motions (n_keys, 6) of that round re-solved with reflectors and alignments held."""

    layout: Layout
    x: np.ndarray
    covariance: np.ndarray
    chi2: float
    dof: int
    residuals: np.ndarray  # (n_rows, 3) mm, reading - model
    reflectors: dict[tuple[str, str], np.ndarray]  # (side, label) -> (3,) mm in the carrier frame
    alignment: dict[str, np.ndarray]  # station -> (6,) tx, ty, tz mm, rotations about x, y, z rad
    trackers: dict[str, np.ndarray]  # station -> (3,) mm
    per_round: dict[tuple[str, int], np.ndarray] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)

    def summary(self) -> dict:
        return summary_of(self)

    @property
    def birge(self) -> float:
        """sqrt(chi^2 / dof): 1 when the residuals scatter as the noise model says."""
        return float(np.sqrt(self.chi2 / max(self.dof, 1)))

    def errors(self, axis: str) -> tuple[list[tuple[float, int]], np.ndarray, np.ndarray]:
        """(keys (position, direction), values (n_keys, 6), covariance (n_keys, 6, n_keys, 6)) of one axis,
        the reference key included (zero, no variance)."""
        lay = self.layout
        keys = sorted(lay.axes[axis] + [lay.reference[axis]])
        first = np.array([lay.err_index.get((axis, *k), -1) for k in keys])  # -1: the reference (the gauge)
        known = np.repeat(first >= 0, 6).reshape(len(keys), 6)
        cols = np.where(known, first[:, None] + np.arange(6), 0)
        vals = np.where(known, self.x[np.maximum(cols, 0)], 0.0)
        c = self.covariance[np.ix_(np.maximum(cols, 0).ravel(), np.maximum(cols, 0).ravel())]
        c = c * np.outer(known.ravel(), known.ravel())
        return keys, vals, c.reshape(len(keys), 6, len(keys), 6)


# ----------------------------------------------------------------------------------------------- layout
def _axes_matrix(m: Machine, rec: Recording) -> np.ndarray:
    """All axis positions (n_rows, n_axes): the measured axis at ``position``, others from pos_<AXIS> or zero."""
    q = np.zeros((len(rec), len(m.axes)))
    for a, v in (rec.other_positions or {}).items():
        q[:, m.index(a)] = v
    for a in np.unique(rec.axis):
        rows = rec.axis == a
        q[rows, m.index(str(a))] = rec.position[rows]
    return q


def _layout(m: Machine, rec: Recording, keys: np.ndarray) -> Layout:
    axes, reference, err_index = {}, {}, {}
    n = 0
    for a in rec.axes():
        rows = np.flatnonzero(rec.axis == a)
        pos = position_key(rec.position[rows])
        q0 = reference_position(pos)
        first = first_readings(rec, rows, q0, reading_order(rec, rows), by=())[()]
        reference[a] = (q0, int(keys[first]))
        ks = sorted({(float(p), int(d)) for p, d in zip(pos, keys[rows])} - {reference[a]})
        axes[a] = ks
        for k in ks:
            err_index[(a, *k)] = n
            n += 6
    reflectors = {}
    for side, label in sorted({(m.side(str(a)), str(p)) for a, p in zip(rec.axis, rec.point)}):
        reflectors[(side, label)] = n
        n += 3
    stations = {}
    for s in sorted(set(rec.stations().tolist())):
        stations[s] = n
        n += 6
    return Layout(axes, reference, err_index, reflectors, stations, n)


def _direction_keys(rec: Recording) -> np.ndarray:
    """Direction of each row where its axis has both directions in the data, else 0 (one unknown per position)."""
    out = np.zeros(len(rec), dtype=int)
    for a in np.unique(rec.axis):
        rows = rec.axis == a
        if (rec.direction[rows] > 0).any() and (rec.direction[rows] < 0).any():
            out[rows] = rec.direction[rows]
    return out


def _trackers(rec: Recording, tracker) -> dict[str, np.ndarray]:
    st = rec.stations()
    out = {}
    for s in sorted(set(st.tolist())):
        rows = np.flatnonzero(st == s)
        if rec.tracker_xyz is not None:
            out[s] = rec.tracker_xyz[rows[0]].copy()
        elif tracker is not None:
            out[s] = np.asarray(tracker, dtype=float).reshape(3)
        else:
            raise InputError(f"{rec.source}: the joint fit weights each reading by the tracker's covariance: give "
                             f"the tracker position (`tracker` x,y,z or tracker_x,tracker_y,tracker_z columns), "
                             f"or use `method` three-point")
    return out


# ----------------------------------------------------------------------------------------------- model
def _state(m: Machine, rec: Recording, lay: Layout, q, keys, sides, x):
    """Exact model readings (n, 3) and the Jacobian blocks (errors, reflectors, alignment) at parameters x."""
    return _state_at(m, q, sides, _rows(m, rec, lay, keys, sides), x)


def _rows(m: Machine, rec: Recording, lay: Layout, keys, sides):
    """Each row's columns in x, which do not change with x: (its reflector's first column (n,), its key's first
    error column or -1 at the reference (n,), the indices of its axis' six error motions in the machine's errors
    (n, 6), its station's first column (n,))."""
    wcol = np.array([lay.reflectors[(s, str(p))] for s, p in zip(sides, rec.point)])
    ecol = np.array([lay.err_index.get((str(a), round(float(p), 6), int(d)), -1)
                     for a, p, d in zip(rec.axis, rec.position, keys)])
    motions = {a: [m.error_names.index(nm) for nm in m.error_motions(a)] for a in map(str, np.unique(rec.axis))}
    mot_idx = np.array([motions[str(a)] for a in rec.axis]).reshape(len(rec), 6)
    acol = np.array([lay.stations[s] for s in rec.stations()])
    return wcol, ecol, mot_idx, acol


def _state_at(m: Machine, q, sides, rows, x):
    """``_state`` with the rows' columns given (``_rows``)."""
    wcol, ecol, mot_idx, acol = rows
    n = len(ecol)
    w = x[wcol[:, None] + np.arange(3)]
    err = np.zeros((n, len(m.error_names)))
    has = ecol >= 0
    err[np.arange(n)[has, None], mot_idx[has]] = x[ecol[has, None] + np.arange(6)]
    pts = np.empty((n, 3))
    jac_e = np.zeros((n, 3, 6))
    rot = np.empty((n, 3, 3))
    for side in ("tool", "table"):
        on = sides == side
        if not on.any():
            continue
        pts[on] = m.points(side, q[on], w[on], err[on])
        je = m.point_jacobian_errors(side, q[on], w[on])
        jac_e[on] = np.take_along_axis(je, mot_idx[on][:, None, :], axis=-1)
        rot[on] = m.rigid_motion(side, q[on])[1]
    a_s = x[acol[:, None] + np.arange(6)]
    model = tp.rigid_point(pts, a_s)
    jac_a = tp.point_rows(pts)
    return model, (ecol, jac_e), (w, rot), (a_s, jac_a)


def _jacobian(rec: Recording, lay: Layout, sides, blocks, whiten: np.ndarray) -> sps.csr_matrix:
    """Whitened sparse Jacobian (3 n, n_params)."""
    (ecol, jac_e), (_, rot), (_, jac_a) = blocks
    n = len(rec)
    sides_cols = np.array([lay.reflectors[(s, str(p))] for s, p in zip(sides, rec.point)])
    st_cols = np.array([lay.stations[s] for s in rec.stations()])
    parts = []
    every = np.ones(n, bool)
    for mat, cols, ok in ((jac_e, ecol, ecol >= 0), (rot, sides_cols, every), (jac_a, st_cols, every)):
        wm = np.einsum("nij,njk->nik", whiten, mat)[ok]  # (k, 3, c)
        c = wm.shape[-1]
        rows = (3 * np.flatnonzero(ok))[:, None, None] + np.arange(3)[None, :, None]
        cc = cols[ok][:, None, None] + np.arange(c)[None, None, :]
        parts.append((wm.ravel(), np.broadcast_to(rows, wm.shape).ravel(), np.broadcast_to(cc, wm.shape).ravel()))
    data, r, c = (np.concatenate(v) for v in zip(*parts))
    return sps.csr_matrix((data, (r, c)), shape=(3 * n, lay.n))


def _gauge(m: Machine, rec: Recording, lay: Layout, warnings: list[str]) -> np.ndarray:
    """Gauge rows C (k, n_params) with C x = 0 (see module docstring)."""
    rows = []
    for j in range(3):  # station translations sum to zero
        r = np.zeros(lay.n)
        r[[c + j for c in lay.stations.values()]] = 1.0
        rows.append(r)
    lin = [a for a in m.linear_axes if a in lay.axes]
    if len(lin) >= 2:
        comp = {a: "XYZ".index(m.positioning_errors[a][2]) for a in lin[:2]}
        c1, c2 = comp[lin[0]], comp[lin[1]]
        fixed = [(lin[0], k) for k in range(3) if k != c1] + [(lin[1], 3 - c1 - c2)]
        for axis, k in fixed:  # least-squares slope over all keys (reference included, value 0) = 0
            keys = lay.axes[axis] + [lay.reference[axis]]
            p = np.array([kk[0] for kk in keys])
            wts = p - p.mean()
            r = np.zeros(lay.n)
            for kk, wt in zip(keys, wts):
                if kk in lay.axes[axis]:
                    r[lay.err_index[(axis, *kk)] + k] = wt
            rows.append(r)
    else:
        warnings.append("joint fit: fewer than two linear axes measured: the frame's rotation is fixed by "
                        "station rotations summing to zero, not by the ISO frame of the linear axes")
        for j in range(3, 6):
            r = np.zeros(lay.n)
            r[[c + j for c in lay.stations.values()]] = 1.0
            rows.append(r)
    return np.array(rows)


def _initial(m: Machine, rec: Recording, lay: Layout, q, keys, sides) -> np.ndarray:
    """Reflector positions from the reference readings (mean over rounds and stations); the rest zero."""
    x = np.zeros(lay.n)
    for (side, label), c in lay.reflectors.items():
        rows = np.flatnonzero((rec.point == label) & (sides == side))
        at_ref = [i for i in rows
                  if (round(float(rec.position[i]), 6), int(keys[i])) == lay.reference[str(rec.axis[i])]]
        use = np.array(at_ref if at_ref else rows)
        b, r = m.rigid_motion(side, q[use])
        x[c:c + 3] = np.einsum("nji,nj->ni", r, rec.xyz[use] - b).mean(axis=0)
    return x


def joint_fit(rec: Recording, m: Machine, tracker=None, spec: trk.TrackerSpec = trk.AT960,
              per_round: bool = True, steps: int = GN_STEPS) -> JointResult:
    """The joint weighted estimate of a recording (see module docstring); tracker (3,) mm when the recording has
    no tracker columns (one station); ``steps`` Gauss-Newton steps."""
    for a in rec.axes():
        m.index(a)
    sides = np.array([m.side(str(a)) for a in rec.axis])
    keys = _direction_keys(rec)
    q = _axes_matrix(m, rec)
    lay = _layout(m, rec, keys)
    trackers = _trackers(rec, tracker)
    st = rec.stations()
    cov = np.empty((len(rec), 3, 3))
    for s, t in trackers.items():
        cov[st == s] = trk.covariance(rec.xyz[st == s], t, spec)
    whiten = np.linalg.inv(np.linalg.cholesky(cov))  # L^-1: whitened residual = L^-1 r
    warnings: list[str] = []
    c_rows = _gauge(m, rec, lay, warnings)
    x = _initial(m, rec, lay, q, keys, sides)
    for _ in range(steps):
        model, *blocks = _state(m, rec, lay, q, keys, sides, x)
        jw = _jacobian(rec, lay, sides, blocks, whiten)
        rw = np.einsum("nij,nj->ni", whiten, rec.xyz - model).ravel()
        dx, kkt_inv, scale = _solve(jw, rw, c_rows)
        x = x + dx
    model, *_ = _state(m, rec, lay, q, keys, sides, x)
    resid = rec.xyz - model
    chi2 = float(np.sum(np.einsum("nij,nj->ni", whiten, resid) ** 2))
    dof = 3 * len(rec) - lay.n + len(c_rows)
    covx = kkt_inv[:lay.n, :lay.n] * np.outer(scale, scale)
    res = JointResult(lay, x, covx, chi2, dof, resid,
                      {k: x[c:c + 3].copy() for k, c in lay.reflectors.items()},
                      {s: x[c:c + 6].copy() for s, c in lay.stations.items()}, trackers, warnings=warnings)
    if per_round:
        res.per_round = _per_round(m, rec, lay, q, keys, sides, x, whiten)
    return res


def linearised(rec: Recording, m: Machine, tracker=None, spec: trk.TrackerSpec = trk.AT960):
    """The joint estimate (``joint_fit`` without the per-round values) and the linear system at it, for trials that
    differ from ``rec`` by micrometres (mtcal.uncertainty.fast): (result, (the whitened Jacobian the Gauss-Newton
    steps use at the estimate, the whitening (n, 3, 3), the whitened residual (3 n,), the inverse of the scaled
    KKT matrix, the column scale)).  A trial's change is dx = S K S J^T dr: one more step from the estimate."""
    res = joint_fit(rec, m, tracker, spec, per_round=False)
    sides = np.array([m.side(str(a)) for a in rec.axis])
    keys = _direction_keys(rec)
    q = _axes_matrix(m, rec)
    st = rec.stations()
    cov = np.empty((len(rec), 3, 3))
    for s, t in res.trackers.items():
        cov[st == s] = trk.covariance(rec.xyz[st == s], t, spec)
    whiten = np.linalg.inv(np.linalg.cholesky(cov))
    model, *blocks = _state(m, rec, res.layout, q, keys, sides, res.x)
    jw = _jacobian(rec, res.layout, sides, blocks, whiten)
    rw = np.einsum("nij,nj->ni", whiten, rec.xyz - model).ravel()
    _, kkt_inv, scale = _solve(jw, rw, _gauge(m, rec, res.layout, []))
    return res, (jw, whiten, rw, kkt_inv, scale)


def _solve(jw: sps.csr_matrix, rw: np.ndarray, c_rows: np.ndarray):
    """Gauge-constrained least squares by the column-scaled normal equations (KKT).  Returns (dx, KKT^-1 of the
    scaled system, column scale)."""
    norms = np.sqrt(np.asarray(jw.multiply(jw).sum(axis=0)).ravel())
    scale = 1.0 / np.where(norms > 0, norms, 1.0)
    js = jw @ sps.diags(scale)
    n = (js.T @ js).toarray()
    cs = c_rows * scale[None, :]
    cs = cs / np.linalg.norm(cs, axis=1, keepdims=True)
    k = len(cs)
    kkt = np.block([[n, cs.T], [cs, np.zeros((k, k))]])
    kkt_inv = np.linalg.inv(kkt)
    rhs = np.concatenate([js.T @ rw, np.zeros(k)])
    return (kkt_inv @ rhs)[:jw.shape[1]] * scale, kkt_inv, scale


def _per_round(m: Machine, rec: Recording, lay: Layout, q, keys, sides, x, whiten) -> dict[tuple[str, int], np.ndarray]:
    """Each round's error motions per key, with reflectors and alignments held at the joint estimate: one
    weighted 6-unknown solve per (round, axis, position, direction) from that pass' readings."""
    x0 = x.copy()
    for c in lay.err_index.values():
        x0[c:c + 6] = 0.0
    model, _, _, _ = _state(m, rec, lay, q, keys, sides, x0)
    _, (_, jac_e), _, _ = _state(m, rec, lay, q, keys, sides, x)
    a = np.einsum("nij,njk->nik", whiten, jac_e)
    b = np.einsum("nij,nj->ni", whiten, rec.xyz - model)
    out = {}
    for axis, ks in lay.axes.items():
        for r in np.unique(rec.round[rec.axis == axis]):
            vals = np.zeros((len(ks) + 1, 6))
            allk = sorted(ks + [lay.reference[axis]])
            vals[:] = np.nan
            for ik, k in enumerate(allk):
                sel = np.flatnonzero((rec.axis == axis) & (rec.round == r) & (position_key(rec.position) == k[0])
                                     & (keys == k[1]))
                if not len(sel):
                    continue
                if k == lay.reference[axis]:
                    vals[ik] = 0.0
                    continue
                aa, bb = a[sel].reshape(-1, 6), b[sel].ravel()
                vals[ik] = np.linalg.lstsq(aa, bb, rcond=None)[0]
            out[(axis, int(r))] = vals
    return out


# ----------------------------------------------------------------------------------------------- per axis
def axis_result(res: JointResult, rec: Recording, m: Machine, axis: str):
    """The joint estimate of one axis as an ``identify.AxisResult``: per position the mean over directions;
    ``per_round`` holds each round's values shifted so that their mean is the joint estimate (their spread over
    rounds, the Type A scatter, is kept); ``covariance`` (n_pos * 6, n_pos * 6) is the joint covariance (scaled by
    the Birge ratio when it exceeds 1)."""

    keys, vals, cov = res.errors(axis)
    positions = np.unique([k[0] for k in keys])
    n_k = len(keys)
    avg = np.zeros((len(positions), n_k))  # position value = mean over the directions measured there
    for ik, k in enumerate(keys):
        avg[np.searchsorted(positions, k[0]), ik] = 1.0
    avg /= avg.sum(axis=1, keepdims=True)
    mean = avg @ vals
    big = np.kron(avg, np.eye(6))
    c = big @ cov.reshape(6 * n_k, 6 * n_k) @ big.T * max(1.0, res.birge**2)
    rounds = np.array(sorted({r for (a, r) in res.per_round if a == axis}))
    per_round = np.full((len(rounds), len(positions), 6), np.nan)
    for ir, r in enumerate(rounds):
        v = res.per_round[(axis, int(r))]
        with np.errstate(invalid="ignore"):
            ok = np.isfinite(v[:, 0])
            a_r = avg * ok[None, :]
            wsum = a_r.sum(axis=1, keepdims=True)
            per_round[ir] = np.where(wsum > 0, (a_r / np.where(wsum > 0, wsum, 1)) @ np.nan_to_num(v), np.nan)
    with np.errstate(invalid="ignore"):
        per_round += mean - np.nanmean(per_round, axis=0)
    reversal = None
    dirs = {k[1] for k in keys}
    if {-1, 1} <= dirs:
        reversal = np.full((len(positions), 6), np.nan)
        for ip, p in enumerate(positions):
            if (p, 1) in keys and (p, -1) in keys:
                reversal[ip] = vals[keys.index((p, 1))] - vals[keys.index((p, -1))]
    rows = rec.axis == axis
    pi = np.searchsorted(positions, position_key(rec.position[rows]))
    rss = np.bincount(pi, np.sum(res.residuals[rows] ** 2, axis=1), len(positions))
    cnt = np.bincount(pi, minlength=len(positions)) * 3
    sig = np.sqrt(np.diagonal(c).reshape(len(positions), 6) * max(1, len(rounds)))
    points = tuple(sorted({str(p) for p in rec.point[rows]}))
    out = AxisResult(axis, positions, rounds, points, per_round, np.sqrt(rss / np.maximum(cnt, 1)), sig,
                     m.error_motions(axis), res.layout.reference[axis][0], True, reversal=reversal, covariance=c,
                     fit_variance_factor=float(np.clip(res.birge**2, FIT_VARIANCE_FLOOR, 1.0)))
    return out


def summary_of(res: JointResult) -> dict:
    """JSON-ready summary: stations (tracker mm, alignment mm / rad with standard deviations), reflectors (mm),
    chi^2, dof and the Birge ratio."""
    sd = np.sqrt(np.diagonal(res.covariance)) * max(1.0, res.birge)
    lay = res.layout
    return {"chi2": res.chi2, "dof": res.dof, "birge_ratio": res.birge,
            "stations": {s: {"tracker": res.trackers[s].tolist(), "alignment": res.alignment[s].tolist(),
                             "alignment_sigma": sd[c:c + 6].tolist()} for s, c in lay.stations.items()},
            "reflectors": {f"{side}:{label}": res.reflectors[(side, label)].tolist()
                           for (side, label) in lay.reflectors},
            "alignment_units": "tx, ty, tz mm; rotations about x, y, z rad (reading = rigid motion of the true point)"}
