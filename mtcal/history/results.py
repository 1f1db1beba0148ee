"""mtcal's result files as the history keeps them: the kind read from the file's own keys, the machine spec where
the file names one, the quantities with their uncertainty (model and uncertainty results), the instrument, the
environment and the hashes of the file, its recording and its model.

Kinds (``KINDS``): ``model`` (an error model, `mtcal identify -o MODEL.json`), ``uncertainty`` (`mtcal uncertainty
--json` / ``-o``), ``iso230-2`` (`mtcal iso230-2 --json`), ``check`` (`mtcal check evaluate --json`), ``verify``
(`mtcal verify --json`) and ``diagnose`` (`mtcal diagnose --json`).  Anything else is refused in one line.

Units inside: quantities in mm and rad as the files hold them (``unit`` "mm" or "rad"); ISO 230-2 parameters in the
file's own unit.
"""
from __future__ import annotations

import csv
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mtcal import _tails
from mtcal.errors import InputError, InputWarning
from mtcal.history.schema import checked_document
from mtcal.io import dumps, file_sha256, read_json

KINDS = ("model", "uncertainty", "iso230-2", "check", "verify", "diagnose")
Z95 = 1.959963984540054  # the normal 97.5 % quantile: k of an interval with infinite degrees of freedom


@dataclass
class Quantity:
    """One value of a result: an error (ISO 230-1 name) at a position of its axis (mm or deg; None for a
    constant), its value and 95 % half-width ``u95`` (``unit``), the degrees of freedom of that interval (None:
    infinite, k = 1.96)."""

    name: str
    value: float
    unit: str
    axis: str | None = None
    position: float | None = None
    u95: float | None = None
    dof: float | None = None


@dataclass
class Result:
    """A result file read for the history (module docstring)."""

    kind: str
    source: str
    document: dict
    spec: str | None
    file_sha256: str
    recording_sha256: str | None = None
    model_sha256: str | None = None
    instrument: str | None = None
    environment: dict = field(default_factory=dict)
    quantities: list[Quantity] = field(default_factory=list)


def kind_of(doc: Any, source: str) -> str:
    """The kind of an mtcal result (module docstring) from its keys; anything else is an InputError."""
    if not isinstance(doc, dict):
        raise InputError(f"not an mtcal result: the file holds a JSON {type(doc).__name__}, not an object", source)
    keys = set(doc)
    if {"trials", "seed", "errors", "constants", "volumetric"} <= keys:
        return "uncertainty"
    if ({"machine", "units"} & keys) and ({"functions", "constants"} & keys):
        return "model"
    if doc.get("standard") == "ISO 230-2:2014" and "axes" in keys:
        return "iso230-2"
    if {"kind", "measured", "predicted", "agrees", "worst_z"} <= keys:
        return "check"
    if {"passed", "errors", "not_covered"} <= keys:
        return "verify"
    if {"base_sigma", "effects", "noise_model"} <= keys:
        return "diagnose"
    if {"axes", "squareness"} <= keys:
        raise InputError("this is the --json answer of `mtcal identify`; add the model it wrote "
                         "(`mtcal identify REC.csv -o MODEL.json`)", source)
    raise InputError("not an mtcal result (expected an error model or the --json answer of mtcal uncertainty, "
                     "iso230-2, check evaluate, verify or diagnose)", source)


def read_result(path: str | Path) -> Result:
    """Read a result file (module docstring): its kind, spec, quantities and provenance, every field the history's
    readers read checked (mtcal.history.schema) and the machine spec it names known; bad files are InputError."""
    p = Path(path)
    doc = read_json(p, "result")
    kind = kind_of(doc, str(p))
    res = Result(kind, str(p), checked_document(kind, doc, str(p)), None, file_sha256(p))
    _READERS[kind](res, p)
    if res.spec is not None:
        check_spec(res.spec, str(p))
    return res


