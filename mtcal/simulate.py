"""Virtual laser tracker: simulated calibration campaigns of a machine with a known error model and planted effects.

The simulated machine follows the exact error-inclusive kinematics (the generated ``tool_point`` /
``table_point`` with the model's errors at every pose); the tracker adds AT960 noise (mtcal.tracker) that
depends on where it stands.  Frames and units: machine frame (= tracker frame after alignment), mm; linear
axes in mm, rotary axes in degrees; errors in mm and rad.

Default campaign (thesis ch. 3, Zhang & Hu three-point method):
* reflectors P, Q, K on the spindle (coordinates relative to the spindle gauge point, ~100 mm apart, at
  different heights) for X, Y, Z, and on the table (workpiece coordinates) for B and C;
* 11 positions over each linear travel (X 0..500, Y 0..450, Z 0..400 mm), B 0..180 step 10, C 0..340 step 20;
  each axis measured with the others at zero (B at C = 0, C at B = 0);
* 4 rounds; in each round the reflector sits in one nest at a time and the axis runs out and back
  (ISO 230-2: every target approached in + then in - direction); the reference reading of a point is its
  first reading at the position closest to zero;
* times: the axis moves at 50 mm/s or 20 deg/s, settles 3 s (stable-point detection), the reading takes 2 s;
  30 s to move the reflector to the next nest, 60 s between rounds, 300 s between axes.
* tracker at Pos. 1 (thesis fig. 5.1: in front of the machine, beam roughly along Y):
  (250, -1500, 150) mm in the machine frame.

PLAN.json (all keys optional; values replace the defaults):
{"tracker": [x, y, z],                      mm, machine frame
 "rounds": 4,
 "axes": {"X": {"positions": [0, 50, ...]} | {"start": 0, "stop": 500, "count": 11},
          "Y": {..., "at": {"X": 250}}, ...},   measured axes in order; "at": other axes' positions (default 0)
 "points": {"tool": {"P": [x, y, z], ...}, "table": {"P": [x, y, z], ...}},   mm, >= 3 non-collinear each
 "bidirectional": true,
 "feed_mm_s": 50, "feed_deg_s": 20, "settle_s": 3, "measure_s": 2, "reflector_change_s": 30,
 "round_pause_s": 60, "axis_change_s": 300, "temperature_c": 20.0}
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Iterable, Mapping

import numpy as np

from mtcal import tracker as trk
from mtcal.effects import Rows, as_effects
from mtcal import schema as sc
from mtcal.errors import InputError
from mtcal.io import atomic_write_text, dumps, read_json
from mtcal.machine import Machine, load_machine
from mtcal.model import ErrorModel
from mtcal.recordings import Recording, make_recording, write_recording

AXIS_ORDER = ("X", "Y", "Z", "B", "C")
MAX_READING_MM = 1e6  # a simulated reading farther than 1 km from the machine origin is no measurement
LINEAR = ("X", "Y", "Z")

# Thesis fig. 5.1 tracker placements (our reading of the sketch; machine frame, mm):
TRACKER_POSITIONS = {
    "pos1": (250.0, -1500.0, 150.0),   # in front of the machine, beam ~ along Y (the thesis' setup)
    "pos2": (-1500.0, 225.0, 150.0),   # beside the machine in line with X, beam ~ along X
    "pos3": (250.0, 225.0, 2000.0),    # above the work zone looking down, beam ~ along Z
}
DEFAULT_TRACKER = TRACKER_POSITIONS["pos1"]

DEFAULT_POSITIONS = {
    "X": np.linspace(0.0, 500.0, 11),
    "Y": np.linspace(0.0, 450.0, 11),
    "Z": np.linspace(0.0, 400.0, 11),
    "B": np.arange(0.0, 180.0 + 1e-9, 10.0),
    "C": np.arange(0.0, 340.0 + 1e-9, 20.0),
}
# Reflector nests: spindle points relative to the gauge point, table points in workpiece coordinates (mm).
DEFAULT_TOOL_POINTS = {"P": (70.0, 0.0, 10.0), "Q": (-35.0, 60.0, 40.0), "K": (-35.0, -60.0, 70.0)}
DEFAULT_TABLE_POINTS = {"P": (150.0, 0.0, 40.0), "Q": (-75.0, 130.0, 80.0), "K": (-75.0, -130.0, 120.0)}


@dataclass
class Plan:
    """A measurement plan (see module docstring for the JSON schema)."""

    tracker: tuple[float, float, float] = DEFAULT_TRACKER
    rounds: int = 4
    positions: dict[str, np.ndarray] = field(
        default_factory=lambda: {k: v.copy() for k, v in DEFAULT_POSITIONS.items()})
    at: dict[str, dict[str, float]] = field(default_factory=dict)
    tool_points: dict[str, tuple] = field(default_factory=lambda: dict(DEFAULT_TOOL_POINTS))
    table_points: dict[str, tuple] = field(default_factory=lambda: dict(DEFAULT_TABLE_POINTS))
    bidirectional: bool = True
    feed_mm_s: float = 50.0
    feed_deg_s: float = 20.0
    settle_s: float = 3.0
    measure_s: float = 2.0
    reflector_change_s: float = 30.0
    round_pause_s: float = 60.0
    axis_change_s: float = 300.0
    temperature_c: float = 20.0
    source: str = "<default plan>"  # the PLAN.json it came from (for messages)

    def points_for(self, axis: str) -> dict[str, tuple]:
        return self.tool_points if axis in LINEAR else self.table_points

    def axis_values(self, axis: str, position: float | np.ndarray) -> np.ndarray:
        """All axis positions (..., 5) when ``axis`` is at ``position`` and the others at their "at" values."""
        q = np.asarray(position, dtype=float)
        out = np.zeros(q.shape + (5,))
        for k, v in self.at.get(axis, {}).items():
            out[..., AXIS_ORDER.index(k)] = v
        out[..., AXIS_ORDER.index(axis)] = q
        return out

    def reference_position(self, axis: str) -> float:
        """The position closest to zero (the reference of every round, design.md)."""
        p = self.positions[axis]
        return float(p[np.argmin(np.abs(p))])


_PLAN_KEYS = {"tracker", "rounds", "axes", "points", "bidirectional", "feed_mm_s", "feed_deg_s", "settle_s",
              "measure_s", "reflector_change_s", "round_pause_s", "axis_change_s", "temperature_c"}


def _xyz(v: Any, where: str) -> tuple[float, float, float]:
    """[x, y, z]: three finite JSON numbers (mm)."""
    if not (isinstance(v, list) and len(v) == 3 and all(isinstance(c, (int, float)) and not isinstance(c, bool)
                                                        and math.isfinite(c) for c in v)):
        raise InputError(f"{where} must be [x, y, z] in mm (three finite numbers), got {v!r}")
    return tuple(float(c) for c in v)


def _points(raw: Any, where: str) -> dict[str, tuple]:
    if not isinstance(raw, Mapping) or len(raw) < 3:
        raise InputError(f"{where}: needs >= 3 labelled points {{label: [x, y, z]}}, got {raw!r}")
    out = {}
    for k, v in raw.items():
        out[str(k)] = _xyz(v, f"{where}: point {k!r}")
    pts = np.array(list(out.values()))
    c = pts - pts.mean(axis=0)
    if np.linalg.matrix_rank(c, tol=1e-6 * max(1.0, np.abs(c).max())) < 2:
        raise InputError(f"{where}: the points are collinear; three non-collinear reflectors are needed")
    return out


def plan_from_dict(raw: Mapping, source: str = "<plan>") -> Plan:
    """Build a Plan from PLAN.json contents; unknown keys and bad values name the file and key."""
    if not isinstance(raw, Mapping):
        raise InputError(f"{source}: a plan must be a JSON object")
    unknown = sorted(set(raw) - _PLAN_KEYS)
    if unknown:
        raise InputError(f"{source}: unknown key(s) {unknown}; allowed: {sorted(_PLAN_KEYS)}")
    plan = Plan()
    kw: dict[str, Any] = {"source": source}
    if "tracker" in raw:
        kw["tracker"] = _xyz(raw["tracker"], f"{source}: tracker")
    if "rounds" in raw:
        r = raw["rounds"]
        if not isinstance(r, int) or isinstance(r, bool) or r < 1:
            raise InputError(f"{source}: rounds must be a positive integer, got {r!r}")
        kw["rounds"] = r
    if "axes" in raw:
        axes = raw["axes"]
        if not isinstance(axes, Mapping) or not axes:
            raise InputError(f"{source}: axes must be an object {{AXIS: {{positions: [...]}}}}")
        pos, at = {}, {}
        for a, spec in axes.items():
            if a not in AXIS_ORDER:
                raise InputError(f"{source}: axes: unknown axis {a!r}; axes are {', '.join(AXIS_ORDER)}")
            spec = spec or {}
            if not isinstance(spec, Mapping):
                raise InputError(f"{source}: axes.{a} must be an object")
            bad = sorted(set(spec) - {"positions", "start", "stop", "count", "at"})
            if bad:
                raise InputError(f"{source}: axes.{a}: unknown key(s) {bad}")
            if "positions" in spec:
                p = sc.numbers(spec["positions"], source, f"axes.{a}.positions", 2)
            elif "start" in spec or "stop" in spec or "count" in spec:
                n = spec.get("count")
                if isinstance(n, bool) or not isinstance(n, int) or n < 2:
                    raise InputError(f"{source}: axes.{a}.count must be a whole number >= 2, got {n!r}")
                p = np.linspace(sc.number(spec.get("start"), source, f"axes.{a}.start"),
                                sc.number(spec.get("stop"), source, f"axes.{a}.stop"), n)
            else:
                p = DEFAULT_POSITIONS[a].copy()
            if p.ndim != 1 or len(p) < 2 or not np.isfinite(p).all() or len(np.unique(p)) != len(p):
                raise InputError(f"{source}: axes.{a}: positions must be >= 2 distinct finite numbers")
            if a == "B" and (p.min() < 0 or p.max() > 180):
                raise InputError(f"{source}: axes.B: positions must lie in [0, 180] deg")
            pos[a] = p
            other = spec.get("at", {}) or {}
            if not isinstance(other, Mapping) or any(k not in AXIS_ORDER or k == a for k in other):
                raise InputError(f"{source}: axes.{a}.at must map other axes to positions, got {other!r}")
            at[a] = {k: sc.number(v, source, f"axes.{a}.at.{k}") for k, v in other.items()}
        kw["positions"], kw["at"] = pos, at
    if "points" in raw:
        pts = raw["points"]
        if not isinstance(pts, Mapping) or set(pts) - {"tool", "table"}:
            raise InputError(f"{source}: points must be {{\"tool\": {{...}}, \"table\": {{...}}}}")
        if "tool" in pts:
            kw["tool_points"] = _points(pts["tool"], f"{source}: points.tool")
        if "table" in pts:
            kw["table_points"] = _points(pts["table"], f"{source}: points.table")
    if "bidirectional" in raw:
        if not isinstance(raw["bidirectional"], bool):
            raise InputError(f"{source}: bidirectional must be true or false")
        kw["bidirectional"] = raw["bidirectional"]
    for k in ("feed_mm_s", "feed_deg_s", "settle_s", "measure_s", "reflector_change_s", "round_pause_s",
              "axis_change_s", "temperature_c"):
        if k in raw:
            v = raw[k]
            if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v) or (
                    v < 0 and k != "temperature_c") or (k.startswith("feed") and v <= 0):
                kind = "positive " if k.startswith("feed") else ""
                raise InputError(f"{source}: {k} must be a {kind}number, got {v!r}")
            kw[k] = float(v)
    return replace(plan, **kw)


def load_plan(path: str | Path) -> Plan:
    return plan_from_dict(read_json(path, "plan"), str(path))


def as_plan(plan: Plan | Mapping | str | Path | None) -> Plan:
    if plan is None:
        return Plan()
    if isinstance(plan, Plan):
        return plan
    if isinstance(plan, Mapping):
        return plan_from_dict(plan)
    return load_plan(plan)


# ---------------------------------------------------------------------------------------------- schedule
def schedule(plan: Plan) -> Rows:
    """Every reading of the campaign in time order (the rows of the recording)."""
    cols: dict[str, list] = {k: [] for k in ("axis", "round", "position", "point", "direction", "time_s", "side",
                                             "local")}
    t = 0.0
    for ia, axis in enumerate(plan.positions):
        if ia:
            t += plan.axis_change_s
        pos = plan.positions[axis]
        out = np.sort(pos)  # out from the end nearer zero (e.g. 0 -> 500; 0 -> -400 runs down)
        if plan.reference_position(axis) == out[-1]:
            out = out[::-1]
        seq = [(float(p), 1 if out[-1] > out[0] else -1) for p in out]
        if plan.bidirectional:
            seq += [(float(p), -d) for p, d in reversed(seq)]
        feed = plan.feed_mm_s if axis in LINEAR else plan.feed_deg_s
        side = "tool" if axis in LINEAR else "table"
        for r in range(1, plan.rounds + 1):
            if r > 1:
                t += plan.round_pause_s
            for ip, (label, xyz) in enumerate(plan.points_for(axis).items()):
                if ip:
                    t += plan.reflector_change_s + abs(seq[-1][0] - seq[0][0]) / feed
                prev = seq[0][0]
                for p, d in seq:
                    t += abs(p - prev) / feed + plan.settle_s
                    prev = p
                    cols["axis"].append(axis)
                    cols["round"].append(r)
                    cols["position"].append(p)
                    cols["point"].append(label)
                    cols["direction"].append(d)
                    cols["time_s"].append(t)
                    cols["side"].append(side)
                    cols["local"].append(xyz)
                    t += plan.measure_s
    axis = np.array(cols["axis"])
    position = np.array(cols["position"], dtype=float)
    axes = np.zeros((len(axis), 5))
    for a in plan.positions:
        m = axis == a
        axes[m] = plan.axis_values(a, position[m])
    return Rows(axis, np.array(cols["round"], dtype=int), position, np.array(cols["point"]),
                np.array(cols["direction"], dtype=int), np.array(cols["time_s"], dtype=float), axes,
                np.array(cols["side"]), np.array(cols["local"], dtype=float).reshape(-1, 3))


def exact_points(machine: Machine, rows: Rows, errors: np.ndarray) -> np.ndarray:
    """Machine-frame reflector positions (n, 3) mm by the exact error-inclusive kinematics."""
    xyz = np.empty((len(rows), 3))
    tool = rows.side == "tool"
    if tool.any():
        xyz[tool] = machine._np.tool_point(rows.axes[tool], errors[tool], rows.local[tool])
    if (~tool).any():
        xyz[~tool] = machine._np.table_point(rows.axes[~tool], errors[~tool], rows.local[~tool])
    return xyz


def _check_poses(m: Machine, pl: Plan, rows: Rows) -> None:
    """Every pose of the plan inside the machine's axis limits (from its spec); the message names the plan axis."""
    for k, (name, lim) in enumerate(zip(m.axes, m.limits)):
        if lim is None:
            continue
        out = (rows.axes[:, k] < lim[0]) | (rows.axes[:, k] > lim[1])
        if out.any():
            i = int(np.flatnonzero(out)[0])
            unit = "deg" if m.axis_kinds[k] == "rotary" else "mm"
            raise InputError(f"{pl.source}: measuring axis {rows.axis[i]} puts {name} at {rows.axes[i, k]:g} {unit}, "
                             f"outside its range [{lim[0]:g}, {lim[1]:g}] {unit} on {m.name}")


