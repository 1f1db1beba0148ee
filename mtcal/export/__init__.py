"""Controller compensation tables from an error model: one module per controller format.

Public entry: ``export_model(model, machine, fmt, out, ...) -> ExportResult`` and ``FORMATS`` (name -> what the
output path is).  The numbers come from ``sampling`` (corrections from the Machine's generated Jacobians); each
format module only lays them out and states its source, units, spacing and sign in its docstring and output.
"""
from __future__ import annotations

import fnmatch
import os
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from mtcal.errors import InputError
from mtcal.export import heidenhain, isg, linuxcnc, siemens
from mtcal.export.sampling import AxisTable, backlash_from, not_held, sample_axis
from mtcal.io import atomic_write_text, record_written, refuse_overwrite, written_by_mtcal
from mtcal.model.errormodel import ErrorModel
from mtcal.model.plausibility import check_model

# name -> (module, output kind: "dir" = a folder of files, "file" = one file)
FORMATS = {"linuxcnc": (linuxcnc, "dir"), "siemens": (siemens, "file"), "heidenhain": (heidenhain, "dir"),
           "tf5280": (isg, "file"), "etalon": (isg, "file")}


@dataclass
class ExportResult:
    """What ``export_model`` wrote and what the format holds of the model.

    Attributes
    ----------
    format : str
        The format written (linuxcnc, siemens, heidenhain, tf5280, etalon).
    files : list of str
        The files written.
    sign : str
        The format's sign convention, with its source (the controller's manual).
    held : list of str
        The model's error names the tables hold.
    not_held : list of str
        The model's error names the format cannot hold (left out).
    tables : list of dict
        Per axis table: axis, unit, points, step, range, reversal, per output its errors and largest correction.
    warnings : list of str
        What the user should know (a forced model, a diagnosis used, ...).
    """

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
                            "max_abs_correction": float(abs(c).max())} for o, c in t.corrections.items()},
            "note": t.note}


