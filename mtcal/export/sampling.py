"""Per-axis tables sampled from an error model for controller export (one job: the numbers every format writes).

Units: positions in mm (linear axes) or deg (rotary axes); a *correction* is in the unit of the axis it is applied
to (mm or deg).  Definition used by every exporter: the correction c_K(q_J) is what must be ADDED to the commanded
position of axis K so that the tool reaches the programmed point while axis J stands at q_J and every other axis at
its reference (zero).  It is the negative of the joint-equivalent error, to first order, obtained from the
Machine's generated Jacobians (d pose / d errors solved against d pose / d axes): no axis letter or sign is written
here, the chain spec decides (e.g. a table-side rotary joint turning with sign -1 gets the opposite sign).

Sampling: a regular grid from the lowest table position of the axis' error functions with ``step``; the last point
is the first one at or beyond the highest position (values there are the end values held).  Reversal (backlash,
ISO 230-2 B) comes from a significant ``backlash`` finding of ``mtcal diagnose``: the error approaching in the
positive direction is E + b/2, in the negative direction E - b/2 (derive/signatures.py).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from mtcal.errors import InputError
from mtcal.model.errormodel import ErrorModel

NICE = (1.0, 2.0, 2.5, 5.0)


@dataclass
class AxisTable:
    """Corrections along one input axis, sampled on a regular grid (mm or deg)."""
    axis: str
    unit: str                               # "mm" or "deg" (positions of ``axis``)
    positions: np.ndarray
    step: float
    corrections: dict[str, np.ndarray]      # output axis -> correction (its unit) at ``positions``
    sources: dict[str, list[str]]           # output axis -> error names that make up that correction
    reversal: float = 0.0                   # joint units of ``axis``: correction(-) - correction(+)
    units: dict[str, str] = field(default_factory=dict)  # output axis -> "mm" or "deg"
    measured_step: float | None = None      # the widest spacing of the model's measured positions (mm or deg)
    note: str = ""                          # what the table holds beyond the measurement (e.g. a held arc)

    def directional(self, sign: int) -> np.ndarray:
        """Own-axis correction when moving in the positive (sign = +1) or negative (-1) direction."""
        return self.corrections[self.axis] - sign * self.reversal / 2.0


def choose_step(lo: float, hi: float, max_points: int) -> float:
    """The finest 1/2/2.5/5 x 10^k step (mm or deg) that covers [lo, hi] with at most ``max_points`` points."""
    if max_points < 2:
        raise InputError(f"a table needs at least 2 points, got `max_points` {max_points}")
    raw = (hi - lo) / (max_points - 1)
    k = math.floor(math.log10(raw))
    for e in (k, k + 1):
        for m in NICE:
            s = m * 10.0 ** e
            if s >= raw * (1 - 1e-12) and _count(lo, hi, s) <= max_points:
                return s
    raise AssertionError("unreachable: 10^(k+2) always fits")


def _count(lo: float, hi: float, step: float) -> int:
    return int(math.ceil((hi - lo) / step - 1e-9)) + 1


def grid(lo: float, hi: float, step: float, max_points: int) -> np.ndarray:
    """lo, lo + step, ... up to the first point >= hi; refuses more than ``max_points`` points."""
    if not (step > 0 and math.isfinite(step)):
        raise InputError(f"`step` must be a positive finite number, got {step}")
    n = _count(lo, hi, step)
    if n > max_points:
        raise InputError(f"step {step:g} gives {n} points over [{lo:g}, {hi:g}]; this format holds at most "
                         f"{max_points} (use a larger `step`)")
    return lo + step * np.arange(max(n, 2))


def axis_range(model: ErrorModel, axis: str) -> tuple[float, float] | None:
    """[lowest, highest] table position of the model's error functions of ``axis`` (None: no function)."""
    pos = [f.positions for f in model.functions.values() if f.axis == axis]
    if not pos:
        return None
    allp = np.concatenate(pos)
    return float(allp.min()), float(allp.max())


