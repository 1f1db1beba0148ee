"""An ISO 230-2 test as a laser interferometer (or any 1-D reference sensor) records it, read as the laser
software exports it.

Three layouts, told apart by the header (``,`` ``;`` or tab separated, detected and said; ``#`` comment lines;
UTF-8, Windows-1252 or UTF-16), the columns found said in one line of the notes:

* **long** -- a row per reading: a target column, a run column, a direction column and the laser reading
  (``measured``: the position reached) or the error (``deviation``: reached minus target) or both, as lab exports
  write them (then both are read, the deviation taken from the reading and the error column checked against it
  on every row, within the rounding of the digits written: ``_cross_check``), optionally air and material
  temperatures, e.g. ``Run,Target (mm),Direction,Laser reading (mm)`` or mtcal's own
  ``target_mm,run,direction,measured_mm``;
* **wide** -- a row per target: a target column, then a column per run and direction, e.g.
  ``Target (mm),Run 1 Fwd (um),Run 1 Rev (um),...`` or ``Sollposition [mm],Lauf 1 vorwaerts Abweichung [um],...``;
  a run column holds errors or readings as its header says (``error``, ``deviation``, ``Abweichung`` /
  ``reading``, ``measured``, ``actual``, ``Messwert``), or, unsaid, errors when its unit is finer than the
  target's (um against mm, arcsec against deg); else ``columns={"values": ...}`` says;
* either one after a **metadata block**: ``key: value`` (or ``key = value``, ``key;value``, ``key,value``) lines
  before the header -- machine, axis, date, units, air temperature, material temperature (the material
  temperature feeds the normalisation to 20 C of every reading without its own; the air temperature is stated:
  the laser's environmental compensation already used it).

Names are matched in English and German (``ROLES``, ``RUN_WORDS``); units from the header (``(mm)``, ``[um]``,
``_mm``, ``µm``, ``°``, ``arcsec``), else from the metadata's ``units``, else ``unit``: declared, never
assumed.  Direction words (``DIRECTIONS``): up/down, +/-, +1/-1, Fwd/Rev, forward/reverse, bwd/backward,
pos/neg, inc/dec, German vorwaerts/rueckwaerts, hin/rueck, Hinlauf/Ruecklauf, French aller/retour; others with
``directions``.  Anything the header does not say is named with ``columns`` ({role: header text}).

The header's claims are checked against the values (``_check_claims``): a deviation beyond ``SPAN_FRACTION`` of
the targets' span is no machine's positioning error (a reading in another unit than its header says, an error
column holding the positions reached), and a column every value of which is its target is the target column
copied, not a measurement: both refused naming the column and the line.  In a ``;``-separated export whose numbers
use decimal commas, a dot is a thousands separator (``1.000`` = 1000, ``1.250,5`` = 1250.5: read so, and said);
a number written with a decimal point among decimal commas, or with thousands separators in a ``,``-separated
file (``"1,000.5"``), is refused naming it.

Every deviation is x_ij = P_ij - P_i (ISO 230-2: one datum for all runs, the sensor's zero); a reading that is not
in the file (an empty cell) is missing (the target's statistics use the runs that have it).  Linear deviations are
returned in um, rotary in arcsec, target positions in mm or deg.
"""
from __future__ import annotations

import csv
import math
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mtcal.errors import InputError
from mtcal.io import read_csv_table
from mtcal.iso230_2.evaluation import Runs, normalise_20c

LENGTH_MM = {"mm": 1.0, "um": 1e-3, "in": 25.4, "inch": 25.4}  # unit -> mm
ANGLE_DEG = {"deg": 1.0, "arcsec": 1.0 / 3600.0}  # unit -> deg
UNIT_WORDS = {"mm": "mm", "um": "um", "µm": "um", "μm": "um", "micron": "um", "microns": "um", "in": "in",
              "inch": "in", "inches": "in", "deg": "deg", "°": "deg", "degree": "deg", "degrees": "deg",
              "arcsec": "arcsec", '"': "arcsec", "″": "arcsec", "sec": "arcsec"}
DIRECTIONS = {  # a direction word of the exports (lower case) -> +1 up / -1 down
    **dict.fromkeys(("up", "+", "+1", "1", "fwd", "forward", "forwards", "pos", "positive", "inc", "increasing",
                     "↑", "vorwärts", "vorwaerts", "vor", "hin", "hinlauf", "aller"), 1),
    **dict.fromkeys(("down", "dn", "-", "-1", "bwd", "backward", "backwards", "back", "rev", "reverse", "neg",
                     "negative", "dec", "decreasing", "↓", "rückwärts", "rueckwaerts", "rück", "rueck",
                     "zurück", "rücklauf", "ruecklauf", "retour"), -1)}
