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


def compensate_program(program: str | os.PathLike, output: str | os.PathLike, model: str | os.PathLike | ErrorModel,
                       *, scope: str = "position", iterations: int | None = None, tool_length: float = 0.0,
                       cone: float = 2.0, outside: str = "hold", tolerance: float = 0.001,
                       precision: int | None = None, residual_every: int = RESIDUAL_EVERY,
                       max_correction: float = MAX_CORRECTION_MM,
                       max_rotary_correction: float = MAX_ROTARY_CORRECTION_DEG, allow_subprograms: bool = False,
                       kind: str = "auto", tables: str | os.PathLike | None = None, force: bool = False,
                       uncertainty: str | os.PathLike | None = None,
                       progress: Callable[[int, int], None] | None = None) -> dict:
    """Write ``output``, the program compensated for ``model`` (a path or an ErrorModel), and return the report.

    scope "position" corrects the tool tip (L-POS ... R-VOL of ISO/TR 16907), "full" also the tool axis (FOR);
    iterations default to 1 (first order) for "position" and 2 (fixed point on the exact model) for "full";
    tool_length (mm) below the error reference point; cone (deg) around B = 0 where only the position is
    corrected; tolerance (mm) the largest predicted mid-segment error before a feed move is subdivided.  A model
    that fails the plausibility guard (mtcal.model.plausibility) raises InputError unless ``force``.
    ``uncertainty``: the JSON of `mtcal uncertainty --program` for this program (its tool tip's interval after
    compensation, a Monte Carlo of the model), reported as "task_uncertainty".  The
    returned dict is the JSON answer of `mtcal compensate` (lengths in mm unless a key says um, angles urad)."""
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
    largest and RMS half-width of the 95 % intervals over the program's moves (um); refused (InputError) when it
    was computed for another program (name or contents: ``provenance``'s sha256) or over the work volume, for
    another model than ``model`` (``ErrorModel.digest``: another recording or identify's options), from fewer than
    two trials, with a non-finite interval, or carries no provenance (an older mtcal)."""
    from pathlib import Path

    from mtcal.io import file_sha256, read_json

    d = read_json(path, "uncertainty result")
    vol = d.get("volumetric", {}) if isinstance(d, dict) else {}
    if vol.get("program") != Path(program).name:
        raise InputError(f"{path}: not the Monte Carlo of this program's tool tip (run `mtcal uncertainty REC.csv "
                         f"--program {Path(program).name}`); it holds {vol.get('program') or 'the work volume'}")
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
        raise InputError(f"{path}: the Monte Carlo of another version of {Path(program).name} (its contents "
                         f"differ): {rerun}")
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
    lo, hi = arrs
    half = np.linalg.norm(hi - lo, axis=1) / 2
    return {"trials": d.get("trials"), "p": d.get("p"), "moves": len(half), "u95_max_um": float(half.max() * 1e3),
            "u95_rms_um": float(np.sqrt(np.mean(half**2)) * 1e3),
            "of": "the tool tip after compensation: the model's own uncertainty at the program's moves (GUM-S1 "
                  "Monte Carlo of the identification, mtcal uncertainty --program); half-width of the 95 % "
                  "interval of |deviation|, per move"}