def export_model(model: ErrorModel, machine, fmt: str, out: str | Path, model_path: str = "MODEL.json",
                 step: float | None = None, max_points: int | None = None, diagnosis: dict | None = None,
                 file_type: int = 0, require: list[str] | None = None, kinematics_comp: bool = False,
                 protect: tuple = (), diagnosis_source: str = "diagnosis", force: bool = False,
                 options: dict | None = None) -> ExportResult:
    """Write controller compensation tables of ``model`` in format ``fmt`` to ``out``, atomically.

    Refused before anything is written when the model fails the plausibility guard (mtcal.model.plausibility;
    ``force`` writes it with a loud warning), the diagnosis is of another machine or recording, a ``require``d
    error name is not held by the format, or there is nothing to write.  Signs, units and table sizes of each
    controller, with their sources: docs/controllers/.

    Parameters
    ----------
    model : ErrorModel
        The error model (mm, rad).
    machine : Machine
        The machine the tables are for (``mtcal.load_machine(model.machine)``); refused when the model is of
        another.
    fmt : {"linuxcnc", "siemens", "heidenhain", "tf5280", "etalon"}
        The format.
    out : str or pathlib.Path
        A folder for linuxcnc and heidenhain, a file otherwise.
    model_path : str, optional
        The model's name in messages and in the files' headers.
    step : float, optional
        Table spacing, mm or deg (default: the finest 1/2/2.5/5 x 10^k that covers each axis' range within the
        format's point limit).
    max_points : int, optional
        Points per table (default: the format's or control's limit).
    diagnosis : dict, optional
        The `mtcal diagnose --json` answer: significant backlash findings give direction-dependent tables.
    file_type : {0, 1}, optional
        linuxcnc COMP_FILE_TYPE: 0 = nominal, forward, reverse positions; 1 = nominal and trims (default 0).
    require : list of str, optional
        Error names that must be held; refused if the format cannot.
    kinematics_comp : bool, optional
        heidenhain: also write KinematicsComp tables.
    protect : tuple, optional
        Paths that must not be written over (the inputs).
    diagnosis_source : str, optional
        The diagnosis' name in messages.
    force : bool, optional
        Write a model that fails the plausibility guard, with a loud warning.
    options : dict, optional
        The format's own: siemens ``control`` (840d, 828d, 808d) and ``measuring_system``; linuxcnc
        ``linear_units`` (mm, inch).

    Returns
    -------
    ExportResult
        The files written, the sign convention, the errors held and not held, per-axis table summaries.

    Raises
    ------
    mtcal.errors.InputError
        An unknown format, a model of another machine, an implausible model (without ``force``), a required
        error not held, nothing to write, an output that is an input.

    Examples
    --------
    >>> import mtcal
    >>> from mtcal.data import path
    >>> model = mtcal.load_model(path("demo_truth.json"))
    >>> res = mtcal.export_model(model, mtcal.load_machine(model.machine), "linuxcnc", "comp")
    >>> res.files[:2], res.held[:2]
    (['comp/joint0_X.comp', 'comp/joint1_Y.comp'], ['E_CB', 'E_CC'])
    """
    options = dict(options or {})
    if fmt not in FORMATS:
        raise InputError(f"unknown format {fmt!r}; known: {', '.join(FORMATS)}")
    if model.machine != machine.name:
        raise InputError(f"{model_path}: the model is of machine {model.machine}, not {machine.name} (`machine`)")
    forced = check_model(model, machine, force, model_path, fit_against_table=True)
    forced += _check_diagnosis(diagnosis, model, machine, diagnosis_source, model_path, force)
    mod, kind = FORMATS[fmt]
    control_limit = siemens.CONTROLS.get(options.get("control"), (None,))[0] if fmt == "siemens" else None
    mp = max_points or control_limit or mod.MAX_POINTS
    if mod.HARD_LIMIT and mp > mod.MAX_POINTS:
        raise InputError(f"format {fmt} holds at most {mod.MAX_POINTS} points per table, got `max_points` {mp}")
    reversal = backlash_from(diagnosis, diagnosis_source)
    foreign = sorted(set(reversal) - set(machine.axes))
    unknown = sorted(set(require or []) - set(machine.error_names))
    if foreign or unknown:
        what = ([f"diagnosis backlash axes {foreign}"] if foreign else []) + (
            [f"error names {unknown}"] if unknown else [])
        raise InputError(f"not of machine {machine.name}: " + "; ".join(what))
    try:
        files, held, tables, sign, notes = _render(model, machine, fmt, step, mp, reversal, model_path, file_type,
                                                   kinematics_comp, options)
    except InputError as exc:  # what the format cannot hold, said of the model it came from
        raise InputError(f"{model_path}: {exc}") from None
    missing = sorted(set(require or []) - held)
    if missing:
        raise InputError(f"format {fmt} cannot hold {', '.join(missing)} "
                         f"(it holds: {', '.join(sorted(held)) or 'nothing'})")
    if not files or not held:
        raise InputError(f"{model_path}: the model has nothing format {fmt} can hold (non-zero: "
                         f"{', '.join(not_held(model, set())) or 'none: an empty model'}); nothing was written")
    written = {t.axis for t in tables}
    warnings = forced + notes + [f"reversal of axis {a} from the diagnosis not written: " +
                         (f"format {fmt} has no direction-dependent table" if fmt in isg.NAMES else
                          "the model has no error function of that axis to give the table its range")
                         for a in reversal if (fmt in isg.NAMES or a not in written)
                         and not (fmt == "siemens" and options.get("control") == "808d")]
    if any(t.reversal for t in tables):
        warnings.append(f"a direction-dependent (backlash) table is written: {mod.BACKLASH_NOTE}")
    paths, stale = _write(files, Path(out), kind, protect, mod)
    warnings += [f"{p}: a table of an earlier export that this export does not rewrite was removed" for p in stale]
    return ExportResult(fmt, paths, sign, sorted(held), not_held(model, held), [_summary(t) for t in tables], warnings)


