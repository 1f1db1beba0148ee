"""Per-axis compensation tables (CSV) of an error model: the error tables with reversed sign."""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from mtcal.io import atomic_write_text
from mtcal.kinematics.machine import Machine
from mtcal.model.errormodel import ErrorModel


# ---------------------------------------------------------------------------------------------- tables
def write_tables(model: ErrorModel, machine: Machine, folder: str | os.PathLike) -> list[str]:
    """Per-axis compensation tables for controllers that take them: the error tables with reversed sign.

    One CSV per axis, ``comp_<AXIS>.csv``: ``position`` (mm or deg) and one column per error function of that
    axis, ``comp_<NAME>_mm`` or ``comp_<NAME>_rad`` = -error, at the union of the functions' table positions
    (functions evaluated as stored, end values held); constants (squareness, axis location) in ``constants.csv``.
    """
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for ax in machine.axes:
        names = sorted(n for n, f in model.functions.items() if f.axis == ax)
        if not names:
            continue
        pos = np.unique(np.concatenate([model.functions[n].positions for n in names]))
        cols = [-model.functions[n](pos, "hold") for n in names]
        head = "position," + ",".join(f"comp_{n}_{'mm' if n[2] in 'XYZ' else 'rad'}" for n in names)
        rows = [",".join([f"{p:.6g}"] + [f"{c[i]:.9g}" for c in cols]) for i, p in enumerate(pos)]
        path = out / f"comp_{ax}.csv"
        atomic_write_text(path, "\n".join([head] + rows) + "\n")
        written.append(str(path))
    if model.constants:
        path = out / "constants.csv"
        atomic_write_text(path, "name,compensation,unit\n" + "".join(
            f"{n},{-v:.9g},{'mm' if n[2] in 'XYZ' else 'rad'}\n" for n, v in sorted(model.constants.items())))
        written.append(str(path))
    return written
