"""Posterior predictive check of every named finding (issue 24 item 3): the effect, at its estimated size, is
planted through the physical simulator into the recording's own schedule, and what it does to the readings,
pushed through the same base, must reproduce the residual pattern the finding claims.

The simulator is mtcal.campaign's (``Effect``: each effect's own physical model, the exact error-inclusive
kinematics for the machine's errors), run noiseless on the recording's rows: axes, reflectors (their positions
from the reference readings, ``Prepared.local``), times, directions and temperatures, about the tracker the noise
model uses.  The displacement d (n, 3) mm it predicts is weighted like the readings and the base's columns are
projected out: p.  The finding's partial residual o (the residual after every selected effect plus what this one
adds beyond the base) is what the recording shows.  Two numbers:

* ``reproduced`` = <p, o> / <p, p>: the share of the predicted pattern the recording holds (1 when the finding's
  size and shape are right), with its standard uncertainty sigma / |p|;
* ``misfit``: chi^2 per degree of freedom of o - p over the readings the effect moves, and its p value (the
  residual there beyond the noise the rest of the recording shows: a pattern the effect claims but does not make).

A finding passes when ``reproduced`` is within PREDICTIVE_TOL (and 3 uncertainties) of 1 and the misfit's p value,
Bonferroni over the named findings, is not below the level.  One that fails stays reported, with the check and
an ``unexplained`` entry in ``confounded_with`` (what the recording holds there is not only this effect).  A
finding with no model in the simulator (a free-form shape; a tracker drift, scale or settling of one station of
several) says so instead.  Units: mm, machine frame; whitened sums."""
from __future__ import annotations

import math

import numpy as np

from mtcal import _tails
from mtcal.campaign.effects import Effect, Rows
from mtcal.campaign.simulate import exact_points
from mtcal.diagnose.engine import Engine
from mtcal.diagnose.prepare import axis_values
from mtcal.diagnose.prepared import Prepared
from mtcal.diagnose.report import Finding
from mtcal.errors import InputError

PREDICTIVE_TOL = 0.2  # |reproduced - 1| allowed beyond 3 uncertainties: the simulator's exact model against the
#                       fit's first-order columns (equal to ~1e-6 for the sizes of a machine's errors)


def rows_of(prep: Prepared) -> Rows:
    """The recording's schedule as the simulator's rows (the other axes at zero, as the diagnosis' Jacobians)."""
    rec = prep.rec
    t = np.where(np.isfinite(rec.time_s), rec.time_s, 0.0)
    return Rows(rec.axis, rec.round, rec.position, rec.point, rec.direction, t,
                axis_values(rec, prep.machine, prep.axes), prep.geometry.side, prep.local, rec.temperature_c)


def _vector(v: np.ndarray) -> tuple[float, str]:
    """(length, 'a;b;c' unit direction) of a 3-vector."""
    n = float(np.linalg.norm(v))
    u = v / n if n > 0 else np.array([0.0, 0.0, 1.0])
    return n, ";".join(f"{c:.17g}" for c in u)


def effects_of(f: Finding, prep: Prepared) -> list[Effect] | str:
    """The simulator's effects that make finding ``f`` at its estimate, or why there are none."""
    c, th, x = f.candidate, np.asarray(f.theta, float), f.candidate.extra
    if x.get("station"):
        return "an effect of one station of several: the simulator has one tracker"
    n = c.name
    out = _of_errors(n, c, th, x)
    if out is None:
        out = _of_readings(n, f, prep, th, x)
    return f"no model of {n} in the simulator" if out is None else out


def _of_errors(n: str, c, th: np.ndarray, x: dict) -> list[Effect] | None:
    """``effects_of`` for the effects on the machine's error functions (None: not one of them)."""
    if n in ("backlash", "scale", "reversal_angular"):
        key = {"backlash": "amount", "scale": "ppm", "reversal_angular": "amount"}[n]
        where = {"error": x["error"]} if n == "reversal_angular" else {"axis": c.axis}
        return [Effect(n, {**where, key: float(th[0])})]
    if n == "second_order":
        return [Effect(n, {"error": x["error"], "coefficient": float(th[0])})]
    if n in ("squareness", "rotary_location"):
        errors = x["error"] if isinstance(x["error"], list) else [x["error"]]
        return [Effect(n, {"error": e, "value": float(v)}) for e, v in zip(errors, th)]
    if n == "periodic":  # a_s sin + a_c cos = A sin(. + phase)
        return [Effect(n, {"axis": c.axis, "amplitude": float(math.hypot(th[0], th[1])), "pitch": x["pitch"],
                           "phase_deg": math.degrees(math.atan2(th[1], th[0]))})]
    if n == "backlash_travel":
        return [Effect(n, {"axis": c.axis, "amount": float(th[0]), "slope": float(th[1])})]
    return None


