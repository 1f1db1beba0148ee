"""Batched trials: the Monte Carlo of the joint estimator with the design factorised once (issue 37).

A trial of the full path (mtcal.uncertainty.trials.trial_block) runs ``identify`` from scratch: the screen, the noise
law's shape test, the joint fit's Gauss-Newton steps from a rough start, the degree selection of every function.
But a trial's readings differ from the campaign's by micrometres, so its joint estimate is one Gauss-Newton step
from the campaign's: with the whitened Jacobian J, the gauge rows C and the column scale S of the campaign's
estimate x0 (mtcal.identify.joint.linearised), a trial's estimate is

    x = x0 + S K (S J^T W (y - f(x0)))       (K: the top-left block of the inverse of the scaled KKT matrix)

for every trial at once (a sparse product and one dense product over a block of trials).  The step's own error is
second order in the trials' change (a reading moves by ~1 um at ~1 m: 1e-6 of the step, far below 1 % of any
interval; the check below measures it).  Everything after the joint fit is linear in x given the degrees chosen:
each axis' table (mean over directions), the reference lines' slopes and the squareness, each function's whitened
values y = L^-1 v (L: the Cholesky factor of the values' covariance, which a trial only scales by its Birge ratio
b^2: mtcal.identify.build._value_covariance), and for every candidate degree the least-squares fit.  The designs are
nested (a polynomial's degree d is the first d columns of degree d + 1; a harmonic series likewise by pairs), so
one QR of the largest design, A = Q R, gives every candidate's residual sum of squares from z = Q^T y:
rss_d = |y - Q z|^2 + sum_{j >= p_d} z_j^2, the BIC score rss_d / b^2 + p_d ln n as ``_gls`` computes it, the
selected degree and its fitted values A_d R_d^-1 z_<p_d> (at the table positions and at the poses; the tool tip's
first-order deviation is linear in the errors).

What is not batched runs the full path, trial by trial, counted by reason (``Batched.counts``): a trial whose
degree selection is a tie (two candidates' scores within ``TIE``), and a trial whose screen finds a gross error
(the campaign's found none) or whose noise law's shape test gives way to the data's law - these two checks cost a
hundred batched trials each, so they run on every ``SAMPLE``-th trial, and the counts say how many of those
differed.  A recording that cannot be batched at all (the three-point method, a screen that removed readings, a
minimum-zone reference line, the data's noise law, which every trial re-estimates) runs the full path with the
reason said.  ``self_check`` runs a few trials both ways before the rest: when any output
differs by more than ``CHECK_TOLERANCE`` of its interval's half-width the Monte Carlo says so and runs the full path.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from mtcal.identify import fitting
from mtcal.kinematics.machine import Machine
from mtcal.measurement.recordings import Recording
from mtcal.uncertainty.inputs import Inputs
from mtcal.uncertainty.trials import Outputs, draw, prepare_draw, trial_block

log = logging.getLogger(__name__)
BLOCK = 200  # trials per batch (per Dask task): ~0.2-0.5 s
TIE = 1e-5  # a degree selection whose best two BIC scores are this close (chi^2 units) is left to the full path (the
# batched and the full path chose the same degrees in every trial compared, gaps down to 0.004 included; at 1e-3,
# 0.7 % of the demo's trials were ties, and their identify runs cost more than all batched trials together)
CHECK_TRIALS = 3  # trials run both ways before the rest
CHECK_TOLERANCE = 0.05  # of an output's 95 % half-width (2 standard deviations of the batched trials): the batched
# step from the campaign's estimate differs from identify's converged fit of a trial by 0.6-2.4 % of a parameter's
# standard deviation (the Gauss-Newton fixed point moves at second order with the trial's readings: the Jacobian
# rows turn with the estimate and the tracker's anisotropic weights amplify it), an output by <= 1 % of its
# half-width in 95 % of cases, up to 4 % (tests/test_uncertainty_fast.py); the differences are of either sign from
# trial to trial, so the intervals move by less; a half-width to two significant digits needs 5 %
REASONS = ("screen", "noise law", "tie")
SAMPLE = 1000  # the screen and the shape test (a hundred batched trials' time each) run on every SAMPLE-th trial


@dataclass
class _Function:
    """One error function's degree selection, linear in the axis' table: where its values sit in the axis' means,
    the slope removal, the whitening, the QR of the largest design and, per candidate size, the fitted values at the
    table positions (``at_table``) and the tool tip's deviation at the poses (``at_poses``)."""

    name: str
    rows: np.ndarray  # indices into the stacked means (n_pos,)
    detrend: np.ndarray  # (n_pos, n_pos): table values from the means (the reference-line slope removed)
    whiten: np.ndarray  # (n_keep, n_pos): L^-1 restricted to the kept positions
    q: np.ndarray  # (n_keep, p_top)
    log_n: float
    sizes: list[int]  # columns of each candidate
    at_table: list[np.ndarray]  # (n_pos, p_k)
    at_poses: list[np.ndarray]  # (3 n_poses, p_k)
    out: slice
    shadow: slice | None


