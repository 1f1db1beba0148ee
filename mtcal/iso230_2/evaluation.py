"""ISO 230-2:2014 evaluation of the positioning accuracy and repeatability of one axis from a tidy recording.

Positional deviation x_ij = actual - target position of the measured axis at target i, run j (ISO 230-2:2014
terms and definitions), from the laser-tracker readings against each round's reference reading (docs/design.md:
the round's reading at the position closest to zero, the first time it is approached):

* linear axis (um): every reflector's reading minus where the nominal motion takes its reference reading,
  projected on the unit direction in which the axis moves the reflector (from the machine's nominal kinematics),
  averaged over the reflectors of the pass (= the deviation at their centroid, the functional point; ``point``
  picks one reflector instead);
* rotary axis (arcsec, urad or deg): the rotation of the rigid reflector set about the nominal axis line beyond
  the commanded angle: the least-squares rigid motion of the points (generated three-point solution,
  derive/threepoint.py) expressed in the axis' stator frame F (z along the axis), its rotation about z, signed
  so that + means turned further in the axis' positive sense.  In-plane translations (radial error motions,
  location errors) and tilts are solved for separately, so they do not leak into the angle; >= 3 points.

Temperature normalisation to 20 C (linear axes, as the standard's nominal differential expansion): with the
expansion coefficient alpha (1/K) of the axis' scale / the part it stands for and the pass' temperature T
(mean temperature_c of its readings), x_ij <- x_ij - alpha (T - 20 C) (P_i - P_0), with P_0 the reference
position: the deviation the axis would show at 20 C.

Statistics (ISO 230-2:2014 terms and definitions, computed per target over the runs that exist, so unequal
numbers of runs per target and direction are fine): x_mean_up/down (mean unidirectional positional deviation),
x_mean_i =
(up + down)/2, B_i = up - down (reversal value), s_up/down (unidirectional standard uncertainty estimate, n - 1),
R_up/down_i = 4 s, R_i = max(2 s_up + 2 s_down + |B_i|, R_up_i, R_down_i); axis: B = max |B_i|, B_mean = mean B_i,
E_up/down = max - min of the unidirectional means, E = max - min over both, M = max - min of x_mean_i,
R_up/down/R = max over targets, A_up = max(x_up + 2 s_up) - min(x_up - 2 s_up), A_down alike, A = over both.
The standard test cycle has 5 runs in each direction: fewer give a warning, not a refusal.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from mtcal.errors import InputError
from mtcal.identify.threepoint import MAX_DEVIATION_MM, frame_data, solve_frame
from mtcal.kinematics.machine import DEFAULT_MACHINE, Machine, load_machine
from mtcal.measurement.passes import first_readings, group_passes, reading_order, reference_position
from mtcal.measurement.recordings import Recording

TARGET_TOLERANCE = {"linear": 0.01, "rotary": 0.01}  # mm / deg: targets closer than this are one target
RUNS = 5  # ISO 230-2:2014 standard test cycle: five runs in each direction at every target
ANGLE_UNITS = {"arcsec": 180.0 / math.pi * 3600.0, "urad": 1e6, "deg": 180.0 / math.pi}  # per rad
TARGET_FIELDS = ("n_up", "n_down", "mean_up", "mean_down", "mean", "reversal", "s_up", "s_down",
                 "R_up", "R_down", "R")
PARAMETERS = {  # name -> meaning (ISO 230-2:2014 terms and definitions)
    "B": "reversal value of the axis, max |B_i|", "B_mean": "mean reversal value, mean of B_i",
    "E_up": "unidirectional systematic positional deviation (up), max - min of mean_up",
    "E_down": "unidirectional systematic positional deviation (down)",
    "E": "bidirectional systematic positional deviation, max - min over both directions' means",
    "M": "range of the mean bidirectional positional deviation, max - min of mean_i",
    "R_up": "unidirectional repeatability (up), max R_up_i", "R_down": "unidirectional repeatability (down)",
    "R": "bidirectional repeatability, max R_i",
    "A_up": "unidirectional accuracy (up), max(mean_up + 2 s_up) - min(mean_up - 2 s_up)",
    "A_down": "unidirectional accuracy (down)", "A": "bidirectional accuracy, over both directions"}


@dataclass
class Runs:
    """One positional deviation per pass: target position (mm or deg), direction (+1 up / -1 down), round,
    deviation (``unit``), and the file lines of its readings."""

    position: np.ndarray
    direction: np.ndarray
    round: np.ndarray
    deviation: np.ndarray
    lines: list[list[int]]
    unit: str
    reference: np.ndarray  # the round's reference position per pass (mm or deg)

    def select(self, keep: np.ndarray) -> "Runs":
        return Runs(self.position[keep], self.direction[keep], self.round[keep], self.deviation[keep],
                    [ln for ln, k in zip(self.lines, keep) if k], self.unit, self.reference[keep])


RESULT_UNITS = {"um": ("um", 1.0), "mm": ("um", 1e-3), "inch": ("um", 1.0 / 25400.0),
                "arcsec": ("arcsec", 1.0), "urad": ("arcsec", 1e6 / ANGLE_UNITS["arcsec"]),
                "deg": ("arcsec", 1.0 / 3600.0)}  # result unit -> (the unit it converts from, factor)


def in_unit(runs: Runs, unit: str) -> Runs:
    """The runs' deviations in ``unit`` (RESULT_UNITS: um, mm, inch for a linear axis; arcsec, urad, deg rotary)."""
    if unit not in RESULT_UNITS or RESULT_UNITS[unit][0] != runs.unit:
        fit = [u for u, (base, _) in RESULT_UNITS.items() if base == runs.unit]
        raise InputError(f"result unit {unit!r} does not fit deviations in {runs.unit} (use {', '.join(fit)})")
    return Runs(runs.position, runs.direction, runs.round, runs.deviation * RESULT_UNITS[unit][1], runs.lines, unit,
                runs.reference)


