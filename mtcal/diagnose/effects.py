"""The candidate effects of the diagnosis: their design columns in the measured coordinates.

Each candidate is one effect at one place (an axis, an error function, a warm-up time constant, a pitch) with
its columns G (n readings, 3 coordinates, k parameters) = d(measured point, machine frame, mm) / d(parameters),
taken from the generated signatures (generated/signatures_numpy.py, derived in derive/signatures.py) and the
generated point Jacobians of the machine (columns of the 41 ISO errors).  Parameter units: backlash mm (rad for
B, C) reversal value; scale ppm; second_order per mm^2 or deg^2; periodic mm (rad) amplitudes of sin and cos;
thermal_drift mm (3-vector final displacement); offset and outlier mm (3-vector shift); tracker_scale ppm;
squareness / rotary_location mm or rad; reversal_angular rad (angle(+ approach) - angle(- approach));
reversal_straightness mm (straightness(+ approach) - straightness(- approach));
nest_creep mm/s (3-vector in the side's local frame); tracker_settling rad/s and rad (rotation vector about the
tracker: ramp rate and settled angle); thermal_temperature ppm/K (expansion) or mm/K (3-vector drift).

Each builder states its candidate's grammar attributes (``Grammar``: where x what x how, derive/grammar.py's
lattice), from which the selection decides (nesting by the columns, ties, rivals, folds, what separates two).
Effect names and vocabulary follow docs/design.md; ``QUASI_STATIC`` are the effects that are themselves smooth
functions of the measured axis' position (part of the fitted base model's family when no model is given).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from scipy.interpolate import BSpline

from mtcal.campaign.effects import NAMES
from mtcal.generated import signatures_numpy as S
from mtcal.kinematics.machine import Machine
from mtcal.measurement.passes import reference_position

# The effect names (docs/design.md): the simulator's physics (the one list, mtcal.campaign.effects.NAMES) and
# what only the diagnosis names (a straightness that differs by approach direction has no simulator model yet).
VOCABULARY = (*NAMES, "reversal_straightness")
QUASI_STATIC = ("scale", "squareness", "rotary_location", "second_order", "cross_axis")
NEEDS_SEPARATION = ("tracker_scale", "periodic")  # named only beyond engine.WEAK_TOL from the base family
UNEXPLAINED = "unexplained"  # name of the free-form candidates: selected, they are reported as unexplained
SIDE = {"spindle": "tool", "table": "table"}  # the side (of the readings) a drift's target moves
TAUS_S = (300.0, 600.0, 1200.0, 1800.0, 3600.0, 7200.0, 14400.0)  # warm-up time constants tried, s


def constants(machine: Machine) -> dict[str, tuple[str, str]]:
    """Squareness and location constants of the machine -> (effect name, the axis whose motion shows it: the
    last letter of the ISO name, e.g. E_C0Y -> Y, E_X0C -> C)."""
    g = machine.error_groups
    return {**{e: ("squareness", e[-1]) for e in g["squareness"]},
            **{e: ("rotary_location", e[-1]) for e in g["location"]}}


@dataclass(frozen=True)
class Where:
    """Where a member acts (derive/grammar.py's *where*): ``at`` one of WHERE (an axis' error motions, a side's
    nests, one nest, a station's frame, the air about the stations, one reading), ``key`` which one (the axis, the
    side, the nest's label; None for the frame, the air and a reading), ``station`` the station of a frame (None:
    the only one, or every one)."""

    at: str
    key: str | None = None
    station: str | None = None


WHERE = ("axis", "side", "nest", "frame", "air", "reading")
WHAT = ("translation", "rotation", "expansion", "scatter")  # an error motion is a translation or a rotation
HOW = ("time", "temperature", "round", "position", "direction")  # what a member depends on
LAW_STEP = "step"  # the time law of a change at one moment (the others: "ramp", "lag"; position: "periodic", ...)


@dataclass(frozen=True)
class How:
    """How a member depends (derive/grammar.py's *how*): ``on`` the variables of HOW it changes with (none: a
    constant), ``law`` its shape in them (a time law "step" / "ramp" / "lag", a position law "periodic" /
    "polynomial"; "" none stated)."""

    on: frozenset = frozenset()
    law: str = ""

    @property
    def gradual(self) -> bool:
        """A change in time that is not a step at one moment."""
        return "time" in self.on and self.law != LAW_STEP


@dataclass(frozen=True)
class Grammar:
    """A candidate's place in the grammar (where x what x how), stated where the candidate is built; the selection
    decides from these attributes and from the candidates' columns, never from their names.  ``free``: a free form
    of its place (named UNEXPLAINED), not a member."""

    where: Where
    what: str
    how: How = How()
    free: bool = False

    @property
    def place(self) -> tuple | None:
        """Where a change in time (or of one round) acts, as the ties compare it: the tracker (a station's frame and
        the air about it are one place, ("tracker", station)), a side, one nest; None for what is constant in time
        and for an axis' error motions or one reading, whose rivals the columns order."""
        if self.where.at in ("axis", "reading") or not self.varies_in_time:
            return None
        if self.where.at in ("frame", "air"):
            return ("tracker", self.where.station)
        return (self.where.at, self.where.key)

    @property
    def varies_in_time(self) -> bool:
        """Depends on time (or on a temperature that follows it) or is specific to one round: validated on held-out
        alternate readings, not held-out rounds (a held-out round fitted alone absorbs a step or a slow change into
        its reflector positions)."""
        return bool(self.how.on & {"time", "temperature", "round"})

    @property
    def alike_at_every_pose(self) -> bool:
        """A translation of a side or of a station's frame, or an expansion of a side about its own layout: it moves
        each nest of the place alike whatever the machine's pose (a turn grows with its lever, an error motion with
        the axis' position, a scale about the tracker with the distance)."""
        return self.what == "translation" and self.where.at in ("side", "frame") or (
            self.what == "expansion" and self.where.at == "side")

    @property
    def step(self) -> bool:
        """A change at one moment that stays (the time law LAW_STEP)."""
        return self.how.law == LAW_STEP

    @property
    def jump(self) -> bool:
        """A rigid shift at one moment: a translation of one round, or a step in time."""
        return self.what == "translation" and ("round" in self.how.on or self.how.law == LAW_STEP)


