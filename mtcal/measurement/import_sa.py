"""SpatialAnalyzer (New River Kinematics) ASCII point exports -> the tidy recording of docs/design.md.

Source: SpatialAnalyzer User Manual, "Exporting ASCII Formatted Points" (kinematics.com/ftp/SA/Install/Driver
Downloads/Misc/Testing/SAUsersManual.zip): points are written in the working frame; the point name is
"Collection Group Target", "Group Target", "Target" or none; then x y z; optional tolerance, coordinate
uncertainties, time stamp, target offsets, comments and measurement details; fields separated by spaces or
commas; SA version, frame and axis information as leading comment lines that start with ``//``.

Layout read here (the manual gives no column grammar beyond that, so this is the assumed common form):
* blank lines and lines starting with ``//`` are skipped; a field separator is a tab if the line has one,
  else a comma if it has one, else runs of spaces;
* an optional header line naming the columns (``Collection, Group, Target, X, Y, Z[, ux, uy, uz][, Time]``;
  ``Point`` or ``Name`` for Target; case-insensitive): then columns are taken by name;
* without a header: the name fields (Collection, Group, Target; a single field ``Collection::Group::Target`` is
  split at ``::``; how many: ``name_fields`` or, by default, the leading fields of the first data line that are
  not numbers), then x y z, then optionally the three coordinate uncertainties, then a time stamp (seconds, or
  a date and time ``YYYY-MM-DD HH:MM:SS[.f]`` / ``YYYY/MM/DD ...``, one field or two).
Lengths are converted to mm from the export's own ``// Units: ...`` comment line when it has one (``Millimeters``,
``Inches``, ``Meters`` or mm, in, m), else from ``units`` (SA's default export unit is mm); a ``units`` given that
contradicts the file's line is refused, naming both.  Time stamps become
time_s (a date-time: seconds since the earliest in the file).  Uncertainties are read and checked but the tidy
recording has no column for them: the summary says so.

Each target name maps to axis, round, position (mm or deg), point and optionally direction, by a mapping file
(CSV with header ``target,axis,round,position,point[,direction]``; ``target`` matches the Target name or the full
``Collection::Group::Target``) or a regular expression with those named groups (full match of the Target name,
else of the full name).  Unmatched targets are an error (listed) unless they are skipped with a count.
"""
from __future__ import annotations

import csv
import io
import math
import re
from dataclasses import dataclass, field
from datetime import datetime
from pathlib import Path

import numpy as np

from mtcal.errors import InputError
from mtcal.io import read_text
from mtcal.measurement.recordings import Recording, make_recording

UNITS_MM = {"mm": 1.0, "in": 25.4, "m": 1000.0}
UNIT_WORDS = {"mm": "mm", "millimeter": "mm", "millimeters": "mm", "millimetre": "mm", "millimetres": "mm",
              "in": "in", "inch": "in", "inches": "in", "m": "m", "meter": "m", "meters": "m", "metre": "m",
              "metres": "m"}  # the words of SA's "// Units:" comment line, read as UNITS_MM's keys
_UNITS_LINE = re.compile(r"^//\s*units?\s*[:=]\s*(.*?)\s*$", re.I)
GROUPS = ("axis", "round", "position", "point")  # required names of a mapping
DIRECTIONS = {"+": 1, "+1": 1, "1": 1, "up": 1, "pos": 1, "-": -1, "-1": -1, "down": -1, "dn": -1, "neg": -1}
HEADER_NAMES = {"collection": "collection", "group": "group", "target": "target", "point": "target",
                "name": "target", "x": "x", "y": "y", "z": "z", "ux": "ux", "uy": "uy", "uz": "uz",
                "time": "time", "timestamp": "time", "time stamp": "time", "time_s": "time",
                "tolerance": "tolerance", "tol": "tolerance"}
PLAUSIBLE_MM = 20000.0  # no machine tool is measured over more than this: beyond it the length unit is wrong
_STAMP = re.compile(r"^\d{4}[-/]\d{2}[-/]\d{2}([ T]\d{1,2}:\d{2}(:\d{2}(\.\d+)?)?)?$")