@dataclass
class Batched:
    """The joint estimator linearised at the campaign's estimate (module docstring); ``counts`` the trials run
    batched and those left to the full path, by reason."""

    x0: np.ndarray
    jw: object  # scipy.sparse (3 n, n_params), whitened Jacobian of the readings at x0
    js_t: object  # scipy.sparse (n_params, 3 n): (J S)^T
    gain: np.ndarray  # (n_params, n_params): S K
    whiten: np.ndarray  # (n, 3, 3)
    rw0: np.ndarray  # (3 n,) whitened residual of the campaign at x0
    xyz0: np.ndarray  # (n, 3) the campaign's readings
    dof: int
    means: np.ndarray  # (n_means, n_params) the axes' tables (position x motion) from x
    slopes: dict[str, np.ndarray]  # E_IJ -> (n_means,) weights: slope = w . means
    functions: list[_Function]
    constants: dict[str, tuple[int, np.ndarray]]  # name -> (output index, (3 n_poses,) deviation per unit)
    volumetric: slice
    tables: bool
    sides: dict  # axis -> the side its reflectors sit on (the screen's; the Machine itself is not shipped to workers)
    law_replaced: bool  # the campaign's shape test gave way to the data's law (not batched: always False)
    prior: object
    tracker: np.ndarray | None
    block: int = BLOCK
    counts: dict[str, int] = field(default_factory=lambda: {"batched": 0, **{r: 0 for r in REASONS}})

    def merge(self, counts: dict[str, int] | None) -> None:
        for k, v in (counts or {}).items():
            self.counts[k] = self.counts.get(k, 0) + v


def prepare(rec: Recording, options: dict, outputs: Outputs) -> tuple[Batched | None, str]:
    """The batched estimator of ``identify(rec, worth=False, **options)`` (options as the trials run it: method
    and tracker given), or (None, why not)."""
    from mtcal.identify import joint as jt
    from mtcal.identify.run import _noise_law
    from mtcal.kinematics.machine import DEFAULT_MACHINE, load_machine
    from mtcal.measurement import tracker as trk
    from mtcal.measurement.screen import screen

    if options.get("method") != "joint":
        return None, f"the {options.get('method')} method is not batched"
    reference = options.get("reference", "least-squares")
    if reference not in ("least-squares", "end-point"):
        return None, f"the {reference} reference line is not linear in the readings"
    if options.get("noise_law") is not None:
        return None, "a given noise law is not batched"
    mach = options.get("machine", DEFAULT_MACHINE)
    m = mach if isinstance(mach, Machine) else load_machine(mach)
    if screen(rec, m.sides).problems:
        return None, "the screen leaves readings of the campaign out (a trial's screen may differ)"
    t = options.get("tracker")
    t = None if t is None else np.asarray(t, dtype=float).reshape(3)
    prior = trk.as_tracker_model(options.get("tracker_model"))
    spec, law = _noise_law(rec, t, [], prior, known=True)
    if law is not None and law.get("source") != "prior":
        return None, "the fit weights by the data's noise law, which each trial re-estimates from its own scatter"
    res, (jw, whiten, rw0, kkt_inv, scale) = jt.linearised(rec, m, t, spec)
    n = res.layout.n
    js = jw @ _diag(scale)
    means, keys_of = _means(res, rec, m)
    b = Batched(res.x.copy(), jw, js.T.tocsr(), kkt_inv[:n, :n] * scale[:, None], whiten, rw0, rec.xyz.copy(),
                res.dof, means, {}, [], {}, outputs.volumetric, outputs.tables, dict(m.sides), False,
                prior, t)
    why = _functions(b, res, m, options, outputs, keys_of)
    return (None, why) if why else (b, "")



def _diag(v):
    import scipy.sparse as sps

    return sps.diags(v)