def _g(at: str, key: str | None = None, what: str = "translation", on: tuple = (), law: str = "",
       station: str | None = None, free: bool = False) -> Grammar:
    return Grammar(Where(at, key, station), what, How(frozenset(on), law), free)


def _motion(error: str) -> str:
    """The *what* of an ISO error motion (E_XX, E_YX: a translation; E_AX: a rotation)."""
    return "translation" if error[2] in "XYZ" else "rotation"


def _target(side: str) -> str:
    """The drift target (SIDE's key) that moves ``side``."""
    return next(t for t, s in SIDE.items() if s == side)


def _side_or_frame(target: str) -> tuple[str, str | None]:
    """(at, key) of a drift's target: the tracker's frame, or the side it moves."""
    return ("frame", None) if target == "tracker" else ("side", SIDE[target])


@dataclass
class Candidate:
    """One candidate effect: ``G`` (n, 3, k) in mm per parameter unit, zero on readings it does not touch."""

    name: str
    axis: str | None
    label: str                  # e.g. "E_XX", "tau=1800 s", "pitch=200 mm"
    G: np.ndarray
    params: list[str]           # parameter names, with units
    direction: str | None = None
    family: str = ""            # candidates sharing a family compete (multiplicity counted over the family)
    extra: dict = field(default_factory=dict)
    refine: Callable[[float], "Candidate"] | None = None  # continuous parameter (tau, pitch) -> candidate
    refine_range: tuple[float, float] | None = None
    refine_value: float | None = None
    nested: "Candidate | None" = None  # the simpler member it contains at its place (selection._simplest)
    grammar: Grammar | None = None  # where x what x how (None: a check beside a candidate, not a member)

    @property
    def title(self) -> str:
        """A short name for a sentence: the name in words (with its variant), or a free form's label."""
        if self.grammar is not None and self.grammar.free:
            return f"the free form of {self.axis or 'the place'} ({self.label})"
        variant = self.extra.get("variant")
        return self.name.replace("_", " ") + (f" ({variant})" if variant else "")

    @property
    def free(self) -> bool:
        """A free form of a place (or a check), not a member of the grammar."""
        return self.grammar is None or self.grammar.free

    @property
    def free_in_time(self) -> bool:
        """A free form of an error motion's shape changing with time (growing_free)."""
        return self.free and self.grammar is not None and "time" in self.grammar.how.on

    @property
    def moved(self) -> np.ndarray:
        """(n,) bool: the readings this effect displaces (a nonzero row of ``G``)."""
        return np.any(self.G != 0, axis=(1, 2))


@dataclass
class Geometry:
    """What the candidates need from the prepared recording (see mtcal.diagnose.prepare)."""

    axis: np.ndarray        # (n,) str
    point: np.ndarray       # (n,) str, reflector labels
    position: np.ndarray    # (n,) mm or deg
    direction: np.ndarray   # (n,) +1 / -1 / 0
    time_s: np.ndarray      # (n,) s, NaN when absent
    side: np.ndarray        # (n,) "tool" / "table"
    xyz: np.ndarray         # (n, 3) mm, each reading's nominal position (its reflector's reference position moved
    #                         by the nominal kinematics): the lever arm of a turn or a scale, free of the reading's
    #                         noise (columns built on the readings themselves fit the residual through their
    #                         differences: icelinker's sigma ratio 9.0 -> 1.8 from a tie's eight columns)
    J: np.ndarray           # (n, 3, n_errors) point Jacobian of the errors at zero error
    machine: Machine
    tracker: np.ndarray | None
    rotation: np.ndarray | None = None   # (n, 3, 3) the reflector's side rotation, local -> machine frame
    temperature_c: np.ndarray | None = None  # (n,) degC, NaN when absent
    station: np.ndarray | None = None    # (n,) station label of every reading (several stations only)
    trackers: dict[str, np.ndarray] | None = None  # station label -> tracker position (3,) mm (several stations)

    def col(self, name: str) -> np.ndarray:
        return self.J[:, :, self.machine.error_names.index(name)]

    def linear(self, axis: str) -> bool:
        return self.machine.kind(axis) == "linear"

    def stations(self) -> list[str | None]:
        """The stations of the tracker-dependent candidates: every label of a multi-station recording, else
        [None] (one station: every reading, ``tracker``)."""
        return list(self.trackers) if self.trackers else [None]

    def at(self, station: str | None) -> tuple[np.ndarray, np.ndarray | None, str]:
        """(readings of ``station`` (bool (n,)), its tracker position (3,) mm, " of station LABEL" or "")."""
        if station is None:
            return np.ones(len(self.axis), bool), self.tracker, ""
        return self.station == station, self.trackers[station], f" of station {station}"


def _tag(station: str | None) -> dict:
    """The ``extra`` entry naming the station of a per-station candidate (none for one station)."""
    return {"station": station} if station else {}


def _on(g: Geometry, axis: str) -> np.ndarray:
    return (g.axis == axis)[:, None]


def backlash(g: Geometry, axis: str) -> Candidate:
    e = g.machine.positioning_errors[axis]
    G = S.backlash_signature(g.col(e), g.direction.astype(float)) * _on(g, axis)
    unit = "mm" if g.linear(axis) else "rad"
    return Candidate("backlash", axis, e, G[:, :, None], [f"reversal value ({unit})"], family=f"backlash {axis}",
                     extra={"error": e}, grammar=_g("axis", axis, _motion(e), ("direction",)))


def scale(g: Geometry, axis: str) -> Candidate:
    e = g.machine.positioning_errors[axis]
    q = g.position if g.linear(axis) else np.deg2rad(g.position)
    G = S.scale_signature(g.col(e), q) * _on(g, axis)
    return Candidate("scale", axis, e, G[:, :, None], ["ppm"], family=f"scale {axis}", extra={"error": e},
                     grammar=_g("axis", axis, _motion(e), ("position",), "polynomial"))


