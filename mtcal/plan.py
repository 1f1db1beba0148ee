"""Measurement planning: the standard uncertainty of every identified error for a tracker placement.

Estimator (one position q of one round, three-point method of Zhang & Hu, thesis ch. 3): the readings r_i(q)
of the reflectors i = P, Q, K and their reference readings r_i(q0) (the position closest to zero, same round)
give the nine equations

    (r_i(q) - r_i(q0)) - (n_i(q) - n_i(q0)) = J_i(q) e(q),   i = P, Q, K,

with n_i the nominal reflector positions and J_i the 3x6 block of the measured axis' six error motions
(E_XJ, E_YJ, E_ZJ, E_AJ, E_BJ, E_CJ; for B and C E_XB .. E_CB) taken from the generated
``tool_point_jacobian_errors`` / ``table_point_jacobian_errors`` (errors referred to the machine origin).
The reflector coordinates are taken from the reference readings themselves, as on the machine.  With
``--tracker`` the nine equations are weighted by the AT960 covariance (mtcal.tracker) of the reading AND of
its reference reading: Sigma_i = C(r_i(q)) + C(r_i(q0)); the solution is generalised least squares through
whitening and QR (never an explicit inverse of the normal matrix).

Linear propagation: Cov(e) = A Sigma A^T with A = (J^T W J)^-1 J^T W (W = Sigma^-1 for "tracker"
weighting, I for "none"), i.e. J+ Sigma J+^T.  Monte Carlo (GUM Supplement 1): draw tracker noise for the
readings and reference readings, run the same estimator on each draw, take the sample standard deviation.
Units: mm for E_X*, E_Y*, E_Z*, E_X0*, rad for the angular errors.
"""
from __future__ import annotations

import math
import sys
from dataclasses import replace
from typing import Iterable

import numpy as np

from mtcal import tracker as trk
from mtcal.errors import InputError
from mtcal.machine import Machine, load_machine
from mtcal.simulate import AXIS_ORDER, LINEAR, TRACKER_POSITIONS, Plan, as_plan
from mtcal.io import save_figure

WEIGHTINGS = ("tracker", "none")


def axis_errors(axis: str) -> list[str]:
    """The six error motions identified per position of an axis (ISO names)."""
    return [f"E_{c}{axis}" for c in "XYZABC"]


def _cols(machine: Machine, axis: str) -> list[int]:
    return [machine.error_names.index(n) for n in axis_errors(axis)]


def _side(axis: str) -> str:
    return "tool" if axis in LINEAR else "table"


def nominal_points(machine: Machine, axis: str, axes: np.ndarray, local: np.ndarray) -> np.ndarray:
    """Nominal machine-frame positions (..., 3) of reflectors ``local`` (..., 3) at axis positions (..., 5)."""
    f = machine._np.tool_point if _side(axis) == "tool" else machine._np.table_point
    axes, local = _lead(axes, local)
    return f(axes, np.zeros(axes.shape[:-1] + (len(machine.error_names),)), local)


def _lead(axes, local) -> tuple[np.ndarray, np.ndarray]:
    """Broadcast the leading dimensions of axes (..., 5) and local (..., 3)."""
    axes, local = np.asarray(axes, dtype=float), np.asarray(local, dtype=float)
    lead = np.broadcast_shapes(axes.shape[:-1], local.shape[:-1])
    return np.broadcast_to(axes, lead + axes.shape[-1:]), np.broadcast_to(local, lead + (3,))


def point_jacobian(machine: Machine, axis: str, axes: np.ndarray, local: np.ndarray) -> np.ndarray:
    """d reading / d (six errors of ``axis``) (..., 3, 6) at zero error."""
    f = machine._np.tool_point_jacobian_errors if _side(axis) == "tool" else machine._np.table_point_jacobian_errors
    return f(*_lead(axes, local))[..., _cols(machine, axis)]