def _of_readings(n: str, f: Finding, prep: Prepared, th: np.ndarray, x: dict) -> list[Effect] | str | None:
    """``effects_of`` for the effects on the readings (None: not one of them)."""
    c = f.candidate
    if n == "thermal_drift":
        size, d = _vector(th)
        return [Effect(n, {"amplitude": size, "direction": d, "tau_s": x["tau_s"], "t0_s": x["t0_s"],
                           "target": x["target"], "temperature_rise_c": 0.0})]
    if n in ("nest_creep", "nest_knock"):
        size, d = _vector(th)
        key = "rate_mm_s" if n == "nest_creep" else "size"
        return [Effect(n, {"point": x["point"], "side": x["side"], key: size, "direction": d, "t0_s": x["t0_s"]})]
    if n == "offset" and x.get("variant") == "tracker knock":
        size, d = _vector(th)
        return [Effect("offset", {"size": size, "direction": d, "t_from_s": x["t0_s"]})]
    if n in ("outlier", "offset"):  # a re-seated nest: its whole (axis, round, point) sequence, a bump from its first
        return _displaced(f, prep, th)
    if n == "tracker_settling":  # rotation vector w dt + a (1 - exp(-dt / tau)): a ramp about w, a settling about a
        (rate, about_w), (angle, about_a) = _vector(th[0::2]), _vector(th[1::2])
        common = {"tau_s": x["tau_s"], "t0_s": x["t0_s"]}
        return [Effect(n, {"rate_rad_s": rate, "angle_rad": 0.0, "about": about_w, **common}),
                Effect(n, {"rate_rad_s": 0.0, "angle_rad": angle, "about": about_a, **common})]
    if n == "tracker_scale":
        return [Effect(n, {"ppm": float(th[0])})]
    if n == "side_expansion":
        if x.get("centre"):
            return "an expansion about a fitted centre: the simulator grows a side about its reflectors' centroid"
        law = {"ppm_per_h": float(th[0])} if x["law"] == "ramp" else {"ppm": float(th[0]), "tau_s": x["tau_s"]}
        return [Effect(n, {"side": x["side"], "law": x["law"], "t0_s": x["t0_s"], **law})]
    if n == "air_index_drift":
        if x["stations"] > 1:
            return "an effect of several stations: the simulator has one tracker"
        law = {"ppm_per_h": float(th[0])} if x["law"] == "ramp" else {"ppm": float(th[0]), "tau_s": x["tau_s"]}
        return [Effect(n, {"law": x["law"], "t0_s": x["t0_s"], **law})]
    if n == "tracker_relevel":
        if x.get("pivot"):
            return "a turn about the readings' centre (no station known): the simulator turns about its tracker"
        angle, about = _vector(np.array([th[0], th[1], 0.0]))
        out = [Effect(n, {"axis": x["from_axis"], "round": x["round"], "angle_rad": angle, "about": about})]
        if x.get("shift"):  # its shift: the tracker knocked at the same t0
            size, d = _vector(th[2:5])
            out.append(Effect("offset", {"size": size, "direction": d, "t_from_s": x["t0_s"]}))
        return out
    if n == "thermal_temperature":
        t_ref = float(prep.rec.temperature_c[np.argmin(prep.order)])
        if x.get("variant") == "expansion":
            return [Effect(n, {"axis": c.axis, "ppm_per_k": float(th[0]), "t_ref_c": t_ref})]
        size, d = _vector(th)
        return [Effect(n, {"ppm_per_k": 0.0, "drift_mm_per_k": size, "direction": d, "target": x["target"],
                           "t_ref_c": t_ref})]
    return None


