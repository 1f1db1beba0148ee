"""Error model JSON (docs/design.md): constants and error functions by ISO 230-1 name, mm and rad.

{"machine": "dmu50", "units": {"length": "mm", "angle": "rad"},
 "constants": {"E_C0Y": 1e-5, ...},
 "functions": {"E_XX": {"axis": "X", "positions": [...], "values": [...], "fit": {...}}}}

A function is evaluated from its fit when one is stored, else piecewise linearly between its table
positions (mm or deg of its axis).  Fits are typed (mtcal.model.fits: Polynomial, Harmonic, Table).
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
from mtcal.kinematics.machine import DEFAULT_MACHINE, Machine, load_machine
from mtcal.model import schema as sc
from mtcal.model.fits import FIT_KEYS, Fit, Harmonic, Polynomial, Table, fit_from_dict

LENGTH_UNITS = {"mm": 1.0, "um": 1e-3, "m": 1e3, "inch": 25.4}
ANGLE_UNITS = {"rad": 1.0, "urad": 1e-6, "mrad": 1e-3, "deg": np.pi / 180, "arcsec": np.pi / 180 / 3600}


@dataclass
class ErrorFunction:
    """One error (ISO 230-1 name) as a function of its axis' position (mm or deg): its table (``positions``,
    ``values`` in mm or rad) and, when identified, the fitted function that is evaluated (mtcal.model.fits)."""

    axis: str
    positions: np.ndarray
    values: np.ndarray
    fit: Fit | None = None
    extra: dict = field(default_factory=dict)  # e.g. std, std_mean per position

    def __post_init__(self):
        self.fit = fit_from_dict(self.fit)

    def __call__(self, pos, extrapolate: str = "error") -> np.ndarray:
        """Value at axis positions (mm or deg), in mm or rad."""
        x = np.asarray(pos, dtype=float)
        if isinstance(self.fit, Harmonic):
            return self.fit(x)
        lo, hi = float(self.positions.min()), float(self.positions.max())
        outside = (x < lo - 1e-9) | (x > hi + 1e-9)
        if outside.any() and extrapolate != "hold":
            bad = float(x[outside].flat[0])
            raise InputError(f"{self.axis} = {bad:g} is outside the measured range [{lo:g}, {hi:g}] of an error "
                             f"function (use extrapolate='hold' to hold the end values)")
        xc = np.clip(x, lo, hi)
        if isinstance(self.fit, Polynomial):
            return self.fit(xc, domain=[lo, hi])
        return np.interp(xc, self.positions, self.values)


@dataclass
class ErrorModel:
    """Errors of one machine by ISO 230-1 name: constants and functions of their axis' position.

    The JSON layout is docs/design.md's, "Files" (``load_model`` / ``save_model``).  ``errors_at(machine, axes)``
    evaluates the error vector at axis positions (a position beyond a function's table is an InputError unless
    ``extrapolate="hold"``); ``kinematics`` is the model's Machine.

    Attributes
    ----------
    machine : str
        The machine spec's name (derive/machines/<name>.toml).
    constants : dict of str to float
        Position-independent errors (squareness, location errors of rotary axes), mm and rad.
    functions : dict of str to ErrorFunction
        Errors as functions of their axis' position (mm or deg): a table and, when identified, the fitted function
        that is evaluated (mtcal.model.fits); values mm and rad.
    meta : dict
        What made the model (method, source, tracker, noise law, worth, warnings).

    Examples
    --------
    >>> import mtcal
    >>> from mtcal.data import path
    >>> model = mtcal.load_model(path("demo_truth.json"))
    >>> e = model.errors_at(model.kinematics, [[100, 0, 0, 0, 0]])  # X Y Z mm, B C deg
    >>> e.shape, f"{e[0, model.kinematics.error_names.index('E_XX')] * 1e3:.3f} um"
    ((1, 41), '0.274 um')
    """

    machine: str = DEFAULT_MACHINE
    constants: dict[str, float] = field(default_factory=dict)
    functions: dict[str, ErrorFunction] = field(default_factory=dict)
    meta: dict[str, Any] = field(default_factory=dict)

    @property
    def kinematics(self) -> Machine:
        """The model's machine (mtcal.Machine, loaded once per process)."""
        return load_machine(self.machine)

    def names(self) -> list[str]:
        return sorted(set(self.constants) | set(self.functions))

    def errors_at(self, machine, axes, extrapolate: str = "error") -> np.ndarray:
        """Error vector (..., n_errors) of ``machine`` (a mtcal.Machine) at axis positions (..., n_axes);
        ``extrapolate``: "error" (a position outside a function's table is an InputError) or "hold" / "clamp"
        (end values held).  Evaluated by ``ErrorEvaluator`` (the one evaluator of error functions)."""
        a = machine.check_axes(axes)
        ev = ErrorEvaluator(self, machine, "error" if extrapolate == "error" else "hold")
        flat = a.reshape(-1, a.shape[-1])
        return ev(flat).reshape(a.shape[:-1] + (len(machine.error_names),))

    def digest(self) -> str:
        """sha256 of what the model evaluates: machine, constants, each function's table and fit (without the
        fit's statistics, ``info``); the same for a model and its file as saved and loaded (JSON floats round-trip
        exactly).  A result derived from a model (a Monte Carlo of it, `mtcal uncertainty`) carries it."""
        import hashlib
        import json

        funcs = {n: {"axis": f.axis, "positions": np.asarray(f.positions, dtype=float).tolist(),
                     "values": np.asarray(f.values, dtype=float).tolist(),
                     "fit": None if f.fit is None else {k: v for k, v in f.fit.to_dict().items() if k != "info"}}
                 for n, f in sorted(self.functions.items())}
        text = json.dumps({"machine": self.machine, "constants": {k: float(v) for k, v in sorted(
            self.constants.items())}, "functions": funcs}, sort_keys=True, default=float)
        return hashlib.sha256(text.encode()).hexdigest()

    def is_zero(self) -> bool:
        return all(v == 0 for v in self.constants.values()) and all(
            not np.any(f.values) and (f.fit is None or f.fit.is_zero()) for f in self.functions.values())

    def to_dict(self) -> dict:
        funcs = {}
        for n, f in sorted(self.functions.items()):
            d = {"axis": f.axis, "positions": f.positions.tolist(), "values": f.values.tolist()}
            if f.fit:
                d["fit"] = f.fit.to_dict()
            d.update(f.extra)
            funcs[n] = d
        return {"machine": self.machine, "units": {"length": "mm", "angle": "rad"},
                "constants": dict(sorted(self.constants.items())), "functions": funcs, **self.meta}