SPAN_FRACTION = 0.1  # a positioning error beyond a tenth of the targets' span is no machine's: a unit or column mix-up
TEMPERATURE_C = (-10.0, 50.0)  # a machine tool under test; outside: a typo or a unit (K, F) mix-up
ROLES = {  # role -> the header words naming it (lower case, units removed)
    "target": ("target", "target position", "nominal", "nominal position", "commanded position", "position",
               "soll", "sollposition", "sollwert", "zielposition", "ziel"),
    "run": ("run", "run no", "run number", "lauf", "lauf nr", "messlauf", "durchlauf"),
    "direction": ("direction", "dir", "approach", "approach direction", "richtung", "anfahrrichtung"),
    "measured": ("measured", "reading", "laser reading", "laser", "actual", "actual position", "measured position",
                 "ist", "istposition", "istwert", "messwert"),
    "deviation": ("deviation", "error", "positional deviation", "position error", "positioning error",
                  "abweichung", "fehler", "positionsabweichung"),
    "air_temperature_c": ("air temperature", "air temp", "lufttemperatur"),
    "material_temperature_c": ("material temperature", "material temp", "materialtemperatur"),
}
RUN_WORDS = ("run", "lauf", "messlauf", "durchlauf")
VALUE_WORDS = {w: role for role in ("measured", "deviation") for w in ROLES[role]}
METADATA = {  # metadata key (lower case) -> field
    "machine": "machine", "maschine": "machine", "axis": "axis", "achse": "axis", "date": "date", "datum": "date",
    "units": "units", "unit": "units", "einheit": "units", "einheiten": "units", "linear units": "units",
    "target units": "target", "target unit": "target", "error units": "deviation", "error unit": "deviation",
    "deviation units": "deviation", "reading units": "measured",
    "air temperature": "air", "air temp": "air", "lufttemperatur": "air",
    "material temperature": "material", "material temp": "material", "materialtemperatur": "material"}
NEEDS = ("an interferometer export needs a target column (e.g. 'Target (mm)') and either a column per run and "
         "direction ('Run 1 Fwd (µm)', 'Run 1 Rev (µm)', ...) or a row per reading with run, direction and the "
         "laser reading or error ('Run,Target (mm),Direction,Error (µm)'); name other headers with "
         "`columns` (--columns target_mm=Pos,run=Lauf,direction=Richtung,deviation_um=Abw)")
_UNIT_TAIL = re.compile(r"^(.*?)[\s_]*(?:[(\[]\s*([^)\]]*?)\s*[)\]]|_([a-zµμ°\"″]+))\s*$")
_TEMP_UNIT = {"c", "°c", "degc", "deg c", "celsius"}


def _norm(text: str) -> str:
    return re.sub(r"[\s_.:#]+", " ", text.strip().lower()).strip()


def split_unit(raw: str) -> tuple[str, str | None]:
    """(name, unit) of a header: ``Target (mm)``, ``Error [µm]``, ``target_mm``, ``Run 1 Fwd µm``; the unit is
    None when the header gives none, ``"C"`` for a temperature in degC, else a key of LENGTH_MM / ANGLE_DEG."""
    text = raw.strip()
    m = _UNIT_TAIL.match(text.lower())
    if m:
        unit = (m.group(2) if m.group(2) is not None else m.group(3)).strip()
        if unit in UNIT_WORDS:
            return _norm(m.group(1)), UNIT_WORDS[unit]
        if unit in _TEMP_UNIT:
            return _norm(m.group(1)), "C"
    words = _norm(text).split(" ")
    if len(words) > 1 and words[-1] in UNIT_WORDS:
        return " ".join(words[:-1]), UNIT_WORDS[words[-1]]
    return _norm(text), None


@dataclass
class Column:
    """A column of the table: its index, header text, role, unit, and (wide layout) run and direction."""

    index: int
    header: str
    role: str
    unit: str | None = None
    run: int | None = None
    direction: int | None = None
    word: str = ""  # the direction word of a wide layout's run column


@dataclass
class Layout:
    """The table's columns as read from its header (or ``columns``)."""

    kind: str  # "long" | "wide"
    columns: dict[str, Column] = field(default_factory=dict)  # long: role -> column; wide: "target", temps
    runs: list[Column] = field(default_factory=list)  # wide: one per run and direction
    value: str | None = None  # "measured" | "deviation": what the deviations are taken from
    check: str | None = None  # long: "deviation" when the error column is there beside the reading (cross-checked)
    inferred: bool = False  # wide: the value kind taken from the units (errors in a finer unit than the target)
    twice: list[tuple[str, int, int]] = field(default_factory=list)  # (role, first column, second column), 0-based


