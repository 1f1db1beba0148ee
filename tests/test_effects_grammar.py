"""Issue 34 item 1: the grammar of effects (derive/grammar.py).  Every effect of the simulator and of the diagnosis is
a named member (where x what moves x how it depends); the new members -- a side's reflectors moving apart in time
(side_expansion), a reversal growing along the travel (backlash_travel), the tracker re-levelled between rounds
(tracker_relevel) -- are planted by the simulator through the exact kinematics and their signatures (generated from
the same expressions) are simulate(effect) - simulate(none) to first order on every shipped spec; planted in
mtcal's own campaigns they are named, sized with an interval that covers the truth, said in words, and nothing else
is named beside them.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import mtcal
from derive import grammar
from mtcal.campaign.plans import Plan
from mtcal.campaign.simulate import simulate
from mtcal.cli import main
from mtcal.diagnose import diagnose
from mtcal.diagnose import effects as fx
from mtcal.diagnose.candidates import layout_offsets, round_starts
from mtcal.diagnose.prepare import prepare
from mtcal.kinematics.defaults import default_positions

SPECS = sorted(p.stem for p in (Path(__file__).resolve().parent.parent / "derive" / "machines").glob("*.toml"))
NEW = ("side_expansion", "backlash_travel", "tracker_relevel")


def test_every_effect_is_a_named_member_of_the_grammar():
    assert set(grammar.MEMBERS) == set(fx.VOCABULARY), set(grammar.MEMBERS) ^ set(fx.VOCABULARY)
    for name, m in grammar.MEMBERS.items():
        assert m.where and m.what and m.how and m.params, name
    assert set(NEW) <= set(fx.VOCABULARY)


def _plan(m: mtcal.Machine) -> Plan:
    pos = {a: p[::3] if p[::3][-1] == p[-1] else np.append(p[::3], p[-1]) for a, p in default_positions(m).items()}
    return Plan(m, rounds=2, positions=pos)


def _cases(m: mtcal.Machine, prep, pl: Plan):
    """(effect, params, theta, signature builder -> G (n, 3, k), linear in the parameter through a translation)."""
    g = prep.geometry
    off = layout_offsets(prep)
    for side in ("tool", "table"):
        t0 = float(np.min(g.time_s[g.side == side]))
        yield ("side_expansion", {"side": side, "ppm_per_h": 1000.0, "t0_s": t0}, [1000.0],
               lambda side=side, t0=t0: fx.side_expansion(g, off, side, t0).G, True)
        yield ("side_expansion", {"side": side, "law": "lag", "ppm": 800.0, "tau_s": 900.0, "t0_s": t0}, [800.0],
               lambda side=side, t0=t0: fx.side_expansion(g, off, side, t0, 900.0).G, True)
    for a in m.axes:
        lin = m.kind(a) == "linear"
        b, s = (0.02, 1e-4) if lin else (1e-4, 2e-6)   # mm, mm/mm or rad, rad/deg: second order shows
        yield ("backlash_travel", {"axis": a, "amount": b, "slope": s}, [b, s],
               lambda a=a: fx.backlash_travel(g, a).G, lin)
    (rank0, where), *_ = round_starts(prep, np.ones(len(g.axis), bool))[len(m.axes) // 2:]
    assert where["round"] == 2  # two rounds: every member is an axis' second round
    t0 = float(prep.rec.time_s[prep.order == rank0][0])
    u = np.array([0.6, 0.8])
    yield ("tracker_relevel", {"axis": where["axis"], "round": where["round"], "angle_rad": 1e-3,
                               "about": "0.6;0.8;0"}, 1e-3 * u,
           lambda: fx.tracker_relevel(g, prep.order >= rank0, t0, where).G, False)


@pytest.mark.parametrize("name", SPECS)
def test_new_members_are_signature_times_parameter_to_first_order(name):
    m = mtcal.load_machine(name)
    pl = _plan(m)
    clean, _ = simulate(None, plan=pl, noise=False)
    prep = prepare(clean, m, tracker=pl.tracker)
    seen = set()
    for effect, params, theta, sig, linear in _cases(m, prep, pl):
        first = np.einsum("nik,k->ni", sig(), np.asarray(theta, dtype=float))
        rem = []
        for s in (1.0, 0.5):
            p = {k: (v * s if k in ("amount", "slope", "ppm", "ppm_per_h", "angle_rad") else v)
                 for k, v in params.items()}
            rec, _ = simulate(None, plan=pl, noise=False, effects=[(effect, p)])
            rem.append(np.abs(rec.xyz - clean.xyz - s * first).max())
        size = np.abs(first).max()
        assert size > 1e-2, (name, effect, params)  # the effect moves the reflectors (mm)
        assert rem[0] < 2e-3 * size, (name, effect, params, rem[0], size)  # first order
        if linear:  # an expansion of the layout, a linear axis' positioning: exact (rounding only)
            assert rem[0] < 1e-10, (name, effect, params, rem)
        else:       # a rotation (the tracker's, a rotary axis' positioning): a genuine second-order remainder
            assert 3.6 < rem[0] / rem[1] < 4.4, (name, effect, params, rem)
        seen.add(effect)
    assert seen == set(NEW)


def test_side_expansion_moves_a_sides_reflectors_apart_about_their_centroid():
    """10 ppm per hour of the table side: every table reflector's distance to the layout's centroid grows by
    1e-5 (t / 1 h) of it (the DMU 50 table reflectors P, Q, K: centroid (0, 0, 80) mm, written here); the spindle
    side does not move."""
    rec0, _ = simulate(None, noise=False)
    rec, truth = simulate(None, noise=False, effects=["side_expansion:side=table,ppm_per_h=10"])
    m = mtcal.load_machine("dmu50")
    table = np.isin(rec.axis, [a for a in m.axes if m.side(a) == "table"])
    local = {"P": (150.0, 0.0, 40.0), "Q": (-75.0, 130.0, 80.0), "K": (-75.0, -130.0, 120.0)}
    off = np.array([np.subtract(local[p], (0.0, 0.0, 80.0)) for p in rec.point[table]])
    growth = 1e-5 * rec.time_s[table] / 3600.0
    d = rec.xyz[table] - rec0.xyz[table]
    np.testing.assert_allclose(np.linalg.norm(d, axis=1), growth * np.linalg.norm(off, axis=1), rtol=1e-9)
    np.testing.assert_allclose(rec.xyz[~table], rec0.xyz[~table], atol=1e-12)
    assert truth["effects"][0]["centroid_local_mm"] == [0.0, 0.0, 80.0]


def test_backlash_travel_is_the_iso_230_2_reversal_at_each_position():
    """amount 2 um at 0 mm, slope 1.2e-5: X's readings differ between approaches by 2 + 0.012 q um (q mm) along
    x: 2 um at 0 to 8 um at 500 mm."""
    rec0, _ = simulate(None, noise=False)
    rec, truth = simulate(None, noise=False, effects=["backlash_travel:axis=X,amount=0.002,slope=1.2e-5"])
    x = rec.axis == "X"
    d = (rec.xyz - rec0.xyz)[x]
    np.testing.assert_allclose(d[:, 0], rec.direction[x] * (0.002 + 1.2e-5 * rec.position[x]) / 2, atol=1e-13)
    assert truth["effects"][0]["reversal_at_ends"] == pytest.approx([0.002, 0.008])


@pytest.mark.parametrize("args, message", [
    (["--effect", "tracker_relevel:about=Z"], "about must be horizontal"),
    (["--effect", "tracker_relevel:round=9"], "axis X has no round 9"),
    (["--effect", "side_expansion:side=head"], "must be one of tool, table"),
    (["--effect", "side_expansion:ppm_per_h=5000"], "must lie in [-1000, 1000]"),
    (["--effect", "backlash_travel:slope=nan"], "not a number"),
])
def test_cli_new_members_bad_input(tmp_path, capsys, args, message):
    assert main(["simulate", "-o", str(tmp_path / "r.csv"), *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mtcal simulate: error:") and message in err, err
    assert not (tmp_path / "r.csv").exists()


# ----------------------------------------------------------------------------- planted and diagnosed
def _rounds_plan(axes: str = "XYC") -> dict:
    return {"axes": {a: {"positions": Plan().positions[a].tolist()} for a in axes}, "rounds": 3}


def _diagnosed(effect: str, seed: int, axes: str = "XYC", extra: tuple = ()):
    rec, truth = mtcal.simulate(seed=seed, plan=_rounds_plan(axes), effects=[effect, *extra])
    d = diagnose(rec, tracker=Plan().tracker)
    found = [f for f in d.effects if f.significant]
    assert len(found) == 1 and not d.unexplained, ([(f.name, f.axis, f.get("where")) for f in found],
                                                   d.unexplained)
    return found[0], truth["effects"][0]


@pytest.mark.slow
def test_a_warming_table_is_named_in_words():
    f, truth = _diagnosed("side_expansion:side=table,ppm_per_h=30", 11)
    assert (f.name, f["side"], f["unit"]) == ("side_expansion", "table", "ppm/h")
    assert f["law"] in ("ramp", "ramp over the record")  # a lag longer than the record is a ramp there
    lo, hi = f["interval_95"]
    assert lo < 30.0 < hi and hi - lo < 15.0, f["interval_95"]
    assert f["says"].startswith("the table-side reflectors move apart") and "ppm per hour" in f["says"]
    assert f["says"].endswith("a warming table") and f["predictive_check"]["passes"]
    assert f.evidence["cv_gain"] > 0


@pytest.mark.slow
def test_a_backlash_growing_along_the_travel_is_named_with_both_ends():
    f, truth = _diagnosed("backlash_travel:axis=X,amount=0.002,slope=1.2e-5", 12)
    assert (f.name, f.axis, f["unit"]) == ("backlash_travel", "X", "mm")
    for end, want in zip(f["reversal_at_ends"], truth["reversal_at_ends"]):
        lo, hi = end["interval_95"]
        assert lo < want < hi and hi - lo < 0.004, (end, want)
    assert [e["position"] for e in f["reversal_at_ends"]] == [0.0, 500.0]
    assert f["says"].startswith("the lost motion of X grows along the travel:") and "at 500 mm" in f["says"]
    assert f.evidence["cv_gain"] > 0 and f["predictive_check"]["passes"]


@pytest.mark.slow
def test_a_tracker_re_levelled_between_rounds_is_one_finding():
    f, truth = _diagnosed("tracker_relevel:axis=Y,round=2,angle_rad=30e-6,about=+X", 13)
    assert f.name == "tracker_relevel" and f["t0_s"] == truth["t0_s"] and f["round"] == 2
    lo, hi = f["interval_95"]
    assert lo < 30e-6 < hi, f["interval_95"]
    assert abs(f["rotation_vector"][0]) > 3 * math.hypot(0, f["uncertainty"])  # about x, well determined
    assert f["says"].startswith("the tracker was re-levelled before round 2 of Y")
    assert f.evidence["cv_gain"] > 0 and f["predictive_check"]["passes"]


@pytest.mark.slow
def test_a_tracker_re_levelled_and_shifted_is_one_finding():
    """The head moved 30 um along +Z as the tracker was re-levelled (30 urad about +X) before Y's second round: one
    re-levelling with its shift (gen2's tracker_relevel plants both); 4814652 offered the turn alone, which cannot
    take the shift: it named a knock of the tracker at the same t0 and left the turn a located misfit of Y
    (position x time)."""
    relevel = "tracker_relevel:axis=Y,round=2,angle_rad=30e-6,about=+X"
    t0 = mtcal.simulate(seed=13, plan=_rounds_plan(), effects=[relevel])[1]["effects"][0]["t0_s"]
    f, truth = _diagnosed(relevel, 13, extra=[f"offset:size=0.03,direction=+Z,t_from_s={t0 - 1e-3}"])
    assert f.name == "tracker_relevel" and f["t0_s"] == truth["t0_s"] == t0
    lo, hi = f["interval_95"]
    assert lo < 30e-6 < hi, f["interval_95"]
    shift, u = np.array(f["shift_mm"]), np.array(f["shift_uncertainty_mm"])
    assert np.all(np.abs(shift - [0.0, 0.0, 0.03]) < 4 * u + 1e-9), (shift, u)
    assert "and shifted" in f["says"] and f["predictive_check"]["passes"]


def test_cli_round_trip_of_the_new_members(tmp_path, capsys):
    out = tmp_path / "rec.csv"
    assert main(["simulate", "-o", str(out), "--rounds", "2", "--no-noise", "--json",
                 "--effect", "side_expansion:side=tool,law=lag,ppm=30,tau_s=1200",
                 "--effect", "backlash_travel:axis=Y,amount=-0.003",
                 "--effect", "tracker_relevel:axis=Z,round=2,about=0;1;0"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert [e["name"] for e in summary["effects"]] == list(NEW)
    truth = json.loads((tmp_path / "rec.truth.json").read_text())
    assert truth["effects"][2]["about"] == [0.0, 1.0, 0.0] and truth["effects"][2]["t0_s"] > 0


# ----------------------------------------------------------------------------- one axis repeating worse
def _scatter(rec, told: bool):
    d = diagnose(rec, tracker=Plan().tracker if told else None)
    return d, d.to_dict()["noise_model"]["axis_scatter"]


@pytest.mark.parametrize("told", [True, False], ids=["tracker told", "tracker not told"])
@pytest.mark.slow
def test_one_axis_repeating_worse_is_found_and_its_readings_reweighted(told):
    """3 um of extra positioning scatter on Y (the default five-axis campaign, 3 rounds): found on Y by the F test
    of the round-to-round scatter along each axis' motion, sized with an interval covering 3 um, said in words --
    and nothing named: without the re-weighting the same campaign gave 3-7 outliers of Y and ~140 located
    'unexplained' entries (seeds 1-3, measured on this branch with the re-weighting switched off)."""
    rec, _ = mtcal.simulate(seed=2, rounds=3, effects=["axis_scatter:axis=Y,sd=0.003,seed=2"])
    d, sc = _scatter(rec, told)
    f = sc["found"]
    assert f["axis"] == "Y" and f["interval_95_mm"][0] < 0.003 < f["interval_95_mm"][1], f
    assert f["says"].startswith("Y repeats worse than X, Z, B and C: ") and "extra scatter along Y" in f["says"]
    assert f["p_adjusted"] < 1e-6 and f["readings_reweighted"] == int(np.sum(rec.axis == "Y"))
    assert not [e.name for e in d.effects if e.significant] and not d.unexplained
    assert "re-weighted" in d.noise.how


def test_the_scatter_test_does_not_fire_on_systematic_effects():
    """The test reads the round-to-round scatter less the cell and round means: a large backlash, a knocked tracker
    and a drift (every one systematic) leave it at the law's scatter; the statistic is an F of the axes' scatter
    along their motion, each axis tested against the others (p > the level on all)."""
    from mtcal.diagnose.scatter import axis_scatter
    m = mtcal.load_machine("dmu50")
    plan = {"axes": {a: {"positions": Plan().positions[a].tolist()} for a in "XYC"}, "rounds": 3}
    rec, _ = mtcal.simulate(seed=5, plan=plan, effects=["backlash:axis=Y,amount=0.02", "offset:size=0.05",
                                                        "thermal_drift:amplitude=0.03,direction=+Y"])
    prep = prepare(rec, m, tracker=Plan().tracker)
    sc = axis_scatter(prep).details["axis_scatter"]
    assert sc["found"] is None and {t["axis"] for t in sc["tested"]} == {"X", "Y", "C"}
    assert all(t["p_adjusted"] > 0.005 for t in sc["tested"]), sc["tested"]


def test_the_scatter_test_is_not_run_through_a_law_the_rounds_rejected():
    """With the tracker given and its law replaced by the one the rounds show (or isotropic), the comparison of the
    axes goes through that law's shape: gen2 seed 3501 (a 1 : 70 and an isotropic tracker, several stations) had
    X and C 'repeating worse' on 3 of 25 runs where nothing did.  Then the test is not run, and says why; the
    same campaign under the prior's law is tested."""
    from dataclasses import replace as with_

    from mtcal.diagnose.scatter import NOT_TESTED, axis_scatter
    rec, _ = mtcal.simulate(seed=2, rounds=3, effects=["axis_scatter:axis=Y,sd=0.003,seed=2"])
    prep = prepare(rec, mtcal.load_machine("dmu50"), tracker=Plan().tracker)
    assert prep.noise.details["axis_scatter"]["found"]["axis"] == "Y"  # prepare ran it under the prior's law
    for kind in ("tracker law estimated (given tracker)", "tracker law estimated (given trackers, per station)",
                 "isotropic"):
        prep.noise = with_(prep.noise, kind=kind)
        sc = axis_scatter(prep).details["axis_scatter"]
        assert sc["found"] is None and sc["not_tested"] == NOT_TESTED and sc["tested"] == []