@dataclass
class AxisEvaluation:
    """ISO 230-2 results of one axis; per-target arrays (one entry per target position) in ``unit``."""

    axis: str
    kind: str  # "linear" | "rotary"
    unit: str  # um | arcsec | urad | deg
    position_unit: str  # mm | deg
    positions: np.ndarray
    targets: dict[str, np.ndarray]
    parameters: dict[str, float]
    runs: Runs
    reference_positions: list[float]
    notes: list[str] = field(default_factory=list)

    def to_dict(self) -> dict:
        return {"axis": self.axis, "kind": self.kind, "unit": self.unit, "position_unit": self.position_unit,
                "reference_positions": self.reference_positions, "positions": self.positions,
                "targets": self.targets, "parameters": self.parameters,
                "parameter_meaning": {k: PARAMETERS[k] for k in self.parameters},
                "runs": [{"position": p, "direction": int(d), "round": int(r), "deviation": v}
                         for p, d, r, v in zip(self.runs.position, self.runs.direction, self.runs.round,
                                               self.runs.deviation)],
                "notes": self.notes}


@dataclass
class Iso230Result:
    """The ISO 230-2 evaluation of a recording: per axis the standard's figures.  ``to_dict()`` is the JSON answer
    of `mtcal iso230-2`.

    Attributes
    ----------
    source : str
        The recording's source.
    axes : dict of str to AxisEvaluation
        Per axis: per-target statistics (``targets``: mean, reversal, s, R per direction) and the parameters
        (``parameters``: A, E, M, R, B and their one-direction forms) in ``unit`` (um for linear axes, arcsec
        or the ``result_unit`` for rotary ones), the runs' deviations and notes.
    temperature : dict or None
        The temperature normalisation applied (``alpha_per_K``, the formula), None when not normalised.
    """

    source: str
    axes: dict[str, AxisEvaluation]
    temperature: dict | None  # {"alpha_per_K", "formula"} when normalised

    def to_dict(self) -> dict:
        return {"file": self.source, "standard": "ISO 230-2:2014", "temperature_normalisation": self.temperature,
                "axes": {a: e.to_dict() for a, e in self.axes.items()}}


