"""Virtual laser tracker: simulated calibration campaigns of a machine with a known error model and planted effects.

The simulated machine follows the exact error-inclusive kinematics (the generated ``tool_point`` /
``table_point`` with the model's errors at every pose); the tracker adds AT960 noise (mtcal.measurement.tracker) that
depends on where it stands.  Frames and units: machine frame (= tracker frame after alignment), mm; linear
axes in mm, rotary axes in degrees; errors in mm and rad.

Default campaign: from the machine's spec ([campaign] of derive/machines/<name>.toml, Machine.campaign):
* reflectors (>= 3, e.g. P, Q, K) on the spindle (coordinates relative to the spindle gauge point) for the axes
  that move the spindle, and on the table (workpiece coordinates) for the axes that move the workpiece;
* positions per axis [start, stop, count]; axes measured in the spec's order, each with the others at zero;
* rounds (4 in the shipped specs); the first named tracker station of the spec (DMU 50: thesis fig. 5.1 Pos. 1,
  in front of the machine, beam roughly along Y);
* in each round the reflector sits in one nest at a time and the axis runs out and back (ISO 230-2: every
  target approached in + then in - direction); the reference reading of a point is its first reading at the
  position closest to zero;
* times: the axis moves at 50 mm/s or 20 deg/s, settles 3 s (stable-point detection), the reading takes 2 s;
  30 s to move the reflector to the next nest, 60 s between rounds, 300 s between axes.

PLAN.json (all keys optional; values replace the defaults):
{"tracker": [x, y, z],                      mm, machine frame
 "rounds": 4,
 "axes": {"X": {"positions": [0, 50, ...]} | {"start": 0, "stop": 500, "count": 11},
          "Y": {..., "at": {"X": 250}}, ...},   measured axes in order; "at": other axes' positions (default 0)
 "points": {"tool": {"P": [x, y, z], ...}, "table": {"P": [x, y, z], ...}},   mm, >= 3 non-collinear each
 "stations": {"front": [x, y, z], "left": [x, y, z], ...},   several tracker stations (mm; mtcal.campaign.stations:
                                            the campaign from each in turn, "rounds" per station)
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

from mtcal.measurement import tracker as trk
from mtcal.model import schema as sc
from mtcal.campaign.effects import Rows, as_effects, parse_items, warm_up_rise
from mtcal.errors import InputError
from mtcal.io import atomic_write_text, dumps, read_json
from mtcal.kinematics.machine import Machine, load_machine
from mtcal.model.errormodel import ErrorModel
from mtcal.measurement.recordings import Recording, make_recording, write_recording


@dataclass(frozen=True)
class WarmUp:
    """Warm-up curve of the simulated temperature channel (a plausible shop-floor warm-up):
    temperature_c = plan temperature + rise_c (1 - exp(-(t - t0_s) / tau_s)) for t > t0_s (degC, K, s)."""

    rise_c: float = 2.0
    tau_s: float = 1800.0
    t0_s: float = 0.0

    def __post_init__(self) -> None:
        for k, lo, hi in (("rise_c", -20.0, 20.0), ("tau_s", 1.0, 1e7), ("t0_s", 0.0, 1e7)):
            v = getattr(self, k)
            if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v) or not lo <= v <= hi:
                raise InputError(f"temperature: {k} must be a number in [{lo:g}, {hi:g}], got {v!r}")

    def rise(self, t: np.ndarray) -> np.ndarray:
        """K above the plan temperature at times t (s)."""
        return warm_up_rise(t, self.rise_c, self.tau_s, self.t0_s)


def parse_warm_up(spec) -> WarmUp:
    """WarmUp from a WarmUp, a mapping or 'rise_c=2,tau_s=1800,t0_s=0' (CLI --temperature; all keys optional)."""
    if isinstance(spec, WarmUp):
        return spec
    if isinstance(spec, str):
        spec = parse_items(spec, "temperature")
        for k, v in spec.items():
            try:
                spec[k] = float(v)
            except ValueError:
                raise InputError(f"temperature: {k}={v!r} is not a number") from None
    if not isinstance(spec, Mapping):
        raise InputError(f"temperature must be 'rise_c=..,tau_s=..,t0_s=..' or a mapping, got {spec!r}")
    bad = sorted(set(spec) - {"rise_c", "tau_s", "t0_s"})
    if bad:
        raise InputError(f"temperature: unknown key(s) {bad}; allowed: rise_c (K), tau_s (s), t0_s (s)")
    return WarmUp(**spec)


MAX_READING_MM = 1e6  # a simulated reading farther than 1 km from the machine origin is no measurement


def tracker_positions(machine: Machine) -> dict[str, tuple[float, float, float]]:
    """The spec's named tracker stations (mm, machine frame); the first is the default."""
    return {k: tuple(v) for k, v in machine.campaign["trackers"]}