class ErrorEvaluator:
    """The one evaluator of an error model's functions for a machine, batched for speed: tables of one axis on
    the same positions share one segment search (values gathered as a block, uniform grids indexed directly),
    harmonic fits of one axis and period share their sines and cosines (multiples by recurrence), anything else
    (polynomial fits) function by function; constants folded in.  ``outside``: "hold" (end values held; counts
    per function in ``outside_counts``) or "error" (InputError naming the axis, position and function)."""

    def __init__(self, model: ErrorModel, machine, outside: str = "hold"):
        if outside not in ("hold", "error"):
            raise InputError(f"outside must be 'hold' or 'error', got {outside!r}")
        m = self.machine = machine
        self.outside = outside
        unknown = sorted(set(model.names()) - set(m.error_names))
        if unknown:
            raise InputError(f"error model has names unknown to machine {m.name}: {unknown}")
        self.const = np.zeros(len(m.error_names))
        for n, v in model.constants.items():
            self.const[m.error_names.index(n)] = v
        self.funcs: list[tuple[str, int, int, ErrorFunction, float, float]] = []
        for n, f in model.functions.items():
            if f.axis not in m.axes:
                raise InputError(f"error function {n} refers to axis {f.axis!r}, not an axis of {m.name}")
            periodic = isinstance(f.fit, Harmonic)
            lo, hi = (-np.inf, np.inf) if periodic else (float(f.positions.min()), float(f.positions.max()))
            self.funcs.append((n, m.error_names.index(n), m.axes.index(f.axis), f, lo, hi))
        self.plan = self._plan()
        self.outside_counts: dict[str, int] = {}

    def _plan(self) -> list[tuple]:
        tables: dict[tuple, list] = {}
        harm: dict[tuple, list] = {}
        plan: list[tuple] = []
        for name, ei, ai, f, lo, hi in self.funcs:
            tabular = f.fit is None or isinstance(f.fit, Table)
            if tabular and len(f.positions) >= 2 and np.all(np.diff(f.positions) > 0):
                tables.setdefault((ai, f.positions.tobytes()), []).append((name, ei, f))
            elif isinstance(f.fit, Harmonic):
                harm.setdefault((ai, float(f.fit.period)), []).append((name, ei, f))
            else:
                plan.append(("single", ai, [name], np.array([ei]), f, lo, hi))
        for (ai, _), members in tables.items():
            xp = members[0][2].positions.astype(float)
            fp = np.array([f.values for _, _, f in members], dtype=float)  # (k, npts)
            cols = np.array([ei for _, ei, _ in members])
            slopes = np.diff(fp, axis=1) / np.diff(xp)
            fp = fp + self.const[cols, None]
            # per segment j: value = a_j + s_j x (rows a then s, one gather for both)
            coef = np.vstack([fp[:, :-1] - slopes * xp[:-1], slopes])
            dx = np.diff(xp)
            step = float(dx[0]) if np.all(np.abs(dx - dx[0]) <= 1e-12 * abs(dx[0])) else 0.0  # uniform grid
            plan.append(("table", ai, [n for n, _, _ in members], cols, xp, step, coef))
        for (ai, period), members in harm.items():
            nh = max(min(len(f.fit.cos), len(f.fit.sin)) for _, _, f in members)
            a0 = np.array([float(f.fit.a0) for _, _, f in members])
            ca, sa = np.zeros((len(members), nh)), np.zeros((len(members), nh))
            for r, (_, _, f) in enumerate(members):
                h = min(len(f.fit.cos), len(f.fit.sin))
                ca[r, :h], sa[r, :h] = f.fit.cos[:h], f.fit.sin[:h]
            cols = np.array([ei for _, ei, _ in members])
            plan.append(("harmonic", ai, [n for n, _, _ in members], cols, period, a0 + self.const[cols], ca, sa))
        return plan

    def __call__(self, q: np.ndarray) -> np.ndarray:
        """Error vector (n, n_errors) at axis positions (n, n_axes), Fortran-ordered (column-contiguous: the
        generated functions read it by column)."""
        q = np.asarray(q, dtype=float)
        et = np.empty((len(self.const), len(q)))  # (n_errors, n): rows contiguous
        et[:] = self.const[:, None]
        self._check_ranges(q)
        for item in self.plan:
            kind, x = item[0], q[:, item[1]]
            if kind == "table":  # piecewise linear, end values held (as np.interp)
                _, _, _, cols, xp, step, coef = item
                xc = np.clip(x, xp[0], xp[-1])
                j = ((xc - xp[0]) * (1.0 / step)).astype(np.intp) if step else np.searchsorted(xp, xc, "right") - 1
                np.clip(j, 0, len(xp) - 2, out=j)
                c = coef[:, j]
                et[cols] = c[:len(cols)] + c[len(cols):] * xc
            elif kind == "harmonic":  # a0 + sum a_h cos(h w) + b_h sin(h w)
                _, _, _, cols, period, a0, ca, sa = item
                w = (2 * np.pi / period) * x
                c1, s1 = np.cos(w), np.sin(w)
                acc = a0[:, None] + (ca[:, :1] * c1 + sa[:, :1] * s1 if ca.shape[1] else 0.0)
                ch, sh = c1, s1
                for h in range(1, ca.shape[1]):
                    ch, sh = ch * c1 - sh * s1, sh * c1 + ch * s1
                    acc += ca[:, h: h + 1] * ch + sa[:, h: h + 1] * sh
                et[cols] = acc
            else:
                _, _, _, cols, f, lo, hi = item
                et[cols[0]] += f(x, "hold")
        return et.T

    def _check_ranges(self, q: np.ndarray) -> None:
        """Counts (or refuses) axis positions outside each error function's range (one check per axis and range)."""
        checked: dict[tuple[int, float, float], int] = {}
        for name, _ei, ai, _f, lo, hi in self.funcs:
            if not np.isfinite(lo):
                continue
            key = (ai, lo, hi)
            if key not in checked:
                x = q[:, ai]
                checked[key] = int(np.count_nonzero((x < lo - 1e-9) | (x > hi + 1e-9)))
            if checked[key]:
                if self.outside == "error":
                    x = q[:, ai]
                    bad = x[(x < lo - 1e-9) | (x > hi + 1e-9)][0]
                    raise InputError(f"{self.machine.axes[ai]} = {float(bad):g} is outside the measured range "
                                     f"[{lo:g}, {hi:g}] of {name} (use extrapolate='hold' to hold the end values)")
                self.outside_counts[name] = self.outside_counts.get(name, 0) + checked[key]


