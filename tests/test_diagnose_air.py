"""Issue 34 items 1-2: the air's refractive index drifting while the tracker's weather compensation keeps its first
value (derive/grammar.py's ``air_index_drift``: every reading of every station scales about its own station by one
law, S + (1 + 1e-6 e h(t)) (p - S)).

An independent generator plants it (benchmarks/gen2, README table row ``air_temperature``: kappa at the end 1.5-5
ppm, a ramp or a first-order lag); before the member existed the diagnosis named it as something false: gen2 seed
3502 campaign 13 (two stations, -3.74 ppm lag, tau 1161 s) "thermal_drift spindle, tau=1185 s", campaign 8 (two
stations, +4.04 ppm lag, tau 1917 s) "thermal_drift tracker of station S1, tau=6001 s".  Now it is named, sized
with an interval that covers the truth, and nothing else is named beside it; a clean campaign does not name it; a
drift of the tracker itself is still named thermal_drift.
"""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import mtcal
from mtcal.campaign.plans import Plan
from mtcal.campaign.simulate import simulate
from mtcal.diagnose import diagnose
from mtcal.measurement.recordings import parse_recording

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

import diagnose_gen2_rates as R  # noqa: E402


def _gen2(tmp_path: Path, seed: int, index: int) -> tuple[Path, dict]:
    """gen2's campaign ``index`` of ``seed`` in the mix benchmarks/diagnose_gen2_rates.py runs as "outside"."""
    subprocess.run([sys.executable, str(R.GEN2), "--out", str(tmp_path), "--seed", str(seed), "--start",
                    str(index), "--n", "1", "--mix", "outside", "--clean-fraction", "0.3"], check=True,
                   capture_output=True)
    path = tmp_path / f"campaign_{index:04d}.csv"
    return path, json.loads(path.with_suffix(".truth.json").read_text())


def _named(d) -> list[tuple[str, str | None]]:
    return [(f.name, f.axis) for f in d.effects if f.significant]


def test_the_air_scales_every_reading_about_the_tracker():
    """law lag, 4 ppm, tau 1800 s: every reading moves by 4e-6 (1 - exp(-t / 1800 s)) (p - S) about the tracker S
    (written here, not from the generated model); the truth gives the scale at the last reading."""
    rec0, _ = simulate(None, noise=False)
    rec, truth = simulate(None, noise=False, effects=["air_index_drift:law=lag,ppm=4,tau_s=1800"])
    S = np.asarray(Plan().tracker, float)
    h = 4e-6 * (1 - np.exp(-rec.time_s / 1800.0))
    np.testing.assert_allclose(rec.xyz - rec0.xyz, h[:, None] * (rec0.xyz - S), rtol=1e-9, atol=1e-12)
    e = truth["effects"][0]
    assert e["law"] == "lag" and e["ppm_at_end"] == pytest.approx(4 * (1 - np.exp(-rec.time_s.max() / 1800.0)))
    ramp, _ = simulate(None, noise=False, effects=["air_index_drift:law=ramp,ppm_per_h=2"])
    np.testing.assert_allclose(ramp.xyz - rec0.xyz, (2e-6 * rec.time_s / 3600.0)[:, None] * (rec0.xyz - S),
                               rtol=1e-9, atol=1e-12)


def test_the_members_signature_is_the_simulated_effect():
    """The candidate's columns (generated from the same SymPy expression) times e are the simulated displacement:
    exactly, for the scale is linear in e."""
    from mtcal.diagnose import effects as fx
    from mtcal.diagnose.prepare import prepare
    pl = Plan()
    rec0, _ = simulate(None, plan=pl, noise=False)
    rec, _ = simulate(None, plan=pl, noise=False, effects=["air_index_drift:law=lag,ppm=5,tau_s=900"])
    prep = prepare(rec0, "dmu50", tracker=pl.tracker)
    G = fx.air_index_drift(prep.geometry, 0.0, 900.0).G[:, :, 0]
    np.testing.assert_allclose(rec.xyz - rec0.xyz, 5.0 * G, rtol=1e-9, atol=1e-12)


