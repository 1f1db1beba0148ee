"""The tracker's noise law from what is rigid (mtcal.measurement.tracker_position.rigid_law, issue 34): within one
pass the reflectors of a side are rigid, so their mutual distances scatter by the tracker's noise alone -- blind to
a drift shared by the side and to the machine's (here the replica's robot's) motion, which the scatter of the
rounds counts as noise.  The replica is tests/test_real_icelinker.py's: icelinker's three base reflectors, tracker
at the origin, law TrackerSpec(0.5, 0.3, 2.0, 1.5) (sigma 0.68 um along, 3.1 um across at 2.84 m), a 40 um drift
and an 8 um / 4 urad pose-to-pose motion shared by the three."""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from mtcal.measurement import tracker as trk
from mtcal.measurement.screen import screen
from mtcal.measurement.tracker import AT960, TrackerSpec
from mtcal.measurement.tracker_position import (
    ACROSS,
    NU,
    T_CONSISTENCY,
    _profile_end,
    estimate_shape,
    refine,
    rigid_law,
    rigid_station,
    station_interval,
)

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import real_icelinker as ri  # noqa: E402
from test_real_icelinker import REF, SPEC, _planted, _readings  # noqa: E402
from test_real_icelinker import _replica as _replica_readings  # noqa: E402


def _replica(n=400, seed=3):
    rec = ri.to_recording(_readings(n, np.random.default_rng(seed))[0])
    return rec.select(screen(rec).keep)


def test_the_law_from_the_mutual_distances_is_the_planted_one_whatever_moves_the_side():
    rec = _replica()
    s_r, s_t = (1e3 * s for s in SPEC.sigmas(2837.0))
    law = rigid_law(rec, np.zeros(3), AT960)
    assert law["transverse"]["determined"] and law["radial"]["determined"], law
    assert law["transverse"]["sigma_um"] == pytest.approx(s_t, rel=0.15), (law, s_t)
    # the rounds count the 8 um shared motion as noise: the used law is the distances', and that is said
    sh = estimate_shape(rec, np.zeros(3), AT960)
    assert sh.rigid["used"] == "mutual distances" and f"the law from {sh.source} is used" in sh.note
    used_r, used_t = (1e3 * s for s in sh.spec.sigmas(2837.0))
    assert used_t == pytest.approx(s_t, rel=0.15) and used_r < 2 * s_r, (used_r, used_t, s_r, s_t)


@pytest.mark.slow
def test_the_laws_intervals_hold_the_planted_law_in_as_many_draws_as_they_say():
    """The replica (8 um and 4 urad of shared motion a pose, a drift, an outlier, stray readings) in 30 draws: both
    scales determined in every draw, and each 95 % interval (the hull of the two detrends') holds the planted sigma
    in at least 26 (four misses or more has probability 0.06 at a true 95 %, five or more 0.016).  Seed 3's radial
    interval, 0.677-0.890 um, misses the planted 0.6755 um by 0.3 % (seed 31 too, by 0.1 %): two of 44 draws,
    95.5 %.  Pair by pair (each distance alone, less a line) the radial scale was not determined (an upper bound
    only)."""
    holds = {"radial": 0, "transverse": 0}
    for seed in range(30):
        law = rigid_law(_replica(seed=seed), np.zeros(3), AT960)
        at = law["at_distance_m"] * 1e3  # mm: the planted sigma and the interval at the law's median distance
        for k, name in enumerate(holds):
            assert law[name]["determined"], (seed, name, law[name])
            lo, hi = (v * AT960.sigmas(at)[k] * 1e3 for v in law[name]["interval_95"])
            holds[name] += bool(lo <= SPEC.sigmas(at)[k] * 1e3 <= hi)
    assert min(holds.values()) >= 26, holds


