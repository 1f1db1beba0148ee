"""The selection decides from the candidates' grammar attributes (where x what x how, mtcal.diagnose.effects.Grammar)
and their columns, never from their names (issue 52): nesting is a column-space inclusion beside the base, the
held-out folds follow from "depends on time or is round-specific", ties from "same where and what, another clock",
and separate_by's advice from which attribute differs.  Each test builds the candidates on one small simulated
campaign (tests/campaigns.py, no effect planted: the columns alone are compared)."""
from __future__ import annotations

import dataclasses

import campaigns as C
import numpy as np
import pytest

from mtcal import load_machine
from mtcal.diagnose import effects as fx
from mtcal.diagnose.design import base_design, engine_for, family_degrees, whiten
from mtcal.diagnose.engine import Score
from mtcal.diagnose.prepare import TIE_POSITIONS, prepare
from mtcal.diagnose.run import MAX_DEGREE
from mtcal.diagnose.selection import Columns, Step, _contains, _may_tie, folds
from mtcal.diagnose.separate import MEASURE_HOW, WITNESS, separate_by
from mtcal.measurement.tracker import AT960


@pytest.fixture(scope="module")
def setup():
    c = C.make(C.Design(rounds=3, axes=("X", "Y", "Z")), (), 1)
    prep = prepare(c.recording, load_machine("dmu50"), None, c.tracker, MAX_DEGREE, TIE_POSITIONS, AT960)
    w = Columns(prep.W)
    eng = engine_for(prep, base_design(prep, family_degrees(prep, MAX_DEGREE)), whiten(prep.W, prep.y))
    return prep, w, eng.copy_base()


def _knock(prep, axis="Y", k=2):
    """A tracker knock at the first reading of ``axis``' round ``k`` and the re-levelling (with its shift) there."""
    g, rec = prep.geometry, prep.rec
    on = (rec.axis == axis) & (rec.round == k)
    t0 = float(rec.time_s[on].min())
    where = {"from_axis": axis, "round": k, "point": str(rec.point[on][0]), "position": 0.0,
             "readings": int((rec.time_s >= t0).sum())}
    knock = fx.tracker_knock(g, t0, where)
    after = rec.time_s >= t0
    relevel = fx.tracker_relevel(g, after, t0, {"round": k, "axis": axis}, None, knock)
    return knock, relevel


def test_nesting_is_computed_from_the_columns(setup):
    """A backlash changing along the travel contains the constant backlash (its columns at g = 0) and not the
    other way round; a re-levelling with its shift contains the knock at its t0; a re-seated reflector (one
    sequence shifted) and a tracker knock (every reading after t0 shifted) contain neither the other."""
    prep, w, base = setup
    g = prep.geometry
    travel, const = fx.backlash_travel(g, "X"), fx.backlash(g, "X")
    assert _contains(base, w, travel, const) and not _contains(base, w, const, travel)
    knock, relevel = _knock(prep)
    assert _contains(base, w, relevel, knock) and not _contains(base, w, knock, relevel)
    rows = np.flatnonzero((prep.rec.axis == "Y") & (prep.rec.round == 1) & (prep.rec.point == prep.rec.point[0]))
    seated = fx.offset(g, rows, {"round": 1, "point": str(prep.rec.point[rows[0]])})
    assert not _contains(base, w, seated, knock) and not _contains(base, w, knock, seated)


def test_the_folds_follow_from_how_a_candidate_depends(setup):
    """The same columns are validated on held-out rounds when the grammar says they repeat over rounds, and on
    held-out alternate readings when it says they depend on time (or are specific to one round): the name plays
    no part."""
    prep, _, _ = setup
    c = fx.backlash(prep.geometry, "X")
    assert folds(prep, c)[1] == "held-out rounds"
    timed = dataclasses.replace(c, grammar=dataclasses.replace(
        c.grammar, how=fx.How(frozenset({"time"}), "ramp")))
    held, how = folds(prep, timed)
    assert how == "held-out alternate readings" and len(held) == 2
    assert not np.any(held[0] & held[1]) and np.all(held[0] | held[1])


