"""HEIDENHAIN nonlinear axis error compensation: `*.COM` value tables and the `*.CMA` table that activates them;
KinematicsComp layout of the ISO 230-1 component errors.

Source: HEIDENHAIN Technical Manual MANUALplus 620 (01/2012) sec. 6.10.3 "Nonlinear axis error compensation":
*.COM columns AXISPOS (compensation points, machine datum), one column per compensated axis named as in
CfgAxes/axisList, BACKLASH (values measured in the negative direction of traverse); *.CMA: one column per axis,
the COM file entered in the column of the axis it depends on ([axis column of the COM] = F(axis column of the CMA)),
a line made active with `*` in ACTIVE; at most 256 entries per COM (TNC 407 Technical Manual, module 9095 error 3).
KinematicsComp: iTNC 530 HSCI Technical Manual, "Recommendation" for COM files: columns C1..C6 of a linear axis X
= EXX, EYX, EZX, EAX, EBX, ECX, of a rotary axis A = EXA, EYA, EZA, EAA, EBA, ECA.
Units and spacing: mm (linear) and deg (rotary axes and, ASSUMED, angular KinematicsComp columns), regular step.
An unlimited rotary axis (a modulo axis on the TNC, whose position runs 0..360 deg) is tabled over one turn
0..360 deg (mtcal.export.sampling.modulo_table: a table measured over 300..420 deg is placed modulo 360, said), at
most 256 points; a table never runs beyond an axis' travel (sampling.axis_grid).
Sign: the tables hold the error (joint-equivalent deviation actual - nominal = minus the correction), as the TNC 407
Technical Manual's example plots "Error in Z" over the compensation points; this sign, the BACKLASH meaning (written
as the value in the negative direction) and the table file syntax (BEGIN/[END], fixed columns) are ASSUMED from
those pages, not from a TNC 640 manual: verify one point on the machine before use.
"""
from __future__ import annotations

import numpy as np

from mtcal.errors import InputError
from mtcal.export import isg, sampling
from mtcal.export.sampling import AxisTable
from mtcal.model.errormodel import ErrorModel

NAME = "heidenhain"
MAX_POINTS = 256
HARD_LIMIT = True   # the controller cannot take more points
CROSS = True
FILES = "*.COM"  # the tables this format writes (a re-export removes stale ones)
BACKLASH_NOTE = ("the BACKLASH column is the reversal: set the machine parameter of the TNC's own backlash "
                 "compensation (MP_backLash / CfgAxisComp backLash) to 0 so it is not compensated twice")
LAYOUT = ("TNC 6xx / MANUALplus 620 nonlinear axis error compensation (*.COM value tables, CONFIG.CMA activation); "
          "fixed-width columns of 14 characters")
POINTS_NOTE = ("at most 256 compensation points per COM table (TNC 407 Technical Manual, module 9095); the total over "
               "all tables is a control limit: check your control's Technical Manual before loading")
COMPTAB_NOTE = ("the KC_<axis>.COM tables act only where the machine's kinematics description references them (COMPTAB "
                "entries of the kinematics model, iTNC 530 HSCI Technical Manual): the machine builder wires them")
SIGN = ("the COM tables hold the error (actual - nominal, joint-equivalent; = -correction); ASSUMED from the TNC "
        "407 / MANUALplus 620 Technical Manuals (not confirmed for TNC 640): verify on the machine")


WIDTH = 14  # characters of every column, its blank separator included


def _table(name: str, unit: str, cols: list[str], rows: list[list[str]]) -> str:
    """A TNC table: BEGIN line, the column names and every row padded to the full fixed width (each field
    WIDTH characters, left-aligned under its name, trailing blanks kept as real TNC tables have them; an empty
    field stays blank), [END].  A field that does not fit its column leaves no blank before the next and would be
    read as another number: refused."""
    for r in rows:
        for c, f in zip(cols, r):
            if len(f) >= WIDTH:
                raise InputError(f"{name}: value {f} of column {c} is {len(f)} characters, a TNC column holds "
                                 f"{WIDTH - 1}: nothing was written")
    out = [f"BEGIN {name} {unit}".rstrip(), "".join(c.ljust(WIDTH) for c in ["NR"] + cols)]
    out += ["".join(c.ljust(WIDTH) for c in [str(i)] + r) for i, r in enumerate(rows)]
    return "\n".join(out + ["[END]", ""])


def _v(x: float, decimals: int = 6) -> str:
    """+d.dddddd; a value that rounds to zero is +0 (no "-0.000000")."""
    r = round(float(x), decimals)
    return f"{0.0 if r == 0 else r:+.{decimals}f}"