# ----------------------------------------------------------------------------- statistics (the standard)
def statistics(position, direction, deviation) -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, float]]:
    """ISO 230-2:2014 per-target values and axis parameters from one deviation per run (any unit).

    position (n,), direction (n,) in {+1, -1}, deviation (n,).  Returns (target positions (m,), per-target
    arrays named as TARGET_FIELDS, axis parameters named as PARAMETERS).  Missing quantities (a target run in
    one direction only, one run) are NaN and left out of the axis maxima and minima."""
    pos, d, x = (np.asarray(v, dtype=float) for v in (position, direction, deviation))
    targets = np.unique(pos)
    t: dict[str, np.ndarray] = {k: np.full(len(targets), np.nan) for k in TARGET_FIELDS}
    for i, p in enumerate(targets):
        for sgn, tag in ((1, "up"), (-1, "down")):
            v = x[(pos == p) & (d == sgn)]
            t[f"n_{tag}"][i] = len(v)
            if len(v):
                t[f"mean_{tag}"][i] = v.mean()
            if len(v) > 1:
                t[f"s_{tag}"][i] = v.std(ddof=1)
    t["mean"] = (t["mean_up"] + t["mean_down"]) / 2
    t["reversal"] = t["mean_up"] - t["mean_down"]
    t["R_up"], t["R_down"] = 4 * t["s_up"], 4 * t["s_down"]
    t["R"] = np.maximum(2 * t["s_up"] + 2 * t["s_down"] + np.abs(t["reversal"]), np.maximum(t["R_up"], t["R_down"]))
    return targets, t, _axis_parameters(t)


def _span(*arrays: np.ndarray) -> float:
    v = np.concatenate(arrays)
    v = v[np.isfinite(v)]
    return float(v.max() - v.min()) if len(v) else math.nan


def _finite(f, v: np.ndarray) -> float:
    v = v[np.isfinite(v)]
    return float(f(v)) if len(v) else math.nan


def _axis_parameters(t: dict[str, np.ndarray]) -> dict[str, float]:
    up_hi, up_lo = t["mean_up"] + 2 * t["s_up"], t["mean_up"] - 2 * t["s_up"]
    dn_hi, dn_lo = t["mean_down"] + 2 * t["s_down"], t["mean_down"] - 2 * t["s_down"]
    both = 1.0 if np.isfinite(t["reversal"]).any() else math.nan  # bidirectional values need both directions
    return {"B": _finite(np.max, np.abs(t["reversal"])), "B_mean": _finite(np.mean, t["reversal"]),
            "E_up": _span(t["mean_up"]), "E_down": _span(t["mean_down"]),
            "E": both * _span(t["mean_up"], t["mean_down"]), "M": _span(t["mean"]),
            "R_up": _finite(np.max, t["R_up"]), "R_down": _finite(np.max, t["R_down"]), "R": _finite(np.max, t["R"]),
            "A_up": _finite(np.max, up_hi) - _finite(np.min, up_lo),
            "A_down": _finite(np.max, dn_hi) - _finite(np.min, dn_lo),
            "A": both * (_finite(np.max, np.concatenate([up_hi, dn_hi]))
                         - _finite(np.min, np.concatenate([up_lo, dn_lo])))}


# ----------------------------------------------------------------------------- deviations from readings
def infer_directions(position: np.ndarray, order: np.ndarray) -> np.ndarray:
    """Approach direction (+1/-1) of readings of one reflector in one round: the sign of the move that reached
    each position, in ``order``; a position read twice in a row is the turn at an end of travel (reversed);
    the first reading takes the sign of the first move."""
    idx = np.argsort(order, kind="stable")
    p = position[idx]
    out = np.zeros(len(p), dtype=int)
    moves = np.sign(np.diff(p))
    first = moves[moves != 0]
    prev = int(first[0]) if len(first) else 1
    for k in range(len(p)):
        if k > 0:
            prev = int(moves[k - 1]) if moves[k - 1] != 0 else -prev
        out[k] = prev
    res = np.empty_like(out)
    res[idx] = out
    return res


def _directions(rec: Recording, idx: np.ndarray, order: np.ndarray, notes: list[str]) -> np.ndarray:
    d = rec.direction[idx].copy()
    if (d != 0).all():
        return d
    if (d != 0).any():
        i = int(idx[np.flatnonzero(d == 0)[0]])
        raise InputError(f"{rec.where(i)}: direction missing while other rows of axis {rec.axis[i]} have one")
    for r in np.unique(rec.round[idx]):
        for pt in np.unique(rec.point[idx]):
            m = (rec.round[idx] == r) & (rec.point[idx] == pt)
            d[m] = infer_directions(rec.position[idx][m], order[idx][m])
    notes.append("no direction column: approach directions inferred from the order of the readings "
                 f"({'time_s' if np.isfinite(rec.time_s[idx]).all() else 'file order'}) per round and reflector")
    return d