def test_where_the_rounds_and_the_distances_agree_the_rounds_law_is_kept_and_nothing_is_said():
    """No shared motion, no drift: both see the tracker's noise; nothing is said (cross_check), the round scatter's
    radial scale stays and the scale across the beams is the distances' (they determine it)."""
    rng = np.random.default_rng(5)
    x = np.repeat(REF[None], 300, axis=0)
    x = x + trk.sample(x, np.zeros(3), rng, SPEC)
    sh = estimate_shape(ri.to_recording(x), np.zeros(3), AT960)
    assert sh.rigid["used"] == ACROSS and sh.note is None and "cross_check" in sh.rigid
    c_t = sh.rigid["transverse"]["factor"]
    assert sh.spec.sigmas(2837.0)[1] == pytest.approx(c_t * AT960.sigmas(2837.0)[1], rel=1e-9)
    assert sh.spec.sigmas(2837.0)[0] == pytest.approx(sh.rigid["round_scatter_factors"]["radial"]
                                                      * AT960.sigmas(2837.0)[0], rel=1e-3)


def test_the_t_fit_is_made_a_normal_sigma():
    """A Student-t (4 dof) fit of normal readings has a scale 0.83 of their sigma (the demo campaign's transverse
    factor read 0.81 against the AT960 it was drawn with before this)."""
    z = np.random.default_rng(0).normal(size=200_000)
    _, _, scale = stats.t.fit(z, fdf=NU, floc=0.0)
    assert scale == pytest.approx(T_CONSISTENCY, rel=0.01)


def _beam_scatter(t, spec, n=40, seed=1):
    """Readings of a 3 x 3 grid of reflectors 1 m across, each read n times with ``spec``'s noise about ``t``."""
    g = np.array([[x, 0.0, z] for x in (-500.0, 0.0, 500.0) for z in (-500.0, 0.0, 500.0)])
    xyz = np.repeat(g, n, axis=0)
    return xyz, trk.sample(xyz, np.asarray(t, float), np.random.default_rng(seed), spec)


def test_a_station_the_scatter_fixes_has_an_interval_that_covers_it():
    t = np.array([0.0, -3000.0, 0.0])
    xyz, r = _beam_scatter(t, AT960)
    pos, logs, f = refine(xyz, r, t + [200.0, 300.0, 0.0])
    out = station_interval(xyz, r, pos, logs, f)
    lo, hi = out["interval_95_mm"]
    assert out["determined"] and lo <= 3000.0 <= hi and hi / lo < 3, out


def test_a_beamless_scatter_leaves_the_station_not_determined():
    """An isotropic instrument read twice per reflector holds no beam: only the transverse level's prior tells a
    distance, and the profile spans 0.95-5.3 m -- "not determined", with the interval, never a curvature sigma of a
    station the data do not fix (the estimate itself: 2.3 m)."""
    t = np.array([0.0, -3000.0, 0.0])
    xyz, r = _beam_scatter(t, TrackerSpec(15.0, 6.0, 15.0, 6.0), n=2)
    pos, logs, f = refine(xyz, r, t)
    out = station_interval(xyz, r, pos, logs, f)
    lo, hi = out["interval_95_mm"]
    assert not out["determined"] and lo <= 3000.0 <= hi and "not determined" in out["note"], out


def test_a_station_placed_by_rounds_that_hold_a_shared_motion_is_not_determined():
    """icelinker without --tracker: the rounds (their 56 um shared drift and the robot's motion) placed the
    station 1.08 m from the readings, "determined" 0.95-1.27 m, where the mutual distances put it 2.8 m away.
    Where the rounds and the distances disagree about the law, the interval is not trusted, and that is said."""
    from mtcal.diagnose.noise import _trusted
    sh = estimate_shape(_replica(), np.zeros(3), AT960)
    assert sh.note  # the replica's shared motion: the two disagree
    interval = {"distance_mm": 1080.6, "interval_95_mm": [948.7, 1265.1], "determined": True}
    out = _trusted(interval, sh)
    assert not out["determined"] and "not determined" in out["note"] and "mutual distances" in out["note"]
    agree = estimate_shape(ri.to_recording(np.repeat(REF[None], 300, axis=0) + trk.sample(
        np.repeat(REF[None], 300, axis=0), np.zeros(3), np.random.default_rng(5), SPEC)), np.zeros(3), AT960)
    assert _trusted(interval, agree) is interval