@dataclass
class SAPoint:
    collection: str
    group: str
    target: str
    xyz: tuple[float, float, float]  # file units
    uncertainty: tuple[float, float, float] | None
    time: float | datetime | None
    line: int

    @property
    def full_name(self) -> str:
        return "::".join(n for n in (self.collection, self.group, self.target) if n)


@dataclass
class ImportResult:
    recording: Recording
    matched: int
    skipped: list[tuple[str, int]]  # (full name, line) of unmatched targets left out
    notes: list[str] = field(default_factory=list)
    units: str = "mm"  # the export's length unit read (its "// Units:" line, or as given)

    def to_dict(self) -> dict:
        return {"units": self.units, "rows": len(self.recording), "axes": self.recording.axes(),
                "matched": self.matched, "skipped": len(self.skipped),
                "skipped_targets": [n for n, _ in self.skipped], "notes": self.notes}


# ----------------------------------------------------------------------------- the export file
def _split(line: str) -> list[str]:
    if "\t" in line:
        return [f.strip() for f in line.split("\t")]
    if "," in line:
        return [f.strip() for f in next(csv.reader([line]))]
    return line.split()


def _number(text: str) -> float | None:
    try:
        v = float(text)
    except ValueError:
        return None
    return v if math.isfinite(v) else None


def _time(fields: list[str], where: str) -> float | datetime | None:
    if not fields:
        return None
    text = " ".join(fields)
    v = _number(text) if len(fields) == 1 else None
    if v is not None:
        return v
    if _STAMP.match(text):
        t = text.replace("/", "-").replace("T", " ")
        for fmt in ("%Y-%m-%d %H:%M:%S.%f", "%Y-%m-%d %H:%M:%S", "%Y-%m-%d %H:%M", "%Y-%m-%d"):
            try:
                return datetime.strptime(t, fmt)
            except ValueError:
                continue
    raise InputError(f"{where}: unrecognised field(s) after x y z: {fields!r}; expected the three uncertainties "
                     f"and/or a time stamp (seconds or YYYY-MM-DD HH:MM:SS); export without other options or add "
                     f"a header line naming the columns")


def _names(fields: list[str], k: int) -> tuple[str, str, str]:
    if k == 1 and "::" in fields[0]:
        parts = fields[0].split("::")
        parts = [""] * (3 - len(parts)) + parts if len(parts) <= 3 else ["::".join(parts[:-2])] + parts[-2:]
        return parts[0], parts[1], parts[2]
    names = [""] * (3 - k) + fields[:k]
    return names[0], names[1], names[2]


def _positional(fields: list[str], k: int, where: str) -> SAPoint:
    if len(fields) < k + 3:
        raise InputError(f"{where}: {len(fields)} fields; expected {k} name field(s) then x y z")
    xyz = [_number(f) for f in fields[k:k + 3]]
    if None in xyz:
        raise InputError(f"{where}: x y z must be numbers, got {fields[k:k + 3]!r}")
    rest = fields[k + 3:]
    numbers = len(rest) if all(_number(f) is not None for f in rest) else None
    if numbers in (1, 2, 5, 6):  # SA's optional tolerance, 3 uncertainties, time: these counts are ambiguous
        raise InputError(f"{where}: {numbers} number(s) after x y z ({rest!r}): a tolerance, uncertainties or a "
                         f"time stamp cannot be told apart by position; add a header line naming the columns "
                         f"(e.g. Collection, Group, Target, X, Y, Z, Tolerance, Time)"
                         + ("; or, if the target names are numbers, numbered targets need `name_fields` 3"
                            if k < 3 and "::" not in fields[0] else ""))
    unc = None
    if len(rest) >= 3 and all(_number(f) is not None for f in rest[:3]):
        unc, rest = tuple(_number(f) for f in rest[:3]), rest[3:]
    c, g, t = _names(fields, k)
    if not t:
        raise InputError(f"{where}: empty target name")
    return SAPoint(c, g, t, tuple(xyz), unc, _time(rest, where), 0)


def _header(fields: list[str], where: str) -> dict[str, int] | None:
    keys = [HEADER_NAMES.get(f.strip().lower()) for f in fields]
    if not {"x", "y", "z", "target"} <= set(keys):
        return None
    col: dict[str, int] = {}
    for i, k in enumerate(keys):
        if k is None:
            continue
        if k in col:
            raise InputError(f"{where}: columns {col[k] + 1} ({fields[col[k]].strip()!r}) and {i + 1} "
                             f"({fields[i].strip()!r}) both name {k!r}: which one is meant is ambiguous")
        col[k] = i
    return col