def second_order(g: Geometry, axis: str, error: str) -> Candidate:
    G = S.second_order_signature(g.col(error), g.position) * _on(g, axis)
    unit = ("mm" if error[2] in "XYZ" else "rad") + "/" + ("mm^2" if g.linear(axis) else "deg^2")
    return Candidate("second_order", axis, error, G[:, :, None], [f"coefficient ({unit})"],
                     family=f"second_order {axis}", extra={"error": error},
                     grammar=_g("axis", axis, _motion(error), ("position",), "polynomial"))


def constant(g: Geometry, name: str, errors: str | list[str]) -> Candidate:
    """Squareness or location constants of one axis (a name or a list), fitted together (a location error of a
    rotary axis is 2-D: testing E_X0C alone would leave E_Y0C to a knock or a drift)."""
    errors = [errors] if isinstance(errors, str) else list(errors)
    axis = constants(g.machine)[errors[0]][1]
    G = np.stack([g.col(e) for e in errors], axis=-1) * _on(g, axis)[:, :, None]
    units = ["mm" if e[2] in "XY" and name == "rotary_location" else "rad" for e in errors]
    return Candidate(name, axis, ", ".join(errors), G, [f"{e} ({u})" for e, u in zip(errors, units)],
                     family=f"{name} {axis}", extra={"error": errors[0] if len(errors) == 1 else list(errors)},
                     grammar=_g("axis", axis, _motion(errors[0])))


def periodic(g: Geometry, axis: str, pitch: float, span: tuple[float, float]) -> Candidate:
    e = g.machine.positioning_errors[axis]
    G = S.periodic_signature(g.col(e), g.position, float(pitch)) * _on(g, axis)[:, :, None]
    unit, amp_unit = g.machine.unit(axis), "mm" if g.linear(axis) else "rad"
    c = Candidate("periodic", axis, f"pitch={pitch:.4g} {unit}", G, [f"sin amplitude ({amp_unit})", "cos amplitude"],
                  family=f"periodic {axis}", extra={"error": e, "pitch": float(pitch), "pitch_unit": unit,
                                                    "amplitude_unit": amp_unit},
                  grammar=_g("axis", axis, _motion(e), ("position",), "periodic"))
    c.refine = lambda p: periodic(g, axis, p, span)
    c.refine_range, c.refine_value = span, float(pitch)
    return c


def pitch_grid(positions: np.ndarray, linear: bool, max_harmonic: int) -> tuple[np.ndarray, tuple[float, float]]:
    """Pitches that the sampling resolves (>= 2.2 position steps) and that are not a low harmonic of the travel."""
    u = np.unique(positions)
    if len(u) < 5:
        return np.zeros(0), (0.0, 0.0)
    step = float(np.min(np.diff(u)))
    travel = float(u[-1] - u[0])
    lo = 2.2 * step
    hi = travel / 1.2 if linear else 360.0 / (max_harmonic + 0.5)
    if hi <= lo:
        return np.zeros(0), (0.0, 0.0)
    n = int(np.ceil(np.log(hi / lo) / np.log(1.08))) + 1
    return np.geomspace(lo, hi, n), (lo, hi)


def thermal_drift(g: Geometry, target: str, tau: float, t0: float, station: str | None = None) -> Candidate:
    """A side (spindle, table) or the tracker (of ``station``: its readings only) drifting from t0 (s)."""
    rows, _, of = g.at(station)
    on = rows if target == "tracker" else g.side == SIDE[target]
    dt = np.where(np.isfinite(g.time_s), np.maximum(g.time_s - t0, 0.0), 0.0)
    G = S.thermal_drift_signature(dt, float(tau)) * on[:, None, None]
    c = Candidate("thermal_drift", None, f"{target}{of}, tau={tau:.0f} s", G,
                  ["A_x (mm)", "A_y (mm)", "A_z (mm)"], family="thermal_drift",
                  extra={"target": target, "tau_s": float(tau), "t0_s": float(t0),
                         **_tag(station)}, grammar=_g(*_side_or_frame(target), on=("time",), law="lag",
                                                       station=station))
    c.refine = lambda t: thermal_drift(g, target, t, t0, station)
    c.refine_range, c.refine_value = (60.0, 86400.0), float(tau)
    return c


def tracker_scale(g: Geometry, station: str | None = None) -> Candidate:
    """The distances of the tracker (of ``station``: its readings only) scaled about it (ppm).  Per station, the
    column is centred on the station's readings: its mean is a translation of the station, which the base's
    alignment unknowns absorb (the fit is the same; the separability, relative to the column, is not dwarfed by
    the tracker's distance).  A scale common to every station is a scale of the machine frame (the axes' scale
    errors): per station, the scale is relative to the first station's (mtcal.diagnose.candidates)."""
    on, t, of = g.at(station)
    G = np.zeros((len(on), 3))
    G[on] = S.tracker_scale_signature(g.xyz[on], t)
    if station is not None:  # less its mean over the station, a translation that its alignment absorbs
        G[on] -= G[on].mean(axis=0)
    rel = f" relative to station {g.stations()[0]}" if station is not None else ""
    return Candidate("tracker_scale", None, f"about the tracker{of}{rel}", G[:, :, None], ["ppm"],
                     family="tracker_scale",
                     extra={"tracker": [float(v) for v in t], **_tag(station)},
                     grammar=_g("frame", what="expansion", station=station))


INSTRUMENT_COORDINATES = ("distance", "azimuth", "elevation")  # the tracker's own, tracker_spherical_signature's
INSTRUMENT_SPANS = (4, 8, 16, 32, 64)  # spline intervals over a coordinate's range: the free forms' resolutions