def _direction_word(w: str, directions: dict[str, int]) -> int | None:
    w = w.strip().lower()
    return directions.get(w, DIRECTIONS.get(w))


def _run_column(k: int, raw: str, directions: dict[str, int]) -> Column | None:
    """A wide layout's run column ("Run 1 Fwd (µm)", "Lauf 2 rückwärts Abweichung [µm]", "Fwd Run 3"), or None."""
    name, unit = split_unit(raw)
    words = name.replace("-", " - ").replace("+", " + ").split()
    role = None
    for w in list(words):
        if w in VALUE_WORDS:
            role = VALUE_WORDS[w]
            words.remove(w)
    run = d = None
    for i, w in enumerate(words):
        if w in RUN_WORDS and i + 1 < len(words) and words[i + 1].isdigit():
            run = int(words[i + 1])
            rest = words[:i] + words[i + 2:]
            break
        m = re.fullmatch(r"(?:run|lauf)(\d+)", w)
        if m:
            run, rest = int(m.group(1)), words[:i] + words[i + 1:]
            break
    if run is None or len(rest) != 1 or (d := _direction_word(rest[0], directions)) is None:
        return None
    word = next((w for w in re.split(r"[\s_]+", raw) if w.lower() == rest[0]), rest[0])
    return Column(k, raw.strip(), role or "", unit, run, d, word)


def _role(raw: str) -> tuple[str | None, str | None]:
    name, unit = split_unit(raw)
    for role, words in ROLES.items():
        if name in words or name == role:
            return role, unit
    return None, unit


def _layout(header: list[str], directions: dict[str, int], columns: dict[str, str] | None) -> Layout | None:
    """The layout the header says (with ``columns`` naming the rest), or None when it is not an interferometer
    table (no target column, or neither run columns nor run and direction columns)."""
    named = {}
    for key, text in (columns or {}).items():
        if key == "values":
            continue
        role, _, unit = key.partition("_") if key not in ROLES else (key, "", "")
        if key in ("air_temperature_c", "material_temperature_c"):
            role, unit = key, "C"
        hits = [k for k, h in enumerate(header) if h.strip().lower() == text.strip().lower()]
        if hits:
            named[hits[0]] = (role, UNIT_WORDS.get(unit, unit) or split_unit(header[hits[0]])[1])
    cols: dict[str, Column] = {}
    runs, twice = [], []
    for k, raw in enumerate(header):
        role, unit = named.get(k) or _role(raw)
        if role is None:
            rc = _run_column(k, raw, directions)
            if rc is not None:
                runs.append(rc)
            continue
        if role in cols:
            twice.append((role, cols[role].index, k))
        cols.setdefault(role, Column(k, raw.strip(), role, unit))
    if "target" not in cols:
        return None
    if runs:
        return Layout("wide", cols, runs, twice=twice)
    if "run" in cols and "direction" in cols:
        return Layout("long", cols, twice=twice)
    return None


def _unknown_columns(header: list[str], lay: Layout) -> list[str]:
    used = {c.index for c in lay.columns.values()} | {c.index for c in lay.runs}
    return [f"column {k + 1} {h.strip()!r}" for k, h in enumerate(header) if k not in used and h.strip()]


@dataclass
class Metadata:
    fields: dict[str, str] = field(default_factory=dict)  # machine, axis, date, units, ... -> value text
    air_c: float | None = None
    material_c: float | None = None
    units: dict[str, str] = field(default_factory=dict)  # "default" / "target" / "deviation" / "measured" -> unit
    other: list[str] = field(default_factory=list)


def _metadata(preamble: list[tuple[int, str]], path) -> Metadata:
    """The metadata block before the table: ``key: value`` lines (``=``, ``;``, tab, ``,`` also separate)."""
    md = Metadata()
    for line, text in preamble:
        m = re.match(r"^\s*([^:=;\t,]+?)\s*[:=;\t,]\s*(.*?)[\s;,]*$", text)
        if not m:
            md.other.append(text.strip())
            continue
        key, value = _norm(m.group(1)), m.group(2).strip().strip('"')
        what = METADATA.get(key)
        if what is None:
            md.other.append(f"{m.group(1).strip()}: {value}")
        elif what in ("air", "material"):
            setattr(md, f"{what}_c", _metadata_temperature(value, key, path, line))
        elif what in ("units", "target", "deviation", "measured"):
            unit = UNIT_WORDS.get(value.lower().strip("() []"))
            if unit is None:
                raise InputError(f"metadata {m.group(1).strip()!r}: {value!r} is not a unit of an interferometer "
                                 f"export ({', '.join(sorted(set(UNIT_WORDS.values())))})", path, line)
            md.units["default" if what == "units" else what] = unit
        else:
            md.fields[what] = value
    return md


