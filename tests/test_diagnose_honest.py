"""Issue 24, classes that went wrong on the independent generator, planted through the physical simulator:
a drift of the table that starts when the rotary axes start (sized from what the readings observe, with its
uncertainty over the onset and time constant), a nest knocked mid-campaign (one reflector displaced from then on,
across axis blocks), a scale growing while its axis is measured without a temperature channel (located and left
unexplained, not named a drift), and a picture per finding."""
from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import campaigns as C
import numpy as np
import pytest

from mtcal import load_machine
from mtcal.diagnose import diagnose, plot_findings

FIVE = C.Design(rounds=4)


def _significant(d):
    return [f for f in d.effects if f.significant]


@pytest.mark.parametrize("seed, told", [(0, True), (1, False)])
@pytest.mark.slow
def test_a_table_drift_starting_with_the_rotary_axes_is_sized_by_what_the_readings_see(seed, told):
    """19 um along +Y, tau 1800 s, from the first reading of B (the table is first seen then): before, reported
    as a 290 um drift from the record's start (+-11 um). Now the onset is the first table reading, the size within
    30 % of the truth and the 95 % interval over (onset, tau) holds it."""
    rec0 = C.make(FIVE, (), 0).recording
    t_b = float(rec0.time_s[rec0.axis == "B"].min())
    c = C.make(FIVE, [("thermal_drift", {"amplitude": 0.019, "tau_s": 1800.0, "direction": "+Y", "target": "table",
                                         "t0_s": t_b})], seed)
    d = diagnose(c.recording, tracker=c.tracker if told else None)
    drifts = [f for f in _significant(d) if f.name == "thermal_drift"]
    if not told and not drifts:  # the warm-up writes the temperature channel: a temperature-driven drift is right
        assert [f.name for f in _significant(d)] == ["thermal_temperature"]
        return
    (f,) = drifts
    assert f["target"] == "table" and f["t0_s"] == pytest.approx(t_b)
    assert abs(f.estimate - 0.019) < 0.3 * 0.019, f.estimate
    lo, hi = f["interval_95"]
    assert lo <= 0.019 <= hi and f["profile"]["members"] > 20


def test_onsets_never_precede_the_side_being_seen():
    """The candidate onsets of the table's drift start at its first reading (the first rotary axis here)."""
    from mtcal.diagnose.candidates import onsets

    rec = C.make(FIVE, (), 0).recording
    table = np.isin(rec.axis, ["B", "C"])
    got = onsets(rec, table)
    assert got[0] == pytest.approx(rec.time_s[rec.axis == "B"].min()) and len(got) == 2


@pytest.mark.parametrize("axis, side", [("Y", "tool"), ("C", "table")])
@pytest.mark.slow
def test_a_knocked_nest_is_one_finding(axis, side):
    """Reflector P knocked by 20 um (its side's +X) in the middle of one axis' block, displaced through the rest
    of the campaign: before, a re-seated nest in the wrong round, tracker knocks and a creep. Now one finding,
    nest_knock of P on that side, 20 um within 30 %, splitting P's readings where the knock did (to one reading),
    with the tracker told and not."""
    rec0 = C.make(FIVE, (), 0).recording
    t0 = float(np.median(rec0.time_s[rec0.axis == axis]))
    c = C.make(FIVE, [("nest_knock", {"side": side, "size": 0.02, "direction": "+X", "t0_s": t0})], 3)
    after = c.truth["effects"][0]["readings_after"]
    for tracker in (c.tracker, None):
        sig = _significant(diagnose(c.recording, tracker=tracker))
        assert [f.name for f in sig] == ["nest_knock"], [(f.name, f.get("where")) for f in sig]
        f = sig[0]
        assert (f["point"], f["side"]) == ("P", side) and abs(f["readings"] - after) <= 1  # t0 to one reading
        assert abs(f.estimate - 0.02) < 0.3 * 0.02, f.estimate


def test_the_simulated_knock_moves_one_nest_from_t0_on():
    """The planted physics: only P's readings from t0 on move, by 20 um (the spindle's frame is the machine's at
    these axes' positions for a tool-side nest, up to the machine's small errors)."""
    clean = C.make(FIVE, (), 5).recording
    side = np.array([load_machine("dmu50").side(a) for a in clean.axis])
    t0 = float(np.median(clean.time_s[(clean.point == "P") & (side == "tool")]))
    knocked = C.make(FIVE, [("nest_knock", {"side": "tool", "size": 0.02, "direction": "+Z", "t0_s": t0})], 5)
    diff = np.linalg.norm(knocked.recording.xyz - clean.xyz, axis=1)
    moved = (clean.point == "P") & (clean.time_s >= t0) & np.isin(clean.axis, ["X", "Y", "Z"])
    assert moved.sum() > 20 and np.allclose(diff[moved], 0.02, atol=2e-5)  # the noise draws differ by nm
    assert diff[~moved].max() < 1e-9
    assert knocked.truth["effects"][0]["readings_after"] == int(((clean.point == "P") & (clean.time_s >= t0)
                                                                 & (side == "tool")).sum())