def default_positions(machine: Machine) -> dict[str, np.ndarray]:
    """The spec's campaign positions of every axis (mm or deg), in the order the axes are measured."""
    return {a: np.linspace(start, stop, count) for a, start, stop, count in machine.campaign["positions"]}


def default_points(machine: Machine, side: str) -> dict[str, tuple]:
    """The spec's reflector nests of one side ("tool": mm from the spindle gauge point; "table": workpiece)."""
    return {k: tuple(v) for k, v in machine.campaign["reflectors"][side]}


@dataclass
class Plan:
    """A measurement plan of one machine (see module docstring for the JSON schema); fields left None take
    the machine's spec defaults."""

    machine: Machine = field(default_factory=lambda: load_machine())
    tracker: tuple[float, float, float] | None = None
    rounds: int | None = None
    positions: dict[str, np.ndarray] | None = None
    at: dict[str, dict[str, float]] = field(default_factory=dict)
    tool_points: dict[str, tuple] | None = None
    table_points: dict[str, tuple] | None = None
    bidirectional: bool = True
    feed_mm_s: float = 50.0
    feed_deg_s: float = 20.0
    settle_s: float = 3.0
    measure_s: float = 2.0
    reflector_change_s: float = 30.0
    round_pause_s: float = 60.0
    axis_change_s: float = 300.0
    temperature_c: float = 20.0
    stations: dict[str, tuple[float, float, float]] | None = None  # several tracker stations (mm), in order
    source: str = "<default plan>"  # the PLAN.json it came from (for messages)

    def __post_init__(self) -> None:
        m = self.machine = self.machine if isinstance(self.machine, Machine) else load_machine(self.machine)
        if self.tracker is None:
            self.tracker = next(iter(tracker_positions(m).values()))
        if self.rounds is None:
            self.rounds = int(m.campaign["rounds"])
        if self.positions is None:
            self.positions = default_positions(m)
        if self.tool_points is None:
            self.tool_points = default_points(m, "tool")
        if self.table_points is None:
            self.table_points = default_points(m, "table")

    def points_for(self, axis: str) -> dict[str, tuple]:
        return self.tool_points if self.machine.side(axis) == "tool" else self.table_points

    def axis_values(self, axis: str, position: float | np.ndarray) -> np.ndarray:
        """All axis positions (..., n_axes) when ``axis`` is at ``position`` and the others at their "at" values."""
        q = np.asarray(position, dtype=float)
        at = {k: np.full(q.shape, v) for k, v in self.at.get(axis, {}).items()}
        return self.machine.axis_vector({**at, axis: q})

    def reference_position(self, axis: str) -> float:
        """The position closest to zero (the reference of every round, design.md)."""
        p = self.positions[axis]
        return float(p[np.argmin(np.abs(p))])