def _by_header(fields: list[str], col: dict[str, int], n: int, where: str) -> SAPoint:
    if len(fields) != n:
        raise InputError(f"{where}: {len(fields)} fields, the header has {n}")
    get = lambda k: fields[col[k]] if k in col else ""  # noqa: E731
    xyz = [_number(get(c)) for c in "xyz"]
    if None in xyz:
        raise InputError(f"{where}: x y z must be numbers, got {[get(c) for c in 'xyz']!r}")
    unc = None
    if all(k in col for k in ("ux", "uy", "uz")) and any(get(k) for k in ("ux", "uy", "uz")):
        unc = tuple(_number(get(k)) for k in ("ux", "uy", "uz"))
        if None in unc:
            raise InputError(f"{where}: uncertainties must be numbers, got {[get(k) for k in ('ux', 'uy', 'uz')]!r}")
    if not get("target"):
        raise InputError(f"{where}: empty target name")
    return SAPoint(get("collection"), get("group"), get("target"), tuple(xyz), unc,
                   _time([get("time")], where) if get("time") else None, 0)


def read_sa_points(text: str, source: str = "<memory>", name_fields: int | None = None,
                   notes: list[str] | None = None) -> list[SAPoint]:
    """Points of a SpatialAnalyzer ASCII export (layout in the module docstring); coordinates in file units."""
    notes = [] if notes is None else notes
    points: list[SAPoint] = []
    col, width, k = None, 0, name_fields
    for n, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip().lstrip("\ufeff")
        if not line or line.startswith("//"):
            continue
        where, fields = f"{source}:{n}", _split(line)
        if not points and col is None and (h := _header(fields, where)) is not None:
            col, width = h, len(fields)
            unknown = [f for f in fields if f.strip().lower() not in HEADER_NAMES]
            if unknown:
                notes.append(f"{source}:{n}: column(s) {unknown} not used")
            continue
        if col is not None:
            p = _by_header(fields, col, width, where)
        else:
            if k is None:
                k = next((i for i, f in enumerate(fields) if _number(f) is not None), len(fields))
                if not 1 <= k <= 3:
                    raise InputError(f"{where}: expected 1-3 name fields (Collection Group Target) before x y z, "
                                     f"found {k}; numeric target names need name_fields (`name_fields`)")
                if k < 3 and "::" not in fields[0]:
                    notes.append(f"{source}:{n}: {k} name field(s) before x y z taken from the first "
                                 f"non-number; numbered targets need `name_fields` 3")
            p = _positional(fields, k, where)
        p.line = n
        points.append(p)
    if not points:
        raise InputError(f"{source}: no points (only comments or blank lines)")
    return points


# ----------------------------------------------------------------------------- mapping target -> recording keys
TargetMap = dict[str, dict[str, str]]  # target name -> {axis, round, position, point[, direction]}


def read_mapping(path: str | Path) -> TargetMap:
    """Mapping CSV: header target,axis,round,position,point[,direction]; one row per target name."""
    p = Path(path)
    rows = list(csv.reader(io.StringIO(read_text(p, "mapping"))))
    rows = [(i + 1, r) for i, r in enumerate(rows) if r and not r[0].lstrip().startswith("#")]
    if not rows:
        raise InputError(f"{p}: empty mapping file")
    header = [h.strip().lower() for h in rows[0][1]]
    dup = sorted({h for h in header if header.count(h) > 1})
    if dup:
        raise InputError(f"{p}:{rows[0][0]}: column(s) {dup} appear twice in the mapping's header")
    need = ("target",) + GROUPS
    if not set(need) <= set(header) or not set(header) <= set(need + ("direction",)):
        raise InputError(f"{p}:{rows[0][0]}: header must be target,axis,round,position,point[,direction], "
                         f"got {','.join(header)}")
    out: TargetMap = {}
    seen: dict[str, int] = {}
    for line, r in rows[1:]:
        if len(r) != len(header):
            raise InputError(f"{p}:{line}: {len(r)} fields, header has {len(header)}")
        row = {h: v.strip() for h, v in zip(header, r)}
        name = row.pop("target")
        if name in seen:
            raise InputError(f"{p}:{line}: target {name!r} mapped again (first at line {seen[name]})")
        seen[name] = line
        out[name] = row | {"_where": f"{p}:{line}"}
    return out


