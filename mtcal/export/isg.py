"""Beckhoff TwinCAT CNC TF5280 (ISG kernel) volumetric compensation: ISG CSV layout and Etalon exchange layout.

Source: Beckhoff Information System, TF5280 Volumetric Compensation: "File formats supported" > "ISG CSV format"
(header row of argument and parameter names, whitespace-separated records, "//" row comments, "#" file break,
e.g. `X EXX EYX EZX EAX EBX ECX`; position errors in a block of their own, e.g. `Y0A Z0A X0B`) and "Etalon Exchange
Format" (INI-like blocks `[C0B]` `VALUE = v` and `[EXY]` `Gridpoints = { position value ... }`, variant "Vendor");
"Modification of compensation values" (`negate XY`, `set_to_zero Z` in the list file).
Units and spacing: errors in mm (translational) and rad (angular), positions in mm (linear) and deg (rotary),
ISO 230-1 names without underscore (E_XX -> EXX, E_C0Y -> C0Y); one regular grid of ``step`` per axis.
Sign: the files hold the errors themselves (ISO 230-1 deviations of the model, squareness right-handed as in
docs/design.md), not corrections: the TF5280 computes the compensation (= -deviation) and no `negate` entry is needed;
that TF5280 reads squareness/location signs with the same right-hand convention is ASSUMED (not stated in the
pages found), so check one constant on the machine.
"""
from __future__ import annotations

import numpy as np

from mtcal.errors import InputError
from mtcal.export.sampling import axis_grid
from mtcal.model.errormodel import ErrorModel

NAMES = ("tf5280", "etalon")
MAX_POINTS = 1000
HARD_LIMIT = False  # the point limit is configurable on the controller
FILES = "*.csv"
BACKLASH_NOTE = ("set the controller's own backlash compensation of that axis to 0 so the reversal is not "
                 "compensated twice")
SIGN = ("the file holds the ISO 230-1 errors (deviations), not corrections; TF5280 computes the compensation; no "
        "`negate` needed; source: Beckhoff TF5280 Volumetric Compensation (file formats, modification of values); "
        "squareness/location sign convention assumed right-handed (docs/design.md)")


def iso_name(name: str) -> str:
    """E_XX -> EXX, E_C0Y -> C0Y (TF5280 spelling)."""
    return name[2:] if name[3] == "0" else name.replace("_", "")


def samples(model: ErrorModel, machine, step: float | None, max_points: int) -> dict[str, tuple]:
    """{axis: (positions, {name: values}, step, note)} for every axis with error functions (mm/rad at mm/deg): the
    grid of mtcal.export.sampling.axis_grid (a given step checked, never beyond the axis' travel, said)."""
    out = {}
    for ax in machine.axes:
        names = sorted(n for n, f in model.functions.items() if f.axis == ax)
        if not names:
            continue
        lo = min(model.functions[n].positions.min() for n in names)
        hi = max(model.functions[n].positions.max() for n in names)
        q, st, note = axis_grid(machine, ax, float(lo), float(hi), step, max_points)
        vals = {n: model.functions[n](q, "hold") for n in names}
        bad = [n for n, v in vals.items() if not np.isfinite(v).all()]
        if bad:
            raise InputError(f"error functions {bad} are not finite on axis {ax} (NaN/inf in the model)")
        out[ax] = (q, vals, st, note)
    return out


def _num(v: float) -> str:
    """Fixed-point, as every example of the TF5280 file formats (no exponent notation, no "-0"): 12 decimals
    (1e-12 mm / rad), trailing zeros dropped."""
    text = f"{float(v):.12f}".rstrip("0").rstrip(".")
    return "0" if text in ("", "-0", "0") else text


def render_csv(model: ErrorModel, machine, step, max_points, model_path: str) -> dict[str, str]:
    lines = [f"// mtcal export {model_path} --format tf5280 (ISG CSV)", f"// {SIGN}",
             "// units: errors mm and rad; positions mm (linear) and deg (rotary)"]
    blocks = []
    if model.constants:
        names = sorted(model.constants)
        blocks.append(["// position errors (constants)", " ".join(iso_name(n) for n in names),
                       " ".join(_num(model.constants[n]) for n in names)])
    for ax, (q, vals, st, note) in samples(model, machine, step, max_points).items():
        names = list(vals)
        b = [f"// component errors of axis {ax}: {len(q)} points, step {st:g}", *([f"// {note}"] if note else []),
             " ".join([ax] + [iso_name(n) for n in names])]
        b += [" ".join([f"{p:.6f}"] + [_num(vals[n][i]) for n in names]) for i, p in enumerate(q)]
        blocks.append(b)
    body = []
    for i, b in enumerate(blocks):
        body += (["#"] if i else []) + b
    return {"": "\n".join(lines + body) + "\n"}


def render_etalon(model: ErrorModel, machine, step, max_points, model_path: str) -> dict[str, str]:
    lines = [f"// mtcal export {model_path} --format etalon (Etalon exchange format, variant Vendor)", f"// {SIGN}",
             "// units: errors mm and rad; positions mm (linear) and deg (rotary)"]
    for n in sorted(model.constants):
        lines += [f"[{iso_name(n)}]", f"VALUE = {_num(model.constants[n])}"]
    for q, vals, st, note in samples(model, machine, step, max_points).values():
        for n, v in vals.items():
            lines += [f"// {n}: {len(q)} points, step {st:g}", *([f"// {note}"] if note else []), f"[{iso_name(n)}]",
                      "Gridpoints = {"]
            lines += [f"    {p:.6f} {_num(x)}" for p, x in zip(q, v)]
            lines.append(f"}}  // end of {iso_name(n)}")
    return {"": "\n".join(lines) + "\n"}


def held(model: ErrorModel) -> set[str]:
    return set(model.constants) | set(model.functions)

