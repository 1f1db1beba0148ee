"""The candidate list of the diagnosis: every effect this recording can show, and notes on those it cannot.

Candidates are built by mtcal.diagnose.effects from the generated signatures (derive/signatures.py); the
scanned ones (outlier, bumped nest, tracker knock) come from mtcal.diagnose.scans at every selection step.
"""
from __future__ import annotations

import math

import numpy as np

from mtcal.diagnose import effects as fx
from mtcal.diagnose.design import ROTARY_HARMONICS, family_degrees
from mtcal.diagnose.engine import WEAK_TOL, Engine
from mtcal.diagnose.prepare import Prepared
from mtcal.diagnose.scans import knock_scan, outlier_scan, where_of

BIDIRECTIONAL = "every target was approached from one direction; measure bidirectionally (ISO 230-2)"
NO_DIRECTION = ("the readings carry no approach direction (no `direction` column, or 0): a reversal shows only "
                "between readings of known approach; write each reading's direction, +1 or -1 "
                "(docs/guide/your-data.md, \"When `direction` is needed\")")
NOT_SEPARABLE = {
    "scale": "a linear positioning error is part of the fitted error function E_JJ; compare with a reference model "
             "(`model`) or measure a length standard (a second tracker station does not separate it: a scale "
             "common to every station is the machine frame's)",
    "second_order": "a quadratic error term is part of the fitted smooth error function; compare with a reference "
                    "model (`model`)",
    "squareness": "with each axis measured alone, a squareness is a linear straightness slope of the fitted "
                  "error functions; measure a diagonal or a plate reversal (mtcal plate) to separate it",
    "rotary_location": "with the reference at the zero position, a location error is a first harmonic of the fitted "
                       "rotary error motions; measure at several positions of the other rotary axis, or compare "
                       "with a reference model (`model`)",
    "cross_axis": "the recording holds every axis with the other axes at zero; measure the axis again with the "
                  "other axis at a second position (plan 'at')",
    "offset": "one (round, reflector) sequence only: a shift of it is the reflector's position itself",
    "tracker_scale": "with one tracker station a radial scale of the tracker looks like axis scale and rotary "
                     "location errors; measure from a second tracker station (separates a scale that differs "
                     "between the stations: the air at another time, another instrument) or against a length "
                     "standard (a scale common to every station)",
    "tracker_scale common": "a scale common to every station's tracker (the air's refractive index over the whole "
                            "campaign) scales the machine frame itself: it is the axes' scale errors; measure "
                            "against a length standard (a scale that differs between stations is tested: "
                            "tracker_scale of a station relative to the first)",
    "tracker_scale station": "the stations see the machine from too similar directions: a scale of one station "
                             "relative to the first looks like the axes' errors; measure from a station at a "
                             "right angle to the others",
    "backlash": BIDIRECTIONAL,
    "thermal_drift": "the recording has no time_s column",
    "air_index_drift station": "the tracker's position is not known (the scatter of the rounds shows no tracker "
                               "shape): a scale of the distances about it cannot be placed; give the tracker's "
                               "position (--tracker or the tracker_x,y,z columns)",
    "air_index_drift undetermined": "the station is not determined by the data (its profile interval, "
                                    "noise_model.station_interval): a scale of the distances about it would be "
                                    "about a guessed point; give the tracker's position (--tracker or the "
                                    "tracker_x,y,z columns) and log the air's temperature and pressure",
    "tracker_settling undetermined": "the station is not determined by the data (its profile interval, "
                                     "noise_model.station_interval): a turn about it would be about a guessed "
                                     "point (a turn and a shift of the readings, which the drifts and knocks "
                                     "offered are, need no station); give the tracker's position (--tracker or "
                                     "the tracker_x,y,z columns)",
    "periodic": "the positions do not resolve a pitch shorter than the travel",
    "periodic few": "{n} positions leave {spare} shape(s) beside the fitted error function, fewer than {need}: any "
                    "misfit of the error function there is as periodic as a periodic error is; measure at more "
                    "positions",
    "periodic long": f"a wave this long is a shape of the fitted error function (less than {WEAK_TOL:.0%} of it "
                     "lies outside the quasi-static family): compare with a reference model (`model`) or measure a "
                     "longer travel",
    "reversal_angular": BIDIRECTIONAL,
    "reversal_straightness": BIDIRECTIONAL,
    "thermal_temperature": "the recording has no (varying) temperature_c column",
    "nest_creep": "the recording has no time_s column",
    "tracker_settling": "the recording has no time_s column",
}


