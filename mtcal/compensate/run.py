"""Compensate one NC program with an error model, end to end: the plausibility guard, the corrected program written
atomically, optional comp tables, and the answer of `mtcal compensate --json` (mm, um, urad as its keys say)."""
from __future__ import annotations

import logging
import os
import time
from typing import Callable

import numpy as np

from mtcal.compensate.program import ProgramCompensator
from mtcal.compensate.solver import MAX_CORRECTION_MM, MAX_ROTARY_CORRECTION_DEG, RESIDUAL_EVERY, Compensator
from mtcal.compensate.tables import write_tables
from mtcal.errors import InputError
from mtcal.model.errormodel import ErrorModel, load_model
from mtcal.model.iso_types import iso_types
from mtcal.model.plausibility import check_model

log = logging.getLogger(__name__)
TASK_POSES = 500  # a program's moves the task-specific Monte Carlo evaluates, at most (evenly spread over it)


def task_poses(program: str | os.PathLike, machine, n: int = TASK_POSES) -> np.ndarray:
    """The nominal axes (m, n_axes) of a G-code program's moves, at most ``n`` of them evenly spread: the poses of
    the task-specific uncertainty (`mtcal uncertainty --program`), the tool tip of this program after
    compensation, and what ``task_uncertainty`` matches a Monte Carlo file's poses against."""
    from mtcal.nc.gcode import read_moves

    q = read_moves(program, machine=machine)
    if not len(q):
        raise InputError(f"{program}: no move with every linear axis known")
    return q[np.unique(np.linspace(0, len(q) - 1, min(n, len(q))).round().astype(int))]