def _passes(rec: Recording, axis: str, point: str | None, notes: list[str]) -> dict:
    """Group the axis' rows into passes (round, position, direction) x reflectors, with reference rows."""
    idx = np.flatnonzero((rec.axis == axis) & ((rec.point == point) if point else True))
    if not len(idx):
        raise InputError(f"{rec.source}: no readings of axis {axis}" + (f" at point {point}" if point else ""))
    order = reading_order(rec, idx)
    direction = _directions(rec, idx, order, notes)
    points = sorted(set(rec.point[idx].tolist()))
    groups = group_passes(rec, idx, direction, axis)
    datum = _datum(rec, idx, order, axis)
    keys, dropped = [], []
    for k in sorted(groups):
        missing = [pt for pt in points if pt not in groups[k]]
        if missing:  # a missing reading is missing: that run has no value at this target (never re-referenced)
            dropped.append(f"round {k[0]} at {k[1]:g} ({'up' if k[2] > 0 else 'down'}: {', '.join(missing)} "
                           f"missing, line {int(rec.line[next(iter(groups[k].values()))])})")
            continue
        keys.append(k)
    if dropped:
        notes.append(f"axis {axis}: {len(dropped)} run(s) left out where a reflector's reading is missing, so the "
                     f"targets' statistics use the runs that have it: " + "; ".join(dropped[:6])
                     + (" ..." if len(dropped) > 6 else ""))
    if not keys:
        raise InputError(f"{rec.source}: axis {axis}: no pass has a reading of every reflector {points} "
                         f"(choose one with `point`)")
    q0 = datum[0]
    return {"keys": keys, "points": points, "q0": np.full(len(keys), q0),
            "rows": np.array([[groups[k][pt] for pt in points] for k in keys]),
            "ref_rows": np.array([[datum[1][pt] for pt in points] for _ in keys])}


def _datum(rec: Recording, idx: np.ndarray, order: np.ndarray, axis: str) -> tuple[float, dict[str, int]]:
    """The one datum of every run (ISO 230-2: x_ij = P_ij - P_i from the same datum): the position closest to
    zero, q0, and each reflector's first reading there (in time, or file order) over the whole recording."""
    q0 = reference_position(rec.position[idx])
    first = {k[0]: i for k, i in first_readings(rec, idx, q0, order).items()}
    missing = sorted(set(rec.point[idx].tolist()) - set(first))
    if missing:
        raise InputError(f"{rec.source}: axis {axis}: reflector(s) {missing} never read at the datum position "
                         f"{q0:g}: their deviations have no datum (choose another with `point`)")
    return q0, first


def _check_size(rec: Recording, d_m: np.ndarray, rows: np.ndarray, unit: str) -> None:
    worst = np.unravel_index(int(np.argmax(np.linalg.norm(d_m, axis=-1))), rows.shape)
    dev = float(np.linalg.norm(d_m[worst]))
    if not dev <= MAX_DEVIATION_MM:
        i = int(rows[worst])
        raise InputError(f"{rec.where(i)}: point {rec.point[i]} is {dev:.3g} mm from where the commanded motion "
                         f"takes its reference reading; positions must be in {unit} and readings in mm in the "
                         f"machine frame (another axis moving? wrong `axis`?)")


def _linear(rec: Recording, axis: str, d_m, d1, rows, pos, q0, alpha: float | None) -> np.ndarray:
    """um along the axis' direction of motion, mean over the pass' reflectors; optionally normalised to 20 C."""
    u = -d1[0, 0] / np.linalg.norm(d1[0, 0])  # reading - nominal of an unmoved point = -(motion of 1 mm)
    dev = (d_m @ u).mean(axis=-1) * 1e3
    if alpha is None:
        return dev
    temps = rec.temperature_c[rows]
    if np.isnan(temps).any():
        i = int(rows[np.isnan(temps)][0])
        raise InputError(f"{rec.where(i)}: no temperature_c; temperature normalisation needs it on every "
                         f"reading of axis {axis}")
    return normalise_20c(dev, temps.mean(axis=-1), pos, q0, alpha)


