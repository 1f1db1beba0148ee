"""What the history checks in a result before it is added, and in a stored result before it is read: every field
that the report and the comparison read, by kind, with its type.  A field that fails is one InputError naming the
file (or the stored result) and the field's path (``axes.X.targets.mean_up``), so that nothing that reads a
result from the history meets a field it cannot read.

Field types: ``NUM`` a finite number; ``NUM_NAN`` a number or null, where mtcal writes NaN as null (read back as
NaN); ``TEXT`` a string; ``TEXT_NULL`` a string or null; ``BOOL``; ``ANY``; a dict spec is an object whose keys
are required, a key starting with "?" optional (other keys are kept unchecked); ``[spec]`` a list of spec;
``Map(spec)`` an object of any keys whose values are spec; ``OneOf(values)``; ``Null(spec)`` spec or null.
Units as mtcal writes them (mm, rad, µm in the report's figures; ISO 230-2 in its file's unit).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from mtcal.errors import InputError

NUM, NUM_NAN, TEXT, TEXT_NULL, BOOL, ANY = "a number", "a number or null", "a string", "a string or null", \
    "true or false", "anything"
CHECK_KINDS = ("circular", "rtest")  # mtcal check's tests (ballbar ISO 230-4, R-test ISO 10791-6)
TRACE_COLUMNS = {"circular": 5, "rtest": 10}  # per point: circular angle, measured, predicted, u, direction;
# R-test position, measured dx dy dz, predicted dx dy dz, u dx dy dz (mtcal.check.evaluate)
ISO_TARGETS = ("mean_up", "mean_down", "reversal", "R", "s_up", "s_down")  # per target, as long as the positions


@dataclass(frozen=True)
class Map:
    value: Any


@dataclass(frozen=True)
class OneOf:
    values: tuple


@dataclass(frozen=True)
class Null:
    spec: Any


NOISE_LAW = {"radial_um": NUM, "radial_um_per_m": NUM, "transverse_um": NUM, "transverse_um_per_m": NUM, "k": NUM,
             "?instrument": TEXT_NULL, "?source": TEXT_NULL}
CHECK = {"kind": OneOf(CHECK_KINDS), "?source": TEXT, "measured": Map(ANY), "predicted": Map(ANY), "agrees": BOOL,
         "worst_z": NUM_NAN, "prediction_u95_mm": NUM_NAN, "?findings": [{"?text": TEXT}], "?trace": [[NUM_NAN]],
         "?plane": TEXT, "?radius_mm": NUM, "?axis": TEXT}
SCHEMAS = {
    "model": {"?noise_law": Null(NOISE_LAW)},
    "uncertainty": {"?trials": NUM, "volumetric": {"?u95_max_mm": NUM_NAN, "?program": TEXT_NULL, "?poses": [ANY]},
                    "?provenance": Null({"?model_sha256": TEXT_NULL})},
    "iso230-2": {"axes": Map({"axis": TEXT, "kind": TEXT, "unit": TEXT, "?position_unit": TEXT, "positions": [NUM],
                              "parameters": Map(NUM_NAN), "?parameter_meaning": Map(TEXT),
                              "targets": {k: [NUM_NAN] for k in ISO_TARGETS}})},
    "check": CHECK,
    "verify": {"passed": BOOL, "errors": [{"text": TEXT, "?within": BOOL}], "?check": Null(CHECK)},
    "diagnose": {"?machine": TEXT_NULL, "effects": [{"name": TEXT, "?axis": TEXT_NULL, "?estimate": NUM_NAN,
                                                     "?note": TEXT_NULL, "?significant": BOOL,
                                                     "?interval_95": Null([NUM_NAN])}],
                 "?unexplained": [ANY], "?base_sigma_ratio": NUM_NAN, "?sigma_ratio_after": NUM_NAN},
}


def checked_document(kind: str, doc: Any, source: str) -> dict:
    """``doc`` checked against the schema of ``kind`` (module docstring), with null read back as NaN where a
    number is read; an InputError names ``source`` and the field."""
    if kind not in SCHEMAS:
        raise InputError(f"not a kind of result the history keeps: {kind!r} (kinds: {', '.join(SCHEMAS)})", source)
    out = _checked(doc, SCHEMAS[kind], "", source)
    if kind == "iso230-2":
        for ax, ev in out["axes"].items():
            for k in ISO_TARGETS:
                if len(ev["targets"][k]) != len(ev["positions"]):
                    _refuse(f"axes.{ax}.targets.{k}", f"{len(ev['targets'][k])} values for "
                                                      f"{len(ev['positions'])} positions", source)
    for i, e in enumerate(out["effects"] if kind == "diagnose" else []):
        if e.get("interval_95") is not None and len(e["interval_95"]) != 2:
            _refuse(f"effects[{i}].interval_95", f"{len(e['interval_95'])} values, not two (low, high)", source)
    for path, check in (("", out if kind == "check" else None), ("check.", out.get("check") if kind == "verify"
                                                                   else None)):
        if check:
            _check_test(check, path, source)
    return out


def _check_test(doc: dict, path: str, source: str) -> None:
    """A check test's cross-field rules: a predicted figure beside each measured one, trace rows of its kind."""
    for k, v in doc["measured"].items():
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            doc["predicted"][k] = _checked(doc["predicted"].get(k), NUM_NAN, f"{path}predicted.{k}", source)
    width = TRACE_COLUMNS[doc["kind"]]
    for i, row in enumerate(doc.get("trace") or []):
        if len(row) != width:
            _refuse(f"{path}trace[{i}]", f"{len(row)} columns, a {doc['kind']} test's trace has {width}", source)


