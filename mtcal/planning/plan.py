"""Measurement planning: the standard uncertainty of every identified error for a tracker placement.

Estimator: mtcal.identify.threepoint.estimate, the one three-point estimator (Zhang & Hu, thesis ch. 3): at one
position q
of one round the readings r_i(q) of the reflectors (P, Q, K) and their reference readings r_i(q0) (the position
closest to zero, same round) give 3 k equations for the six error motions of the measured axis (E_X<J> ..
E_C<J>), written in the axis' own frame F (Machine.axis_frame) with the generated design rows; the reflector
coordinates are taken from the reference readings themselves, as on the machine.  With ``--tracker`` the
equations are weighted by the AT960 covariance (mtcal.measurement.tracker) of the reading AND of its reference reading
(mtcal.identify.threepoint.delta_covariance); the solution is generalised least squares through whitening and QR.

Linear propagation: Cov(e) = A Sigma A^T with A = (J^T W J)^-1 J^T W (W = Sigma^-1 for "tracker"
weighting, I for "none"), i.e. J+ Sigma J+^T.  Monte Carlo (GUM Supplement 1): draw tracker noise for the
readings and reference readings, run the same estimator on each draw, take the sample standard deviation.
Units: mm for E_X*, E_Y*, E_Z*, rad for the angular errors.
"""
from __future__ import annotations

import logging
import math
from dataclasses import asdict, dataclass, field, replace
from typing import Iterable

import numpy as np

from mtcal.campaign.plans import Plan, as_plan
from mtcal.errors import InputError
from mtcal.generated import threepoint_numpy as tp
from mtcal.identify.threepoint import delta_covariance, estimate, frame_data
from mtcal.io import save_figure
from mtcal.kinematics.defaults import tracker_positions
from mtcal.kinematics.machine import DEFAULT_MACHINE, Machine, load_machine
from mtcal.measurement import tracker as trk
from mtcal.planning.joint import joint_monte_carlo, joint_sigma

WEIGHTINGS = ("tracker", "none")
ESTIMATORS = ("auto", "joint", "three-point")  # auto: what identify uses (joint with a tracker position)
log = logging.getLogger(__name__)


def nominal_points(machine: Machine, axis: str, axes: np.ndarray, local: np.ndarray) -> np.ndarray:
    """Nominal machine-frame positions (..., 3) of reflectors ``local`` (..., 3) at axis positions (..., n_axes)."""
    axes, local = np.asarray(axes, dtype=float), np.asarray(local, dtype=float)
    lead = np.broadcast_shapes(axes.shape[:-1], local.shape[:-1])
    return machine.points(axis, np.broadcast_to(axes, lead + axes.shape[-1:]), np.broadcast_to(local, lead + (3,)))


def _design(machine: Machine, plan: Plan, axis: str, positions, tracker, spec: trk.TrackerSpec):
    """Nominal readings and the estimator's design at ``positions`` (P,): (axes (P, n_axes), axes0 (n_axes,),
    r (P, k, 3), r0 (k, 3), design rows in F (P, k, 3, 6), covariance of a reading's and of the reference
    reading's share of the deltas in F (P, k, 3, 3) each)."""
    pos = np.atleast_1d(np.asarray(positions, dtype=float))
    local = np.array(list(plan.points_for(axis).values()), dtype=float)          # (k, 3)
    ax = plan.axis_values(axis, pos)                                             # (P, n_axes)
    ax0 = plan.axis_values(axis, plan.reference_position(axis))
    r = nominal_points(machine, axis, ax[:, None, :], local)                     # (P, k, 3)
    r0 = nominal_points(machine, axis, ax0, local)                               # (k, 3)
    pts, _, rf, _, rrel = frame_data(machine, axis, ax, ax0, r, np.broadcast_to(r0, r.shape))
    c_read, c_ref = delta_covariance(r, np.broadcast_to(r0, r.shape), rrel, rf, tracker, parts=True, spec=spec)
    return ax, ax0, r, r0, tp.point_rows(pts), c_read, c_ref