def normalise_20c(dev_um: np.ndarray, temp_c: np.ndarray, pos_mm: np.ndarray, p0_mm, alpha: float) -> np.ndarray:
    """Deviations (um) of a linear axis normalised to 20 C: x - alpha (T - 20 C) (P - P_0) (the nominal
    differential expansion of the scale / part over the travel from the datum P_0; alpha in 1/K, T in C)."""
    return dev_um - alpha * (np.asarray(temp_c) - 20.0) * (np.asarray(pos_mm) - p0_mm) * 1e3


def _rotary(rec: Recording, axis: str, pts, dls, rf1, rrel1, points, angle_unit: str) -> np.ndarray:
    """Turn about the axis beyond the commanded angle in ``angle_unit``, + in the axis' positive sense."""
    if angle_unit not in ANGLE_UNITS:
        raise InputError(f"angle unit must be one of {', '.join(ANGLE_UNITS)}, got {angle_unit!r}")
    turn = np.swapaxes(rf1, -1, -2) @ rrel1 @ rf1  # nominal rotation by +1 deg, in F
    if not abs(abs(turn[0, 1, 0]) - math.sin(math.radians(1.0))) < 1e-9:
        raise RuntimeError(f"axis {axis}: its stator frame's z is not the rotation axis (generated frames)")
    if len(points) < 3:
        raise InputError(f"{rec.source}: the angle of rotary axis {axis} needs >= 3 reflectors on the table, "
                         f"got {points}")
    e, _, _ = solve_frame(pts, dls)
    return float(np.sign(turn[0, 1, 0])) * e[:, 5] * ANGLE_UNITS[angle_unit]


def deviations(rec: Recording, axis: str, machine: Machine, point: str | None = None, angle_unit: str = "arcsec",
               alpha: float | None = None, notes: list[str] | None = None) -> Runs:
    """Positional deviation of every pass of ``axis`` (see the module docstring): um for a linear axis,
    ``angle_unit`` for a rotary one; ``alpha`` (1/K) normalises linear deviations to 20 C."""
    notes = [] if notes is None else notes
    linear = machine.axis_kinds[machine.axes.index(axis)] == "linear"
    ps = _passes(rec, axis, point, notes)
    rows, q0 = ps["rows"], ps["q0"]
    pos = np.array([k[1] for k in ps["keys"]])
    refs = rec.xyz[ps["ref_rows"]]
    at = lambda q: machine.axis_vector({axis: q})  # noqa: E731  (the other axes at zero)
    pts, dls, _, d_m, _ = frame_data(machine, axis, at(pos), at(q0), rec.xyz[rows], refs)
    _check_size(rec, d_m, rows, "mm" if linear else "deg")
    # the nominal motion by one unit from the reference: direction (linear) or sense of rotation in F (rotary)
    _, _, rf1, d1, rrel1 = frame_data(machine, axis, at(q0[:1] + 1.0), at(q0[:1]), refs[:1], refs[:1])
    if linear:
        dev, unit = _linear(rec, axis, d_m, d1, rows, pos, q0, alpha), "um"
    else:
        dev, unit = _rotary(rec, axis, pts, dls, rf1, rrel1, ps["points"], angle_unit), angle_unit
        if alpha is not None:
            notes.append(f"temperature normalisation applies to linear axes; rotary axis {axis} left as measured")
    return Runs(pos, np.array([k[2] for k in ps["keys"]]), np.array([k[0] for k in ps["keys"]]), dev,
                [sorted(int(rec.line[i]) for i in r) for r in rows], unit, q0)


# ----------------------------------------------------------------------------- the whole evaluation
def _select_targets(runs: Runs, targets, axis: str, notes: list[str]) -> Runs:
    if targets is None:
        return runs
    want = np.round(np.asarray(targets, dtype=float), 6)
    have = np.unique(runs.position)
    absent = [float(t) for t in want if not np.isclose(have, t, atol=1e-6).any()]
    if absent:
        raise InputError(f"target position(s) {absent} of axis {axis} are not in the recording (positions: "
                         f"{', '.join(f'{p:g}' for p in have)})")
    keep = np.isclose(runs.position[:, None], want[None, :], atol=1e-6).any(axis=1)
    dropped = sorted(set(runs.position[~keep].tolist()))
    if dropped:
        notes.append(f"{len(dropped)} position(s) not among the target points left out: "
                     + ", ".join(f"{p:g}" for p in dropped))
    return runs.select(keep)