TIE = 1e-7  # relative: two scans' scores this close are one fit (round-off of a chi-square; evidence is ~1e-2)
PERIODIC_SPARE = 5  # shapes over the positions beside the error function a periodic error needs: its own two, its
#                    pitch (fitted over a grid) and two more to check it against (selection.inadequate_because).  With
#                    3 (one to check against), on 11-12 positions a smooth error function's waves beyond degree 7 were
#                    named periodic errors of pitch 108-184 mm wherever the tracker reads 0.15 um along the beam
#                    (gen2, five seeds: 7 runs of 1420)


def _spare_shapes(prep: Prepared, axis: str, max_degree: int) -> int:
    """The shapes over ``axis``'s positions that its fitted error function leaves free: distinct positions - 1
    (the reflector's position) - the family's columns (degree on a linear axis, two per harmonic on a rotary)."""
    deg = family_degrees(prep, max_degree)[axis]
    n = len(np.unique(prep.rec.position[prep.rec.axis == axis]))
    return n - 1 - (deg if prep.geometry.linear(axis) else 2 * deg)


def candidates(prep: Prepared, max_degree: int) -> tuple[list[fx.Candidate], list[dict]]:
    """All candidates that can be tested, and notes on the ones this recording cannot show."""
    g = prep.geometry
    out: list[fx.Candidate] = []
    notes: list[dict] = []
    for a in prep.axes:
        out += _axis_candidates(prep, a, max_degree, notes)
    groups: dict[tuple[str, str, bool], list[str]] = {}
    for e, (name, a) in fx.constants(prep.machine).items():
        if a in prep.axes:
            groups.setdefault((name, a, e[2] in "XYZ"), []).append(e)  # offsets and tilts apart
    out += [fx.constant(g, name, errors) for (name, _, _), errors in groups.items()]
    out += _time_candidates(prep, notes)
    out += _temperature(prep, notes)
    if g.trackers:  # the first station's scale is the frame's: a scale common to every station is the machine's
        out += [fx.tracker_scale(g, st) for st in g.stations()[1:]]
        notes.append({"name": "tracker_scale", "axis": None, "not_separable": NOT_SEPARABLE["tracker_scale common"]})
    elif g.tracker is not None:
        out.append(fx.tracker_scale(g))
    out += [c for st in g.stations() for k in range(len(fx.INSTRUMENT_COORDINATES)) for n in fx.INSTRUMENT_SPANS
            if (c := fx.instrument_map(g, k, n, st)) is not None]
    for s, (_a, r, label) in enumerate(prep.seq_keys):
        rows = np.flatnonzero(prep.seq == s)
        out.append(fx.offset(g, rows, {"round": int(r), "point": str(label)}))
    out += grammar_members(prep, notes)
    return out, notes


def _axis_candidates(prep: Prepared, a: str, max_degree: int, notes: list[dict]) -> list[fx.Candidate]:
    """The candidates of one axis: reversals, periodic errors, scale, changes over rounds, second-order terms
    (``notes``: what this recording cannot show of them)."""
    g, rec = prep.geometry, prep.rec
    out: list[fx.Candidate] = []
    on = rec.axis == a
    dirs = set(rec.direction[on].tolist())
    if {1, -1} <= dirs:
        out += reversal_named(prep, a)
        out.append(fx.reversal_free(g, a))
    else:
        why = NO_DIRECTION if dirs == {0} else None
        notes += [{"name": nm, "axis": a, "not_separable": why or NOT_SEPARABLE[nm]}
                  for nm in ("backlash", "reversal_angular", "reversal_straightness")]
    grid, span = fx.pitch_grid(rec.position[on], g.linear(a), min(max_degree, ROTARY_HARMONICS))
    spare = _spare_shapes(prep, a, max_degree)
    if len(grid) and spare < PERIODIC_SPARE:
        notes.append({"name": "periodic", "axis": a, "not_separable": NOT_SEPARABLE["periodic few"].format(
            n=len(np.unique(rec.position[on])), spare=spare, need=PERIODIC_SPARE)})
        grid = []
    for pitch in grid:
        out.append(fx.periodic(g, a, pitch, span))
    out.append(fx.scale(g, a))
    rounds = len(set(rec.round[on].tolist()))
    if np.isfinite(rec.time_s[on]).all() and rounds >= 2:  # a change over rounds: linear from two on
        out += [fx.growing_free(g, a, full) for full in ((False, True) if rounds > 2 else (False,))]
        if rounds > 2:  # two rounds: one motion's bow changing between them is as much its stops' scatter
            out += [fx.growing_free(g, a, motion=e) for e in prep.machine.error_motions(a)]  # (gen2 3502/16)
        if len(fx.axis_blocks(g, a)) > 1:  # measured in several blocks: growing again in each
            out.append(fx.growing_free(g, a, full=False, per_block=True))
    for e in prep.machine.error_motions(a):
        out.append(fx.second_order(g, a, e))
    notes.append({"name": "cross_axis", "axis": a, "not_separable": NOT_SEPARABLE["cross_axis"]})
    return out