def _means(res, rec: Recording, m: Machine):
    """(the axes' tables as a linear map of x: (sum n_pos * 6, n_params), {axis: (positions, first row)}): each
    position's value is the mean over the directions measured there (mtcal.identify.joint.axis_result)."""
    lay = res.layout
    blocks, where, row = [], {}, 0
    for axis in rec.axes():
        keys = sorted(lay.axes[axis] + [lay.reference[axis]])
        positions = np.unique([k[0] for k in keys])
        avg = np.zeros((len(positions), len(keys)))
        for ik, k in enumerate(keys):
            avg[np.searchsorted(positions, k[0]), ik] = 1.0
        avg /= avg.sum(axis=1, keepdims=True)
        mat = np.zeros((len(positions) * 6, lay.n))
        for ik, k in enumerate(keys):
            c = lay.err_index.get((axis, *k))
            if c is None:
                continue  # the reference: zero
            for ip in np.flatnonzero(avg[:, ik]):
                mat[ip * 6 + np.arange(6), c + np.arange(6)] += avg[ip, ik]
        blocks.append(mat)
        where[axis] = (positions, row)
        row += len(positions) * 6
    return np.vstack(blocks), where


def _functions(b: Batched, res, m: Machine, options: dict, outputs: Outputs, keys_of) -> str:
    """Fill ``b.slopes``, ``b.functions`` and ``b.constants`` (the layout of ``outputs``); a reason when the
    outputs do not match what identify builds."""
    reference = options.get("reference", "least-squares")
    max_degree, max_harmonics = options.get("max_degree", 7), options.get("max_harmonics", 6)
    dev = _unit_deviations(m, outputs)
    if dev is None:
        return "the tool tip's deviation is not linear in the errors"
    for axis, (positions, row) in keys_of.items():
        names = m.error_motions(axis)
        if m.kind(axis) == "linear":
            g = fitting.slope_weights(positions, reference)
            for i, nm in enumerate(names[:3]):
                if nm != m.positioning_errors[axis]:
                    w = np.zeros(len(b.means))
                    w[row + np.arange(len(positions)) * 6 + i] = g
                    b.slopes[nm] = w
    for axis, (positions, row) in keys_of.items():
        if len(positions) < 2:
            continue
        periodic = m.kind(axis) == "rotary" and fitting.is_periodic(positions)
        c_all = _table_covariance(res, axis, positions)  # a trial scales it by its Birge ratio
        for i, nm in enumerate(m.error_motions(axis)):
            if nm not in outputs.functions or not np.array_equal(outputs.functions[nm][1], positions):
                return f"the outputs' positions of {nm} are not identify's table"
            b.functions.append(_function(b, m, nm, axis, i, positions, row, c_all, periodic,
                                         res.layout.reference[axis][0], max_degree, max_harmonics, reference,
                                         outputs, dev))
    names = set(b.slopes)
    for nm, (pair, _sign) in fitting.SQUARENESS_PAIRS.items():
        if set(pair) <= names:
            if nm not in outputs.constants:
                return f"the outputs lack the constant {nm}"
            b.constants[nm] = (outputs.constants[nm], dev[:, m.error_names.index(nm)])
    if set(b.constants) != set(outputs.constants):
        return "the outputs' constants are not identify's"
    if {f.name for f in b.functions} != set(outputs.functions):
        return "the outputs' functions are not identify's"
    return ""


def _table_covariance(res, axis: str, positions: np.ndarray) -> np.ndarray:
    """(n_pos * 6, n_pos * 6) the covariance of an axis' table from the joint covariance, before the Birge ratio
    (mtcal.identify.joint.axis_result scales it by max(1, b^2), mtcal.identify.build._value_covariance by
    min(1, b^2): a trial's values are fitted with b^2 times this)."""
    keys, _, cov = res.errors(axis)
    avg = np.zeros((len(positions), len(keys)))
    for ik, k in enumerate(keys):
        avg[np.searchsorted(positions, k[0]), ik] = 1.0
    avg /= avg.sum(axis=1, keepdims=True)
    big = np.kron(avg, np.eye(6))
    return big @ cov.reshape(6 * len(keys), 6 * len(keys)) @ big.T