def _metadata_temperature(value: str, key: str, path, line: int) -> float:
    m = re.fullmatch(r"([+-]?\d+(?:[.,]\d+)?)\s*(°\s*c|deg\s*c|c|°)?", value.strip().lower())
    if not m:
        raise InputError(f"metadata {key!r}: {value!r} is not a temperature in degC (a number, optionally °C)",
                         path, line)
    return _temperature(m.group(1).replace(",", "."), key, path, line)


_GROUPED = re.compile(r"^\s*[+-]?[1-9]\d{0,2}(?:\.\d{3})+(?:,\d*)?\s*$")  # 1.000 / 1.250,5: thousands separators
_COMMA = re.compile(r"^\s*[+-]?\d*,\d+(?:[eE][+-]?\d+)?\s*$")  # a decimal comma (mtcal.io reads it as a point)
_POINT = re.compile(r"^\s*[+-]?\d*\.\d+(?:[eE][+-]?\d+)?\s*$")
_COMMA_GROUPED = re.compile(r"^\s*[+-]?[1-9]\d{0,2}(?:,\d{3})+(?:\.\d*)?\s*$")  # 1,000.5


def _thousands(path, hline: int, data: list[tuple[int, list[str]]]) -> int:
    """A ``;``-separated export whose numbers use decimal commas writes thousands with a dot: such fields of
    ``data`` (as the file has them: mtcal.io has turned the decimal commas into points) are read as thousands
    (``1.000`` = 1000); a decimal point among decimal commas is refused naming its line.  The count read so."""
    from mtcal.io import csv_separator, read_text

    with warnings.catch_warnings():  # the encoding is said once, by the reader
        warnings.simplefilter("ignore")
        text = read_text(path, "ISO 230-2 readings").splitlines()
    if csv_separator(text[hline - 1]) != ";":
        return 0
    raw = {line: next(csv.reader([text[line - 1]], delimiter=";")) for line, _ in data}
    if not any(_COMMA.match(x) or (_GROUPED.match(x) and "," in x) for r in raw.values() for x in r):
        return 0
    n = 0
    for line, fields in data:
        for k, x in enumerate(raw[line][:len(fields)]):
            if _GROUPED.match(x):
                fields[k] = x.strip().replace(".", "").replace(",", ".")
                n += 1
            elif _POINT.match(x):
                raise InputError(f"{x.strip()!r} is written with a decimal point, the file's other numbers with "
                                 f"decimal commas (a dot there is a thousands separator): one convention per file",
                                 path, line)
    return n


def _number(text: str, col: str, path, line: int) -> float:
    try:
        v = float(text)
    except ValueError:
        grouped = " (thousands separators: write plain numbers, e.g. 1000.5)" if _COMMA_GROUPED.match(text) else ""
        raise InputError(f"column {col!r}: expected a number, got {text!r}{grouped}", path, line) from None
    if not math.isfinite(v):
        raise InputError(f"column {col!r}: {text!r} is not a finite number", path, line)
    return v


def _temperature(text: str, col: str, path, line: int) -> float:
    if not text.strip():
        return math.nan
    t = _number(text, col, path, line)
    lo, hi = TEMPERATURE_C
    if not lo <= t <= hi:
        raise InputError(f"column {col!r}: {t:g} degC is outside {lo:g}..{hi:g} degC (a typo, or kelvin / "
                         f"fahrenheit?)", path, line)
    return t


def _parse_columns(columns: str | dict | None) -> dict[str, str] | None:
    """``--columns ROLE=HEADER,...`` (or a dict) -> {role: header}; roles: ROLES' (target/measured/deviation with
    an optional unit suffix, target_mm), and ``values`` (measured | deviation: what a wide table's run columns hold)."""
    if columns is None or isinstance(columns, dict):
        return columns
    out = {}
    for part in columns.split(","):
        key, eq, text = part.partition("=")
        base = key.strip().lower().split("_")[0]
        if not eq or not text.strip() or not (base in ROLES or base in ("air", "material", "values")):
            raise InputError(f"`columns`: {part.strip()!r} is not ROLE=HEADER (roles: target, run, direction, "
                             f"measured, deviation, air_temperature_c, material_temperature_c, each with an optional "
                             f"unit suffix as target_mm; values=measured|deviation for a wide table)")
        out[key.strip().lower()] = text.strip()
    if out.get("values", "deviation") not in ("measured", "deviation"):
        raise InputError(f"`columns`: values={out['values']!r}: a wide table's run columns hold 'measured' (laser "
                         f"readings) or 'deviation' (errors)")
    return out