def _time_candidates(prep: Prepared, notes: list[dict]) -> list[fx.Candidate]:
    """The candidates that change with time: the sides' and trackers' drifts, nest creep, the tracker's
    settling (``notes``: why none where the recording has no time)."""
    g, rec = prep.geometry, prep.rec
    out: list[fx.Candidate] = []
    if np.isfinite(rec.time_s).all():
        t0 = float(np.min(rec.time_s))
        sides = set(g.side.tolist())
        targets = (["spindle"] if "tool" in sides else []) + (["table"] if "table" in sides else [])
        for target in targets:  # a side's drift may start when it is first seen or when an axis' block starts
            for onset in onsets(rec, g.side == fx.SIDE[target]):
                out += [fx.thermal_drift(g, target, tau, onset) for tau in fx.TAUS_S]
        nests = sorted(set(zip(rec.point.tolist(), g.side.tolist())))   # a label may name a nest on each side
        out += [fx.nest_creep(g, label, side, t0) for label, side in nests]
        guessed = undetermined(prep)
        for st in g.stations():  # a tracker's drift and settling start when that station is set up
            on, tracker, _ = g.at(st)
            ts = float(np.min(rec.time_s[on]))
            if len(sides) > 1 or st is not None:  # one side, one station: the tracker's drift is the side's
                out += [fx.thermal_drift(g, "tracker", tau, ts, st) for tau in fx.TAUS_S]
            if tracker is not None and not guessed:
                out += [fx.tracker_settling(g, tau, ts, st) for tau in fx.TAUS_S]
        if guessed:
            notes.append({"name": "tracker_settling", "axis": None, "kind": "station undetermined",
                          "not_separable": NOT_SEPARABLE["tracker_settling undetermined"]})
    else:
        notes += [{"name": nm, "axis": None, "not_separable": NOT_SEPARABLE[nm]}
                  for nm in ("thermal_drift", "nest_creep", "tracker_settling")]
    return out


def grammar_members(prep: Prepared, notes: list[dict]) -> list[fx.Candidate]:
    """The grammar's members of issue 34 (derive/grammar.py) this recording can show: a side's reflectors moving
    apart (a ramp or a lag in time, from the side's first reading), an axis' reversal changing along its travel
    (bidirectional axes), the tracker re-levelled at the first reading of a round (a tracker position known)."""
    g, rec = prep.geometry, prep.rec
    out: list[fx.Candidate] = []
    for a in prep.axes:
        if {1, -1} <= set(rec.direction[rec.axis == a].tolist()):
            out.append(fx.backlash_travel(g, a))
    if not np.isfinite(rec.time_s).all():
        notes.append({"name": "side_expansion", "axis": None, "not_separable": NOT_SEPARABLE["thermal_drift"]})
    else:
        offset = layout_offsets(prep)
        for side in ("tool", "table"):
            seen = g.side == side
            if len(set(rec.point[seen].tolist())) < 2:
                continue  # one reflector: no layout to grow
            t0 = float(np.min(rec.time_s[seen]))
            out += [fx.side_expansion(g, offset, side, t0, tau, centre) for tau in (None, *fx.TAUS_S)
                    for centre in (False, True)]
    out += air_index_drift(prep, notes)
    for st in g.stations():
        rows, tracker, _ = g.at(st)
        # a turn alone is about the station; with its shift, about any point: where no station is known (the
        # readings weighted equally), the shifted turn about the readings' centre
        pivot = None if tracker is not None else rec.xyz[rows].mean(axis=0)
        for rank0, where in round_starts(prep, rows):
            t0 = float(rec.time_s[prep.order == rank0][0]) if np.isfinite(rec.time_s).all() else float("nan")
            after = prep.order >= rank0
            if pivot is None and not undetermined(prep):
                out.append(fx.tracker_relevel(g, after, t0, where, st))
            if np.isfinite(t0):
                at = np.flatnonzero(rows & after)
                knock = fx.tracker_knock(g, t0, {"from_axis": where["axis"], **where_of(prep, at)}, st)
                out.append(fx.tracker_relevel(g, after, t0, where, st, knock, pivot))
    return out