def check_spec(spec: Any, source: str) -> str:
    """A machine spec mtcal knows (derive/machines); anything else is an InputError naming the known ones."""
    from mtcal.kinematics.machine import available_machines
    known = available_machines()
    if spec not in known:
        raise InputError(f"unknown machine spec {str(spec)[:40]!r} (mtcal knows {', '.join(known)})", source)
    return spec


def _find(name: Any, beside: Path) -> Path | None:
    """A file a result names (a recording, a model), as given or beside the result; None when absent."""
    if not isinstance(name, str) or not name or name.startswith("<"):
        return None
    for c in (Path(name), beside.parent / name, beside.parent / Path(name).name):
        if c.is_file():
            return c
    return None


def _recording(res: Result, name: Any, p: Path) -> None:
    """The recording's hash and its mean temperatures (``temperature_c`` column) when the file can be found."""
    rec = _find(name, p)
    if rec is None:
        return
    res.recording_sha256 = file_sha256(rec)
    temps, bad = _temperatures(rec)
    if bad:
        line, text = bad[0]
        warnings.warn(f"{rec}:{line}: temperature_c {text!r} is not a number ({len(bad)} such reading(s)): the "
                      f"environment keeps the {len(temps)} that are", InputWarning, stacklevel=2)
    if temps:
        res.environment["temperature_c"] = {"mean": sum(temps) / len(temps), "min": min(temps), "max": max(temps)}
        if bad:
            res.environment["temperature_c"].update(readings=len(temps), not_numbers=len(bad))


def _temperatures(rec: Path) -> tuple[list[float], list[tuple[int, str]]]:
    """A recording's ``temperature_c`` readings (degC) that are finite numbers, and (line, text) of those that are
    not (empty cells are no reading)."""
    with rec.open(newline="", encoding="utf-8", errors="replace") as fh:
        lines = [(i, line) for i, line in enumerate(fh, 1) if not line.lstrip().startswith("#")]
    reader = csv.DictReader(line for _, line in lines)
    temps, bad = [], []
    for row in reader:
        text = (row.get("temperature_c") or "").strip()
        if not text:
            continue
        try:
            v = float(text)
        except ValueError:
            v = math.nan
        if math.isfinite(v):
            temps.append(v)
        else:
            bad.append((lines[reader.line_num - 1][0], text))
    return temps, bad


def _number(v: Any) -> float | None:
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) else None


def _dof_of(u95: float, std_mean: float | None, n: Any) -> float | None:
    """Degrees of freedom of an interval: infinite (None) when u95 = 1.96 std_mean (the joint fit's covariance),
    else those of the rounds' Type A, n - 1 (Student's t; docs/design.md, identify)."""
    if std_mean is None or std_mean <= 0 or abs(u95 / std_mean - Z95) < 1e-3:
        return None
    return float(n) - 1 if isinstance(n, (int, float)) and n > 1 else None


def _model(res: Result, p: Path) -> None:
    from mtcal.model.errormodel import model_from_dict
    model = model_from_dict(res.document, str(p))  # the model's own checks (names, units, machine)
    res.spec, res.model_sha256 = model.machine, res.file_sha256
    meta = model.meta
    law = meta.get("noise_law") or {}
    res.instrument = law.get("instrument") and f"laser tracker ({law['instrument']})"
    _recording(res, meta.get("identified_from"), p)
    for n, f in sorted(model.functions.items()):
        u95, sm, nn = f.extra.get("u95"), f.extra.get("std_mean"), f.extra.get("n")
        for i, (x, v) in enumerate(zip(f.positions.tolist(), f.values.tolist())):
            u = _number(u95[i]) if isinstance(u95, list) and i < len(u95) else None
            s = _number(sm[i]) if isinstance(sm, list) and i < len(sm) else None
            dof = _dof_of(u, s, nn[i] if isinstance(nn, list) and i < len(nn) else None) if u else None
            res.quantities.append(Quantity(n, float(v), _unit(n), f.axis, float(x), u, dof))
    sigma, type_a = meta.get("squareness_sigma") or {}, meta.get("squareness_type_a") or {}
    for n, v in sorted(model.constants.items()):
        u, dof = None, None
        if _number(sigma.get(n)) is not None:  # the joint fit's standard deviation
            u = Z95 * sigma[n]
        elif isinstance(type_a.get(n), dict) and _number(type_a[n].get("std_mean")) is not None:
            k = len(type_a[n].get("rounds", []))
            dof = float(k - 1) if k > 1 else None
            u = (_tails.t_ppf(0.975, dof) if dof else Z95) * type_a[n]["std_mean"]
        res.quantities.append(Quantity(n, float(v), _unit(n), None, None, u, dof))