def _scale(name: str, units: dict) -> float:
    """Factor to mm (translational names E_X.., E_Y.., E_Z..) or rad (E_A.., E_B.., E_C..)."""
    return LENGTH_UNITS[units["length"]] if name[2] in "XYZ" else ANGLE_UNITS[units["angle"]]


# the --json answers of other commands, by keys only they have: given as a model, they are named, not parsed
ANSWERS = (("diagnose", ("effects", "base_sigma")), ("plate", ("alpha", "beta", "gamma")),
           ("identify --json", ("axes", "squareness", "weighted")), ("compensate --json", ("program", "residual")),
           ("export --json", ("format", "files", "sign")), ("iso230-2 --json", ("standard", "axes")),
           ("plan --json", ("tracker", "axes", "mid_travel")), ("simulate (truth)", ("effects", "tracker", "seed")))


def _not_an_answer(raw: dict, source: str) -> None:
    for cmd, keys in ANSWERS:
        if all(k in raw for k in keys) and not ("functions" in raw or "constants" in raw):
            raise InputError(f"this is the JSON answer of `mtcal {cmd}`, not an error model (an error model is "
                             f"written by `mtcal identify REC.csv -o MODEL.json`)", source)


def load_model(path: str | Path) -> ErrorModel:
    """Read an error model JSON (docs/design.md, "Files").

    Parameters
    ----------
    path : str or pathlib.Path
        The model file, as ``save_model`` or `mtcal identify -o` write it.

    Returns
    -------
    ErrorModel
        The model, values converted to mm and rad from the file's ``"units"``.

    Raises
    ------
    mtcal.errors.InputError
        A file that is no error model (another command's JSON answer is named), a bad name, unit or value.

    Examples
    --------
    >>> import mtcal
    >>> from mtcal.data import path
    >>> model = mtcal.load_model(path("demo_truth.json"))
    >>> model.machine, len(model.functions)
    ('dmu50', 30)
    """
    return model_from_dict(read_json(path, "model"), str(path))


def model_from_dict(raw: Any, source: str = "<model>") -> ErrorModel:
    """Check an error model (module docstring) against its machine and convert it to mm and rad.

    Names come from the machine (``machine.error_names``); a function's axis must be the axis its error moves
    with (ISO 230-1: the last letter, E_XX over X), constants are any error name; every number finite."""
    from mtcal.kinematics.machine import load_machine
    sc.obj(raw, source, "the model")
    _not_an_answer(raw, source)
    machine = raw.get("machine", DEFAULT_MACHINE)
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
    """Write an error model JSON (mm and rad, ISO 230-1 names; docs/design.md, "Files") atomically.

    Parameters
    ----------
    model : ErrorModel
        The model to write.
    path : str or pathlib.Path
        The file (replaced atomically: a reader never sees half a file).

    Returns
    -------
    None

    Examples
    --------
    >>> import mtcal
    >>> from mtcal.data import path
    >>> mtcal.save_model(mtcal.load_model(path("demo_truth.json")), "model.json")
    >>> mtcal.load_model("model.json").machine
    'dmu50'
    """
    atomic_write_text(path, dumps(model.to_dict()) + "\n")