def test_a_station_about_which_the_distances_show_no_tracker_noise_is_not_determined():
    """icelinker without --tracker (benchmarks/real_icelinker.py's data): the rounds put the station at (2418, 611,
    -1586) mm, 1.08 m from the readings, "determined" 0.95-1.27 m; about it the mutual distances' transverse factor
    was 3e-8, not determined (about the tracker's origin: 0.18, 0.17-0.18), and the rounds' radial factor 7.5 was
    within 2x of the distances' 15, so the disagreement rule said nothing and the station stood.  The replica
    about the same point: the mutual distances, all of a pass's jointly with the station free (rigid_station),
    put it where the tracker stood (2.84 m from the readings), not where the rounds did.  Profiled about the
    rounds' station, its direction held near theirs (86 deg from the tracker's as seen from the readings), the
    distance read 4.0-30 m (seed 0: 5.3-30 m); about the distances' own best (_rigid_best) it holds 2.84 m."""
    for seed in (3, 0):
        st = rigid_station(_replica(seed=seed), np.array([2418.5, 611.2, -1586.2]), AT960)
        lo, hi = st["interval_95_mm"]
        assert 1080.6 < lo < 2837.0 < hi, (seed, st["interval_95_mm"])


def test_a_station_beyond_the_search_bound_is_not_determined():
    """A tracker 28 m away: the beams are nearly parallel and the profile stays within the 95 % level up to the
    search's bound (MAX_DISTANCE, 30 m, where the likelihood is made infinite). The interval ends at the bound, not
    where the data end it: "not determined". On main the set 16.9-30 m spans less than 2x and was called
    determined (and, its profile read by a chain from 0.3 m, 1641 above the best at 22.5 m, where it is 0.65)."""
    t = np.array([0.0, -28000.0, 0.0])
    xyz, r = _beam_scatter(t, AT960)
    pos, logs, f = refine(xyz, r, t)
    out = station_interval(xyz, r, pos, logs, f)
    lo, hi = out["interval_95_mm"]
    profile = dict(map(tuple, out["profile"]))
    assert not out["determined"] and hi == 30000.0 and lo <= 22500.0, out
    assert profile[22496.8] < 3.84, profile  # the profile read from the estimate outwards


def test_the_profile_near_a_determined_station_is_read_from_the_estimate():
    """3 m: the profile 0.06 m from the estimate is a few units. A chain of BFGS fits from the grid's near end (0.3 m)
    read ~1820 there (stuck in another basin of the tilts and scales): the chain starts at the estimate."""
    t = np.array([0.0, -3000.0, 0.0])
    xyz, r = _beam_scatter(t, AT960)
    pos, logs, f = refine(xyz, r, t)
    out = station_interval(xyz, r, pos, logs, f)
    profile = dict(map(tuple, out["profile"]))
    assert out["determined"] and profile[3000.0] < 10.0 and 100.0 < profile[4000.6] < 1000.0, profile


