"""The candidate effects of the diagnosis: their design columns in the measured coordinates, and the list
of candidates a recording offers (``candidates``).

Each candidate is one effect at one place (an axis, an error function, a warm-up time constant, a pitch) with
its columns G (n readings, 3 coordinates, k parameters) = d(measured point, machine frame, mm) / d(parameters),
taken from the generated signatures (generated/signatures_numpy.py, derived in derive/signatures.py) and the
generated point Jacobians of the machine (columns of the 41 ISO errors).  Parameter units: backlash mm (rad for
B, C) reversal value; scale ppm; second_order per mm^2 or deg^2; periodic mm (rad) amplitudes of sin and cos;
thermal_drift mm (3-vector final displacement); offset and outlier mm (3-vector shift); tracker_scale ppm;
squareness / rotary_location mm or rad.

Effect names and vocabulary follow design.md; ``QUASI_STATIC`` are the effects that are themselves smooth
functions of the measured axis' position (part of the fitted base model's family when no model is given).
"""
from __future__ import annotations


from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable

import numpy as np

from mtcal.generated import signatures_numpy as S
from mtcal.machine import Machine

if TYPE_CHECKING:
    from mtcal.diagnose.prepare import Prepared

VOCABULARY = ("thermal_drift", "backlash", "scale", "squareness", "rotary_location", "periodic", "outlier",
              "cross_axis", "second_order", "tracker_scale", "offset")
QUASI_STATIC = ("scale", "squareness", "rotary_location", "second_order", "cross_axis")
TAUS_S = (300.0, 600.0, 1200.0, 1800.0, 3600.0, 7200.0, 14400.0)  # warm-up time constants tried, s


def constants(machine: Machine) -> dict[str, tuple[str, str]]:
    """Squareness and location constants of the machine -> (effect name, the axis whose motion shows it: the
    last letter of the ISO name, e.g. E_C0Y -> Y, E_X0C -> C)."""
    g = machine.error_groups
    return {**{e: ("squareness", e[-1]) for e in g["squareness"]},
            **{e: ("rotary_location", e[-1]) for e in g["location"]}}


@dataclass
class Candidate:
    """One candidate effect: ``G`` (n, 3, k) in mm per parameter unit, zero on readings it does not touch."""

    name: str
    axis: str | None
    label: str                  # e.g. "E_XX", "tau=1800 s", "pitch=200 mm"
    G: np.ndarray
    params: list[str]           # parameter names, with units
    direction: str | None = None
    family: str = ""            # candidates sharing a family compete (multiplicity counted over the family)
    extra: dict = field(default_factory=dict)
    refine: Callable[[float], "Candidate"] | None = None  # continuous parameter (tau, pitch) -> candidate
    refine_range: tuple[float, float] | None = None
    refine_value: float | None = None


@dataclass
class Geometry:
    """What the candidates need from the prepared recording (see mtcal.diagnose.prepare)."""

    axis: np.ndarray        # (n,) str
    position: np.ndarray    # (n,) mm or deg
    direction: np.ndarray   # (n,) +1 / -1 / 0
    time_s: np.ndarray      # (n,) s, NaN when absent
    side: np.ndarray        # (n,) "tool" / "table"
    xyz: np.ndarray         # (n, 3) mm
    J: np.ndarray           # (n, 3, n_errors) point Jacobian of the errors at zero error
    machine: Machine
    tracker: np.ndarray | None

    def col(self, name: str) -> np.ndarray:
        return self.J[:, :, self.machine.error_names.index(name)]

    def linear(self, axis: str) -> bool:
        return self.machine.kind(axis) == "linear"


def _on(g: Geometry, axis: str) -> np.ndarray:
    return (g.axis == axis)[:, None]


def backlash(g: Geometry, axis: str) -> Candidate:
    e = g.machine.positioning_errors[axis]
    G = S.backlash_signature(g.col(e), g.direction.astype(float)) * _on(g, axis)
    unit = "mm" if g.linear(axis) else "rad"
    return Candidate("backlash", axis, e, G[:, :, None], [f"reversal value ({unit})"], family=f"backlash {axis}",
                     extra={"error": e})


def scale(g: Geometry, axis: str) -> Candidate:
    e = g.machine.positioning_errors[axis]
    q = g.position if g.linear(axis) else np.deg2rad(g.position)
    G = S.scale_signature(g.col(e), q) * _on(g, axis)
    return Candidate("scale", axis, e, G[:, :, None], ["ppm"], family=f"scale {axis}", extra={"error": e})