def com_file(t: AxisTable) -> tuple[str, str]:
    """(file name, text) of the COM table of input axis ``t.axis``: error columns per compensated axis; with a
    reversal the own column holds the error moving in the positive direction and BACKLASH the negative one."""
    name = f"{t.axis}.COM"
    outs = list(t.corrections)
    cols = {o: -t.corrections[o] for o in outs}
    if t.reversal:
        cols[t.axis], cols["BACKLASH"] = -t.directional(+1), -t.directional(-1)
    rows = [[_v(p)] + [_v(c[i]) for c in cols.values()] for i, p in enumerate(t.positions)]
    return name, _table(name, "MM", ["AXISPOS"] + list(cols), rows)


def cma_file(tables: list[AxisTable], machine) -> str:
    axes = list(machine.axes)
    row = ["*"] + [next((f"{t.axis}.COM" for t in tables if t.axis == a), "") for a in axes]
    return _table("CONFIG.CMA", "", ["ACTIVE"] + axes, [row])


def kc_files(model: ErrorModel, machine, step: float | None, max_points: int) -> dict[str, str]:
    """KinematicsComp COM per axis with error functions: C1..C6 = E_X?, E_Y?, E_Z? (mm), E_A?, E_B?, E_C? (deg,
    assumed), sampled on the axis' grid."""
    files = {}
    for ax, (q, vals, st, _) in isg.samples(model, machine, step, max_points).items():
        q, vals = _turn(ax, q, vals, st, model, machine, max_points, step is not None)
        cols = [vals.get(f"E_{c}{ax}", np.zeros(len(q))) for c in "XYZABC"]
        cols[3:] = [np.degrees(v) for v in cols[3:]]
        rows = [[_v(p)] + [_v(v[i], 9) for v in cols] for i, p in enumerate(q)]
        name = f"KC_{ax}.COM"
        files[name] = _table(name, "MM", ["AXISPOS", "C1", "C2", "C3", "C4", "C5", "C6"], rows)
    return files


def _turn(ax: str, q: np.ndarray, vals: dict, st: float, model: ErrorModel, machine, max_points: int,
          step_given: bool) -> tuple[np.ndarray, dict]:
    """A KinematicsComp table of an unlimited rotary axis over one turn 0..360 deg, as its COM table is."""
    if not sampling.unlimited_rotary(machine, ax):
        return q, vals
    spacing = [np.diff(np.unique(f.positions)).max() for f in model.functions.values()
               if f.axis == ax and len(np.unique(f.positions)) > 1]
    t = sampling.modulo_table(AxisTable(ax, "deg", q, st, vals, {}, measured_step=max(spacing, default=None)),
                              machine, max_points, step_given, MAX_POINTS, "a TNC COM table")
    return t.positions, t.corrections


def as_written(tables: list[AxisTable], machine, max_points: int, step_given: bool) -> list[AxisTable]:
    """The COM tables as the files hold them: an unlimited rotary axis' over one turn 0..360 deg (module
    docstring), at most ``max_points``; the others as sampled."""
    return [sampling.modulo_table(t, machine, max_points, step_given, MAX_POINTS, "a TNC COM table") for t in tables]


def kc_held(model: ErrorModel) -> set[str]:
    """Names the KinematicsComp tables hold: the component errors (functions) of every axis."""
    return {n for n in model.functions if n[3] != "0"}


def render(tables: list[AxisTable], machine, model: ErrorModel, model_path: str,
           kinematics_comp: bool, step: float | None = None, max_points: int = MAX_POINTS) -> dict[str, str]:
    files = dict(com_file(t) for t in tables)
    files["CONFIG.CMA"] = cma_file(tables, machine)
    if kinematics_comp:
        files.update(kc_files(model, machine, step, max_points))
    files["README.txt"] = "\n".join([
        f"mtcal export {model_path} --format heidenhain", f"sign: {SIGN}",
        "units: mm (linear), deg (rotary); AXISPOS from the machine datum",
        f"layout: {LAYOUT}", f"points: {POINTS_NOTE}",
        f"backlash: {BACKLASH_NOTE}" if any(t.reversal for t in tables) else "backlash: no BACKLASH column written",
        *([f"KinematicsComp: {COMPTAB_NOTE}"] if kinematics_comp else []),
        *[f"table: {t.note}" for t in tables if t.note],
        f"files: {', '.join(files)}", ""])
    return files