def linear_covariance(machine: Machine, plan: Plan, axis: str, positions, tracker,
                      weighting: str = "tracker", spec: trk.TrackerSpec = trk.AT960, approaches: int = 1) -> np.ndarray:
    """Cov (P, 6, 6) of the six identified errors of ``axis`` at ``positions`` (P,) for one round.

    Each of ``approaches`` passes (1, or 2 for out and back) has one reading per reflector; all share the round's
    reference reading; the pass solutions are averaged (as mtcal.identify.threepoint does).  With A = (J^T W J)^-1
    J^T W the
    per-pass estimator (W = Sigma_pass^-1 for weighting "tracker", I for "none"), Cov = A Sigma_round A^T with
    Sigma_round = C(r) / approaches + R_rel C(r0) R_rel^T: J+ Sigma J+^T.  For one pass and "tracker"
    weighting this is (J^T Sigma^-1 J)^-1 = R^-1 R^-T from the QR of the whitened design."""
    if weighting not in WEIGHTINGS:
        raise InputError(f"weighting must be one of {WEIGHTINGS}, got {weighting!r}")
    if int(approaches) != approaches or approaches < 1:
        raise InputError(f"approaches must be a positive integer, got {approaches!r}")
    tracker = np.asarray(tracker, dtype=float)
    _, _, _, _, jac, c_read, c_ref = _design(machine, plan, axis, positions, tracker, spec)
    n_p, k = jac.shape[:2]
    c_pass = c_read + c_ref                                                      # (P, k, 3, 3) in F
    c_round = c_read / approaches + c_ref
    if weighting == "tracker":
        lc = np.linalg.cholesky(c_pass)                                          # whitening of one pass
        jw = np.linalg.solve(lc, jac).reshape(n_p, 3 * k, 6)
        q, rr = np.linalg.qr(jw)
        rinv = np.linalg.inv(rr)   # 6x6 triangular of the whitened design: Cov = R^-1 R^-T for one pass
        if approaches == 1:
            return rinv @ np.swapaxes(rinv, -1, -2)
        g = np.linalg.solve(lc, np.linalg.solve(lc, c_round).swapaxes(-1, -2))   # L^-1 S L^-T per reflector
        s = np.zeros((n_p, 3 * k, 3 * k))
        for i in range(k):
            s[:, 3 * i:3 * i + 3, 3 * i:3 * i + 3] = g[:, i]
        a = rinv @ np.swapaxes(q, -1, -2)                                        # (P, 6, 3k) on whitened data
        return a @ s @ np.swapaxes(a, -1, -2)
    s = np.zeros((n_p, 3 * k, 3 * k))
    for i in range(k):
        s[:, 3 * i:3 * i + 3, 3 * i:3 * i + 3] = c_round[:, i]
    pinv = np.linalg.pinv(jac.reshape(n_p, 3 * k, 6))                            # (P, 6, 3k)
    return pinv @ s @ np.swapaxes(pinv, -1, -2)