def second_order(g: Geometry, axis: str, error: str) -> Candidate:
    G = S.second_order_signature(g.col(error), g.position) * _on(g, axis)
    unit = ("mm" if error[2] in "XYZ" else "rad") + "/" + ("mm^2" if g.linear(axis) else "deg^2")
    return Candidate("second_order", axis, error, G[:, :, None], [f"coefficient ({unit})"],
                     family=f"second_order {axis}", extra={"error": error})


def constant(g: Geometry, name: str, error: str) -> Candidate:
    axis = constants(g.machine)[error][1]
    G = g.col(error) * _on(g, axis)
    unit = "mm" if error[2] in "XY" and name == "rotary_location" else "rad"
    return Candidate(name, axis, error, G[:, :, None], [f"{error} ({unit})"], family=name, extra={"error": error})


def periodic(g: Geometry, axis: str, pitch: float, span: tuple[float, float]) -> Candidate:
    e = g.machine.positioning_errors[axis]
    G = S.periodic_signature(g.col(e), g.position, float(pitch)) * _on(g, axis)[:, :, None]
    unit, amp_unit = g.machine.unit(axis), "mm" if g.linear(axis) else "rad"
    c = Candidate("periodic", axis, f"pitch={pitch:.4g} {unit}", G, [f"sin amplitude ({amp_unit})", "cos amplitude"],
                  family=f"periodic {axis}", extra={"error": e, "pitch": float(pitch), "pitch_unit": unit,
                                                    "amplitude_unit": amp_unit})
    c.refine = lambda p: periodic(g, axis, p, span)
    c.refine_range, c.refine_value = span, float(pitch)
    return c


def pitch_grid(positions: np.ndarray, linear: bool, max_harmonic: int) -> tuple[np.ndarray, tuple[float, float]]:
    """Pitches that the sampling resolves (>= 2.2 position steps) and that are not a low harmonic of the travel."""
    u = np.unique(positions)
    if len(u) < 5:
        return np.zeros(0), (0.0, 0.0)
    step = float(np.min(np.diff(u)))
    travel = float(u[-1] - u[0])
    lo = 2.2 * step
    hi = travel / 1.2 if linear else 360.0 / (max_harmonic + 0.5)
    if hi <= lo:
        return np.zeros(0), (0.0, 0.0)
    n = int(np.ceil(np.log(hi / lo) / np.log(1.08))) + 1
    return np.geomspace(lo, hi, n), (lo, hi)


def thermal_drift(g: Geometry, target: str, tau: float, t0: float) -> Candidate:
    on = {"spindle": g.side == "tool", "table": g.side == "table", "tracker": np.ones(len(g.axis), bool)}[target]
    dt = np.where(np.isfinite(g.time_s), np.maximum(g.time_s - t0, 0.0), 0.0)
    G = S.thermal_drift_signature(dt, float(tau)) * on[:, None, None]
    c = Candidate("thermal_drift", None, f"{target}, tau={tau:.0f} s", G,
                  ["A_x (mm)", "A_y (mm)", "A_z (mm)"], family="thermal_drift",
                  extra={"target": target, "tau_s": float(tau), "t0_s": float(t0)})
    c.refine = lambda t: thermal_drift(g, target, t, t0)
    c.refine_range, c.refine_value = (60.0, 86400.0), float(tau)
    return c


def tracker_scale(g: Geometry) -> Candidate:
    G = S.tracker_scale_signature(g.xyz, g.tracker)
    return Candidate("tracker_scale", None, "about the tracker", G[:, :, None], ["ppm"], family="tracker_scale",
                     extra={"tracker": [float(v) for v in g.tracker]})


def outlier(g: Geometry, rows: np.ndarray, mode: str, where: dict) -> Candidate:
    on = np.zeros(len(g.axis))
    on[rows] = 1.0
    G = S.outlier_signature(on)
    label = (f"{mode}: round {where['round']} point {where['point']} at {where['position']:g} "
             f"({where['approach']:+d}), {where['readings']} reading(s)")
    return Candidate("outlier", str(g.axis[rows[0]]), label, G,
                     ["s_x (mm)", "s_y (mm)", "s_z (mm)"], family="outlier",
                     extra={"mode": mode, "rows": [int(r) for r in rows], **where})


def offset(g: Geometry, rows: np.ndarray, where: dict) -> Candidate:
    """A shift of every reading of one (axis, round, reflector) sequence: a reflector re-seated in its nest, or
    the whole round displaced (mm, machine frame)."""
    on = np.zeros(len(g.axis))
    on[rows] = 1.0
    G = S.outlier_signature(on)
    return Candidate("offset", str(g.axis[rows[0]]), f"round {where['round']} point {where['point']}", G,
                     ["s_x (mm)", "s_y (mm)", "s_z (mm)"], family=f"offset {g.axis[rows[0]]}",
                     extra={"variant": "re-seated nest", **where})