def instrument_map(g: Geometry, coordinate: int, spans: int, station: str | None = None) -> Candidate | None:
    """The tracker (of ``station``) reading one of its own coordinates (INSTRUMENT_COORDINATES: its distance, in
    mm, or its azimuth or elevation, in rad) off by a free function of that coordinate, the same in every round --
    a distance meter's or an angle encoder's error map: the coordinate's column of tracker_spherical_signature
    times each cubic B-spline of ``spans`` intervals, knots at quantiles of the coordinate's distinct values so that
    every interval holds readings.  It spans a scale about the tracker (a distance error linear in the distance).
    None where the coordinate takes fewer distinct values than the spline has columns."""
    on, t, of = g.at(station)
    if t is None:
        return None
    x = S.tracker_spherical_coordinates(g.xyz[on], t)[:, coordinate]
    levels = np.unique(np.round(x, 9))
    if len(levels) < 2 * (spans + 3):
        return None
    inner = np.quantile(levels, np.linspace(0, 1, spans + 1))
    knots = np.r_[[inner[0]] * 3, inner, [inner[-1]] * 3]
    B = BSpline.design_matrix(np.clip(x, inner[0], inner[-1]), knots, 3).toarray()
    G = np.zeros((len(on), 3, B.shape[1]))
    G[on] = S.tracker_spherical_signature(g.xyz[on], t)[:, :, coordinate][:, :, None] * B[:, None, :]
    what = INSTRUMENT_COORDINATES[coordinate]
    unit = "mm" if coordinate == 0 else "rad"
    return Candidate(UNEXPLAINED, None, f"the tracker{of}'s {what} read off as a function of it ({spans} spans)", G,
                     [f"{what} error at spline {k + 1} ({unit})" for k in range(B.shape[1])],
                     family=f"{UNEXPLAINED} instrument",
                     extra={"kind": "instrument", "coordinate": what, "spans": spans, "tracker": [float(c) for c in t],
                            **_tag(station)},
                     grammar=_g("frame", what="expansion", on=("position",), station=station, free=True))


def outlier(g: Geometry, rows: np.ndarray, mode: str, where: dict) -> Candidate:
    on = np.zeros(len(g.axis))
    on[rows] = 1.0
    G = S.outlier_signature(on)
    label = (f"{mode}: round {where['round']} point {where['point']} at {where['position']:g} "
             f"({where['approach']:+d}), {where['readings']} reading(s)")
    return Candidate("outlier", str(g.axis[rows[0]]), label, G,
                     ["s_x (mm)", "s_y (mm)", "s_z (mm)"], family="outlier",
                     extra={"mode": mode, "rows": [int(r) for r in rows], **where},
                     grammar=_g("reading", on=("round",)))


def offset(g: Geometry, rows: np.ndarray, where: dict) -> Candidate:
    """A shift of every reading of one (axis, round, reflector) sequence: a reflector re-seated in its nest, or
    the whole round displaced (mm, machine frame)."""
    on = np.zeros(len(g.axis))
    on[rows] = 1.0
    G = S.outlier_signature(on)
    return Candidate("offset", str(g.axis[rows[0]]), f"round {where['round']} point {where['point']}", G,
                     ["s_x (mm)", "s_y (mm)", "s_z (mm)"], family=f"offset {g.axis[rows[0]]}",
                     extra={"variant": "re-seated nest", "rows": [int(r) for r in rows], **where},
                     grammar=_g("nest", str(where["point"]), on=("round",)))


def tracker_knock(g: Geometry, t0: float, where: dict, station: str | None = None) -> Candidate:
    """The tracker (stand; of ``station``: its readings only, until it is re-aligned) knocked at ``t0`` (s): every
    reading from t0 on, of every axis and reflector, displaced by one constant vector (mm, machine frame) -- the
    planted effect ``offset`` of mtcal.campaign.effects.  The change point t0 is scanned over the gaps between reading
    times (mtcal.diagnose.scans.knock_scan)."""
    rows, _, of = g.at(station)
    on = (rows & np.isfinite(g.time_s) & (g.time_s >= t0)).astype(float)
    G = S.outlier_signature(on)
    label = (f"tracker{of} knocked at t0 = {t0:.6g} s (from axis {where['from_axis']} round {where['round']} "
             f"point {where['point']} at {where['position']:g}, {where['readings']} reading(s) after)")
    return Candidate("offset", None, label, G, ["s_x (mm)", "s_y (mm)", "s_z (mm)"], family="offset",
                     extra={"variant": "tracker knock", "t0_s": float(t0), **where,
                            **_tag(station)}, grammar=_g("frame", on=("time",), law=LAW_STEP, station=station))


def reversal_angular(g: Geometry, axis: str, error: str) -> Candidate:
    """An angular error (pitch, yaw or roll) of a linear axis that differs between + and - approach by r (rad)."""
    G = S.reversal_angular_signature(g.col(error), g.direction.astype(float)) * _on(g, axis)
    return Candidate("reversal_angular", axis, error, G[:, :, None], ["r = angle(+) - angle(-) (rad)"],
                     family=f"reversal_angular {axis}", extra={"error": error},
                     grammar=_g("axis", axis, _motion(error), ("direction",)))


def reversal_straightness(g: Geometry, axis: str, error: str) -> Candidate:
    """A straightness of a linear axis that differs between + and - approach by r (mm): the carriage sits to one
    side of its guideway's play after each approach (a lateral play); the same generated signature as backlash,
    on the straightness error's column."""
    G = S.backlash_signature(g.col(error), g.direction.astype(float)) * _on(g, axis)
    return Candidate("reversal_straightness", axis, error, G[:, :, None],
                     ["r = straightness(+) - straightness(-) (mm)"], family=f"reversal_straightness {axis}",
                     extra={"error": error}, grammar=_g("axis", axis, _motion(error), ("direction",)))


def nest_creep(g: Geometry, label: str, side: str, t0: float) -> Candidate:
    """One reflector's nest (label, on the tool or table side: a label may name a nest on each) creeping at a
    constant velocity (mm/s, the side's local frame) from t0 (s)."""
    on = (g.point == label) & (g.side == side) & np.isfinite(g.time_s)
    dt = np.where(on, np.maximum(g.time_s - t0, 0.0), 0.0)
    G = S.nest_creep_signature(g.rotation.reshape(-1, 9), dt) * on[:, None, None]
    return Candidate("nest_creep", None, f"point {label} ({side} side)", G,
                     ["v_x (mm/s)", "v_y (mm/s)", "v_z (mm/s)"], family="nest_creep",
                     extra={"point": str(label), "side": side, "t0_s": float(t0)},
                     grammar=_g("nest", str(label), on=("time",), law="ramp"))