# ---------------------------------------------------------------------------------------------- campaign
def simulate(model: ErrorModel | None = None, *, machine: str | Machine = "dmu50", tracker=None,
             rounds: int | None = None,
             seed: int | None = 0, effects: Iterable = (), noise: bool = True, plan=None,
             spec: trk.TrackerSpec = trk.AT960) -> tuple[Recording, dict]:
    """(recording, truth) of one simulated campaign; see ``simulate_campaign``."""
    m = machine if isinstance(machine, Machine) else load_machine(machine)
    pl = as_plan(plan)
    if tracker is not None:
        pl = replace(pl, tracker=tuple(float(c) for c in (trk.parse_xyz(tracker) if isinstance(tracker, str)
                                                          else np.asarray(tracker, dtype=float).reshape(3))))
    if rounds is not None:
        if int(rounds) != rounds or rounds < 1:
            raise InputError(f"rounds must be a positive integer, got {rounds!r}")
        pl = replace(pl, rounds=int(rounds))
    eff = as_effects(effects)
    t_pos = np.asarray(pl.tracker, dtype=float)
    if not np.isfinite(t_pos).all():
        raise InputError(f"tracker position must be finite, got {pl.tracker}")
    rows = schedule(pl)
    _check_poses(m, pl, rows)
    if model is not None and model.machine != m.name:
        raise InputError(f"error model is for machine {model.machine!r}, simulating {m.name!r}")
    errors = (model.errors_at(m, rows.axes) if model is not None
              else np.zeros((len(rows), len(m.error_names))))
    with np.errstate(over="ignore", invalid="ignore"):  # non-finite readings are refused below, in one line
        for e in eff:
            e.add_errors(rows, errors, m.error_names)
        xyz = exact_points(m, rows, errors)
        for e in eff:
            e.apply_readings(rows, xyz, t_pos)
        if noise and np.isfinite(xyz).all():
            xyz = xyz + trk.sample(xyz, t_pos, np.random.default_rng(seed), spec)
    bad = ~(np.abs(xyz) <= MAX_READING_MM).all(axis=1)  # NaN compares False
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InputError(f"simulated reading of axis {rows.axis[i]} at {rows.position[i]:g} is not finite or beyond "
                         f"{MAX_READING_MM:g} mm: an effect or model value is out of range "
                         f"({', '.join(e.name for e in eff) or 'no effects'})")
    temp = pl.temperature_c + sum((e.temperature_rise(rows.time_s) for e in eff), np.zeros(len(rows)))
    rec = make_recording(rows.axis, rows.round, rows.position, rows.point, xyz, rows.time_s, rows.direction, temp)
    truth = {
        "machine": m.name,
        "units": {"length": "mm", "angle": "rad", "position": "mm (X, Y, Z) or deg (B, C)", "time": "s"},
        "tracker": list(pl.tracker),
        "tracker_spec": {"radial_um": spec.radial_um, "radial_um_per_m": spec.radial_um_per_m,
                         "transverse_um": spec.transverse_um, "transverse_um_per_m": spec.transverse_um_per_m,
                         "k": spec.k},
        "noise": bool(noise),
        "seed": seed,
        "rounds": pl.rounds,
        "axes": {a: {"positions": pl.positions[a].tolist(), "at": pl.at.get(a, {}),
                     "reference_position": pl.reference_position(a)} for a in pl.positions},
        "points": {"tool": {k: list(v) for k, v in pl.tool_points.items()},
                   "table": {k: list(v) for k, v in pl.table_points.items()}},
        "model": None if model is None else model.to_dict(),
        "effects": [e.truth(rows) for e in eff],
    }
    rec.truth = truth
    return rec, truth


