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

from mtcal.errors import InputError
from mtcal.io import atomic_write_text, dumps, read_json

LENGTH_UNITS = {"mm": 1.0, "um": 1e-3, "m": 1e3}
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
        return all(v == 0 for v in self.constants.values()) and all(
            not np.any(f.values) and not (f.fit and any(np.any(np.asarray(v, dtype=float) != 0)
                                                         for k, v in f.fit.items() if k in ("coefficients", "a0", "cos", "sin")))
            for f in self.functions.values())

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
    lu, au = units.get("length", "mm"), units.get("angle", "rad")
    if lu not in LENGTH_UNITS or au not in ANGLE_UNITS:
        raise InputError(f"units must be length in {list(LENGTH_UNITS)} and angle in {list(ANGLE_UNITS)}, got {units}")
    return LENGTH_UNITS[lu] if name[2] in "XYZ" else ANGLE_UNITS[au]


def load_model(path: str | Path) -> ErrorModel:
    """Read an error model JSON; values are converted to mm and rad from its "units"."""
    return model_from_dict(read_json(path, "model"), str(path))


def model_from_dict(raw: dict, source: str = "<model>") -> ErrorModel:
    units = raw.get("units", {"length": "mm", "angle": "rad"})
    consts = {}
    for n, v in raw.get("constants", {}).items():
        if not isinstance(v, (int, float)) or not np.isfinite(v):
            raise InputError(f"{source}: constant {n} must be a finite number, got {v!r}")
        consts[n] = float(v) * _scale(n, units)
    funcs = {}
    for n, f in raw.get("functions", {}).items():
        try:
            pos = np.asarray(f["positions"], dtype=float)
            val = np.asarray(f["values"], dtype=float) * _scale(n, units)
            axis = f["axis"]
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(f"{source}: function {n} needs axis, positions and values ({exc})") from None
        if pos.ndim != 1 or pos.shape != val.shape or len(pos) < 2:
            raise InputError(f"{source}: function {n}: positions and values must be equal-length lists (>= 2)")
        if not (np.isfinite(pos).all() and np.isfinite(val).all()):
            raise InputError(f"{source}: function {n} contains NaN/inf")
        if np.any(np.diff(pos) <= 0):
            raise InputError(f"{source}: function {n}: positions must increase strictly")
        fit = f.get("fit")
        if fit and _scale(n, units) != 1.0:
            raise InputError(f"{source}: function {n}: fits must be stored in mm and rad")
        extra = {k: v for k, v in f.items() if k not in ("axis", "positions", "values", "fit")}
        funcs[n] = ErrorFunction(axis, pos, val, fit, extra)
    meta = {k: v for k, v in raw.items() if k not in ("machine", "units", "constants", "functions")}
    return ErrorModel(raw.get("machine", "dmu50"), consts, funcs, meta)


def save_model(model: ErrorModel, path: str | Path) -> None:
    atomic_write_text(path, dumps(model.to_dict()) + "\n")
