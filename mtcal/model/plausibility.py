"""The plausibility guard on an error model before anything made from it reaches a machine (export, compensate).

A wrong table or program with exit 0 is the worst thing mtcal can produce, so a model is refused (InputError naming
the error, the position and the bound) when
* a value is not finite (a table value, its fitted function over the table's span, a constant);
* a magnitude is beyond what a machine tool's geometric error can be, by class (ISO 230-1):
  translational errors (straightness, positioning, location offsets) beyond ``TRANSLATION_FRACTION`` of the
  machine's longest linear travel (at least ``TRANSLATION_MIN_MM``): 1 mm on a 500 mm machine, where real errors
  are tens of um: a model in um read as mm (20 um -> 20 mm) is caught;
  angular errors (angular error motions, squareness, location tilts) beyond ``ANGLE_MAX_RAD`` (2 mrad, 400");
* a table lies outside its axis' travel (the spec's limits), or a rotary axis without limits spans more than a
  turn.
``force=True`` turns each refusal into a loud warning (returned) for a user who knows better.
"""
from __future__ import annotations

import numpy as np

from mtcal.errors import InputError
from mtcal.kinematics.machine import Machine
from mtcal.model.errormodel import ErrorModel

TRANSLATION_FRACTION = 2e-3  # of the longest linear travel (mm)
TRANSLATION_MIN_MM = 0.2
ANGLE_MAX_RAD = 2e-3
FIT_SAMPLES = 201  # points at which a fitted function is evaluated over its table's span


def _travel_mm(machine: Machine) -> float:
    from mtcal.kinematics.defaults import default_positions
    pos = default_positions(machine)
    spans = [float(np.ptp(pos[a])) for a in machine.axes if machine.kind(a) == "linear" and a in pos]
    return max(spans or [500.0])


def translation_bound(machine: Machine, span_mm: float | None = None) -> float:
    """The bound of a translational error of the machine (mm): what a geometric error can be at most over its
    longest linear travel, or over ``span_mm`` (a measured check's span, e.g. a ballbar circle's diameter:
    mtcal.check.evaluate)."""
    return max(TRANSLATION_MIN_MM, TRANSLATION_FRACTION * (_travel_mm(machine) if span_mm is None else span_mm))


def bounds(machine: Machine) -> dict[str, float]:
    """The bound of every error name of the machine (mm for translational, rad for angular)."""
    t = translation_bound(machine)
    return {n: (ANGLE_MAX_RAD if _angular(n) else t) for n in machine.error_names}


def _angular(name: str) -> bool:
    """ISO 230-1 names: E_<direction><axis> and E_<direction>0<axis>; A, B, C directions are rotations."""
    return name[2] in "ABC"


def _unit(name: str, v: float) -> str:
    return f"{v * 1e6:.6g} urad" if _angular(name) else f"{v * 1e3:.6g} um"


def check_model(model: ErrorModel, machine: Machine, force: bool = False, what: str = "model") -> list[str]:
    """Refuse an implausible model (module docstring); with ``force`` return the violations as warnings."""
    problems = _problems(model, machine)
    if problems and not force:
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        raise InputError(f"{what}: {problems[0]}{more}; nothing was written (`force` writes it anyway)")
    return [f"FORCED past the plausibility guard: {p}" for p in problems]


def _problems(model: ErrorModel, machine: Machine) -> list[str]:
    b = bounds(machine)
    out = []
    for name, v in model.constants.items():
        if not np.isfinite(v):
            out.append(f"constant {name} = {v} is not a finite number")
        elif abs(v) > b.get(name, np.inf):
            out.append(f"constant {name} = {_unit(name, v)} is beyond the plausibility bound {_unit(name, b[name])} "
                       f"(a model in um or urad read as mm or rad?)")
    for name, f in model.functions.items():
        out += _function_problems(name, f, machine, b.get(name, np.inf))
    return out


def _function_problems(name: str, f, machine: Machine, bound: float) -> list[str]:
    out = []
    lim = machine.limits[machine.index(f.axis)]
    lo, hi = float(np.min(f.positions)), float(np.max(f.positions))
    unit = machine.unit(f.axis)
    if lim is not None and (lo < lim[0] - 1e-9 or hi > lim[1] + 1e-9):
        out.append(f"{name}: its table spans {f.axis} = {lo:g}..{hi:g} {unit}, outside the axis' travel "
                   f"[{lim[0]:g}, {lim[1]:g}] {unit} on {machine.name}")
    elif lim is None and machine.kind(f.axis) == "rotary" and hi - lo > 360.0 + 1e-9:
        out.append(f"{name}: its table spans {f.axis} = {lo:g}..{hi:g} deg, more than one turn")
    x = np.linspace(lo, hi, FIT_SAMPLES) if hi > lo else f.positions
    with np.errstate(all="ignore"):
        fitted = np.asarray(f(x, "hold"), dtype=float)
    for label, pos, vals in (("table", f.positions, np.asarray(f.values, dtype=float)), ("fitted function", x, fitted)):
        bad = ~np.isfinite(vals)
        if bad.any():
            out.append(f"{name}: its {label} is not finite at {f.axis} = {pos[np.argmax(bad)]:g} {unit}")
            continue
        k = int(np.argmax(np.abs(vals)))
        if abs(vals[k]) > bound:
            out.append(f"{name} = {_unit(name, vals[k])} at {f.axis} = {pos[k]:g} {unit} ({label}) is beyond the "
                       f"plausibility bound {_unit(name, bound)} (a model in um or urad read as mm or rad?)")
    return out
