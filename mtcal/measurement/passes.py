"""The measurement convention of a recording, written once (docs/design.md, "Files"): which readings are the same
position, in what order readings were taken, how one axis' readings group into passes, and which reading is the
reference.  Identification (three-point and joint), ISO 230-2 and the diagnosis all use these.

* The same position: positions equal after rounding to POSITION_DECIMALS (1e-6 mm or deg).
* Reading order: time_s where every reading concerned has a time, else the line in the file.
* A pass: the readings of one axis at one (round, position, direction), one per reflector (point).
* The reference position: the measured position closest to zero; the reference reading: the first reading
  there (in reading order), per round or per recording as the caller's rule says.
"""
from __future__ import annotations

from typing import Iterable

import numpy as np

from mtcal.errors import InputError
from mtcal.measurement.recordings import Recording

POSITION_DECIMALS = 6  # mm or deg: positions that agree to 1e-6 are one position


def position_key(q) -> np.ndarray:
    """Positions (mm or deg) as the keys that say "the same position"."""
    return np.round(np.asarray(q, dtype=float), POSITION_DECIMALS)


def reading_order(rec: Recording, rows: np.ndarray) -> np.ndarray:
    """Sort key (one per row of ``rec``) of the order readings were taken: time_s when every row of ``rows`` has
    one, else the line in the file."""
    return rec.time_s if np.isfinite(rec.time_s[rows]).all() else rec.line.astype(float)


def reference_position(positions: np.ndarray) -> float:
    """The position closest to zero among ``positions`` (mm or deg), as a position key."""
    k = position_key(positions)
    return float(k[np.argmin(np.abs(k))])


def first_readings(rec: Recording, rows: np.ndarray, q0: float, order: np.ndarray,
                   by: Iterable[str] = ("point",)) -> dict[tuple, int]:
    """The first reading (in ``order``) at position ``q0`` among ``rows``, one per distinct value of the
    Recording fields ``by`` (e.g. ("round", "point")); keys are tuples of those values ((), for by=())."""
    by = tuple(by)
    at = rows[position_key(rec.position[rows]) == q0]
    out: dict[tuple, int] = {}
    for i in at[np.argsort(order[at], kind="stable")]:
        key = tuple(_value(getattr(rec, f)[i]) for f in by)
        out.setdefault(key, int(i))
    return out


def _value(v):
    return v.item() if isinstance(v, np.generic) else v


def group_passes(rec: Recording, rows: Iterable[int], directions: Iterable[int], axis: str, *,
                 by_station: bool = False, repeats: str = "refuse") -> dict[tuple, dict[str, int]]:
    """The readings ``rows`` of one axis as passes: {(round, position key, direction): {point: row}}, with the
    station first in the key when ``by_station``.  A point read twice in one pass is refused naming both lines
    (``repeats="refuse"``: repeats are never averaged silently) or its first reading kept (``"first"``: the
    gross-error screen, which reports the repeat itself)."""
    groups: dict[tuple, dict[str, int]] = {}
    st = rec.stations() if by_station else None
    for i, d in zip(rows, directions):
        key = (int(rec.round[i]), float(position_key(rec.position[i])), int(d))
        key = (st[i], *key) if by_station else key
        g = groups.setdefault(key, {})
        pt = str(rec.point[i])
        if pt in g:
            if repeats == "first":
                continue
            raise InputError(f"{rec.where(i)}: point {pt} read twice (first at line {int(rec.line[g[pt]])}) in one "
                             f"pass: axis {axis}, round {key[-3]}, position {key[-2]:g}, direction {key[-1]:+d}; "
                             f"repeated readings of one pass are not averaged silently: remove one or give it its "
                             f"own round")
        g[pt] = int(i)
    return groups