def _displaced(f: Finding, prep: Prepared, th: np.ndarray) -> list[Effect]:
    """An outlier reading, a bump (the rest of the round) or a re-seated nest (its whole sequence: a bump from its
    first reading) as the simulator's outlier."""
    rows = np.flatnonzero(f.touched)
    first = rows[np.argmin(prep.order[rows])]
    rec = prep.rec
    size, d = _vector(th)
    mode = "reading" if len(rows) == 1 else "bump"
    return [Effect("outlier", {"axis": str(rec.axis[first]), "round": int(rec.round[first]),
                               "position": float(rec.position[first]), "point": str(rec.point[first]),
                               "size": size, "direction": d, "mode": mode, "approach": int(rec.direction[first])})]


def simulated(prep: Prepared, effects: list[Effect]) -> np.ndarray:
    """(n, 3) mm: what ``effects`` move the recording's readings by, through the simulator (noiseless, no other
    error: the difference of the exact kinematics with and without them)."""
    m, rows = prep.machine, rows_of(prep)
    points = {"tool": {}, "table": {}}
    for s, p, loc in zip(rows.side.tolist(), rows.point.tolist(), rows.local):
        points[s].setdefault(p, tuple(loc))
    bound = [e.bind(m, points) for e in effects]
    local = rows.local.copy()
    for e in bound:
        e.move_nests(rows, local)
    errors = np.zeros((len(rows), len(m.error_names)))
    for e in bound:
        e.add_errors(rows, errors, m)
    base = exact_points(m, rows, np.zeros_like(errors))
    xyz = exact_points(m, Rows(**{**rows.__dict__, "local": local}), errors)
    tracker = prep.geometry.tracker if prep.geometry.tracker is not None else np.zeros(3)
    for e in bound:
        e.apply_readings(rows, xyz, tracker)
    return xyz - base


def check(prep: Prepared, base: Engine, f: Finding, r_after: np.ndarray, sigma: float, n_named: int,
          level: float) -> dict:
    """The check of one finding (module docstring): ``base`` the reported base's engine, ``r_after`` (3n,) the
    whitened residual after every selected effect, ``sigma`` its scale, ``n_named`` the findings checked."""
    try:
        eff = effects_of(f, prep)
        if isinstance(eff, str):
            return {"checked": False, "why": eff}
        d = simulated(prep, eff)
    except InputError as exc:  # e.g. an outlier at a reading of no approach direction: the simulator cannot place it
        return {"checked": False, "why": f"the simulator refuses it: {exc}"}
    Wd = np.einsum("nij,nj->ni", prep.W, d).reshape(-1)
    p = Wd - base.project(Wd[:, None])[:, 0]
    o = r_after + f.fitted
    pp = float(p @ p)
    if pp <= 0:
        return {"checked": False, "why": "the simulated effect is inside the base"}
    beta, u = float(p @ o) / pp, sigma / math.sqrt(pp)
    moved = np.repeat(np.linalg.norm(d, axis=1) > 1e-3 * np.abs(d).max(), 3)
    k = int(moved.sum())
    chi2 = float(np.sum((o - p)[moved] ** 2)) / sigma**2
    p_misfit = float(_tails.chi2_sf(chi2, k)) if k else 1.0
    ok = abs(beta - 1) <= PREDICTIVE_TOL + 3 * u and min(1.0, p_misfit * n_named) >= level
    return {"checked": True, "simulated_with": [{"name": e.name, **_plain(e.params)} for e in eff],
            "reproduced": beta, "reproduced_u": u, "misfit_chi2_per_dof": chi2 / max(k, 1),
            "misfit_p_adjusted": min(1.0, p_misfit * n_named), "readings_moved": k // 3, "passes": bool(ok)}


def _plain(params: dict) -> dict:
    """The simulator's parameters as JSON values (NaN: None)."""
    return {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in params.items()
            if v is not None}


def predictive_checks(prep: Prepared, base: Engine, findings: list[Finding], r_after: np.ndarray, sigma: float,
                      level: float) -> None:
    """Check every significant named finding (module docstring) and record the check in its details
    (``predictive_check``); one that fails gets an ``unexplained`` entry in ``confounded_with``."""
    named = [f for f in findings if f.significant and f.candidate is not None]
    for f in named:
        res = check(prep, base, f, r_after, sigma, len(named), level)
        f.details["predictive_check"] = res
        if res.get("checked") and not res["passes"]:
            f.details.setdefault("confounded_with", []).append(
                {"name": "unexplained", "axis": f.axis, "where": "the readings it moves",
                 "why": f"simulated at its estimate it reproduces {res['reproduced']:.2f} of the pattern, "
                        f"misfit left chi^2/dof {res['misfit_chi2_per_dof']:.2f}"})