def _reference(machine, axis: str, q: np.ndarray) -> np.ndarray:
    """Axis vectors (n, n_axes): ``axis`` at q, the others at zero (inside their limits)."""
    a = np.zeros((len(q), len(machine.axes)))
    for k, lim in enumerate(machine.limits):
        if lim is not None:
            a[:, k] = min(max(0.0, lim[0]), lim[1])
    a[:, machine.axes.index(axis)] = q
    return a


def _generic(machine) -> np.ndarray:
    """One configuration where every joint moves the tool pose (linear 100 mm, rotary 30 deg inside limits)."""
    a = np.array([100.0 if k == "linear" else 30.0 for k in machine.axis_kinds])
    for k, lim in enumerate(machine.limits):
        if lim is not None:
            a[k] = min(max(a[k], lim[0]), lim[1])
    return a


def joint_factor(machine, axis: str, name: str) -> float:
    """k such that d pose / d ``name`` = k * d pose / d ``axis`` (axis per mm or deg); refuses if the error is not
    a pure displacement of that joint (checked to 1e-9 relative at a generic configuration)."""
    a = _generic(machine)
    ja = machine.jacobian_axes(a)[:, machine.axes.index(axis)]
    je = machine.jacobian_errors(a)[:, machine.error_names.index(name)]
    k = float(ja @ je / (ja @ ja))
    if np.linalg.norm(je - k * ja) > 1e-9 * max(np.linalg.norm(je), 1e-300):
        raise InputError(f"{name} is not a displacement of joint {axis} on machine {machine.name}: "
                         "no joint table can hold it")
    return k


def positioning_name(machine, axis: str) -> str | None:
    """The error of ``axis`` that is a displacement of the joint itself (E_XX for X; for a rotary axis the rotation
    about its own stator z, e.g. E_CB for a tilted B), found from the generated Jacobians, not from letters."""
    for n in (f"E_{c}{axis}" for c in "XYZABC"):
        if n in machine.error_names:
            try:
                if abs(joint_factor(machine, axis, n)) > 1e-12:
                    return n
            except InputError:
                continue
    return None


def squareness_of(machine, axis: str) -> list[str]:
    """Squareness constants that act when ``axis`` (linear) moves alone (from the generated Jacobians)."""
    q = np.array([0.0, 100.0])
    je = machine.jacobian_errors(_reference(machine, axis, q))[:, :3, :]
    out = []
    for name in machine.error_groups.get("squareness", []):
        col = je[:, :, machine.error_names.index(name)]
        if np.allclose(col[0], 0.0) and not np.allclose(col[1], 0.0):
            out.append(name)
    return out


def _linear_corrections(model: ErrorModel, machine, axis: str, q: np.ndarray, names: list[str],
                        outputs: list[str]) -> dict[str, np.ndarray]:
    """Corrections of the linear ``outputs`` (mm) cancelling the tool-point deviation of ``names`` along ``axis``."""
    a = _reference(machine, axis, q)
    e = np.zeros((len(q), len(machine.error_names)))
    for n in names:
        i = machine.error_names.index(n)
        e[:, i] = model.functions[n](q, "hold") if n in model.functions else model.constants.get(n, 0.0)
    dev = np.einsum("nij,nj->ni", machine.jacobian_errors(a)[:, :3, :], e)
    cols = [machine.axes.index(o) for o in outputs]
    ja = machine.jacobian_axes(a)[:, :3, cols]
    delta = np.stack([np.linalg.lstsq(ja[i], dev[i], rcond=None)[0] for i in range(len(q))])
    return {o: -delta[:, k] for k, o in enumerate(outputs)}


def _held_names(model: ErrorModel, machine, axis: str, own: str, cross: bool) -> list[str]:
    """Errors of ``axis`` a table can hold that the model has: the positioning error, and with ``cross`` (linear
    axes) the straightness errors and the squareness constants that act when the axis moves."""
    names = [own]
    if cross and machine.axis_kinds[machine.axes.index(axis)] == "linear":
        names = [n for n in (f"E_{c}{axis}" for c in "XYZ") if n in machine.error_names]
        names += squareness_of(machine, axis)
    return [n for n in names if n in model.functions or model.constants.get(n, 0.0) != 0.0]


