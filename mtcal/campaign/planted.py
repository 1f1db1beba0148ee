"""What a planted effect does to a simulated campaign (``mtcal.campaign.effects`` holds the effects' names,
parameters and models in words): its increment of the machine's error functions, the motion of a reflector nest,
the change of the readings, and the truth it records.  Each model is a generated function of derive/signatures.py.

``e`` is a bound ``mtcal.campaign.effects.Effect``, ``rows`` the campaign's ``mtcal.campaign.effects.Rows``.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from mtcal.generated import signatures_numpy as S


def unit(direction) -> np.ndarray:
    """The unit vector of a parsed direction: "+X" .. "-Z" or a 3-tuple."""
    if not isinstance(direction, str):
        return np.asarray(direction, dtype=float)
    u = np.zeros(3)
    u["XYZ".index(direction[1])] = -1.0 if direction[0] == "-" else 1.0
    return u



def add_errors(e, rows, errors: np.ndarray, machine) -> None:
    """Add the (bound) effect's error contribution in place to ``errors`` (n, n_errors) of ``machine``."""
    p, n = e.params, e.name
    idx = {name: i for i, name in enumerate(machine.error_names)}

    def q_of(axis: str) -> np.ndarray:
        return rows.axes[:, machine.index(axis)]

    def q_si(axis: str) -> np.ndarray:  # mm, or rad for rotary
        q = q_of(axis)
        return np.deg2rad(q) if machine.kind(axis) == "rotary" else q

    # the increments of the error functions are the generated models of derive/signatures.py (whose
    # derivatives are the diagnosis' signatures): each effect is written once
    if n == "backlash":
        on = rows.axis == p["axis"]
        errors[on, idx[e.error]] += S.backlash_model(rows.direction[on].astype(float), [p["amount"]])[:, 0]
    elif n == "periodic":
        ph = np.deg2rad(p["phase_deg"])
        amp = [p["amplitude"] * np.cos(ph), p["amplitude"] * np.sin(ph)]  # a sin(x + ph) = a_s sin x + a_c cos x
        errors[:, idx[e.error]] += S.periodic_model(q_of(p["axis"]), float(p["pitch"]), amp)[:, 0]
    elif n == "scale":
        errors[:, idx[e.error]] += S.scale_model(q_si(p["axis"]), [p["ppm"]])[:, 0]
    elif n in ("squareness", "rotary_location"):
        errors[:, idx[p["error"]]] += p["value"]
    elif n == "cross_axis":
        own = p["error"][-1]
        errors[:, idx[p["error"]]] += S.cross_axis_model(q_of(own), q_of(p["on"]), [p["coefficient"]])[:, 0]
    elif n == "second_order":
        errors[:, idx[p["error"]]] += S.second_order_model(q_of(p["error"][-1]), [p["coefficient"]])[:, 0]
    elif n == "reversal_angular":  # the approach direction is that of the measured axis
        on = rows.axis == p["error"][-1]
        errors[on, idx[p["error"]]] += S.reversal_angular_model(rows.direction[on].astype(float),
                                                                [p["amount"]])[:, 0]
    elif n == "thermal_temperature":
        errors[:, idx[e.error]] += S.thermal_temperature_model(q_of(p["axis"]), e.delta_t(rows),
                                                                  [p["ppm_per_k"]])[:, 0]
    elif n == "axis_scatter":  # a variance component: the positioning repeats worse by sd at every reading
        on = rows.axis == p["axis"]
        errors[on, idx[e.error]] += np.random.default_rng(p["seed"]).normal(0.0, p["sd"], int(on.sum()))
    elif n == "backlash_travel":  # the grammar's direction x position (derive/grammar.py)
        on = rows.axis == p["axis"]
        d, q = rows.direction[on].astype(float), q_of(p["axis"])[on]
        errors[on, idx[e.error]] += S.backlash_travel_model(d, q, [p["amount"], p["slope"]])[:, 0]


def move_nests(e, rows, local: np.ndarray) -> None:
    """nest_creep, nest_knock: add the nest's creep or step to the reflector's local coordinates (n, 3) mm in
    place, before the exact kinematics carry them to the machine frame."""
    if e.name == "side_expansion":
        _expand(e, rows, local)
    if e.name not in ("nest_creep", "nest_knock"):
        return
    p = e.params
    on = (rows.point == p["point"]) & (rows.side == p["side"])
    if e.name == "nest_knock":  # the creep's model with a step for the time: displacement * [t >= t0]
        after = (rows.time_s[on] >= e.knock_time(rows)).astype(float)
        local[on] += S.nest_creep_model(p["size"] * unit(p["direction"]), after)
        return
    dt = np.maximum(rows.time_s[on] - p["t0_s"], 0.0)
    local[on] += S.nest_creep_model(p["rate_mm_s"] * unit(p["direction"]), dt)


