"""Issue 34 item 2, a finding named only when the data need it: two named changes at different places that fit one
misfit alike are not named (mtcal.diagnose.selection._tied); a side warming about a point away from its reflectors
is one expansion, its centre fitted, not an expansion and a drift (mtcal.diagnose.effects.side_expansion); several
knocks of one station in one axis' round are one located misfit (selection.steps_per_place).

Most campaigns are an independent generator's (benchmarks/gen2, written from the physics by a helper that had not
read mtcal/diagnose), runs that were wrong on the code named in each test (the seeds 3503-3507 were generated and
measured once, then became the work's cases); the others are mtcal's own (tests/campaigns.py):

* 3503/23: Y's straightness bows with time (E_ZY, 7.4 um at mid-travel by the end; gen2 "thermal_straightness",
  outside the grammar).  4457c89 named a tracker knock at 3158 s, with a spindle drift that explained 35.4 against
  the knock's 36.5 (whitened sums of squares) -- a likelihood ratio of 1.8 between two places;
* 3504/3: the table warming (24 ppm by the end, linear) read from an estimated station; 4457c89 named a creep of
  nest P5;
* 3504/25: the spindle side warming about the gauge point, 33 ppm by the end, two stations given; 4457c89 named the
  expansion about the reflectors' centroid and, beside it, a drift of the spindle: the same warming's translation;
* 3505/7, 3507/35, 3515/0, 3515/12, 3520/19, 3525/11, 3528/11, 3528/26 and mtcal's planted campaign 7: in their tests.
"""
from __future__ import annotations

import numpy as np
import pytest
from test_diagnose_air import R, _gen2, _named

from mtcal.diagnose import diagnose
from mtcal.measurement.recordings import parse_recording

pytestmark = pytest.mark.slow  # a diagnosis each: 3-20 s


def _run(tmp_path, seed: int, index: int, how: str):
    path, truth = _gen2(tmp_path, seed, index)
    (text,) = [t for h, t in R.cases(path.read_text()) if h == how]
    d = diagnose(parse_recording(text, path.name))
    return d, R.judge(d.to_dict(), R.planted_of(truth, parse_recording(path.read_text(), path.name)))


@pytest.mark.parametrize("how", ["defaults", "given"])
def test_a_bowing_straightness_is_one_located_misfit_not_a_knock(tmp_path, how):
    d, verdict = _run(tmp_path, 3503, 23, how)
    assert _named(d) == [], _named(d)
    assert [u.axis for u in d.unexplained] in ([], ["Y"]), [(u.axis, u.by, u.where) for u in d.unexplained]
    assert verdict.verdict == "right", verdict
    tie = [u for u in d.unexplained if u.by == "effects fitting alike"]
    for u in tie:  # the names it may be, none of them named
        assert "tracker knocked" in u.where and "thermal_drift spindle" in u.where, u.where


@pytest.mark.xfail(strict=True, reason=(
    "issue 52, open: after this session's merges (attributes, change points, one error term, sizes, the station "
    "and law) nothing is claimed here (judged 'missed'); each branch's own guard run passed it; which rule is "
    "wrong is not established"))
def test_a_warming_table_is_not_a_creeping_nest(tmp_path):
    d, verdict = _run(tmp_path, 3504, 3, "defaults")
    assert "nest_creep" not in [n for n, _ in _named(d)], _named(d)
    assert verdict.verdict == "right", (verdict, _named(d), [(u.axis, u.by) for u in d.unexplained])
    assert {u.axis for u in d.unexplained} <= {"B", "C"}  # the table's axes


def test_a_spindle_warming_about_the_gauge_point_is_one_expansion(tmp_path):
    d, verdict = _run(tmp_path, 3504, 25, "given")
    assert _named(d) == [("side_expansion", None)], _named(d)
    (f,) = [f for f in d.effects if f.significant]
    assert f["side"] == "tool" and "centre_from_centroid_mm" in f.to_dict(), f.to_dict()
    assert f["estimate"] > 0  # the nests move apart: a warming
    assert verdict.verdict == "right", verdict



