"""Planted effects for simulated laser-tracker campaigns: documented physical models with known truth.

Each effect is one physical mechanism with named parameters (defaults below), applied by
``mtcal.campaign.simulate`` either to the machine's error vector at every reading (then the exact kinematics carry
it to the reflectors) or to the tracker readings themselves.  Units: mm and rad for errors, mm or deg for
axis positions (the axis' own unit), s for time, ppm = 1e-6.

Names (docs/design.md): thermal_drift, backlash, periodic, scale, squareness, rotary_location, cross_axis,
outlier, second_order, offset, tracker_scale; issue 13: reversal_angular, nest_creep, tracker_settling,
thermal_temperature; issue 24: nest_knock; issue 34: side_expansion, backlash_travel, tracker_relevel, axis_scatter,
air_index_drift.
Parameters are checked (finite, in a physical range) and a bad one is an InputError.
API: ``effects=[("backlash", {"axis": "X", "amount": 0.004})]`` or
``Effect`` objects; CLI: ``--effect backlash:axis=X,amount=0.004``.

Models (q = axis position in mm or deg, d = approach direction +1/-1, t = time_s of the reading):
* thermal_drift  the measured points translate along ``direction`` by amplitude * (1 - exp(-(t - t0_s)/tau_s))
                 for t > t0_s (exponential warm-up); target "spindle" moves points on the spindle (spindle
                 growth), "table" points on the table, "tracker" every reading (drift of the tracker stand).
                 The temperature_c column rises by temperature_rise_c with the same time law.
* backlash       reversal of one axis: its positioning error (E_XX for X, E_CC for C ...) gets + d * amount / 2,
                 i.e. amount = error(+ approach) - error(- approach) in the error's own ISO 230-1 sense (mm for
                 linear, rad for rotary axes).  Against ISO 230-2's reversal value B = mean(dev up) - mean(dev
                 down) (deviation = actual - target in the commanded sense): B = amount on a linear axis (its
                 positioning error points along its motion in every shipped spec); on a rotary axis B = s amount,
                 s = +1 when a positive command turns about +z of the axis' stator frame (the sense of E_C<R>),
                 -1 otherwise (DMU 50's C, T_0^w = ... Rz(-C): amount = +20 urad reads B = -20 urad).  Classic
                 lost motion (the axis stops short in the direction of travel: B < 0) is a negative amount on a
                 linear axis (tests/test_effects_new_physics.py checks both through mtcal.iso230_2.evaluation).
* reversal_angular  direction-dependent pitch / yaw / roll of a linear axis: its angular error ``error`` (E_AJ,
                 E_BJ, E_CJ of a linear axis J) gets + d * amount / 2 on the readings of J's motion, so the angle
                 differs by amount (rad) between + and - approach (e.g. a carriage rocking on its guides as the
                 drive force reverses).
* nest_creep     one reflector's nest (``point`` on ``side``) creeps at rate_mm_s along ``direction`` (the side's
                 local frame: spindle or workpiece coordinates), linearly from t0_s: local + v (t - t0_s); the
                 exact kinematics carry it to the machine frame (it turns with the table).  10 um/h = 2.78e-6 mm/s.
* nest_knock     one reflector's nest (``point`` on ``side``) knocked at t0_s: displaced by ``size`` mm along
                 ``direction`` (the side's local frame) from then on, through the rest of that axis' block and the
                 next ones (default t0_s: the middle of that nest's readings; a knock after them is refused).
* tracker_settling  the tracker stand settles: every reading turns about the axis ``about`` through the tracker
                 position by theta = rate_rad_s (t - t0_s) + angle_rad (1 - exp(-(t - t0_s) / tau_s)) (a ramp
                 and / or a first-order settling); exact rotation, distances to the tracker unchanged.
* thermal_temperature  thermal drift driven by the recorded temperature_c (T, degC; T_ref = t_ref_c, default the
                 first reading's): the positioning error of linear ``axis`` gets + 1e-6 ppm_per_k (T - T_ref) q
                 (expansion of the scale / screw), and the points of ``target`` (spindle or table) move by
                 drift_mm_per_k (T - T_ref) along ``direction``.  The simulator writes a warm-up temperature
                 channel (mtcal.campaign.simulate.WarmUp, default 2 K with tau 1800 s) when this effect is planted.
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
* side_expansion (issue 34, a member of derive/grammar.py) the reflectors of ``side`` move apart about their
                 layout's centroid (the side's local frame): local + 1e-6 h (local - centroid), h = ppm_per_h (t -
                 t0_s) / 3600 (law "ramp": a warming table, ppm per hour) or ppm (1 - exp(-(t - t0_s) / tau_s))
                 (law "lag").
* backlash_travel  a reversal growing along the travel (a worn screw): positioning error + d (amount + slope q) / 2,
                 amount the reversal at q = 0 (mm, rad rotary) and slope its change per mm (rad per deg).
* axis_scatter   one axis repeating worse than the others: its positioning error gets an independent random
                 N(0, sd^2) at every reading of it (mm, rad rotary; ``seed``): scatter along its motion.
* tracker_relevel  the tracker re-levelled between two rounds: every reading from the first of ``round`` of
                 ``axis`` on turns by angle_rad about the horizontal axis ``about`` through the tracker (exact).
* air_index_drift  the air's refractive index drifts while the tracker's weather compensation keeps its first value:
                 every reading scales about the tracker, tracker + (1 + 1e-6 h) (point - tracker), h = ppm_per_h (t -
                 t0_s) / 3600 (law "ramp") or ppm (1 - exp(-(t - t0_s) / tau_s)) (law "lag"); about -1 ppm per K of
                 air temperature (see tracker_scale), so 3 ppm is the air 3 K cooler.

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

from mtcal.campaign import planted
from mtcal.campaign.planted import unit
from mtcal.errors import InputError
from mtcal.generated import signatures_numpy as S


def _axis(v: str) -> str:
    """An axis name (checked against the machine in ``Effect.bind``)."""
    a = str(v).strip().upper()
    if not a.isalpha():
        raise InputError(f"axis must be an axis name, got {v!r}")
    return a


def _dir(v) -> str | tuple[float, float, float]:
    """"+X" .. "-Z" (an axis direction), or a vector "a;b;c" (or a sequence) -> its unit vector."""
    if not isinstance(v, str):
        v = ";".join(str(c) for c in v)
    a = str(v).strip().upper()
    if ";" in a:
        try:
            u = np.array([float(c) for c in a.split(";")])
        except ValueError:
            u = np.zeros(0)
        if u.shape != (3,) or not np.isfinite(u).all() or np.linalg.norm(u) < 1e-12:
            raise InputError(f"a direction vector must be three finite numbers a;b;c, not all zero, got {v!r}")
        return tuple(float(c) for c in u / np.linalg.norm(u))
    if a.lstrip("+-") not in ("X", "Y", "Z"):
        raise InputError(f"direction must be X, Y, Z, -X, -Y, -Z or a vector a;b;c, got {v!r}")
    return a if a[0] in "+-" else "+" + a


def _in(lo: float, hi: float, what: str = "") -> Callable[[str], float]:
    """A finite number in [lo, hi] (``what``: the physical reason for the range, for the message)."""
    def parse(v) -> float:
        x = _float(v)
        if math.isnan(x):  # only a non-string NaN gets here: a default passed on ("not given")
            return x
        if not lo <= x <= hi:
            raise InputError(f"must lie in [{lo:g}, {hi:g}]{' (' + what + ')' if what else ''}")
        return x
    return parse


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
                 "amount": (0.004, _float, "error(+ approach) - error(- approach), mm (rad for a rotary axis)")},
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
    "reversal_angular": {"error": (None, _error_name, "angular error function of a linear axis (E_A<J>, E_B<J>, "
                                                      "E_C<J>); default E_B of the first linear axis"),
                         "amount": (80e-6, _in(-1e-2, 1e-2, "rad"), "rad, angle(+ approach) - angle(- approach)")},
    "nest_creep": {"point": (None, str, "point label; default the first reflector of the side"),
                   "side": (None, _choice("tool", "table"), "side carrying the nest; default the first axis' side"),
                   "rate_mm_s": (10e-3 / 3600, _in(0.0, 1e-3, "mm/s: a creep, at most 3.6 mm/h"),
                                 "mm/s (10 um/h = 2.78e-6)"),
                   "direction": ("+Z", _dir, "X, Y, Z, -X, -Y, -Z or a;b;c, the side's local frame"),
                   "t0_s": (0.0, _in(0.0, 1e7), "s, start of the creep")},
    "nest_knock": {"point": (None, str, "point label; default the first reflector of the side"),
                   "side": (None, _choice("tool", "table"), "side carrying the nest; default the first axis' side"),
                   "size": (0.020, _in(-5.0, 5.0, "mm"), "mm"),
                   "direction": ("+Z", _dir, "X, Y, Z, -X, -Y, -Z or a;b;c, the side's local frame"),
                   "t0_s": (math.nan, _float, "s; default: the middle of that nest's readings")},
    "tracker_settling": {"angle_rad": (20e-6, _in(-1e-2, 1e-2, "rad"), "rad, final tilt of the settling"),
                         "tau_s": (1800.0, _in(1.0, 1e7, "s"), "s, settling time constant"),
                         "rate_rad_s": (0.0, _in(-1e-5, 1e-5, "rad/s"), "rad/s, steady tilt rate (a ramp)"),
                         "about": ("+X", _dir, "rotation axis through the tracker, machine frame (horizontal for "
                                               "a sinking stand): X, Y, Z, -X, -Y, -Z or a;b;c"),
                         "t0_s": (0.0, _in(0.0, 1e7), "s, start of the settling")},
    "thermal_temperature": {"axis": (None, _axis, "linear axis that expands; default the first linear axis"),
                            "ppm_per_k": (10.0, _in(-100.0, 100.0, "ppm/K"), "expansion of the axis' positioning "
                                                                            "per kelvin, 1e-6/K"),
                            "drift_mm_per_k": (0.0, _in(-1.0, 1.0, "mm/K"), "drift of the target side per kelvin"),
                            "direction": ("+Z", _dir, "drift direction: X, Y, Z, -X, -Y, -Z or a;b;c"),
                            "target": ("spindle", _choice("spindle", "table"), "side that drifts"),
                            "t_ref_c": (math.nan, _in(-50.0, 100.0, "degC"),
                                        "degC, temperature of zero effect; default the first reading's")},
    "side_expansion": {"side": ("table", _choice("tool", "table"), "side whose reflector layout grows"),
                       "law": ("ramp", _choice("ramp", "lag"), "time law: ramp (ppm_per_h) or lag (ppm, tau_s)"),
                       "ppm_per_h": (10.0, _in(-1000.0, 1000.0, "ppm per hour"), "ramp: growth, 1e-6 per hour"),
                       "ppm": (20.0, _in(-1000.0, 1000.0, "ppm"), "lag: final growth, 1e-6"),
                       "tau_s": (1800.0, _in(1.0, 1e7, "s"), "lag: time constant, s"),
                       "t0_s": (0.0, _in(0.0, 1e7), "s, start of the growth")},
    "backlash_travel": {"axis": (None, _axis, "axis; default the machine's first"),
                        "amount": (0.002, _in(-1.0, 1.0, "mm or rad"), "reversal b at position 0: error(+ approach) "
                                                                       "- error(- approach), mm (rad rotary)"),
                        "slope": (1.2e-5, _in(-1e-3, 1e-3, "per mm or deg"),
                                  "change of the reversal per mm (rad per deg) of travel: 1.2e-5 -> 2 um at 0 to "
                                  "8 um at 500 mm")},
    "tracker_relevel": {"axis": (None, _axis, "axis of the round; default the machine's first"),
                        "round": (2, _int, "the round (1-based) from whose first reading on the tracker is "
                                           "re-levelled"),
                        "angle_rad": (20e-6, _in(-1e-2, 1e-2, "rad"), "rad, rotation of the re-levelling"),
                        "about": ("+X", _dir, "horizontal axis through the tracker (machine frame): X, Y, -X, -Y "
                                              "or a;b;0")},
    "axis_scatter": {"axis": (None, _axis, "axis; default the machine's first"),
                     "sd": (0.003, _in(0.0, 1.0, "mm or rad"), "mm (rad rotary): extra random scatter of the axis' "
                                                               "positioning, one standard deviation"),
                     "seed": (1, _int, "seed of the scatter's random numbers")},
    "air_index_drift": {"law": ("lag", _choice("ramp", "lag"), "time law: ramp (ppm_per_h) or lag (ppm, tau_s)"),
                        "ppm_per_h": (2.0, _in(-100.0, 100.0, "ppm per hour"), "ramp: scale change, 1e-6 per hour"),
                        "ppm": (4.0, _in(-100.0, 100.0, "ppm"), "lag: final scale change, 1e-6"),
                        "tau_s": (1800.0, _in(1.0, 1e7, "s"), "lag: time constant, s"),
                        "t0_s": (0.0, _in(0.0, 1e7), "s, when the compensation was last set")},
    "tracker_scale": {"ppm": (math.nan, _float, "scale of distances, 1e-6; default from dt_c, dp_hpa, drh_pct"),
                      "dt_c": (2.0, _float, "air temperature minus the tracker's assumed, degC"),
                      "dp_hpa": (0.0, _float, "air pressure minus assumed, hPa"),
                      "drh_pct": (0.0, _float, "relative humidity minus assumed, %")},
}
NAMES = tuple(PARAMS)


@dataclass
class Rows:
    """The schedule of a campaign, one entry per reading (see mtcal.campaign.simulate)."""

    axis: np.ndarray       # (n,) str, the measured axis
    round: np.ndarray      # (n,) int, 1-based
    position: np.ndarray   # (n,) mm or deg
    point: np.ndarray      # (n,) str
    direction: np.ndarray  # (n,) +1/-1
    time_s: np.ndarray     # (n,)
    axes: np.ndarray       # (n, n_axes) all axis positions, in the machine's axis order
    side: np.ndarray       # (n,) "tool" or "table"
    local: np.ndarray      # (n, 3) reflector coordinates on its side, mm
    temperature_c: np.ndarray | None = None  # (n,) degC, the recorded temperature channel (set by simulate)

    def __len__(self) -> int:
        return len(self.axis)


@dataclass
class Effect:
    """One planted effect: ``name`` in NAMES and its parameters (missing keys take the defaults)."""

    name: str
    params: dict = field(default_factory=dict)
    error: str | None = field(default=None, repr=False)  # the positioning error it acts on (set by ``bind``)
    centroid: np.ndarray | None = field(default=None, repr=False)  # side_expansion: the side's layout centroid

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
        if self.name == "thermal_temperature":
            p["axis"] = p["axis"] or lin[0]
            if machine.kind(p["axis"]) != "linear":
                self._bad("axis", p["axis"], lin)
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
        elif self.name == "reversal_angular":
            p["error"] = p["error"] or f"E_B{lin[0]}"
            self._member("error", p["error"], [f"E_{c}{a}" for a in lin for c in "ABC"])
        elif self.name in ("nest_creep", "nest_knock"):
            p["side"] = p["side"] or machine.side(machine.axes[0])
            labels = list(points[p["side"]]) if points else [k for k, _ in machine.campaign["reflectors"][p["side"]]]
            p["point"] = p["point"] or labels[0]
            self._member("point", p["point"], labels)
        if self.name in ("cross_axis", "second_order"):
            funcs = machine.error_groups["linear"] + machine.error_groups["rotary"]
            self._member("error", p["error"], funcs)
        if self.name == "side_expansion":
            pts = (points or {}).get(p["side"]) or dict(machine.campaign["reflectors"][p["side"]])
            centroid = np.mean(np.asarray(list(pts.values()), dtype=float), axis=0)
        if self.name == "tracker_relevel" and abs(unit(p["about"])[2]) > 1e-9:
            raise InputError(f"effect tracker_relevel: about must be horizontal (a re-levelling turns about "
                             f"horizontal axes through the tracker: X, Y or a;b;0), got {p['about']!r}")
        if self.name == "outlier" and p["point"] is None:
            side = machine.side(p["axis"])
            p["point"] = next(iter(points[side])) if points else machine.campaign["reflectors"][side][0][0]
        out = Effect(self.name, {})
        out.params = p
        out.error = machine.positioning_errors[p["axis"]] if "axis" in p else None
        if self.name == "side_expansion":
            out.centroid = centroid
        return out

    def _member(self, key: str, value: str, options) -> None:
        if value not in options:
            self._bad(key, value, options)

    def _bad(self, key: str, value, options) -> None:
        raise InputError(f"effect {self.name}: {key} must be one of {', '.join(options)} (this machine's"
                         f"{' campaign' if key == 'point' else ''}), got {value!r}")

    # -------------------------------------------------------------- what the effect does (mtcal.campaign.planted)
    def add_errors(self, rows: Rows, errors: np.ndarray, machine) -> None:
        """Add this (bound) effect's error contribution in place to ``errors`` (n, n_errors) of ``machine``."""
        planted.add_errors(self, rows, errors, machine)

    def move_nests(self, rows: Rows, local: np.ndarray) -> None:
        """nest_creep, nest_knock, side_expansion: move the reflectors' local coordinates (n, 3) mm in place."""
        planted.move_nests(self, rows, local)

    def apply_readings(self, rows: Rows, xyz: np.ndarray, tracker: np.ndarray) -> None:
        """Modify the readings (n, 3) in place."""
        planted.apply_readings(self, rows, xyz, tracker)

    def truth(self, rows: Rows | None = None) -> dict:
        """The planted truth: parameters, the affected error / axis, and derived values."""
        return planted.truth(self, rows)

    # -------------------------------------------------------------- times and values the models use
    def relevel_time(self, rows: Rows) -> float:
        """tracker_relevel: time (s) of the first reading of ``round`` of ``axis`` (the first re-levelled)."""
        p = self.params
        on = (rows.axis == p["axis"]) & (rows.round == p["round"])
        if not on.any():
            raise InputError(f"effect tracker_relevel: axis {p['axis']} has no round {p['round']}")
        return float(rows.time_s[on].min())

    def delta_t(self, rows: Rows) -> np.ndarray:
        """thermal_temperature: T - T_ref (K) of every reading (T_ref default: the first reading's)."""
        t = rows.temperature_c
        ref = self.params["t_ref_c"]
        return t - (t[0] if math.isnan(ref) else ref)

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

    def settling_angle(self, t: np.ndarray) -> np.ndarray:
        """tracker_settling: tilt (rad) of the tracker at times t (s)."""
        p = self.params
        dt = np.maximum(np.asarray(t, dtype=float) - p["t0_s"], 0.0)
        return S.tracker_settling_angle([p["rate_rad_s"], p["angle_rad"]], dt, p["tau_s"])[..., 0]

    def knock_time(self, rows: Rows) -> float:
        """nest_knock: when the nest is knocked (s; default the middle of that nest's readings).  A knock after
        its last reading moves nothing: refused."""
        p = self.params
        on = (rows.point == p["point"]) & (rows.side == p["side"])
        t = float(np.median(rows.time_s[on])) if math.isnan(p["t0_s"]) and on.any() else p["t0_s"]
        if not np.any(on & (rows.time_s >= t)):
            raise InputError(f"effect nest_knock: point {p['point']} ({p['side']} side) is not read after t0_s = "
                             f"{t:g} s: the knock would move nothing")
        return float(t)

    def offset_time(self, rows: Rows) -> float:
        """offset: when the tracker is knocked (s; default half the campaign's duration)."""
        t = self.params["t_from_s"]
        return float(rows.time_s.max() / 2 if math.isnan(t) else t)

    def temperature_rise(self, t: np.ndarray) -> np.ndarray:
        """K added to the temperature channel at times t (s): thermal_drift's warm-up, else 0."""
        if self.name != "thermal_drift":
            return np.zeros(np.shape(t))
        p = self.params
        return warm_up_rise(t, p["temperature_rise_c"], p["tau_s"], p["t0_s"])


def parse_items(text: str, what: str) -> dict[str, str]:
    """'key=value,key=value' -> {key: value} (strings); ``what`` names the option in the error message."""
    params: dict[str, str] = {}
    for item in filter(None, (s.strip() for s in str(text).split(","))):
        k, eq, v = item.partition("=")
        if not eq or not k.strip():
            raise InputError(f"{what}: expected key=value, got {item!r}")
        params[k.strip()] = v.strip()
    return params


def parse_effect(text: str) -> Effect:
    """'NAME' or 'NAME:key=value,key=value' (CLI --effect) -> Effect."""
    name, _, rest = str(text).partition(":")
    return Effect(name.strip(), parse_items(rest, f"effect {text!r}"))


def warm_up_rise(t, rise_c: float, tau_s: float, t0_s: float) -> np.ndarray:
    """K above the starting temperature at times t (s) of a warm-up rise_c (1 - exp(-(t - t0_s) / tau_s)) for
    t > t0_s (the generated warm-up curve of derive/signatures.py)."""
    dt = np.maximum(np.asarray(t, dtype=float) - t0_s, 0.0)
    return S.thermal_temperature_curve(0.0, rise_c, dt, tau_s)[..., 0]


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