def _plan_rec(effect: str | None, seed: int):
    plan = {"axes": {a: {"positions": Plan().positions[a].tolist()} for a in "XYC"}, "rounds": 3}
    return mtcal.simulate(seed=seed, plan=plan, effects=[effect] if effect else [])


@pytest.mark.slow
def test_an_air_change_from_one_station_is_named_with_its_size():
    """mtcal's own campaign (X, Y, C, three rounds, the tracker given): 4 ppm with a time constant of 1800 s."""
    rec, _ = _plan_rec("air_index_drift:law=lag,ppm=4,tau_s=1800", 11)
    d = diagnose(rec, tracker=Plan().tracker)
    assert _named(d) == [("air_index_drift", None)] and not d.unexplained, (_named(d), d.unexplained)
    f = d.effects[0]
    lo, hi = f["interval_95"]
    assert f["unit"] == "ppm" and lo < 4.0 < hi and hi - lo < 1.0, f["interval_95"]
    assert f["says"].startswith("the tracker's distances lengthen by 4.") and "weather compensation" in f["says"]
    assert f.evidence["cv_gain"] > 0 and f["predictive_check"]["passes"]


@pytest.mark.slow
def test_a_tracker_drift_is_still_named_thermal_drift():
    """A drift of the tracker stand (20 um along +Y, tau 1200 s: the beam's direction, so the air's scale is its
    rival) is named thermal_drift as before, not the air."""
    rec, _ = _plan_rec("thermal_drift:target=tracker,amplitude=0.02,tau_s=1200,direction=+Y", 11)
    d = diagnose(rec, tracker=Plan().tracker)
    assert _named(d) == [("thermal_drift", None)], _named(d)
    assert d.effects[0]["estimate"] == pytest.approx(0.02, abs=0.002)


def test_a_clean_campaign_names_no_air_change():
    rec, _ = _plan_rec(None, 11)
    d = diagnose(rec, tracker=Plan().tracker)
    assert _named(d) == []
    air = [f for f in d.effects if f.name == "air_index_drift"]
    assert air and not air[0].significant  # offered, tested, not significant


@pytest.mark.slow
@pytest.mark.parametrize("index", [8, 13])
def test_gen2_air_changes_are_named_not_a_thermal_drift(tmp_path, index):
    """gen2 seed 3502 campaigns 8 and 13 (two stations each, the tracker given): on e58d8c4 named a thermal_drift
    alone (judged wrong). A drift of the spindle or of one station's tracker explains as much of these as the air
    (whitened sums of squares 117.8 against 116.8, 148.2 against 141.6: selection._contained_elsewhere): the two are
    not told apart here, so the drift named lists the air's drift beside it and the judge takes that; where the air
    is named, its fit holds the planted change at the last reading within its 95 % interval.  Where a drift of the
    tracker and a change at another place (a side growing) fit alike (selection._tied), nothing is named: one
    located misfit says what it may be."""
    path, truth = _gen2(tmp_path, 3502, index)
    (air,) = [e for e in truth["effects"] if e["name"] == "air_temperature"]
    rec = parse_recording(path.read_text(), path.name)
    d = diagnose(rec)
    named = _named(d)
    planted = R.planted_of(truth, rec)
    assert R.judge(d.to_dict(), planted).verdict == "right"
    if d.unexplained:
        assert not named and [u.by for u in d.unexplained] == ["effects fitting alike"], (named, d.unexplained)
        assert "drift" in d.unexplained[0].where, d.unexplained[0].where
        return
    assert len(named) == 1, named
    f = d.effects[0]
    if f.name == "air_index_drift":
        lo, hi = f["change_over_record"]["interval_95"]  # the scale at the last reading, over the time constant
        assert lo < air["details"]["ppm_at_end"] < hi and lo * hi > 0 and hi - lo < 5.0, (lo, air["details"], hi)
    else:
        assert f.name == "thermal_drift" and "air_index_drift" in [c["name"] for c in f["confounded_with"]], f


