"""Measured check tests read from plain CSV files (docs/guide/checks.md):

circular test (ballbar)::

    # plane: XY
    # radius_mm: 150
    # centre_mm: 0,0,-200          (optional: the linear axes' positions at the centre, mm)
    # fixed_deg: B=0,C=0           (optional: the rotary axes, deg)
    angle_deg,deviation_mm,direction
    0,0.0012,1

angle counter-clockwise from the plane's first axis (deg), deviation = measured minus nominal radius (mm,
positive outward), direction +1 counter-clockwise / -1 clockwise;

R-test sweep::

    # axis: C
    # sphere_mm: 100,0,50          (workpiece coordinates, mm)
    # fixed_deg: B=0               (optional)
    position_deg,dx_mm,dy_mm,dz_mm

the sphere's centre relative to the tool ball in the machine frame (mm).  Header keys may be given as options
instead (options win); ``# kind: circular|rtest`` is optional (the columns tell)."""
from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mtcal.campaign.effects import parse_items
from mtcal.errors import InputError

CIRCULAR_COLUMNS = ("angle_deg", "deviation_mm", "direction")
RTEST_COLUMNS = ("position_deg", "dx_mm", "dy_mm", "dz_mm")


@dataclass
class MeasuredCheck:
    """A measured check test (``read_check``, or a simulated one: mtcal.check.simulate_circular).

    Attributes
    ----------
    kind : str
        ``"circular"`` (ballbar) or ``"rtest"``.
    source : str
        Where it came from.
    info : dict
        Its header as given: plane, radius_mm, centre_mm, fixed_deg (circular); axis, sphere_mm (R-test).
    data : dict of str to numpy.ndarray
        Its columns, name -> (n,): angle_deg, deviation_mm, direction (circular); position_deg, dx_mm, dy_mm,
        dz_mm (R-test).
    """

    kind: str
    source: str
    info: dict = field(default_factory=dict)
    data: dict[str, np.ndarray] = field(default_factory=dict)
    lines: np.ndarray | None = None  # each reading's line in the file (1-based), None when not from a file


def _header(lines: list[str], source: str) -> tuple[dict, int]:
    info, k = {}, 0
    for k, line in enumerate(lines):
        s = line.strip()
        if not s:
            continue
        if not s.startswith("#"):
            return info, k
        body = s[1:].split("(")[0].strip()
        if ":" in body:
            key, val = (x.strip() for x in body.split(":", 1))
            key = key.lower()
            if key in info and info[key][0] != val:
                raise InputError(f"{source}, line {k + 1}: {key} given twice ({info[key][0]!r} at line "
                                 f"{info[key][1]}, {val!r} here): which one was measured? (two tests in one file?)")
            info[key] = (val, k + 1)
    raise InputError(f"{source}: no data (a header line of column names, then one row per reading)")


def _numbers(val: str, n: int | None, what: str, source: str, line: int) -> tuple[float, ...]:
    try:
        out = tuple(float(v) for v in val.split(","))
    except ValueError:
        raise InputError(f"{source}, line {line}: {what} must be numbers separated by commas, got {val!r}") from None
    if (n is not None and len(out) != n) or not np.isfinite(out).all():
        raise InputError(f"{source}, line {line}: {what} needs {n} finite numbers, got {val!r}")
    return out


def parse_fixed(text: str, what: str) -> dict[str, float]:
    """'B=0,C=30' -> {axis: deg}: the rotary axes held during a check test (mtcal.campaign.effects.parse_items, the
    one key=value reader); ``what`` names the field or option in the message."""
    out = {}
    for name, num in parse_items(text, what).items():
        try:
            out[name.upper()] = float(num)
        except ValueError:
            raise InputError(f"{what}: items are AXIS=deg, got {name}={num!r}") from None
    return out


def is_check_file(path: str | Path) -> bool:
    """Whether a CSV file is a check test (its column header names a circular test's or an R-test's columns)."""
    with open(path, encoding="utf-8-sig") as fh:
        for line in fh:
            s = line.strip()
            if s and not s.startswith("#"):
                head = {h.strip() for h in s.split(",")}
                return set(CIRCULAR_COLUMNS[:2]) <= head or set(RTEST_COLUMNS) <= head
    return False