def undetermined(prep: Prepared) -> bool:
    """Whether the station was estimated from the rounds' scatter and the data do not determine it (its profile
    interval, mtcal.diagnose.noise: noise_model.station_interval): then nothing is offered that turns or scales
    the readings about it (a settling, a re-levelling without its shift, the air's drift)."""
    interval = prep.noise.details.get("station_interval")
    return interval is not None and not interval["determined"]


def air_index_drift(prep: Prepared, notes: list[dict]) -> list[fx.Candidate]:
    """The air's refractive index drifting from the first reading on, one law for every station (a ramp, or a lag
    over fx.TAUS_S): offered where the station(s) are known -- given (--tracker, the tracker_x,y,z columns), or
    estimated from the scatter of the rounds and determined by it (mtcal.diagnose.noise's station interval); else
    a note says why not (a scale about a station the data do not place is not this effect's shape)."""
    g, rec = prep.geometry, prep.rec
    interval = prep.noise.details.get("station_interval")
    why = (NOT_SEPARABLE["thermal_drift"] if not np.isfinite(rec.time_s).all() else
           NOT_SEPARABLE["air_index_drift station"] if g.tracker is None and not g.trackers else
           NOT_SEPARABLE["air_index_drift undetermined"] if undetermined(prep) else None)
    if why is not None:
        notes.append({"name": "air_index_drift", "axis": None, "not_separable": why,
                      **({"kind": "station undetermined", "untested": fx.air_grammar(),
                          "where": "the air's refractive index drifting (not tested: the station is not determined)"}
                         if why != NOT_SEPARABLE["thermal_drift"] else {})})
        return []
    t0, how = float(np.min(rec.time_s)), "estimated" if interval is not None else "given"
    return [fx.air_index_drift(g, t0, None, how)] + [fx.air_index_drift(g, t0, tau, how) for tau in fx.TAUS_S]


def layout_offsets(prep: Prepared) -> np.ndarray:
    """(n, 3) mm: each reading's reflector position (the side's local frame, prepare's reference positions) less the
    centroid of the reflectors read on its axis."""
    off = np.zeros((len(prep.rec), 3))
    for a in prep.axes:
        on = prep.rec.axis == a
        labels = sorted(set(prep.rec.point[on].tolist()))
        centroid = np.mean([prep.local[on & (prep.rec.point == p)][0] for p in labels], axis=0)
        off[on] = prep.local[on] - centroid
    return off