def nest_knock(g: Geometry, label: str, side: str, t0: float, where: dict) -> Candidate:
    """One reflector's nest (label, on the tool or table side) knocked at ``t0`` (s): displaced by one vector (mm,
    the side's local frame) from then on, across the axis blocks that follow -- the creep's generated signature
    with a step for the time.  t0 is scanned over the gaps between that nest's reading times
    (mtcal.diagnose.scans.knock_scan)."""
    on = (g.point == label) & (g.side == side) & np.isfinite(g.time_s)
    step = (on & (g.time_s >= t0)).astype(float)
    G = S.nest_creep_signature(g.rotation.reshape(-1, 9), step) * on[:, None, None]
    return Candidate("nest_knock", None, f"point {label} ({side} side) knocked at t0 = {t0:.6g} s (from axis "
                     f"{where['from_axis']} round {where['round']} at {where['position']:g}, {where['readings']} "
                     f"reading(s) after)", G, ["s_x (mm)", "s_y (mm)", "s_z (mm)"], family="nest_knock",
                     extra={"point": str(label), "side": side, "t0_s": float(t0), "frame": f"the {side} side's",
                            **where}, grammar=_g("nest", str(label), on=("time",), law=LAW_STEP))


def tracker_settling(g: Geometry, tau: float, t0: float, station: str | None = None) -> Candidate:
    """The tracker (of ``station``: its readings only) turning slowly about an axis through it: rotation vector
    w dt + a (1 - exp(-dt/tau)) (rad/s, rad; x, y, z components), every reading rotated about the tracker."""
    on, t, of = g.at(station)
    dt = np.where(np.isfinite(g.time_s), np.maximum(g.time_s - t0, 0.0), 0.0)
    G = np.zeros((len(on), 3, 6))
    G[on] = np.concatenate([S.tracker_settling_signature(g.xyz[on], t, u, dt[on], float(tau)) for u in np.eye(3)],
                           axis=-1)
    params = [f"{k}_{c}" for c in "xyz" for k in ("w (rad/s)", "a (rad)")]
    c = Candidate("tracker_settling", None, f"about the tracker{of}, tau={tau:.0f} s", G, params,
                  family="tracker_settling", extra={"tau_s": float(tau), "t0_s": float(t0),
                                                    "t_end_s": float(np.nanmax(g.time_s[on])),
                                                    "tracker": [float(v) for v in t],
                                                    **_tag(station)},
                  grammar=_g("frame", what="rotation", on=("time",), law="lag", station=station))
    c.refine = lambda t: tracker_settling(g, t, t0, station)
    c.refine_range, c.refine_value = (60.0, 86400.0), float(tau)
    return c


def thermal_temperature_scale(g: Geometry, axis: str, dT: np.ndarray) -> Candidate:
    """The positioning error of a linear axis growing with the recorded temperature rise: 1e-6 k dT q (ppm/K)."""
    e = g.machine.positioning_errors[axis]
    G = S.thermal_temperature_signature(g.col(e), g.position, dT) * _on(g, axis)
    return Candidate("thermal_temperature", axis, f"expansion of {e} with temperature", G[:, :, None],
                     ["k (ppm/K)"], family="thermal_temperature", extra={"error": e, "variant": "expansion"},
                     grammar=_g("axis", axis, _motion(e), ("position", "temperature"), "polynomial"))


def thermal_temperature_drift(g: Geometry, target: str, dT: np.ndarray) -> Candidate:
    """A side (spindle, table) or the tracker drifting by c dT with the recorded temperature rise (mm/K)."""
    on = np.ones(len(g.axis), bool) if target == "tracker" else g.side == SIDE[target]
    G = S.thermal_temperature_drift_signature(dT) * on[:, None, None]
    return Candidate("thermal_temperature", None, f"{target} drifting with temperature", G,
                     ["c_x (mm/K)", "c_y (mm/K)", "c_z (mm/K)"], family="thermal_temperature",
                     extra={"target": target, "variant": "drift"},
                     grammar=_g(*_side_or_frame(target), on=("temperature",)))


# ----------------------------------------------------------------------------- free-form checks of a named effect
def reversal_free(g: Geometry, axis: str) -> Candidate:
    """Free-form reversal of an axis: per reflector, a 3-vector r (mm, the side's local frame; reading(+ approach)
    - reading(- approach)) by which its readings differ between the directions of approach.  It spans every
    reversal effect of the axis (backlash, reversal_angular, a lateral play of the guideway): what it explains
    beyond a named one, that one's signature leaves unexplained.  Selected itself, it is reported under
    "unexplained" (located by direction x point), never as a named effect."""
    on = (g.axis == axis) & (g.direction != 0)
    half = np.where(on, 0.5 * g.direction, 0.0)
    labels = sorted(set(g.point[on].tolist()))
    G = np.concatenate([S.nest_creep_signature(g.rotation.reshape(-1, 9), np.where(g.point == p, half, 0.0))
                        for p in labels], axis=-1)
    return Candidate(UNEXPLAINED, axis, "direction of approach x reflector (free-form reversal)", G,
                     [f"r_{c}({p}) (mm)" for p in labels for c in "xyz"], family=f"{UNEXPLAINED} reversal {axis}",
                     extra={"points": labels, "kind": "reversal"},
                     grammar=_g("axis", axis, on=("direction",), free=True))


def axis_blocks(g: Geometry, axis: str) -> list[np.ndarray]:
    """The blocks of ``axis`` (bool (n,) each, in time order): its readings cut where the reading before one in time
    is of another axis -- one uninterrupted stretch of measuring the axis (a station's rounds of it, one after
    another).  Needs every reading's time."""
    order = np.argsort(g.time_s, kind="stable")
    mine = g.axis[order] == axis
    starts = mine & ~np.r_[False, mine[:-1]]
    label = np.cumsum(starts) * mine
    out = []
    for b in range(1, int(label.max(initial=0)) + 1):
        sel = np.zeros(len(g.axis), bool)
        sel[order[label == b]] = True
        out.append(sel)
    return out


