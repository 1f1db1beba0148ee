"""Readings exported by Leica/Hexagon Inspire: one file per axis position, read into a Recording (mm, machine frame)."""
from __future__ import annotations

import numpy as np

from mtcal.errors import InputError
from mtcal.io import read_text
from mtcal.kinematics.machine import DEFAULT_MACHINE, Machine, load_machine
from mtcal.measurement.recordings import Recording

INSPIRE_ORDER = ("K", "P", "Q")  # thesis appendices C, D: blocks of K, then P, then Q rows


def parse_positions(text: str) -> np.ndarray:
    """'start:stop:count' (inclusive, evenly spaced) or 'a,b,c,...' -> positions (mm or deg)."""
    try:
        if ":" in text:
            a, b, n = text.split(":")
            p = np.linspace(float(a), float(b), int(n))
        else:
            p = np.array([float(v) for v in text.split(",")])
    except ValueError:
        p = np.array([])
    if len(p) < 2 or not np.isfinite(p).all():
        raise InputError(f"`positions` must be start:stop:count (count >= 2) or a comma list of >= 2 finite numbers, "
                         f"got {text!r}")
    return p


def read_inspire(paths, axis: str, positions=None, machine: str | Machine = DEFAULT_MACHINE) -> Recording:
    """Recording from Inspire exports as the thesis used them: one CSV per round (file order = round 1, 2, ...),
    rows 'label, x, y, z' (mm, machine frame), in blocks of K, P, Q readings over the same positions (one
    direction).  ``positions`` (mm or deg) default to the thesis plan of the axis when the block length matches.
    A first line that is not numeric is taken as a header; any other bad line is an error naming file and line."""
    from mtcal.kinematics.defaults import default_positions
    from mtcal.measurement.recordings import make_recording
    m = machine if isinstance(machine, Machine) else load_machine(machine)
    axis = axis.upper()
    if axis not in m.axes:
        raise InputError(f"`axis` {axis}: not an axis of machine {m.name} ({', '.join(m.axes)})")
    rows: dict[str, list] = {k: [] for k in ("round", "position", "point", "xyz", "line", "file")}
    for r, path in enumerate(paths, start=1):
        text = read_text(path, "Inspire export")
        data = []
        for ln, line in enumerate(text.splitlines(), start=1):
            if not line.strip():
                continue
            f = [c.strip() for c in line.split(",")]
            try:
                xyz = [float(v) for v in f[1:4]] if len(f) >= 4 else None
            except ValueError:
                xyz = None
            if xyz is None:
                if not data and ln == 1:
                    continue  # header
                raise InputError(f"{path}:{ln}: expected 'label, x, y, z' in mm, got {line.strip()!r}") from None
            if not np.isfinite(xyz).all():
                raise InputError(f"{path}:{ln}: NaN/inf is not a measurement")
            data.append((ln, xyz))
        if len(data) % 3 or not data:
            raise InputError(f"{path}: {len(data)} readings is not three equal blocks (K, P, Q) of one per position")
        n = len(data) // 3
        pos = (np.asarray(positions, dtype=float) if positions is not None
               else default_positions(m).get(axis))
        if pos is None or len(pos) != n:
            raise InputError(f"{path}: blocks of {n} readings; give the {n} positions of axis {axis} "
                             f"(`positions` start:stop:count)")
        for k, (ln, xyz) in enumerate(data):
            for key, v in zip(rows, (r, pos[k % n], INSPIRE_ORDER[k // n], xyz, ln, str(path))):
                rows[key].append(v)
    rec = make_recording([axis] * len(rows["round"]), rows["round"], rows["position"], rows["point"],
                         np.array(rows["xyz"]), source=" + ".join(map(str, paths)))
    rec.line = np.array(rows["line"])
    return rec