def simulate_campaign(model: ErrorModel | None = None, *, machine="dmu50", tracker=None, rounds=4, seed=0,
                      effects=(), noise=True, plan=None) -> Recording:
    """A simulated laser-tracker campaign as a Recording (tidy CSV columns incl. time_s, direction, temperature_c).

    model: error model of the simulated machine (None = no errors); machine: name or Machine; tracker: (3,) mm
    or "x,y,z" (None = the plan's, default thesis Pos. 1 = DEFAULT_TRACKER); rounds: overrides the plan's
    (default 4; pass None to keep the plan's); seed: numpy Generator seed; effects: see mtcal.effects;
    noise: AT960 noise on/off; plan: Plan, dict or PLAN.json path (module docstring).
    The planted truth is attached as ``recording.truth`` (a dict, also written by ``write_campaign``).
    """
    rec, _ = simulate(model, machine=machine, tracker=tracker, rounds=rounds, seed=seed, effects=effects,
                      noise=noise, plan=plan)
    return rec


def truth_path(csv_path: str | Path) -> Path:
    """REC.csv -> REC.truth.json (the sidecar with the planted truth)."""
    p = Path(csv_path)
    return p.with_name((p.name[:-4] if p.name.lower().endswith(".csv") else p.name) + ".truth.json")


def write_campaign(rec: Recording, truth: Mapping, path: str | Path) -> Path:
    """Write REC.csv and REC.truth.json atomically; returns the truth path."""
    write_recording(rec, path)
    tp = truth_path(path)
    atomic_write_text(tp, dumps(dict(truth)) + "\n")
    return tp