def test_the_scale_across_the_beams_is_the_distances_where_they_determine_it(tmp_path):
    """gen2 seed 3546 campaign 28 (outside mix, tracker given; gen2's at960-like law, 13.2 um across the beams at
    3.88 m, 1.0 um along): the tracker re-levelled before C's round 4 spreads the rounds' scatter across the beams
    (0.97 times the AT960's transverse sigma), not the mutual distances (0.687, 95 % 0.669-0.706: 13.15 um).
    On 9f55f98 the rounds' factors were used since the two agreed within 2x; their ratio (1.34 times the AT960's)
    passed for the AT960's shape, the readings were weighted 2.5x too wide across the beams against along them,
    and a free-form reversal of Z was located where nothing was planted (F = 3.6, p_adj 1.2e-4).  The distances
    determine the transverse scale best (43 gen2 campaigns of seed 3601: all within 25 % of gen2's law, the
    rounds' 93 %): it is theirs wherever determined, the radial the rounds'.  Now the data's shape weights the
    readings, and the re-levelling is the one finding."""
    import diagnose_gen2_rates as R

    from mtcal.diagnose import diagnose
    from mtcal.measurement.recordings import parse_recording

    R.generate(str(tmp_path), 1, 3546, 28, "outside")
    path = tmp_path / "campaign_0028.csv"
    truth = __import__("json").loads(path.with_suffix(".truth.json").read_text())
    rec = parse_recording(path.read_text(), path.name)
    sh = estimate_shape(rec, rec.tracker_xyz[0], AT960)
    n = truth["tracker"]["noise"]
    L = sh.rigid["at_distance_m"]
    s_t = n["a_t_um"] + n["b_t_um_per_m"] * L
    used_t = 1e3 * sh.spec.sigmas(L * 1e3)[1]
    assert used_t == pytest.approx(s_t, rel=0.1), (used_t, s_t)
    assert sh.replaces_base, sh.to_dict()
    d = diagnose(rec).to_dict()
    assert d["unexplained"] == [], d["unexplained"]
    assert [e["name"] for e in d["effects"] if e["significant"]] == ["tracker_relevel"], d["effects"]


@pytest.mark.slow  # two whole diagnoses: 10-20 s
def test_a_re_levelling_does_not_leave_a_bump_where_the_law_is_the_datas(tmp_path):
    """gen2 seed 3546 campaign 9 (one station, gen2's at960-like law 0.66 of the AT960's across the beams at 1.86 m,
    1.06 along; the tracker re-levelled before Y's round 4): the rounds read 0.83 across (the re-levelling spreads
    them), the distances 0.66.  On 9f55f98 the rounds' ratio (1.31) kept the AT960's shape, and beside the
    re-levelling "outlier C bump: round 2 point P7 at 108 (-1), 7 reading(s)" was named (F = 15.3) in both runs,
    seven readings 2-3 sigma off along the beam.  With the distances' scale across the beams the data's shape (1.6-1.7
    times the AT960's) weights the readings, with the station estimated and given alike: the re-levelling alone."""
    import diagnose_gen2_rates as R

    from mtcal.diagnose import diagnose
    from mtcal.measurement.recordings import parse_recording

    R.generate(str(tmp_path), 1, 3546, 9, "outside")
    path = tmp_path / "campaign_0009.csv"
    for how, text in R.cases(path.read_text()):
        d = diagnose(parse_recording(text, path.name)).to_dict()
        assert [e["name"] for e in d["effects"] if e["significant"]] == ["tracker_relevel"], (how, d["effects"])
        assert d["noise_model"]["law"]["source"] == "data", (how, d["noise_model"]["law"])