def rigid_motion(machine: Machine, axis: str, axes) -> tuple[np.ndarray, np.ndarray]:
    """(b (..., 3), R (..., 3, 3)) with nominal reading = b + R local at axis positions (..., 5).

    The nominal map local -> machine frame is a rigid motion: read off exactly from its value at 0 and at
    the three unit vectors (R is a rotation, identity on the spindle side)."""
    ax = np.asarray(axes, dtype=float)
    f = machine._np.tool_point if _side(axis) == "tool" else machine._np.table_point
    ax4 = np.broadcast_to(ax[..., None, :], ax.shape[:-1] + (4, 5))
    basis = f(ax4, np.zeros(ax4.shape[:-1] + (len(machine.error_names),)), np.vstack([np.zeros(3), np.eye(3)]))
    b = basis[..., 0, :]
    return b, np.swapaxes(basis[..., 1:, :] - b[..., None, :], -1, -2)  # columns: images of the unit vectors


def local_from_reference(machine: Machine, axis: str, axes0: np.ndarray, r0: np.ndarray) -> np.ndarray:
    """Reflector coordinates on their side (..., 3) from reference readings r0 (..., 3) at axes0 (5,)."""
    b, rot = rigid_motion(machine, axis, axes0)
    return np.einsum("ji,...j->...i", rot, np.asarray(r0, dtype=float) - b)  # R^-1 = R^T


def solve_positions(machine: Machine, axis: str, axes: np.ndarray, axes0: np.ndarray, r: np.ndarray,
                    r0: np.ndarray, tracker=None, spec: trk.TrackerSpec = trk.AT960) -> np.ndarray:
    """Errors (..., 6) of ``axis`` from readings r (..., k, 3) at axes (..., 5) and reference readings
    r0 (..., k, 3) at axes0 (5,); tracker (3,) mm weights by the AT960 covariance, None = unweighted.
    ``axes`` only needs to broadcast against r's leading dimensions (pass (P, 5) for many draws)."""
    r, r0 = np.asarray(r, dtype=float), np.asarray(r0, dtype=float)
    axes = np.asarray(axes, dtype=float)
    b, rot = rigid_motion(machine, axis, axes)                                   # (..., 3), (..., 3, 3)
    b0, rot0 = rigid_motion(machine, axis, axes0)
    local = np.einsum("ji,...j->...i", rot0, r0 - b0)                            # (..., k, 3)
    # Delta = (r - r0) - (n(q) - n(q0)) with n(q0) = r0 by construction of ``local``
    delta = r - b[..., None, :] - np.einsum("...ij,...kj->...ki", rot, local)
    jac = point_jacobian(machine, axis, axes[..., None, :], local)               # (..., k, 3, 6)
    if tracker is not None:
        rel = rot @ rot0.T
        cov = trk.covariance(r, tracker, spec) + np.einsum(
            "...ij,...kjl,...ml->...kim", rel, trk.covariance(r0, tracker, spec), rel)
        lc = np.linalg.cholesky(cov)
        jac = np.linalg.solve(lc, jac)
        delta = np.linalg.solve(lc, delta[..., None])[..., 0]
    k = local.shape[-2]
    jac = jac.reshape(jac.shape[:-3] + (3 * k, 6))
    delta = delta.reshape(delta.shape[:-2] + (3 * k,))
    q, rr = np.linalg.qr(jac)
    return np.linalg.solve(rr, np.einsum("...ji,...j->...i", q, delta)[..., None])[..., 0]


def delta_covariance(machine: Machine, axis: str, axes, axes0, r, r0, tracker,
                     spec: trk.TrackerSpec = trk.AT960) -> np.ndarray:
    """Covariance (..., k, 3, 3) of the deviations Delta_i = (r_i - r0_i) - (n_i(q) - n_i(q0)) in mm^2.

    The reflector coordinates come from the reference reading, so Delta_i = r_i - b(q) - R(q) R(q0)^T (r0_i -
    b(q0)): the reference noise enters rotated by the relative rotation R_rel = R(q) R(q0)^T (identity for the
    linear axes, the table's rotation for B and C).  Cov = C(r_i) + R_rel C(r0_i) R_rel^T."""
    _, rq = rigid_motion(machine, axis, axes)
    _, r0q = rigid_motion(machine, axis, axes0)
    rel = rq @ np.swapaxes(r0q, -1, -2)
    c0 = trk.covariance(r0, tracker, spec)
    return trk.covariance(r, tracker, spec) + rel @ c0 @ np.swapaxes(rel, -1, -2)