def compensate_program(program: str | os.PathLike, output: str | os.PathLike, model: str | os.PathLike | ErrorModel,
                       *, scope: str = "position", iterations: int | None = None, tool_length: float = 0.0,
                       cone: float = 2.0, outside: str = "hold", tolerance: float = 0.001,
                       precision: int | None = None, residual_every: int = RESIDUAL_EVERY,
                       max_correction: float = MAX_CORRECTION_MM,
                       max_rotary_correction: float = MAX_ROTARY_CORRECTION_DEG, allow_subprograms: bool = False,
                       kind: str = "auto", tables: str | os.PathLike | None = None, force: bool = False,
                       uncertainty: str | os.PathLike | None = None,
                       progress: Callable[[int, int], None] | None = None) -> dict:
    """Write ``output``, the program compensated for ``model``, and return the report.

    Every move is corrected so that the machine with the model's errors puts the tool tip (and with scope
    ``"full"`` the tool axis) where the nominal program puts it, exactly to first order on the generated
    error-inclusive kinematics (mtcal.compensate.solver.Compensator); feed moves are subdivided where the
    predicted mid-segment error exceeds ``tolerance``.  The output is written atomically, never onto an input.

    Parameters
    ----------
    program : str or os.PathLike
        The NC program: G-code (G0/G1 with the machine's axis words) or CL data (x y z i j k).
    output : str or os.PathLike
        The compensated program to write.
    model : str, os.PathLike or ErrorModel
        The error model (or its JSON file).
    scope : {"position", "full"}, optional
        ``"position"`` corrects the tool tip (L-POS ... R-VOL of ISO/TR 16907); ``"full"`` also the tool axis (FOR)
        outside the ``cone``.
    iterations : int, optional
        1: first-order correction; more: fixed-point iterations on the exact model (default 1 for "position", 2
        for "full").
    tool_length : float, optional
        Tool length below the error reference point, mm (default 0).
    cone : float, optional
        Scope "full": no orientation correction while the tool axis is within this angle of the rotary axis, deg,
        blended in up to twice it (default 2).
    outside : {"hold", "error"}, optional
        An axis position beyond an error table: hold the end value and count it (``report["warnings"]
        ["outside_range"]``), or refuse (default "hold").
    tolerance : float, optional
        Largest predicted mid-segment tool-tip error before a feed move is subdivided, mm (default 0.001).
    precision : int, optional
        Least decimals written (mm and deg; inch one more); more if the input has more (default 4).
    residual_every : int, optional
        Evaluate the exact residual of what is written on every k-th move and every inserted point (default 20).
    max_correction : float, optional
        Refuse a linear-axis correction larger than this, mm: a model in the wrong units (default 1).
    max_rotary_correction : float, optional
        The same for rotary axes, deg (default 0.1).
    allow_subprograms : bool, optional
        Pass subprogram calls unchanged with a warning (their moves are not compensated); default: refused.
    kind : {"auto", "gcode", "cl"}, optional
        Input kind (default: by extension, .cl/.cls/.apt are CL data).
    tables : str or os.PathLike, optional
        Also write per-axis compensation tables (CSV) into this folder.
    force : bool, optional
        Compensate with a model that fails the plausibility guard (mtcal.model.plausibility), with a loud warning.
    uncertainty : str or os.PathLike, optional
        The JSON of `mtcal uncertainty --program` for this program: the tool tip's interval after compensation,
        reported as ``"task_uncertainty"``.
    progress : callable, optional
        ``progress(done, total)`` called as blocks are written.

    Returns
    -------
    dict
        The JSON answer of `mtcal compensate`: ``moves``, ``lines_changed``, ``iso_16907`` (the error types
        covered), the tool tip's deviation before and the solver's residual after, warnings (``outside_range``:
        evaluations held per error).  Lengths in mm unless a key says um, angles in urad.

    Raises
    ------
    mtcal.errors.InputError
        A model that fails the plausibility guard (without ``force``), a bad program line (named), a correction
        beyond ``max_correction``, an output that is an input.

    Examples
    --------
    >>> import mtcal
    >>> from mtcal.data import path
    >>> model = mtcal.load_model(path("demo_truth.json"))
    >>> report = mtcal.compensate_program(path("sample_5axis.nc"), "part_comp.nc", model)
    >>> report["moves"], report["warnings"]["outside_range"]
    (275, {})
    """
    mdl = model if isinstance(model, ErrorModel) else load_model(model)
    name = str(model) if not isinstance(model, ErrorModel) else "<model>"
    for w in check_model(mdl, mdl.kinematics, force, name):
        log.warning("warning: %s", w)
    if iterations is None:
        iterations = 2 if scope == "full" else 1
    comp = Compensator(mdl, scope=scope, tool_length=tool_length, iterations=iterations, cone=cone, outside=outside)
    task = task_uncertainty(uncertainty, program, mdl) if uncertainty else None  # refused before anything is written
    t0 = time.perf_counter()
    pc = ProgramCompensator(comp, tolerance=tolerance, precision=precision, progress=progress,
                            residual_every=residual_every, max_correction=max_correction,
                            max_rotary_correction=max_rotary_correction, allow_subprograms=allow_subprograms)
    rep = pc.run(str(program), str(output), kind)
    dt = time.perf_counter() - t0
    written = write_tables(mdl, comp.machine, tables) if tables else []
    full = scope == "full"
    return {
        "program": str(program), "output": str(output), "model": name, "machine": comp.machine.name,
        "scope": scope, "iterations": iterations, "tool_length_mm": tool_length,
        "iso_16907": iso_types(mdl, mdl.kinematics, scope),
        "lines": rep.lines, "moves": rep.moves, "lines_changed": rep.lines_changed,
        "lines_inserted": rep.lines_inserted, "subdivided_moves": rep.subdivided_moves,
        "residual": {"of": "the written program's tool tip on the model itself: the compensation's numerical "
                           "residual, not the machine's remaining error (that is task_uncertainty, or model_worth)",
                     "evaluated_on": rep.residual_evaluated_on(),
                     "position_um": rep.position.as_dict(1e3),
                     "orientation_urad": (rep.orientation if full else rep.orientation_all).as_dict(1e6),
                     "orientation_all_urad": rep.orientation_all.as_dict(1e6),
                     "mid_segment_um": rep.mid_position.as_dict(1e3)},
        "uncompensated": {"evaluated_on": "all moves (first order)",
                          "position_um": rep.before_position.as_dict(1e3),
                          "orientation_urad": rep.before_orientation.as_dict(1e6)},
        "singularity": {"cone_deg": cone, "moves_in_cone": rep.in_cone, "moves_blended": rep.blended,
                        "max_c_correction_deg": round(rep.max_c_correction, 6), "b_clipped": comp.clipped_b},
        "warnings": {"outside_range": comp.outside_counts, "uncompensated_rapids": rep.uncompensated_rapids},
        "tables": written, "seconds": round(dt, 3),
        "model_worth": mdl.meta.get("worth"),
        **({"task_uncertainty": task} if task else {}),
    }