def test_the_station_scatter_is_blind_to_a_motion_of_a_whole_round():
    """station_scatter (what places an unknown station, in identify and the diagnosis): the rounds' scatter less
    each round's mean.  A translation of any whole round (a knock or a re-levelling between rounds, a drift, the
    replica's robot moving the base) leaves it unchanged (to a picometre: rounding of readings 2.8 m away); the
    rounds' scatter takes it in."""
    from mtcal.measurement.tracker_position import round_scatter, station_scatter
    rec = _replica(300)
    moved = rec.select(np.ones(len(rec), bool))
    rng = np.random.default_rng(8)
    for rnd in np.unique(rec.round):
        moved.xyz[rec.round == rnd] += rng.normal(0.0, 0.02, 3)  # 20 um, every reading of the round alike
    assert np.abs(station_scatter(moved) - station_scatter(rec)).max() < 1e-9  # 1 pm: rounding of 2.8 m
    assert np.abs(round_scatter(moved) - round_scatter(rec)).max() > 0.01


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(3, 13))
def test_without_the_tracker_the_weights_hold_the_mutual_distances_and_only_the_planted_is_named(seed):
    """Issue 34 ("the law within 2x of what the mutual distances show"; "the findings the same with and without
    --tracker"), on the replica without the tracker's position: the weights of the diagnosis predict each mutual
    distance's scatter (benchmarks/real_icelinker.py predicted_pair_sd: the covariances the weights stand for,
    projected on the pair) within 2x of the scatter it shows (its robust sd about a running median).  The station
    was placed from the rounds' scatter, which holds the replica's 8 um pose-to-pose motion: seed 3 then predicted
    8.2, 1.8 and 3.2 times the distances' scatter (icelinker itself: 22, 7.9 and 7.8; now 1.7, 1.4 and 1.4).
    With the tracker given at the origin and without it, what is named is what was planted: the drift, and the
    displaced reading (file line 150) where it is seen; tracker knocks at F = 11-16 (seeds 7, 9, 12: steps of
    the poses' shared motion, significant against the readings' noise, not against the poses' own motion) are
    not (selection._stops_move_together)."""
    from mtcal.diagnose import diagnose
    x, planted_round = _replica_readings(seed)
    law = ri.pair_law(x, np.ones(len(x), bool), 51, np.zeros(3))
    measured = np.array([v["sd_um"] for v in law["pairs"].values()])
    without = diagnose(ri.to_recording(x))
    ratio = ri.predicted_pair_sd(without.noise.W, np.median(x, axis=0)) / measured
    assert np.all((ratio > 0.5) & (ratio < 2.0)), ratio
    given = diagnose(ri.to_recording(x), tracker=np.zeros(3))
    for d in (without, given):
        named = [ri.same_as(f) for f in d.effects if f.significant]
        assert "name=thermal_drift variant=ramp over the record" in named, named
        assert set(named) <= _planted(planted_round), named


def _simulated(seed: int):
    """The demo plan on the DMU 50, four rounds, the AT960's law about a known tracker (tests/test_noise_shape.py's
    station): the truth of both scales is 1."""
    from dataclasses import replace

    from mtcal.campaign.plans import as_plan
    from mtcal.campaign.simulate import simulate
    from mtcal.data import path
    from mtcal.data.make_demo_data import DEMO_PLAN
    from mtcal.kinematics.machine import load_machine
    from mtcal.model.errormodel import load_model

    m = load_machine("dmu50")
    plan = replace(as_plan(DEMO_PLAN, m), tracker=SIM_T, rounds=4)
    return simulate(load_model(path("demo_truth.json")), machine=m, plan=plan, seed=seed)[0]


SIM_T = (250.0, -1500.0, 150.0)


def test_the_joint_law_of_the_distances_holds_the_simulators_law():
    """A clean simulated campaign (AT960 noise only): the law from the mutual distances, all of a pass's jointly
    under the restricted likelihood, determines both scales here and holds the truth (1, 1) in their intervals,
    under either detrend.  Pair by pair the radial scale was not determined (1.01, interval 0-3.2: an upper bound
    only; seed 2: no bound at all)."""
    law = rigid_law(_simulated(0), np.array(SIM_T), AT960)
    for k in ("radial", "transverse"):
        lo, hi = law[k]["interval_95"]
        assert law[k]["determined"] and lo is not None and hi is not None, (k, law[k])
        assert lo <= 1.0 <= hi, (k, law[k])
        for kind, v in law[k]["by_detrend"].items():
            assert v["interval_95"][0] <= 1.0 <= v["interval_95"][1], (k, kind, v)
    assert law["transverse"]["determined"]