def _block_time(g: Geometry, axis: str, per_block: bool) -> np.ndarray:
    """tau of growing_free (n,): (t - the mid time) / the duration, of the axis' whole span of time or of each of
    its blocks (axis_blocks); zero off the axis."""
    tau = np.zeros(len(g.axis))
    for on in axis_blocks(g, axis) if per_block else [(g.axis == axis) & np.isfinite(g.time_s)]:
        t = g.time_s[on]
        tau[on] = (t - 0.5 * (t.min() + t.max())) / max(float(np.ptp(t)), 1e-9)
    return tau


def growing_free(g: Geometry, axis: str, full: bool = True, motion: str | None = None,
                 per_block: bool = False) -> Candidate:
    """Free-form change of an axis' error motions with time while it is measured: each of its six error motions
    plus sum c_eji s_j tau_i, s_1 = s and s_2 = s^2 (s = the position from the axis' reference position over the
    travel; a rotary axis: cos and sin less their values there), tau_1 = tau and tau_2 = tau^2 - mean (tau = (t -
    the block's mid time) / its duration), c_eji in mm or rad.  A scale or straightness growing over the rounds (a
    ball screw warming with no temperature channel).  Like the base's error functions it vanishes at the reference
    position (mtcal.measurement.passes), so a drift of the whole side stays thermal_drift's.  Selected itself, it
    is reported under "unexplained" (located by position x time), never as a named effect.  ``full`` False: the
    linear member only (s_1 tau_1 of each error motion: six columns, a scale or a slope growing steadily), the
    family's sharper test of the commonest case.  ``per_block``: tau of each block of the axis (axis_blocks)
    instead of its whole span: a screw warming while the axis moves and cooling while the others are measured,
    the growth starting again in each block (a station's rounds).  ``motion``: one error motion's shape along the
    travel growing steadily (s_1 tau_1 and s_2 tau_1 of that motion only: two columns), the sharpest test where
    one guideway bows or one screw grows as it warms (gen2 3589/16: a straightness E_XY bowing 8.9 um by the end,
    F = 4.7 on the six linear columns, missed; its own shape p = 8e-9); offered from three rounds
    (mtcal.diagnose.candidates)."""
    on = (g.axis == axis) & np.isfinite(g.time_s)  # the caller makes sure the axis' times are all known
    tau = _block_time(g, axis, per_block)
    q = g.position[on]
    q0 = reference_position(q)
    if g.linear(axis):
        s = (q - q0) / max(float(np.ptp(q)), 1e-9)
        shapes = [s, s**2][:2 if full or motion else 1]
    else:
        th, t0 = np.deg2rad(q), np.deg2rad(q0)
        shapes = [np.cos(th) - np.cos(t0), np.sin(th) - np.sin(t0)]
    times = [tau[on], tau[on] ** 2 - np.mean(tau[on] ** 2)][:2 if full and not motion else 1]
    errors = [motion] if motion else list(g.machine.error_motions(axis))
    cols, names = [], []
    for e in errors:
        for i, tm in enumerate(times):
            for j, sh in enumerate(shapes):
                f = np.zeros(len(g.axis))
                f[on] = sh * tm
                cols.append(g.col(e) * f[:, None])
                names.append(f"c_{e},{j + 1}{i + 1} ({'rad' if e[2] in 'ABC' else 'mm'})")
    label = (f"position x time, {motion} (one error motion growing steadily while measured)" if motion else
             "position x time (error motions changing while measured)" if full else
             "position x time, linear (error motions growing steadily while measured)")
    if per_block:
        label = label.replace("while measured", "in each block of the axis, from its mid time")
    return Candidate(UNEXPLAINED, axis, label, np.stack(cols, axis=-1), names, family=f"{UNEXPLAINED} growing {axis}",
                     extra={"kind": "growing", "errors": errors, "per_block": per_block},
                     grammar=_g("axis", axis, on=("position", "time"), free=True))


def repeated(g: Geometry, c: Candidate) -> Candidate:
    """The readings at the places of a scanned outlier (axis, reflector, position, approach) in the other rounds,
    shifted by one 3-vector (mm, machine frame): a displacement found there too is not a one-off event."""
    key = np.array([f"{a}|{p}|{q!r}|{d}" for a, p, q, d in zip(g.axis, g.point, g.position, g.direction)])
    return _others_shifted(c, key, "outlier (other rounds)", "same places, other rounds")


def by_pose(g: Geometry, point: str, side: str, degree: int) -> list[Candidate]:
    """The nest ``point`` on ``side`` displaced on its own with the pose of the machine, the same in every round
    and either direction, a translation (mm, machine frame): [smoothly: a polynomial of ``degree`` in each axis'
    position per station and axis (Legendre, the axis' travel scaled to [-1, 1]), the sharper member; free: at
    each pose it is read at more than once (station, axis, position)].  The free form of a nest's displacement
    that depends on the pose and not on the time; [] where no pose repeats."""
    on = (g.point == point) & (g.side == side)
    st = g.station if g.station is not None else np.full(len(on), "")
    key = np.array([f"{s}|{a}|{p!r}" for s, a, p in zip(st, g.axis, g.position)])
    ids, counts = np.unique(key[on], return_counts=True)
    if not (counts >= 2).any():
        return []
    smooth = []
    for s, a in sorted(set(zip(st[on].tolist(), g.axis[on].tolist()))):
        rows = on & (st == s) & (g.axis == a)
        x = g.position[rows]
        t = (2 * x - x.max() - x.min()) / ((x.max() - x.min()) or 1.0)
        for d in range(degree + 1 if len(set(x.tolist())) > degree else 1):
            col = np.zeros(len(on))
            col[rows] = np.polynomial.legendre.legval(t, [0] * d + [1])
            smooth.append(col)
    free = [(on & (key == k)).astype(float) for k in ids[counts >= 2]]
    return [Candidate(UNEXPLAINED, None, f"point {point} ({side} side) displaced with the pose{how}",
                      np.concatenate([S.outlier_signature(c) for c in cols], axis=-1),
                      [f"pose term {j + 1} {x} (mm)" for j in range(len(cols)) for x in "xyz"], family="check")
            for cols, how in ((smooth, ", smoothly"), (free, ""))]