def _unit(name: str) -> str:
    """"rad" for an angular error (ISO 230-1: E_A.., E_B.., E_C..), "mm" for a translational one."""
    return "rad" if len(name) > 2 and name[2] in "ABC" else "mm"


def _uncertainty(res: Result, p: Path) -> None:
    d = res.document
    inputs = d.get("inputs") or {}
    res.instrument = "laser tracker (Monte Carlo of its law)"
    _recording(res, inputs.get("recording"), p)
    for n, e in sorted((d.get("errors") or {}).items()):
        for x, m, lo, hi in zip(e.get("positions", []), e.get("mean", []), e.get("lo95", []), e.get("hi95", [])):
            if None not in (_number(x), _number(m), _number(lo), _number(hi)):
                res.quantities.append(Quantity(n, m, _unit(n), e.get("axis"), x, (hi - lo) / 2))
    for n, c in sorted((d.get("constants") or {}).items()):
        if None not in (_number(c.get("mean")), _number(c.get("lo95")), _number(c.get("hi95"))):
            res.quantities.append(Quantity(n, c["mean"], _unit(n), None, None, (c["hi95"] - c["lo95"]) / 2))
    vol = d.get("volumetric") or {}
    if _number(vol.get("u95_max_mm")) is not None:
        res.quantities.append(Quantity("tool_tip_u95_max", vol["u95_max_mm"], "mm"))


def _iso230_2(res: Result, p: Path) -> None:
    d = res.document
    res.instrument = "ISO 230-2 readings"
    if d.get("temperature_normalisation"):
        res.environment["temperature_normalisation"] = d["temperature_normalisation"]
    _recording(res, d.get("file"), p)
    for ax, ev in sorted((d.get("axes") or {}).items()):
        for k, v in (ev.get("parameters") or {}).items():
            if _number(v) is not None:
                res.quantities.append(Quantity(k, v, ev.get("unit", ""), ax))


def _check(res: Result, p: Path) -> None:
    d = res.document
    res.instrument = {"circular": "ballbar (ISO 230-4 circular test)", "rtest": "R-test (ISO 10791-6)"}[d["kind"]]
    for k, v in (d.get("measured") or {}).items():
        if _number(v) is not None:
            res.quantities.append(Quantity(k, v, "mm" if k.endswith("_mm") else ""))


def _verify(res: Result, p: Path) -> None:
    d = res.document
    _recording(res, d.get("source"), p)
    res.instrument = "check test" if d.get("check") else "laser tracker"


def _diagnose(res: Result, p: Path) -> None:
    d = res.document
    res.spec = d.get("machine") if isinstance(d.get("machine"), str) else None
    law = (d.get("noise_model") or {}).get("law") or {}
    res.instrument = law.get("instrument") and f"laser tracker ({law['instrument']})"
    _recording(res, d.get("recording"), p)


_READERS = {"model": _model, "uncertainty": _uncertainty, "iso230-2": _iso230_2, "check": _check,
            "verify": _verify, "diagnose": _diagnose}


def document_text(doc: dict) -> str:
    """The stored text of a result (JSON; NaN as null, as mtcal writes it)."""
    return dumps(doc)