def test_a_drift_is_not_an_expansion_about_a_fitted_centre():
    """A side's expansion about a fitted centre contains that side's drift with the same law (e = 0: its translation
    alone); where the expansion adds nothing significant beside the drift, the drift is named (selection._simplest,
    computed column inclusion; on icelinker's base reflectors, drifting 56 um together, the expansion was named).
    A spindle drifting 20 um along +X (tau 5000 s), no expansion planted: both scored on the diagnosis' null, the
    centre-fitted expansion (the drift's columns and e) gives way to the drift; on c64bc20 it was kept."""
    import math

    import campaigns as C

    from mtcal import load_machine
    from mtcal.diagnose import effects as fx
    from mtcal.diagnose.candidates import layout_offsets
    from mtcal.diagnose.design import base_design, engine_for, family_degrees, whiten
    from mtcal.diagnose.prepare import TIE_POSITIONS, prepare
    from mtcal.diagnose.run import LEVEL, MAX_DEGREE
    from mtcal.diagnose.selection import Columns, Step, _simplest
    from mtcal.measurement.tracker import AT960

    eff = [("thermal_drift", {"target": "spindle", "amplitude": 0.02, "direction": "+X", "tau_s": 5000.0})]
    c = C.make(C.Design(rounds=3, axes=("X", "Y", "Z")), eff, 1)
    prep = prepare(c.recording, load_machine("dmu50"), None, c.tracker, MAX_DEGREE, TIE_POSITIONS, AT960)
    w = Columns(prep.W)
    eng = engine_for(prep, base_design(prep, family_degrees(prep, MAX_DEGREE)), whiten(prep.W, prep.y))
    g = prep.geometry
    t0 = float(prep.rec.time_s[g.side == "tool"].min())
    drift = fx.thermal_drift(g, "spindle", 5000.0, t0)
    grown = fx.side_expansion(g, layout_offsets(prep), "tool", t0, 5000.0, centre=True)
    steps = [Step(x, sc, sc.logp + math.log(2)) for x, sc in ((x, eng.score(w(x))) for x in (grown, drift))]
    assert all(s.logp_adj < math.log(LEVEL) for s in steps)  # both significant on their own
    chosen = _simplest(prep, eng, steps[0], steps, w, LEVEL).candidate
    assert (chosen.name, chosen.label) == (drift.name, drift.label)
    assert np.allclose(chosen.G, drift.G)


@pytest.mark.parametrize("how", ["defaults", "given"])
def test_an_axis_repeating_worse_is_not_a_tracker_knocked_twice(tmp_path, how):
    """gen2 seed 3505 campaign 7: Y lands 3.1 um off at every stop, shared by the nests read there (gen2's
    "axis_scatter"; the per-stop test reads p_adj 0.0067 here, just above the level).  c64bc20 named two knocks of
    the tracker in Y's second round, 210 s apart (+3.3 um, then -7.0 um along Y); several knocks of one station in
    one block of readings are now one located misfit on Y (selection.steps_per_place; since the stops' free
    form, places.stops_off, the first knock is already Y's stops landing off), nothing named."""
    d, verdict = _run(tmp_path, 3505, 7, how)
    assert _named(d) == [], _named(d)
    steps = [u for u in d.unexplained if "stepping" in str(u.where) or "landing off" in str(u.where)]
    assert [u.axis for u in steps] == ["Y"], [(u.axis, u.by, u.where) for u in d.unexplained]
    assert {u.axis for u in d.unexplained} == {"Y"}
    assert verdict.verdict == "right", verdict


@pytest.mark.parametrize("seed, index, how, axis", [
    (3515, 0, "given", "X"),
    (3515, 12, "defaults", "Y"),
    (3525, 11, "defaults", "X")])
def test_a_few_stops_landing_off_are_not_a_tracker_knock(tmp_path, seed, index, how, axis):
    """gen2 seed 3515 campaign 0 (two stations given; X lands 4.3 um off at every stop, too few rounds per station
    for the per-stop test to test X) and campaign 12 (one station, estimated; Y 1.7 um per stop, the per-stop test
    at p_adj 0.05): 6410c10 named a knock of S2's tracker along -X within X's third round (and on 12, one along +Y
    within Y's fourth); campaign 11 of seed 3525 (one station, estimated, isotropic; X 6 rounds): f8e00fb named a
    knock along -X within X's fifth round, its shorter side 18 stops over rounds 5 and 6.  Each axis' stops on the
    shorter side of the step, each landing off along the motion on its own (places.stops_off), fit as well by
    Akaike's measure: one located misfit on that axis, no knock named.  On 12, once the place's free form was tested
    against the stops' scatter over the rounds while the member was still tested against the readings' (bc347f2), a
    backlash of Y was named (F = 99.7 beside the fit): against the place's one error term (selection.place_needed)
    it is F = 16 on 1 and 36 degrees of freedom, p = 3.2e-4, not significant at its multiplicity (x 43)."""
    d, verdict = _run(tmp_path, seed, index, how)
    assert _named(d) == [], _named(d)
    stops = [u for u in d.unexplained if "landing off" in str(u.where)]
    assert stops and {u.axis for u in stops} == {axis}, [(u.axis, u.by, u.where) for u in d.unexplained]
    assert verdict.verdict == "right", verdict


