"""Planted effects for simulated laser-tracker campaigns: documented physical models with known truth.

Each effect is one physical mechanism with named parameters (defaults below), applied by
``mtcal.simulate`` either to the machine's error vector at every reading (then the exact kinematics carry
it to the reflectors) or to the tracker readings themselves.  Units: mm and rad for errors, mm or deg for
axis positions (the axis' own unit), s for time, ppm = 1e-6.

Names (design.md): thermal_drift, backlash, periodic, scale, squareness, rotary_location, cross_axis,
outlier, second_order, offset, tracker_scale.  API: ``effects=[("backlash", {"axis": "X", "amount": 0.004})]`` or
``Effect`` objects; CLI: ``--effect backlash:axis=X,amount=0.004``.

Models (q = axis position in mm or deg, d = approach direction +1/-1, t = time_s of the reading):
* thermal_drift  the measured points translate along ``direction`` by amplitude * (1 - exp(-(t - t0_s)/tau_s))
                 for t > t0_s (exponential warm-up); target "spindle" moves points on the spindle (spindle
                 growth), "table" points on the table, "tracker" every reading (drift of the tracker stand).
                 The temperature_c column rises by temperature_rise_c with the same time law.
* backlash       reversal (lost motion) of one axis: its positioning error (E_XX for X, E_CC for C ...)
                 gets + d * amount / 2, so the ISO 230-2 reversal value mean(dev up) - mean(dev down) = amount
                 (mm for linear, rad for rotary axes).
* periodic       ball-screw / worm-gear periodic positioning error: positioning error + amplitude *
                 sin(2 pi q / pitch + phase_deg).  Sampling must resolve the pitch (default 200 mm; a 50 mm
                 step aliases pitches of 100 mm and below).
* scale          linear scale error of an axis: positioning error + ppm * 1e-6 * q (q in rad for rotary).
* squareness     a squareness constant of the machine (its spec's squareness group, e.g. E_C0Y; rad, ISO 230-1
                 right-hand convention).
* rotary_location  a location constant of a rotary axis (E_X0<R>, E_Y0<R> mm; E_A0<R>, E_B0<R> rad).
* cross_axis     an error of one axis depends on another axis' position (e.g. sag of the first linear axis in z
                 growing with the second's overhang): error + coefficient * q_own * q_on.  Invisible when the axis is
                 measured with ``on`` at zero (the default campaign); a plan with "at" shows it.
* outlier        a gross reading: one reading (mode "reading") or that reflector for the rest of the round
                 (mode "bump": a knocked magnet nest) displaced by ``size`` mm along ``direction``.
* second_order   a quadratic term in an error function: error + coefficient * q^2 (per mm^2 or deg^2).

Axes and error names come from the machine (``Effect.bind``): an effect's default axis is the machine's first
axis, its default error the positioning error of that axis (E_XX on an X axis, E_C<R> on a rotary axis), the
first squareness / location constant of the spec, and its default reflector the first of its side.
* offset         the tracker (stand) is knocked at t_from_s: every later reading is displaced by ``size`` mm
                 along ``direction`` (the rest of the current round no longer matches its reference reading).
* tracker_scale  the tracker's distances scale by ppm about the tracker position (refractive index of air
                 wrong): ppm given directly, else from the air's deviation from the tracker's assumed state,
                 ppm = -1.0 dt_c + 0.3 dp_hpa - 0.01 drh_pct (thesis Table 2.1 sensitivities, signs from the
                 refractive index: warmer air -> lower n -> distances read short).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, Mapping

import numpy as np

from mtcal.errors import InputError
from mtcal.generated import signatures_numpy as S



def _axis(v: str) -> str:
    """An axis name (checked against the machine in ``Effect.bind``)."""
    a = str(v).strip().upper()
    if not a.isalpha():
        raise InputError(f"axis must be an axis name, got {v!r}")
    return a


def _dir(v: str) -> str:
    a = str(v).strip().upper()
    if a.lstrip("+-") not in ("X", "Y", "Z"):
        raise InputError(f"direction must be X, Y, Z, -X, -Y or -Z, got {v!r}")
    return a if a[0] in "+-" else "+" + a


def _unit(direction: str) -> np.ndarray:
    u = np.zeros(3)
    u["XYZ".index(direction[1])] = -1.0 if direction[0] == "-" else 1.0
    return u


def _choice(*options: str) -> Callable[[str], str]:
    def parse(v: str) -> str:
        s = str(v).strip().lower()
        if s not in options:
            raise InputError(f"must be one of {', '.join(options)}, got {v!r}")
        return s
    return parse


def _error_name(v: str) -> str:
    s = str(v).strip()
    if not (len(s) in (4, 5) and s.startswith("E_")):
        raise InputError(f"not an ISO 230-1 error name: {v!r}")
    return s.upper().replace("E_", "E_", 1)


def _float(v) -> float:
    x = float(v)
    if math.isnan(x) and isinstance(v, str):
        raise InputError(f"not a number: {v!r}")
    if math.isinf(x):
        raise InputError(f"must be finite, got {v!r}")
    return x


def _positive(v) -> float:
    x = _float(v)
    if not x > 0:
        raise InputError(f"must be positive, got {v!r}")
    return x


def _int(v) -> int:
    x = float(v)
    if x != int(x):
        raise InputError(f"must be an integer, got {v!r}")
    return int(x)


# name -> {key: (default, parser, doc)}
PARAMS: dict[str, dict[str, tuple[Any, Callable, str]]] = {
    "thermal_drift": {"amplitude": (0.010, _float, "mm, final displacement"),
                      "tau_s": (1800.0, _positive, "s, warm-up time constant"),
                      "direction": ("+Z", _dir, "X, Y, Z or -X, -Y, -Z"),
                      "target": ("spindle", _choice("spindle", "table", "tracker"), "what drifts"),
                      "t0_s": (0.0, _float, "s, start of the warm-up"),
                      "temperature_rise_c": (2.0, _float, "degC, rise of the temperature_c column")},
    "backlash": {"axis": (None, _axis, "axis; default the machine's first"),
                 "amount": (0.004, _float, "reversal value, mm (rad for a rotary axis)")},
    "periodic": {"axis": (None, _axis, "axis; default the machine's first"),
                 "amplitude": (0.002, _float, "mm (rad for a rotary axis)"),
                 "pitch": (200.0, _positive, "mm (deg for a rotary axis)"),
                 "phase_deg": (0.0, _float, "deg")},
    "scale": {"axis": (None, _axis, "axis; default the machine's first"),
              "ppm": (20.0, _float, "1e-6 of the position")},
    "squareness": {"error": (None, _error_name, "a squareness constant of the machine; default its first"),
                   "value": (50e-6, _float, "rad")},
    "rotary_location": {"error": (None, _error_name, "location constant of a rotary axis; default E_X0 of the last"),
                        "value": (0.020, _float, "mm or rad")},
    "cross_axis": {"error": (None, _error_name, "error function of the own axis (last letter); default E_Z of "
                                                "the first linear axis"),
                   "on": (None, _axis, "the other axis; default the second linear axis"),
                   "coefficient": (1e-7, _float, "per mm (or deg) of own axis and of the other axis")},
    "outlier": {"axis": (None, _axis, "axis; default the machine's first"), "round": (1, _int, "round (1-based)"),
                "position": (math.nan, _float, "mm or deg; default: the middle position of the axis"),
                "point": (None, str, "point label; default the first reflector of the axis"),
                "size": (0.050, _float, "mm"),
                "direction": ("+Z", _dir, "X, Y, Z or -X, -Y, -Z"),
                "mode": ("reading", _choice("reading", "bump"), "one reading, or the rest of the round"),
                "approach": (1, _int, "which approach direction of that position: +1 or -1")},
    "second_order": {"error": (None, _error_name, "error function (its axis is the last letter); default the "
                                                  "positioning error of the first axis"),
                     "coefficient": (2e-8, _float, "per mm^2 (deg^2 for B, C): 2e-8 -> 5 um at 500 mm")},
    "offset": {"size": (0.020, _float, "mm"), "direction": ("+X", _dir, "X, Y, Z or -X, -Y, -Z"),
               "t_from_s": (math.nan, _float, "s; default: half the campaign's duration")},
    "tracker_scale": {"ppm": (math.nan, _float, "scale of distances, 1e-6; default from dt_c, dp_hpa, drh_pct"),
                      "dt_c": (2.0, _float, "air temperature minus the tracker's assumed, degC"),
                      "dp_hpa": (0.0, _float, "air pressure minus assumed, hPa"),
                      "drh_pct": (0.0, _float, "relative humidity minus assumed, %")},
}
NAMES = tuple(PARAMS)


@dataclass
class Rows:
    """The schedule of a campaign, one entry per reading (see mtcal.simulate)."""

    axis: np.ndarray       # (n,) str, the measured axis
    round: np.ndarray      # (n,) int, 1-based
    position: np.ndarray   # (n,) mm or deg
    point: np.ndarray      # (n,) str
    direction: np.ndarray  # (n,) +1/-1
    time_s: np.ndarray     # (n,)
    axes: np.ndarray       # (n, n_axes) all axis positions, in the machine's axis order
    side: np.ndarray       # (n,) "tool" or "table"
    local: np.ndarray      # (n, 3) reflector coordinates on its side, mm

    def __len__(self) -> int:
        return len(self.axis)


@dataclass
class Effect:
    """One planted effect: ``name`` in NAMES and its parameters (missing keys take the defaults)."""

    name: str
    params: dict = field(default_factory=dict)
    error: str | None = field(default=None, repr=False)  # the positioning error it acts on (set by ``bind``)

    def __post_init__(self):
        if self.name not in PARAMS:
            raise InputError(f"unknown effect {self.name!r}; known: {', '.join(NAMES)}")
        spec = PARAMS[self.name]
        unknown = sorted(set(self.params) - set(spec))
        if unknown:
            raise InputError(f"effect {self.name}: unknown key(s) {unknown}; allowed: "
                             + ", ".join(f"{k} ({d[2]}, default {d[0]})" for k, d in spec.items()))
        full = {}
        for k, (default, parse, _doc) in spec.items():
            v = self.params.get(k, default)
            try:
                full[k] = parse(v) if k in self.params and v is not None else v
            except (TypeError, ValueError) as exc:
                raise InputError(f"effect {self.name}: {k}={v!r}: {exc}") from None
        self.params = full
        if self.name == "outlier" and full["approach"] not in (1, -1):
            raise InputError(f"effect outlier: approach must be +1 or -1, got {full['approach']}")

    def bind(self, machine, points: Mapping[str, Mapping] | None = None) -> "Effect":
        """This effect with its defaults resolved and its axes / errors checked against ``machine`` (a
        mtcal.Machine); ``points``: the campaign's reflectors {side: {label: xyz}} (default reflector)."""
        p = dict(self.params)
        lin = machine.linear_axes
        if "axis" in p:
            p["axis"] = p["axis"] or machine.axes[0]
            self._member("axis", p["axis"], machine.axes)
        if self.name == "squareness":
            p["error"] = p["error"] or machine.error_groups["squareness"][0]
            self._member("error", p["error"], machine.error_groups["squareness"])
        elif self.name == "rotary_location":
            p["error"] = p["error"] or f"E_X0{machine.rotary_axes[-1]}"
            self._member("error", p["error"], machine.error_groups["location"])
        elif self.name == "cross_axis":
            p["error"] = p["error"] or f"E_Z{lin[0]}"
            p["on"] = p["on"] or lin[1]
            self._member("on", p["on"], machine.axes)
        elif self.name == "second_order":
            p["error"] = p["error"] or machine.positioning_errors[machine.axes[0]]
        if self.name in ("cross_axis", "second_order"):
            funcs = machine.error_groups["linear"] + machine.error_groups["rotary"]
            self._member("error", p["error"], funcs)
        if self.name == "outlier" and p["point"] is None:
            side = machine.side(p["axis"])
            p["point"] = next(iter(points[side])) if points else machine.campaign["reflectors"][side][0][0]
        out = Effect(self.name, {})
        out.params = p
        out.error = machine.positioning_errors[p["axis"]] if "axis" in p else None
        return out

    def _member(self, key: str, value: str, options) -> None:
        if value not in options:
            self._bad(key, value, options)

    def _bad(self, key: str, value, options) -> None:
        raise InputError(f"effect {self.name}: {key} must be one of {', '.join(options)} (this machine's), "
                         f"got {value!r}")

    # -------------------------------------------------------------- errors (mm, rad) per reading
    def add_errors(self, rows: Rows, errors: np.ndarray, machine) -> None:
        """Add this (bound) effect's error contribution in place to ``errors`` (n, n_errors) of ``machine``."""
        p, n = self.params, self.name
        idx = {e: i for i, e in enumerate(machine.error_names)}

        def q_of(axis: str) -> np.ndarray:
            return rows.axes[:, machine.index(axis)]

        def q_si(axis: str) -> np.ndarray:  # mm, or rad for rotary
            q = q_of(axis)
            return np.deg2rad(q) if machine.kind(axis) == "rotary" else q

        # the increments of the error functions are the generated models of derive/signatures.py (whose
        # derivatives are the diagnosis' signatures): each effect is written once
        if n == "backlash":
            on = rows.axis == p["axis"]
            errors[on, idx[self.error]] += S.backlash_model(rows.direction[on].astype(float), [p["amount"]])[:, 0]
        elif n == "periodic":
            ph = np.deg2rad(p["phase_deg"])
            amp = [p["amplitude"] * np.cos(ph), p["amplitude"] * np.sin(ph)]  # a sin(x + ph) = a_s sin x + a_c cos x
            errors[:, idx[self.error]] += S.periodic_model(q_of(p["axis"]), float(p["pitch"]), amp)[:, 0]
        elif n == "scale":
            errors[:, idx[self.error]] += S.scale_model(q_si(p["axis"]), [p["ppm"]])[:, 0]
        elif n in ("squareness", "rotary_location"):
            errors[:, idx[p["error"]]] += p["value"]
        elif n == "cross_axis":
            own = p["error"][-1]
            errors[:, idx[p["error"]]] += S.cross_axis_model(q_of(own), q_of(p["on"]), [p["coefficient"]])[:, 0]
        elif n == "second_order":
            errors[:, idx[p["error"]]] += S.second_order_model(q_of(p["error"][-1]), [p["coefficient"]])[:, 0]

    # -------------------------------------------------------------- readings (mm)
    def drift(self, t: np.ndarray) -> np.ndarray:
        """thermal_drift: fraction (0..1) of the final displacement reached at times t (s)."""
        p = self.params
        dt = np.maximum(np.asarray(t, dtype=float) - p["t0_s"], 0.0)
        return 1.0 - np.exp(-dt / p["tau_s"])

    def tracker_ppm(self) -> float:
        p = self.params
        if not math.isnan(p["ppm"]):
            return p["ppm"]
        return -1.0 * p["dt_c"] + 0.3 * p["dp_hpa"] - 0.01 * p["drh_pct"]

    def outlier_rows(self, rows: Rows) -> np.ndarray:
        """Indices of the readings the outlier displaces."""
        p = self.params
        on = rows.axis == p["axis"]
        if not on.any():
            return np.zeros(0, dtype=int)
        pos = p["position"]
        if math.isnan(pos):
            levels = np.unique(rows.position[on])
            pos = float(levels[len(levels) // 2])
        sel = on & (rows.round == p["round"]) & (rows.point == p["point"])
        hit = np.flatnonzero(sel & np.isclose(rows.position, pos) & (rows.direction == p["approach"]))
        if len(hit) == 0:
            raise InputError(f"effect outlier: no reading of axis {p['axis']} round {p['round']} point "
                             f"{p['point']} at position {pos:g} approached {p['approach']:+d}")
        first = hit[0]
        if p["mode"] == "reading":
            return np.array([first])
        later = np.flatnonzero(sel & (rows.time_s >= rows.time_s[first]))
        return later

    def apply_readings(self, rows: Rows, xyz: np.ndarray, tracker: np.ndarray) -> None:
        """Modify the readings (n, 3) in place."""
        p, n = self.params, self.name
        if n == "thermal_drift":
            side = {"spindle": "tool", "table": "table"}.get(p["target"])
            on = np.ones(len(rows), bool) if p["target"] == "tracker" else rows.side == side
            dt = np.maximum(rows.time_s[on] - p["t0_s"], 0.0)
            xyz[on] += S.thermal_drift_displacement(p["amplitude"] * _unit(p["direction"]), dt, p["tau_s"])
        elif n == "outlier":
            xyz[self.outlier_rows(rows)] += p["size"] * _unit(p["direction"])
        elif n == "offset":
            xyz[rows.time_s >= self.offset_time(rows)] += p["size"] * _unit(p["direction"])
        elif n == "tracker_scale":
            xyz[:] = S.tracker_scale_reading(xyz, tracker, self.tracker_ppm())

    def offset_time(self, rows: Rows) -> float:
        t = self.params["t_from_s"]
        return float(rows.time_s.max() / 2 if math.isnan(t) else t)

    def temperature_rise(self, t: np.ndarray) -> np.ndarray:
        if self.name != "thermal_drift":
            return np.zeros(np.shape(t))
        return self.params["temperature_rise_c"] * self.drift(t)

    # -------------------------------------------------------------- truth
    def truth(self, rows: Rows | None = None) -> dict:
        """The planted truth: parameters, the affected error / axis, and derived values."""
        p, n = self.params, self.name
        out: dict[str, Any] = {"name": n, "params": {k: (None if isinstance(v, float) and math.isnan(v) else v)
                                                      for k, v in p.items()}}
        if n in ("backlash", "periodic", "scale"):
            out.update(axis=p["axis"], error=self.error)
            if n == "backlash":
                out["reversal"] = p["amount"]
        elif n in ("squareness", "rotary_location"):
            out.update(error=p["error"], value=p["value"],
                       axis=p["error"][-1] if n == "squareness" else p["error"][-1])
        elif n in ("cross_axis", "second_order"):
            out.update(error=p["error"], axis=p["error"][-1])
        elif n == "thermal_drift":
            out.update(direction=p["direction"], amplitude=p["amplitude"])
        elif n == "outlier":
            out.update(axis=p["axis"], direction=p["direction"])
            if rows is not None:
                i = self.outlier_rows(rows)
                out["rows"] = [{"axis": str(rows.axis[k]), "round": int(rows.round[k]),
                                "position": float(rows.position[k]), "point": str(rows.point[k]),
                                "direction": int(rows.direction[k])} for k in i]
        elif n == "tracker_scale":
            out["ppm"] = self.tracker_ppm()
        elif n == "offset":
            out.update(direction=p["direction"], size=p["size"])
            if rows is not None:
                t = self.offset_time(rows)
                i = np.flatnonzero(rows.time_s >= t)
                out["t_from_s"] = t
                if len(i):
                    out["first_row"] = {"axis": str(rows.axis[i[0]]), "round": int(rows.round[i[0]]),
                                        "position": float(rows.position[i[0]]), "point": str(rows.point[i[0]])}
        return out


def parse_effect(text: str) -> Effect:
    """'NAME' or 'NAME:key=value,key=value' (CLI --effect) -> Effect."""
    name, _, rest = str(text).partition(":")
    name = name.strip()
    params: dict[str, str] = {}
    for item in filter(None, (s.strip() for s in rest.split(","))):
        k, eq, v = item.partition("=")
        if not eq or not k.strip():
            raise InputError(f"effect {text!r}: expected key=value, got {item!r}")
        params[k.strip()] = v.strip()
    return Effect(name, params)


def as_effects(effects: Iterable) -> list[Effect]:
    """Effects from Effect objects, (name, params) pairs, 'name:key=value' strings or dicts with "name"."""
    out = []
    for e in effects or ():
        if isinstance(e, Effect):
            out.append(Effect(e.name, dict(e.params)))
        elif isinstance(e, str):
            out.append(parse_effect(e))
        elif isinstance(e, Mapping):
            d = dict(e)
            name = d.pop("name", None)
            params = d.pop("params", d)
            out.append(Effect(str(name), dict(params)))
        else:
            try:
                name, params = e
            except (TypeError, ValueError):
                raise InputError(f"an effect must be Effect, (name, params), 'name:key=value' or a dict, "
                                 f"got {e!r}") from None
            out.append(Effect(str(name), dict(params or {})))
    return out
