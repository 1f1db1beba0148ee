"""A thermal test as a data logger exports it: a CSV (``,`` ``;`` or tab separated; UTF-8, Windows-1252, UTF-16;
``#`` comments) or an Excel workbook (.xlsx, its first sheet), a row per reading, a header naming each column's
quantity by its unit.

Header styles, read without options: ``time (s), spindle (rpm), ch1 (um), ..., t1 (degC)`` (unit in brackets or
parentheses, FL_THERMAL's own ``ch1(um)``, ``t1(°C)``) and ``time_s, spindle_rpm, ch1_um, ..., t1_c`` (unit as a
``_`` suffix). The unit says the quantity (``UNITS``): a time (s, min, h: the first such column), a spindle
speed (rpm), a displacement channel (um, mm, nm), a temperature (degC; degF and K converted because the header
says so). A temperature column without a unit, or whose values cannot be degrees Celsius of a machine under test
(``TEMPERATURE_C``: K or F read as C), is refused: the unit is declared, never assumed. ``columns`` renames
headers the reader does not understand (``{"Zeit": "time (s)", "Fühler 1": "t1 (degC)"}``).

Directions of the displacement channels (ISO 230-3's five-sensor set-up: X1, X2, Y1, Y2 along two lines of the
test mandrel ``spacing`` mm apart, Z on its end): from a channel named by its direction (``X1 (um)``), or given
(``directions={"ch1": "X1", ...}``); without them each channel is its own direction and no tilt is evaluated.
"""
from __future__ import annotations

import json
import re
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from xml.etree import ElementTree

import numpy as np

from mtcal.errors import InputError
from mtcal.io import read_csv_table

UNITS = {  # unit word (lower case) -> (quantity, factor to the internal unit: s, rpm, um, degC offset handled)
    "s": ("time", 1.0), "sec": ("time", 1.0), "min": ("time", 60.0), "h": ("time", 3600.0),
    "rpm": ("speed", 1.0), "1/min": ("speed", 1.0), "min-1": ("speed", 1.0), "min^-1": ("speed", 1.0),
    "um": ("displacement", 1.0), "µm": ("displacement", 1.0), "μm": ("displacement", 1.0),
    "mm": ("displacement", 1000.0), "nm": ("displacement", 1e-3),
    "degc": ("temperature", "C"), "°c": ("temperature", "C"), "c": ("temperature", "C"),
    "celsius": ("temperature", "C"), "degf": ("temperature", "F"), "°f": ("temperature", "F"),
    "k": ("temperature", "K"),
}
TEMPERATURE_C = (-20.0, 120.0)  # a reading of a machine under test, degC; outside: K or F read as C
ROOM_F = (59.0, 95.0)  # the median sensor's median here (15..35 C in F): a room in degrees Fahrenheit
STUCK_SHARE = 0.5  # a sensor repeating one value over this share of the test (and STUCK_MIN readings) is stuck
STUCK_MIN = 10
DIRECTIONS = ("X1", "X2", "Y1", "Y2", "X", "Y", "Z")
PAIRS = {"X": ("X1", "X2"), "Y": ("Y1", "Y2")}  # tilt about Y from the X pair (B), about X from the Y pair (A)
_BRACKET = re.compile(r"^(?P<name>.*?)\s*[\(\[](?P<unit>[^\)\]]*)[\)\]]\s*$")
_SUFFIX = re.compile(r"^(?P<name>.+?)_(?P<unit>[A-Za-z°µμ]+)$")


@dataclass
class ThermalTest:
    """A thermal test as read: readings in time order, units converted to s, rpm, um, degC.

    Attributes
    ----------
    source : str
        The file read.
    time_s : ndarray, shape (n,)
        Time of each reading (s), strictly increasing.
    spindle_rpm : ndarray or None
        The spindle speed (rpm), None when the file has none (an environmental test).
    channels : dict of str to ndarray
        Displacement channels (um), in the file's order.
    temperatures : dict of str to ndarray
        Temperatures (degC).
    directions : dict of str to str
        Channel -> direction (X1, X2, Y1, Y2, X, Y, Z); empty when not known.
    spacing_mm : float or None
        Distance between the two sensors of a pair along the mandrel (mm), for the tilts.
    lines : ndarray
        File line of each reading (for messages).
    notes : list of str
        What the reader did (units converted, the columns found).
    """

    source: str
    time_s: np.ndarray
    spindle_rpm: np.ndarray | None
    channels: dict[str, np.ndarray]
    temperatures: dict[str, np.ndarray]
    directions: dict[str, str] = field(default_factory=dict)
    spacing_mm: float | None = None
    lines: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    notes: list[str] = field(default_factory=list)

    def __len__(self) -> int:
        return len(self.time_s)

    def where(self, i: int) -> int:
        """The file line of reading ``i``."""
        return int(self.lines[i]) if len(self.lines) else i + 2