def _parse_directions(directions: str | dict | None) -> dict[str, int]:
    if directions is None or isinstance(directions, dict):
        return {k.lower(): v for k, v in (directions or {}).items()}
    out = {}
    for part in directions.split(","):
        word, eq, sense = part.partition("=")
        d = DIRECTIONS.get(sense.strip().lower()) if eq else None
        if d is None or not word.strip():
            raise InputError(f"`directions`: {part.strip()!r} is not WORD=up or WORD=down")
        out[word.strip().lower()] = d
    return out


def looks_like_readings(path: str | Path) -> bool:
    """Whether a file is an interferometer export rather than a tracker recording (whose header is its first line
    and names axis, x, y and z): every file that is not such a recording is read (or refused) as readings."""
    with warnings.catch_warnings():  # the separator and encoding are said once, by the reader that reads it
        warnings.simplefilter("ignore")
        rows = read_csv_table(path, "ISO 230-2 input")[1]
    names = {f.strip().lower() for f in rows[0][1]}
    return not {"axis", "x", "y", "z"} <= names


def read_readings(path: str | Path, unit: str | None = None, alpha: float | None = None,
                  columns: str | dict | None = None, directions: str | dict | None = None,
                  ) -> tuple[Runs, str, list, dict]:
    """(runs, kind "linear" | "rotary", notes, metadata) of an interferometer export (module docstring).

    Parameters
    ----------
    path : the export (CSV / text).
    unit : the unit of target / reading / error columns whose header and metadata give none (LENGTH_MM,
        ANGLE_DEG keys).
    alpha : expansion coefficient (1/K): normalise a linear axis to 20 C with the material temperature (a column,
        or the metadata's for readings without one).
    columns : ``ROLE=HEADER,...`` or {role: header}: the headers the layout does not recognise.
    directions : ``WORD=up,WORD=down,...`` or {word: +1/-1}: direction words beyond ``DIRECTIONS``.

    Returns
    -------
    runs : one deviation per reading (um linear, arcsec rotary), target positions in mm or deg.
    kind : "linear" or "rotary".
    notes : the layout and columns found (one line), metadata, units.
    metadata : {"machine", "axis", "date", "air_temperature_c", "material_temperature_c", ...} as read.
    """
    if unit is not None and unit not in LENGTH_MM and unit not in ANGLE_DEG:
        raise InputError(f"`unit` must be one of {', '.join([*LENGTH_MM, *ANGLE_DEG])}, got {unit!r}")
    cols, dirs = _parse_columns(columns), _parse_directions(directions)
    preamble, rows = read_csv_table(path, "ISO 230-2 readings", lambda f: _layout(f, dirs, cols) is not None)
    if not rows:
        line, text = preamble[0]
        named = [t for k, t in (cols or {}).items() if k != "values"]
        raise InputError(f"no interferometer table found (first line {text.strip()[:80]!r})"
                         + (f"; no line has every header `columns` names ({', '.join(map(repr, named))})" if named
                            else "") + f": {NEEDS}", path, line)
    (hline, header), data = rows[0], rows[1:]
    lay = _layout(header, dirs, cols)
    md = _metadata(preamble, path)
    for role, a, b in lay.twice:
        raise InputError(f"column {role!r} appears twice (columns {a + 1} and {b + 1})", path, hline)
    unknown = _unknown_columns(header, lay)
    if unknown:
        raise InputError(f"{', '.join(unknown)}: not a column of an interferometer export ({NEEDS})", path, hline)
    units = _units(lay, md, unit, cols, path, hline)
    kind = _kind(units, path, hline)
    if not data:
        raise InputError("no readings after the header", path, hline)
    grouped = _thousands(path, hline, data)
    out = (_read_wide if lay.kind == "wide" else _read_long)(lay, data, header, units, kind, dirs, path)
    _check_claims(out, lay, path, hline)
    if "material_temperature_c" not in lay.columns and md.material_c is not None:
        out["temp"] = [md.material_c] * len(out["temp"])
    runs, notes = _runs(out, kind, alpha, path)
    notes.insert(0, _said(path, lay, units, md, out["words"]))
    if grouped:
        notes.insert(1, f"{grouped} number(s) written with thousands separators among decimal commas read as such "
                        f"('1.000' = 1000, '1.250,5' = 1250.5)")
    if out["checked"]:
        notes.insert(1, f"the errors agree with the laser readings minus the targets at all {len(out['checked'])} "
                        f"readings (largest difference {max(out['checked']):.3g} "
                        f"{'um' if kind == 'linear' else 'arcsec'}, within the digits written)")
    meta = {**md.fields, "air_temperature_c": md.air_c, "material_temperature_c": md.material_c}
    return runs, kind, notes, {k: v for k, v in meta.items() if v is not None}