def test_the_distances_of_a_pass_are_an_independent_set_whatever_the_reflectors_shape():
    """Three reflectors on a line: their three distances have a singular covariance (the fixed 3 k - 6 set made
    identify fail with LinAlgError before its collinear refusal, tests/fuzz's identify_collinear_points); the set
    kept is the rank of the rigidity matrix: k - 1 on a line, 2 k - 3 in a plane, 3 k - 6 in general."""
    from mtcal.measurement.tracker_position import _framework

    line = np.array([[0.0, 0.0, 0.0], [100.0, 0.0, 0.0], [250.0, 0.0, 0.0]])
    plane = np.array([[0.0, 0.0, 0.0], [100.0, 0.0, 0.0], [0.0, 120.0, 0.0], [90.0, 80.0, 0.0]])
    space = np.vstack([plane[:3], [[30.0, 40.0, 110.0]]])
    assert len(_framework(line)) == 2 and len(_framework(plane)) == 5 and len(_framework(space)) == 6
    assert len(_framework(np.vstack([space, [[70.0, -20.0, 60.0]]]))) == 9


def test_the_fixed_beams_likelihood_is_the_direct_one_and_its_concentrated_scale_the_best():
    """FixedBeams (each pass's R and T diagonalised once, the common scale in closed form) against
    RigidLikelihood.given (each Sigma_p inverted and the GLS solved at every call), under both detrends, at scales
    from nil-like to large, on the simulated campaign: the same value to 1e-9 of it; and the concentrated value at a
    log ratio is the minimum of the direct one over the common scale (a fine line search), at the scales it
    returns."""
    from mtcal.measurement.tracker_position import FixedBeams, RigidLikelihood, _pass_groups

    rec = _simulated(0)
    for kind in ("line", "bending"):
        lik = RigidLikelihood(_pass_groups(rec), rec.xyz, kind, AT960)
        parts = lik.parts(np.array(SIM_T))
        fb = FixedBeams(lik, parts)
        assert fb.ok
        for logs in ([0.0, 0.0], [1.3, -0.4], [-5.0, 2.0], [-25.0, 0.3], [0.2, -20.0]):
            direct = lik.given(parts, logs)
            assert abs(fb.value(logs) - direct) <= 1e-9 * abs(direct), (kind, logs)
        for theta in (-3.0, 0.4, 2.5):
            value, logs = fb.concentrated(theta)
            assert logs[0] - logs[1] == pytest.approx(theta)
            assert value == pytest.approx(lik.given(parts, logs), rel=1e-12)
            line = [lik.given(parts, logs + d) for d in np.linspace(-0.05, 0.05, 11)]
            assert value <= min(line) + 1e-9 * abs(value), (kind, theta)


def test_a_law_whose_profile_cannot_be_bracketed_leaves_its_end_unknown_not_the_diagnosis_stopped(tmp_path):
    """gen2 seed 3690 campaign 3 (benchmarks/gen2: a knocked nest and a growing scale), its readings as the
    benchmark gives them: a pass's transverse covariance is singular, the restricted likelihood's A indefinite by
    rounding at scales here and there, and the profile of a scale infinite beside finite values.  Before:
    brentq's ValueError ("f(a) and f(b) must have different signs") stopped `mtcal diagnose`.  Now that end of the
    interval is not known and the scale not determined."""
    import diagnose_gen2_rates as R  # benchmarks/ is on the path (above)

    from mtcal.diagnose import diagnose

    path = R.generate(str(tmp_path), 1, 3690, 3, "v3")[0]
    for _, text in R.cases(path.read_text()):
        assert diagnose(R.parse_recording(text, path.name)).effects is not None
    # the end itself: a crossing where the profile brackets zero, else not known
    def prof(g):
        return g * g - 4.0

    assert _profile_end(prof, 0.0, 3.0, prof(0.0), prof(3.0)) == pytest.approx(math.exp(1.0), rel=1e-3)  # g = 2
    assert _profile_end(prof, 0.0, 3.0, prof(0.0), math.inf) is None
    assert _profile_end(prof, 0.0, 3.0, math.nan, prof(3.0)) is None
    assert _profile_end(lambda g: math.nan, 0.0, 3.0, prof(0.0), prof(3.0)) is None  # not a number inside
