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
  turn;
* on export (``fit_against_table``), a fitted function disagrees with its own table (every exporter evaluates the
  fit, so the table the model states is not what the controller would get): at some position |fit - table|
  exceeds ``FIT_LEAVES_K`` / 1.96 times the table value's 95 % expanded uncertainty (``u95`` of the function's
  ``extra``, as identify writes it: Student's t for a few rounds, 1.96 sigma for the joint fit, so 4 sigma there),
  else ``FIT_LEAVES_K`` times its standard uncertainty (``std_mean``), or, where the model states no uncertainty,
  ``FIT_UNSTATED_FRACTION`` of the table's largest |value|; never below ``FIT_FLOOR`` (0.1 um, 0.5 urad), what no
  table is measured to.
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
FIT_LEAVES_K = 4.0  # a fit that misses a table value by more than this many of its standard deviations disagrees
FIT_UNSTATED_FRACTION = 0.1  # no stated uncertainty: a miss beyond this fraction of the table's largest |value|
FIT_FLOOR = {"translation": 1e-4, "angle": 0.5e-6}  # mm, rad: a miss below this is no disagreement


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


def check_model(model: ErrorModel, machine: Machine, force: bool = False, what: str = "model",
                fit_against_table: bool = False) -> list[str]:
    """Refuse an implausible model (module docstring); with ``force`` return the violations as warnings.
    ``fit_against_table``: also refuse a fitted function that disagrees with its own table (export's check)."""
    problems = _problems(model, machine, fit_against_table)
    if problems and not force:
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        raise InputError(f"{what}: {problems[0]}{more}; nothing was written (`force` writes it anyway)")
    return [f"FORCED past the plausibility guard: {p}" for p in problems]


def _problems(model: ErrorModel, machine: Machine, fit_against_table: bool = False) -> list[str]:
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
        out += _fit_disagrees(name, f, machine) if fit_against_table else []
    return out


def _short(name: str, v: float) -> str:
    return f"{v * 1e6:.3g} urad" if _angular(name) else f"{v * 1e3:.3g} um"


def _per_position(f, key: str, n: int) -> np.ndarray:
    """A per-position uncertainty list of the function's ``extra`` (None entries: NaN); all NaN when absent."""
    v = f.extra.get(key) if isinstance(f.extra, dict) else None
    if not isinstance(v, (list, tuple)) or len(v) != n:  # absent or not a list per position: not stated
        return np.full(n, np.nan)
    try:
        return np.array([np.nan if x is None else x for x in v], dtype=float)
    except (TypeError, ValueError):  # a word where a number belongs: not stated (the table is guarded alone)
        return np.full(n, np.nan)


def _fit_disagrees(name: str, f, machine: Machine) -> list[str]:
    """The position where the fitted function misses its own table most beyond the table's uncertainty (module
    docstring), as one problem; [] when it does not (or has no fit: the table is then what is evaluated)."""
    if f.fit is None or getattr(f.fit, "kind", "") == "table" or len(f.positions) < 1:
        return []
    vals = np.asarray(f.values, dtype=float)
    with np.errstate(all="ignore"):
        fitted = np.asarray(f(f.positions, "hold"), dtype=float)
    if not (np.isfinite(vals).all() and np.isfinite(fitted).all()):
        return []  # said by _function_problems
    miss = np.abs(fitted - vals)
    u95, sm = (_per_position(f, key, len(vals)) for key in ("u95", "std_mean"))
    use95 = np.isfinite(u95) & (u95 > 0)
    stated = use95 | (np.isfinite(sm) & (sm > 0))
    unc = np.where(use95, u95 * FIT_LEAVES_K / 1.96, np.where(stated, FIT_LEAVES_K * np.nan_to_num(sm), 0.0))
    floor = FIT_FLOOR["angle" if _angular(name) else "translation"]
    largest = float(np.abs(vals).max())
    limit = np.where(stated, np.maximum(unc, floor), max(floor, FIT_UNSTATED_FRACTION * largest))
    if not (miss > limit).any():
        return []
    k = int(np.argmax(miss / limit))
    unit = machine.unit(f.axis)
    if use95[k]:
        why = (f"{miss[k] / u95[k]:.2f} times the table value's 95 % expanded uncertainty {_short(name, u95[k])} (the "
               f"bound is {FIT_LEAVES_K / 1.96:.2f} times, 4 sigma for a normal distribution)")
    elif stated[k]:
        why = (f"{miss[k] / sm[k]:.1f} sigma of the table value (its standard uncertainty {_short(name, sm[k])}; the "
               f"bound is {FIT_LEAVES_K:g} sigma)")
    else:
        why = ((f"{100 * miss[k] / largest:.0f} % of the table's largest value" if largest > 0 else
                "the table is zero everywhere")
               + f" (the model states no uncertainty; the bound is {100 * FIT_UNSTATED_FRACTION:g} % of the table's "
                 f"largest value): a model's values are the table its fit stands for")
    return [f"{name}: its fitted function ({f.fit.kind}) gives {_short(name, fitted[k])} at {f.axis} = "
            f"{f.positions[k]:g} {unit} where its own table says {_short(name, vals[k])}, {_short(name, miss[k])} "
            f"off: {why}; every export format evaluates the fit (identify again with a higher "
            f"`max_degree` / `max_harmonics`, or more rounds)"]


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
