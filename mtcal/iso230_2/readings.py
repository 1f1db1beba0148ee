"""An ISO 230-2 test as a laser interferometer (or any 1-D reference sensor) records it: one row per reading.

CSV (``,`` ``;`` or tab separated, detected and said; ``#`` comment lines; UTF-8, Windows-1252 or UTF-16):

    target_mm,run,direction,measured_mm[,air_temperature_c,material_temperature_c]

* ``target`` and ``measured`` (the position reached) or ``deviation`` (reached minus target), each with its unit
  as a suffix (``_mm``, ``_um``, ``_in`` for a linear axis; ``_deg``, ``_arcsec`` for a rotary one) or, without a
  suffix, the unit given by ``unit`` (``--unit``): units are declared, never assumed.
* ``run``: the run number j (a whole number); ``direction``: up / down (also +1 / -1, +, -, fwd / bwd).
* ``air_temperature_c``, ``material_temperature_c``: optional, in degC, range-checked (``TEMPERATURE_C``); the
  material temperature normalises a linear axis to 20 C when an expansion coefficient is given.

Every deviation is x_ij = P_ij - P_i (ISO 230-2: one datum for all runs, the sensor's zero); a reading that is
not in the file is missing (the target's statistics use the runs that have it).  Linear deviations are returned
in um, rotary in arcsec, target positions in mm or deg.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from mtcal.errors import InputError
from mtcal.io import read_csv_rows
from mtcal.iso230_2.evaluation import Runs, normalise_20c

LENGTH_MM = {"mm": 1.0, "um": 1e-3, "in": 25.4, "inch": 25.4}  # unit -> mm
ANGLE_DEG = {"deg": 1.0, "arcsec": 1.0 / 3600.0}  # unit -> deg
DIRECTIONS = {"up": 1, "+": 1, "+1": 1, "1": 1, "fwd": 1, "forward": 1, "pos": 1,
              "down": -1, "dn": -1, "-": -1, "-1": -1, "bwd": -1, "backward": -1, "neg": -1}
TEMPERATURE_C = (-10.0, 50.0)  # a machine tool under test; outside: a typo or a unit (K, F) mix-up
BASES = ("target", "run", "direction", "measured", "deviation", "air_temperature_c", "material_temperature_c")
_NAME = re.compile(r"^(target|measured|deviation)(?:_(mm|um|in|inch|deg|arcsec))?$")


def is_readings_header(fields: list[str]) -> bool:
    """Whether a CSV header is this layout (a ``target`` column) rather than a tracker recording."""
    return any(_NAME.match(f.strip().lower()) and f.strip().lower().startswith("target") for f in fields)


def _columns(header: list[str], path, line: int, unit: str | None) -> tuple[dict[str, int], dict[str, str]]:
    """{base: column index}, {base: unit} of the header; duplicates, unknown and ambiguous columns refused."""
    cols, units = {}, {}
    for k, raw in enumerate(header):
        name = raw.strip().lower()
        m = _NAME.match(name)
        base = m.group(1) if m else name
        if base not in BASES:
            raise InputError(f"column {k + 1} {raw.strip()!r} is not a column of the ISO 230-2 readings layout "
                             f"({', '.join(BASES)}; target/measured/deviation with a unit suffix)", path, line)
        if base in cols:
            raise InputError(f"column {base!r} appears twice (columns {cols[base] + 1} and {k + 1})", path, line)
        cols[base] = k
        if m:
            units[base] = m.group(2) or unit
    for need in ("target", "run", "direction"):
        if need not in cols:
            raise InputError(f"missing column {need!r} (header: {', '.join(h.strip() for h in header)})", path, line)
    if ("measured" in cols) == ("deviation" in cols):
        raise InputError("give one of 'measured' (the position reached) and 'deviation' (reached - target): "
                         + ("both are present, which is ambiguous" if "measured" in cols else "neither is present"),
                         path, line)
    for base, u in units.items():
        if u is None:
            raise InputError(f"the unit of column {base!r} is not declared: name it {base}_mm, {base}_um, "
                             f"{base}_in, {base}_deg or {base}_arcsec, or give `unit`", path, line)
    return cols, units


def _kind(units: dict[str, str], path, line: int) -> str:
    kinds = {"linear" if u in LENGTH_MM else "rotary" for u in units.values()}
    if len(kinds) > 1:
        raise InputError(f"columns mix length and angle units ({units}): one axis is linear or rotary", path, line)
    return kinds.pop()


def _number(text: str, col: str, path, line: int) -> float:
    try:
        v = float(text)
    except ValueError:
        raise InputError(f"column {col!r}: expected a number, got {text!r}", path, line) from None
    if not math.isfinite(v):
        raise InputError(f"column {col!r}: {text!r} is not a finite number", path, line)
    return v


def read_readings(path: str | Path, unit: str | None = None, alpha: float | None = None) -> tuple[Runs, str, list]:
    """(runs, kind "linear" | "rotary", notes) of a readings file (module docstring).  ``unit`` declares the
    unsuffixed target / measured / deviation columns; ``alpha`` (1/K) normalises a linear axis to 20 C with the
    material temperature (needed on every row)."""
    if unit is not None and unit not in LENGTH_MM and unit not in ANGLE_DEG:
        raise InputError(f"`unit` must be one of {', '.join([*LENGTH_MM, *ANGLE_DEG])}, got {unit!r}")
    rows = read_csv_rows(path, "ISO 230-2 readings")
    (hline, header), data = rows[0], rows[1:]
    cols, units = _columns(header, path, hline, unit)
    kind = _kind(units, path, hline)
    if not data:
        raise InputError("no readings after the header", path, hline)
    scale = LENGTH_MM if kind == "linear" else ANGLE_DEG
    out = {k: [] for k in ("target", "run", "direction", "dev", "temp", "line")}
    seen: dict[tuple, int] = {}
    for line, f in data:
        if len(f) != len(header):
            raise InputError(f"{len(f)} fields, the header has {len(header)}", path, line)
        target = _number(f[cols["target"]], "target", path, line) * scale[units["target"]]
        run = _number(f[cols["run"]], "run", path, line)
        if run != int(run) or run < 0:
            raise InputError(f"column 'run': a run number is a whole number, got {f[cols['run']]!r}", path, line)
        d = DIRECTIONS.get(f[cols["direction"]].strip().lower())
        if d is None:
            raise InputError(f"column 'direction': {f[cols['direction']]!r} is not up/down (+1/-1)", path, line)
        key = (round(target, 9), int(run), d)
        if key in seen:
            raise InputError(f"run {int(run)} at target {f[cols['target']].strip()} ({'up' if d > 0 else 'down'}) "
                             f"read twice (first at line {seen[key]})", path, line)
        seen[key] = line
        if "measured" in cols:
            dev = _number(f[cols["measured"]], "measured", path, line) * scale[units["measured"]] - target
        else:
            dev = _number(f[cols["deviation"]], "deviation", path, line) * scale[units["deviation"]]
        temps = {c: _temperature(f[cols[c]], c, path, line) for c in ("air_temperature_c", "material_temperature_c")
                 if c in cols}
        out["target"].append(target), out["run"].append(int(run)), out["direction"].append(d)
        out["dev"].append(dev * (1e3 if kind == "linear" else 3600.0)), out["line"].append(line)
        out["temp"].append(temps.get("material_temperature_c", math.nan))
    return _runs(out, kind, alpha, path, units)


def _temperature(text: str, col: str, path, line: int) -> float:
    if not text.strip():
        return math.nan
    t = _number(text, col, path, line)
    lo, hi = TEMPERATURE_C
    if not lo <= t <= hi:
        raise InputError(f"column {col!r}: {t:g} degC is outside {lo:g}..{hi:g} degC (a typo, or kelvin / "
                         f"fahrenheit?)", path, line)
    return t


def _runs(out: dict, kind: str, alpha: float | None, path, units: dict) -> tuple[Runs, str, list]:
    pos = np.array(out["target"])
    p0 = float(pos[np.argmin(np.abs(pos))])
    dev = np.array(out["dev"])
    notes = [f"{path}: read as {kind} axis readings; units {', '.join(f'{k} {u}' for k, u in units.items())}; "
             f"deviations x_ij = P_ij - P_i from the sensor's one datum"]
    if alpha is not None:
        temp = np.array(out["temp"])
        if kind != "linear":
            raise InputError("temperature normalisation applies to a linear axis", path)
        if np.isnan(temp).any():
            raise InputError("no material_temperature_c: temperature normalisation needs it on every reading", path,
                             out["line"][int(np.flatnonzero(np.isnan(temp))[0])])
        dev = normalise_20c(dev, temp, pos, p0, alpha)
    runs = Runs(pos, np.array(out["direction"]), np.array(out["run"]), dev, [[ln] for ln in out["line"]],
                "um" if kind == "linear" else "arcsec", np.full(len(pos), p0))
    return runs, kind, notes
