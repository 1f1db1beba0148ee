"""The free form of a named effect's place: one finding per mismatch (issue 34 item 2, docs/design.md).

A named effect says *what* moved *where* and *how*.  Its place -- an axis' reversal or poses, one station's
tracker, one nest, one side -- has a free form that spans the named effect and every other motion of the same kind
there: a reversal free at every position, every nest free at every pose of the axis, a rigid step (translation and
rotation about the tracker) of the station, the same step or creep at every nest of the side, a drift of each nest
of the side on its own.  The name enters only if the data do not still need that free form beside it (an F test at
the diagnosis' level, nested: the free form spans the named effect).  When they do, the mismatch is outside the
named effect; it is then reported once, as an ``unexplained`` entry located at the place with its shape (the free
form fitted: where, along what, how large), and the selection goes on beside it, so that what the name would have
left behind is not named again by others (a warming table's nests moving apart, taken nest by nest, came out as a
creep and three knocks).

Every free form is built from the generated signatures (generated/signatures_numpy.py, derive/signatures.py): a
reading's displacement (outlier_signature: I3 on the chosen readings), a nest's motion in its side's frame
(nest_creep_signature: R dt), a turn about the tracker (tracker_settling_signature's ramp column, u x (point - T)
dt, with dt a step).  Units: mm (translations, machine frame or the side's frame), rad (turns).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import BSpline

from mtcal.diagnose import effects as fx
from mtcal.generated import signatures_numpy as S

REVERSALS = ("backlash", "backlash_travel", "reversal_angular", "reversal_straightness")
MAX_STOPS = 48  # stops the free form of stops landing off takes a column each for (stops_off)
MAX_AXIS_STOPS = 400  # stops of one axis the split-plot test takes a column each for (stops_of)


@dataclass
class Place:
    """The free form of a named candidate's place: ``candidate`` (an UNEXPLAINED candidate whose ``extra`` says
    where: "place", "by", "note"), the ``named`` columns it must be tested beside (the candidate's own, and every
    named effect of the same kind at that place), and ``why``: the words for a name the free form is needed
    beside ({F} and {p} filled in by the caller).  ``sharper``: members of the free form with fewer columns
    (the commonest shape of the mismatch), tested beside the named ones too (the level shared among all tests):
    the whole free form spreads its evidence over every column."""

    candidate: fx.Candidate
    named: list[fx.Candidate]
    why: str
    sharper: tuple[fx.Candidate, ...] = ()


def place_of(prep, c: fx.Candidate, named_reversals) -> Place | None:
    """The free form of the place of the named candidate ``c`` (None: no free form beyond the checks of
    mtcal.diagnose.selection.inadequate_because).  ``named_reversals``: axis -> the named reversal candidates of
    that axis (mtcal.diagnose.candidates.reversal_named)."""
    g = prep.geometry
    if c.name in REVERSALS and c.axis is not None:
        return _reversal_place(g, c.axis, [c, *named_reversals(c.axis)])
    if c.name == "offset" and c.extra.get("variant") == "tracker knock":
        return _tracker_place(g, c)
    if c.name == "tracker_settling":
        return _settling_place(prep, c)
    if c.name in ("nest_knock", "nest_creep"):
        return _side_nests(g, c)
    if c.name == "thermal_drift":
        return _nest_drifts(g, c)
    if c.name == "side_expansion":
        return _side_layout(g, c)
    if c.grammar is not None and c.grammar.where.at == "axis" and not c.grammar.free \
            and c.grammar.how.on <= {"position"}:
        return _axis_poses(g, c)
    return None


def tie(c: fx.Candidate, rivals: list[fx.Candidate], leads: list[float]) -> fx.Candidate:
    """The named effect ``c`` and the ``rivals`` of other physics that fit its misfit alike (``leads``: c's chi^2
    lead over each, in the residual variance; mtcal.diagnose.selection._tied) as one free form: their columns
    together, reported as one located mismatch that may be any of them (the data do not say which); ``common`` in
    its ``extra``: the readings every one of them moves, where they agree the misfit is; ``at_axis``: the axis
    where ``c``'s change in time happens (its t0's), where one is named."""
    names = [_words(x) for x in (c, *rivals)]
    alike = ", ".join(f"{n} (behind by {d:.1f})" for n, d in zip(names[1:], leads))
    common = np.logical_and.reduce([x.moved for x in (c, *rivals)])
    return fx.Candidate(fx.UNEXPLAINED, c.axis, f"{names[0]}, or {alike}",
                        np.concatenate([c.G] + [x.G for x in rivals], axis=-1),
                        [f"{x.name}: {p}" for x in (c, *rivals) for p in x.params],
                        family=f"{fx.UNEXPLAINED} tie {c.family}", extra={
                            "kind": "place", "by": "effects fitting alike", "place": "one misfit",
                            "names": [x.name for x in (c, *rivals)], "common": common,
                            "at_axis": c.extra.get("from_axis"),
                            "note": f"one misfit that {' or '.join(names)} fit alike (chi^2 leads below "
                                    "2 ln 100, Jeffreys' decisive): the data do not say which, so none is named; "
                                    "physics outside the list may fit it as well"})


def unsteady(steps: list[fx.Candidate]) -> fx.Candidate:
    """Several steps of one place (a station's frame: knocks, re-levellings; one nest) found by its change-point
    search (mtcal.diagnose.scans.change_points: k >= 2 steps that do not come back) as one free form: their columns
    together -- the place's readings stepping again and again (the tracker disturbed and settling, the machine's
    stops landing off: an axis repeating worse, something in the beam; a nest loose in its seat), not a tracker or
    a nest knocked several times."""
    x = steps[0].extra
    t0 = [k.extra["t0_s"] for k in steps]
    at = ", ".join(f"{t:.6g}" for t in t0)
    causes = ("the nest loose in its seat, the side under it settling" if "side" in x else
              "the tracker disturbed and settling, the machine's stops landing off (an axis repeating worse), "
              "something in the beam")
    what = f"the reflector {x['point']} ({x['side']} side)" if "side" in x else "every reading"
    words = (f"{what} steps {len(steps)} times (at {at} s, from axis {x['from_axis']} round {x['round']}): {causes} "
             "-- not one knock after another")
    extra = (_at_the_nest(x, words) if "side" in x else _at_the_tracker(x.get("station"), words)) | {"t0_s": min(t0)}
    return fx.Candidate(fx.UNEXPLAINED, x["from_axis"], f"{what} stepping at t = {at} s, from axis "
                        f"{x['from_axis']} round {x['round']}", np.concatenate([k.G for k in steps], axis=-1),
                        [f"step {i + 1} {q}" for i, k in enumerate(steps) for q in k.params],
                        family=f"{fx.UNEXPLAINED} place unsteady", extra=extra)


def _at_the_tracker(station: str | None, note: str, **more) -> dict:
    """The ``extra`` of a free form located at the tracker of ``station`` (its readings moving together in time):
    where, along what (``by``), the words (``note``) and ``more`` (e.g. t0_s)."""
    of = f" of station {station}" if station else ""
    return {"kind": "place", "by": "time (station frame)", "place": f"the tracker{of}", **more,
            **({"station": station} if station else {}), "note": note}


def _at_the_nest(x: dict, note: str) -> dict:
    """The ``extra`` of a free form located at the nest of a nest knock (its ``extra`` ``x``: point, side)."""
    return {"kind": "place", "by": f"time ({x['side']} side's frame)", "place": f"the nest of {x['point']}",
            "side": x["side"], "points": [x["point"]], "note": note}


PATH_SPANS = 12  # spans of a path (frame_path, nest_path): cubic B-splines, knots even in the readings' order


def _smooth_order(prep, rows: np.ndarray) -> np.ndarray:
    """A smooth basis of the reading order at every reading, (n, PATH_SPANS + 3): cubic B-splines of the readings'
    rank in time (Prepared.order) on PATH_SPANS spans evenly spaced from the first to the last of ``rows`` (zero off
    them), each less its value at the first (the motion there is the base's).  Smooth through every knot, a path
    cannot take a step at one; smooth in the order of the readings, not in the clock, it cannot hide a step in a
    pause between rounds either (a tracker re-levelled while the machine stood, gen2 3611/18, was fitted as well
    by a path of the clock rising in the pause)."""
    k = prep.order.astype(float)
    k0, k1 = float(np.min(k[rows])), float(np.max(k[rows]))
    inner = np.linspace(k0, k1, PATH_SPANS + 1)
    knots = np.r_[[k0] * 3, inner, [k1] * 3]
    B = np.zeros((len(k), PATH_SPANS + 3))
    B[rows] = BSpline.design_matrix(k[rows], knots, 3).toarray() - BSpline.design_matrix([k0], knots, 3).toarray()
    return B


FRAME_MOTION = ("x (mm)", "y (mm)", "z (mm)", "w_x (rad)", "w_y (rad)", "w_z (rad)")  # a frame's rigid motion


def _frame_motion(g, station: str | None, on: np.ndarray) -> np.ndarray:
    """(n, 3, 6): the readings ``on`` (bool (n,), of ``station``) moved rigidly with the station's frame
    (_rigid_motion) about the tracker, else about the station's readings' centre (with the translation beside it, a
    turn about any point is the same motion); zero elsewhere."""
    rows, tracker, _ = g.at(station)
    out = np.zeros((len(rows), 3, 6))
    out[on] = _rigid_motion(g.xyz[on], tracker if tracker is not None else g.xyz[rows].mean(axis=0))
    return out


def frame_path(prep, c: fx.Candidate) -> fx.Candidate:
    """The frame of ``c``'s station moving smoothly with time: a rigid motion (a translation, mm, machine frame, and
    a turn, rad, about the tracker, else the readings' centre: with the translation beside it, a turn about any
    point is the same motion) smooth in the order of the readings (_smooth_order: cubic B-splines), relative to the
    first reading (the frame's alignment is the base's).  A step of the frame (a knock, a re-levelling) gives way
    where this path is still needed beside it (selection._change_points)."""
    g = prep.geometry
    station = c.extra.get("station")
    rows, _, of = g.at(station)
    basis = _smooth_order(prep, rows)
    motion = _frame_motion(g, station, rows)
    return fx.Candidate(fx.UNEXPLAINED, None, f"the tracker{of}'s frame moving smoothly with time",
                        np.concatenate([motion * b[:, None, None] for b in basis.T], axis=-1),
                        [f"{p} (spline {k + 1})" for k in range(basis.shape[1]) for p in FRAME_MOTION],
                        family=f"{fx.UNEXPLAINED} place path{of}", extra=_at_the_tracker(station, (
                            f"every reading of the tracker{of} moves together, smoothly with time, not in one step: "
                            "the tracker's stand or the measured side drifting or wandering (with the temperature, "
                            "with a robot's or the machine's pose) -- a step at one time fits it no better")))


def nest_path(prep, c: fx.Candidate) -> fx.Candidate:
    """The nest of a nest knock ``c`` moving smoothly with time: a translation (mm, its side's frame: the creep's
    generated signature with a smooth function of the readings' order, _smooth_order), relative to the first
    reading.  A nest's step gives way where this path is still needed beside it (selection._change_points): a base
    reflector of icelinker's replica wandering 10-15 um against the other two was named knocked one to three
    times (tests/test_real_icelinker.py)."""
    g, x = prep.geometry, c.extra
    on = step_rows(prep, c)
    basis = _smooth_order(prep, np.ones(len(on), bool))
    rot = g.rotation.reshape(-1, 9)
    return fx.Candidate(fx.UNEXPLAINED, None, f"point {x['point']} ({x['side']} side) moving smoothly with time",
                        np.concatenate([S.nest_creep_signature(rot, b * on) for b in basis.T], axis=-1),
                        [f"{k} (mm, spline {j + 1})" for j in range(basis.shape[1]) for k in "xyz"],
                        family=f"{fx.UNEXPLAINED} place path {x['side']} {x['point']}", extra=_at_the_nest(x, (
                            f"the reflector {x['point']} moves in its nest on the {x['side']} side smoothly with "
                            "time, not in one step: the nest or the side under it creeping, warming or settling -- a "
                            "step at one time fits it no better")))


def stops_off(prep, c: fx.Candidate) -> fx.Candidate | None:
    """A tracker knock within a linear axis' readings as the free form of that axis' stops landing off: one column
    per stop of the shorter side of the step within the axis (the station's readings of the axis before t0, or
    after it: the base's offsets per axis take a step that is constant over an axis' readings, so the knock is
    seen as that split), the axis' positioning column on the nests read at it (mm along the motion; the stops
    are Prepared.stop's) -- what an axis repeating worse shows where a few of its stops land off together; None
    for any other candidate, a rotary axis, or a shorter side of more than MAX_STOPS stops
    (icelinker's robot, a pass a round: 454 "stops" that a drift of the base moves together)."""
    x = c.extra
    if c.name != "offset" or x.get("variant") != "tracker knock":
        return None
    g, axis = prep.geometry, x["from_axis"]
    if not g.linear(axis):
        return None
    rows, _, of = g.at(x.get("station"))
    rows = rows & (g.axis == axis)
    after = c.moved & rows
    before = rows & ~after
    short = after if after.sum() <= before.sum() else before
    stop = prep.stop
    ids = list(dict.fromkeys(stop[short].tolist()))
    if not ids or len(ids) > MAX_STOPS:
        return None
    rnd = ", ".join(map(str, sorted(set(prep.rec.round[short].tolist()))))
    G = _stop_columns(prep, axis, ids)
    return fx.Candidate(fx.UNEXPLAINED, axis, f"{len(ids)} stop(s) of axis {axis}{of} landing off (round(s) {rnd}), "
                        f"or the tracker{of} knocked at t0 = {x['t0_s']:.6g} s",
                        G, [f"stop {k + 1} along {axis} (mm)" for k in range(len(ids))],
                        family=f"{fx.UNEXPLAINED} place stops {axis}", extra={
                            "kind": "place", "by": "round x position", "place": f"axis {axis}'s stops",
                            **({"station": x["station"]} if x.get("station") else {}), "t0_s": x["t0_s"],
                            "note": f"the readings of {len(ids)} stop(s) of axis {axis} (round(s) {rnd}) are off the "
                                    "others along the axis' motion, about as well told by each stop landing off on "
                                    f"its own (the axis repeating worse) as by the tracker{of} knocked: the data do "
                                    "not say which"})


def stop_motions(prep, W: np.ndarray, pattern: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Every stop (Prepared.stop: the nests read while the machine stood still) moving on its own by the
    displacement ``pattern`` ((n, 3) mm, machine frame: a step's fitted motion at every reading, zero where it does
    not act), each by its own amount, as the blocks of Engine.score_blocks: the stop's rows of the whitened vector
    (``W``, (n, 3, 3)) and its one whitened column, normalised (none for a stop the pattern does not move) -- the
    stops moving together at random from one to the next in the step's own way (a robot moving the base, the
    machine landing off, the tracker disturbed between them), of which the step between stops is one contrast
    (mtcal.diagnose.selection._split_plot).  The step's own direction, not every rigid motion of a stop: where the
    stops move more one way than another (icelinker's base: 14 um along Y from pose to pose, 2 um along Z), the
    scatter of every way pooled is not the step's error."""
    stop = prep.stop
    order = np.argsort(stop, kind="stable")
    out = []
    for rows in np.split(order, np.flatnonzero(np.diff(stop[order])) + 1):
        col = np.einsum("mij,mj->mi", W[rows], pattern[rows]).reshape(-1, 1)
        size = float(np.linalg.norm(col))
        if size > 0:
            out.append(((3 * rows[:, None] + np.arange(3)).ravel(), col / size))
    return out


REPLICATE_TOL = 1e-9  # columns equal within this share of their largest over a group's readings: its mean


def replicate_strata(prep, W: np.ndarray, G: np.ndarray) -> tuple[list, list, np.ndarray] | None:
    """(units, cells, nests) of the readings the columns ``G`` ((n, 3, k), mm per unit, unwhitened) move, for
    strata.pure_error and strata.lack_of_fit: the replicates whose scatter is the error term of G's test.

    A cell is what is repeated over the rounds: one station, axis, position and direction of approach; a unit is
    one stop -- the cell in one round, its nests together (the split plot: the nests of one stop share whatever
    the stop shares); ``nests`` (n,) codes each reading's nest, so that the readings' own scatter is their round x
    nest interaction within the cells (strata.pure_error's variance components: a contrast between stops is set
    against what a stop shares, one between the nests of a stop against what each reading has of its own).  Each
    unit and cell as Engine.score_blocks' blocks: its rows of the whitened vector (``W``, (n, 3, 3)) and an
    orthonormal basis of its mean (the three whitened coordinates of a translation of its readings).  None where G
    is not the same at each nest over the rounds (a function of the time, not of the stop) or no cell is repeated
    (no pure error)."""
    rec, g = prep.rec, prep.geometry
    moved = np.any(G.reshape(len(G), -1) != 0, axis=1)
    if not moved.any():
        return None
    idx = np.flatnonzero(moved)
    cell = [(s, a, q, d) for s, a, q, d in zip(rec.stations()[idx], rec.axis[idx], g.position[idx],
                                                 g.direction[idx])]
    by_stop = _groups(idx, [(*c, r) for c, r in zip(cell, rec.round[idx])])
    by_cell = _groups(idx, cell)
    if not _constant(G, _groups(idx, [(*c, p) for c, p in zip(cell, rec.point[idx])])) or len(by_stop) == len(by_cell):
        return None
    nests = np.unique(rec.point.astype(str), return_inverse=True)[1]
    return [_mean_block(W, rows) for rows in by_stop], [_mean_block(W, rows) for rows in by_cell], nests


def _groups(idx: np.ndarray, keys: list[tuple]) -> list[list[int]]:
    """The readings ``idx`` grouped by their ``keys`` (one list of readings per key, in first-seen order)."""
    out: dict[tuple, list[int]] = {}
    for i, k in zip(idx.tolist(), keys):
        out.setdefault(k, []).append(i)
    return list(out.values())


def _constant(G: np.ndarray, groups: list[list[int]]) -> bool:
    """Whether every column of ``G`` is the same at every reading of each group (to REPLICATE_TOL)."""
    scale = max(float(np.abs(G).max()), 1e-300)
    return all(np.abs(G[rows] - G[rows[:1]]).max() <= REPLICATE_TOL * scale for rows in groups)


def _mean_block(W: np.ndarray, rows: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """(rows of the whitened vector, orthonormal basis of a translation of the readings ``rows``)."""
    r = np.asarray(rows)
    q, _ = np.linalg.qr(W[r].reshape(-1, 3))
    return (3 * r[:, None] + np.arange(3)).ravel(), q


def step_rows(prep, c: fx.Candidate) -> np.ndarray:
    """(n,) bool: the readings of the place of a step ``c`` -- its station's (a knock, a re-levelling) or its nest's
    (a nest knock) -- before its t0 as well as after."""
    g = prep.geometry
    if c.name == "nest_knock":
        return (g.point == c.extra["point"]) & (g.side == c.extra["side"]) & np.isfinite(g.time_s)
    return g.at(c.extra.get("station"))[0]


def stops_rigid(prep, W: np.ndarray, of: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Every stop (Prepared.stop) that reads one of the readings ``of`` (bool (n,)) moving rigidly on its own -- a
    translation (mm) and a turn about its nests' centre (rad), machine frame -- as the blocks of
    Engine.score_blocks: the stop's rows of the whitened vector (``W``, (n, 3, 3)) and an orthonormal basis of its
    whitened columns (rank 3 for one nest, 5 for two, 6 for more).  What a nest's step must be seen beside where
    the stops move at random (a robot's base tilting from pose to pose): the step's share that is a rigid motion of
    its stop is not told from it, only its share that changes the stop's layout (selection._against_stops)."""
    g, stop = prep.geometry, prep.stop
    out = []
    for s in np.unique(stop[of]):
        rows = np.flatnonzero(stop == s)
        xyz = g.xyz[rows]
        motion = _rigid_motion(xyz, xyz.mean(axis=0))
        u, sv, _ = np.linalg.svd(np.einsum("mij,mjk->mik", W[rows], motion).reshape(-1, 6), full_matrices=False)
        out.append(((3 * rows[:, None] + np.arange(3)).ravel(), u[:, sv > 1e-9 * sv[0]]))
    return out


def step_pattern(prep, c: fx.Candidate, theta: np.ndarray) -> np.ndarray:
    """(n, 3) mm, machine frame: the motion the step ``c`` with parameters ``theta`` (a knock: a shift, mm; a
    re-levelling: a turn about the tracker, rad, and its shift; a nest knock: a shift, mm, in its side's frame) would
    give every reading of its place (step_rows), before its t0 as well as after."""
    g = prep.geometry
    rows = step_rows(prep, c)
    out = np.zeros((len(rows), 3))
    if c.name == "nest_knock":
        out[rows] = np.einsum("nij,j->ni", S.nest_creep_signature(g.rotation.reshape(-1, 9)[rows],
                                                                   np.ones(int(rows.sum()))), theta)
        return out
    shift = theta
    if c.name == "tracker_relevel":
        out[rows] = S.tracker_relevel_signature(g.xyz[rows], np.asarray(c.extra["tracker"]), 1.0) @ theta[:2]
        shift = theta[2:] if c.extra["shift"] else np.zeros(3)
    out[rows] += shift
    return out


def place_motion(prep, c: fx.Candidate) -> np.ndarray:
    """(n, 3, p) mm per parameter, machine frame: the motion of the step ``c``'s place (step_rows) per parameter of
    ``c`` (step_pattern of each unit vector) at every reading of the place, before its t0 as well as after -- the
    columns a change point of that place switches on (mtcal.diagnose.scans.change_points)."""
    p = c.G.shape[2]
    return np.stack([step_pattern(prep, c, e) for e in np.eye(p)], axis=-1)


def bump(prep, c: fx.Candidate, inside: np.ndarray) -> fx.Candidate:
    """The place of a step ``c`` (its station's frame, or its nest) displaced for a while and back: the readings
    ``inside`` (bool (n,), the place's readings between the two change points) moved together -- the frame by a
    rigid motion (a translation, mm, machine frame, and a turn, rad, about the tracker, else the readings' centre),
    the nest by a translation in its side's frame, mm -- and every other reading not at all.  A step that a second
    step takes back gives way to it (selection._change_points): icelinker's replica with base_2
    64 um off for poses 101-125 had base_2 named knocked at 101 and again at 126 (tests/test_real_icelinker.py)."""
    g, x, rec = prep.geometry, c.extra, prep.rec
    first, last = (int(i) for i in np.flatnonzero(inside)[np.argsort(prep.order[inside])[[0, -1]]])
    span = (f"from axis {rec.axis[first]} round {int(rec.round[first])} to round {int(rec.round[last])} "
            f"(t = {rec.time_s[first]:.6g} s to {rec.time_s[last]:.6g} s, {int(inside.sum())} readings)")
    if c.name == "nest_knock":
        G = S.nest_creep_signature(g.rotation.reshape(-1, 9), inside.astype(float))
        return fx.Candidate(fx.UNEXPLAINED, None, f"point {x['point']} ({x['side']} side) displaced {span} and back",
                            G, ["x (mm)", "y (mm)", "z (mm)"], family=f"{fx.UNEXPLAINED} place bump {x['side']} "
                            f"{x['point']}", extra=_at_the_nest(x, (
                                f"the reflector {x['point']} on the {x['side']} side is displaced for a while and "
                                "comes back: the nest bumped and re-seated, or its side tilted for a while -- not a "
                                "knock, which stays")))
    station = x.get("station")
    of = g.at(station)[2]
    return fx.Candidate(fx.UNEXPLAINED, None, f"the tracker{of}'s frame displaced {span} and back",
                        _frame_motion(g, station, inside), list(FRAME_MOTION),
                        family=f"{fx.UNEXPLAINED} place bump{of}", extra=_at_the_tracker(station, (
                            f"every reading of the tracker{of} moves together for a while and comes back: the "
                            "tracker's stand or the measured side bumped or tilted for a while (a robot's pose, a "
                            "load on the table) -- not a knock or a re-levelling, which stays")))


def _stop_columns(prep, axis: str, ids: list[int]) -> np.ndarray:
    """(n, 3, len(ids)): one column per stop ``ids`` (Prepared.stop) of the linear ``axis``, its positioning column
    (mm along the motion) on the nests read at that stop."""
    col = prep.geometry.col(prep.machine.positioning_errors[axis])
    G = np.zeros((len(col), 3, len(ids)))
    for k, s in enumerate(ids):
        on = prep.stop == s
        G[on, :, k] = col[on]
    return G


def stops_of(prep, c: fx.Candidate) -> fx.Candidate | None:
    """The free form of the stops a named effect ``c`` moves whole: every stop of its linear axis landing off on
    its own along the motion (one column each, _stop_columns), when each of ``c``'s columns moves every reading
    along the axis' motion, by the same amount at every nest read at one stop (a backlash, a graded backlash, a
    scale: functions of the stop's position and direction); None for any other candidate, a rotary axis, or an
    axis of more than MAX_AXIS_STOPS stops.  The split-plot design: such an effect is a contrast between stops, so
    its error term is their scatter (mtcal.diagnose.selection._against_the_stops)."""
    g, axis = prep.geometry, c.axis
    if axis is None or c.name == fx.UNEXPLAINED or not g.linear(axis):
        return None
    on = g.axis == axis
    if np.any(c.G[~on]):
        return None
    col = g.col(prep.machine.positioning_errors[axis])[on]            # (m, 3)
    Gc = c.G[on]                                                      # (m, 3, k)
    along = np.einsum("mi,mik->mk", col, Gc) / np.einsum("mi,mi->m", col, col)[:, None]
    scale = np.abs(Gc).max() or 1.0
    if np.abs(Gc - col[:, :, None] * along[:, None, :]).max() > 1e-9 * scale:
        return None                                                   # not along the motion
    stop = prep.stop[on]
    ids, inv = np.unique(stop, return_inverse=True)
    if len(ids) > MAX_AXIS_STOPS:
        return None
    mean = np.zeros((len(ids), along.shape[1]))
    np.add.at(mean, inv, along)
    mean /= np.bincount(inv)[:, None]
    if np.abs(along - mean[inv]).max() > 1e-9 * scale:
        return None                                                   # differs between the nests of a stop
    return fx.Candidate(fx.UNEXPLAINED, axis, f"every stop of axis {axis} landing off on its own",
                        _stop_columns(prep, axis, ids.tolist()),
                        [f"stop {k + 1} along {axis} (mm)" for k in range(len(ids))],
                        family=f"{fx.UNEXPLAINED} place stops {axis}", extra={
                            "kind": "place", "by": "round x position", "place": f"axis {axis}'s stops"})


def _words(c: fx.Candidate) -> str:
    """A named candidate in a few words: its name, axis and label."""
    return f"{c.name} {c.axis or ''} {c.label}".replace("  ", " ").strip()


def _reversal_place(g, axis: str, named: list[fx.Candidate]) -> Place | None:
    """Direction of approach x position: the reversal (reading(+) - reading(-), a 3-vector in the machine frame,
    mm) free at every measured position of the axis.  It spans the constant reversals of the rigid carriage that
    the named effects are (backlash, a lateral play) as they act at one reflector, and a lost motion that grows
    or changes along the travel (a worn screw) that none of them is."""
    on = (g.axis == axis) & (g.direction != 0)
    positions = np.unique(g.position[on])
    if len(positions) < 3:
        return None
    half = np.where(on, 0.5 * g.direction, 0.0)
    G = np.concatenate([S.outlier_signature(np.where(g.position == q, half, 0.0)) for q in positions], axis=-1)
    unit = g.machine.unit(axis)
    free = fx.Candidate(fx.UNEXPLAINED, axis, "direction of approach x position (free-form reversal)", G,
                        [f"r_{k}({q:g} {unit}) (mm)" for q in positions for k in "xyz"],
                        family=f"{fx.UNEXPLAINED} place reversal {axis}",
                        extra={"kind": "place", "by": "direction x position", "positions": positions.tolist(),
                               "unit": unit, "place": f"axis {axis}",
                               "note": f"the readings of {axis} differ between the directions of approach by an "
                                       "amount that changes along the travel, beyond every rigid reversal of the "
                                       "axis (backlash, straightness and angular reversals): a lost motion "
                                       "growing or changing with the position (a worn screw, a varying preload)"})
    s = np.zeros(len(g.axis))
    s[on] = (g.position[on] - positions[0]) / (positions[-1] - positions[0])
    linear = fx.Candidate("reversal x position", axis, "", S.outlier_signature(half * s), [], family="check")
    return Place(free, named, "the reversal of " + axis + " changes along the travel beyond the named reversals "
                 "of the axis together (direction of approach x position beside them: F = {F}, p = {p}): a lost "
                 "motion that varies with the position, not a constant one", (linear,))


def _tracker_place(g, c: fx.Candidate) -> Place | None:
    """A rigid step of the station's frame from t0: the knock's translation and a turn about the tracker (rad, a
    rotation vector: the tracker re-levelled or turned on its stand)."""
    station = c.extra.get("station")
    rows, tracker, of = g.at(station)
    if tracker is None:
        return None
    turn = _turn(g, tracker, rows & np.isfinite(g.time_s) & (g.time_s >= c.extra["t0_s"]))
    free = fx.Candidate(fx.UNEXPLAINED, None, f"rigid step of the tracker{of}'s frame at t0 = "
                        f"{c.extra['t0_s']:.6g} s", np.concatenate([c.G, turn], axis=-1),
                        list(c.params) + ["w_x (rad)", "w_y (rad)", "w_z (rad)"],
                        family=f"{fx.UNEXPLAINED} place tracker", extra=_at_the_tracker(station, (
                            f"every reading of the tracker{of} from t0 = {c.extra['t0_s']:.6g} s on moves by a step "
                            "that also turns about the tracker: the tracker re-levelled or turned on its stand (a "
                            "knock alone translates)"), t0_s=c.extra["t0_s"]))
    return Place(free, [c], "the step at t0 also turns the readings about the tracker (a turn beside the knock's "
                 "translation: F = {F}, p = {p}): the tracker re-levelled or turned, not knocked")


def _turn(g, tracker: np.ndarray, on: np.ndarray) -> np.ndarray:
    """(n, 3, 3) mm per rad: the readings ``on`` (bool (n,)) turned about the tracker (mm, machine frame) by a
    rotation vector's x, y, z components -- tracker_settling_signature's ramp column u x (point - T) with dt 1."""
    turn = np.zeros((len(on), 3, 3))
    turn[on] = _turn_about(g.xyz[on], tracker)
    return turn


def _rigid_motion(xyz: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """(m, 3, 6): the points ``xyz`` (m, 3) mm moved rigidly -- a translation (outlier_signature: I3, mm) and a
    turn about ``centre`` (_turn_about, mm per rad) -- FRAME_MOTION's six parameters."""
    return np.concatenate([S.outlier_signature(np.ones(len(xyz))), _turn_about(xyz, centre)], axis=-1)


def _turn_about(xyz: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """(m, 3, 3) mm per rad: the points ``xyz`` (m, 3) mm turned about ``centre`` by a rotation vector's x, y, z
    components -- tracker_settling_signature's ramp column u x (point - centre) with dt 1."""
    return np.stack([S.tracker_settling_signature(xyz, centre, u, np.ones(len(xyz)), 1.0)[:, :, 0]
                     for u in np.eye(3)], axis=-1)


def _axis_poses(g, c: fx.Candidate) -> Place:
    """Every nest of the axis of ``c`` (a quasi-static error motion of it: a scale, a quadratic, a periodic or
    constant error) displaced on its own at every pose (a translation per nest, station and position, pooled over
    the rounds and directions), beside the axis' error motions tabulated at its positions: whatever an error motion
    moves, it moves the nests of a pose rigidly together, so what the free form adds beyond them is the nests of a
    pose moving differently -- a reflector or the tracker reading off with the pose (a cyclic distance error, an
    incidence), not an error motion of the axis."""
    axis = c.axis
    on = g.axis == axis
    cells = fx.by_cell(g, np.flatnonzero(on), directions=False)
    labels = sorted(set(g.point[on].tolist()))
    free = fx.Candidate(fx.UNEXPLAINED, axis, f"every nest of axis {axis} displaced on its own at every pose",
                        cells.G, cells.params, family=f"{fx.UNEXPLAINED} place poses {axis}",
                        extra={"kind": "place", "by": "position x point", "place": f"the nests of axis {axis}",
                               "points": labels,
                               "note": f"the nests of axis {axis} move differently from each other at its poses, "
                                       "the same in every round, beyond any error motion of the axis (which moves "
                                       "the nests of a pose together): a reflector, or the tracker, reading off "
                                       "with the pose"})
    return Place(free, [c, fx.tabulated(g, axis)], f"the nests of axis {axis} move differently at its poses beyond "
                 "any error motion of it (each nest free at every pose beside the error motions tabulated there: "
                 "F = {F}, p = {p}): not an error motion of the axis")


def _side_nests(g, c: fx.Candidate) -> Place | None:
    """The same motion (a step at t0 or a creep from t0, 3-vector in the side's frame, mm or mm/s) at every nest
    of the named nest's side, each its own."""
    side, label = c.extra["side"], c.extra["point"]
    others = sorted(set(g.point[(g.side == side) & (g.point != label)].tolist()))
    if not others:
        return None
    time_law = (np.isfinite(g.time_s) & (g.time_s >= c.extra["t0_s"])).astype(float) if c.name == "nest_knock" \
        else np.where(np.isfinite(g.time_s), np.maximum(g.time_s - c.extra["t0_s"], 0.0), 0.0)
    rot = g.rotation.reshape(-1, 9)
    G = [S.nest_creep_signature(rot, np.where((g.point == p) & (g.side == side), time_law, 0.0)) for p in others]
    what = "step" if c.name == "nest_knock" else "creep"
    free = fx.Candidate(fx.UNEXPLAINED, None, f"every nest of the {side} side ({what} of each)",
                        np.concatenate([c.G] + G, axis=-1), [f"{p} {k}" for p in [label] + others for k in "xyz"],
                        family=f"{fx.UNEXPLAINED} place side {side}",
                        extra={"kind": "place", "by": f"nest x time ({side} side)", "place": f"the {side} side",
                               "side": side, "t0_s": c.extra["t0_s"], "points": [label] + others,
                               "note": f"the nests of the {side} side move with time, each its own way (a {what} "
                                       f"of one nest does not explain it): the side warming or growing (its nests "
                                       "moving apart) or distorting"})
    return Place(free, [c], f"the other nests of the {side} side move too (the same {what} at each beside it: "
                 "F = {F}, p = {p}): a motion or growth of the side, not of one nest")


def _side_layout(g, c: fx.Candidate) -> Place:
    """Each nest of the expanding side moving on its own with the expansion's law (a translation each, the side's
    frame: derive/grammar.py's expansion at unit offsets, ppm mm or ppm/h mm), which spans the expansion about any
    centre: the side's nests moving apart unevenly (one nest creeping, the side warping), which a growth alike is
    not.  icelinker's base: one mutual distance grows 7.9 um while the other two shrink 1.5 and 3.9 um, and the
    side was named expanding 25 ppm per hour about a centre fitted 2.5 m away."""
    x = c.extra
    side = x["side"]
    on = (g.side == side) & np.isfinite(g.time_s)
    nests = sorted(set(g.point[on].tolist()))
    dt = np.where(on, np.maximum(g.time_s - x["t0_s"], 0.0), 0.0)
    R = g.rotation.reshape(-1, 9)
    shift = np.zeros((len(on), 3, 3))  # the side moving along its x, y, z with the expansion's law
    for k, u in enumerate(np.eye(3)):
        unit = np.broadcast_to(u, (int(on.sum()), 3))
        shift[on, :, k] = (S.side_expansion_ramp_signature(R[on], unit, dt[on]) if x["law"] == "ramp" else
                           S.side_expansion_lag_signature(R[on], unit, dt[on], x["tau_s"]))
    law = "ramp" if x["law"] == "ramp" else f"lag, tau={x['tau_s']:.0f} s"
    free = fx.Candidate(fx.UNEXPLAINED, None, f"every nest of the {side} side (its own motion, {law})",
                        np.concatenate([shift * (g.point == p)[:, None, None] for p in nests], axis=-1),
                        [f"{p} {k}" for p in nests for k in "xyz"],
                        family=f"{fx.UNEXPLAINED} place side {side}",
                        extra={"kind": "place", "by": f"nest x time ({side} side)", "place": f"the {side} side",
                               "side": side, "t0_s": x["t0_s"], "points": nests,
                               "note": f"the nests of the {side} side move apart with time unevenly, each its own "
                                       "way (a growth alike about any centre does not explain it): the side warping "
                                       "or distorting, one nest creeping in its seat"})
    return Place(free, [c], f"the nests of the {side} side do not move apart alike (each nest's own motion with the "
                 "same law beside the growth: F = {F}, p = {p}): a distortion of the side, not an expansion")


def _nest_drifts(g, c: fx.Candidate) -> Place | None:
    """Each nest of the drifting side (or of every side, for the tracker) with its own drift of the same time law
    (3-vector each, mm): the side's nests moving apart or differently, which a translation of the side is not; and
    the drifting readings scaling about their station with that law (ppm; each station its own, about the tracker
    given or estimated, else the readings' centroid: with the drift's translation beside it, a scale about any point
    is one about the station) -- the air's refractive index drifting, which moves each reading along its beam."""
    moved = c.moved
    nests = sorted(set(zip(g.point[moved].tolist(), g.side[moved].tolist())))
    scale = _drift_scale(g, c, moved)
    if len(nests) < 2 and scale is None:
        return None
    G = np.concatenate([c.G * ((g.point == p) & (g.side == s))[:, None, None] for p, s in nests]
                       + ([] if scale is None else [scale.G]), axis=-1)
    target = c.extra["target"]
    free = fx.Candidate(fx.UNEXPLAINED, None, f"each nest of the {target}'s readings drifting on its own, and a "
                        "scale about the tracker", G, [f"{p} ({s}) {k}" for p, s in nests for k in "xyz"]
                        + ([] if scale is None else scale.params), family=f"{fx.UNEXPLAINED} place drift {target}",
                        extra={"kind": "place", "by": "nest x time", "place": f"the {target}",
                               "tau_s": c.extra["tau_s"], "t0_s": c.extra["t0_s"],
                               "points": [p for p, _ in nests],
                               "note": f"the nests read through the {target} move apart or differently with time: "
                                       "not one translation of the side (a drift) but a growth or distortion (the "
                                       "side warming unevenly), or every distance to the tracker scaling (the "
                                       "air's refractive index drifting uncompensated)"})
    return Place(free, [c], "the drifting readings move apart or scale (each nest's own drift, or a scale about the "
                 "tracker, beside the common one: F = {F}, p = {p}): a growth, a distortion or the air, not one "
                 "translation", () if scale is None else (scale,))


def _drift_scale(g, c: fx.Candidate, moved: np.ndarray) -> fx.Candidate | None:
    """The readings a drift ``c`` moves (``moved``) scaling with its time law about their station (each station's
    tracker, given or estimated; else their centroid): derive/grammar.py's expansion about the tracker, the air's
    lag signature (mm per ppm), one column per station.  None where the drift's readings are of one place only."""
    dt = np.where(np.isfinite(g.time_s), np.maximum(g.time_s - c.extra["t0_s"], 0.0), 0.0)
    cols = []
    for st in g.stations():
        rows, tracker, _ = g.at(st)
        on = rows & moved
        if not on.any():
            continue
        centre = tracker if tracker is not None else g.xyz[on].mean(axis=0)
        G = np.zeros((len(g.axis), 3, 1))
        G[on, :, 0] = S.air_index_drift_lag_signature(g.xyz[on], centre, dt[on], c.extra["tau_s"])
        cols.append(G)
    if not cols:
        return None
    return fx.Candidate("scale with the drift", None, "", np.concatenate(cols, axis=-1),
                        [f"scale {k + 1} (ppm)" for k in range(len(cols))], family="check")


def _settling_place(prep, c: fx.Candidate) -> Place | None:
    """A turn of the station's frame about the tracker free in every block of readings (one axis' round: rad, a
    rotation vector per block, relative to the first block in time): a tilt that jumps between blocks (the tracker
    re-levelled between rounds) as well as one that settles smoothly, which the named settling is."""
    g, rec = prep.geometry, prep.rec
    station = c.extra.get("station")
    rows, tracker, of = g.at(station)
    if tracker is None:
        return None
    blocks = _blocks(rec, rows)
    if len(blocks) < 3:
        return None
    cols = [_turn(g, tracker, sel) for sel in blocks[1:]]  # relative to the first block (a turn common to all
    #                                                          is the station's alignment)
    free = fx.Candidate(fx.UNEXPLAINED, None, f"turn of the tracker{of}'s frame in each block of readings",
                        np.concatenate(cols, axis=-1),
                        [f"w_{k}(block {b + 2}) (rad)" for b in range(len(cols)) for k in "xyz"],
                        family=f"{fx.UNEXPLAINED} place tracker turn", extra={
                            "kind": "place", "by": "block of readings (station frame)", "place": f"the tracker{of}",
                            **({"station": station} if station else {}),
                            "note": f"the readings of the tracker{of} turn about it from one block of readings to "
                                    "the next, not as a smooth settling: the tracker re-levelled or turned between "
                                    "rounds (log the tracker's level and station changes)"})
    return Place(free, [c], "the turn about the tracker jumps between blocks of readings beyond the settling "
                 "(a turn per block beside it: F = {F}, p = {p}): re-levelled or turned, not settling")


MAX_BLOCKS = 12  # blocks of a free turn: an axis' round each, or this many runs of readings in time where more


def _blocks(rec, rows: np.ndarray) -> list[np.ndarray]:
    """The blocks of readings of ``rows`` (bool (n,)) in time order: one per (axis, round), or MAX_BLOCKS runs of
    equal count in time where there are more (a recording of a thousand poses)."""
    keys = sorted(set(zip(rec.axis[rows].tolist(), rec.round[rows].tolist())))
    first = {k: float(np.min(rec.time_s[rows & (rec.axis == k[0]) & (rec.round == k[1])])) for k in keys}
    keys.sort(key=lambda k: (first[k], k))
    if len(keys) <= MAX_BLOCKS:
        return [rows & (rec.axis == a) & (rec.round == r) for a, r in keys]
    idx = np.flatnonzero(rows)
    idx = idx[np.argsort(rec.time_s[idx], kind="stable")]
    out = []
    for part in np.array_split(idx, MAX_BLOCKS):
        sel = np.zeros(len(rows), bool)
        sel[part] = True
        out.append(sel)
    return out
