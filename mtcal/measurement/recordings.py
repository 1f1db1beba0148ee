"""Laser-tracker recordings: the tidy CSV of docs/design.md, read with checks that name file, row and problem.

Columns: axis,round,position,point,x,y,z (required) and time_s,direction,temperature_c (optional).
axis in {X, Y, Z, B, C}; position in mm (linear) or degrees (rotary); x, y, z in mm in the machine frame.
Several tracker stations (docs/design.md, optional): ``station`` (a label; absent = one station) and
``tracker_x,tracker_y,tracker_z`` (mm, machine frame, the approximate tracker position, constant within a
station); a round belongs to one station.  ``pos_<AXIS>`` columns: the other axes' positions during the
reading (mm or deg; absent = at zero).
Row numbers in messages are 1-based file lines (the header is line 1).
"""
from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mtcal.errors import InputError
from mtcal.io import atomic_write_text, read_csv_rows

REQUIRED = ("axis", "round", "position", "point", "x", "y", "z")
OPTIONAL = ("time_s", "direction", "temperature_c")
STATION_COLUMNS = ("station", "tracker_x", "tracker_y", "tracker_z")


@dataclass
class Recording:
    """A laser-tracker recording: its columns as arrays, one entry per reading (docs/design.md, "Files").

    Attributes
    ----------
    axis : numpy.ndarray of str, shape (n,)
        The axis moved (a name of the machine spec's axes).
    round : numpy.ndarray of int, shape (n,)
        Round number (1, 2, ...).
    position : numpy.ndarray of float, shape (n,)
        Commanded position of that axis, mm (linear) or deg (rotary).
    point : numpy.ndarray of str, shape (n,)
        Reflector nest label.
    xyz : numpy.ndarray of float, shape (n, 3)
        The reading, mm, machine frame.
    time_s : numpy.ndarray of float, shape (n,)
        Time of the reading, s; NaN where the column is absent.
    direction : numpy.ndarray of int, shape (n,)
        Approach direction +1 / -1; 0 where the column is absent.
    temperature_c : numpy.ndarray of float, shape (n,)
        A temperature channel, degC; NaN where absent.
    line : numpy.ndarray of int, shape (n,)
        The file line of each row (for messages).
    source : str
        Where the readings came from (a path, or ``"<memory>"``).
    truth : dict or None
        The planted truth of a simulated campaign (mtcal.campaign.simulate), else None.
    station : numpy.ndarray of str or None
        Tracker station label per row; None: one station (column absent).
    tracker_xyz : numpy.ndarray of float, shape (n, 3), or None
        Where each row's tracker stood, mm, machine frame; None: column absent.
    other_positions : dict of str to numpy.ndarray, or None
        The other axes' positions during each reading (``pos_<AXIS>`` columns; mm or deg); None: all at zero.

    See Also
    --------
    read_recording : read and check a recording CSV.
    mtcal.campaign.simulate.simulate : a simulated recording.
    """

    axis: np.ndarray  # str
    round: np.ndarray  # int
    position: np.ndarray  # float, mm or deg
    point: np.ndarray  # str
    xyz: np.ndarray  # (n, 3) mm
    time_s: np.ndarray  # float, NaN when absent
    direction: np.ndarray  # int, +1/-1, 0 when absent
    temperature_c: np.ndarray  # float, NaN when absent
    line: np.ndarray  # int
    source: str = "<memory>"
    truth: dict | None = None  # planted truth of a simulated campaign (mtcal.campaign.simulate), else None
    station: np.ndarray | None = None  # str label per row; None = one station (column absent)
    tracker_xyz: np.ndarray | None = None  # (n, 3) mm, machine frame; None = column absent
    other_positions: dict[str, np.ndarray] | None = None  # {axis: (n,) mm or deg} from pos_<AXIS> columns

    def __len__(self) -> int:
        return len(self.axis)

    def select(self, mask: np.ndarray) -> "Recording":
        return Recording(*(getattr(self, f)[mask] for f in _FIELDS), source=self.source,
                         station=None if self.station is None else self.station[mask],
                         tracker_xyz=None if self.tracker_xyz is None else self.tracker_xyz[mask],
                         other_positions=None if self.other_positions is None else
                         {a: v[mask] for a, v in self.other_positions.items()})

    def stations(self) -> np.ndarray:
        """Station label of every row ("" for all rows when the recording has one station)."""
        return np.full(len(self), "", dtype=object) if self.station is None else self.station

    def axes(self) -> list[str]:
        """The measured axes in the order they first appear in the file."""
        return list(dict.fromkeys(self.axis.tolist()))

    def where(self, i: int) -> str:
        return f"{self.source}:{int(self.line[i])}"