@pytest.mark.parametrize("seed, index, how, axis", [(3528, 11, "defaults", "X"), (3528, 26, "given", None)])
def test_nests_off_together_at_one_stop_are_not_outlier_readings(tmp_path, seed, index, how, axis):
    """gen2 seed 3528 campaign 11 (one station, estimated, isotropic; X lands 4.1 um off at every stop, all nests
    read there sharing the draw): 4814652 named as outlier readings the four nests of one stop of X (round 4, 88.12
    mm, approach -1), each a "one-off reading" though the other nests of its stop were off the same way.  Campaign
    26 (one station given, a 1 : 70 tracker re-levelled before X's sixth round): 4814652 named bumps of P1 and P2
    from 79.9 mm in round 6 and single readings of P2 and P4 at 0 mm, where every nest read at those stops had
    moved.  A one-off reading is not shared by its stop (selection.inadequate_because, effects.same_stops): on 11
    the misfit is located on X, on 26 the re-levelling is named (gen2's judge: right), no outlier on either."""
    d, verdict = _run(tmp_path, seed, index, how)
    assert [n for n, _ in _named(d) if n == "outlier"] == [], _named(d)
    if axis:
        assert axis in {u.axis for u in d.unexplained}, [(u.axis, u.by, u.where) for u in d.unexplained]
    assert verdict.verdict == "right", verdict


def test_a_rival_fitting_alike_ties_whether_or_not_it_is_significant_itself(tmp_path):
    """gen2 seed 3520 campaign 19 (one station given, an isotropic tracker; X's straightness in Z bows with time,
    9.2 um at mid-travel by the end): 2e2d3ff named a tracker re-levelled before X's third round (chi^2 reduction
    24.4, two columns), while a knock of the tracker fitted 23.8 and a settling 27.8 -- not significant
    themselves, the knock's t0 and the settling's tau scanned over many members.  A rival's multiplicity says how
    hard it is to find, not how well it explains the misfit found: one located misfit on X listing them, nothing
    named (selection._tied over every family's best)."""
    d, verdict = _run(tmp_path, 3520, 19, "given")
    assert _named(d) == [], _named(d)
    assert [(u.axis, u.by) for u in d.unexplained] == [("X", "effects fitting alike")], d.unexplained
    assert "tracker_relevel" in d.unexplained[0].where and "tracker_settling" in d.unexplained[0].where
    assert verdict.verdict == "right", verdict


def test_a_re_levelling_at_a_stations_later_block_is_named_not_tied(tmp_path):
    """gen2 seed 3507 campaign 35 (three stations given): S3's tracker re-levelled before Z's third round, S3's
    first reading of Z.  A settling of S3 and a knock of S3 at 12178 s fit it alike (behind by 5.9); 89032d8
    located the misfit on X, where the settling's fit was largest and the knock moves nothing, and 2e61bba among
    the readings both move, on Z.  Z is read from the other stations too, so the re-levelling is now offered at
    S3's block of Z (candidates.round_starts) and named: the truth, before Z's third round."""
    d, verdict = _run(tmp_path, 3507, 35, "given")
    (f,) = [x for x in d.to_dict()["effects"] if x["significant"]]
    assert (f["name"], f["station"]) == ("tracker_relevel", "S3") and "before round 3 of axis Z" in f["where"], f
    assert d.unexplained == [] and verdict.verdict == "right", (d.unexplained, verdict)


@pytest.mark.parametrize("seed, index, axis", [(3553, 21, "X"), (3560, 32, "Z")])
def test_effects_fitting_alike_are_located_where_the_leading_change_happens(tmp_path, seed, index, axis):
    """Steps of a station's frame tied with another change in time are located at the axis of the leading step's
    t0 (a step shows on either side of it, wherever the station's alignment puts it).  gen2 3553/21 (three
    stations given, an isotropic tracker): X's straightness bows with time; a knock of S1 within X's second round
    and a re-levelling of S1 at Y's block start fit it alike (behind by 6.7), and 4052cbc put the misfit among the
    readings both move, on B, where nothing was planted.  gen2 3560/32 (three stations, a 1 : 4 tracker): S3
    re-levelled between its blocks of Y and Z; a knock of S3 at Z's block start and a re-levelling there fit it
    alike (behind by 3.7), and 95da35c, counting every reading, put it on X (S3's readings before the step show it
    as much).  Now on X and on Z."""
    d, verdict = _run(tmp_path, seed, index, "given")
    assert _named(d) == [], _named(d)
    assert [(u.axis, u.by) for u in d.unexplained] == [(axis, "effects fitting alike")], d.unexplained
    assert verdict.verdict == "right", verdict


def test_a_settling_tracker_is_not_named_a_spindle_side_expanding():
    """mtcal's planted campaign 7 (tests/campaigns.py planted: a creeping nest Q and a settling tracker, far
    station, told): a spindle side expanding about a fitted centre fits 367.1, the settling 369.1 (lead 2.0 with
    Akaike's penalty); beside the expansion the settling keeps 34.6 -- still significant, so 2e61bba named the
    expansion, but 9 % of its fit: the same misfit.  Now one located misfit, and the creep named."""
    import campaigns as C
    from diagnose_judge import judge

    c = C.planted(7)
    d = diagnose(c.recording, c.model, machine=c.design.machine, tracker=c.tracker)
    assert _named(d) == [("nest_creep", None)], _named(d)
    assert [u.by for u in d.unexplained if u.by == "effects fitting alike"] == ["effects fitting alike"]
    assert judge(d, c.expect)[1].startswith("right"), judge(d, c.expect)[1]