def parse_header(text: str) -> tuple[str, str | None]:
    """(name, unit word or None) of one header: ``ch1 (um)``, ``ch1(um)``, ``ch1 [um]``, ``ch1_um``."""
    text = text.strip()
    m = _BRACKET.match(text)
    if m:
        return m.group("name").strip(), m.group("unit").strip().lower().replace(" ", "")
    m = _SUFFIX.match(text)
    if m and m.group("unit").lower() in UNITS:
        return m.group("name"), m.group("unit").lower()
    return text, None


def read_thermal_test(path: str | Path, columns: dict | str | None = None, directions: dict | str | None = None,
                      spacing_mm: float | None = None) -> ThermalTest:
    """Read a thermal test (module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        CSV or .xlsx file.
    columns : dict or str, optional
        Header renames ``{header: "name (unit)"}``, or their text ``HEADER=NAME (UNIT),...`` or a JSON file.
    directions : dict or str, optional
        ``{channel: direction}`` or ``ch1=X1,ch2=X2,...``; every channel must have one.
    spacing_mm : float, optional
        The sensors' spacing along the mandrel within a pair (mm): needed for the tilts.

    Returns
    -------
    ThermalTest

    Raises
    ------
    mtcal.errors.InputError
        One line naming file, line and problem: no time column, time not increasing, a missing or non-numeric
        value, a stuck sensor, a temperature without a unit or not in degC, a channel without a direction.
    """
    src = str(path)
    header, body = _table(path)
    header = [_rename(h, parse_mapping(columns, "columns")) for h in header]
    roles = _roles(header, src)
    data = _numbers(body, header, src)
    lines = np.array([i for i, _ in body])
    t_col = roles["time"][0]
    t = data[:, t_col[0]] * t_col[2]
    bad = np.flatnonzero(np.diff(t) <= 0)
    if bad.size:
        i = bad[0] + 1
        raise InputError(f"time not increasing: {t[i]:g} s after {t[i - 1]:g} s", src, lines[i])
    notes = [f"columns: time {header[t_col[0]]!r}" + "".join(
        f"; {q} " + ", ".join(repr(header[c[0]]) for c in roles[q]) for q in ("speed", "displacement",
                                                                            "temperature") if roles[q])]
    rpm = data[:, roles["speed"][0][0]] if roles["speed"] else None
    ch = {c[1]: data[:, c[0]] * c[2] for c in roles["displacement"]}
    temps = {c[1]: _celsius(data[:, c[0]], c[2], c[1], src, lines, notes) for c in roles["temperature"]}
    if not ch:
        raise InputError("no displacement channel (a column in um, mm or nm)", src, 1)
    _check_room_f(temps, src)
    for name, v in {**ch, **temps}.items():
        _check_stuck(name, v, src, lines)
    test = ThermalTest(src, t, rpm, ch, temps, lines=lines, notes=notes)
    test.directions = _directions(test, parse_mapping(directions, "directions"), src)
    test.spacing_mm = spacing_mm
    return test


def _table(path: str | Path) -> tuple[list[str], list[tuple[int, list[str]]]]:
    if str(path).lower().endswith(".xlsx"):
        rows = _xlsx_rows(path)
    else:
        rows = read_csv_table(path, "thermal test")[1]
    if len(rows) < 2:
        raise InputError("no readings after the header", path, rows[0][0] if rows else 1)
    return rows[0][1], rows[1:]


