"""Batched trials: the Monte Carlo of the joint estimator with the design factorised once (issue 37).

A trial of the full path (mtcal.uncertainty.trials.trial_block) runs ``identify`` from scratch: the screen, the noise
law's shape test, the joint fit's Gauss-Newton steps from a rough start, the degree selection of every function.
But a trial's readings differ from the campaign's by micrometres, so its joint estimate is two Gauss-Newton steps
from the campaign's, both with the campaign's factorisation.  With the whitened Jacobian J, the gauge rows C and the
column scale S of the campaign's estimate x0 (mtcal.identify.joint.linearised), the first step is

    dx1 = S K (S J^T W (y - f(x0)))       (K: the top-left block of the inverse of the scaled KKT matrix)

for every trial at once (a sparse product and one dense product over a block of trials).  It is first order: a
trial moves the reflectors by up to ~20 um and the poorly resolved rotation errors by up to ~0.5 mrad, so the
Jacobian identify builds at the trial's estimate has turned by ~2e-4 and the model has moved by its bilinear terms
(rotation x lever, station rotation x point) beyond J dx1: identify's converged fit differs from dx1 by up to 4.5 %
of a parameter's standard deviation (X and C from one station; measured against 6 Gauss-Newton steps, which agree
with identify's 2 to 0.03 %).  The second step (``_second``) is the Gauss-Newton step from x0 + dx1 to second
order, per distinct reading (an axis pose, a key, a reflector, a station: the rounds repeat them), batched: the
Jacobian's turn (exactly linear in the reflector's and the point's moves) and the model's second-order terms
(differences of the exact model, once, ``_second_order``) give the gradient there, and the campaign's K the step.
What is left is third order and the trial's own weights: 0.1-0.2 % of a standard deviation.

Everything after the joint fit is linear in x given the degrees chosen: each axis' table (mean over directions),
the reference lines' slopes and the squareness, each function's values.  identify fits them by generalised least
squares with the covariance of its trial's fit, which has turned with the Jacobian too: per unit move of each
reflector coordinate d cov = -cov dN cov (``_turns``), and a function fitted with the campaign's covariance moves
by up to 1.8 % of its 95 % half-width (E_CC, 6 harmonics).  So per trial and function the covariance is the
campaign's plus its turn, times the trial's Birge factor b^2 (mtcal.identify.build._value_covariance), its
Cholesky factor L whitens the values, y = L^-1 v, and one QR of the whitened largest design, L^-1 A = Q R, gives
every candidate degree's residual sum of squares from z = Q^T y (the designs are nested: a polynomial's degree d is
the first d columns of degree d + 1; a harmonic series likewise by pairs): rss_d = |y - Q z|^2 + sum_{j >= p_d}
z_j^2, the BIC score rss_d / b^2 + p_d ln n as ``_gls`` computes it, the selected degree and its coefficients
R_d^-1 z_<p_d> at the table positions and at the poses (the tool tip's first-order deviation is linear in the
errors); batched over the trials (``_nested``).  Trial for trial (tests/test_uncertainty_fast.py) every error and
constant agrees with identify's within 0.1 % of its 95 % half-width.

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
from mtcal.uncertainty.trials import Outputs, Prepared, draw_many, prepare_draw, trial_block

log = logging.getLogger(__name__)
BLOCK = 200  # trials per batch (per Dask task): ~0.3 s on one core
TIE = 1e-5  # a degree selection whose best two BIC scores are this close (chi^2 units) is left to the full path (the
# batched and the full path chose the same degrees in every trial compared, gaps down to 0.004 included; at 1e-3,
# 0.7 % of the demo's trials were ties, and their identify runs cost more than all batched trials together)
CHECK_TRIALS = 3  # trials run both ways before the rest
CHECK_TOLERANCE = 0.01  # of an output's 95 % half-width (2 standard deviations of the batched trials): the issue's
# "every error within 1 % of its u95"; measured (tests/test_uncertainty_fast.py) <= 0.1 % on one and four stations,
# the demo campaign and the head-B machine (before the second step and the covariance's turn: up to 4 %)
REASONS = ("screen", "noise law", "tie")
SAMPLE = 1000  # the screen and the shape test (a hundred batched trials' time each) run on every SAMPLE-th trial


@dataclass
class _Function:
    """One error function's degree selection, linear in the axis' table: where its values sit in the axis' means,
    the slope removal, the positions the fit weighs (``keep``), the whitening L^-1 of the values' covariance at
    the campaign's estimate (``whiten``, with ``_gls``'s floor), the QR of the whitened largest design
    (``q``, ``r_inv``: R^-1), the covariance's turn whitened, per unit move of each reflector coordinate
    (``turn`` (R, k * k): a trial's whitened covariance is I + dw . turn, then times its Birge factor), the largest
    design at every table position (``a_top``) and the tool tip's deviation at the poses per coefficient
    (``a_poses``)."""

    name: str
    rows: np.ndarray  # indices into the stacked means (n_pos,)
    detrend: np.ndarray  # (n_pos, n_pos): table values from the means (the reference-line slope removed)
    keep: np.ndarray  # (n_pos,) bool
    whiten: np.ndarray  # (k, k)
    q: np.ndarray  # (k, p_top)
    r_inv: np.ndarray  # (p_top, p_top) upper triangular
    turn: np.ndarray  # (R, k * k)
    a_top: np.ndarray  # (n_pos, p_top)
    a_poses: np.ndarray  # (3 n_poses, p_top)
    log_n: float
    sizes: list[int]  # columns of each candidate
    out: slice
    shadow: slice | None


@dataclass
class _Second:
    """What the second Gauss-Newton step needs (``_second``), per distinct reading (``u``: an axis pose, an error
    key, a reflector and a station; the rounds repeat them): the columns of its 15 local parameters (``cols``
    (u, 15): its key's six error motions, -1 at the reference, its reflector's three coordinates, its station's
    six), the unwhitened Jacobian blocks identify builds at the campaign's estimate (``jac_e`` (u, 3, 6),
    ``rot`` (u, 3, 3)) and their turn (``d_jac_e`` (u, 3 (k), 3, 6) = d jac_e / d w_k; ``d_jac_a`` (9, 6) =
    d point_rows / d p_k, stacked over (k, output)); the model's departure from identify's Jacobian to second
    order: ``lin`` (u, 15, 3) and, over the local parameters ``used`` in a second-order term, ``hess`` (u, d,
    3 d): Q_o = sum z_d hess[d, e, o] z_e;
    ``spread`` (3 u, 3 n) sums W_i^T over a distinct reading's rows, its transpose spreads back with W_i;
    ``to_e``, ``to_a`` (n_params, 6 u) map per-reading gradients onto the parameters; ``scale`` the column
    scale."""

    cols: np.ndarray
    has: np.ndarray
    inv: np.ndarray  # (n,) each reading's distinct reading
    jac_e: np.ndarray
    rot: np.ndarray
    d_jac_e: np.ndarray
    d_jac_a: np.ndarray
    lin: np.ndarray
    used: np.ndarray
    hess: np.ndarray
    spread: object
    to_e: object
    to_a: object
    scale: np.ndarray


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
    second: _Second | None = None
    drawing: tuple[Inputs, Prepared] | None = None  # prepare_draw's, made once per worker and inputs (fast_block)
    turn_cols: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))  # reflector coordinates (R,)
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
    if not screen(rec, m.sides).keep.all():
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
                prior, t, _second_order(rec, m, res, whiten, scale))
    why = _functions(b, res, m, options, outputs, keys_of)
    return (None, why) if why else (b, "")


SECOND_FLOOR_MM = 1e-8  # a second-order term whose effect at one standard deviation of its parameters is below this
# (mm at a reading) is left out of the second step (the readings' noise is >= 1e-4 mm)


def _second_order(rec: Recording, m: Machine, res, whiten: np.ndarray, scale: np.ndarray) -> _Second:
    """``_Second`` at the campaign's joint estimate ``res`` (mtcal.identify.joint): identify's Jacobian blocks
    (``joint._state``) on the distinct readings, their turn, the model's departure from them (``_departure``) and
    the maps between readings, distinct readings and parameters."""
    import scipy.sparse as sps

    from mtcal.generated import threepoint_numpy as tp
    from mtcal.identify import joint as jt

    lay = res.layout
    sides = np.array([m.side(str(a)) for a in rec.axis])
    keys = jt._direction_keys(rec)
    q = jt._axes_matrix(m, rec)
    wcol, ecol, _, acol = jt._rows(m, rec, lay, keys, sides)
    _, first, inv = np.unique(np.column_stack([q, ecol, wcol, acol]), axis=0, return_index=True,
                              return_inverse=True)
    inv = inv.ravel()
    args = (m, q[first], sides[first], jt._rows(m, rec.select(first), lay, keys[first], sides[first]))
    has = ecol[first] >= 0
    cols = np.column_stack([np.where(has[:, None], ecol[first, None] + np.arange(6), 0),
                            wcol[first, None] + np.arange(3), acol[first, None] + np.arange(6)])
    nu, n = len(first), len(rec)
    jac_e, rot, lin, used, hess, d_e = _departure(res, args, cols, has)
    zero = tp.point_rows(np.zeros((1, 3)))[0]
    d_a = np.stack([tp.point_rows(np.eye(3)[k:k + 1])[0] - zero for k in range(3)])  # (k, 3, 6)
    rows = (3 * inv)[:, None, None] + np.arange(3)[None, :, None]
    cc = (3 * np.arange(n))[:, None, None] + np.arange(3)[None, None, :]
    wt = whiten.transpose(0, 2, 1)  # W_i^T: row (u, o) <- column (i, p)
    spread = sps.csr_matrix((wt.ravel(), (np.broadcast_to(rows, wt.shape).ravel(),
                                          np.broadcast_to(cc, wt.shape).ravel())), shape=(3 * nu, 3 * n))
    flat = np.arange(6 * nu).reshape(nu, 6)
    to_e = sps.csr_matrix((np.ones(int(has.sum()) * 6), (cols[has, :6].ravel(), flat[has].ravel())),
                          shape=(lay.n, 6 * nu))
    to_a = sps.csr_matrix((np.ones(6 * nu), (cols[:, 9:].ravel(), flat.ravel())), shape=(lay.n, 6 * nu))
    return _Second(cols, has, inv, jac_e, rot, d_e, d_a.reshape(9, 6), lin, used, hess, spread.tocsr(), to_e, to_a,
                   scale)


def _departure(res, args: tuple, cols: np.ndarray, has: np.ndarray):
    """(jac_e, rot, lin, used, hess, d_jac_e) of ``_Second`` on the distinct readings (``args`` for
    ``joint._state_at``; ``cols`` (u, 15) their local parameters' columns, ``has``: not at the reference): by
    differences of the exact model, each of the 15 local parameters moved in every distinct reading at once (steps
    of 1 mm and 1 mrad: the model is quadratic in the lengths and nearly so in the small angles), its first- and
    second-order departure from identify's Jacobian; a term is kept where it moves a reading by more than
    ``SECOND_FLOOR_MM`` at one standard deviation of its parameters."""
    from mtcal.identify import joint as jt

    f0, (_, jac_e), (_, rot), (_, jac_a) = jt._state_at(*args, res.x)
    h = np.array([1.0] * 3 + [1e-3] * 3 + [1.0] * 3 + [1.0] * 3 + [1e-3] * 3)  # (E_X.., E_A..: mm, rad; w mm;
    # the station's translations mm, rotations rad: mtcal.identify.joint)
    vec = []
    for d in range(15):
        v = np.zeros(len(res.x))
        v[np.unique(cols[has if d < 6 else slice(None), d])] = h[d]
        vec.append(v)

    def f(x):
        return jt._state_at(*args, x)[0]

    plus, minus = [f(res.x + v) for v in vec], [f(res.x - v) for v in vec]
    jl = np.concatenate([jac_e, rot, jac_a], axis=2)  # (u, 3, 15): identify's J
    lin = np.stack([(plus[d] - minus[d]) / (2 * h[d]) for d in range(15)], axis=1) - jl.transpose(0, 2, 1)
    lin[~has, :6] = 0.0
    sd = np.sqrt(np.maximum(np.diagonal(res.covariance), 0.0))
    sd_local = np.array([sd[cols[has if d < 6 else slice(None), d]].max(initial=0.0) for d in range(15)])
    lin[:, sd_local * np.abs(lin).max(axis=(0, 2)) <= SECOND_FLOOR_MM] = 0.0
    terms = {}
    for d in range(15):
        for e in range(d, 15):
            if sd_local[d] == 0 or sd_local[e] == 0:
                continue
            hq = ((plus[d] + minus[d] - 2 * f0) / h[d] ** 2 / 2 if d == e else
                  (f(res.x + vec[d] + vec[e]) - plus[d] - plus[e] + f0) / (h[d] * h[e]))
            if d < 6:
                hq[~has] = 0.0
            if np.abs(hq).max() * sd_local[d] * sd_local[e] > SECOND_FLOOR_MM:
                terms[(d, e)] = hq
    used = np.array(sorted({d for pr in terms for d in pr}), dtype=int)
    hess = np.zeros((len(f0), len(used), len(used), 3))  # Q_o = sum_de z_d H[d, e, o] z_e over the terms kept
    for (d, e), hq in terms.items():
        hess[:, np.searchsorted(used, d), np.searchsorted(used, e)] += hq
    d_e = np.stack([jt._state_at(*args, res.x + vec[6 + k])[1][1] - jac_e for k in range(3)], axis=1) / h[6]
    return jac_e, rot, lin, used, hess.reshape(len(f0), len(used), 3 * len(used)), d_e


def _second(b: Batched, s: _Second, dx: np.ndarray, resid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The second Gauss-Newton step of every trial from its first (dx (n_params, T), its whitened residual
    resid (3 n, T)): (dx2 (n_params, T), the whitened residual after it (3 n, T)).

    identify's fit stops where J(x)^T W^T r(x) = 0 (J: the Jacobian it builds at x, W: the whitening, r: the
    whitened residual).  At x0 + dx its Jacobian has turned (the error motions' columns with the reflector's
    move dw: d_jac_e[dw]; the station's with the point's move dp = jac_e de + rot dw: d_jac_a[dp]) and the model
    has moved by Q beyond J dx (its second-order terms, and where identify's Jacobian is not the model's exact
    one); per distinct reading, the gradient there is to second order g = dJ^T W^T r - J^T W^T W Q, and the
    step dx2 = S K S g with the campaign's factorisation (its change is third order).  Measured on X and C from
    one station: identify's fit minus the one linear step up to 4.5 % of a parameter's standard deviation."""
    t = dx.shape[1]
    nu = len(s.has)
    z = dx[s.cols].transpose(0, 2, 1)  # (u, T, 15)
    z[~s.has, :, :6] = 0.0
    de, dw = z[..., :6], z[..., 6:9]
    dp = np.matmul(de, s.jac_e.transpose(0, 2, 1)) + np.matmul(dw, s.rot.transpose(0, 2, 1))  # (u, T, 3)
    q = np.matmul(z, s.lin)  # (u, T, 3) mm
    if len(s.used):
        zu = np.ascontiguousarray(z[..., s.used])
        q += np.einsum("utd,utdo->uto", zu, np.matmul(zu, s.hess).reshape(nu, t, len(s.used), 3))
    sr = np.asarray(s.spread @ resid).reshape(nu, 3, t).transpose(0, 2, 1)  # (u, T, 3): sum of W^T r
    ge = np.matmul((dw[..., :, None] * sr[..., None, :]).reshape(nu, t, 9),
                   s.d_jac_e.reshape(nu, 9, 6))  # (u, T, 6)
    ga = (dp[..., :, None] * sr[..., None, :]).reshape(nu, t, 9) @ s.d_jac_a
    wq = np.asarray(s.spread.T @ q.transpose(0, 2, 1).reshape(3 * nu, t))  # (3 n, T): W Q per reading
    g = (s.scale[:, None] * np.asarray(s.to_e @ ge.transpose(0, 2, 1).reshape(6 * nu, t)
                                       + s.to_a @ ga.transpose(0, 2, 1).reshape(6 * nu, t))
         - np.asarray(b.js_t @ wq))
    dx2 = b.gain @ g
    return dx2, resid - wq  # J dx2 left out: r . J dx2 = lambda . C dx2 = 0 (the gauge), |J dx2|^2 fourth order


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
    b.turn_cols, turns = _turns(b, res)
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
        c_all, dc_all = _table_covariance(res, axis, positions, turns)  # a trial scales it by its Birge ratio
        for i, nm in enumerate(m.error_motions(axis)):
            if nm not in outputs.functions or not np.array_equal(outputs.functions[nm][1], positions):
                return f"the outputs' positions of {nm} are not identify's table"
            b.functions.append(_function(b, m, nm, axis, i, positions, row, c_all, dc_all, periodic,
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


def _turns(b: Batched, res) -> tuple[np.ndarray, list]:
    """(the reflector coordinates' columns (R,), the normal matrix' turn per unit move of each, dN_r =
    J^T dJ_r + dJ_r^T J, scipy.sparse (n_params, n_params)): identify's Jacobian of a trial turns with its
    reflectors' moves (the error motions' columns, ``_Second.d_jac_e``), and so does the covariance its fits
    weigh by.  The station columns' turn with the point's move is left out: one station's are held by the gauge;
    on four stations the trials still agree with identify within 1 % (tests/test_uncertainty_fast.py)."""
    import scipy.sparse as sps

    s = b.second
    lay = res.layout
    cols = np.array(sorted(c + k for c in lay.reflectors.values() for k in range(3)), dtype=int)
    if s is None:
        return np.zeros(0, dtype=int), []
    wd = np.einsum("nop,nkpj->nkoj", b.whiten, s.d_jac_e[s.inv])  # (n, k, 3, 6) whitened
    ecol = s.cols[s.inv, :6]
    has = s.has[s.inv]
    wcol = s.cols[s.inv, 6]
    turns = []
    for c in cols:
        out = []
        for k in range(3):
            on = np.flatnonzero(has & (wcol + k == c))
            if len(on):
                rows = np.broadcast_to((3 * on)[:, None, None] + np.arange(3)[None, :, None], (len(on), 3, 6))
                cc = np.broadcast_to(ecol[on][:, None, :], (len(on), 3, 6))
                out.append((wd[on, k].ravel(), rows.ravel(), cc.ravel()))
        if out:
            data, r, cc = (np.concatenate(v) for v in zip(*out))
            dj = sps.csr_matrix((data, (r, cc)), shape=b.jw.shape)
            dn = (b.jw.T @ dj).tocsr()
            turns.append((dn + dn.T).tocsr())
        else:
            turns.append(sps.csr_matrix((lay.n, lay.n)))
    return cols, turns


def _table_covariance(res, axis: str, positions: np.ndarray, turns: list) -> tuple[np.ndarray, np.ndarray]:
    """(n_pos * 6, n_pos * 6) the covariance of an axis' table from the joint covariance, before the Birge ratio
    (mtcal.identify.joint.axis_result scales it by max(1, b^2), mtcal.identify.build._value_covariance by
    min(1, b^2): a trial's values are fitted with b^2 times this), and its turn (R, n_pos * 6, n_pos * 6) per
    unit move of each reflector coordinate: d cov = -cov dN_r cov (``_turns``)."""
    import scipy.sparse as sps

    keys, _, cov = res.errors(axis)
    avg = np.zeros((len(positions), len(keys)))
    for ik, k in enumerate(keys):
        avg[np.searchsorted(positions, k[0]), ik] = 1.0
    avg /= avg.sum(axis=1, keepdims=True)
    big = np.kron(avg, np.eye(6))
    lay = res.layout
    first = np.array([lay.err_index.get((axis, *k), -1) for k in keys])
    known = np.repeat(first >= 0, 6)
    cols = (np.maximum(first, 0)[:, None] + np.arange(6)).ravel()
    g = big @ (res.covariance[cols, :] * known[:, None])  # (n_pos * 6, n_params)
    if turns:  # all reflector coordinates at once: (R n_params, n_params) @ g^T, then g @ each block
        r = len(turns)
        dng = np.asarray(sps.vstack(turns).tocsr() @ np.ascontiguousarray(g.T)).reshape(r, len(g.T), len(g))
        turn = -np.matmul(g[None], dng)
    else:
        turn = np.zeros((0,) + (len(big),) * 2)
    return big @ cov.reshape(6 * len(keys), 6 * len(keys)) @ big.T, turn


def _function(b: Batched, m: Machine, nm: str, axis: str, i: int, positions: np.ndarray, row: int, c_all: np.ndarray,
              dc_all: np.ndarray, periodic: bool, x_ref: float, max_degree: int, max_harmonics: int, reference: str,
              outputs: Outputs, dev: np.ndarray) -> _Function:
    """One function's selection as fitting.fit_polynomial / fit_harmonic with the joint covariance (``_gls``)."""
    n = len(positions)
    rows = row + np.arange(n) * 6 + i
    cov = c_all[i::6, i::6]
    dcov = dc_all[:, i::6, i::6]
    detrend = np.eye(n)
    if nm in b.slopes:
        g = fitting.slope_weights(positions, reference)
        detrend = np.eye(n) - np.outer(positions, g)
        cov = detrend @ cov @ detrend.T
        dcov = detrend @ dcov @ detrend.T
    keep = (np.diagonal(cov) > 0) & (positions != x_ref)
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
    lo, hi = float(positions.min()), float(positions.max())
    col = outputs.functions[nm][2]
    pose_x = outputs.poses[:, m.index(axis)] if len(outputs.poses) else np.zeros(0)
    pose_x = pose_x if periodic else np.clip(pose_x, lo, hi)
    d = dev[:, m.error_names.index(nm)]  # (3 P,) deviation per unit of this error at each pose
    a_poses = np.repeat(design(pose_x, top), 3, axis=0) * d[:, None]
    shadow = None if outputs.tables else slice(outputs.shadow.start + col.start, outputs.shadow.start + col.stop)
    ck, dk = cov[np.ix_(keep, keep)], dcov[:, keep][:, :, keep]
    k = len(ck)
    wl = np.linalg.inv(np.linalg.cholesky(ck + 1e-6 * np.trace(ck) / k * np.eye(k)))
    floor = 1e-6 * np.trace(dk, axis1=1, axis2=2) / k  # the floor moves with the trace
    turn = wl[None] @ (dk + floor[:, None, None] * np.eye(k)[None]) @ wl.T[None]
    q, r = np.linalg.qr(wl @ a_top[keep])
    return _Function(nm, rows, detrend, keep, wl, q, np.linalg.inv(r) if r.size else r,
                     turn.reshape(len(dk), k * k), a_top, a_poses, float(np.log(keep.sum())), sizes, col, shadow)


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

    if b.drawing is None or b.drawing[0] != inputs:  # kept on the worker's copy for its next blocks
        b.drawing = (inputs, prepare_draw(rec, trackers, inputs))
    xyz = draw_many(rec, trackers, inputs, seed, ks, b.drawing[1])
    why = [_differs(b, rec, xyz[i]) if k % SAMPLE == 0 else "" for i, k in enumerate(ks)]
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
    if not screen(trial, b.sides).keep.all():
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
    dx, b2 = _step(b, xyz)
    return _outputs(b, outputs, dx, b2, sizes)


def _step(b: Batched, xyz: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(the trials' change of the joint estimate dx (n_params, T), their squared Birge ratios (T,)) from their
    readings ``xyz`` (T, n, 3) mm (fastest as ``draw_many`` lays them out, trials last in memory): the linear step
    from the campaign's estimate, then the second Gauss-Newton step (``_second``).  Residuals are kept (3 n, T)."""
    t = len(xyz)
    d = (xyz - b.xyz0[None]).transpose(1, 2, 0)  # (n, 3, T)
    rw = np.matmul(b.whiten, d).reshape(-1, t) + b.rw0[:, None]  # (3 n, T) whitened
    dx = b.gain @ np.asarray(b.js_t @ rw)  # (n_params, T)
    resid = rw - np.asarray(b.jw @ dx)
    if b.second is not None:
        dx2, resid = _second(b, b.second, dx, resid)
        dx = dx + dx2
    b2 = np.einsum("it,it->t", resid, resid) / max(b.dof, 1)
    return dx, b2


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
    dw = dx[b.turn_cols].T  # (T, R) the reflectors' moves: the covariance's turn
    for f in b.functions:
        v = means[:, f.rows] @ f.detrend.T  # the table (T, n_pos), reference-line slope removed
        z, rss, er = _nested(f, v, dw)
        scores = rss / factor[:, None] + f.log_n * np.asarray(f.sizes)[None, :]
        pick = np.argmin(scores, axis=1)
        if scores.shape[1] > 1:
            two = np.partition(scores, 1, axis=1)[:, :2]
            tie |= two[:, 1] - two[:, 0] < TIE
            if sizes is not None:
                sizes.setdefault("gap", []).append(two[:, 1] - two[:, 0])
        if sizes is not None:
            sizes[f.name] = pick
        top = f.q.shape[1]
        fitted = np.zeros_like(v)
        if top:  # the selected size's coefficients c = R_p^-1 z_eff,<p: R^-1 is upper triangular
            p = np.asarray(f.sizes)[pick]
            z_eff = z - er[np.arange(t), pick] @ f.q
            coef = np.where(np.arange(top)[None, :] < p[:, None], z_eff, 0.0) @ f.r_inv.T
            fitted = coef @ f.a_top.T
            vol += coef @ f.a_poses.T
        out[:, f.out] = v if b.tables else fitted
        if f.shadow is not None:
            out[:, f.shadow] = v
    out[:, b.volumetric] = vol
    return out, tie


def _nested(f: _Function, v: np.ndarray, dw: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(each trial's z_eff (T, p_top): R c = z_eff for its coefficients c of every candidate size (the
    columns from the size on left to the caller), each candidate's residual sum of squares (T, n_sizes)) of the
    trials' tables ``v`` (T, n_pos) with the whitened covariance I + E, E = dw . turn (~1e-3), to first order in E
    (the second order is ~1e-6 of the fit): y = L^-1 v, z = Q^T y, the candidates' residuals r_p = y - Q_p z_p,
    rss_p = |r_p|^2 - r_p^T E r_p and z_eff = z - Q^T E r_p (the generalised least squares' first-order change,
    (A^T A)^-1 A^T (-E) r_p)."""
    t = len(v)
    y = v[:, f.keep] @ f.whiten.T  # (T, k)
    z = y @ f.q  # (T, p_top)
    k, top = f.q.shape
    steps = np.zeros((t, top + 1, k))
    steps[:, 1:] = np.cumsum(z[:, :, None] * f.q.T[None], axis=1)  # Q_p z_p for p = 0 .. top
    resid = y[:, None, :] - steps[:, f.sizes]  # (T, n_sizes, k)
    if len(f.turn):
        e = (dw @ f.turn).reshape(t, k, k)
        er = resid @ e  # E symmetric: (E r_p)^T
    else:
        er = np.zeros_like(resid)
    rss = np.sum(resid * (resid - er), axis=2)
    return z, rss, er


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