def by_station(g: Geometry, point: str, side: str) -> Candidate | None:
    """The nest of ``point`` on ``side`` read differently from each station: a translation (mm, machine frame) of
    its readings from every station but the first (the first's is its reference position); None where it is read
    from one station only."""
    on = (g.point == point) & (g.side == side)
    stations = [] if g.station is None else sorted(set(g.station[on].tolist()))
    if len(stations) < 2:
        return None
    G = np.concatenate([S.outlier_signature((on & (g.station == st)).astype(float)) for st in stations[1:]], axis=-1)
    return Candidate(UNEXPLAINED, None, f"point {point} ({side} side) per station", G,
                     [f"{st} {x} (mm)" for st in stations[1:] for x in "xyz"], family="check")


def by_cell(g: Geometry, rows: np.ndarray, directions: bool = True) -> Candidate:
    """The readings ``rows`` (indices) displaced freely in every cell they fall in -- one nest at one pose and
    direction of approach (station, axis, position, direction; ``directions`` False: both directions one cell),
    pooled over the rounds: a 3-vector (mm, machine frame) per cell, each cell's readings (outlier_signature).
    Whatever a located group's readings do that repeats at its poses, and every reading of a group read once (a
    round, a time window)."""
    rows = np.asarray(rows, dtype=int)
    st = g.station if g.station is not None else np.full(len(g.axis), "")
    d = g.direction[rows] if directions else np.zeros(len(rows))
    key = np.array([f"{p}|{s}|{a}|{q!r}|{e}" for p, s, a, q, e in
                    zip(g.point[rows], st[rows], g.axis[rows], g.position[rows], d)])
    cols = []
    for k in np.unique(key):
        on = np.zeros(len(g.axis))
        on[rows[key == k]] = 1.0
        cols.append(S.outlier_signature(on))
    return Candidate(UNEXPLAINED, None, "the group's readings free in every cell", np.concatenate(cols, axis=-1),
                     [f"cell {j + 1} {x} (mm)" for j in range(len(cols)) for x in "xyz"], family="check")


def same_stops(g: Geometry, c: Candidate, stop: np.ndarray) -> Candidate:
    """The other readings of the stops of a scanned outlier or a re-seated nest (``stop``: every reading's stop,
    mtcal.diagnose.prepared.Prepared.stop; the other nests read while the machine stood there), shifted by one
    3-vector (mm, machine frame): a displacement they share is the stop's (landing off, or the tracker moved), not
    a reading's."""
    return _others_shifted(c, stop, "outlier (same stops)", "other nests, same stops")


def _others_shifted(c: Candidate, key: np.ndarray, name: str, label: str) -> Candidate:
    """The readings sharing a ``key`` (n,) with the rows (``extra``) of ``c``, those rows left out,
    shifted by one 3-vector (mm, machine frame): a check beside the outlier, not a candidate."""
    rows = np.asarray(c.extra["rows"])
    on = np.isin(key, key[rows])
    on[rows] = False
    return Candidate(name, c.axis, label, S.outlier_signature(on.astype(float)), [], family="check")


def _per_position(g: Geometry, axis: str, errors: list[str]) -> np.ndarray:
    """(n, 3, len(errors) x positions): each error's Jacobian column where ``axis`` stands at each of its distinct
    positions, zero elsewhere (error-major)."""
    on = g.axis == axis
    return np.stack([g.col(e) * (on & (g.position == q))[:, None] for e in errors
                     for q in np.unique(g.position[on])], axis=2)


def by_position(g: Geometry, c: Candidate) -> Candidate:
    """The free shape of a periodic error's error motion over its axis' positions: one column per distinct position
    (the error motion's Jacobian column where the axis stands there): the shapes a periodic error is one of."""
    return Candidate("periodic (free shape)", c.axis, "every position", _per_position(g, c.axis, [c.extra["error"]]),
                     [], family="check")


def tabulated(g: Geometry, axis: str) -> Candidate:
    """Every error motion of ``axis`` free at every measured position (its Jacobian column where the axis stands
    there): any quasi-static error of the axis, however shaped -- what a compensation table at these positions
    holds."""
    return Candidate("error function (tabulated)", axis, "every error motion at every position",
                     _per_position(g, axis, list(g.machine.error_motions(axis))), [], family="check")


# ----------------------------------------------------------------------------- the grammar's members of issue 34
def side_expansion(g: Geometry, offset: np.ndarray, side: str, t0: float, tau: float | None = None,
                   centre: bool = False) -> Candidate:
    """The reflectors of ``side`` (tool or table) moving apart about their layout's centroid from t0 (s):
    ``offset`` (n, 3) mm is each reading's reflector position less the centroid of its axis' reflectors (the side's
    local frame, mtcal.diagnose.prepare's reference positions); a ramp (``tau`` None: e in ppm per hour) or a
    first-order lag of time constant ``tau`` (e in ppm, the final growth): derive/grammar.py's expansion x ramp_h
    or lag.  ``centre``: about a centre the data fix instead (a spindle grows from its bearing, a table about its
    clamping, not about the reflectors): three more columns, the same law's expansion at unit offsets along the
    side's axes, i.e. e (centroid - centre) in ppm mm (or ppm/h mm), the side's frame.  With a centre and a lag,
    its ``nested`` member is the side's drift with that law (thermal_drift): an expansion about a centre far from
    the reflectors is their translation, and it is named only where its growth is needed beside that
    (selection._simplest)."""
    on = (g.side == side) & np.isfinite(g.time_s)
    dt = np.where(on, np.maximum(g.time_s - t0, 0.0), 0.0)
    R = g.rotation.reshape(-1, 9)
    offsets = [offset] + ([np.broadcast_to(u, offset.shape) for u in np.eye(3)] if centre else [])
    G = np.zeros((len(g.axis), 3, len(offsets)))
    for k, off in enumerate(offsets):
        G[on, :, k] = (S.side_expansion_ramp_signature(R[on], off[on], dt[on]) if tau is None else
                       S.side_expansion_lag_signature(R[on], off[on], dt[on], float(tau)))
    law = "ramp" if tau is None else f"lag, tau={tau:.0f} s"
    unit = "ppm/h" if tau is None else "ppm"
    c = Candidate("side_expansion", None, f"{side} side, {law}" + (", centre fitted" if centre else ""), G,
                  [f"e ({unit})"] + ([f"e (centroid - centre)_{k} ({unit} mm)" for k in "xyz"] if centre else []),
                  family="side_expansion",
                  extra={"side": side, "law": "ramp" if tau is None else "lag", "t0_s": float(t0),
                         **({} if tau is None else {"tau_s": float(tau)}), "centre": centre,
                         "t_end_s": float(np.nanmax(g.time_s[on])) if on.any() else float(t0)},
                  grammar=_g("side", side, "expansion", ("time",), "ramp" if tau is None else "lag"),
                  nested=thermal_drift(g, _target(side), tau, t0) if centre and tau is not None else None)
    if tau is not None:
        c.refine = lambda t: side_expansion(g, offset, side, t0, t, centre)
        c.refine_range, c.refine_value = (60.0, 86400.0), float(tau)
    return c


