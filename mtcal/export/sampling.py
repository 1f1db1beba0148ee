"""Per-axis tables sampled from an error model for controller export (one job: the numbers every format writes).

Units: positions in mm (linear axes) or deg (rotary axes); a *correction* is in the unit of the axis it is applied
to (mm or deg).  Definition used by every exporter: the correction c_K(q_J) is what must be ADDED to the commanded
position of axis K so that the tool reaches the programmed point while axis J stands at q_J and every other axis at
its reference (zero).  It is the negative of the joint-equivalent error, to first order, obtained from the
Machine's generated Jacobians (d pose / d errors solved against d pose / d axes): no axis letter or sign is written
here, the chain spec decides (e.g. a table-side rotary joint turning with sign -1 gets the opposite sign).

Sampling (``axis_grid``): a regular grid from the lowest table position of the axis' error functions with ``step``;
the last point is the first one at or beyond the highest position (values there are the end values held).  A given
``step`` is checked: finite, no finer than the tables' written resolution (MIN_STEP), no coarser than the measured
span, within the format's points; one that does not divide the span is said (the table runs beyond the
measurement by the remainder, the end value held).  No table runs beyond the axis' travel (the machine's limits):
a grid that would is moved back to end at the travel's end (said), or refused when it cannot fit.  An unlimited
rotary axis, where the format has modulo tables, is written over one turn 0..360 deg (``modulo_grid``: a given
step must divide the turn, else refused naming the nearest that do).  Reversal (backlash,
ISO 230-2 B) comes from a significant ``backlash`` finding of ``mtcal diagnose``: the error approaching in the
positive direction is E + b/2, in the negative direction E - b/2 (derive/signatures.py).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from mtcal.errors import InputError
from mtcal.model.errormodel import ErrorModel

NICE = (1.0, 2.0, 2.5, 5.0)
MIN_STEP = 1e-6  # mm or deg: every format writes table positions to 6 decimals; a finer step repeats positions


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


def check_step(step: float, lo: float, hi: float, max_points: int, what: str = "", given: bool = True) -> None:
    """A table spacing ``step`` (mm or deg) over [lo, hi]: a positive finite number, no finer than MIN_STEP (the
    tables' written resolution), no coarser than the span when ``given`` by the user (two points, one beyond the
    measurement), giving at most ``max_points`` points (counted without overflow: ``5e-324``); InputError naming
    ``what`` (e.g. "axis B")."""
    where = f"{what}: " if what else ""
    if not (math.isfinite(step) and step > 0):
        raise InputError(f"{where}`step` must be a positive finite number, got {step}")
    if step < MIN_STEP:
        raise InputError(f"{where}`step` {step:g} is finer than {MIN_STEP:g}, the resolution the tables write "
                         f"positions with")
    if given and hi > lo and step > hi - lo + 1e-9:
        raise InputError(f"{where}`step` {step:g} is larger than the measured span [{lo:g}, {hi:g}] ({hi - lo:g}): "
                         f"a table of two points, one beyond the measurement; give a `step` of at most {hi - lo:g}")
    if (hi - lo) / step > max_points - 1 + 1e-9:
        n = (hi - lo) / step + 1
        raise InputError(f"{where}step {step:g} gives {n:.0f} points over [{lo:g}, {hi:g}]; this format holds at "
                         f"most {max_points} (use a larger `step`)")


def grid(lo: float, hi: float, step: float, max_points: int, what: str = "", given: bool = True) -> np.ndarray:
    """lo, lo + step, ... up to the first point >= hi (``check_step`` first)."""
    check_step(step, lo, hi, max_points, what, given)
    return lo + step * np.arange(max(_count(lo, hi, step), 2))


def axis_grid(machine, axis: str, lo: float, hi: float, step: float | None,
              max_points: int) -> tuple[np.ndarray, float, str]:
    """(positions, step, note) of ``axis``' table over its measured [lo, hi] (mm or deg): ``step`` checked
    (``check_step``), else the finest 1/2/2.5/5 x 10^k (``choose_step``); the note says a given step that does not
    divide the span.  A grid beyond the axis' travel (``machine.limits``) is moved back to end at the travel's end
    and said; refused when it does not fit within the travel."""
    k = machine.axes.index(axis)
    unit = "mm" if machine.axis_kinds[k] == "linear" else "deg"
    st = step if step is not None else choose_step(lo, hi, max_points)
    q = grid(lo, hi, st, max_points, f"axis {axis}", step is not None)
    notes = []
    if step is not None and q[-1] > hi + 1e-9 * max(1.0, abs(hi)):
        notes.append(f"axis {axis}: step {st:g} {unit} does not divide the measured span [{lo:g}, {hi:g}] "
                     f"({hi - lo:g} {unit}): the table covers {q[-1] - q[0]:g} {unit}, its end beyond the "
                     f"measurement held at the measured end value")
    lim = machine.limits[k]
    if lim is not None:  # a model measured beyond the travel is the plausibility guard's (forced: its range kept)
        lim = (min(lim[0], lo), max(lim[1], hi))
    if lim is not None and (q[-1] > lim[1] + 1e-9 or q[0] < lim[0] - 1e-9):
        shifted = q - (q[-1] - lim[1]) if q[-1] > lim[1] else q + (lim[0] - q[0])
        if shifted[0] < lim[0] - 1e-9 or shifted[-1] > lim[1] + 1e-9:
            raise InputError(f"axis {axis}: a table at step {st:g} {unit} over the measured [{lo:g}, {hi:g}] needs "
                             f"{q[-1] - q[0]:g} {unit}, more than the travel [{lim[0]:g}, {lim[1]:g}] {unit} can "
                             f"hold: give a `step` that divides {hi - lo:g} {unit}")
        notes.append(f"axis {axis}: the table at step {st:g} {unit} would reach {q[-1] if q[-1] > lim[1] else q[0]:g} "
                     f"{unit}, beyond the travel [{lim[0]:g}, {lim[1]:g}] {unit}: written over [{shifted[0]:g}, "
                     f"{shifted[-1]:g}] {unit} instead, the unmeasured ends held at the measured end values")
        q = shifted
    return q, st, "; ".join(notes)


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
    q, st, note = axis_grid(machine, axis, lo, hi, step, max_points)
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
                     float(max(measured)) if measured else None, note)


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


# ---------------------------------------------------------------------------------------------- modulo tables
def unlimited_rotary(machine, axis: str) -> bool:
    """A rotary axis without travel limits (its position read modulo 360 deg by the controls with modulo tables)."""
    k = machine.axes.index(axis)
    return machine.axis_kinds[k] == "rotary" and machine.limits[k] is None


def divisions(n: float, up: bool = True) -> int:
    """The number of steps of a full turn: a divisor of 360000 (so that STEP = 360/n has at most three decimals and
    MIN + n STEP = 360 exactly, as K3 requires of MAX), the smallest not below ``n`` (``up``) or the largest not
    above it."""
    k = max(1, int(math.ceil(n - 1e-9)) if up else int(math.floor(n + 1e-9)))
    while 360000 % k:
        k += 1 if up else -1
    return k


def _turn_divisions(step: float, axis: str, hard: int | None, control: str) -> int:
    """The steps of a turn at a given ``step``: it must divide 360 deg into whole steps (of at most three decimals),
    else refused naming the nearest that do, never silently changed; and fit the control's ``hard`` points."""
    n = 360.0 / step
    if abs(n - round(n)) > 1e-9 * n or 360000 % round(n):
        near = sorted({360.0 / divisions(n, up=False), 360.0 / divisions(n)} - {0.0})
        raise InputError(f"axis {axis} is an unlimited rotary axis, written as a modulo table over the whole turn "
                         f"0..360 deg: `step` {step:g} deg does not divide 360 deg into whole steps (nearest that "
                         f"do: {' or '.join(f'{s:g}' for s in near)} deg)")
    n = int(round(n))
    if hard is not None and n + 1 > hard:
        raise InputError(f"axis {axis} is an unlimited rotary axis, written as a modulo table over the whole turn: a "
                         f"full turn at step {step:g} deg needs {n + 1} points, {control} holds {hard} per table: give "
                         f"a `step` of at least {360.0 / divisions(hard - 1, up=False):g} deg, or none")
    return n