def monte_carlo(machine: Machine, plan: Plan, axis: str, positions, tracker, n: int, seed: int = 0,
                weighting: str = "tracker", spec: trk.TrackerSpec = trk.AT960, approaches: int = 1,
                chunk: int = 2000) -> np.ndarray:
    """Estimates (n, P, 6) of the six errors of ``axis`` from n simulated rounds (zero true errors, AT960 noise
    on every reading and on the shared reference reading; ``approaches`` passes per round, solutions averaged),
    each through mtcal.identify.threepoint.estimate."""
    tracker = np.asarray(tracker, dtype=float)
    ax, ax0, r, r0, _, _, _ = _design(machine, plan, axis, positions, tracker, spec)
    n_p, k = r.shape[:2]
    ch_r = np.linalg.cholesky(trk.covariance(r, tracker, spec))
    ch_0 = np.linalg.cholesky(trk.covariance(r0, tracker, spec))
    rng = np.random.default_rng(seed)
    out = np.empty((n, n_p, 6))
    step = max(1, chunk // approaches)
    for s in range(0, n, step):
        m = min(step, n - s)
        rr = r + np.einsum("pkij,napkj->napki", ch_r, rng.standard_normal((m, approaches, n_p, k, 3)))
        rr0 = r0 + np.einsum("kij,nkj->nki", ch_0, rng.standard_normal((m, k, 3)))
        est = estimate(machine, axis, ax, ax0, rr, np.broadcast_to(rr0[:, None, None], rr.shape),
                       None if weighting == "none" else tracker, spec)[0]
        out[s:s + m] = est.mean(axis=1)
    return out


def mid_position(plan: Plan, axis: str) -> float:
    """The plan position closest to mid-travel, other than the reference position (where the errors are zero by
    definition: a travel symmetric about zero would otherwise report the reference)."""
    p = plan.positions[axis]
    mid = (p.min() + p.max()) / 2
    p = p[p != plan.reference_position(axis)]
    return float(p[np.argmin(np.abs(p - mid))])


def _machine_and_plan(machine, plan) -> tuple[Machine, Plan]:
    """The machine (given, else the plan's, else the default) and the plan for it."""
    if machine is None:
        machine = plan.machine if isinstance(plan, Plan) else DEFAULT_MACHINE
    m = machine if isinstance(machine, Machine) else load_machine(machine)
    return m, as_plan(plan, m)


@dataclass
class PlanResult:
    """The answer of `mtcal plan` (mm and rad): predicted standard uncertainties of the identified errors.

    Attributes
    ----------
    tracker : list of float
        The tracker position, mm, machine frame.
    machine : str
        The machine spec.
    weighting : str
        ``"tracker"`` (the noise law's covariance) or ``"none"``.
    rounds : int
        Rounds of the plan.
    approaches_per_round : int
        2 when each position is approached out and back, else 1.
    estimator : str
        What was predicted (the joint fit or the three-point method) and how.
    mid_travel : dict of str to float
        Per axis the position the ``axes`` figures are at, mm or deg.
    axes : dict of str to dict
        Per axis, per error name: the standard uncertainty of one round's value at mid-travel, mm or rad.
    mean_of_rounds : dict of str to dict
        The same for the mean of ``rounds`` rounds.
    by_position : dict of str to dict
        Per axis the figures at every planned position.
    monte_carlo : dict or None
        The Monte Carlo check of the linear prediction, when asked (``monte_carlo_n``).
    stations : dict of str to list of float, or None
        The plan's tracker stations, when several.
    """

    tracker: list[float]
    machine: str
    weighting: str
    rounds: int
    approaches_per_round: int
    estimator: str
    mid_travel: dict[str, float] = field(default_factory=dict)
    axes: dict[str, dict[str, float]] = field(default_factory=dict)
    mean_of_rounds: dict[str, dict[str, float]] = field(default_factory=dict)
    by_position: dict[str, dict] = field(default_factory=dict)
    monte_carlo: dict | None = None
    stations: dict[str, list[float]] | None = None

    def to_dict(self) -> dict:
        out = {"units": {"length": "mm", "angle": "rad"}, **asdict(self)}
        for k in ("monte_carlo", "stations"):
            if out[k] is None:
                del out[k]
        return out


def plan_uncertainty(tracker=None, plan=None, *, machine: str | Machine | None = None, monte_carlo_n: int = 0,
                     seed: int = 0, weighting: str = "tracker", axes: Iterable[str] | None = None,
                     estimator: str = "auto", tracker_model=None) -> PlanResult:
    """Predict, before measuring, how well a plan identifies every error: the answer of `mtcal plan`.

    The prediction is of the estimator ``identify`` will use with the same inputs: the joint weighted fit
    (mtcal.planning.joint, linear propagation at the plan's nominal readings; ``monte_carlo_n`` noisy campaigns
    through the same fit to check it), or the three-point method (``linear_covariance`` / ``monte_carlo`` of this
    module).  ``identify`` uses the joint fit when it has a tracker position, given or estimated from the rounds'
    scatter; the three-point method only by name, or when the station cannot be estimated.

    Parameters
    ----------
    tracker : array_like, shape (3,), optional
        Tracker position, mm, machine frame (default: the plan's).
    plan : Plan, dict or str, optional
        The measurement plan (a Plan, its JSON dict or a PLAN.json path; default: the machine spec's campaign).
    machine : str or Machine, optional
        The machine spec (default: the plan's, else ``dmu50``).
    monte_carlo_n : int, optional
        Also run this many simulated draws (GUM Supplement 1) to check the linear prediction (default 0).
    seed : int, optional
        Seed of the draws.
    weighting : {"tracker", "none"}, optional
        Weight by the tracker law's covariance (as identify does with a tracker position; default) or not
        (three-point only).
    axes : iterable of str, optional
        Predict only these axes (default: every axis of the plan).
    estimator : {"auto", "joint", "three-point"}, optional
        ``"auto"``: the joint fit with weighting "tracker", three-point with weighting "none".
    tracker_model : str or TrackerSpec, optional
        The tracker's noise law (an instrument's name, ``"a_r,b_r,a_t,b_t[,k]"`` or a TrackerSpec; default the
        AT960's).

    Returns
    -------
    PlanResult
        Per axis and error the standard uncertainty of one round and of the mean of the rounds (mm, rad).

    Raises
    ------
    mtcal.errors.InputError
        An unknown estimator, the joint fit without weighting, an axis not in the plan, a bad plan.

    Examples
    --------
    >>> import mtcal
    >>> res = mtcal.plan_uncertainty((250, -1500, 150), axes=["X"])  # the DMU 50's default plan
    >>> res.mid_travel
    {'X': 250.0}
    >>> {k: round(v * 1e3, 2) for k, v in res.mean_of_rounds["X"].items() if k in ("E_XX", "E_ZX")}  # um
    {'E_XX': 3.91, 'E_ZX': 3.22}
    """
    spec = trk.as_tracker_model(tracker_model)
    if estimator not in ESTIMATORS:
        raise InputError(f"`estimator` must be one of {', '.join(ESTIMATORS)}, got {estimator!r}")
    if estimator == "auto":
        estimator = "joint" if weighting == "tracker" else "three-point"
    if estimator == "joint" and weighting != "tracker":
        raise InputError("the joint fit weights by the tracker's law: it needs `weighting` tracker")
    m, pl = _machine_and_plan(machine, plan)
    if tracker is not None:
        pl = replace(pl, tracker=tuple(float(c) for c in np.asarray(tracker, dtype=float).reshape(3)))
    names = list(axes) if axes is not None else list(pl.positions)
    for a in names:
        if a not in pl.positions:
            raise InputError(f"axis {a!r} is not in the plan (axes: {', '.join(pl.positions)})")
    if estimator == "joint":
        return _plan_joint(m, pl, names, monte_carlo_n, seed, spec)
    t = np.asarray(pl.tracker, dtype=float)
    approaches = 2 if pl.bidirectional else 1
    res = PlanResult(t.tolist(), m.name, weighting, pl.rounds, approaches,
                     "one round as mtcal identify reports it: per pass one reading per reflector at the position and "
                     "the round's reference reading (position closest to zero, first approach), 3 equations per "
                     "reflector (mtcal.identify.threepoint.estimate), " +
                     (f"generalised LS weighted by {spec.whose} covariance" if weighting == "tracker"
                      else "ordinary LS")
                     + "; the passes of a round (out and back) averaged; mean_of_rounds: independent rounds")
    if monte_carlo_n:
        res.monte_carlo = {"n": int(monte_carlo_n), "seed": seed, "solver": "mtcal.identify.threepoint.estimate",
                           "axes": {}}
    for a in names:
        pos = pl.positions[a]
        sd = np.sqrt(np.einsum("pii->pi", linear_covariance(m, pl, a, pos, t, weighting, spec, approaches)))
        _axis_figures(res, m, pl, a, pos, sd, sd / math.sqrt(pl.rounds))
        en = m.error_motions(a)
        if monte_carlo_n:
            log.info("Monte Carlo %d rounds of axis %s", monte_carlo_n, a)
            est = monte_carlo(m, pl, a, [res.mid_travel[a]], t, int(monte_carlo_n), seed, weighting, spec,
                              approaches)
            res.monte_carlo["axes"][a] = {n: float(v) for n, v in zip(en, est[:, 0].std(axis=0, ddof=1))}
    return res


def _axis_figures(res: PlanResult, m: Machine, pl: Plan, a: str, pos: np.ndarray, one_round: np.ndarray,
                  mean: np.ndarray) -> int:
    """Axis ``a`` of ``res`` from the standard uncertainties (P, 6) at ``pos`` of one round and of the mean of the
    rounds: at mid-travel, and per position (one round; None at the reference position, zero by definition).
    Returns the mid-travel index."""
    mid = mid_position(pl, a)
    i_mid = int(np.argmin(np.abs(pos - mid)))
    en = m.error_motions(a)
    ref = pl.reference_position(a)
    res.mid_travel[a] = mid
    res.axes[a] = {n: float(one_round[i_mid, j]) for j, n in enumerate(en)}
    res.mean_of_rounds[a] = {n: float(mean[i_mid, j]) for j, n in enumerate(en)}
    res.by_position[a] = {"positions": pos.tolist(), **{n: [None if p == ref else float(v)
                                                              for p, v in zip(pos, one_round[:, j])]
                                                         for j, n in enumerate(en)}}
    return i_mid


def _plan_joint(m: Machine, pl: Plan, names: list[str], monte_carlo_n: int, seed: int,
                spec: trk.TrackerSpec = trk.AT960) -> PlanResult:
    """PlanResult of the joint fit: ``mean_of_rounds`` its standard uncertainty from all rounds (linear
    propagation), ``axes`` and ``by_position`` the one-round equivalent (times sqrt(rounds)), ``monte_carlo`` the
    standard deviation over ``monte_carlo_n`` campaigns (one-round equivalent, as ``axes``)."""
    approaches = 2 if pl.bidirectional else 1
    stations = {k: list(v) for k, v in pl.stations.items()} if pl.stations else None
    res = PlanResult(list(pl.tracker), m.name, "tracker", pl.rounds, approaches,
                     "the joint weighted fit mtcal identify uses with a tracker position (mtcal.identify.joint): "
                     "every reading of " + (f"{len(stations)} stations" if stations else "the station") + " in one "
                     f"fit weighted by {spec.whose} covariance, reflectors and station alignments estimated; "
                     "mean_of_rounds: the estimate from all rounds (linear propagation, mtcal.planning.joint); axes "
                     "and by_position: its one-round equivalent (times sqrt(rounds))")
    lin = joint_sigma(m, pl, spec)
    mc = joint_monte_carlo(m, pl, int(monte_carlo_n), seed, spec) if monte_carlo_n else None
    if mc is not None:
        res.monte_carlo = {"n": int(monte_carlo_n), "seed": seed, "solver": "mtcal.identify.joint.joint_fit",
                           "of": "campaigns of the plan, one-round equivalent as axes", "axes": {}}
    root = math.sqrt(pl.rounds)
    for a in names:
        pos, sd = lin[a]
        i_mid = _axis_figures(res, m, pl, a, pos, sd * root, sd)
        if mc is not None:
            res.monte_carlo["axes"][a] = {n: float(v * root) for n, v in zip(m.error_motions(a), mc[a][1][i_mid])}
    if stations:
        res.stations = stations
    return res


# ---------------------------------------------------------------------------------------------- placement map
def placement_map(xs, ys, z: float, plan=None, *, machine: str | Machine | None = None,
                  weighting: str = "tracker") -> dict[str, np.ndarray]:
    """Predicted one-round uncertainty over tracker floor positions (x, y) at head height z (machine frame, mm).

    Returns arrays (len(ys), len(xs)): "translational" = RMS of the translational errors of the linear axes at
    mid-travel (mm), "angular" = RMS of their angular errors (rad)."""
    m, pl = _machine_and_plan(machine, plan)
    gx, gy = np.meshgrid(np.asarray(xs, float), np.asarray(ys, float))
    trans = np.zeros(gx.shape)
    ang = np.zeros(gx.shape)
    lin = [a for a in m.linear_axes if a in pl.positions]
    for iy in range(gx.shape[0]):
        for ix in range(gx.shape[1]):
            t = np.array([gx[iy, ix], gy[iy, ix], z])
            v_t, v_a = [], []
            for a in lin:
                cov = linear_covariance(m, pl, a, [mid_position(pl, a)], t, weighting,
                                        approaches=2 if pl.bidirectional else 1)[0]
                v = np.diag(cov)
                v_t += list(v[:3])
                v_a += list(v[3:])
            trans[iy, ix] = math.sqrt(np.mean(v_t))
            ang[iy, ix] = math.sqrt(np.mean(v_a))
    return {"x": gx, "y": gy, "translational": trans, "angular": ang}


def enclosure(plan: Plan, margin: float = 400.0) -> tuple[float, float, float, float]:
    """(x0, x1, y0, y1) mm: the floor box of every nominal reflector position of the plan plus ``margin`` (the
    machine's enclosure, no place for a tracker)."""
    pts = np.concatenate([nominal_points(plan.machine, a, plan.axis_values(a, p)[:, None, :],
                                         np.array(list(plan.points_for(a).values())))[..., :2].reshape(-1, 2)
                          for a, p in plan.positions.items()])
    lo, hi = pts.min(axis=0) - margin, pts.max(axis=0) + margin
    return float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1])


