"""The answer of the diagnosis: typed findings and their JSON form (docs/design.md's contract), headlines of the
estimates, the alias (Nyquist) check of periodic findings, ramps over the record, and the residual plots.

JSON keys beyond docs/design.md's (documented in the docs): "noise_model" (how the readings were weighted),
"unexplained" (located mismatches no candidate explains), per effect "confounded_with" (candidates this
campaign cannot tell apart from it, each with "separate_by"), "possible_alias" (periodic: pitches that give
the same readings), "variant": "ramp over the record" (thermal drift whose time constant exceeds the record).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mtcal.diagnose import effects as fx
from mtcal.diagnose.engine import Engine
from mtcal.diagnose.noise import NoiseModel
from mtcal.diagnose.prepare import Prepared
from mtcal.diagnose.scans import Beyond, Located, beyond_fit
from mtcal.io import save_figure

ALIKE = 0.9  # an error motion whose own growing member fits this share of the best one's: alike through the beams
#             (an anisotropic tracker sees mostly the beam's component: gen2 3581/30, a straightness E_YZ of Z
#             fitted as well by E_ZZ where the beams run along Y and Z)


@dataclass
class Finding:
    """One effect of the answer; ``details`` holds the effect-specific keys (estimate's unit, vector, where, ...).
    Reads like its JSON dict (``f["name"]``, ``f.get("where")``)."""

    name: str
    axis: str | None
    direction: str | None
    significant: bool
    estimate: float | None
    sigma_after: float | None
    evidence: dict | None
    details: dict = field(default_factory=dict)
    # what the effect adds to the fit beyond the base (whitened, (3 n,)): its picture (mtcal.diagnose.pictures)
    fitted: np.ndarray | None = field(default=None, repr=False, compare=False)
    touched: np.ndarray | None = field(default=None, repr=False, compare=False)  # (n,) the readings it moves
    # the candidate and its joint estimate (parameters in the candidate's units): the predictive check's input
    candidate: Any = field(default=None, repr=False, compare=False)
    theta: np.ndarray | None = field(default=None, repr=False, compare=False)

    def to_dict(self) -> dict:
        return {"name": self.name, "axis": self.axis, "direction": self.direction, "significant": self.significant,
                "estimate": self.estimate, "sigma_after": self.sigma_after, "evidence": self.evidence,
                **self.details}

    def __getitem__(self, key: str) -> Any:
        return self.to_dict()[key]

    def get(self, key: str, default: Any = None) -> Any:
        return self.to_dict().get(key, default)

    def __contains__(self, key: str) -> bool:
        return key in self.to_dict()


@dataclass
class Diagnosis:
    """The diagnosis of a recording: the noise left by the quasi-static model, the effects found, the mismatches
    located but not named.  ``to_dict()`` is the JSON answer of `mtcal diagnose` (docs/design.md).

    Attributes
    ----------
    base_sigma : float
        RMS of the whitened residual of the base (quasi-static) model, mm.
    base_sigma_ratio : float
        That residual relative to the noise model (1: the tracker's specification).
    sigma_after : float
        The same after the effects found are fitted, mm.
    sigma_ratio_after : float
        Its ratio to the noise model.
    effects : list of Finding
        Every candidate effect tested, ``significant`` or not, with its estimate and evidence (reads like its JSON
        dict: ``f["name"]``, ``f.get("where")``).
    located : list of Located
        Where the residual is larger than the noise (axis, position, reflector, round).
    base : dict
        The base model: degrees of the fitted error functions, parameters.
    noise : NoiseModel
        The noise model the readings were weighted by (the tracker's law, checked by the rounds).
    unexplained : list of Located
        Mismatches no named effect explains.
    notes : list of str
        What the data cannot separate, and why (``not separable: ...``).
    residuals_before : numpy.ndarray or None
        Residuals of the base model (n, 3), mm.
    residuals_after : numpy.ndarray or None
        Residuals with the effects, (n, 3), mm.
    prep : Prepared or None
        The prepared problem (machine, recording, design).
    data_problems : list of dict
        Gross errors found and left out (mtcal.measurement.screen).
    """

    base_sigma: float
    base_sigma_ratio: float
    sigma_after: float
    sigma_ratio_after: float
    effects: list[Finding]
    located: list[Located]
    base: dict
    noise: NoiseModel
    unexplained: list[Located] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    residuals_before: np.ndarray | None = None
    residuals_after: np.ndarray | None = None
    prep: Prepared | None = None
    data_problems: list[dict] = field(default_factory=list)  # gross errors left out (mtcal.measurement.screen)

    def to_dict(self) -> dict:
        return {**({"machine": self.prep.machine.name, "recording": self.prep.rec.source} if self.prep else {}),
                "base_sigma": self.base_sigma, "base_sigma_ratio": self.base_sigma_ratio,
                "sigma_after": self.sigma_after, "sigma_ratio_after": self.sigma_ratio_after,
                "effects": [e.to_dict() for e in self.effects], "located": [x.to_dict() for x in self.located],
                "unexplained": [_unexplained(x) for x in self.unexplained],
                "base_model": self.base, "noise_model": self.noise.to_dict(),
                "units": {"length": "mm", "angle": "rad", "position": "mm (linear axes) or deg (rotary axes)",
                          "sigma_ratio": "1 = the tracker's specification (noise_model.law) when the readings are "
                                         "weighted by it (noise_model)"},
                **({"data_problems": self.data_problems} if self.data_problems else {}),
                "notes": self.notes}


def _unexplained(x: Located) -> dict:
    return {"axis": x.axis, "by": x.by, "where": x.where, "size_mm": x.shift_mm if x.kind == "mean" else None,
            "size_sd_mm": x.shift_sd_mm if x.kind == "mean" else None,
            "kind": x.kind, "p_adjusted": x.p_adjusted, "readings": x.readings,
            "chi2_per_dof": x.mean_shift_chi2_per_dof if x.kind == "mean" else x.spread_chi2_per_dof,
            "note": x.note}


def beyond(prep: Prepared, beside: Engine, c: fx.Candidate, w, sigma: float) -> Beyond:
    """The displacement the free form ``c`` adds beyond ``beside`` (the base and every other selected entry;
    mtcal.diagnose.scans.beyond_fit): a motion the base or another entry can take (a shared drift, a reflector's
    position) is not counted again; ``sigma``: the residual scale of the whole fit."""
    return beyond_fit(prep.W, beside, w(c), sigma)


def free_form_located(prep: Prepared, beside: Engine, s, w, sigma: float) -> Located:
    """A selected free-form candidate (a misfit no named effect explains) as an unexplained, located mismatch,
    sized by the displacement its fit adds beyond the base and every other entry (``beside``; :func:`beyond`) at
    the reading where it is largest, with its standard uncertainty (``shift_sd_mm``) -- never a raw coefficient of
    the free form, which the base could trade against: a free-form reversal (direction x point) names that
    reading's reflector; a position x time free form by ``_growing_located``; a place's free form by
    ``_place_located``."""
    c = s.candidate
    b = beyond(prep, beside, c, w, sigma)
    if c.extra.get("kind") == "growing":
        return _growing_located(prep, beside, c, s, b, w)
    if c.extra.get("kind") == "place":
        return _place_located(prep, c, s, b, (c.extra.get("at_axis") or _seen_most(prep, beside, c, b.theta, w))
                              if "names" in c.extra else None)
    k, size, sd = b.largest()
    if c.extra.get("kind") == "instrument":
        return _instrument_located(prep, c, s, b, k, size, sd)
    note = ("the readings differ between the directions of approach, and differently for each reflector, beyond "
            "what the rigid reversals of the axis (backlash, straightness and angular reversals) explain together; "
            f"largest beyond the base: {size * 1e3:.2f} +- {sd * 1e3:.2f} um at reflector {prep.rec.point[k]} "
            "(a reading's displacement: half its reversal, reading(+ approach) - reading(- approach))")
    return Located(c.axis, "direction x point", c.label, float(-s.logp_adj / math.log(10)),
                   min(1.0, math.exp(s.logp_adj)), "mean", int(np.sum(c.moved)), s.score.F,
                   0.0, size, note, sd)


def _instrument_located(prep: Prepared, c: fx.Candidate, s, b: Beyond, k: int, size: float, sd: float) -> Located:
    """A selected error map of the tracker (effects.instrument_map) as an unexplained mismatch at the station: the
    tracker reads one of its own coordinates off by a function of it, the same in every round; sized as the others
    (the largest displacement it adds beyond the base, a reading's)."""
    what, of = c.extra["coordinate"], f" of station {c.extra['station']}" if "station" in c.extra else ""
    note = (f"the tracker{of} reads its {what} off by a function of the {what}, the same in every round and at "
            f"every reflector (a distance meter's or an angle encoder's error map: {c.extra['spans']} spline "
            f"intervals over the {what}s read): up to {size * 1e3:.2f} +- {sd * 1e3:.2f} um at a reading beyond the "
            f"base (reflector {prep.rec.point[k]}); measure from a second station, or compare the instrument with "
            "a reference over the same distances and angles, to name it")
    return Located(None, f"tracker {what}", c.label, float(-s.logp_adj / math.log(10)),
                   min(1.0, math.exp(s.logp_adj)), "mean", int(b.moved.sum()), s.score.F, 0.0, size, note, sd)


def _growing_located(prep: Prepared, eng: Engine, c: fx.Candidate, s, b: Beyond, w) -> Located:
    """A selected position x time free form as an unexplained mismatch: its size is the largest displacement it
    adds beyond the base and the other entries (mm, a reading's, :func:`beyond`), and the error motion whose own
    columns explain the most of it is named in the note with what would name the physics."""
    k, size, sd = b.largest()
    errors = c.extra["errors"]
    if len(errors) == 1:  # one motion's member: the others' own members, as alike through these beams or not
        errors = list(prep.machine.error_motions(c.axis))
        share = [eng.score(w(fx.growing_free(prep.geometry, c.axis, motion=e))).delta for e in errors]
    else:
        per = len(c.params) // len(errors)
        share = [eng.score(w(fx.Candidate(c.name, c.axis, "", c.G[:, :, j * per:(j + 1) * per], []))).delta
                 for j in range(len(errors))]
    j = int(np.argmax(share))
    frac = share[j] / max(s.score.delta, 1e-300)
    alike = [e for e, d in zip(errors, share) if e != errors[j] and d >= ALIKE * share[j]]
    note = (f"the error motions of axis {c.axis} change while it is measured (position x time: not a drift of a "
            f"side, which moves every position alike): up to {size * 1e3:.2f} +- {sd * 1e3:.2f} um at a reading "
            f"beyond the base, mostly {errors[j]} ({min(frac, 1.0):.0%} of it alone"
            + (f"; {' or '.join(alike)} fit{'s' if len(alike) == 1 else ''} it alike through these beams" if alike
               else "") + "); a scale or straightness growing with the machine's "
            "temperature (e.g. a ball screw warming): record a temperature channel (temperature_c) and the "
            "diagnosis names it (thermal_temperature), or let the axis reach a steady temperature first")
    return Located(c.axis, "position x time", errors[j], float(-s.logp_adj / math.log(10)),
                   min(1.0, math.exp(s.logp_adj)), "mean", int(b.moved.sum()),
                   s.score.F, 0.0, size, note, sd)


def _seen_most(prep: Prepared, eng: Engine, c: fx.Candidate, theta: np.ndarray, w) -> str:
    """The axis whose readings show most of what the free form ``c`` fits (``theta``) beyond the base, among the
    readings its named effects all move (``common``, where they agree the misfit is; all where none is): the sum
    over the axis' readings of the squared whitened fit after the base's projection (a step of every later
    reading is mostly the base's offsets where it is constant, and seen where the base cannot take it).  Used
    where the leading effect names no axis its change happens in (``at_axis``: a knock's, a re-levelling's is
    where it is located, as a step at t0 shows on either side of it wherever the station's alignment puts it:
    gen2 3553/21, a knock within X's second round tied with a re-levelling at Y's block start, was put on B among
    the readings both move, and 3560/32, a knock and a re-levelling of S3 at Z's block start, on X among all)."""
    G = w(c)
    f = ((G - eng.copy_base().project(G)) @ theta).reshape(len(prep.rec), -1)
    on = c.extra["common"] if c.extra["common"].any() else np.ones(len(prep.rec), bool)
    axes = list(dict.fromkeys(prep.rec.axis[on].tolist()))
    return max(axes, key=lambda a: float(np.sum(f[on & (prep.rec.axis == a)] ** 2)))


def _place_located(prep: Prepared, c: fx.Candidate, s, b: Beyond, axis: str | None = None) -> Located:
    """A selected free form of a named effect's place (mtcal.diagnose.places) as an unexplained mismatch: where
    (the place, and ``axis`` or else the axis of the reading it moves most), its shape (``by``), the largest
    displacement it adds beyond the base and the other entries at a reading (mm, machine frame, :func:`beyond`,
    with its standard uncertainty) and when and where that is, with the place's words."""
    k, size, sd = b.largest()
    rec = prep.rec
    at = (f"; largest beyond the base {size * 1e3:.2f} +- {sd * 1e3:.2f} um at axis {rec.axis[k]} round "
          f"{int(rec.round[k])} point {rec.point[k]} at {rec.position[k]:g}"
          + (f", t = {rec.time_s[k]:.0f} s" if np.isfinite(rec.time_s[k]) else ""))
    return Located(axis or c.axis or str(rec.axis[k]), c.extra["by"], f"{c.extra['place']}: {c.label}",
                   float(-s.logp_adj / math.log(10)), min(1.0, math.exp(s.logp_adj)), "mean",
                   int(b.moved.sum()), s.score.F, 0.0, size, c.extra["note"] + at, sd)


def headline(c: fx.Candidate, theta: np.ndarray, cov: np.ndarray) -> dict:
    """The reported estimate (one number with its unit and standard uncertainty) and all parameters."""
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    params = {p: float(v) for p, v in zip(c.params, theta)}
    if c.name in GRAMMAR_HEADLINES:  # issue 34's members: their figure, interval and words
        return {**GRAMMAR_HEADLINES[c.name](c, theta, cov), "parameters": params, "direction": None}
    if c.name == "periodic":
        amp = float(np.hypot(*theta))
        g = theta / amp if amp > 0 else np.zeros(2)
        u = float(math.sqrt(max(g @ cov @ g, 0.0)))
        params["phase_deg"] = float(np.degrees(np.arctan2(theta[1], theta[0])))
        return {"estimate": amp, "uncertainty": u, "unit": c.extra["amplitude_unit"],
                "parameters": params, "direction": None}
    if c.extra.get("variant") == "tracker knock" or c.name == "nest_knock":  # a step: its size (mm), from t0 on
        size = float(np.linalg.norm(theta))
        g = theta / size if size > 0 else np.zeros(3)
        k = int(np.argmax(np.abs(theta)))
        return {"estimate": size, "uncertainty": float(math.sqrt(max(g @ cov @ g, 0.0))), "unit": "mm",
                "parameters": params, "direction": ("+" if theta[k] >= 0 else "-") + "XYZ"[k],
                "unit_vector": [float(v) for v in g], "t0_s": c.extra["t0_s"],
                "vector": [float(v) for v in theta], "vector_uncertainty": [float(v) for v in sd]}
    if c.name == "tracker_settling":  # the rotation reached at the end of the record (no extrapolation), rad
        dt = c.extra["t_end_s"] - c.extra["t0_s"]
        M = np.kron(np.eye(3), [[dt, 1.0 - math.exp(-dt / c.extra["tau_s"])]])   # (3, 6): rotation vector
        rot, rcov = M @ theta, M @ cov @ M.T
        size = float(np.linalg.norm(rot))
        gv = rot / size if size > 0 else np.zeros(3)
        k = int(np.argmax(np.abs(rot)))
        return {"estimate": size, "uncertainty": float(math.sqrt(max(gv @ rcov @ gv, 0.0))), "unit": "rad",
                "parameters": params, "direction": ("+" if rot[k] >= 0 else "-") + "XYZ"[k],
                "rotation_vector": [float(v) for v in rot], "record_s": dt,
                "note": "rotation of the readings about the tracker reached at the end of the record"}
    if c.name in ("thermal_drift", "outlier", "offset", "nest_creep") or c.extra.get("variant") == "drift":
        k = int(np.argmax(np.abs(theta) / np.maximum(sd, 1e-300)))  # the best-determined component
        unit = {"nest_creep": "mm/s", "thermal_temperature": "mm/K"}.get(c.name, "mm")
        return {"estimate": float(abs(theta[k])), "uncertainty": float(sd[k]), "unit": unit, "parameters": params,
                "direction": ("+" if theta[k] >= 0 else "-") + "XYZ"[k],
                "vector": [float(v) for v in theta], "vector_uncertainty": [float(v) for v in sd]}
    k = int(np.argmax(np.abs(theta) / np.maximum(sd, 1e-300)))  # several constants: the best-determined
    unit = c.params[k].split("(")[-1].rstrip(")") if "(" in c.params[k] else c.params[k]
    return {"estimate": float(theta[k]), "uncertainty": float(sd[k]), "unit": unit, "parameters": params,
            "direction": None, **({"error": c.params[k].split(" ")[0]} if len(theta) > 1 else {})}


Z95 = 1.959964  # the normal distribution's 97.5 % point: 95 % intervals of linear functions of the estimate


def _linear(a: np.ndarray, theta: np.ndarray, cov: np.ndarray) -> tuple[float, float, list[float]]:
    """The estimate a . theta, its standard uncertainty and 95 % interval."""
    v, u = float(a @ theta), float(math.sqrt(max(a @ cov @ a, 0.0)))
    return v, u, [v - Z95 * u, v + Z95 * u]


def _um(v: float, unit: str) -> str:
    """A length (mm) in um or an angle (rad) in urad, for the words."""
    return f"{v * 1e3:.2g} um" if unit == "mm" else f"{v * 1e6:.2g} urad"


def _side_expansion_head(c: fx.Candidate, theta: np.ndarray, cov: np.ndarray) -> dict:
    """side_expansion: the growth of the side's layout (ppm per hour for a ramp, ppm for a lag's final value; a lag
    whose time constant exceeds the record: its mean rate over the record, ppm per hour, no final value)."""
    side, ramp_law, x = c.extra["side"], c.extra["law"] == "ramp", c.extra
    record = x["t_end_s"] - x["t0_s"]
    slow = not ramp_law and x["tau_s"] > record > 0  # a lag beyond the record: its mean rate over the record
    scale = (1.0 - math.exp(-record / x["tau_s"])) / (record / 3600.0) if slow else 1.0
    a = np.zeros(len(theta))
    a[0] = scale
    v, u, ci = _linear(a, theta, cov)
    ramp_law = ramp_law or slow
    how = "move apart" if v >= 0 else "move together"
    warm = f"a {'warming' if v >= 0 else 'cooling'} {'table' if side == 'table' else 'spindle side'}"
    rate = (f"{abs(v):.2g} ppm per hour (95 %: {ci[0]:.2g} to {ci[1]:.2g})" if ramp_law else
            f"by {abs(v):.2g} ppm with a time constant of {c.extra['tau_s']:.0f} s (95 %: {ci[0]:.2g} to "
            f"{ci[1]:.2g} ppm)")
    return {"estimate": v, "uncertainty": u, "unit": "ppm/h" if ramp_law else "ppm", "interval_95": ci,
            **({"law": "ramp over the record", "record_s": record,
                "note": f"time constant beyond the record ({x['tau_s']:.0f} s > {record:.0f} s): the mean rate "
                        "over the record is reported, no final value"} if slow else {}),
            **_centre(theta, cov),
            "says": f"the {side}-side reflectors {how} {rate} about {_about(theta)}: {warm}"}


def _centre(theta: np.ndarray, cov: np.ndarray) -> dict:
    """A side_expansion about a fitted centre: the centre less the reflectors' centroid (mm, the side's frame),
    -theta[1:4] / theta[0], with its standard uncertainty to first order; {} about the centroid."""
    if len(theta) < 4 or theta[0] == 0:
        return {}
    d = -theta[1:4] / theta[0]
    J = np.hstack([(theta[1:4] / theta[0] ** 2)[:, None], -np.eye(3) / theta[0]])
    u = np.sqrt(np.maximum(np.diag(J @ cov[:4, :4] @ J.T), 0.0))
    return {"centre_from_centroid_mm": d.tolist(), "centre_uncertainty_mm": u.tolist()}


def _about(theta: np.ndarray) -> str:
    """Where a side's expansion is about, in words."""
    if len(theta) < 4 or theta[0] == 0:
        return "their centroid"
    return (f"a point {np.linalg.norm(theta[1:4] / theta[0]):.0f} mm from their centroid (the centre fitted: "
            "centre_from_centroid_mm)")


def _backlash_travel_head(c: fx.Candidate, theta: np.ndarray, cov: np.ndarray) -> dict:
    """backlash_travel: the reversal at both ends of the measured travel (the estimate: at the end where it is
    larger), each with its 95 % interval."""
    unit, qu = c.extra["unit"], c.extra["position_unit"]
    ends = [(q, *_linear(np.array([1.0, q]), theta, cov)) for q in c.extra["travel"]]
    far = max(ends, key=lambda e: abs(e[1]))
    grows = "grows" if abs(ends[1][1]) > abs(ends[0][1]) else "shrinks"
    return {"estimate": far[1], "uncertainty": far[2], "unit": unit, "interval_95": far[3],
            "reversal_at_ends": [{"position": q, "reversal": v, "uncertainty": u, "interval_95": ci}
                                 for q, v, u, ci in ends],
            "says": f"the lost motion of {c.axis} {grows} along the travel: {_um(abs(ends[0][1]), unit)} at "
                    f"{ends[0][0]:g} {qu} to {_um(abs(ends[1][1]), unit)} at {ends[1][0]:g} {qu} (reversal "
                    f"error(+) - error(-); 95 %: {_um(ends[0][3][0], unit)} to {_um(ends[0][3][1], unit)} and "
                    f"{_um(ends[1][3][0], unit)} to {_um(ends[1][3][1], unit)})"}


def _tracker_relevel_head(c: fx.Candidate, theta: np.ndarray, cov: np.ndarray) -> dict:
    """tracker_relevel: the size of the rotation step (rad) about the horizontal axis it turns about; with its
    shift (``extra["shift"]``), the shift's vector (mm, machine frame) and its standard uncertainties too."""
    w, wc = theta[:2], cov[:2, :2]
    size = float(np.linalg.norm(w))
    a = w / size if size > 0 else np.array([1.0, 0.0])
    _, u, ci = _linear(a, w, wc)
    about = [float(a[0]), float(a[1]), 0.0]
    shift = {}
    words = ""
    if c.extra.get("shift"):
        v = theta[2:5]
        shift = {"shift_mm": [float(x) for x in v],
                 "shift_uncertainty_mm": [float(math.sqrt(max(x, 0.0))) for x in np.diag(cov)[2:5]]}
        words = f", and shifted {np.linalg.norm(v) * 1e3:.2g} um ({', '.join(f'{x * 1e3:.2g}' for x in v)} um)"
    through = "it" if "pivot" not in c.extra else "the readings' centre (no station known; the shift is at it)"
    return {"estimate": size, "uncertainty": u, "unit": "rad", "interval_95": [max(ci[0], 0.0), ci[1]],
            "rotation_vector": [float(w[0]), float(w[1]), 0.0], "about": about, "t0_s": c.extra["t0_s"], **shift,
            "says": f"the tracker was re-levelled before round {c.extra['round']} of {c.extra['from_axis']}: every "
                    f"later reading turned {size * 1e6:.2g} urad (95 %: {max(ci[0], 0.0) * 1e6:.2g} to "
                    f"{ci[1] * 1e6:.2g}) about the horizontal axis ({about[0]:.2f}, {about[1]:.2f}, 0) through "
                    f"{through}{words}"}


def _air_index_drift_head(c: fx.Candidate, theta: np.ndarray, cov: np.ndarray) -> dict:
    """air_index_drift: the change of the tracker's distance scale (ppm per hour for a ramp, ppm for a lag's final
    value; a lag whose time constant exceeds the record: its mean rate over the record, ppm per hour), and the
    air temperature change it amounts to at about 1 ppm per K (mtcal.campaign.effects' tracker_scale).  A lag's
    interval is widened over its time constant by the profile (``_profiled``)."""
    x = c.extra
    record = x["t_end_s"] - x["t0_s"]
    slow = x["law"] == "lag" and x["tau_s"] > record > 0
    scale = (1.0 - math.exp(-record / x["tau_s"])) / (record / 3600.0) if slow else 1.0
    v, u, ci = _linear(np.array([scale]), theta, cov)
    ramp_law = x["law"] == "ramp" or slow
    return {"estimate": v, "uncertainty": u, "unit": "ppm/h" if ramp_law else "ppm", "interval_95": ci,
            "tracker": x["tracker_from"],
            **({"law": "ramp over the record", "record_s": record,
                "note": f"time constant beyond the record ({x['tau_s']:.0f} s > {record:.0f} s): the mean rate "
                        "over the record is reported, no final value"} if slow else {}),
            "says": _air_says(x, v, ci, ramp_law)}


def _air_says(x: dict, v: float, ci: list[float], ramp_law: bool) -> str:
    """The air's drift in words: its size (``v``, ``ci``: ppm per hour or ppm) and what it amounts to."""
    size = (f"{abs(v):.2g} ppm per hour (95 %: {ci[0]:.2g} to {ci[1]:.2g})" if ramp_law else
            f"by {abs(v):.2g} ppm with a time constant of {x['tau_s']:.0f} s (95 %: {ci[0]:.2g} to {ci[1]:.2g} ppm)")
    stations = "every station's" if x["stations"] > 1 else "the tracker's"
    where = "" if x["tracker_from"] == "given" else " (about the station estimated from the rounds' scatter)"
    return (f"{stations} distances {'lengthen' if v >= 0 else 'shorten'} {size}{where}: the air's refractive index "
            f"drifted and the weather compensation did not follow (the air {'cooling' if v >= 0 else 'warming'} by "
            f"about {abs(v):.2g} K{' per hour' if ramp_law else ''} at 1 ppm per K, or its pressure changing)")


def _air_profiled(prep: Prepared, eng: Engine, others: list[np.ndarray], c: fx.Candidate, w, details: dict
                  ) -> dict:
    """The air's drift (a lag) sized over its time constant (mtcal.diagnose.profile): the 95 % interval of the
    reported figure (the final change, or the mean rate over the record where tau exceeds it), its standard
    uncertainty at least the interval's half-width / 1.96, the change at the last reading (ppm) with its interval,
    and the words again; {} for a ramp (no nuisance parameter)."""
    from mtcal.diagnose.profile import Z95, members, profile

    x = c.extra
    prof = profile(eng, others, members(prep, c), w, 0, x["t_end_s"])
    if prof is None:
        return {}
    record = x["t_end_s"] - x["t0_s"]
    rate = details.get("law") == "ramp over the record"
    lo, hi = (v / (record / 3600.0) for v in prof["change_interval_95"]) if rate else prof["interval_95"]
    v = details["estimate"]
    frac = (record / 3600.0) if rate else 1.0 - math.exp(-record / x["tau_s"])
    return {"interval_95": [lo, hi], "uncertainty": max(details["uncertainty"], (hi - lo) / (2 * Z95)),
            "profile": prof, "change_over_record": {"ppm": v * frac, "interval_95": prof["change_interval_95"],
                                                    "record_s": record},
            "says": _air_says(x, v, [lo, hi], rate)}


GRAMMAR_HEADLINES = {"side_expansion": _side_expansion_head, "backlash_travel": _backlash_travel_head,
                     "tracker_relevel": _tracker_relevel_head, "air_index_drift": _air_index_drift_head}


def ramp(c: fx.Candidate, head: dict, t: np.ndarray) -> dict:
    """A warm-up whose time constant exceeds the record is reported as the change over the record (mm), with no
    final value (an extrapolation beyond the record); else the final value plus the change over the record."""
    if c.name != "thermal_drift" or not np.isfinite(t).all():
        return head
    record = float(np.max(t) - c.extra["t0_s"])
    frac = 1.0 - math.exp(-record / c.extra["tau_s"])
    change = [v * frac for v in head["vector"]]
    if c.extra["tau_s"] <= record:
        return {**head, "change_over_record": change, "record_s": record}
    k = "XYZ".index(head["direction"][1])  # the headline's component (its direction and uncertainty)
    return {**head, "variant": "ramp over the record", "estimate": abs(change[k]),
            "uncertainty": head["uncertainty"] * frac, "vector": change,
            "vector_uncertainty": [v * frac for v in head["vector_uncertainty"]], "record_s": record,
            "parameters": {}, "tau_s": None,
            "note": f"time constant beyond the record ({c.extra['tau_s']:.0f} s > {record:.0f} s): the change over "
                    f"the record is reported, no final value"}


def possible_aliases(prep: Prepared, c: fx.Candidate, eng: Engine, w) -> list[dict]:
    """Pitches that the sampled positions cannot tell from the periodic finding ``c`` (Nyquist): for the
    position step s, 1/p' = |1/p -+ k/s| (k = 1, 2), kept when their columns overlap c's (cos > 0.9)."""
    if c.name != "periodic":
        return []
    u = np.unique(prep.rec.position[prep.rec.axis == c.axis])
    s = float(np.min(np.diff(u)))
    p = c.extra["pitch"]
    out = []
    for k in (1, 2):
        for sign in (1, -1):
            f = abs(1.0 / p + sign * k / s)
            if f <= 0 or abs(1.0 / f - p) < 1e-6 * p:
                continue
            pa = 1.0 / f
            alt = fx.periodic(prep.geometry, c.axis, pa, (pa, pa))
            cos = eng.overlap(w(c), w(alt))
            if cos > 0.9:
                out.append({"pitch": pa, "overlap_cos": cos, "unit": c.extra["pitch_unit"]})
    return sorted(out, key=lambda a: a["pitch"])


def plot_residuals(diag: Diagnosis, directory) -> list[str]:
    """PNG of the raw residuals (um) of every axis before and after the selected effects."""
    import os

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    prep = diag.prep
    os.makedirs(directory, exist_ok=True)
    n = len(prep.rec)
    paths = []
    for tag, rw in (("before", diag.residuals_before), ("after", diag.residuals_after)):
        if prep.weighted:  # whitened: every component has unit variance at the tracker's specification
            raw, ylab, labels = rw.reshape(n, 3), "whitened", ("w1", "w2", "w3")
        else:
            raw, ylab, labels = rw.reshape(n, 3) * 1e3, "residual, um", ("x", "y", "z")
        fig, axs = plt.subplots(len(prep.axes), 1, figsize=(9, 2.2 * len(prep.axes)), squeeze=False)
        for ax, a in zip(axs[:, 0], prep.axes):
            idx = np.flatnonzero(prep.rec.axis == a)
            idx = idx[np.argsort(prep.order[idx])]
            for k, c in enumerate(labels):
                ax.plot(np.arange(len(idx)), raw[idx, k], ".", ms=2, label=c)
            ax.set_ylabel(f"{a} {ylab}")
            ax.legend(loc="upper right", fontsize=7, ncol=3)
        axs[-1, 0].set_xlabel("reading (time order within the axis)")
        fig.suptitle(f"residuals {tag} the diagnosed effects ({prep.rec.source})")
        fig.tight_layout()
        p = os.path.join(str(directory), f"residuals_{tag}.png")
        save_figure(fig, p, dpi=110)
        plt.close(fig)
        paths.append(p)
    return paths




def selected_findings(prep: Prepared, eng: Engine, steps, w, cv, null_model: str) -> list[Finding]:
    """Findings of the selected steps: joint estimates on ``eng`` (the reported base), cumulative sigma after
    each, validation ``cv(step, others) -> (gain or None, how)``, aliases, ramps and confounds."""
    from mtcal.diagnose.design import raw_sigma
    from mtcal.diagnose.engine import WEAK_TOL
    Gs = [w(s.candidate) for s in steps]
    theta_all, cov_all = eng.estimate(Gs) if steps else (np.zeros(0), np.zeros((0, 0)))
    cum, base = eng.copy_base(), eng.copy_base()
    out, off = [], 0
    for i, s in enumerate(steps):
        c, sc = s.candidate, s.score
        k = c.G.shape[-1]
        h = ramp(c, headline(c, theta_all[off:off + k], cov_all[off:off + k, off:off + k]), prep.rec.time_s)
        off += k
        cum.add(Gs[i])
        gain, how = cv(s, Gs[:i] + Gs[i + 1:])
        ev = {"test": "F", "F": sc.F, "dof": [sc.k, sc.dof], "p_value": math.exp(sc.logp),
              "p_adjusted": min(1.0, math.exp(s.logp_adj)), "log10_p_adjusted": s.logp_adj / math.log(10),
              "cv_gain": gain, "cv": how, "separability": sc.sep,
              "multiplicity": "Bonferroni over families x members", "null": null_model}
        d = h.pop("direction")
        details = {"uncertainty": h.pop("uncertainty"), "unit": h.pop("unit"),
                   "sigma_ratio_after": cum.sigma,
                   "where": (f"step along {d}, {c.label}" if "t0_s" in h and c.name == "offset" else c.label),
                   **{k2: v for k2, v in c.extra.items() if not k2.startswith("_") and k2 != "rows"}}
        est = h.pop("estimate")
        details.update(h)
        details.update(_profiled(prep, eng, Gs[:i] + Gs[i + 1:], c, w, d, {**details, "estimate": est}))
        v = Gs[i] @ theta_all[off - k:off]
        f = Finding(c.name, c.axis, d, True, est, raw_sigma(prep, cum.r, cum.dof), ev, details,
                    fitted=v - base.project(v[:, None])[:, 0], touched=c.moved,
                    candidate=c, theta=theta_all[off - k:off].copy())
        if s.confounded_with:
            details["confounded_with"] = s.confounded_with
        aliases = possible_aliases(prep, c, eng.copy_base(), w)
        if aliases:
            details["possible_alias"] = aliases
            details["where"] = (f"{c.label} or an alias: pitch "
                                f"{', '.join(format(a['pitch'], '.4g') for a in aliases)} {c.extra['pitch_unit']}")
            details["note"] = ("possible alias: the positions sample every "
                               f"{float(np.min(np.diff(np.unique(prep.rec.position[prep.rec.axis == c.axis])))):g} "
                               f"{c.extra['pitch_unit']}, so pitches "
                               f"{', '.join(format(a['pitch'], '.4g') for a in aliases)} give the same readings; "
                               "measure at a finer, non-uniform step")
        if sc.sep < WEAK_TOL:
            details["note"] = "weakly separable from the base model: the estimate is correlated with the fitted errors"
        if gain is not None and not gain > 0:
            f.significant = False
            details["note"] = f"significant in the F test but no gain on {how}"
        out.append(f)
    return out


def _profiled(prep: Prepared, eng: Engine, others: list[np.ndarray], c: fx.Candidate, w, direction: str | None,
              details: dict) -> dict:
    """A side's drift sized over its nuisance parameters (mtcal.diagnose.profile): the 95 % interval of the
    reported figure (the final value, or the change over the record for a ramp), its standard uncertainty at least
    the interval's half-width / 1.96, and the profile's report; {} for other findings."""
    from mtcal.diagnose.profile import Z95, members, profile

    if c.name == "air_index_drift":
        return _air_profiled(prep, eng, others, c, w, details)
    if not direction:
        return {}
    k = "XYZ".index(direction[1])
    prof = profile(eng, others, members(prep, c), w, k, float(np.nanmax(prep.rec.time_s)))
    if prof is None:
        return {}
    sign = 1.0 if direction[0] == "+" else -1.0
    key = "change_interval_95" if details.get("variant") == "ramp over the record" else "interval_95"
    lo, hi = sorted(sign * v for v in prof[key])
    return {"interval_95": [lo, hi], "uncertainty": max(details["uncertainty"], (hi - lo) / (2 * Z95)),
            "profile": prof}


def rejected_findings(last: dict, chosen: set, notes: list[dict], inadequate: list = ()) -> list[Finding]:
    """The best candidate of every family not selected (not significant, or significant but ``inadequate``: its
    model does not explain the misfit it fits; ``"inadequate"`` says why) and the not-separable notes."""
    out = []
    bad = {s.candidate.family: s for s in inadequate}
    for fam, s in sorted({**last, **bad}.items(), key=lambda kv: kv[1].logp_adj):
        if fam in chosen or s.candidate.name == fx.UNEXPLAINED:
            continue
        c, sc = s.candidate, s.score
        out.append(Finding(c.name, c.axis, None, False, None, None,
                           {"test": "F", "F": sc.F, "p_value": math.exp(sc.logp),
                            "p_adjusted": min(1.0, math.exp(s.logp_adj)), "cv_gain": None, "separability": sc.sep},
                           {"where": c.label, **({"inadequate": s.inadequate} if s.inadequate else {})}))
    for nt in notes:
        out.append(Finding(nt["name"], nt["axis"], None, False, None, None, None,
                           {"not_separable": nt["not_separable"],
                            **({"separability": nt["separability"]} if "separability" in nt else {})}))
    return out