_PLAN_KEYS = {"tracker", "stations", "rounds", "axes", "points", "bidirectional", "feed_mm_s", "feed_deg_s", "settle_s",
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


def plan_from_dict(raw: Mapping, source: str = "<plan>", machine: str | Machine | None = None) -> Plan:
    """Build a Plan of ``machine`` (default: the default machine) from PLAN.json contents; unknown keys and bad
    values name the file and key."""
    if not isinstance(raw, Mapping):
        raise InputError(f"{source}: a plan must be a JSON object")
    unknown = sorted(set(raw) - _PLAN_KEYS)
    if unknown:
        raise InputError(f"{source}: unknown key(s) {unknown}; allowed: {sorted(_PLAN_KEYS)}")
    plan = Plan(machine if machine is not None else load_machine())
    m = plan.machine
    defaults = default_positions(m)
    kw: dict[str, Any] = {"source": source}
    if "tracker" in raw:
        kw["tracker"] = _xyz(raw["tracker"], f"{source}: tracker")
    if "stations" in raw:
        st = raw["stations"]
        if not isinstance(st, Mapping) or not st:
            raise InputError(f"{source}: stations must be an object {{label: [x, y, z]}} (mm)")
        kw["stations"] = {str(k): _xyz(v, f"{source}: stations.{k}") for k, v in st.items()}
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
            if a not in m.axes:
                raise InputError(f"{source}: axes: unknown axis {a!r}; axes of {m.name} are {', '.join(m.axes)}")
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
                p = defaults[a].copy()
            if p.ndim != 1 or len(p) < 2 or not np.isfinite(p).all() or len(np.unique(p)) != len(p):
                raise InputError(f"{source}: axes.{a}: positions must be >= 2 distinct finite numbers")
            lim = m.limits[m.index(a)]
            if lim and (p.min() < lim[0] or p.max() > lim[1]):
                raise InputError(f"{source}: axes.{a}: positions must lie in [{lim[0]:g}, {lim[1]:g}] {m.unit(a)}")
            pos[a] = p
            other = spec.get("at", {}) or {}
            if not isinstance(other, Mapping) or any(k not in m.axes or k == a for k in other):
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


def load_plan(path: str | Path, machine: str | Machine | None = None) -> Plan:
    return plan_from_dict(read_json(path, "plan"), str(path), machine)


def as_plan(plan: Plan | Mapping | str | Path | None, machine: str | Machine | None = None) -> Plan:
    """A Plan of ``machine`` from a Plan, a dict, a PLAN.json path or None (the spec's default campaign)."""
    m = machine if isinstance(machine, Machine) or machine is None else load_machine(machine)
    if plan is None:
        return Plan(m) if m is not None else Plan()
    if isinstance(plan, Plan):
        if m is not None and plan.machine.name != m.name:
            raise InputError(f"the plan is for machine {plan.machine.name!r}, not {m.name!r}")
        return plan
    if isinstance(plan, Mapping):
        return plan_from_dict(plan, machine=m)
    return load_plan(plan, m)


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
        feed = plan.feed_mm_s if plan.machine.kind(axis) == "linear" else plan.feed_deg_s
        side = plan.machine.side(axis)
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
    axes = np.zeros((len(axis), len(plan.machine.axes)))
    for a in plan.positions:
        m = axis == a
        axes[m] = plan.axis_values(a, position[m])
    return Rows(axis, np.array(cols["round"], dtype=int), position, np.array(cols["point"]),
                np.array(cols["direction"], dtype=int), np.array(cols["time_s"], dtype=float), axes,
                np.array(cols["side"]), np.array(cols["local"], dtype=float).reshape(-1, 3))


def exact_points(machine: Machine, rows: Rows, errors: np.ndarray) -> np.ndarray:
    """Machine-frame reflector positions (n, 3) mm by the exact error-inclusive kinematics."""
    xyz = np.empty((len(rows), 3))
    for side in ("tool", "table"):
        on = rows.side == side
        if on.any():
            xyz[on] = machine.points(side, rows.axes[on], rows.local[on], errors[on])
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
            raise InputError(f"{pl.source}: measuring axis {rows.axis[i]} puts {name} at {rows.axes[i, k]:.10g} "
                             f"{unit}, outside its range [{lim[0]:g}, {lim[1]:g}] {unit} on {m.name}")


# ---------------------------------------------------------------------------------------------- campaign
def simulate(model: ErrorModel | None = None, *, machine: str | Machine | None = None, tracker=None,
             rounds: int | None = None, seed: int | None = 0, effects: Iterable = (), noise: bool = True, plan=None,
             spec: trk.TrackerSpec = trk.AT960, temperature=None) -> tuple[Recording, dict]:
    """(recording, truth) of one simulated campaign; see ``simulate_campaign``.  ``temperature``: a warm-up
    curve of the temperature channel (WarmUp, mapping or 'rise_c=2,tau_s=1800,t0_s=0'); the default WarmUp()
    when an effect reads the temperature (thermal_temperature), else a constant channel (thermal_drift adds its
    own rise)."""
    if machine is None:
        machine = plan.machine if isinstance(plan, Plan) else (model.machine if model is not None else None)
    m = machine if isinstance(machine, Machine) else load_machine(*([machine] if machine else []))
    pl = as_plan(plan, m)
    if tracker is not None:
        pl = replace(pl, tracker=tuple(float(c) for c in (trk.parse_xyz(tracker) if isinstance(tracker, str)
                                                          else np.asarray(tracker, dtype=float).reshape(3))))
    if rounds is not None:
        if int(rounds) != rounds or rounds < 1:
            raise InputError(f"rounds must be a positive integer, got {rounds!r}")
        pl = replace(pl, rounds=int(rounds))
    eff = [e.bind(m, {"tool": pl.tool_points, "table": pl.table_points}) for e in as_effects(effects)]
    t_pos = np.asarray(pl.tracker, dtype=float)
    if not np.isfinite(t_pos).all():
        raise InputError(f"tracker position must be finite, got {pl.tracker}")
    rows = schedule(pl)
    _check_poses(m, pl, rows)
    warm = parse_warm_up(temperature) if temperature is not None else (
        WarmUp() if any(e.name == "thermal_temperature" for e in eff) else None)
    rows.temperature_c = pl.temperature_c + sum((e.temperature_rise(rows.time_s) for e in eff),
                                                np.zeros(len(rows))) + (0.0 if warm is None else warm.rise(rows.time_s))
    for e in eff:
        e.move_nests(rows, rows.local)
    if model is not None and model.machine != m.name:
        raise InputError(f"error model is for machine {model.machine!r}, simulating {m.name!r}")
    errors = (model.errors_at(m, rows.axes) if model is not None
              else np.zeros((len(rows), len(m.error_names))))
    with np.errstate(over="ignore", invalid="ignore"):  # non-finite readings are refused below, in one line
        for e in eff:
            e.add_errors(rows, errors, m)
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
    rec = make_recording(rows.axis, rows.round, rows.position, rows.point, xyz, rows.time_s, rows.direction,
                         rows.temperature_c)
    moved = [a for a in m.axes if np.any(rows.axes[rows.axis != a, m.index(a)] != 0)]
    if moved:  # other axes away from zero during a measurement: pos_<AXIS> columns (design.md)
        rec.other_positions = {a: rows.axes[:, m.index(a)].copy() for a in moved}
    truth = {
        "machine": m.name,
        "units": {"length": "mm", "angle": "rad", "position": "mm (linear axes) or deg (rotary axes)", "time": "s"},
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
        "temperature": {"start_c": pl.temperature_c,
                        **({} if warm is None else {"rise_c": warm.rise_c, "tau_s": warm.tau_s, "t0_s": warm.t0_s})},
        "effects": [e.truth(rows) for e in eff],
    }
    rec.truth = truth
    return rec, truth


def simulate_campaign(model: ErrorModel | None = None, *, machine=None, tracker=None, rounds=4, seed=0,
                      effects=(), noise=True, plan=None, temperature=None) -> Recording:
    """A simulated laser-tracker campaign as a Recording (tidy CSV columns incl. time_s, direction, temperature_c).

    model: error model of the simulated machine (None = no errors); machine: name or Machine (default: the
    plan's, else the model's, else the default machine); tracker: (3,) mm or "x,y,z" (None = the plan's, default
    the spec's first tracker station); rounds: overrides the plan's (default 4; pass None to keep the plan's);
    seed: numpy Generator seed; effects: see mtcal.campaign.effects;
    noise: AT960 noise on/off; plan: Plan, dict or PLAN.json path (module docstring); temperature: warm-up
    curve of the temperature_c channel (see ``simulate``).
    The planted truth is attached as ``recording.truth`` (a dict, also written by ``write_campaign``).
    """
    rec, _ = simulate(model, machine=machine, tracker=tracker, rounds=rounds, seed=seed, effects=effects,
                      noise=noise, plan=plan, temperature=temperature)
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