def plot_placement_map(path, plan=None, *, tracker=None, z: float | None = None, machine=None,
                       extent=(-2500.0, 3000.0, -2500.0, 3000.0), step: float = 250.0) -> dict:
    """PNG map of the predicted uncertainty over tracker floor positions; returns the map arrays plus
    "best": {"translational": [x, y], "angular": [x, y]} (the best grid cell outside the machine)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    m, pl = _machine_and_plan(machine, plan)
    z = float(pl.tracker[2] if z is None else z)
    xs = np.arange(extent[0], extent[1] + 1e-9, step)
    ys = np.arange(extent[2], extent[3] + 1e-9, step)
    mp = placement_map(xs, ys, z, pl, machine=m)
    x0, x1, y0, y1 = enclosure(pl)
    inside = ((mp["x"] > x0) & (mp["x"] < x1) & (mp["y"] > y0) & (mp["y"] < y1))
    fig, axs = plt.subplots(1, 2, figsize=(12, 5.2), constrained_layout=True)
    for ax, key, scale, unit in ((axs[0], "translational", 1e3, "um"), (axs[1], "angular", 1e6, "urad")):
        v = np.ma.masked_where(inside, mp[key] * scale)
        im = ax.pcolormesh(mp["x"], mp["y"], v, shading="nearest", cmap="viridis")
        fig.colorbar(im, ax=ax, label=f"RMS one-round sigma, {unit}")
        ax.add_patch(plt.Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, hatch="//", ec="grey"))
        for name, p in tracker_positions(m).items():
            if abs(p[2] - z) < 1 and extent[0] <= p[0] <= extent[1] and extent[2] <= p[1] <= extent[3]:
                ax.plot(p[0], p[1], "w^", ms=9, mec="k")
                ax.annotate(name, (p[0], p[1]), xytext=(6, 6), textcoords="offset points", color="w")
        vv = np.where(inside, np.inf, mp[key])
        iy, ix = np.unravel_index(np.argmin(vv), vv.shape)
        ax.plot(mp["x"][iy, ix], mp["y"][iy, ix], "wx", ms=10, mew=2)
        if tracker is not None:
            ax.plot(tracker[0], tracker[1], "r*", ms=12, mec="k")
        ax.set_xlabel("tracker x, mm (machine frame)")
        ax.set_ylabel("tracker y, mm")
        ax.set_aspect("equal")
        ax.set_title(f"{key} errors of {', '.join(m.linear_axes)} (mid-travel), tracker z = {z:g} mm", fontsize=10)
    fig.suptitle("Predicted one-round uncertainty vs tracker floor position (x: best grid cell, *: given)")
    save_figure(fig, path, dpi=110)
    plt.close(fig)
    mp["best"] = {}
    for key in ("translational", "angular"):
        vv = np.where(inside, np.inf, mp[key])
        iy, ix = np.unravel_index(np.argmin(vv), vv.shape)
        mp["best"][key] = [float(mp["x"][iy, ix]), float(mp["y"][iy, ix])]
    return mp