def _expand(e, rows, local: np.ndarray) -> None:
    """side_expansion: the side's reflectors move apart about their layout's centroid (the side's local frame,
    mm), 1e-6 ppm_per_h (t - t0_s) / 3600 s (ramp) or 1e-6 ppm (1 - exp(-(t - t0_s) / tau_s)) (lag)."""
    p = e.params
    on = rows.side == p["side"]
    dt = np.maximum(rows.time_s[on] - p["t0_s"], 0.0)
    off = local[on] - e.centroid
    local[on] += (S.side_expansion_ramp_model(off, dt, [p["ppm_per_h"]]) if p["law"] == "ramp" else
                  S.side_expansion_lag_model(off, dt, p["tau_s"], [p["ppm"]]))


def apply_readings(e, rows, xyz: np.ndarray, tracker: np.ndarray) -> None:
    """Modify the readings (n, 3) in place."""
    p, n = e.params, e.name
    if n == "thermal_drift":
        side = {"spindle": "tool", "table": "table"}.get(p["target"])
        on = np.ones(len(rows), bool) if p["target"] == "tracker" else rows.side == side
        dt = np.maximum(rows.time_s[on] - p["t0_s"], 0.0)
        xyz[on] += S.thermal_drift_displacement(p["amplitude"] * unit(p["direction"]), dt, p["tau_s"])
    elif n == "outlier":
        xyz[e.outlier_rows(rows)] += p["size"] * unit(p["direction"])
    elif n == "offset":
        xyz[rows.time_s >= e.offset_time(rows)] += p["size"] * unit(p["direction"])
    elif n == "tracker_scale":
        xyz[:] = S.tracker_scale_reading(xyz, tracker, e.tracker_ppm())
    elif n == "thermal_temperature":
        on = rows.side == {"spindle": "tool", "table": "table"}[p["target"]]
        xyz[on] += S.thermal_temperature_displacement(p["drift_mm_per_k"] * unit(p["direction"]),
                                                      e.delta_t(rows)[on])
    elif n == "tracker_settling":
        xyz[:] = S.tracker_settling_reading(xyz, tracker, unit(p["about"]), e.settling_angle(rows.time_s))
    elif n == "air_index_drift":
        dt = np.maximum(rows.time_s - p["t0_s"], 0.0)
        xyz += (S.air_index_drift_ramp_model(xyz, tracker, dt, [p["ppm_per_h"]]) if p["law"] == "ramp" else
                S.air_index_drift_lag_model(xyz, tracker, dt, p["tau_s"], [p["ppm"]]))
    elif n == "tracker_relevel":  # a rotation step about the tracker (exact), from the round's first reading
        on = rows.time_s >= e.relevel_time(rows)
        xyz[on] = S.tracker_settling_reading(xyz[on], tracker, unit(p["about"]), p["angle_rad"])


def truth(e, rows=None) -> dict:
    """The planted truth: parameters, the affected error / axis, and derived values."""
    p = e.params
    out: dict[str, Any] = {"name": e.name, "params": {k: (None if isinstance(v, float) and math.isnan(v) else
                                                           list(v) if isinstance(v, tuple) else v)
                                                       for k, v in p.items()}}
    (_truth_of_errors if e.name in ERROR_EFFECTS else _truth_of_readings)(e, rows, out)
    return out


# the effects that act on the machine's error vector (``add_errors``); the others act on the readings
ERROR_EFFECTS = ("backlash", "periodic", "scale", "squareness", "rotary_location", "cross_axis", "second_order",
                 "reversal_angular", "thermal_temperature", "axis_scatter", "backlash_travel")