@pytest.mark.slow
def test_a_scale_growing_while_measured_is_located_not_named():
    """X's scale grows with a 3 K warm-up while X is measured (100 ppm/K, no temperature channel given): before, a
    279 um spindle drift, a settling tracker, a knock. Now one unexplained mismatch located by position x time,
    mostly E_XX, and no named effect."""
    c = C.make(C.Design(rounds=5, axes=("X", "Y", "Z")),
               [("thermal_temperature", {"axis": "X", "ppm_per_k": 100.0, "drift_mm_per_k": 0.0})], 0,
               temperature="rise_c=3,tau_s=1800,t0_s=0")
    rec = replace(c.recording, temperature_c=np.full(len(c.recording), np.nan))
    d = diagnose(rec, tracker=c.tracker).to_dict()
    assert [e["name"] for e in d["effects"] if e["significant"]] == []
    (u,) = d["unexplained"]
    assert (u["axis"], u["by"], u["where"]) == ("X", "position x time", "E_XX") and 0.03 < u["size_mm"] < 0.2


@pytest.mark.parametrize("seed", range(4))
def test_a_scale_growing_over_two_rounds_is_located_or_said_to_be_confounded(seed):
    """The same physics over two rounds (30 ppm/K, 3 K): the position x time form needed three rounds, so a knock
    or a drift was named alone (gen2: a growing scale became a tracker knock in 5 runs of 284).  Now the linear
    member (a scale or slope growing steadily) is tested from two rounds: the mismatch is located on X, or the
    named effect says it cannot be told from it (confounded_with), or -- a knock and a drift of the spindle fitting
    it alike (selection._tied) -- it is located on X as one misfit that none of them is named for."""
    c = C.make(C.Design(rounds=2, axes=("X", "Y", "Z")),
               [("thermal_temperature", {"axis": "X", "ppm_per_k": 30.0, "drift_mm_per_k": 0.0})], seed,
               temperature="rise_c=3,tau_s=1800,t0_s=0")
    rec = replace(c.recording, temperature_c=np.full(len(c.recording), np.nan))
    d = diagnose(rec, tracker=c.tracker).to_dict()
    located = [(u["axis"], u["by"]) for u in d["unexplained"]]
    for e in (e for e in d["effects"] if e["significant"]):
        said = [(x["axis"], x["where"].split(",")[0]) for x in e.get("confounded_with") or []
                if x["name"] == "unexplained"]
        assert ("X", "position x time") in said, (e["name"], e["where"], said)
    assert located in ([], [("X", "position x time")], [("X", "effects fitting alike")])
    assert located or any(e["significant"] for e in d["effects"])


def test_a_picture_per_finding(tmp_path):
    """A planted backlash of X gets its picture: the partial residual split by approach direction (um, machine
    frame, along the effect), the + and - means on either side of zero and well apart."""
    c = C.make(C.Design(rounds=4, axes=("X", "Y", "Z")), [("backlash", {"axis": "X", "amount": 0.012})], 2)
    d = diagnose(c.recording, tracker=c.tracker)
    paths = plot_findings(d, tmp_path)
    assert [p.rsplit("/", 1)[-1] for p in paths] == ["finding_1_backlash_X.png"]
    assert (tmp_path / "finding_1_backlash_X.png").stat().st_size > 10000
    from mtcal.diagnose.pictures import _series
    f = _significant(d)[0]
    y, m, on = _series(d, f)
    rec = d.prep.rec
    up, down = (y[on & (rec.direction == s)].mean() for s in (1, -1))
    assert up * down < 0 and abs(up - down) > 1.0


def test_a_knock_after_the_nest_is_last_read_is_refused():
    """A planted knock that would move nothing (the tool-side nest is not read once the rotary axes start) is an
    input error, not a silent no-op."""
    from mtcal.errors import InputError

    rec = C.make(FIVE, (), 5).recording
    with pytest.raises(InputError, match="is not read after t0_s"):
        C.make(FIVE, [("nest_knock", {"side": "tool", "t0_s": float(rec.time_s.max())})], 5)