def group_targets(runs: Runs, kind: str, axis: str, notes: list[str], tolerance: float | None = None,
                  source: str | None = None) -> Runs:
    """Targets closer than ``tolerance`` (mm or deg; default TARGET_TOLERANCE) are one target: a run's targets
    written a few um off are the targets of the other runs, not new ones.  Each reading keeps its deviation from its
    own written target (x_ij = P_ij - P_i); the group takes its most often written value.  Refused, naming them,
    when a group spans more than the tolerance or holds two readings of one run and direction (``source``: the
    file named in the refusal)."""
    tol = TARGET_TOLERANCE[kind] if tolerance is None else tolerance
    unit = "mm" if kind == "linear" else "deg"
    values = np.unique(runs.position)
    groups = [g for g in np.split(values, np.flatnonzero(np.diff(values) > tol) + 1) if len(g) > 1]
    if not groups:
        return runs
    pos, said = runs.position.copy(), []
    for g in groups:
        if g[-1] - g[0] > tol:
            raise InputError(f"axis {axis}: targets {', '.join(f'{v:g}' for v in g)} {unit} are each within "
                             f"{tol:g} {unit} of the next but span {g[-1] - g[0]:g} {unit}: not one target; give "
                             f"a `target_tolerance` that separates them or write the targets as they were commanded",
                             source)
        members = np.flatnonzero(np.isin(runs.position, g))
        first: dict[tuple[int, int], int] = {}
        for i in members:
            key = (int(runs.round[i]), int(runs.direction[i]))
            if key in first and runs.position[first[key]] != runs.position[i]:
                j = first[key]
                raise InputError(f"axis {axis}: targets {runs.position[j]:g} (line {runs.lines[j][0]}) and "
                                 f"{runs.position[i]:g} {unit} are within {tol:g} {unit} of each other, one target, "
                                 f"but both are read in run {key[0]} {'up' if key[1] > 0 else 'down'}: give a "
                                 f"`target_tolerance` below {abs(runs.position[i] - runs.position[j]):g} {unit} to "
                                 f"keep them apart", source, runs.lines[i][0])
            first.setdefault(key, i)
        vals, counts = np.unique(runs.position[members], return_counts=True)
        rep = float(vals[int(np.argmax(counts))])
        pos[members] = rep
        said.append(f"{', '.join(f'{v:g}' for v in vals if v != rep)} -> {rep:g}")
    notes.append(f"axis {axis}: targets within {tol:g} {unit} of each other taken as one target (each reading's "
                 f"deviation from its own written target): " + "; ".join(said[:6]) + (" ..." if len(said) > 6 else ""))
    return Runs(pos, runs.direction, runs.round, runs.deviation, runs.lines, runs.unit, runs.reference)


def _warn_design(t: dict[str, np.ndarray], positions: np.ndarray, axis: str, notes: list[str]) -> None:
    few = [f"{p:g}" for p, nu, nd in zip(positions, t["n_up"], t["n_down"]) if min(nu, nd) < RUNS]
    if few:
        notes.append(f"axis {axis}: fewer than {RUNS} runs in a direction at {len(few)} target(s) "
                     f"({', '.join(few[:6])}{' ...' if len(few) > 6 else ''}); ISO 230-2's standard test cycle has "
                     f"{RUNS} each way")
    if (t["n_down"] == 0).all() or (t["n_up"] == 0).all():
        notes.append(f"axis {axis}: unidirectional runs only: reversal and bidirectional values are undefined (NaN)")
    if len(positions) < 5:
        notes.append(f"axis {axis}: {len(positions)} target positions; ISO 230-2 asks for at least 5")