def tracker_knock(g: Geometry, t0: float, where: dict) -> Candidate:
    """The tracker (stand) knocked at ``t0`` (s): every reading from t0 on, of every axis and reflector, displaced
    by one constant vector (mm, machine frame) -- the planted effect ``offset`` of mtcal.effects.  The change
    point t0 is scanned over the gaps between reading times (mtcal.diagnose._knock_scan)."""
    on = (np.isfinite(g.time_s) & (g.time_s >= t0)).astype(float)
    G = S.outlier_signature(on)
    label = (f"tracker knocked at t0 = {t0:.6g} s (from axis {where['from_axis']} round {where['round']} point "
             f"{where['point']} at {where['position']:g}, {where['readings']} reading(s) after)")
    return Candidate("offset", None, label, G, ["s_x (mm)", "s_y (mm)", "s_z (mm)"], family="offset",
                     extra={"variant": "tracker knock", "t0_s": float(t0), **where})

NOT_SEPARABLE = {
    "scale": "a linear positioning error is part of the fitted error function E_JJ; compare with a reference model "
             "(--model) or measure a length standard / a second tracker station",
    "second_order": "a quadratic error term is part of the fitted smooth error function; compare with a reference "
                    "model (--model)",
    "squareness": "with each axis measured alone, a squareness is a linear straightness slope of the fitted "
                  "error functions; measure a diagonal or a plate reversal (mtcal plate) to separate it",
    "rotary_location": "with the reference at the zero position, a location error is a first harmonic of the fitted "
                       "rotary error motions; measure at several positions of the other rotary axis, or compare "
                       "with a reference model (--model)",
    "cross_axis": "the recording holds every axis with the other axes at zero; measure the axis again with the "
                  "other axis at a second position (plan 'at')",
    "offset": "one (round, reflector) sequence only: a shift of it is the reflector's position itself",
    "tracker_scale": "with one tracker station a radial scale of the tracker looks like axis scale and rotary "
                     "location errors; measure from a second tracker station or against a length standard",
    "backlash": "every target was approached from one direction; measure bidirectionally (ISO 230-2)",
    "thermal_drift": "the recording has no time_s column",
    "periodic": "the positions do not resolve a pitch shorter than the travel",
}


# ---------------------------------------------------------------------------------------------- candidates
def all_candidates(prep: "Prepared", max_degree: int) -> tuple[list[Candidate], list[dict]]:
    """All candidates that can be tested, and notes on the ones this recording cannot show."""
    g, rec = prep.geometry, prep.rec
    out: list[Candidate] = []
    notes: list[dict] = []
    for a in prep.axes:
        on = rec.axis == a
        dirs = set(rec.direction[on].tolist())
        if {1, -1} <= dirs:
            out.append(backlash(g, a))
        else:
            notes.append({"name": "backlash", "axis": a, "not_separable": NOT_SEPARABLE["backlash"]})
        grid, span = pitch_grid(rec.position[on], g.linear(a), max_degree)
        for pitch in grid:
            out.append(periodic(g, a, pitch, span))
        out.append(scale(g, a))
        for e in prep.machine.error_motions(a):
            out.append(second_order(g, a, e))
        notes.append({"name": "cross_axis", "axis": a, "not_separable": NOT_SEPARABLE["cross_axis"]})
    for e, (name, a) in constants(prep.machine).items():
        if a in prep.axes:
            out.append(constant(g, name, e))
    if np.isfinite(rec.time_s).all():
        t0 = float(np.min(rec.time_s))
        sides = set(g.side.tolist())
        targets = (["spindle"] if "tool" in sides else []) + (["table"] if "table" in sides else []) + (
            ["tracker"] if len(sides) > 1 else [])
        for target in targets:
            for tau in TAUS_S:
                out.append(thermal_drift(g, target, tau, t0))
    else:
        notes.append({"name": "thermal_drift", "axis": None, "not_separable": NOT_SEPARABLE["thermal_drift"]})
    if g.tracker is not None:
        out.append(tracker_scale(g))
    for s, (_a, r, label) in enumerate(prep.seq_keys):
        rows = np.flatnonzero(prep.seq == s)
        out.append(offset(g, rows, {"round": int(r), "point": str(label)}))
    return out, notes