def compile_pattern(pattern: str) -> re.Pattern:
    """The naming pattern: a regular expression with named groups axis, round, position, point [, direction]."""
    try:
        rx = re.compile(pattern)
    except re.error as exc:
        raise InputError(f"`pattern` is not a valid regular expression: {exc}") from None
    missing = [g for g in GROUPS if g not in rx.groupindex]
    if missing:
        raise InputError(f"`pattern` needs the named groups {list(GROUPS)} (+ optional direction); missing "
                         f"{missing}: write them as (?P<axis>...)")
    return rx


def _lookup(p: SAPoint, mapping: TargetMap | None, rx: re.Pattern | None, source: str) -> dict[str, str] | None:
    if mapping is not None:
        return mapping.get(p.target, mapping.get(p.full_name))
    m = rx.fullmatch(p.target) or rx.fullmatch(p.full_name)
    if m is None:
        return None
    found = {k: v for k, v in m.groupdict().items() if v is not None}
    absent = [g for g in GROUPS if g not in found]
    if absent:
        raise InputError(f"{source}:{p.line}: target {p.full_name} matches `pattern` but its group(s) {absent} took "
                         f"no part in the match (optional groups?): every target needs {list(GROUPS)}")
    return found


def _keys(found: dict[str, str], where: str, axes: tuple[str, ...]) -> tuple[str, int, float, str, int]:
    """axis, round, position, point, direction (0 = not given) from mapped text, checked."""
    ax = found["axis"].strip().upper()
    if ax not in axes:
        raise InputError(f"{where}: axis {found['axis']!r} is not one of the machine's axes ({', '.join(axes)})")
    rnd, pos = _number(found["round"]), _number(found["position"])
    if rnd is None or rnd != int(rnd):
        raise InputError(f"{where}: round must be an integer, got {found['round']!r}")
    if pos is None:
        raise InputError(f"{where}: position must be a number (mm or deg), got {found['position']!r}")
    if not found["point"].strip():
        raise InputError(f"{where}: empty point label")
    d = found.get("direction", "").strip().lower()
    if d and d not in DIRECTIONS:
        raise InputError(f"{where}: direction {found['direction']!r} is not one of {', '.join(DIRECTIONS)}")
    return ax, int(rnd), pos, found["point"].strip(), DIRECTIONS.get(d, 0)


# ----------------------------------------------------------------------------- the whole import
def _times(points: list[SAPoint], source: str) -> np.ndarray:
    kinds = {type(p.time) for p in points}
    if kinds == {type(None)}:
        return np.full(len(points), np.nan)
    if len(kinds) > 1:
        raise InputError(f"{source}: time stamps on some points only, or of mixed kinds (seconds and dates)")
    if datetime in kinds:
        t0 = min(p.time for p in points)
        return np.array([(p.time - t0).total_seconds() for p in points])
    return np.array([p.time for p in points], dtype=float)


def file_units(text: str, source: str = "<memory>") -> tuple[str | None, int]:
    """The length unit an export states in its ``// Units: ...`` comment line (a key of UNITS_MM) and that line's
    number, or (None, 0) without one; a unit mtcal does not read, or two lines that disagree, are refused."""
    found: tuple[str | None, int] = (None, 0)
    for n, raw in enumerate(text.splitlines(), start=1):
        m = _UNITS_LINE.match(raw.strip().lstrip("\ufeff"))
        if m is None:
            continue
        unit = UNIT_WORDS.get(m.group(1).lower().rstrip("."))
        if unit is None:
            raise InputError(f"{source}:{n}: the export's units are {m.group(1)!r}; mtcal reads Millimeters, Inches "
                             f"or Meters (export again in one of them)")
        if found[0] is not None and found[0] != unit:
            raise InputError(f"{source}:{n}: units {m.group(1)!r} contradict line {found[1]} ({found[0]})")
        found = (unit, n) if found[0] is None else found
    return found