def modulo_table(tab: AxisTable, machine, max_points: int | None, step_given: bool, hard: int | None,
                 control: str) -> AxisTable:
    """An unlimited rotary axis' table as a modulo table over the whole turn 0..360 deg, on the finest step of whole
    divisions of 360 deg not coarser than the table's -- with no ``step_given``, no more than ``max_points`` points;
    a given step must divide the turn and fit ``hard`` points of ``control`` (``_turn_divisions``).  The measured
    arc [lo, hi] (any start, e.g. 300..420 or -60..60) is placed modulo 360; a full turn (the gap to lo + 360 no
    wider than the measurement's own spacing) is interpolated across that gap, a partial turn holds the unmeasured
    arc at the value of the nearer measured end; ``note`` says which.  Other tables unchanged."""
    if not unlimited_rotary(machine, tab.axis):
        return tab
    lo, hi = float(tab.positions[0]), float(tab.positions[-1])
    span = hi - lo
    if span > 360.0 + 1e-9:
        raise InputError(f"axis {tab.axis} is measured over {span:g} deg, more than one turn: a modulo table holds "
                         f"one turn (give the model one turn of {tab.axis})")
    if step_given:
        n = _turn_divisions(tab.step, tab.axis, hard, control)
    else:
        n = divisions(360.0 / tab.step)
        if max_points is not None and n + 1 > max_points:
            n = divisions(max_points - 1, up=False)
    x = np.arange(n + 1) * (360.0 / n)
    x[-1] = 360.0
    u = np.mod(x - lo, 360.0)
    full = 360.0 - span <= (tab.measured_step or tab.step) + 1e-9
    note = (f"{tab.axis} (an unlimited rotary axis) written as a modulo table over one turn 0..360 deg, the measured "
            f"[{lo:g}, {hi:g}] deg placed modulo 360")
    if full:
        at = lo + u
    else:
        at = np.where(u <= span + 1e-9, lo + u, np.where(u - span <= 360.0 - u, hi, lo))
        a, b = hi % 360.0, lo % 360.0
        note += (f"; less than a turn: {a:g}..{b:g} deg not measured: held at the value of the nearer measured end "
                 f"({a:g} or {b:g} deg)")
    per = {}
    for o, c in tab.corrections.items():
        v = np.interp(at, tab.positions, c, period=360.0) if full else np.interp(at, tab.positions, c)
        v[-1] = v[0]
        per[o] = v
    return replace(tab, positions=x, step=360.0 / n, corrections=per, note=note)