def _refuse(where: str, problem: str, source: str):
    raise InputError(f"field '{where}': {problem}", source)


def _checked(v: Any, spec: Any, where: str, source: str) -> Any:
    """``v`` checked against ``spec`` at the path ``where`` (module docstring)."""
    if isinstance(spec, Null):
        return None if v is None else _checked(v, spec.spec, where, source)
    if isinstance(spec, dict):
        if not isinstance(v, dict):
            _refuse(where or "(the file)", f"{_what(v)} is not an object", source)
        out = dict(v)
        for key, sub in spec.items():
            name = key.lstrip("?")
            at = f"{where}.{name}" if where else name
            if name in v:
                out[name] = _checked(v[name], sub, at, source)
            elif not key.startswith("?"):
                _refuse(at, "missing", source)
        return out
    if isinstance(spec, list):
        if not isinstance(v, list):
            _refuse(where, f"{_what(v)} is not a list", source)
        return [_checked(x, spec[0], f"{where}[{i}]", source) for i, x in enumerate(v)]
    if isinstance(spec, Map):
        if not isinstance(v, dict):
            _refuse(where, f"{_what(v)} is not an object", source)
        return {k: _checked(x, spec.value, f"{where}.{k}", source) for k, x in v.items()}
    if isinstance(spec, OneOf):
        if v not in spec.values:
            _refuse(where, f"{_what(v)} is not one of {', '.join(map(repr, spec.values))}", source)
        return v
    return _scalar(v, spec, where, source)


def _scalar(v: Any, spec: str, where: str, source: str) -> Any:
    number = isinstance(v, (int, float)) and not isinstance(v, bool)
    if spec == ANY or (spec in (TEXT, TEXT_NULL) and isinstance(v, str)) or (spec == TEXT_NULL and v is None) \
            or (spec == BOOL and isinstance(v, bool)):
        return v
    if spec == NUM_NAN and v is None:
        return math.nan
    if spec in (NUM, NUM_NAN) and number and (spec == NUM_NAN or math.isfinite(v)):
        return v
    _refuse(where, f"{_what(v)} is not {spec}", source)


def _what(v: Any) -> str:
    text = repr(v)
    return text if len(text) <= 40 else text[:37] + "..."
