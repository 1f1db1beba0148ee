"""Unit and frame slips of a recording, refused before any estimator runs (identify's every method, diagnose).

A tracker reading moves with its axis as the commanded (nominal) motion takes it: a reflector on the part an axis
moves, read at position q, lies where the nominal rigid motion from the round's reference position q0 takes its
reference reading, to within the machine's geometric errors (tens of um; a knocked nest or a blunder is the gross
screen's, mtcal.measurement.screen).  A reading MAX_DEVIATION_MM or farther from there is no machine error but a
slip of the data: readings in inch, linear positions in inch with readings in mm, rotary positions in radians, the
x, y, z columns swapped, another axis moving, or every reading the same point (a tracker that did not follow the
reflectors).  The recording is refused (InputError) naming the file, the line, the reading's distance and, when
one of those slips undone makes every reading of the axis follow the commanded motion, that slip.

Frame: readings (mm) in the machine frame, positions in mm (linear) or deg (rotary), the axes not measured at
zero; each (station, axis, round, point) is referred to its own first reading at the round's reference position
(mtcal.measurement.passes: the position closest to zero).
"""
from __future__ import annotations

import numpy as np

from mtcal.errors import InputError
from mtcal.kinematics.machine import Machine
from mtcal.measurement.passes import first_readings, position_key, reading_order, reference_position
from mtcal.measurement.recordings import Recording

MAX_DEVIATION_MM = 1.0  # a reading this far from the nominal motion is a unit / frame / axis mix-up, not an error
SAME_MM = 1e-6  # readings equal to this are one point
INCH_MM = 25.4

# each slip: (words, undo (positions, readings, kind) -> (positions, readings)), kind "linear" or "rotary"
SLIPS = (
    ("the readings are in inch", lambda q, m, k: (q, m * INCH_MM)),
    ("the readings are in metres", lambda q, m, k: (q, m * 1000.0)),
    ("the positions are in inch", lambda q, m, k: (q * INCH_MM, m) if k == "linear" else None),
    ("the positions are in radians", lambda q, m, k: (np.degrees(q), m) if k == "rotary" else None),
    ("the x and y columns are swapped", lambda q, m, k: (q, m[:, [1, 0, 2]])),
    ("the x and z columns are swapped", lambda q, m, k: (q, m[:, [2, 1, 0]])),
    ("the y and z columns are swapped", lambda q, m, k: (q, m[:, [0, 2, 1]])),
)


def check_units_and_frame(rec: Recording, machine: Machine, max_deviation_mm: float = MAX_DEVIATION_MM) -> None:
    """Refuse ``rec`` (InputError naming file, line and the slip) when an axis' readings are all one point or a
    reading lies ``max_deviation_mm`` or farther from where the commanded motion takes its reference reading
    (module docstring); axes the machine does not have are left to the caller."""
    for axis in rec.axes():
        if axis not in machine.axes:
            continue
        rows = np.flatnonzero(rec.axis == axis)
        _all_one_point(rec, axis, rows)
        rows, refs = _references(rec, rows)
        if not len(rows):
            continue
        dev = _deviation(machine, axis, rec.position[rows], rec.position[refs], rec.xyz[rows], rec.xyz[refs])
        k = int(np.argmax(dev))
        if dev[k] < max_deviation_mm:
            continue
        i, j = rows[k], refs[k]
        unit = machine.unit(axis)
        raise InputError(f"{rec.where(i)}: axis {axis} round {int(rec.round[i])}: point {rec.point[i]} at {axis} = "
                         f"{rec.position[i]:g} {unit} is "
                         f"{dev[k]:.3g} mm from where the commanded motion takes its reference reading (line "
                         f"{int(rec.line[j])}); geometric errors are far smaller: "
                         f"{_which_slip(rec, machine, axis, rows, refs, max_deviation_mm)}")


def _all_one_point(rec: Recording, axis: str, rows: np.ndarray) -> None:
    if len(np.unique(position_key(rec.position[rows]))) < 2:
        return
    xyz = rec.xyz[rows]
    if np.ptp(xyz, axis=0).max() <= SAME_MM:
        raise InputError(f"{rec.source}, lines {int(rec.line[rows].min())}-{int(rec.line[rows].max())}: every reading "
                         f"of axis {axis} is the same point ({', '.join(f'{v:g}' for v in xyz[0])}) while the axis "
                         f"moves: the tracker did not follow the reflectors (or the export repeats one reading)")


def _references(rec: Recording, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(rows that have a reference reading, each one's reference row): the first reading of the same station,
    round and point at the round's reference position."""
    st = rec.stations()
    order = reading_order(rec, rows)
    keep, refs = [], []
    for s in np.unique(st[rows]):
        for r in np.unique(rec.round[rows]):
            ri = rows[(st[rows] == s) & (rec.round[rows] == r)]
            if not len(ri):
                continue
            first = first_readings(rec, ri, reference_position(rec.position[ri]), order)
            for i in ri:
                j = first.get((str(rec.point[i]),), first.get((rec.point[i],)))
                if j is not None:
                    keep.append(i)
                    refs.append(j)
    return np.array(keep, dtype=int), np.array(refs, dtype=int)


def _deviation(machine: Machine, axis: str, q: np.ndarray, q0: np.ndarray, m: np.ndarray,
               m0: np.ndarray) -> np.ndarray:
    """|reading - nominal| (n,) mm: the nominal rigid motion of ``axis`` from q0 to q applied to the reference
    reading m0 (the other axes at zero)."""
    t0, r0 = machine.rigid_motion(axis, machine.axis_vector({axis: q0}))
    tq, rq = machine.rigid_motion(axis, machine.axis_vector({axis: q}))
    w = np.einsum("nji,nj->ni", r0, m0 - t0)
    return np.linalg.norm(m - (np.einsum("nij,nj->ni", rq, w) + tq), axis=1)


def _which_slip(rec: Recording, machine: Machine, axis: str, rows: np.ndarray, refs: np.ndarray,
                limit: float) -> str:
    """The slip that, undone, makes every reading of the axis follow the commanded motion; else the list."""
    unit = machine.unit(axis)
    kind = machine.kind(axis)
    q, m = rec.position, rec.xyz
    for words, undo in SLIPS:
        u = undo(q, m, kind)
        if u is None:
            continue
        uq, um = u
        if _deviation(machine, axis, uq[rows], uq[refs], um[rows], um[refs]).max() < limit:
            return f"{words} (undone, every reading of {axis} follows the commanded motion); positions must be in " \
                   f"{unit} and readings in mm in the machine frame"
    return (f"positions must be in {unit} and readings in mm in the machine frame (positions in inch, metres or "
            f"radians? readings in inch? the x, y, z columns swapped? another axis moving?)")