def test_one_motion_by_two_clocks_never_ties_and_two_time_laws_at_the_tracker_may(setup):
    """A side's drift with time and the same side's drift with a temperature are one motion by two clocks (same
    where and what, another how): never tied.  At the tracker a knock and a drift (another time law, the same
    readings) may tie; a knock and the re-levelling that contains it (computed) may not."""
    prep, w, base = setup
    g = prep.geometry
    t0 = float(np.nanmin(prep.rec.time_s))
    dT = np.where(np.isfinite(prep.rec.time_s), (prep.rec.time_s - t0) / 3600.0, 0.0)
    drift = fx.thermal_drift(g, "spindle", 1800.0, t0)
    by_temperature = fx.thermal_temperature_drift(g, "spindle", dT)
    assert not _may_tie(base, w, _step(drift, 2.0), _step(by_temperature, 1.0))
    knock, relevel = _knock(prep)
    tracker_drift = fx.thermal_drift(g, "tracker", 1800.0, t0)
    assert _may_tie(base, w, _step(knock, 2.0), _step(tracker_drift, 1.0))
    assert not _may_tie(base, w, _step(knock, 2.0), _step(relevel, 2.5))  # it nests the knock: never tied


def _step(c: fx.Candidate, delta: float) -> Step:
    """A step of ``c`` whose columns explain ``delta`` of the misfit (what _may_tie compares)."""
    return Step(c, Score(True, 1.0, delta=delta), -50.0)


def test_separate_by_names_the_measurement_of_the_attribute_that_differs(setup):
    """how differs (the position): measure along the travel; where differs (the air and a side): one sentence
    whichever comes first, the air's witness first; what differs (a turn and a shift of the tracker's frame):
    reflectors at several distances; the law differs (a step and a settling turn of the frame): log the times."""
    prep, _, _ = setup
    g = prep.geometry
    t0 = float(np.nanmin(prep.rec.time_s))
    travel, const = fx.backlash_travel(g, "X"), fx.backlash(g, "X")
    assert separate_by(travel, const).startswith("measure at more positions over the whole travel")
    assert separate_by(const, travel).endswith("backlash travel changes with the direction of approach and the "
                                               "position, backlash with the direction of approach only")
    air, drift = fx.air_index_drift(g, t0), fx.thermal_drift(g, "table", 1800.0, t0)
    assert separate_by(air, drift) == separate_by(drift, air)
    assert separate_by(drift, air).startswith("measure from a second station at a right angle")
    knock, relevel = _knock(prep)
    assert "grows with the lever" in separate_by(relevel, knock)
    settling = fx.tracker_settling(g, 1800.0, t0)
    assert set(WITNESS) == set(fx.WHERE) and set(MEASURE_HOW) == set(fx.HOW)  # a template for every value
    assert separate_by(relevel, settling).startswith("log the times")
    assert "is a step that stays" in separate_by(relevel, settling)


WHERE_WORDS = {"axis": "one axis", "side": "side", "nest": "one reflector", "reading": "one reflector",
               "frame": "tracker", "air": "tracker"}


def test_every_candidates_attributes_agree_with_the_grammars_members(setup):
    """derive/grammar.py states every member's where x what x how in words (MEMBERS); each candidate's structured
    attributes, stated where mtcal.diagnose.effects builds it, say the same: the place, what moves, what it depends
    on and its time law."""
    from derive.grammar import MEMBERS
    from mtcal.diagnose.candidates import candidates

    prep, _, _ = setup
    g = prep.geometry
    built, _ = candidates(prep, MAX_DEGREE)
    rows = np.flatnonzero(prep.seq == 0)[:1]
    where = {"round": 1, "point": str(prep.rec.point[rows[0]]), "position": 0.0, "approach": 1, "readings": 1,
             "from_axis": "X"}
    t0 = float(np.nanmin(prep.rec.time_s))
    built += [*_knock(prep), fx.outlier(g, rows, "reading", where), fx.air_index_drift(g, t0),
              fx.nest_knock(g, str(prep.rec.point[rows[0]]), str(g.side[rows[0]]), t0 + 600.0, where)]
    names = set()
    for c in (c for c in built if not c.free and c.name in MEMBERS):
        m, gr = MEMBERS[c.name], c.grammar
        assert WHERE_WORDS[gr.where.at] in m.where, (c.name, gr, m)
        assert gr.what in m.what or gr.what in ("translation", "rotation") and "error" in m.what, (c.name, gr, m)
        for v in ("direction", "position", "temperature"):
            assert (v in gr.how.on) <= (v in m.how), (c.name, v, m)
        assert gr.how.on or "constant" in m.how, (c.name, m)
        assert gr.how.law not in (fx.LAW_STEP, "ramp", "lag") or gr.how.law in m.how, (c.name, gr.how.law, m)
        assert "round" not in gr.how.on or fx.LAW_STEP in m.how, (c.name, m)
        names.add(c.name)
    assert len(names) >= 17, sorted(names)  # every member this XYZ campaign (no temperature channel) offers