def sample_axis(model: ErrorModel, machine, axis: str, step: float | None, max_points: int, cross: bool,
                reversal: float = 0.0) -> AxisTable | None:
    """The table of ``axis`` over its measured range: own positioning correction (+ the other linear axes'
    corrections for straightness and squareness when ``cross``).  ``reversal``: backlash b in mm or rad
    (diagnose).  None when the model has nothing this table can hold for the axis."""
    own = positioning_name(machine, axis)
    names = _held_names(model, machine, axis, own, cross) if own else []
    span = axis_range(model, axis)
    if not names or span is None:
        return None
    lo, hi = span
    st = step if step is not None else choose_step(lo, hi, max_points)
    q = grid(lo, hi, st, max_points)
    k_own = joint_factor(machine, axis, own)
    linear = machine.axis_kinds[machine.axes.index(axis)] == "linear"
    if linear:
        outs = [a for a, k in zip(machine.axes, machine.axis_kinds) if k == "linear"] if cross else [axis]
        sources = {o: [n for n in names if _touches(machine, axis, n, o)] for o in outs}
        sources = {o: s for o, s in sources.items() if s}
        corr = _linear_corrections(model, machine, axis, q, names, list(sources))
    else:
        sources = {axis: [own]} if own in model.functions else {}
        corr = {axis: -k_own * model.functions[own](q, "hold")} if sources else {}
    if not corr:
        return None
    for o, c in corr.items():
        if not np.isfinite(c).all():
            raise InputError(f"axis {axis}: the correction of {o} is not finite (NaN/inf in the model)")
    units = {o: "mm" if machine.axis_kinds[machine.axes.index(o)] == "linear" else "deg" for o in corr}
    measured = [np.diff(np.unique(f.positions)).max() for f in model.functions.values()
                if f.axis == axis and len(np.unique(f.positions)) > 1]
    return AxisTable(axis, "mm" if linear else "deg", q, st, corr, sources, k_own * reversal, units,
                     float(max(measured)) if measured else None)


def _touches(machine, axis: str, name: str, out: str) -> bool:
    """Does error ``name`` (acting along ``axis``) move the tool along the direction of linear axis ``out``?"""
    a = _reference(machine, axis, np.array([100.0]))
    je = machine.jacobian_errors(a)[0, :3, machine.error_names.index(name)]
    ja = machine.jacobian_axes(a)[0, :3, :]
    lin = [i for i, k in enumerate(machine.axis_kinds) if k == "linear"]
    d = np.linalg.lstsq(ja[:, lin], je, rcond=None)[0]
    return abs(d[lin.index(machine.axes.index(out))]) > 1e-12 * max(np.abs(d).max(), 1e-300)


def backlash_from(diagnosis: dict | None, source: str = "diagnosis") -> dict[str, float]:
    """Reversal values b (mm or rad) by axis from the significant ``backlash`` effects of ``mtcal diagnose --json``."""
    if diagnosis is None:
        return {}
    effects = diagnosis.get("effects") if isinstance(diagnosis, dict) else None
    if not isinstance(effects, list):
        raise InputError(f"{source}: not a `mtcal diagnose --json` answer (no \"effects\" list)")
    out = {}
    for e in effects:
        if isinstance(e, dict) and e.get("name") == "backlash" and e.get("significant"):
            b = e.get("estimate")
            if not isinstance(b, (int, float)) or not math.isfinite(b):
                raise InputError(f"{source}: backlash of axis {e.get('axis')} has no finite estimate")
            unit = e.get("unit", "mm or rad")
            if unit not in FINDING_UNITS:
                raise InputError(f"{source}: backlash of axis {e.get('axis')}: unit {unit!r} is not one of "
                                 f"{', '.join(FINDING_UNITS)}")
            out[str(e["axis"])] = float(b) * FINDING_UNITS[unit]
    return out


FINDING_UNITS = {"mm or rad": 1.0, "mm": 1.0, "rad": 1.0, "um": 1e-3, "urad": 1e-6, "deg": math.pi / 180}


def not_held(model: ErrorModel, held: set[str]) -> list[str]:
    """Non-zero names of the model that the exported tables do not contain."""
    nz = {n for n, v in model.constants.items() if v != 0.0}
    nz |= {n for n, f in model.functions.items() if np.any(f.values) or f.fit}
    return sorted(nz - held)
