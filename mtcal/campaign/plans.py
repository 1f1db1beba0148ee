"""Campaign plans: which axes, positions, reflector nests, rounds, tracker stations and times (PLAN.json), and
the schedule of readings a plan makes.  Units: mm and degrees (axes), seconds (times), machine frame.

PLAN.json (all keys optional; values replace the machine spec's defaults, mtcal.kinematics.defaults):
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
from typing import Any, Mapping

import numpy as np

from mtcal.campaign.effects import Rows
from mtcal.errors import InputError
from mtcal.io import read_json
from mtcal.kinematics.defaults import default_points, default_positions, tracker_positions
from mtcal.kinematics.machine import Machine, load_machine
from mtcal.model import schema as sc


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
        """The position closest to zero (the reference of every round, docs/design.md)."""
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
        kw["positions"], kw["at"] = _axes(raw["axes"], source, m)
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


def _axes(axes: Any, source: str, m: Machine) -> tuple[dict[str, np.ndarray], dict[str, dict[str, float]]]:
    """(positions, other axes' positions) by axis from a plan's "axes" object; bad values name the key."""
    if not isinstance(axes, Mapping) or not axes:
        raise InputError(f"{source}: axes must be an object {{AXIS: {{positions: [...]}}}}")
    defaults = default_positions(m)
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
        pos[a] = _positions(spec, a, source, m, defaults[a])
        other = spec.get("at", {}) or {}
        if not isinstance(other, Mapping) or any(k not in m.axes or k == a for k in other):
            raise InputError(f"{source}: axes.{a}.at must map other axes to positions, got {other!r}")
        at[a] = {k: sc.number(v, source, f"axes.{a}.at.{k}") for k, v in other.items()}
    return pos, at


def _positions(spec: Mapping, a: str, source: str, m: Machine, default: np.ndarray) -> np.ndarray:
    """One axis' positions (mm or deg): listed, start/stop/count, or the spec's default; distinct, finite and
    inside the axis' limits."""
    if "positions" in spec:
        p = sc.numbers(spec["positions"], source, f"axes.{a}.positions", 2)
    elif "start" in spec or "stop" in spec or "count" in spec:
        n = spec.get("count")
        if isinstance(n, bool) or not isinstance(n, int) or n < 2:
            raise InputError(f"{source}: axes.{a}.count must be a whole number >= 2, got {n!r}")
        p = np.linspace(sc.number(spec.get("start"), source, f"axes.{a}.start"),
                        sc.number(spec.get("stop"), source, f"axes.{a}.stop"), n)
    else:
        p = default.copy()
    if p.ndim != 1 or len(p) < 2 or not np.isfinite(p).all() or len(np.unique(p)) != len(p):
        raise InputError(f"{source}: axes.{a}: positions must be >= 2 distinct finite numbers")
    lim = m.limits[m.index(a)]
    if lim and (p.min() < lim[0] or p.max() > lim[1]):
        raise InputError(f"{source}: axes.{a}: positions must lie in [{lim[0]:g}, {lim[1]:g}] {m.unit(a)}")
    return p


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
