"""Error model JSON (design.md): constants and error functions by ISO 230-1 name, mm and rad.

{"machine": "dmu50", "units": {"length": "mm", "angle": "rad"},
 "constants": {"E_C0Y": 1e-5, ...},
 "functions": {"E_XX": {"axis": "X", "positions": [...], "values": [...], "fit": {...}}}}

A function is evaluated from its fit when one is stored, else piecewise linearly between its table
positions (mm or deg of its axis).  Fits: {"kind": "polynomial", "coefficients": [c0, c1, ...],
"domain": [lo, hi]} (numpy.polynomial.Polynomial with that domain, i.e. x mapped to [-1, 1]) or
{"kind": "harmonic", "period": 360, "a0": v, "cos": [a1, ...], "sin": [b1, ...]}.
Positions outside the table are an error unless ``extrapolate="hold"`` (end values held).
Missing names are zero.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from mtcal import schema as sc
from mtcal.errors import InputError
from mtcal.io import atomic_write_text, dumps, read_json

LENGTH_UNITS = {"mm": 1.0, "um": 1e-3, "m": 1e3, "inch": 25.4}
ANGLE_UNITS = {"rad": 1.0, "urad": 1e-6, "mrad": 1e-3, "deg": np.pi / 180, "arcsec": np.pi / 180 / 3600}


@dataclass
class ErrorFunction:
    axis: str
    positions: np.ndarray
    values: np.ndarray
    fit: dict | None = None
    extra: dict = field(default_factory=dict)  # e.g. std, std_mean per position

    def __call__(self, pos, extrapolate: str = "error") -> np.ndarray:
        """Value at axis positions (mm or deg), in mm or rad."""
        x = np.asarray(pos, dtype=float)
        fit = self.fit or {}
        kind = fit.get("kind")
        if kind == "harmonic":
            w = 2 * np.pi * x / float(fit.get("period", 360.0))
            out = np.full(x.shape, float(fit.get("a0", 0.0)))
            for h, (a, b) in enumerate(zip(fit.get("cos", []), fit.get("sin", [])), start=1):
                out = out + a * np.cos(h * w) + b * np.sin(h * w)
            return out
        lo, hi = float(self.positions.min()), float(self.positions.max())
        outside = (x < lo - 1e-9) | (x > hi + 1e-9)
        if outside.any() and extrapolate != "hold":
            bad = float(x[outside].flat[0])
            raise InputError(f"{self.axis} = {bad:g} is outside the measured range [{lo:g}, {hi:g}] of an error "
                             f"function (use extrapolate='hold' to hold the end values)")
        xc = np.clip(x, lo, hi)
        if kind == "polynomial":
            p = np.polynomial.Polynomial(fit["coefficients"], domain=fit.get("domain", [lo, hi]))
            return p(xc)
        if kind not in (None, "table"):
            raise InputError(f"unknown fit kind {kind!r}")
        return np.interp(xc, self.positions, self.values)


@dataclass
class ErrorModel:
    machine: str = "dmu50"
    constants: dict[str, float] = field(default_factory=dict)
    functions: dict[str, ErrorFunction] = field(default_factory=dict)
    meta: dict[str, Any] = field(default_factory=dict)

    def names(self) -> list[str]:
        return sorted(set(self.constants) | set(self.functions))

    def errors_at(self, machine, axes, extrapolate: str = "error") -> np.ndarray:
        """Error vector (..., n_errors) of ``machine`` (a mtcal.Machine) at axis positions (..., n_axes)."""
        a = machine.check_axes(axes)
        unknown = sorted(set(self.names()) - set(machine.error_names))
        if unknown:
            raise InputError(f"error model has names unknown to machine {machine.name}: {unknown}")
        e = np.zeros(a.shape[:-1] + (len(machine.error_names),))
        for name, v in self.constants.items():
            e[..., machine.error_names.index(name)] = v
        for name, f in self.functions.items():
            if f.axis not in machine.axes:
                raise InputError(f"error function {name} refers to axis {f.axis!r}, not an axis of {machine.name}")
            e[..., machine.error_names.index(name)] += f(a[..., machine.axes.index(f.axis)], extrapolate)
        return e

    def is_zero(self) -> bool:
        def fit_zero(fit: dict | None) -> bool:
            return not fit or not any(np.any(np.asarray(v, dtype=float) != 0) for k, v in fit.items()
                                      if k in ("coefficients", "a0", "cos", "sin"))
        return all(v == 0 for v in self.constants.values()) and all(
            not np.any(f.values) and fit_zero(f.fit) for f in self.functions.values())

    def to_dict(self) -> dict:
        funcs = {}
        for n, f in sorted(self.functions.items()):
            d = {"axis": f.axis, "positions": f.positions.tolist(), "values": f.values.tolist()}
            if f.fit:
                d["fit"] = f.fit
            d.update(f.extra)
            funcs[n] = d
        return {"machine": self.machine, "units": {"length": "mm", "angle": "rad"},
                "constants": dict(sorted(self.constants.items())), "functions": funcs, **self.meta}


def _scale(name: str, units: dict) -> float:
    """Factor to mm (translational names E_X.., E_Y.., E_Z..) or rad (E_A.., E_B.., E_C..)."""
    return LENGTH_UNITS[units["length"]] if name[2] in "XYZ" else ANGLE_UNITS[units["angle"]]


def load_model(path: str | Path) -> ErrorModel:
    """Read an error model JSON; values are converted to mm and rad from its "units"."""
    return model_from_dict(read_json(path, "model"), str(path))


def model_from_dict(raw: Any, source: str = "<model>") -> ErrorModel:
    """Check an error model (module docstring) against its machine and convert it to mm and rad.

    Names come from the machine (``machine.error_names``); a function's axis must be the axis its error moves
    with (ISO 230-1: the last letter, E_XX over X), constants are any error name; every number finite."""
    from mtcal.machine import load_machine
    sc.obj(raw, source, "the model")
    machine = raw.get("machine", "dmu50")
    if not isinstance(machine, str):
        raise InputError(f"machine must be a machine name, got {machine!r}", source)
    try:
        m = load_machine(machine)
    except InputError as exc:
        raise InputError(f"machine: {exc.problem}", source) from None
    units = _units(raw.get("units", {"length": "mm", "angle": "rad"}), source)
    consts = {}
    for n, v in sc.obj(raw.get("constants", {}), source, "constants").items():
        _known_name(n, m, source, "constants")
        consts[n] = sc.number(v, source, f"constants.{n}") * _scale(n, units)
    funcs = {}
    for n, f in sc.obj(raw.get("functions", {}), source, "functions").items():
        funcs[n] = _function(n, f, m, units, source)
    meta = {k: v for k, v in raw.items() if k not in ("machine", "units", "constants", "functions")}
    return ErrorModel(m.name, consts, funcs, meta)


def _units(u: Any, source: str) -> dict:
    sc.obj(u, source, "units")
    sc.known_keys(u, ("length", "angle"), source, "units")
    out = {"length": u.get("length", "mm"), "angle": u.get("angle", "rad")}
    if out["length"] not in LENGTH_UNITS or out["angle"] not in ANGLE_UNITS:
        raise InputError(f"units: length must be one of {list(LENGTH_UNITS)} and angle one of {list(ANGLE_UNITS)}, "
                         f"got {dict(u)}", source)
    return out


def _known_name(n: str, m, source: str, where: str) -> None:
    if n not in m.error_names:
        raise InputError(f"{where}: {n!r} is not an error of machine {m.name} (names: {', '.join(m.error_names)})",
                         source)


def _function(n: str, f: Any, m, units: dict, source: str) -> ErrorFunction:
    """One error function: axis, positions (strictly increasing), values (same length), optional fit."""
    where = f"functions.{n}"
    _known_name(n, m, source, "functions")
    motion = set(m.error_groups.get("linear", [])) | set(m.error_groups.get("rotary", []))
    if n not in motion:
        raise InputError(f"{where}: {n} is a constant (squareness or axis location), not a function of an axis; "
                         "give it under constants", source)
    sc.obj(f, source, where)
    axis = f.get("axis")
    if axis != n[-1]:
        raise InputError(f"{where}: axis must be {n[-1]!r} ({n} is a function of {n[-1]}), got {axis!r}", source)
    pos = sc.numbers(f.get("positions"), source, f"{where}.positions", 2)
    val = sc.numbers(f.get("values"), source, f"{where}.values", 2) * _scale(n, units)
    if pos.shape != val.shape:
        raise InputError(f"{where}: {len(pos)} positions but {len(val)} values", source)
    if np.any(np.diff(pos) <= 0):
        raise InputError(f"{where}.positions must increase strictly", source)
    fit = f.get("fit")
    if fit is not None:
        _check_fit(fit, source, f"{where}.fit")
        if _scale(n, units) != 1.0:
            raise InputError(f"{where}: fits must be stored in mm and rad (units length mm, angle rad)", source)
    extra = {k: v for k, v in f.items() if k not in ("axis", "positions", "values", "fit")}
    return ErrorFunction(axis, pos, val, fit, extra)


FIT_KEYS = {"polynomial": ("coefficients", "domain"), "harmonic": ("period", "a0", "cos", "sin"), "table": ()}


def _check_fit(fit: Any, source: str, where: str) -> None:
    sc.obj(fit, source, where)
    kind = fit.get("kind")
    if kind not in FIT_KEYS:
        raise InputError(f"{where}.kind must be one of {list(FIT_KEYS)}, got {kind!r}", source)
    missing = [k for k in FIT_KEYS[kind] if k not in fit]
    if missing:
        raise InputError(f"{where}: a {kind} fit needs {', '.join(FIT_KEYS[kind])}; missing {', '.join(missing)}",
                         source)
    if kind == "polynomial":
        sc.numbers(fit["coefficients"], source, f"{where}.coefficients", 1)
        lo, hi = sc.numbers(fit["domain"], source, f"{where}.domain", 2)[:2]
        if len(fit["domain"]) != 2 or not lo < hi:
            raise InputError(f"{where}.domain must be [lo, hi] with lo < hi, got {fit['domain']!r}", source)
    elif kind == "harmonic":
        sc.number(fit["period"], source, f"{where}.period", positive=True)
        sc.number(fit["a0"], source, f"{where}.a0")
        c = sc.numbers(fit["cos"], source, f"{where}.cos")
        s = sc.numbers(fit["sin"], source, f"{where}.sin")
        if len(c) != len(s):
            raise InputError(f"{where}: cos and sin need the same number of terms ({len(c)} vs {len(s)})", source)


def save_model(model: ErrorModel, path: str | Path) -> None:
    atomic_write_text(path, dumps(model.to_dict()) + "\n")
