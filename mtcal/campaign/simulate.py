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

The plan (PLAN.json, its defaults and the schedule of readings) is mtcal.campaign.plans.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Iterable, Mapping

import numpy as np

from mtcal.campaign.effects import Rows, as_effects, parse_items, warm_up_rise
from mtcal.campaign.plans import Plan, as_plan, schedule
from mtcal.errors import InputError
from mtcal.io import atomic_write_text, dumps
from mtcal.kinematics.machine import Machine, load_machine
from mtcal.measurement import tracker as trk
from mtcal.measurement.recordings import Recording, make_recording, write_recording
from mtcal.model.errormodel import ErrorEvaluator, ErrorModel


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
             spec: trk.TrackerSpec = trk.AT960, temperature=None, extrapolate: str = "error") -> tuple[Recording, dict]:
    """A simulated laser-tracker campaign of a machine with known errors and planted effects (module docstring).

    The machine follows the exact error-inclusive kinematics with the model's errors at every pose; the tracker
    adds its noise law's noise about where it stands.

    Parameters
    ----------
    model : ErrorModel, optional
        Errors of the simulated machine (None: no errors).
    machine : str or Machine, optional
        The machine (default: the plan's, else the model's, else ``dmu50``).
    tracker : array_like, shape (3,), or str, optional
        Tracker position, mm, machine frame, or ``"x,y,z"`` (default: the plan's, the spec's first station).
    rounds : int, optional
        Rounds (default: the plan's, 4 in the shipped specs).
    seed : int, optional
        Seed of the noise (numpy Generator; default 0).
    effects : iterable, optional
        Effects to plant: ``"name:key=value,..."`` strings or Effect objects (mtcal.campaign.effects).
    noise : bool, optional
        Add the tracker's noise (default True).
    plan : Plan, dict or str, optional
        The measurement plan (a Plan, its JSON dict or a PLAN.json path; default: the spec's campaign).
    spec : TrackerSpec, optional
        The tracker's noise law (default the AT960's).
    temperature : WarmUp, dict or str, optional
        A warm-up curve of the temperature channel (``"rise_c=2,tau_s=1800,t0_s=0"``); default: WarmUp() when an
        effect reads the temperature (thermal_temperature), else a constant channel.
    extrapolate : {"error", "hold"}, optional
        A pose beyond one of the model's error tables: refused (default) or the table's end value held; the
        evaluations held are counted in ``truth["model_held"]``.

    Returns
    -------
    recording : Recording
        The readings (mm, machine frame), with the truth attached as ``recording.truth``.
    truth : dict
        What was planted: tracker, noise law, seed, plan, model, effects and their parameters (``write_campaign``
        writes it beside the CSV as REC.truth.json).

    Raises
    ------
    mtcal.errors.InputError
        A bad plan, effect or option; a pose beyond the machine's limits; a pose beyond the model's range without
        ``extrapolate="hold"``; a model of another machine.

    Examples
    --------
    >>> import mtcal
    >>> rec, truth = mtcal.simulate(rounds=2, seed=1, effects=["backlash:axis=X,amount=0.004"])
    >>> len(rec), rec.axes()
    (840, ['X', 'Y', 'Z', 'B', 'C'])
    >>> truth["effects"][0]["name"], truth["effects"][0]["params"]
    ('backlash', {'axis': 'X', 'amount': 0.004})
    """
    if machine is None:
        machine = plan.machine if isinstance(plan, Plan) else (model.machine if model is not None else None)
    m = machine if isinstance(machine, Machine) else load_machine(*([machine] if machine else []))
    pl = _plan(plan, m, tracker, rounds)
    eff = [e.bind(m, {"tool": pl.tool_points, "table": pl.table_points}) for e in as_effects(effects)]
    t_pos = np.asarray(pl.tracker, dtype=float)
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
    if extrapolate not in ("error", "hold"):
        raise InputError(f"extrapolate must be 'error' or 'hold', got {extrapolate!r}")
    held: dict[str, int] = {}
    if model is not None:  # "hold": a pose beyond a function's table takes its end value (counted in the truth)
        ev = ErrorEvaluator(model, m, extrapolate)
        errors, held = ev(m.check_axes(rows.axes)), ev.outside_counts
    else:
        errors = np.zeros((len(rows), len(m.error_names)))
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
    if moved:  # other axes away from zero during a measurement: pos_<AXIS> columns (docs/design.md)
        rec.other_positions = {a: rows.axes[:, m.index(a)].copy() for a in moved}
    rec.truth = _truth(m, pl, spec, noise, seed, model, warm, [e.truth(rows) for e in eff])
    if held:
        rec.truth["model_held"] = dict(held)  # error name -> readings whose pose is beyond its table (end value)
    return rec, rec.truth


def _plan(plan, m: Machine, tracker, rounds) -> Plan:
    """The plan of a simulation with the caller's tracker position and number of rounds (checked)."""
    pl = as_plan(plan, m)
    if tracker is not None:
        pl = replace(pl, tracker=tuple(float(c) for c in (trk.parse_xyz(tracker) if isinstance(tracker, str)
                                                          else np.asarray(tracker, dtype=float).reshape(3))))
    if rounds is not None:
        if int(rounds) != rounds or rounds < 1:
            raise InputError(f"rounds must be a positive integer, got {rounds!r}")
        pl = replace(pl, rounds=int(rounds))
    if not np.isfinite(np.asarray(pl.tracker, dtype=float)).all():
        raise InputError(f"tracker position must be finite, got {pl.tracker}")
    return pl


def _truth(m: Machine, pl: Plan, spec: trk.TrackerSpec, noise: bool, seed, model: ErrorModel | None,
           warm: WarmUp | None, effects: list[dict]) -> dict:
    """What a simulated campaign planted (written beside it by ``write_campaign``; docs/design.md)."""
    return {
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
        "effects": effects,
    }


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