def _render(model: ErrorModel, machine, fmt: str, step, mp: int, reversal: dict, model_path: str, file_type: int,
            kinematics_comp: bool, options: dict) -> tuple[dict[str, str], set[str], list[AxisTable], str, list[str]]:
    """The format's files, the error names they hold, the tables as written (what the command prints), the sign
    statement and the notes on what the tables hold beyond the model or leave out."""
    mod = FORMATS[fmt][0]
    if fmt in isg.NAMES:
        render = isg.render_csv if fmt == "tf5280" else isg.render_etalon
        notes = [s[3] for s in isg.samples(model, machine, step, mp).values() if s[3]]
        return render(model, machine, step, mp, model_path), isg.held(model), [], isg.SIGN, notes
    tables = _tables(model, machine, mod, step, mp, reversal)
    notes: list[str] = []
    if fmt == "siemens":
        tables, notes = siemens.as_written(tables, machine, options.get("control", "840d"), mp, step is not None)
    else:
        tables = heidenhain.as_written(tables, machine, mp, step is not None) if fmt == "heidenhain" else tables
        notes = [t.note for t in tables if t.note]
    held = {n for t in tables for s in t.sources.values() for n in s}
    if fmt == "linuxcnc":
        return (linuxcnc.render(tables, machine, file_type, model_path, **options), held, tables,
                linuxcnc.SIGN[file_type], notes)
    if fmt == "siemens":
        return siemens.render(tables, machine, model_path, "", **options), held, tables, siemens.SIGN, notes
    files = heidenhain.render(tables, machine, model, model_path, kinematics_comp, step, mp)
    return files, held | (heidenhain.kc_held(model) if kinematics_comp else set()), tables, heidenhain.SIGN, notes


def _check_diagnosis(diagnosis: dict | None, model: ErrorModel, machine, source: str, model_path: str,
                     force: bool) -> list[str]:
    """A diagnosis must be of the model's machine and of the recording the model was identified from."""
    if not isinstance(diagnosis, dict):
        return []
    if diagnosis.get("machine", machine.name) != machine.name:
        raise InputError(f"{source}: a diagnosis of machine {diagnosis['machine']}, the model is of {machine.name}")
    rec, ident = diagnosis.get("recording"), model.meta.get("identified_from")
    if not (rec and ident and Path(str(rec)).name != Path(str(ident)).name):
        return []
    problem = (f"{source} diagnoses {rec}, the model {model_path} was identified from {ident}: its backlash is of "
               f"another measurement")
    if not force:
        raise InputError(problem + "; nothing was written (`force` writes it anyway)")
    return [f"FORCED: {problem}"]


def _write(files: dict[str, str], out: Path, kind: str, protect: tuple, mod) -> tuple[list[str], list[str]]:
    """Write every file after checking that none of them is an input (``protect``): one file atomically; a folder
    through a temporary folder beside it, renamed into place when new, else its files moved in one by one (each
    atomic).  Files of an earlier mtcal export in that folder that this one does not rewrite (another axis' table)
    are removed and returned, so no stale table stays beside the new ones; only files mtcal wrote and nobody
    changed since (mtcal.io.written_by_mtcal) are removed or replaced (mtcal.io.refuse_foreign, ``--force``)."""
    paths = [out / name if kind == "dir" else out for name in files]
    for p in paths:
        refuse_overwrite(p, *protect)
    if kind != "dir":
        atomic_write_text(out, next(iter(files.values())))
        return [str(out)], []
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
    try:
        for name, text in files.items():
            (tmp / name).write_text(text, encoding="utf-8", newline="")
        if not out.exists():
            os.replace(tmp, out)
            for p in paths:
                record_written(p)
            return [str(p) for p in paths], []
        index = _mtcal_text(out)
        stale = sorted(p for p in out.iterdir() if p.is_file() and p.name not in files
                       and fnmatch.fnmatch(p.name, mod.FILES) and p.name in index and written_by_mtcal(p))
        for name in files:
            os.replace(tmp / name, out / name)
            record_written(out / name)
        for p in stale:
            p.unlink()
        return [str(p) for p in paths], [str(p) for p in stale]
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _mtcal_text(folder: Path) -> str:
    """The text of the files an earlier mtcal export wrote into ``folder`` (they say "mtcal export" and name the
    tables they wrote): a table is removed as stale only when one of them names it."""
    out = []
    for p in folder.iterdir():
        if p.is_file() and p.stat().st_size < 1_000_000:
            text = p.read_text(encoding="utf-8", errors="replace")
            if "mtcal export" in text[:2000]:
                out.append(text)
    return "\n".join(out)