def task_uncertainty(path: str | os.PathLike, program: str | os.PathLike, model: ErrorModel | None = None) -> dict:
    """The tool tip's uncertainty after compensation from `mtcal uncertainty --program` (its JSON at ``path``): the
    largest and RMS half-width of the 95 % intervals over the program's moves (um).  The program is matched by its
    contents, not its name: ``provenance``'s sha256 of the program (a byte-identical copy under another name is
    the same program, said in ``"computed_for"``), and the file's poses and intervals must be the program's
    (``task_poses``: as many, at the same axes; a file cut short with its hashes intact is refused).  Refused
    (InputError) too over the work volume, for another model than ``model`` (``ErrorModel.digest``: another
    recording or identify's options), from fewer than two trials, with a non-finite interval, or with no
    provenance (an older mtcal)."""
    from pathlib import Path

    from mtcal.io import file_sha256, read_json

    d = read_json(path, "uncertainty result")
    vol = d.get("volumetric", {}) if isinstance(d, dict) else {}
    if not isinstance(vol, dict) or not vol.get("program"):
        raise InputError(f"{path}: not the Monte Carlo of this program's tool tip (run `mtcal uncertainty REC.csv "
                         f"--program {Path(program).name}`); it holds the work volume")
    prov = d.get("provenance") if isinstance(d.get("provenance"), dict) else {}
    rerun = (f"run `mtcal uncertainty REC.csv --program {Path(program).name}` on the recording the model was "
             f"identified from, with identify's options")
    if not prov.get("model_sha256") or not isinstance(prov.get("program"), dict):
        raise InputError(f"{path}: carries no provenance (the hashes of its model and program; an older mtcal): "
                         f"{rerun}")
    if model is not None and prov["model_sha256"] != model.digest():
        raise InputError(f"{path}: the Monte Carlo of another model (another recording, or identify run with "
                         f"other options): {rerun}")
    if prov["program"].get("sha256") != file_sha256(program):
        name = Path(program).name
        raise InputError(f"{path}: " + (f"the Monte Carlo of another version of {name} (its contents differ)"
                                        if vol["program"] == name else
                                        f"not the Monte Carlo of this program's tool tip: it was computed for "
                                        f"{vol['program']}, whose contents differ from {name}'s") + f": {rerun}")
    trials = d.get("trials")
    if not isinstance(trials, int) or trials < 2:
        raise InputError(f"{path}: {trials} trials: an interval needs at least 2 (run more `trials`)")
    try:
        arrs = [np.asarray(vol["deviation_xyz_mm"][k], dtype=float) for k in ("lo95", "hi95")]
    except (KeyError, TypeError, ValueError):
        raise InputError(f"{path}: no intervals of the tool tip (volumetric.deviation_xyz_mm lo95, hi95)") from None
    if arrs[0].shape != arrs[1].shape or arrs[0].ndim != 2 or not len(arrs[0]) or not all(
            np.isfinite(a).all() for a in arrs):
        raise InputError(f"{path}: the tool tip's intervals hold a non-finite value or none at all: not a usable "
                         f"Monte Carlo; {rerun}")
    _same_moves(path, program, vol, len(arrs[0]), model, rerun)
    lo, hi = arrs
    half = np.linalg.norm(hi - lo, axis=1) / 2
    return {"trials": d.get("trials"), "p": d.get("p"), "moves": len(half), "u95_max_um": float(half.max() * 1e3),
            "computed_for": str(vol["program"]),
            "u95_rms_um": float(np.sqrt(np.mean(half**2)) * 1e3),
            "of": "the tool tip after compensation: the model's own uncertainty at the program's moves (GUM-S1 "
                  "Monte Carlo of the identification, mtcal uncertainty --program); half-width of the 95 % "
                  "interval of |deviation|, per move"}


def _same_moves(path, program, vol: dict, n: int, model: ErrorModel | None, rerun: str) -> None:
    """The Monte Carlo file's poses are the program's (``task_poses``): as many as its intervals, as many as the
    program gives, at the same axes (to 1e-6 mm / deg); else refused naming both counts."""
    from pathlib import Path

    from mtcal.kinematics.machine import DEFAULT_MACHINE, load_machine

    want = task_poses(program, model.kinematics if model is not None else load_machine(DEFAULT_MACHINE))
    try:
        have = np.asarray(vol.get("poses"), dtype=float)
    except (TypeError, ValueError):
        have = np.zeros((0, 0))
    if have.shape != want.shape or n != len(want):
        raise InputError(f"{path}: holds {n} moves' intervals at {len(have)} poses, the Monte Carlo of "
                         f"{Path(program).name} has {len(want)} (its moves, at most {TASK_POSES} evenly spread): a "
                         f"file cut short or edited; {rerun}")
    k = np.flatnonzero(np.abs(have - want).max(axis=1) > 1e-6) if have.size else []
    if len(k):
        raise InputError(f"{path}: its pose {int(k[0]) + 1} is not the program's move there (axes "
                         f"{have[k[0]].round(6).tolist()} against {want[k[0]].round(6).tolist()}): an edited file; "
                         f"{rerun}")