def backlash_travel(g: Geometry, axis: str) -> Candidate:
    """The reversal (backlash) of an axis changing along its travel: positioning error + d / 2 (b + g q)
    (derive/grammar.py's error x direction, position x direction): b the reversal at position 0 (mm, rad rotary),
    g its change per mm (rad per deg)."""
    e = g.machine.positioning_errors[axis]
    G = S.backlash_travel_signature(g.col(e), g.direction.astype(float), g.position) * _on(g, axis)[:, :, None]
    unit, qunit = ("mm", "mm") if g.linear(axis) else ("rad", "deg")
    q = g.position[g.axis == axis]
    return Candidate("backlash_travel", axis, e, G, [f"b at 0 {qunit} ({unit})", f"g ({unit}/{qunit})"],
                     family=f"backlash_travel {axis}",
                     extra={"error": e, "travel": [float(q.min()), float(q.max())], "unit": unit,
                            "position_unit": qunit},
                     grammar=_g("axis", axis, _motion(e), ("position", "direction")))


def tracker_relevel(g: Geometry, after: np.ndarray, t0: float, where: dict, station: str | None = None,
                    knock: Candidate | None = None, pivot: np.ndarray | None = None) -> Candidate:
    """The tracker (of ``station``) re-levelled between two rounds: every reading from the first of the round
    ``where`` names on (``after``, bool (n,)) turned about horizontal axes (x, y, machine frame) through the tracker
    by w_x, w_y (rad) -- derive/grammar.py's rotation about the tracker x step.  With ``knock`` (the tracker knocked
    at the same t0: ``tracker_knock`` on the same readings) also shifted by its vector (mm): a re-levelled head
    seldom stays where it was (gen2 plants 0-40 um), and a turn about a station placed a few mm off is a turn about
    the true one and a shift.  The knock is then its ``nested`` member: the turn is named only where the data need
    it beside the shift (selection._simplest).  ``pivot`` (mm; with ``knock`` only): the turn about it instead of
    the tracker, where no station is known -- with its shift the same motion, the shift stated at the pivot."""
    rows, t, of = g.at(station)
    t = t if pivot is None else np.asarray(pivot, dtype=float)
    on = rows & after
    G = np.zeros((len(g.axis), 3, 2))
    G[on] = S.tracker_relevel_signature(g.xyz[on], t, 1.0)
    params = ["w_x (rad)", "w_y (rad)"]
    if knock is not None:
        G = np.concatenate([G, knock.G], axis=2)
        params += knock.params
    return Candidate("tracker_relevel", None, f"tracker{of} re-levelled {'and shifted ' if knock else ''}before "
                     f"round {where['round']} of axis {where['axis']} (t0 = {t0:.6g} s, {int(on.sum())} reading(s) "
                     "after)", G, params, family="tracker_relevel",
                     extra={"t0_s": float(t0), "round": int(where["round"]), "from_axis": str(where["axis"]),
                            "tracker": [float(v) for v in t], "shift": knock is not None,
                            **({} if pivot is None else {"pivot": "the readings' centre (no station known)"}),
                            **_tag(station)},
                     nested=knock, grammar=_g("frame", what="rotation", on=("time",), law=LAW_STEP, station=station))


def air_grammar(law: str = "") -> Grammar:
    """The air's drift in the grammar: an expansion about every station, changing with time."""
    return _g("air", what="expansion", on=("time",), law=law)


def air_index_drift(g: Geometry, t0: float, tau: float | None = None, station: str = "given") -> Candidate:
    """The air's refractive index drifting from t0 (s) while the tracker's weather compensation keeps its value
    there: every reading of every station scales about its own station by the same 1e-6 e h(t) (one air, one law;
    derive/grammar.py's expansion about the tracker x ramp_h or lag): a ramp (``tau`` None: e in ppm per hour) or a
    first-order lag of time constant ``tau`` (e in ppm, the final change).  ``station``: "given" (the tracker
    position(s) of the recording or --tracker) or "estimated" (mtcal.diagnose.noise's, determined by the data)."""
    G = np.zeros((len(g.axis), 3))
    dt = np.where(np.isfinite(g.time_s), np.maximum(g.time_s - t0, 0.0), 0.0)
    for st in g.stations():
        on, tracker, _ = g.at(st)
        G[on] = (S.air_index_drift_ramp_signature(g.xyz[on], tracker, dt[on]) if tau is None else
                 S.air_index_drift_lag_signature(g.xyz[on], tracker, dt[on], float(tau)))
    law = "ramp" if tau is None else f"lag, tau={tau:.0f} s"
    n = len(g.stations())
    c = Candidate("air_index_drift", None, f"about the tracker{' (every station)' if n > 1 else ''}, {law}",
                  G[:, :, None], ["e (ppm/h)" if tau is None else "e (ppm)"], family="air_index_drift",
                  extra={"law": "ramp" if tau is None else "lag", "t0_s": float(t0),
                         **({} if tau is None else {"tau_s": float(tau)}), "stations": n, "tracker_from": station,
                         "t_end_s": float(np.nanmax(g.time_s))}, grammar=air_grammar("ramp" if tau is None else "lag"))
    if tau is not None:
        c.refine = lambda t: air_index_drift(g, t0, t, station)
        c.refine_range, c.refine_value = (60.0, 86400.0), float(tau)
    return c