def _xlsx_rows(path: str | Path) -> list[tuple[int, list[str]]]:
    """The first sheet of a workbook as (row number, cell texts), read with the standard library (shared strings
    and the sheet's XML; Office Open XML, ECMA-376 part 1, 18.3 and 18.4)."""
    ns = "{http://schemas.openxmlformats.org/spreadsheetml/2006/main}"
    try:
        with zipfile.ZipFile(path) as z:
            names = z.namelist()
            shared = [] if "xl/sharedStrings.xml" not in names else [
                "".join(t.text or "" for t in si.iter(f"{ns}t"))
                for si in ElementTree.fromstring(z.read("xl/sharedStrings.xml")).findall(f"{ns}si")]
            sheet = ElementTree.fromstring(z.read(sorted(n for n in names if n.startswith("xl/worksheets/sheet"))[0]))
    except (zipfile.BadZipFile, KeyError, IndexError, ElementTree.ParseError) as exc:
        raise InputError(f"not a readable .xlsx workbook ({exc})", path) from None
    out = []
    for row in sheet.iter(f"{ns}row"):
        cells = {}
        for c in row.findall(f"{ns}c"):
            v = c.find(f"{ns}v")
            col = re.match(r"[A-Z]+", c.get("r", "A")).group(0)
            k = sum((ord(ch) - 64) * 26 ** i for i, ch in enumerate(reversed(col))) - 1
            text = "" if v is None else v.text or ""
            cells[k] = shared[int(text)] if c.get("t") == "s" and text else text
        if cells:
            out.append((int(row.get("r", len(out) + 1)), [cells.get(k, "") for k in range(max(cells) + 1)]))
    return out