def import_sa(text: str, source: str = "<memory>", mapping: TargetMap | None = None, pattern: str | None = None,
              units: str | None = None, skip_unmatched: bool = False, name_fields: int | None = None,
              machine=None) -> ImportResult:
    """SpatialAnalyzer export text -> tidy Recording (xyz in mm); exactly one of ``mapping`` / ``pattern``;
    the axes must be axes of ``machine`` (mtcal.Machine or name; default: the default machine).  ``units``: the
    export's length unit (mm, in, m); default: its ``// Units:`` line, else mm (``ImportResult.units``)."""
    from mtcal.kinematics.machine import Machine, load_machine
    axes = (machine if isinstance(machine, Machine) else load_machine(*([machine] if machine else []))).axes
    if (mapping is None) == (pattern is None):
        raise InputError("give exactly one of a mapping file (`mapping`) or a naming pattern (`pattern`)")
    if units is not None and units not in UNITS_MM:
        raise InputError(f"`units` must be one of {', '.join(UNITS_MM)}, got {units!r}")
    stated, at = file_units(text, source)
    if units is not None and stated is not None and units != stated:
        raise InputError(f"{source}:{at}: the export says its units are {stated}, `units` says {units}: "
                         f"leave `units` out to read the file's")
    units = units or stated or "mm"
    rx = compile_pattern(pattern) if pattern is not None else None
    notes: list[str] = []
    points = read_sa_points(text, source, name_fields, notes)
    keep, keys, skipped = [], [], []
    for p in points:
        found = _lookup(p, mapping, rx, source)
        if found is None:
            skipped.append((p.full_name, p.line))
            continue
        where = f"{source}:{p.line}" + (f" (mapping: {found['_where']})" if "_where" in found else "")
        keep.append(p)
        keys.append(_keys(found, where, axes))
    if skipped and not skip_unmatched:
        shown = "; ".join(f"{n} (line {ln})" for n, ln in skipped[:10])
        hint = "".join(f"; {n}" for n in notes if "name field(s)" in n)
        raise InputError(f"{source}: {len(skipped)} target(s) match no {'mapping row' if mapping else 'pattern'}: "
                         f"{shown}{' ...' if len(skipped) > 10 else ''} (`skip_unmatched` leaves them out){hint}")
    if not keep:
        raise InputError(f"{source}: no target matched")
    if skipped:
        notes.append(f"{len(skipped)} unmatched target(s) left out (`skip_unmatched`)")
    _check_duplicates(keep, keys, source)
    if any(p.uncertainty is not None for p in keep):
        notes.append("coordinate uncertainties were read but the tidy recording has no column for them: not carried")
    xyz = _in_mm(np.array([p.xyz for p in keep], dtype=float), units, keep, source)
    ax, rnd, pos, pt, d = (list(c) for c in zip(*keys))
    rec = make_recording(ax, rnd, pos, pt, xyz, _times(keep, source), d, source=source)
    rec.line = np.array([p.line for p in keep])
    return ImportResult(rec, len(keep), skipped, notes, units)


def _in_mm(xyz: np.ndarray, units: str, points: list[SAPoint], source: str) -> np.ndarray:
    """Readings in mm; refused when the result is not a machine tool's size (the export's unit is another)."""
    with np.errstate(over="ignore"):
        mm = xyz * UNITS_MM[units]
    size = np.abs(mm).max(axis=1)
    bad = np.flatnonzero(~np.isfinite(size) | (size > PLAUSIBLE_MM))
    if len(bad):
        i = int(bad[0])
        raise InputError(f"{source}:{points[i].line}: target {points[i].full_name} at {size[i]:.4g} mm after "
                         f"converting from {units}: beyond {PLAUSIBLE_MM:g} mm, no machine tool's size (is the "
                         f"export really in {units}? `units`)")
    return mm


def _check_duplicates(points: list[SAPoint], keys: list[tuple], source: str) -> None:
    seen: dict[tuple, int] = {}
    for p, k in zip(points, keys):
        key = k + (p.time if isinstance(p.time, float) else str(p.time),)
        if key in seen:
            raise InputError(f"{source}:{p.line}: target {p.full_name} maps to the same reading as line "
                             f"{seen[key]} (axis {k[0]}, round {k[1]}, position {k[2]:g}, point {k[3]}); repeated "
                             f"readings need a direction or a time stamp")
        seen[key] = p.line