@pytest.mark.parametrize("axis, size, seed", [("C", 0.09, 2), ("C", 0.09, 3), ("Y", 0.06, 2)])
@pytest.mark.slow
def test_a_one_off_reading_is_not_mistaken_for_a_recurring_pattern(axis, size, seed):
    """A single gross reading (round 2, +X): named an outlier of its axis, with the tracker told and not. Before, the
    recurrence check scored the same places in the other rounds without the outlier fitted, where the base's share
    of it shows (tens of um against a sub-um beam), and rejected it as "a systematic pattern" (these seeds: missed;
    issue 24's rotary outlier)."""
    c = C.make(FIVE, [("outlier", {"axis": axis, "size": size, "direction": "+X", "round": 2})], seed)
    for tracker in (c.tracker, None):
        sig = _significant(diagnose(c.recording, tracker=tracker))
        assert [(f.name, f.axis) for f in sig] == [("outlier", axis)], [(f.name, f.get("where")) for f in sig]
        assert abs(sig[0].estimate - size) < 0.3 * size


# ------------------------------------------------------------------------------------------ few positions: no period
# gen2 seed 7 campaign 185's E_XX (um) at its 10 positions of X (there 29.3-471.9 mm; here the same grid in the
# spec's X range): two undulations over the travel, tabulated
E_XX_10 = [-1.321, -4.494, -4.576, 0.837, 8.335, 12.497, 12.066, 10.420, 10.005, 8.566]
X_10 = [round(29.3 + k * 49.1778 - 250.0, 3) for k in range(10)]


@pytest.mark.slow
def test_a_tabulated_error_function_on_ten_positions_is_no_periodic_error():
    """On 10 positions the error function of degree 7 leaves 2 shapes free, exactly as many as a periodic error
    has columns: whatever the polynomial leaves of a tabulated E_XX is "periodic" at some pitch (gen2: a long
    wave named periodic, 3 of 420 runs wrong at the defaults).  The periodic family is now tested only where the
    positions leave PERIODIC_SPARE shapes (its two, its pitch and two to check it against), and it must leave no misfit
    over the positions beside it; here it is stated out of reach instead, naming the positions."""
    import json

    from mtcal.campaign.simulate import simulate_campaign
    from mtcal.data import path
    from mtcal.model.errormodel import model_from_dict

    truth = json.loads(Path(path("demo_truth.json")).read_text())
    truth["functions"]["E_XX"] = {"axis": "X", "positions": X_10, "values": [v * 1e-3 for v in E_XX_10]}
    rec = simulate_campaign(model_from_dict(truth), seed=2, rounds=None,
                            plan={"axes": {"X": {"positions": X_10}}, "rounds": 8})
    d = diagnose(rec)
    named = [(e.name, e.axis) for e in d.effects if e.significant]
    assert ("periodic", "X") not in named, named
    notes = [e.get("not_separable") for e in d.effects if (e.name, e.axis) == ("periodic", "X")]
    assert any("10 positions" in (n or "") for n in notes), notes


@pytest.mark.slow
def test_a_smooth_error_function_on_twelve_positions_is_no_periodic_error():
    """gen2 (benchmarks/gen2) seed 19, campaign 88: a clean campaign, Y measured at 12 positions, a 1 : 70 tracker
    (0.16 um + 0.04 um/m along the beam).  Y's error functions hold four half-waves over the travel; what degree 7
    leaves of them (about 0.5 um) was named a periodic error of pitch 108 mm (p_adj 0.002).  With the pitch and two
    shapes to check it against counted (PERIODIC_SPARE 5), 12 positions leave too few: nothing is named."""
    import sys
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    import diagnose_gen2_rates as R

    (run,) = [r for r in R.run(n=1, seed=19, start=88, progress=False) if r["how"] == "defaults"]
    assert run["classes"] == ["clean"] and run["verdict"] == "right", run["wrong"]


@pytest.mark.slow
def test_a_shape_the_tabulated_error_functions_explain_is_not_unexplained(tmp_path):
    """gen2 seed 19, campaign 183: a clean campaign, Y at 10 positions, a 1 : 70 tracker (0.15 um along the beam
    at 2 m).  What degree 7 leaves of Y's smooth error function (0.7-2.5 um at 150.4, 288.6 ... mm, the same in
    every round) was reported unexplained.  Every error motion of Y free at every measured position explains it: a
    quasi-static shape beyond the family's degree, now reported with the base (base_model.shape_beyond_family),
    nothing unexplained, nothing named."""
    import sys
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    import diagnose_gen2_rates as R

    (path,) = R.generate(str(tmp_path), 1, 19, 183)
    for how, text in R.cases(path.read_text()):
        a = R.answer_of(text, path.name)
        assert not a["unexplained"] and not [e for e in a["effects"] if e["significant"]], how
        shapes = a["base_model"]["shape_beyond_family"]
        assert {u["axis"] for u in shapes} == {"Y"} and any(u["by"] == "position" for u in shapes), shapes
        assert max(u["shift_mm"] for u in shapes if u["shift_mm"]) < 0.01