def _function(b: Batched, m: Machine, nm: str, axis: str, i: int, positions: np.ndarray, row: int, c_all: np.ndarray,
              periodic: bool, x_ref: float, max_degree: int, max_harmonics: int, reference: str, outputs: Outputs,
              dev: np.ndarray) -> _Function:
    """One function's selection as fitting.fit_polynomial / fit_harmonic with the joint covariance (``_gls``)."""
    n = len(positions)
    rows = row + np.arange(n) * 6 + i
    cov = c_all[i::6, i::6]
    detrend = np.eye(n)
    if nm in b.slopes:
        g = fitting.slope_weights(positions, reference)
        detrend = np.eye(n) - np.outer(positions, g)
        cov = detrend @ cov @ detrend.T
    keep = (np.diagonal(cov) > 0) & (positions != x_ref)
    ck = cov[np.ix_(keep, keep)]
    chol = np.linalg.cholesky(ck + 1e-6 * np.trace(ck) / len(ck) * np.eye(len(ck)))
    if periodic:
        top = max(0, min(max_harmonics, (n - 2) // 2))

        def design(xx, k):
            return fitting._harm_design(xx, k, 360.0, x_ref)
        sizes = [2 * h for h in range(top + 1)]
    else:
        top = max(0, min(max_degree, n - 2))
        dom = (float(positions.min()), float(positions.max()))

        def design(xx, k):
            return fitting._poly_design(xx, k, dom, x_ref)
        sizes = list(range(top + 1))
    a_top = design(positions, top)
    q, r = np.linalg.qr(np.linalg.solve(chol, a_top[keep]))
    lo, hi = float(positions.min()), float(positions.max())
    col = outputs.functions[nm][2]
    pose_x = outputs.poses[:, m.index(axis)] if len(outputs.poses) else np.zeros(0)
    pose_x = pose_x if periodic else np.clip(pose_x, lo, hi)
    a_poses = design(pose_x, top)
    d = dev[:, m.error_names.index(nm)]  # (3 P,) deviation per unit of this error at each pose
    at_table, at_poses = [], []
    for p in sizes:
        rinv = np.linalg.inv(r[:p, :p]) if p else np.zeros((0, 0))
        at_table.append(a_top[:, :p] @ rinv)
        at_poses.append(np.repeat(a_poses[:, :p] @ rinv, 3, axis=0) * d[:, None])
    shadow = None if outputs.tables else slice(outputs.shadow.start + col.start, outputs.shadow.start + col.stop)
    return _Function(nm, rows, detrend, np.linalg.inv(chol) @ np.eye(n)[keep], q, float(np.log(keep.sum())),
                     sizes, at_table, at_poses, col, shadow)


def _unit_deviations(m: Machine, outputs: Outputs) -> np.ndarray | None:
    """(3 P, n_errors): the tool tip's first-order deviation (x, y, z per pose) per unit of each error, or None
    when the deviation is not linear in the errors (checked on a random error vector)."""
    p = outputs.poses
    ne = len(m.error_names)
    if not len(p):
        return np.zeros((0, ne))
    eye = np.eye(ne)
    d = np.stack([m.deviation(p, np.broadcast_to(eye[j], (len(p), ne)).copy())[:, :3].ravel() for j in range(ne)],
                 axis=1)
    e = np.random.default_rng(0).normal(0.0, 1e-5, ne)
    direct = m.deviation(p, np.broadcast_to(e, (len(p), ne)).copy())[:, :3].ravel()
    return d if np.allclose(d @ e, direct, rtol=1e-9, atol=1e-12) else None


# ---------------------------------------------------------------------------------------------- trials
def fast_block(b: Batched, rec: Recording, trackers: np.ndarray, inputs: Inputs, options: dict, outputs: Outputs,
               seed: int, ks: list[int]) -> tuple[list[int], np.ndarray, dict[str, int]]:
    """Trials ``ks`` batched (module docstring; run on a worker): (ks, output vectors (len(ks), size), counts by
    path).  Trial k draws from ``np.random.default_rng([seed, k])`` as the full path's does."""

    t = len(ks)
    xyz = np.empty((t,) + rec.xyz.shape)
    why: list[str] = []
    prepared = prepare_draw(rec, trackers, inputs)
    for i, k in enumerate(ks):
        xyz[i] = draw(rec, trackers, inputs, np.random.default_rng([seed, k]), prepared)
        why.append(_differs(b, rec, xyz[i]) if k % SAMPLE == 0 else "")
    out, tie = _batched(b, outputs, xyz)
    counts = {"batched": 0, **{r: 0 for r in REASONS}}
    for i, k in enumerate(ks):
        reason = why[i] or ("tie" if tie[i] else "")
        counts[reason or "batched"] += 1
        if reason:  # the full path, trial by trial
            out[i] = trial_block(rec, trackers, inputs, options, outputs, seed, [k])[1][0]
    return ks, out, counts


def _differs(b: Batched, rec: Recording, xyz: np.ndarray) -> str:
    """Why identify would treat these readings otherwise than the campaign's (a reason of ``REASONS``), or ""."""
    from dataclasses import replace

    from mtcal.identify.run import _noise_law
    from mtcal.measurement.screen import screen

    trial = replace(rec, xyz=xyz)
    if screen(trial, b.sides).problems:
        return "screen"
    _, law = _noise_law(trial, b.tracker, [], b.prior, known=True)
    if (law is not None and law.get("source") != "prior") != b.law_replaced:
        return "noise law"
    return ""


def _batched(b: Batched, outputs: Outputs, xyz: np.ndarray, sizes: dict | None = None
             ) -> tuple[np.ndarray, np.ndarray]:
    """(output vectors (T, size), tie (T,) bool) of the trials' readings ``xyz`` (T, n, 3) by the linearised
    estimator; ``sizes``: filled with each function's selected size per trial (the degree, or the number of
    harmonics)."""
    t = len(xyz)
    rw = np.einsum("nij,tnj->tni", b.whiten, xyz - b.xyz0).reshape(t, -1) + b.rw0
    dx = b.gain @ np.asarray(b.js_t @ rw.T)  # (n_params, T)
    resid = rw - np.asarray(b.jw @ dx).T
    b2 = np.einsum("ti,ti->t", resid, resid) / max(b.dof, 1)
    return _outputs(b, outputs, dx, b2, sizes)


def _outputs(b: Batched, outputs: Outputs, dx: np.ndarray, b2: np.ndarray, sizes: dict | None = None
             ) -> tuple[np.ndarray, np.ndarray]:
    """``_batched``'s outputs from the trials' change of the joint estimate dx (n_params, T) and their squared
    Birge ratios b2 (T,)."""
    t = len(b2)
    factor = np.maximum(1.0, b2) * np.clip(b2, 1e-12, 1.0)  # the values' covariance over the campaign's
    means = (b.means @ (b.x0[:, None] + dx)).T  # (T, n_means)
    out = np.zeros((t, outputs.size))
    vol = np.zeros((t, b.volumetric.stop - b.volumetric.start))
    sq = fitting.squareness({nm: means @ w for nm, w in b.slopes.items()})
    for nm, (i, d) in b.constants.items():
        out[:, i] = sq[nm]
        vol += sq[nm][:, None] * d[None, :]
    tie = np.zeros(t, dtype=bool)
    for f in b.functions:
        v = means[:, f.rows] @ f.detrend.T  # the table (T, n_pos), reference-line slope removed
        y = v @ f.whiten.T
        z = y @ f.q
        outside = np.sum((y - z @ f.q.T) ** 2, axis=1)
        tail = np.cumsum((z ** 2)[:, ::-1], axis=1)[:, ::-1]  # sum_{j >= p} z_j^2
        rss = np.column_stack([outside[:, None] + np.hstack([tail, np.zeros((t, 1))])[:, f.sizes]])
        scores = rss / factor[:, None] + f.log_n * np.asarray(f.sizes)[None, :]
        pick = np.argmin(scores, axis=1)
        if scores.shape[1] > 1:
            two = np.partition(scores, 1, axis=1)[:, :2]
            tie |= two[:, 1] - two[:, 0] < TIE
            if sizes is not None:
                sizes.setdefault("gap", []).append(two[:, 1] - two[:, 0])
        if sizes is not None:
            sizes[f.name] = pick
        fitted = np.zeros_like(v)
        for k, p in enumerate(f.sizes):
            sel = pick == k
            if p and sel.any():
                fitted[sel] = z[sel, :p] @ f.at_table[k].T
                vol[sel] += z[sel, :p] @ f.at_poses[k].T
        out[:, f.out] = v if b.tables else fitted
        if f.shadow is not None:
            out[:, f.shadow] = v
    out[:, b.volumetric] = vol
    return out, tie


def self_check(b: Batched, rec: Recording, trackers: np.ndarray, inputs: Inputs, options: dict,
               outputs: Outputs, seed: int, ks: list[int]) -> tuple[bool, dict, tuple]:
    """Trials ``ks`` batched, the first ``CHECK_TRIALS`` of them also by the full path: (whether every output
    agrees within ``CHECK_TOLERANCE`` of its 95 % half-width (2 standard deviations over ``ks``), the check's
    report, the batched block (ks, values, counts))."""

    block = fast_block(b, rec, trackers, inputs, options, outputs, seed, ks)
    vals = block[1]
    first = ks[:CHECK_TRIALS]
    _, full = trial_block(rec, trackers, inputs, options, outputs, seed, first)
    half = 2 * vals.std(axis=0, ddof=1)
    diff = np.abs(vals[:len(first)] - full)
    ratio = np.where(half > 0, diff / np.where(half > 0, half, 1.0), np.where(diff > 1e-9, np.inf, 0.0))
    worst = float(ratio.max())
    report = {"trials": len(first), "largest_difference_of_half_width": worst, "tolerance": CHECK_TOLERANCE,
              "against": f"the spread of {len(ks)} batched trials"}
    return worst <= CHECK_TOLERANCE, report, block