def _units(lay: Layout, md: Metadata, unit: str | None, cols: dict | None, path, line: int) -> dict[str, str]:
    """{"target": unit, "value": unit} and the wide table's value role: header, else metadata, else ``unit``."""
    if lay.kind == "long":
        values = [r for r in ("measured", "deviation") if r in lay.columns]
        if not values:
            raise InputError("give 'measured' (the position reached) or 'deviation' (reached - target) or both: "
                             "neither is present", path, line)
        lay.value, lay.check = values[0], (values[1] if len(values) == 2 else None)
        vunit = lay.columns[lay.value].unit
    else:
        said = {c.role for c in lay.runs if c.role}
        if len(said) > 1:
            raise InputError("the run columns say both errors and readings: one kind per table", path, line)
        lay.value = said.pop() if said else (cols or {}).get("values")
        vunits = {c.unit for c in lay.runs}
        if len(vunits) > 1:
            raise InputError(f"the run columns have different units ({', '.join(sorted(map(str, vunits)))})", path,
                             line)
        vunit = vunits.pop()
    tunit = lay.columns["target"].unit or md.units.get("target") or md.units.get("default") or unit
    vunit = vunit or md.units.get(lay.value or "deviation") or md.units.get("default") or unit
    said = [("target", tunit, lay.columns["target"]),
            (lay.value or "run", vunit, lay.columns.get(lay.value) or lay.runs[0])]
    if lay.check:
        col = lay.columns[lay.check]
        said.append((lay.check, col.unit or md.units.get(lay.check) or md.units.get("default") or unit, col))
    for what, u, col in said:
        if u is None or u == "C":
            raise InputError(f"the unit of column {col.header!r} is not declared ({what}): write it in the header "
                             f"('{col.header} (mm)', '_mm', '[µm]'), in the metadata ('Units: mm') or give `unit`",
                             path, line)
    if lay.value is None:
        finer = (tunit in LENGTH_MM and vunit == "um" and tunit != "um") or (tunit == "deg" and vunit == "arcsec")
        if not finer:
            raise InputError(f"the run columns ({lay.runs[0].header!r} ...) do not say whether they hold errors or "
                             f"laser readings: write 'error' or 'reading' in their headers, or give --columns "
                             f"values=deviation (errors) or --columns values=measured (readings)", path, line)
        lay.value, lay.inferred = "deviation", True
    return {"target": tunit, "value": vunit, **({"check": said[2][1]} if lay.check else {})}


def _check_claims(out: dict, lay: Layout, path, hline: int) -> None:
    """The header's claims against the values: a deviation beyond SPAN_FRACTION of the targets' span (a reading in
    another unit than its header says, an error column holding the positions reached, run columns taken as errors
    from their unit that hold readings), or a column whose every value is its target (copied, not measured), is
    refused at the header's line naming the column and the line of its largest deviation."""
    dev = np.array(out["dev"]) / (1e3 if out["kind"] == "linear" else 3600.0)  # mm or deg
    target, unit = np.array(out["target"]), ("mm" if out["kind"] == "linear" else "deg")
    span = float(np.ptp(target))
    k = int(np.argmax(np.abs(dev)))
    col, line = out["col"][k], out["line"][k]
    if not np.any(dev) and len(dev) > 1:
        raise InputError(f"column {col!r}: no deviation at any of the {len(dev)} readings (every one its target "
                         f"exactly): the target column copied, or nominal values, not a measurement", path, hline)
    if span <= 0 or abs(dev[k]) <= SPAN_FRACTION * span:
        return
    said = (f"column {col!r}: a deviation of {dev[k]:.6g} {unit} at target {target[k]:g} {unit} (line {line}), "
            f"{100 * abs(dev[k]) / span:.0f} % of the targets' span ({span:g} {unit}; a positioning error is "
            f"below {100 * SPAN_FRACTION:g} %)")
    if lay.inferred:
        why = ("the run columns are taken as errors, their unit being finer than the target's: laser readings "
               "rather than errors? Say which with --columns values=measured or --columns values=deviation")
    elif lay.value == "deviation":
        why = ("an error column holding the positions reached? (write 'reading' in its header or give --columns "
               "values=measured), or errors in another unit than its header says")
    else:
        ratio = float(np.dot(target, target + dev) / np.dot(target, target)) if np.any(target) else math.nan
        why = (f"the readings are {ratio:.6g} x their targets: positions in another unit than the header says?"
               if np.isfinite(ratio) and abs(ratio - 1) > 0.01 else
               "readings in another unit than the header says, or of another axis?")
    raise InputError(f"{said}: {why}", path, hline)


