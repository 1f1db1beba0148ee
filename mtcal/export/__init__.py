"""Controller compensation tables from an error model: one module per controller format.

Public entry: ``export_model(model, machine, fmt, out, ...) -> ExportResult`` and ``FORMATS`` (name -> what the
output path is).  The numbers come from ``sampling`` (corrections from the Machine's generated Jacobians); each
format module only lays them out and states its source, units, spacing and sign in its docstring and output.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from mtcal.errors import InputError
from mtcal.export import heidenhain, isg, linuxcnc, siemens
from mtcal.export.sampling import AxisTable, backlash_from, not_held, sample_axis
from mtcal.io import atomic_write_text, refuse_overwrite
from mtcal.model import ErrorModel

# name -> (module, output kind: "dir" = a folder of files, "file" = one file)
FORMATS = {"linuxcnc": (linuxcnc, "dir"), "siemens": (siemens, "file"), "heidenhain": (heidenhain, "dir"),
           "tf5280": (isg, "file"), "etalon": (isg, "file")}


@dataclass
class ExportResult:
    format: str
    files: list[str]
    sign: str
    held: list[str]
    not_held: list[str]
    tables: list[dict] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


def _tables(model: ErrorModel, machine, mod, step, max_points, reversal) -> list[AxisTable]:
    out = []
    for ax in machine.axes:
        t = sample_axis(model, machine, ax, step, max_points, mod.CROSS, reversal.get(ax, 0.0))
        if t is not None:
            out.append(t)
    return out


def _summary(t: AxisTable) -> dict:
    return {"axis": t.axis, "unit": t.unit, "points": len(t.positions), "step": t.step,
            "from": float(t.positions[0]), "to": float(t.positions[-1]), "reversal": t.reversal,
            "outputs": {o: {"unit": t.units[o], "errors": t.sources[o],
                            "max_abs_correction": float(abs(c).max())} for o, c in t.corrections.items()}}


def export_model(model: ErrorModel, machine, fmt: str, out: str | Path, model_path: str = "MODEL.json",
                 step: float | None = None, max_points: int | None = None, diagnosis: dict | None = None,
                 file_type: int = 0, require: list[str] | None = None, kinematics_comp: bool = False,
                 protect: tuple = (), diagnosis_source: str = "diagnosis") -> ExportResult:
    """Write ``fmt`` to ``out`` (a folder for "dir" formats, a file otherwise) atomically; refuse before writing
    anything when a ``require``d error name is not held by the format."""
    if fmt not in FORMATS:
        raise InputError(f"unknown format {fmt!r}; known: {', '.join(FORMATS)}")
    mod, kind = FORMATS[fmt]
    mp = max_points or mod.MAX_POINTS
    if mod.HARD_LIMIT and mp > mod.MAX_POINTS:
        raise InputError(f"format {fmt} holds at most {mod.MAX_POINTS} points per table, got --max-points {mp}")
    reversal = backlash_from(diagnosis, diagnosis_source)
    foreign = sorted(set(reversal) - set(machine.axes))
    unknown = sorted(set(require or []) - set(machine.error_names))
    if foreign or unknown:
        what = ([f"diagnosis backlash axes {foreign}"] if foreign else []) + (
            [f"error names {unknown}"] if unknown else [])
        raise InputError(f"not of machine {machine.name}: " + "; ".join(what))
    if fmt in isg.NAMES:
        render = isg.render_csv if fmt == "tf5280" else isg.render_etalon
        files, held, tables = render(model, machine, step, mp, model_path), isg.held(model), []
        sign = isg.SIGN
    else:
        tables = _tables(model, machine, mod, step, mp, reversal)
        held = {n for t in tables for s in t.sources.values() for n in s}
        if fmt == "linuxcnc":
            files, sign = linuxcnc.render(tables, machine, file_type, model_path), linuxcnc.SIGN[file_type]
        elif fmt == "siemens":
            files, sign = siemens.render(tables, machine, model_path, ""), siemens.SIGN
        else:
            files = heidenhain.render(tables, machine, model, model_path, kinematics_comp, step, mp)
            sign = heidenhain.SIGN
            if kinematics_comp:
                held |= heidenhain.kc_held(model)
    missing = sorted(set(require or []) - held)
    if missing:
        raise InputError(f"format {fmt} cannot hold {', '.join(missing)} "
                         f"(it holds: {', '.join(sorted(held)) or 'nothing'})")
    if not files or (kind == "dir" and not tables):
        raise InputError(f"the model has nothing format {fmt} can hold (non-zero: {', '.join(not_held(model, set()))})")
    paths = _write(files, Path(out), kind, protect)
    written = {t.axis for t in tables}
    warnings = [f"reversal of axis {a} from the diagnosis not written: " +
                (f"format {fmt} has no direction-dependent table" if fmt in isg.NAMES else
                 "the model has no error function of that axis to give the table its range")
                for a in reversal if fmt in isg.NAMES or a not in written]
    return ExportResult(fmt, paths, sign, sorted(held), not_held(model, held), [_summary(t) for t in tables], warnings)


def _write(files: dict[str, str], out: Path, kind: str, protect: tuple) -> list[str]:
    """Write every file atomically after checking that none of them is an input (``protect``)."""
    paths = [out / name if kind == "dir" else out for name in files]
    for p in paths:
        refuse_overwrite(p, *protect)
    for p, text in zip(paths, files.values()):
        atomic_write_text(p, text)
    return [str(p) for p in paths]
