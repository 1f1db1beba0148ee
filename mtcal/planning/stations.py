"""Designing a multi-station measurement: which tracker stations, which reflector spacing, how many rounds, for a
target volumetric uncertainty of the identified model (issue 14).

Prediction (linear propagation through the joint estimator, mtcal.identify.joint): the covariance of the joint
estimate of a candidate campaign is the estimator's own covariance on the campaign's exact readings (nominal
machine, AT960 noise model of each station); the volumetric uncertainty over the work volume is that covariance
propagated to the tool-tip position at random poses inside the measured ranges: the model's error motions at a
pose are the per-position estimates interpolated linearly (held at the ends), the tool-tip deviation is
``Machine.jacobian_errors`` times them (first order).  Reported as the RMS over the poses of the standard
uncertainty of the 3-D deviation (sqrt of the trace of its covariance), mm.  The compensated machine's remaining
error is the model's error (first order: compensation with a model off by d leaves d), so the same number
predicts it.  The identified model's fitted functions smooth the per-position estimates: the prediction is an
upper bound for the model after fitting (tests: the Monte Carlo of the real estimator against the prediction).

Design (greedy): candidate stations are the allowed floor positions at the allowed heights; the best single
station first, then the station that lowers the prediction most, until the target is met or the time budget
(hours of measuring; one round from one station takes the plan's schedule time, moving the tracker
``STATION_CHANGE_S``) is used; wider reflector layouts (up to the fixture's limit) and more rounds are tried
against more stations at the same measuring time.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass, field, replace

import numpy as np

from mtcal.campaign.plans import Plan, schedule
from mtcal.campaign.stations import STATION_CHANGE_S, simulate_stations
from mtcal.errors import InputError
from mtcal.identify.joint import JointResult, joint_fit
from mtcal.kinematics.machine import Machine
from mtcal.measurement.recordings import Recording


def scaled_points(plan: Plan, scale: float) -> Plan:
    """The plan with every reflector layout spread ``scale`` times about its centroid (mm)."""
    def spread(pts: dict) -> dict:
        c = np.mean(list(pts.values()), axis=0)
        return {k: tuple(float(v) for v in c + scale * (np.asarray(p) - c)) for k, p in pts.items()}
    return replace(plan, tool_points=spread(plan.tool_points), table_points=spread(plan.table_points))


def poses(plan: Plan, n: int = 400, seed: int = 0) -> np.ndarray:
    """Random axis positions (n, n_axes) inside the plan's measured ranges (others at zero)."""
    rng = np.random.default_rng(seed)
    m = plan.machine
    q = np.zeros((n, len(m.axes)))
    for a, p in plan.positions.items():
        q[:, m.index(a)] = rng.uniform(p.min(), p.max(), n)
    return q


def deviation_map(res: JointResult, m: Machine, grid: np.ndarray) -> np.ndarray:
    """H (n_grid, 3, n_params): the tool-tip deviation (mm) at each pose as a linear function of the joint
    parameter vector (per-position error motions, mean over directions, interpolated linearly)."""
    lay = res.layout
    jac = m.jacobian_errors(grid)[:, :3, :]
    h = np.zeros((len(grid), 3, lay.n))
    for axis in lay.axes:
        keys = sorted(lay.axes[axis] + [lay.reference[axis]])
        pos = np.unique([k[0] for k in keys])
        x = grid[:, m.index(axis)]
        wts = np.stack([np.interp(x, pos, np.eye(len(pos))[i]) for i in range(len(pos))], axis=1)  # (g, P)
        jc = jac[:, :, [m.error_names.index(nm) for nm in m.error_motions(axis)]]  # (g, 3, 6)
        for k in keys:
            if k == lay.reference[axis]:
                continue
            ip = int(np.searchsorted(pos, k[0]))
            share = 1.0 / sum(1 for kk in keys if kk[0] == k[0])
            c = lay.err_index[(axis, *k)]
            h[:, :, c:c + 6] += (wts[:, ip] * share)[:, None, None] * jc
    return h


def _rms_um(h: np.ndarray, cov: np.ndarray) -> float:
    """RMS over poses of the 3-D standard uncertainty (um) of deviations h (3 n_grid, n) @ x, x ~ (0, cov)."""
    return float(np.sqrt(np.sum((h @ cov) * h) / (len(h) / 3)) * 1e3)


@dataclass
class Prediction:
    """Predicted volumetric standard uncertainty (um, RMS over the poses) of the identified model and of the
    compensated machine, and the campaign it is for."""

    stations: list[tuple[str, list[float]]]
    rounds_per_station: int
    reflector_scale: float
    hours: float
    model_um: float
    compensated_um: float
    per_axis_um: dict[str, float] = field(default_factory=dict)
    monte_carlo_um: float | None = None  # the same figure by Monte Carlo of identify (mtcal.uncertainty.design)


def campaign_hours(plan: Plan, n_stations: int, rounds: int) -> float:
    """Measuring time (h): the plan's schedule for ``rounds`` rounds from each station plus moving between."""
    t = float(schedule(replace(plan, rounds=rounds)).time_s.max())
    return (n_stations * t + (n_stations - 1) * STATION_CHANGE_S) / 3600.0