def parse_mapping(value: dict | str | None, what: str) -> dict[str, str]:
    """A ``{key: value}`` option as given: a dict, ``KEY=VALUE,...`` text, or a JSON file of an object."""
    if value is None or isinstance(value, dict):
        return dict(value or {})
    if value.lower().endswith(".json"):
        try:
            obj = json.loads(Path(value).read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise InputError(f"`{what}` {value}: not a readable JSON file ({exc})") from None
        if not isinstance(obj, dict):
            raise InputError(f"`{what}` {value}: expected a JSON object {{header: ...}}")
        return {str(k): str(v) for k, v in obj.items()}
    out = {}
    for part in value.split(","):
        if "=" not in part:
            raise InputError(f"`{what}`: expected KEY=VALUE[,KEY=VALUE...], got {part!r}")
        k, v = part.split("=", 1)
        out[k.strip()] = v.strip()
    return out


def _rename(h: str, renames: dict[str, str]) -> str:
    return renames.get(h.strip(), h)


def _roles(header: list[str], src: str) -> dict[str, list[tuple[int, str, object]]]:
    """{quantity: [(column, name, factor)]} from the header's units; a column without a known unit is refused."""
    roles: dict[str, list] = {"time": [], "speed": [], "displacement": [], "temperature": []}
    for k, h in enumerate(header):
        name, unit = parse_header(h)
        if unit not in UNITS:
            what = f"unit {unit!r} is not one of a thermal test" if unit else "no unit"
            raise InputError(f"column {k + 1} {h.strip()!r}: {what} (say it: `name (s|rpm|um|mm|degC|degF|K)`, "
                             f"or rename it with `columns`)", src, 1)
        quantity, factor = UNITS[unit]
        roles[quantity].append((k, name or h.strip(), factor))
    if not roles["time"]:
        raise InputError("no time column (a header with unit s, min or h)", src, 1)
    if len(roles["speed"]) > 1:
        raise InputError("more than one spindle speed column (rpm): " + ", ".join(c[1] for c in roles["speed"]),
                         src, 1)
    names = [c[1] for q in ("displacement", "temperature") for c in roles[q]]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise InputError(f"column name(s) given twice: {', '.join(dup)}", src, 1)
    return roles


def _numbers(body: list[tuple[int, list[str]]], header: list[str], src: str) -> np.ndarray:
    out = np.empty((len(body), len(header)))
    for r, (line, fields) in enumerate(body):
        if len(fields) < len(header) or not all(f.strip() for f in fields[:len(header)]):
            k = next(k for k in range(len(header)) if k >= len(fields) or not fields[k].strip())
            raise InputError(f"missing value of {header[k].strip()!r} (a sensor that dropped out)", src, line)
        for k in range(len(header)):
            try:
                out[r, k] = float(fields[k])
            except ValueError:
                out[r, k] = np.nan
            if not np.isfinite(out[r, k]):
                raise InputError(f"{header[k].strip()!r}: not a finite number: {fields[k]!r}", src, line)
    return out


def _celsius(v: np.ndarray, unit: str, name: str, src: str, lines: np.ndarray, notes: list[str]) -> np.ndarray:
    """degC from the header's unit; a value outside TEMPERATURE_C (K or F read as C) refused."""
    c = v - 273.15 if unit == "K" else (v - 32.0) * 5.0 / 9.0 if unit == "F" else v
    if unit != "C":
        notes.append(f"{name}: in {'K' if unit == 'K' else 'degF'} (the header says so), converted to degC")
    bad = np.flatnonzero((c < TEMPERATURE_C[0]) | (c > TEMPERATURE_C[1]))
    if bad.size:
        i = bad[0]
        raise InputError(f"temperature {name} = {v[i]:g} is {c[i]:g} degC, outside {TEMPERATURE_C[0]:g}.."
                         f"{TEMPERATURE_C[1]:g} degC of a machine under test: K or degF read as degC? (say the unit "
                         f"in the header: degC, degF or K)", src, lines[i])
    return c


def _check_room_f(temps: dict[str, np.ndarray], src: str) -> None:
    """The median sensor reading 59..95 (a room of 15..35 C in degrees Fahrenheit) is refused."""
    med = sorted(float(np.median(v)) for v in temps.values())
    if len(med) >= 2 and ROOM_F[0] <= float(np.median(med)) <= ROOM_F[1]:
        raise InputError(f"the temperatures' median reading is {np.median(med):.1f} 'degC' (sensors' medians "
                         f"{med[0]:.1f}..{med[-1]:.1f}): a room in degrees Fahrenheit? (say degF in the header if "
                         f"so)", src, 1)


def _check_stuck(name: str, v: np.ndarray, src: str, lines: np.ndarray) -> None:
    """A sensor repeating one reading over STUCK_SHARE of the test (at least STUCK_MIN readings) is stuck."""
    change = np.flatnonzero(np.diff(v) != 0)
    starts = np.concatenate([[0], change + 1])
    ends = np.concatenate([change, [len(v) - 1]])
    k = int(np.argmax(ends - starts))
    run = ends[k] - starts[k] + 1
    if run >= max(STUCK_MIN, STUCK_SHARE * len(v)):
        raise InputError(f"sensor {name} is stuck: the same reading {v[starts[k]]:g} from line {lines[starts[k]]} "
                         f"to line {lines[ends[k]]} ({run} of {len(v)} readings)", src, lines[starts[k]])


def _directions(test: ThermalTest, given: dict[str, str], src: str) -> dict[str, str]:
    """Channel -> direction: given for every channel, or every channel named by its direction, or none."""
    named = {c: c.upper() for c in test.channels if c.upper() in DIRECTIONS}
    if not given:
        return named if len(named) == len(test.channels) else {}
    unknown = sorted(set(given) - set(test.channels))
    if unknown:
        raise InputError(f"`directions` names channel(s) {', '.join(unknown)} the file does not have (it has "
                         f"{', '.join(test.channels)})", src)
    missing = [c for c in test.channels if c not in given]
    if missing:
        raise InputError(f"channel(s) without a direction: {', '.join(missing)} (`directions` must give each of "
                         f"{', '.join(test.channels)} one of {', '.join(DIRECTIONS)})", src)
    out = {c: given[c].strip().upper() for c in test.channels}
    bad = {c: d for c, d in out.items() if d not in DIRECTIONS}
    if bad:
        raise InputError("not a direction: " + ", ".join(f"{c}={d}" for c, d in bad.items())
                         + f" (one of {', '.join(DIRECTIONS)})", src)
    dup = sorted({d for d in out.values() if list(out.values()).count(d) > 1})
    if dup:
        raise InputError(f"direction(s) given to more than one channel: {', '.join(dup)}", src)
    return out