def round_starts(prep: Prepared, rows: np.ndarray) -> list[tuple[int, dict]]:
    """The first reading (its rank in time) of every round of an axis among ``rows`` (one station's readings) but
    the axis' first, with the axis and round it starts: where a tracker may have been re-levelled between two rounds
    of an axis (the rounds before and after show the step; at the start of an axis' block the base's positions and
    error functions of the axes after it would take the rotation, and only the positions those axes share could
    show it: a quasi-static misfit of the shared positions, not a re-levelling).  Only a start whose previous
    reading in time is of the same axis counts: rounds numbered out of time order (gen2 held-out seed 3501: "before
    round 1 of axis B" at B's block start on a clean campaign) open a block too.  But where other stations read the
    axis too, its base is theirs as well and the station's alignment is fixed by its readings before: a block's
    start (not the station's first reading) counts there (gen2 seed 3536 campaign 28: S2 re-levelled between its
    blocks of Y and C, found as a settling of S2 and a knock of S1)."""
    rec, first = prep.rec, {}
    for i in np.flatnonzero(rows):
        k = (str(rec.axis[i]), int(rec.round[i]))
        first[k] = min(first.get(k, prep.order[i]), prep.order[i])
    opening = {a: min(r for (b, _), r in first.items() if b == a) for a, _ in first}
    ranks = np.sort(prep.order[rows])
    axis_at = {int(prep.order[i]): str(rec.axis[i]) for i in np.flatnonzero(rows)}
    elsewhere = {a: bool(np.any(~rows & (rec.axis == a))) for a in opening}

    def within_block(r: int) -> bool:  # the reading before it in time is of the same axis (not a block's start)
        k = int(np.searchsorted(ranks, r))
        return k > 0 and axis_at[int(ranks[k - 1])] == axis_at[int(r)]

    def counts(a: str, r: int) -> bool:
        return r != opening[a] and within_block(r) or elsewhere[a] and r != ranks[0]

    return sorted((r, {"axis": a, "round": n}) for (a, n), r in first.items() if counts(a, r))


def onsets(rec, seen: np.ndarray) -> list[float]:
    """Where a side's drift may start (s): its first reading (``seen``: the side's rows) and the start of each axis'
    block after it.  Never before the side is first seen: the readings cannot tell when a drift began before
    they watched that side (any earlier onset has the same shape from then on, only a larger, extrapolated
    amplitude), so the size stated is the one they observe."""
    first = float(np.min(rec.time_s[seen]))
    starts = {float(np.min(rec.time_s[rec.axis == a])) for a in np.unique(rec.axis)}
    return sorted({first} | {t for t in starts if t > first})


def reversal_named(prep: Prepared, axis: str) -> list[fx.Candidate]:
    """The named reversal effects of an axis: backlash and, for a linear axis, the reversals of its two
    straightnesses and three angular errors -- together every rigid motion of the carriage that differs between
    the directions of approach."""
    g, m = prep.geometry, prep.machine
    out = [fx.backlash(g, axis)]
    if g.linear(axis):
        own = m.positioning_errors[axis]
        out += [fx.reversal_straightness(g, axis, e) for e in m.error_motions(axis) if e[2] in "XYZ" and e != own]
        out += [fx.reversal_angular(g, axis, e) for e in m.error_motions(axis) if e[2] in "ABC"]
    return out


def _temperature(prep: Prepared, notes: list[dict]) -> list[fx.Candidate]:
    """thermal_temperature candidates when temperature_c is recorded and varies: dT = T - T(first reading), K."""
    g, rec = prep.geometry, prep.rec
    T = rec.temperature_c
    if not np.isfinite(T).all() or np.ptp(T) <= 0:
        notes.append({"name": "thermal_temperature", "axis": None,
                      "not_separable": NOT_SEPARABLE["thermal_temperature"]})
        return []
    dT = T - T[np.argmin(prep.order)]
    out = [fx.thermal_temperature_scale(g, a, dT) for a in prep.axes if g.linear(a)]
    sides = set(g.side.tolist())
    targets = (["spindle"] if "tool" in sides else []) + (["table"] if "table" in sides else [])
    return out + [fx.thermal_temperature_drift(g, t, dT) for t in targets]


def scanned(prep: Prepared, eng: Engine) -> list[tuple[str, fx.Candidate, int]]:
    """The scanned candidates on the current residuals: (family, best member, members scanned)."""
    out = []
    oscan, ocount = outlier_scan(prep, eng)
    if ocount:
        out.append(("outlier", fx.outlier(prep.geometry, oscan["rows"], oscan["mode"], where_of(prep, oscan["rows"])),
                    ocount))
    # tracker knock: the change point t0 scanned over the reading times of each station (kcount members in all)
    scans = [(st, *knock_scan(prep, eng, prep.geometry.at(st)[0])) for st in prep.geometry.stations()]
    kcount = sum(c for _, _, c in scans)
    if kcount:
        (st, kscan, _), same = _earliest_of_equal(s for s in scans if s[2])
        c = fx.tracker_knock(prep.geometry, kscan["t0"], _knock_where(prep, kscan), st)
        if same:
            c.extra["same_fit_as"] = "; ".join(
                f"station {o} knocked at t0 = {k['t0']:.6g} s by the opposite step" for o, k, _ in same) + (
                ": the readings fix only the step between the stations (the reflectors read after it are shared "
                "by them), not which station moved; the earliest step is named")
        out.append(("offset", c, kcount))
    nest = _nest_knock(prep, eng)
    return out + ([nest] if nest else [])