def evaluate(rec: Recording, axis: str | None = None, machine: str | Machine = DEFAULT_MACHINE, targets=None,
             alpha: float | None = None, angle_unit: str = "arcsec", point: str | None = None,
             result_unit: str | None = None, target_tolerance: float | None = None) -> Iso230Result:
    """ISO 230-2:2014 evaluation of the positioning of one axis, or of every axis in a recording.

    Deviations (actual - target) are taken from one datum for all runs; a missing reading is missing (never filled);
    approach directions come from the ``direction`` column or, without it, from the order of the readings.

    Parameters
    ----------
    rec : Recording
        The readings (mm, machine frame): each target approached in + and - direction in every run (round).
    axis : str, optional
        The axis (default: every axis in the recording).
    machine : str or Machine, optional
        The machine spec (default ``dmu50``).
    targets : array_like, optional
        Evaluate only these target positions (mm or deg).
    alpha : float, optional
        Expansion coefficient, 1/K: normalise linear axes to 20 degC from ``temperature_c``.
    angle_unit : str, optional
        Unit of rotary axes' deviations (default ``"arcsec"``).
    point : str, optional
        Use this reflector only (default: all, averaged per reading).
    result_unit : str, optional
        The deviations' unit (RESULT_UNITS; default um for linear, ``angle_unit`` for rotary axes).
    target_tolerance : float, optional
        Targets closer than this (mm or deg) are one target (``group_targets``; default: the stated tolerance).

    Returns
    -------
    Iso230Result
        Per axis the standard's figures A, E, M, R, B (and per direction), per-target statistics, notes.

    Raises
    ------
    mtcal.errors.InputError
        An axis not in the recording or of the machine, too few runs, a bad unit.

    Examples
    --------
    >>> import mtcal
    >>> from mtcal.data import path
    >>> ev = mtcal.evaluate_iso230_2(mtcal.read_recording(path("demo_campaign.csv")), "X")
    >>> x = ev.axes["X"]
    >>> x.unit, {k: round(x.parameters[k], 1) for k in ("A", "E", "M", "R", "B")}
    ('um', {'A': 63.0, 'E': 26.2, 'M': 20.3, 'R': 45.1, 'B': 18.1})
    """
    m = machine if isinstance(machine, Machine) else load_machine(machine)
    axes = [axis] if axis else rec.axes()
    out: dict[str, AxisEvaluation] = {}
    for a in axes:
        if a not in m.axes:
            raise InputError(f"axis {a} is not an axis of machine {m.name} ({', '.join(m.axes)})")
        if a not in rec.axes():
            raise InputError(f"{rec.source}: no readings of axis {a} (axes present: {', '.join(rec.axes())})")
        notes: list[str] = []
        runs = deviations(rec, a, m, point, "arcsec" if result_unit else angle_unit, alpha, notes)
        if result_unit is not None:
            runs = in_unit(runs, result_unit)
        notes.append(f"one datum for every run (ISO 230-2 x_ij = P_ij - P_i): each reflector's first reading at "
                     f"the position closest to zero ({', '.join(f'{r:g}' for r in sorted(set(runs.reference)))})")
        out[a] = evaluate_runs(runs, a, m.kind(a), targets, notes, target_tolerance, rec.source)
    return Iso230Result(rec.source, out, temperature_normalisation(alpha))


def temperature_normalisation(alpha: float | None) -> dict | None:
    """The normalisation statement of a result (None without alpha)."""
    if alpha is None:
        return None
    return {"alpha_per_K": alpha, "formula": "x <- x - alpha * (T - 20 C) * (P - P_0) (linear axes; T: the "
            "material temperature of the run, P_0: the datum position)"}


def evaluate_runs(runs: Runs, axis: str, kind: str, targets=None, notes: list[str] | None = None,
                  target_tolerance: float | None = None, source: str | None = None) -> AxisEvaluation:
    """ISO 230-2 evaluation of one axis from its runs' deviations (any input: a tracker recording through
    ``deviations``, or an interferometer's readings, mtcal.iso230_2.readings); ``kind`` "linear" | "rotary";
    targets closer than ``target_tolerance`` (mm / deg, default TARGET_TOLERANCE) are one (``group_targets``)."""
    notes = [] if notes is None else notes
    runs = group_targets(runs, kind, axis, notes, target_tolerance, source)
    runs = _select_targets(runs, targets, axis, notes)
    positions, t, params = statistics(runs.position, runs.direction, runs.deviation)
    _warn_design(t, positions, axis, notes)
    return AxisEvaluation(axis, kind, runs.unit, "mm" if kind == "linear" else "deg", positions, t, params, runs,
                          sorted(set(runs.reference.tolist())), notes)