@pytest.mark.slow
@pytest.mark.parametrize("index", [5])
def test_a_gen2_clean_campaign_of_two_stations_names_no_air_change(tmp_path, index):
    """gen2 seed 3502 campaign 5 (two stations): clean; the air's drift is tested, not named."""
    path, truth = _gen2(tmp_path, 3502, index)
    assert not truth["effects"]
    d = diagnose(parse_recording(path.read_text(), path.name))
    assert "air_index_drift" not in [n for n, _ in _named(d)]
    assert any(f.name == "air_index_drift" for f in d.effects)


def test_a_drift_lists_the_air_where_the_station_is_not_determined():
    """Where the air's drift could not be tested (candidates' note: the station not determined, the untested
    member's grammar with it), a selected drift lists it in confounded_with with what separates them (gen2 seed
    9000 campaign 2, B and C from one station, the tracker columns removed: a 4.6 ppm air ramp came out as a drift
    of the table alone); a tested station adds nothing; nor does a note of another kind, nor a step (a knock is
    no gradual change)."""
    from mtcal.diagnose import effects as fx
    from mtcal.diagnose.candidates import NOT_SEPARABLE
    from mtcal.diagnose.engine import Score
    from mtcal.diagnose.selection import Step, untested_confounds

    def drift(law: str = "lag") -> Step:
        g = fx.Grammar(fx.Where("side", "table"), "translation", fx.How(frozenset({"time"}), law))
        c = fx.Candidate("thermal_drift", None, "table, tau=1800 s", np.zeros((2, 3, 3)), ["A_x", "A_y", "A_z"],
                         grammar=g)
        return Step(c, Score(True, 1.0), -50.0)

    undetermined = {"name": "air_index_drift", "axis": None, "kind": "station undetermined",
                    "not_separable": NOT_SEPARABLE["air_index_drift undetermined"], "untested": fx.air_grammar(),
                    "where": "the air's refractive index drifting (not tested: the station is not determined)"}
    s = drift()
    untested_confounds([s], [undetermined])
    (rival,) = s.confounded_with
    assert rival["name"] == "air_index_drift" and "not determined" in rival["where"]
    assert rival["separate_by"].startswith("measure from a second station at a right angle")
    s = drift()
    untested_confounds([s], [{"name": "air_index_drift", "axis": None,
                              "not_separable": NOT_SEPARABLE["air_index_drift station"]}])
    untested_confounds([s], [])
    assert s.confounded_with == []
    knock = drift(fx.LAW_STEP)
    untested_confounds([knock], [undetermined])
    assert knock.confounded_with == []


@pytest.mark.slow
def test_a_drift_lists_the_air_where_the_rounds_do_not_place_the_station(tmp_path):
    """gen2 seed 3537 campaign 12 (one station, the tracker columns removed, an isotropic tracker: the rounds'
    scatter has no shape to place the station; the air ramps to 5 ppm): the air cannot be offered, a drift of the
    tracker along the beams is named.  4814652 named it alone (the note of an unplaced station was not the kind
    untested_confounds reads); the drift now lists the air beside it, with what separates them."""
    path, truth = _gen2(tmp_path, 3537, 12)
    assert [e["name"] for e in truth["effects"]] == ["air_temperature"]
    rec = parse_recording(path.read_text(), path.name)
    (text,) = [t for h, t in R.cases(path.read_text()) if h == "defaults"]
    d = diagnose(parse_recording(text, path.name))
    assert _named(d) == [("thermal_drift", None)], _named(d)
    rivals = d.effects[0].to_dict().get("confounded_with") or []
    air = [c for c in rivals if c["name"] == "air_index_drift"]
    assert len(air) == 1, [c["name"] for c in rivals]
    assert "not determined" in air[0]["where"] and air[0]["separate_by"].startswith("measure from a second station")
    assert R.judge(d.to_dict(), R.planted_of(truth, rec)).verdict == "right"