def _nest_knock(prep: Prepared, eng: Engine) -> tuple[str, fx.Candidate, int] | None:
    """A knocked nest: the change point scanned over each nest's reading times (one vector in the side's frame from
    t0 on), the best over the nests, with the members scanned in all."""
    g = prep.geometry
    if not np.isfinite(prep.rec.time_s).all():
        return None
    frame = g.rotation.reshape(-1, 3, 3)
    scans = [((label, side), *knock_scan(prep, eng, (g.point == label) & (g.side == side), frame))
             for label, side in sorted(set(zip(g.point.tolist(), g.side.tolist())))]
    count = sum(c for _, _, c in scans)
    if not count:
        return None
    ((label, side), best, _), _ = _earliest_of_equal(s for s in scans if s[2])
    return "nest_knock", fx.nest_knock(g, label, side, best["t0"], _knock_where(prep, best)), count


def _earliest_of_equal(scans) -> tuple[tuple, list[tuple]]:
    """The best of several knock scans ((key, best, count) each) and the others that fit equally well.  Scores
    equal to ``TIE`` (relative; a chi-square's round-off, far below any evidence) are the same fit: two stations'
    steps that only the step between them fixes, or two nests' (tests/test_diagnose_multistation.py).  Which one
    is named is then a rule of the data -- the earliest step (then the key) -- never whichever of two equal
    scores the floating point rounds up (numpy 2.4.6 / scipy 1.17.1 named the other station of a campaign)."""
    scans = list(scans)
    top = max(s[1]["delta"] for s in scans)
    equal = sorted((s for s in scans if s[1]["delta"] >= top - TIE * max(1.0, abs(top))),
                   key=lambda s: (s[1]["t0"], str(s[0])))
    return equal[0], equal[1:]


def _knock_where(prep: Prepared, scan: dict) -> dict:
    """Where a scanned knock (``knock_scan``'s best) starts: the axis of its first reading after t0, that
    reading's round, point and position, and the readings either side of the change."""
    first = scan["rows"][np.argmin(prep.order[scan["rows"]])]
    return {"from_axis": str(prep.rec.axis[first]), **where_of(prep, scan["rows"]),
            "last_reading_before_s": scan["before_s"], "first_reading_after_s": scan["after_s"]}


def screen(cands: list[fx.Candidate], notes: list[dict], eng: Engine, w) -> list[fx.Candidate]:
    """Drop the quasi-static candidates that the fitted base family explains (not separable from it; the
    tracker scale and a periodic error also when only weakly separable, fx.NEEDS_SEPARATION: what little of them
    lies outside the family fits the family's own misfit) and note why (appended to ``notes``; a periodic error's
    from the shortest pitch dropped)."""
    keep, seen = [], {}
    for c in cands:
        if c.name in fx.QUASI_STATIC or c.name in fx.NEEDS_SEPARATION:
            sc = eng.score(w(c))
            if not sc.separable or (c.name in fx.NEEDS_SEPARATION and sc.sep < WEAK_TOL):
                key = ("tracker_scale station" if "station" in c.extra else
                       "periodic long" if c.name == "periodic" else c.name)
                note = seen.get((c.name, c.axis))
                if note is None:
                    seen[(c.name, c.axis)] = note = {"name": c.name, "axis": c.axis,
                                                     "not_separable": NOT_SEPARABLE[key], "separability": sc.sep}
                    notes.append(note)
                if c.name == "periodic":
                    note["pitch_from"] = min(note.get("pitch_from", math.inf), c.extra["pitch"])
                    note["separability"] = max(note["separability"], sc.sep)
                    note["not_separable"] = (f"pitches of {note['pitch_from']:.4g} {c.extra['pitch_unit']} and "
                                             f"longer: {NOT_SEPARABLE[key]}")
                continue
        keep.append(c)
    return keep