def _kind(units: dict[str, str], path, line: int) -> str:
    kinds = {"linear" if u in LENGTH_MM else "rotary" for u in units.values()}
    if len(kinds) > 1:
        raise InputError(f"columns mix length and angle units ({units}): one axis is linear or rotary", path, line)
    return kinds.pop()


def _empty(kind: str) -> dict:
    return {k: [] for k in ("target", "run", "direction", "dev", "temp", "line", "col")} | {"words": {}, "kind": kind,
                                                                                          "checked": []}


def _add(out: dict, target: float, run: int, d: int, value: float, value_kind: str, temp: float, line: int,
         seen: dict, shown: str, path, col: str) -> None:
    """One reading: deviation x = P - P_i (um / arcsec) from a reading or an error (both already in mm / deg)."""
    key = (round(target, 9), run, d)
    if key in seen:
        raise InputError(f"run {run} at target {shown} ({'up' if d > 0 else 'down'}) read twice (first at line "
                         f"{seen[key]})", path, line)
    seen[key] = line
    dev = value - target if value_kind == "measured" else value
    out["target"].append(target), out["run"].append(run), out["direction"].append(d)
    out["dev"].append(dev * (1e3 if out["kind"] == "linear" else 3600.0)), out["line"].append(line)
    out["temp"].append(temp), out["col"].append(col)


def _scale(kind: str) -> dict[str, float]:
    return LENGTH_MM if kind == "linear" else ANGLE_DEG


def _read_long(lay: Layout, data, header, units, kind, dirs, path) -> dict:
    out, seen, sc = _empty(kind), {}, _scale(kind)
    c = {r: col.index for r, col in lay.columns.items()}
    for line, f in data:
        if len(f) != len(header):
            raise InputError(f"{len(f)} fields, the header has {len(header)}", path, line)
        target = _number(f[c["target"]], "target", path, line) * sc[units["target"]]
        run = _number(f[c["run"]], "run", path, line)
        if run != int(run) or run < 0:
            raise InputError(f"column 'run': a run number is a whole number, got {f[c['run']]!r}", path, line)
        word = f[c["direction"]].strip()
        d = _direction_word(word, dirs)
        if d is None:
            raise InputError(f"column 'direction': {word!r} is not up/down (+1/-1, Fwd/Rev, forward/reverse, "
                             f"vorwärts/rückwärts, ...; `directions` names others)", path, line)
        out["words"].setdefault(word, d)
        value = _number(f[c[lay.value]], lay.value, path, line) * sc[units["value"]]
        if lay.check:
            _cross_check(out, lay, f, c, units, sc, target, value, path, line)
        temps = {r: _temperature(f[c[r]], r, path, line) for r in ("air_temperature_c", "material_temperature_c")
                 if r in c}
        _add(out, target, int(run), d, value, lay.value, temps.get("material_temperature_c", math.nan), line, seen,
             f[c["target"]].strip(), path, lay.columns[lay.value].header)
    return out


def _digit(text: str) -> float:
    """The unit of the last digit written of a number (``-49.23`` -> 0.01, ``1.5e-3`` -> 1e-4, ``12`` -> 1)."""
    mant, _, exp = text.strip().lower().partition("e")
    decimals = len(mant.partition(".")[2])
    return 10.0 ** (int(exp or 0) - decimals)


def _cross_check(out: dict, lay: Layout, f: list[str], c: dict, units: dict, sc: dict, target: float, value: float,
                 path, line: int) -> None:
    """A row with both the laser reading P and its error e: the deviation is P - target (x_ij, from the reading);
    e must agree with it within the rounding of the digits written (half a last digit of reading and error
    both; the target is commanded, exact), else the row is refused naming both columns (an error written as
    target - reading said so)."""
    cm, ce = lay.columns[lay.value], lay.columns[lay.check]
    err = _number(f[c[lay.check]], lay.check, path, line) * sc[units["check"]]
    dev = value - target
    tol = 0.5 * sum(_digit(f[c[r]]) * sc[units[k]] for r, k in ((lay.value, "value"), (lay.check, "check"))) * (
        1 + 1e-9) + 1e-12  # the target is the commanded position: exact
    scale, unit = (1e3, "um") if out["kind"] == "linear" else (3600.0, "arcsec")
    out["checked"].append(abs(err - dev) * scale)
    if abs(err - dev) > tol:
        sign = " (the error written as target - reading?)" if abs(err + dev) <= tol else ""
        raise InputError(f"column {ce.header!r} says {err * scale:.6g} {unit}, the laser reading {cm.header!r} minus "
                         f"the target {dev * scale:.6g} {unit}: they disagree by {abs(err - dev) * scale:.3g} {unit}, "
                         f"beyond the rounding of the digits written ({tol * scale:.3g} {unit}){sign}", path, line)