def _truth_of_errors(e, rows, out: dict) -> None:
    """``truth``'s entries of an effect on the error functions: the error and axis it acts on."""
    p, n = e.params, e.name
    if n in ("backlash", "periodic", "scale"):
        out.update(axis=p["axis"], error=e.error)
        if n == "backlash":
            out["reversal"] = p["amount"]
    elif n in ("squareness", "rotary_location"):
        out.update(error=p["error"], value=p["value"], axis=p["error"][-1])
    elif n in ("cross_axis", "second_order"):
        out.update(error=p["error"], axis=p["error"][-1])
    elif n == "reversal_angular":
        out.update(error=p["error"], axis=p["error"][-1], reversal=p["amount"])
    elif n == "thermal_temperature":
        out.update(axis=p["axis"], error=e.error, ppm_per_k=p["ppm_per_k"], drift_mm_per_k=p["drift_mm_per_k"])
        if rows is not None and rows.temperature_c is not None:
            dT = e.delta_t(rows)
            out.update(t_ref_c=float(rows.temperature_c[0] if math.isnan(p["t_ref_c"]) else p["t_ref_c"]),
                       delta_t_range_k=[float(dT.min()), float(dT.max())])
    elif n == "axis_scatter":
        out.update(axis=p["axis"], error=e.error)
    elif n == "backlash_travel":
        out.update(axis=p["axis"], error=e.error)
        if rows is not None:
            q = rows.position[rows.axis == p["axis"]]
            if len(q):
                ends = [float(q.min()), float(q.max())]
                out.update(travel=ends, reversal_at_ends=[p["amount"] + p["slope"] * v for v in ends])


def _truth_of_nests(e, rows, out: dict) -> None:
    """``truth``'s entries of a nest's creep or knock."""
    p = e.params
    if e.name == "nest_creep":
        out.update(point=p["point"], side=p["side"], rate_mm_s=p["rate_mm_s"], rate_um_h=p["rate_mm_s"] * 3.6e6,
                   direction=unit(p["direction"]).tolist())
        if rows is not None:  # the creep over the record (no extrapolation beyond it)
            on = (rows.point == p["point"]) & (rows.side == p["side"])
            span = float(np.maximum(rows.time_s[on] - p["t0_s"], 0.0).max()) if on.any() else 0.0
            out["displacement_mm"] = p["rate_mm_s"] * span
        return
    out.update(point=p["point"], side=p["side"], size=p["size"], direction=unit(p["direction"]).tolist())
    if rows is not None:
        t = e.knock_time(rows)
        on = (rows.point == p["point"]) & (rows.side == p["side"]) & (rows.time_s >= t)
        out.update(t0_s=t, readings_after=int(on.sum()),
                   from_axis=str(rows.axis[on][np.argmin(rows.time_s[on])]) if on.any() else None)


def _truth_of_readings(e, rows, out: dict) -> None:
    """``truth``'s entries of an effect on the readings (the tracker, the air, a nest, a side)."""
    p, n = e.params, e.name
    if n == "thermal_drift":
        out.update(direction=p["direction"], amplitude=p["amplitude"])
    elif n == "outlier":
        out.update(axis=p["axis"], direction=p["direction"])
        if rows is not None:
            out["rows"] = [{"axis": str(rows.axis[k]), "round": int(rows.round[k]),
                            "position": float(rows.position[k]), "point": str(rows.point[k]),
                            "direction": int(rows.direction[k])} for k in e.outlier_rows(rows)]
    elif n == "tracker_scale":
        out["ppm"] = e.tracker_ppm()
    elif n in ("nest_creep", "nest_knock"):
        _truth_of_nests(e, rows, out)
    elif n == "tracker_settling":
        out.update(about=unit(p["about"]).tolist())
        if rows is not None:
            out["angle_at_end_rad"] = float(e.settling_angle(rows.time_s.max()))
    elif n == "tracker_relevel":
        out.update(about=unit(p["about"]).tolist(), angle_rad=p["angle_rad"])
        if rows is not None:
            out["t0_s"] = e.relevel_time(rows)
    elif n == "side_expansion":
        out.update(side=p["side"], law=p["law"], centroid_local_mm=[float(v) for v in e.centroid])
    elif n == "air_index_drift":
        out.update(law=p["law"])
        if rows is not None:  # the scale at the last reading, ppm
            dt = max(float(rows.time_s.max()) - p["t0_s"], 0.0)
            out["ppm_at_end"] = (p["ppm_per_h"] * dt / 3600.0 if p["law"] == "ramp" else
                                 p["ppm"] * (1.0 - math.exp(-dt / p["tau_s"])))
    elif n == "offset":
        out.update(direction=p["direction"], size=p["size"])
        if rows is not None:
            t = e.offset_time(rows)
            i = np.flatnonzero(rows.time_s >= t)
            out["t_from_s"] = t
            if len(i):
                out["first_row"] = {"axis": str(rows.axis[i[0]]), "round": int(rows.round[i[0]]),
                                    "position": float(rows.position[i[0]]), "point": str(rows.point[i[0]])}