def read_check(path: str | Path) -> MeasuredCheck:
    r"""Read a measured circular test (ballbar) or R-test sweep from a plain CSV (module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        The file: ``# key: value`` header lines, then a header row and the data (angle_deg, deviation_mm,
        direction for a circular test; position_deg, dx_mm, dy_mm, dz_mm for an R-test; mm and deg).

    Returns
    -------
    MeasuredCheck
        Its kind, header and columns.

    Raises
    ------
    mtcal.errors.InputError
        A bad header key or value, column or row, named by file and line.

    Examples
    --------
    >>> import mtcal
    >>> rows = "".join(f"{a},{0.001 * (a % 90 == 0)},{d}\n" for d in (1, -1) for a in range(0, 360, 10))
    >>> _ = open("ballbar.csv", "w").write("# plane: XY\n# radius_mm: 150\nangle_deg,deviation_mm,direction\n" + rows)
    >>> test = mtcal.read_check("ballbar.csv")
    >>> test.kind, test.info, len(test.data["angle_deg"])
    ('circular', {'plane': 'XY', 'radius_mm': 150.0}, 72)
    """
    source = str(path)
    lines = Path(path).read_text(encoding="utf-8-sig").splitlines()
    raw, start = _header(lines, source)
    rows = list(csv.reader(lines[start:]))
    head = [h.strip() for h in rows[0]]
    kind = ("circular" if set(CIRCULAR_COLUMNS[:2]) <= set(head) else
            "rtest" if set(RTEST_COLUMNS) <= set(head) else None)
    if kind is None:
        raise InputError(f"{source}, line {start + 1}: columns must be {','.join(CIRCULAR_COLUMNS)} (circular test) or "
                         f"{','.join(RTEST_COLUMNS)} (R-test), got {','.join(head)}")
    data, lines = _columns(rows[1:], head, CIRCULAR_COLUMNS if kind == "circular" else RTEST_COLUMNS, source,
                           start + 2)
    if kind == "circular":
        _paths(data, lines, "direction" in head, source)
    info: dict = {}
    for key, (val, line) in raw.items():
        if key in ("centre_mm", "sphere_mm"):
            info[key] = _numbers(val, 3 if key == "sphere_mm" else None, key, source, line)
        elif key == "radius_mm":
            info[key] = _numbers(val, 1, key, source, line)[0]
        elif key == "fixed_deg":
            info[key] = parse_fixed(val, f"{source}, line {line}: fixed_deg")
        elif key in ("plane", "axis"):
            info[key] = val.upper()
    return MeasuredCheck(kind, source, info, data, lines)


def _columns(rows: list[list[str]], head: list[str], need: tuple[str, ...], source: str,
             first: int) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """(columns {name: (n,)}, each reading's line (n,)); a cell that is not a finite number is refused."""
    idx = {c: head.index(c) for c in need if c in head}
    out: dict[str, list[float]] = {c: [] for c in idx}
    lines = []
    for k, row in enumerate(rows):
        if not row or not "".join(row).strip():
            continue
        for c, i in idx.items():
            try:
                v = float(row[i])
            except (ValueError, IndexError):
                raise InputError(f"{source}, line {first + k}: {c} must be a number, got "
                                 f"{row[i] if i < len(row) else 'nothing'!r}") from None
            if not np.isfinite(v):
                raise InputError(f"{source}, line {first + k}: {c} must be finite, got {row[i]!r}")
            out[c].append(v)
        lines.append(first + k)
    arr = {c: np.array(v) for c, v in out.items()}
    if "direction" in need and "direction" not in arr:
        arr["direction"] = np.ones(len(next(iter(arr.values()))))
    bad = np.flatnonzero(~np.isin(arr["direction"], (-1, 1))) if "direction" in arr else []
    if len(bad):
        raise InputError(f"{source}, line {lines[bad[0]]}: direction must be +1 (counter-clockwise) or -1 "
                         f"(clockwise), got {arr['direction'][bad[0]]:g}")
    if len(next(iter(arr.values()))) < 3:
        raise InputError(f"{source}: a check test needs at least 3 readings")
    return arr, np.array(lines, dtype=int)


OVERRUN_DEG = 30.0  # a path may run past its start by this much (ISO 230-4's overrun arcs), not a second turn


def _paths(data: dict[str, np.ndarray], lines: np.ndarray, has_direction: bool, source: str) -> None:
    """A circular test's file holds one path per direction, each in its order of travel: refused (naming the
    line) when the readings of a direction come in two blocks or turn more than once (two tests concatenated), or,
    without a direction column, when the angle runs back (both directions in the file: say which is which)."""
    th, d = data["angle_deg"], data["direction"]
    runs = np.flatnonzero(np.diff(d) != 0) + 1
    starts = np.concatenate([[0], runs])
    seen: dict[float, int] = {}
    for a, b in zip(starts, np.concatenate([runs, [len(d)]])):
        key = float(d[a])
        if key in seen:
            raise InputError(f"{source}, line {lines[a]}: the {'counter-clockwise' if key > 0 else 'clockwise'} "
                             f"readings start again (they began at line {lines[seen[key]]}): two tests in one "
                             f"file? One test a file, each direction's readings in their order of travel")
        seen[key] = a
        step = np.diff(th[a:b])
        step = (step + 180.0) % 360.0 - 180.0  # the wrap at 360 is one step on
        moving = np.sign(step[step != 0])
        back = np.flatnonzero(np.sign(step) == -moving[0]) if len(moving) else []  # against the first move
        if len(back):
            i = a + int(back[0]) + 1
            if not has_direction:
                raise InputError(f"{source}, line {lines[i]}: angle_deg runs back ({th[i - 1]:g} then {th[i]:g} "
                                 f"deg) and there is no direction column: both directions in one file? Give "
                                 f"direction (+1 counter-clockwise, -1 clockwise) on every row")
            raise InputError(f"{source}, line {lines[i]}: angle_deg runs back ({th[i - 1]:g} then {th[i]:g} deg) "
                             f"within the {'counter-clockwise' if key > 0 else 'clockwise'} path: each direction's "
                             f"readings in their order of travel, one test a file")
        turn = float(np.abs(step).sum())
        if turn > 360.0 + OVERRUN_DEG:
            i = a + int(np.searchsorted(np.cumsum(np.abs(step)), 360.0 + OVERRUN_DEG)) + 1
            path = f"the {'counter-clockwise' if key > 0 else 'clockwise'} path" if has_direction else \
                "the readings (no direction column)"
            raise InputError(f"{source}, line {lines[min(i, b - 1)]}: {path} turn {turn:.0f} deg, more than once "
                             f"round: two tests or both directions in one file? One test a file, direction (+1 "
                             f"counter-clockwise, -1 clockwise) on every row")