def nominal_campaign(plan: Plan, stations, rounds: int = 1, scale: float = 1.0, model=None) -> Recording:
    """The exact readings of a candidate campaign (stations aligned exactly, no noise) of the nominal machine, or
    of ``model``'s: ``stations`` [(label, (x, y, z) mm)], ``rounds`` per station, reflector layouts spread ``scale``
    times."""
    rec, _ = simulate_stations(model, stations, machine=plan.machine, rounds=rounds, plan=scaled_points(plan, scale),
                               noise=False, alignment_um=0.0, alignment_urad=0.0)
    return rec


def predict(plan: Plan, stations, rounds: int = 1, scale: float = 1.0, grid: np.ndarray | None = None) -> Prediction:
    """Prediction for one campaign: ``stations`` [(label, (x, y, z) mm)], ``rounds`` per station, reflector
    layouts spread ``scale`` times."""
    m = plan.machine
    rec = nominal_campaign(plan, stations, rounds, scale)
    res = joint_fit(rec, m, per_round=False, steps=1)  # exact nominal readings: one linearisation is exact
    g = poses(plan) if grid is None else grid
    h = deviation_map(res, m, g).reshape(-1, res.layout.n)
    um = _rms_um(h, res.covariance)
    per_axis = {}
    for axis in res.layout.axes:
        sel = np.zeros(res.layout.n, bool)
        for k in res.layout.axes[axis]:
            c = res.layout.err_index[(axis, *k)]
            sel[c:c + 6] = True
        per_axis[axis] = _rms_um(h[:, sel], res.covariance[np.ix_(sel, sel)])
    return Prediction([(s, list(map(float, t))) for s, t in stations], rounds, scale,
                      campaign_hours(plan, len(stations), rounds), um, um, per_axis)


@dataclass
class Design:
    """The recommended campaign and the path to it (each step's prediction)."""

    target_um: float
    recommended: Prediction
    met: bool
    steps: list[Prediction]
    alternatives: list[Prediction]
    decided_by: str = "linear propagation"

    def to_dict(self) -> dict:
        return {"units": {"uncertainty": "um (RMS over the work volume of the 3-D standard uncertainty)",
                          "position": "mm, machine frame", "time": "h"}, **asdict(self)}


def candidate_stations(floor, heights) -> list[tuple[str, tuple[float, float, float]]]:
    """Every allowed floor position (x, y mm) at every allowed height (z mm), labelled x_y_z."""
    out = [(f"{x:.0f}_{y:.0f}_{z:.0f}", (float(x), float(y), float(z))) for x, y in floor for z in heights]
    if not out:
        raise InputError("no candidate stations: give floor positions and heights")
    return out


def default_floor(plan: Plan, distance: float = 1000.0) -> list[tuple[float, float]]:
    """Eight floor positions (x, y mm) ``distance`` outside the machine's enclosure (mtcal.planning.plan.enclosure):
    the middles of its four sides and its four corners."""
    from mtcal.planning.plan import enclosure
    x0, x1, y0, y1 = enclosure(plan)
    xs, ys = (x0 - distance, (x0 + x1) / 2, x1 + distance), (y0 - distance, (y0 + y1) / 2, y1 + distance)
    return [(x, y) for x in xs for y in ys if (x, y) != (xs[1], ys[1])]


def _outside_the_enclosure(plan: Plan, floor) -> None:
    from mtcal.planning.plan import enclosure
    x0, x1, y0, y1 = enclosure(plan)
    for x, y in floor:
        if x0 < x < x1 and y0 < y < y1:
            raise InputError(f"floor position {x:g},{y:g} mm is inside the machine's enclosure (x {x0:g} .. {x1:g}, "
                             f"y {y0:g} .. {y1:g} mm: the work volume's reflector positions and a margin): no place "
                             f"for a tracker (`floor`, machine frame)")


def design(plan: Plan, floor, heights, target_um: float = 3.0, max_hours: float | None = None,
           max_scale: float = 1.0, max_stations: int = 4, progress=None) -> Design:
    """Greedy station choice (module docstring) with 1 round per station and the widest allowed reflector
    layout, then the same measuring time spent as more rounds on fewer stations for comparison.  A floor position
    inside the machine's enclosure (mtcal.planning.plan.enclosure: the work volume's reflector positions plus its
    margin) is refused: no tracker stands in the work volume."""
    _outside_the_enclosure(plan, floor)
    cands = candidate_stations(floor, heights)
    grid = poses(plan)
    chosen: list = []
    steps: list[Prediction] = []
    scale = float(max_scale)
    best = None
    while len(chosen) < min(max_stations, len(cands)):
        trial = []
        for c in cands:
            if c in chosen:
                continue
            p = predict(plan, chosen + [c], 1, scale, grid)
            if max_hours is not None and p.hours > max_hours:
                continue
            trial.append((p.model_um, c, p))
            if progress:
                progress(f"{len(chosen) + 1} station(s) with {c[0]}: {p.model_um:.2f} um")
        if not trial:
            break
        _, c, best = min(trial, key=lambda t: t[0])
        chosen.append(c)
        steps.append(best)
        if best.model_um <= target_um:
            break
    if best is None:
        raise InputError(f"no campaign fits in {max_hours} h")
    alternatives = []
    if len(chosen) > 1 and len(chosen) % 2 == 0:  # the same time as more rounds from half the stations
        alternatives.append(predict(plan, chosen[: len(chosen) // 2], 2, scale, grid))
    if scale != 1.0:
        alternatives.append(predict(plan, chosen, 1, 1.0, grid))
    return Design(target_um, best, best.model_um <= target_um, steps, alternatives)