def _read_wide(lay: Layout, data, header, units, kind, dirs, path) -> dict:
    out, seen, sc = _empty(kind), {}, _scale(kind)
    tcol = lay.columns["target"].index
    mcol = lay.columns.get("material_temperature_c")
    for col in lay.runs:
        out["words"].setdefault(col.word, col.direction)
    for line, f in data:
        if len(f) != len(header):
            raise InputError(f"{len(f)} fields, the header has {len(header)}", path, line)
        target = _number(f[tcol], lay.columns["target"].header, path, line) * sc[units["target"]]
        temp = _temperature(f[mcol.index], mcol.header, path, line) if mcol else math.nan
        for col in lay.runs:
            if not f[col.index].strip():
                continue  # a missing reading is missing
            value = _number(f[col.index], col.header, path, line) * sc[units["value"]]
            _add(out, target, col.run, col.direction, value, lay.value, temp, line, seen, f[tcol].strip(), path,
                 col.header)
    if not out["target"]:
        raise InputError("no readings in the run columns", path, data[0][0])
    return out


def _said(path, lay: Layout, units: dict, md: Metadata, words: dict[str, int]) -> str:
    """The one line naming the layout and the columns found."""
    kind = {"measured": "laser readings", "deviation": "errors"}[lay.value]
    senses = ", ".join(f"{w} = {'up' if d > 0 else 'down'}" for w, d in words.items())
    if lay.kind == "wide":
        runs = sorted({c.run for c in lay.runs})
        cols = (f"{len(lay.runs)} run columns {lay.runs[0].header!r} ... {lay.runs[-1].header!r} (runs "
                f"{runs[0]}-{runs[-1]}; {senses}) as {kind} in {units['value']}"
                + (" (the headers do not say: errors, their unit being finer than the target's)" if lay.inferred
                   else ""))
        text = f"read as a wide export (a column per run and direction): target {lay.columns['target'].header!r} " \
               f"in {units['target']}; {cols}"
    else:
        c = lay.columns
        text = (f"read as a long export (a row per reading): target {c['target'].header!r} in {units['target']}, "
                f"run {c['run'].header!r}, direction {c['direction'].header!r} ({senses}), {kind} "
                f"{c[lay.value].header!r} in {units['value']}")
        if lay.check:
            text += (f", and the errors {c[lay.check].header!r} in {units['check']} checked against them (the "
                     f"deviations are the readings')")
    extra = [f"{r.split('_')[0]} temperature {c.header!r}" for r, c in lay.columns.items() if r.endswith("_c")]
    meta = [f"{k} {v}" for k, v in md.fields.items()]
    meta += [f"{w} {t:g} °C" for w, t in (("air", md.air_c), ("material", md.material_c)) if t is not None]
    meta += md.other
    return (f"{path}: {text}" + (f"; {', '.join(extra)}" if extra else "")
            + (f"; metadata: {', '.join(meta)}" if meta else ""))


def _runs(out: dict, kind: str, alpha: float | None, path) -> tuple[Runs, list]:
    pos = np.array(out["target"])
    p0 = float(pos[np.argmin(np.abs(pos))])
    dev = np.array(out["dev"])
    notes = ["deviations x_ij = P_ij - P_i from the sensor's one datum"]
    if alpha is not None:
        temp = np.array(out["temp"])
        if kind != "linear":
            raise InputError("temperature normalisation applies to a linear axis", path)
        if np.isnan(temp).any():
            raise InputError("no material temperature (a material_temperature_c column, or 'Material temperature: "
                             "T °C' in the metadata): temperature normalisation needs it on every reading", path,
                             out["line"][int(np.flatnonzero(np.isnan(temp))[0])])
        dev = normalise_20c(dev, temp, pos, p0, alpha)
    runs = Runs(pos, np.array(out["direction"]), np.array(out["run"]), dev, [[ln] for ln in out["line"]],
                "um" if kind == "linear" else "arcsec", np.full(len(pos), p0))
    return runs, notes
