"""The candidate list of the diagnosis: every effect this recording can show, and notes on those it cannot.

Candidates are built by mtcal.diagnose_effects from the generated signatures (derive/signatures.py); the
scanned ones (outlier, bumped nest, tracker knock) come from mtcal.diagnose.scans at every selection step.
"""
from __future__ import annotations

import numpy as np

from mtcal import diagnose_effects as fx
from mtcal.diagnose.engine import Engine
from mtcal.diagnose.prepare import Prepared
from mtcal.diagnose.scans import knock_scan, outlier_scan, where_of

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


def candidates(prep: Prepared, max_degree: int) -> tuple[list[fx.Candidate], list[dict]]:
    """All candidates that can be tested, and notes on the ones this recording cannot show."""
    g, rec = prep.geometry, prep.rec
    out: list[fx.Candidate] = []
    notes: list[dict] = []
    for a in prep.axes:
        on = rec.axis == a
        dirs = set(rec.direction[on].tolist())
        if {1, -1} <= dirs:
            out.append(fx.backlash(g, a))
        else:
            notes.append({"name": "backlash", "axis": a, "not_separable": NOT_SEPARABLE["backlash"]})
        grid, span = fx.pitch_grid(rec.position[on], g.linear(a), max_degree)
        for pitch in grid:
            out.append(fx.periodic(g, a, pitch, span))
        out.append(fx.scale(g, a))
        for e in prep.machine.error_motions(a):
            out.append(fx.second_order(g, a, e))
        notes.append({"name": "cross_axis", "axis": a, "not_separable": NOT_SEPARABLE["cross_axis"]})
    for e, (name, a) in fx.constants(prep.machine).items():
        if a in prep.axes:
            out.append(fx.constant(g, name, e))
    if np.isfinite(rec.time_s).all():
        t0 = float(np.min(rec.time_s))
        sides = set(g.side.tolist())
        targets = (["spindle"] if "tool" in sides else []) + (["table"] if "table" in sides else []) + (
            ["tracker"] if len(sides) > 1 else [])
        for target in targets:
            for tau in fx.TAUS_S:
                out.append(fx.thermal_drift(g, target, tau, t0))
    else:
        notes.append({"name": "thermal_drift", "axis": None, "not_separable": NOT_SEPARABLE["thermal_drift"]})
    if g.tracker is not None:
        out.append(fx.tracker_scale(g))
    for s, (a, r, label) in enumerate(prep.seq_keys):
        rows = np.flatnonzero(prep.seq == s)
        out.append(fx.offset(g, rows, {"round": int(r), "point": str(label)}))
    return out, notes

def scanned(prep: Prepared, eng: Engine) -> list[tuple[str, fx.Candidate, int]]:
    """The scanned candidates on the current residuals: (family, best member, members scanned)."""
    out = []
    oscan, ocount = outlier_scan(prep, eng)
    if ocount:
        out.append(("outlier", fx.outlier(prep.geometry, oscan["rows"], oscan["mode"], where_of(prep, oscan["rows"])),
                    ocount))
    kscan, kcount = knock_scan(prep, eng)
    if kcount:  # tracker knock: the change point t0 scanned over the reading times (kcount members)
        first = kscan["rows"][np.argmin(prep.order[kscan["rows"]])]
        where = {"from_axis": str(prep.rec.axis[first]), **where_of(prep, kscan["rows"]),
                 "last_reading_before_s": kscan["before_s"], "first_reading_after_s": kscan["after_s"]}
        out.append(("offset", fx.tracker_knock(prep.geometry, kscan["t0"], where), kcount))
    return out


def screen(cands: list[fx.Candidate], notes: list[dict], eng: Engine, w) -> list[fx.Candidate]:
    """Drop the quasi-static candidates that the fitted base family explains (not separable from it; the
    tracker scale also when only weakly separable) and note why (appended to ``notes``)."""
    from mtcal.diagnose.engine import WEAK_TOL
    keep, seen = [], set()
    for c in cands:
        if c.name in fx.QUASI_STATIC or c.name == "tracker_scale":
            sc = eng.score(w(c))
            if not sc.separable or (c.name == "tracker_scale" and sc.sep < WEAK_TOL):
                if (c.name, c.axis) not in seen:
                    seen.add((c.name, c.axis))
                    notes.append({"name": c.name, "axis": c.axis, "not_separable": NOT_SEPARABLE[c.name],
                                  "separability": sc.sep})
                continue
        keep.append(c)
    return keep