def identify_solver(plan: Plan, axis: str):
    """mtcal.identify.identify_position wrapped to the signature of ``solve_positions`` (None when that module
    or function is missing, or when the plan holds other axes away from zero, which identify assumes)."""
    try:
        from mtcal.identify import identify_position
    except Exception:  # identify is another module's job; planning works without it
        return None
    if any(plan.at.get(axis, {}).values()):
        return None
    ref = plan.reference_position(axis)

    def solve(machine, axis_, axes, axes0, r, r0, tracker=None, spec=trk.AT960):
        pos = np.asarray(axes, dtype=float)[..., AXIS_ORDER.index(axis_)]
        return identify_position(axis_, pos, r, r0, ref, tracker, machine).errors
    solve.__name__ = "mtcal.identify.identify_position"
    return solve


def _solver(plan: Plan, axis: str, solver):
    if solver in (None, "auto"):
        return identify_solver(plan, axis) or solve_positions
    if solver == "identify":
        f = identify_solver(plan, axis)
        if f is None:
            raise InputError("mtcal.identify.identify_position is not available for this plan")
        return f
    if solver == "plan":
        return solve_positions
    return solver


def linear_covariance(machine: Machine, plan: Plan, axis: str, positions, tracker,
                      weighting: str = "tracker", spec: trk.TrackerSpec = trk.AT960, approaches: int = 1) -> np.ndarray:
    """Cov (P, 6, 6) of the six identified errors of ``axis`` at ``positions`` (P,) for one round.

    Each of ``approaches`` passes (1, or 2 for out and back) has one reading per reflector; all share the round's
    reference reading; the pass solutions are averaged (as mtcal.identify does).  With A = (J^T W J)^-1 J^T W the
    per-pass estimator (W = Sigma_pass^-1 for weighting "tracker", I for "none"), Cov = A Sigma_round A^T with
    Sigma_round = C(r) / approaches + R_rel C(r0) R_rel^T: J+ Sigma J+^T.  For one pass and "tracker"
    weighting this is (J^T Sigma^-1 J)^-1 = R^-1 R^-T from the QR of the whitened design."""
    if weighting not in WEIGHTINGS:
        raise InputError(f"weighting must be one of {WEIGHTINGS}, got {weighting!r}")
    if int(approaches) != approaches or approaches < 1:
        raise InputError(f"approaches must be a positive integer, got {approaches!r}")
    pos = np.atleast_1d(np.asarray(positions, dtype=float))
    tracker = np.asarray(tracker, dtype=float)
    local = np.array(list(plan.points_for(axis).values()), dtype=float)          # (k, 3)
    k, n_p = len(local), len(pos)
    ax = plan.axis_values(axis, pos)                                             # (P, 5)
    ax0 = plan.axis_values(axis, plan.reference_position(axis))
    axk = np.broadcast_to(ax[:, None, :], (n_p, k, 5))
    r = nominal_points(machine, axis, axk, local)                                # (P, k, 3)
    r0 = nominal_points(machine, axis, np.broadcast_to(ax0, (k, 5)), local)       # (k, 3)
    jac = point_jacobian(machine, axis, axk, local)                              # (P, k, 3, 6)
    c_pass = delta_covariance(machine, axis, axk, ax0, r, r0, tracker, spec)      # (P, k, 3, 3)
    c_read = trk.covariance(r, tracker, spec)
    c_round = c_pass - c_read * (1.0 - 1.0 / approaches)                         # (P, k, 3, 3)
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
                weighting: str = "tracker", spec: trk.TrackerSpec = trk.AT960, solver="plan",
                approaches: int = 1, chunk: int = 2000) -> np.ndarray:
    """Estimates (n, P, 6) of the six errors of ``axis`` from n simulated rounds (zero true errors, AT960 noise
    on every reading and on the shared reference reading; ``approaches`` passes per round, solutions averaged).
    solver: "plan" (``solve_positions``), "identify" (mtcal.identify.identify_position), "auto" (identify when
    available) or a callable like solve_positions."""
    pos = np.atleast_1d(np.asarray(positions, dtype=float))
    tracker = np.asarray(tracker, dtype=float)
    local = np.array(list(plan.points_for(axis).values()), dtype=float)
    k = len(local)
    ax = plan.axis_values(axis, pos)
    ax0 = plan.axis_values(axis, plan.reference_position(axis))
    r = nominal_points(machine, axis, np.broadcast_to(ax[:, None, :], (len(pos), k, 5)), local)   # (P, k, 3)
    r0 = nominal_points(machine, axis, np.broadcast_to(ax0, (k, 5)), local)                        # (k, 3)
    ch_r = np.linalg.cholesky(trk.covariance(r, tracker, spec))
    ch_0 = np.linalg.cholesky(trk.covariance(r0, tracker, spec))
    rng = np.random.default_rng(seed)
    solve = _solver(plan, axis, solver)
    out = np.empty((n, len(pos), 6))
    step = max(1, chunk // approaches)
    for s in range(0, n, step):
        m = min(step, n - s)
        rr = r + np.einsum("pkij,napkj->napki", ch_r, rng.standard_normal((m, approaches, len(pos), k, 3)))
        rr0 = r0 + np.einsum("kij,nkj->nki", ch_0, rng.standard_normal((m, k, 3)))
        est = solve(machine, axis, ax, ax0, rr, np.broadcast_to(rr0[:, None, None], rr.shape),
                    None if weighting == "none" else tracker, spec)
        out[s:s + m] = est.mean(axis=1)
    return out


def mid_position(plan: Plan, axis: str) -> float:
    """The plan position closest to mid-travel."""
    p = plan.positions[axis]
    return float(p[np.argmin(np.abs(p - (p.min() + p.max()) / 2))])


def plan_uncertainty(tracker=None, plan=None, *, machine: str | Machine = "dmu50", monte_carlo_n: int = 0,
                     seed: int = 0, weighting: str = "tracker", axes: Iterable[str] | None = None,
                     progress: bool = False, solver="auto") -> dict:
    """The answer of `mtcal plan`: {"tracker", "axes": {AXIS: {NAME: sigma at mid-travel}}, ...} in mm and rad."""
    m = machine if isinstance(machine, Machine) else load_machine(machine)
    pl = as_plan(plan)
    if tracker is not None:
        pl = replace(pl, tracker=tuple(float(c) for c in np.asarray(tracker, dtype=float).reshape(3)))
    t = np.asarray(pl.tracker, dtype=float)
    names = list(axes) if axes is not None else list(pl.positions)
    approaches = 2 if pl.bidirectional else 1
    out: dict = {"tracker": t.tolist(), "machine": m.name, "units": {"length": "mm", "angle": "rad"},
                 "estimator": "one round as mtcal identify reports it: per pass one reading per reflector at the "
                              "position and the round's reference reading (position closest to zero, first approach), "
                              "9 equations, " +
                              ("generalised LS weighted by the AT960 covariance" if weighting == "tracker"
                               else "ordinary LS")
                              + "; the passes of a round (out and back) averaged; mean_of_rounds: independent rounds",
                 "approaches_per_round": approaches,
                 "weighting": weighting, "rounds": pl.rounds, "mid_travel": {}, "axes": {}, "mean_of_rounds": {},
                 "by_position": {}}
    if monte_carlo_n:
        out["monte_carlo"] = {"n": int(monte_carlo_n), "seed": seed, "axes": {}}
    for a in names:
        if a not in pl.positions:
            raise InputError(f"axis {a!r} is not in the plan (axes: {', '.join(pl.positions)})")
        mid = mid_position(pl, a)
        pos = pl.positions[a]
        cov = linear_covariance(m, pl, a, pos, t, weighting, approaches=approaches)
        sd = np.sqrt(np.einsum("pii->pi", cov))
        i_mid = int(np.argmin(np.abs(pos - mid)))
        en = axis_errors(a)
        out["mid_travel"][a] = mid
        out["axes"][a] = {n: float(sd[i_mid, j]) for j, n in enumerate(en)}
        out["mean_of_rounds"][a] = {n: float(sd[i_mid, j] / math.sqrt(pl.rounds)) for j, n in enumerate(en)}
        ref = pl.reference_position(a)
        out["by_position"][a] = {"positions": pos.tolist(),
                                 **{n: [None if p == ref else float(v) for p, v in zip(pos, sd[:, j])]
                                    for j, n in enumerate(en)}}
        if monte_carlo_n:
            if progress:
                print(f"mtcal plan: Monte Carlo {monte_carlo_n} rounds of axis {a}", file=sys.stderr)
            solve = _solver(pl, a, solver)
            out["monte_carlo"].setdefault("solver", {})[a] = getattr(solve, "__name__", str(solve)).replace(
                "solve_positions", "mtcal.plan.solve_positions")
            est = monte_carlo(m, pl, a, [mid], t, int(monte_carlo_n), seed, weighting, solver=solve,
                              approaches=approaches)
            out["monte_carlo"]["axes"][a] = {n: float(v) for n, v in zip(en, est[:, 0].std(axis=0, ddof=1))}
    return out


# ---------------------------------------------------------------------------------------------- placement map
def placement_map(xs, ys, z: float, plan=None, *, machine: str | Machine = "dmu50",
                  weighting: str = "tracker") -> dict[str, np.ndarray]:
    """Predicted one-round uncertainty over tracker floor positions (x, y) at head height z (machine frame, mm).

    Returns arrays (len(ys), len(xs)): "translational" = RMS of the nine translational errors of X, Y, Z at
    mid-travel (mm), "angular" = RMS of their nine angular errors (rad)."""
    m = machine if isinstance(machine, Machine) else load_machine(machine)
    pl = as_plan(plan)
    gx, gy = np.meshgrid(np.asarray(xs, float), np.asarray(ys, float))
    trans = np.zeros(gx.shape)
    ang = np.zeros(gx.shape)
    lin = [a for a in LINEAR if a in pl.positions]
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


def plot_placement_map(path, plan=None, *, tracker=None, z: float | None = None, machine="dmu50",
                       extent=(-2500.0, 3000.0, -2500.0, 3000.0), step: float = 250.0) -> dict:
    """PNG map of the predicted uncertainty over tracker floor positions; returns the map arrays plus
    "best": {"translational": [x, y], "angular": [x, y]} (the best grid cell outside the machine)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pl = as_plan(plan)
    z = float(pl.tracker[2] if z is None else z)
    xs = np.arange(extent[0], extent[1] + 1e-9, step)
    ys = np.arange(extent[2], extent[3] + 1e-9, step)
    mp = placement_map(xs, ys, z, pl, machine=machine)
    # The machine's enclosure (X travel x Y travel plus 400 mm) is no place for a tracker.
    inside = ((mp["x"] > -400) & (mp["x"] < 900) & (mp["y"] > -400) & (mp["y"] < 850))
    fig, axs = plt.subplots(1, 2, figsize=(12, 5.2), constrained_layout=True)
    for ax, key, scale, unit in ((axs[0], "translational", 1e3, "um"), (axs[1], "angular", 1e6, "urad")):
        v = np.ma.masked_where(inside, mp[key] * scale)
        im = ax.pcolormesh(mp["x"], mp["y"], v, shading="nearest", cmap="viridis")
        fig.colorbar(im, ax=ax, label=f"RMS one-round sigma, {unit}")
        ax.add_patch(plt.Rectangle((-400, -400), 1300, 1250, fill=False, hatch="//", ec="grey"))
        for name, p in TRACKER_POSITIONS.items():
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
        ax.set_title(f"{key} errors of X, Y, Z (mid-travel), tracker z = {z:g} mm", fontsize=10)
    fig.suptitle("Predicted one-round uncertainty vs tracker floor position (x: best grid cell, *: given)")
    save_figure(fig, path, dpi=110)
    plt.close(fig)
    mp["best"] = {}
    for key in ("translational", "angular"):
        vv = np.where(inside, np.inf, mp[key])
        iy, ix = np.unravel_index(np.argmin(vv), vv.shape)
        mp["best"][key] = [float(mp["x"][iy, ix]), float(mp["y"][iy, ix])]
    return mp