_FIELDS = ("axis", "round", "position", "point", "xyz", "time_s", "direction", "temperature_c", "line")


def _float(text: str, col: str, where: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise InputError(f"{where}: column {col!r} is not a number: {text!r}") from None
    if not math.isfinite(v):
        raise InputError(f"{where}: column {col!r} is {text!r} (NaN/inf is not a measurement)")
    return v


def read_recording(path: str | Path, machine=None) -> Recording:
    """Read and check a recording CSV (the tidy layout of docs/design.md, "Files").

    Header required; units mm and degrees; encodings and ``;`` exports as mtcal.io.read_csv_rows reads them.

    Parameters
    ----------
    path : str or pathlib.Path
        The CSV file: ``axis,round,position,point,x,y,z`` and optional ``time_s,direction,temperature_c``,
        ``station,tracker_x,tracker_y,tracker_z``, ``pos_<AXIS>``.
    machine : mtcal.Machine or str, optional
        The machine whose axes the recording's must be (default: the default machine, ``dmu50``).

    Returns
    -------
    Recording
        The readings, mm in the machine frame, positions in mm or deg.

    Raises
    ------
    mtcal.errors.InputError
        A bad file, header, row or value, named by file and line.

    Examples
    --------
    >>> import mtcal
    >>> from mtcal.data import path
    >>> rec = mtcal.read_recording(path("demo_campaign.csv"))
    >>> rec.axes(), len(rec)
    (['X', 'Y', 'Z', 'B', 'C'], 1680)
    """
    return _parse_rows(read_csv_rows(path, "recording"), str(path), _machine(machine))


def _machine(machine):
    from mtcal.kinematics.machine import Machine, load_machine
    return machine if isinstance(machine, Machine) else load_machine(*([machine] if machine else []))


def parse_recording(text: str, source: str = "<memory>", machine=None) -> Recording:
    """A recording from CSV text (comma-separated)."""
    rows = [(i + 1, r) for i, r in enumerate(csv.reader(io.StringIO(text))) if r and not r[0].lstrip().startswith("#")]
    if not rows:
        raise InputError(f"empty file, expected header {','.join(REQUIRED)}", source)
    return _parse_rows(rows, source, _machine(machine))


def _columns(hline: int, header: list[str], source: str, machine) -> tuple[list[str], list[str], list[str]]:
    """(header lower-cased, its pos_<AXIS> columns, its tracker_x,y,z columns); a missing, unknown or incomplete
    column is an InputError naming the header's line."""
    header = [h.strip().lower() for h in header]
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        raise InputError(f"{source}:{hline}: missing column(s) {missing}; header must contain "
                         f"{','.join(REQUIRED)} (optional {','.join(OPTIONAL)})")
    pos_cols = [c for c in header if c.startswith("pos_") and c[4:].upper() in machine.axes]
    unknown = [c for c in header if c not in REQUIRED + OPTIONAL + STATION_COLUMNS and c not in pos_cols]
    if unknown:
        raise InputError(f"{source}:{hline}: unknown column(s) {unknown}; allowed: "
                         f"{REQUIRED + OPTIONAL + STATION_COLUMNS} and pos_<AXIS> ({', '.join(machine.axes)})")
    trk_cols = [c for c in STATION_COLUMNS[1:] if c in header]
    if trk_cols and len(trk_cols) != 3:
        raise InputError(f"{source}:{hline}: tracker position needs all of tracker_x,tracker_y,tracker_z")
    return header, pos_cols, trk_cols


def _reading(r: list[str], col: dict[str, int], where: str, machine) -> tuple:
    """(axis, round, position, point, xyz, time_s, direction, temperature_c) of one data row, each checked."""
    ax = r[col["axis"]].strip().upper()
    if ax not in machine.axes:
        raise InputError(f"{where}: axis {r[col['axis']]!r} is not one of the axes of machine {machine.name} "
                         f"({', '.join(machine.axes)}; `machine` names another)")
    rnd_f = _float(r[col["round"]], "round", where)
    if rnd_f != int(rnd_f):
        raise InputError(f"{where}: round must be an integer, got {r[col['round']]!r}")
    pos = _float(r[col["position"]], "position", where)
    pt = r[col["point"]].strip()
    if not pt:
        raise InputError(f"{where}: empty point label")
    xyz = [_float(r[col[c]], c, where) for c in "xyz"]
    t = _float(r[col["time_s"]], "time_s", where) if "time_s" in col and r[col["time_s"]].strip() else math.nan
    d = 0
    if "direction" in col and r[col["direction"]].strip():
        d = _float(r[col["direction"]], "direction", where)
        if d not in (1.0, -1.0):
            raise InputError(f"{where}: direction must be +1 or -1, got {r[col['direction']]!r}")
    tc = (_float(r[col["temperature_c"]], "temperature_c", where)
          if "temperature_c" in col and r[col["temperature_c"]].strip() else math.nan)
    return ax, int(rnd_f), pos, pt, xyz, t, int(d), tc


def _parse_rows(rows: list[tuple[int, list[str]]], source: str, machine=None) -> Recording:
    hline, header = rows[0]
    header, pos_cols, trk_cols = _columns(hline, header, source, machine)
    col = {c: header.index(c) for c in header}
    out = {f: [] for f in _FIELDS}
    seen: dict[tuple, tuple[int, list[str]]] = {}  # key -> (first line, its fields)
    extra: dict[str, list] = {"station": [], "tracker": [], **{c: [] for c in pos_cols}}
    for line, r in rows[1:]:
        where = f"{source}:{line}"
        if len(r) != len(header):
            raise InputError(f"{where}: {len(r)} fields, header has {len(header)}")
        ax, rnd, pos, pt, xyz, t, d, tc = _reading(r, col, where, machine)
        extra["station"].append(r[col["station"]].strip() if "station" in col else "")
        extra["tracker"].append([_float(r[col[c]], c, where) for c in STATION_COLUMNS[1:]] if trk_cols else [])
        for c in pos_cols:
            extra[c].append(_float(r[col[c]], c, where) if r[col[c]].strip() else 0.0)
        key = (ax, rnd, pos, pt, d, t, extra["station"][-1])
        if key in seen and seen[key][1] != [c.strip() for c in r]:  # an exact copy is the screen's to report
            raise InputError(f"{where}: duplicate of line {seen[key][0]} (axis {ax}, round {rnd}, "
                             f"position {pos:g}, point {pt}); repeated readings need distinct direction or time_s")
        seen.setdefault(key, (line, [c.strip() for c in r]))
        for f, v in zip(_FIELDS, (ax, rnd, pos, pt, xyz, t, d, tc, line)):
            out[f].append(v)
    if not out["axis"]:
        raise InputError(f"{source}: header but no data rows")
    rec = Recording(np.array(out["axis"]), np.array(out["round"], dtype=int), np.array(out["position"], dtype=float),
                    np.array(out["point"]), np.array(out["xyz"], dtype=float).reshape(-1, 3),
                    np.array(out["time_s"], dtype=float), np.array(out["direction"], dtype=int),
                    np.array(out["temperature_c"], dtype=float), np.array(out["line"], dtype=int), source,
                    station=np.array(extra["station"], dtype=object) if "station" in col else None,
                    tracker_xyz=np.array(extra["tracker"], dtype=float) if trk_cols else None,
                    other_positions={c[4:].upper(): np.array(extra[c]) for c in pos_cols} or None)
    _check_units(rec, machine.linear_axes)
    check_stations(rec)
    return rec


def check_stations(rec: Recording) -> None:
    """A round belongs to one station; a station's tracker position is constant (docs/design.md)."""
    st = rec.stations()
    for r in np.unique(rec.round):
        rows = np.flatnonzero(rec.round == r)
        labels = np.unique(st[rows])
        if len(labels) > 1:
            i = int(rows[np.flatnonzero(st[rows] != st[rows[0]])[0]])
            raise InputError(f"{rec.where(i)}: round {int(r)} is measured from stations {sorted(labels)}; a round "
                             f"belongs to one station (give the other station's rows their own round number)")
    if rec.tracker_xyz is None:
        return
    for s_ in np.unique(st):
        rows = np.flatnonzero(st == s_)
        dev = np.abs(rec.tracker_xyz[rows] - rec.tracker_xyz[rows[0]]).max(axis=1)
        if (dev > 1e-6).any():
            i = int(rows[np.flatnonzero(dev > 1e-6)[0]])
            raise InputError(f"{rec.where(i)}: tracker position differs from line {int(rec.line[rows[0]])} of the "
                             f"same station {s_!r}; it is constant within a station (use a new station label)")


def _check_units(rec: Recording, linear) -> None:
    """Positions of a linear axis all within +-2 while the points move by metres' worth: metres, not mm."""
    for ax in linear:
        m = rec.axis == ax
        if m.sum() < 2:
            continue
        span = np.ptp(rec.position[m])
        moved = np.ptp(rec.xyz[m], axis=0).max()
        if 0 < span <= 2.0 and moved > 50 * span:
            i = int(np.flatnonzero(m)[0])
            raise InputError(f"{rec.where(i)}: axis {ax} positions span only {span:g} while the points move "
                             f"{moved:.1f} mm; positions must be in mm (were they written in metres?)")


def format_recording(rec: Recording, precision: int = 6) -> str:
    """CSV text of a recording (optional columns written when any row has them)."""
    cols = list(REQUIRED)
    has_t, has_d = (~np.isnan(rec.time_s)).any(), (rec.direction != 0).any()
    has_c = (~np.isnan(rec.temperature_c)).any()
    cols += [c for c, h in zip(OPTIONAL, (has_t, has_d, has_c)) if h]
    if rec.station is not None:
        cols.append("station")
    if rec.tracker_xyz is not None:
        cols += list(STATION_COLUMNS[1:])
    others = rec.other_positions or {}
    cols += [f"pos_{a}" for a in others]
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(cols)
    f = f"{{:.{precision}f}}"
    for i in range(len(rec)):
        row = [rec.axis[i], int(rec.round[i]), f"{rec.position[i]:.12g}", rec.point[i],
               *(f.format(v) for v in rec.xyz[i])]
        if has_t:
            row.append(f"{rec.time_s[i]:.3f}")
        if has_d:
            row.append(int(rec.direction[i]))
        if has_c:
            row.append(f"{rec.temperature_c[i]:.3f}")
        if rec.station is not None:
            row.append(rec.station[i])
        if rec.tracker_xyz is not None:
            row += [f"{v:.3f}" for v in rec.tracker_xyz[i]]
        row += [f"{others[a][i]:.12g}" for a in others]  # positions: 1e-10 mm or deg, not a reading's noise
        w.writerow(row)
    return buf.getvalue()


def write_recording(rec: Recording, path: str | Path, precision: int = 6) -> None:
    """Atomic write of the tidy CSV (xyz with ``precision`` decimals of a mm; default 1 nm)."""
    atomic_write_text(path, format_recording(rec, precision))


def make_recording(axis, round_, position, point, xyz, time_s=None, direction=None, temperature_c=None,
                   source: str = "<simulated>") -> Recording:
    """Build a Recording from arrays (simulation, tests)."""
    n = len(axis)
    nan = np.full(n, np.nan)
    return Recording(np.asarray(axis), np.asarray(round_, dtype=int), np.asarray(position, dtype=float),
                     np.asarray(point).astype(str), np.asarray(xyz, dtype=float).reshape(n, 3),
                     nan.copy() if time_s is None else np.asarray(time_s, dtype=float),
                     np.zeros(n, dtype=int) if direction is None else np.asarray(direction, dtype=int),
                     nan.copy() if temperature_c is None else np.asarray(temperature_c, dtype=float),
                     np.arange(2, n + 2), source)
