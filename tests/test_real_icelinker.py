"""benchmarks/real_icelinker.py (public tracker readings of three fixed base reflectors, not shipped) checked on a
planted replica of its layout: the same three reflectors and tracker at the origin, the tracker noise drawn as the
simulator draws it (mtcal.measurement.tracker.sample) under a known law, a slow drift and a pose-to-pose motion
shared by the three, and planted gross errors (no target: (0, 0, 0); another target: the robot's reflector).  The
screen must flag exactly those readings and name the class, the independent check must find a 40 um outlier the
screen leaves alone, and the law from the mutual distances must be the planted one whatever the shared motion."""
from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

from mtcal.measurement import tracker as trk

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import real_icelinker as ri  # noqa: E402

REF = np.array([[2478.9, 547.7, -561.7], [2910.3, 825.2, -558.0], [2778.0, -5.6, -562.9]])  # mm, as the data's
SPEC = trk.TrackerSpec(0.5, 0.3, 2.0, 1.5)  # MPE um, um/m: sigma 0.68 um along, 3.1 um across at 2.84 m
DRIFT_UM = np.array([-40.0, 25.0, 20.0])
NO_TARGET = {(40, 2), (130, 1), (131, 2), (250, 2)}  # (file line, reflector index)
OTHER = {(60, 2), (200, 2)}
OUTLIER = (150, 0)


def _readings(n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """(n, 3, 3) base readings and the robot reflector (n, 3), mm."""
    x = REF[None] + np.linspace(0.0, 1.0, n)[:, None, None] * DRIFT_UM * 1e-3
    for i in range(n):  # the shared motion: a small rotation (~4 urad) and a translation (~8 um)
        w = rng.normal(0.0, 4e-6, 3)
        x[i] += np.cross(w, x[i]) + rng.normal(0.0, 8e-3, 3)
    x = x + trk.sample(x, np.zeros(3), rng, SPEC)
    robot = np.array([2500.0, 0.0, -450.0]) + rng.normal(0.0, 50.0, (n, 3))
    for line, k in NO_TARGET:
        x[line - 1, k] = 0.0
    for line, k in OTHER:
        x[line - 1, k] = robot[line - 1]
    x[OUTLIER[0] - 1, OUTLIER[1]] += np.array([0.03, -0.02, 0.02])
    return x, robot


def _folder(tmp_path: Path, n: int = 1000) -> Path:
    x, robot = _readings(n, np.random.default_rng(3))
    for k, name in enumerate(ri.NAMES):
        np.savetxt(tmp_path / f"measured_{name}.txt", x[:, k])
    np.savetxt(tmp_path / "measured_SMR_2.txt", robot)
    return tmp_path


@pytest.mark.slow
def test_the_script_finds_the_planted_rows_the_drift_and_the_law(tmp_path):
    out = ri.run(_folder(tmp_path), with_diagnosis=True)
    flagged = {(r["line"], ri.NAMES.index(r["file"][9:-4]), r["looks_like"].split(":")[0].split(",")[0])
               for r in out["screen"]["flagged"]}
    assert flagged == ({(ln, k, "no target") for ln, k in NO_TARGET} | {(ln, k, "another target") for ln, k in OTHER})
    assert all("robot's SMR_2" in r["looks_like"] for r in out["screen"]["flagged"]
               if r["looks_like"].startswith("another"))
    assert OUTLIER[0] in [r["line"] for r in out["independent_check"]["kept_but_suspicious"]]
    assert np.abs(np.array(out["drift"]["shared_first_to_last_um"]) - DRIFT_UM).max() < 8.0  # 2.5 um/end
    law, (s_r, s_t) = out["noise_law"]["mutual_distances"], (1e3 * s for s in SPEC.sigmas(2837.0))
    assert abs(law["transverse_sigma_um"] / s_t - 1) < 0.15, (law, s_t)
    assert law["radial_sigma_um"] < 1.5 * s_r < 1.5 * law["upper_bounds_um"]["radial"], (law, s_r)
    # --diagnose: both runs' weights hold the mutual distances' scatter within 2x, the planted drift named in both
    d = out["diagnosis"]
    for how in ("without_tracker", "tracker_at_origin"):
        assert all(0.5 < v < 2.0 for v in d[how]["predicted_over_measured"]), (how, d[how])
    assert "name=thermal_drift variant=ramp over the record" in d["in_both"], d


def test_a_knock_in_a_recording_of_one_reading_per_nest_and_round_has_a_held_out_gain():
    """icelinker's layout (one pose a round, each base reflector read once in it: every (axis, round, point)
    sequence is one reading) with the tracker knocked 30 um at pose 150 of 300.  The knock is named, and its
    held-out gain is computed on alternate rounds of each nest: alternate readings within the one-reading
    sequences leave one fold empty, and the knock was reported with no gain and a wrong reason ("the held-out folds
    leave no residual", icelinker's every finding)."""
    from mtcal.diagnose import diagnose

    rng = np.random.default_rng(5)
    n = 300
    x = REF[None] + trk.sample(np.repeat(REF[None], n, axis=0), np.zeros(3), rng, SPEC)
    x[150:] += np.array([0.03, -0.01, 0.0])
    d = diagnose(ri.to_recording(x), tracker=np.zeros(3))
    named = [f for f in d.effects if f.significant]
    assert [f.get("variant") for f in named] == ["tracker knock"], [f.get("where") for f in named]
    assert named[0].evidence["cv_gain"] > 0.5, named[0].evidence


def test_where_the_station_is_not_determined_no_turn_about_it_is_offered():
    """The replica's 300 poses without the tracker's position: the rounds' scatter holds the poses' shared motion,
    so the station it places is not determined (noise_model.station_interval).  A turn about that station (a
    settling tracker; a re-levelling without its shift) is then a turn about a guessed point, as the air's scale
    about it already was: stated not separable, with the measurement that separates it.  On icelinker, a settling
    about the rounds' station 1.08 m from the readings was the strongest candidate (F = 19 600) and the findings
    changed with the station."""
    from mtcal.diagnose import diagnose

    x, _ = _replica(3)
    d = diagnose(ri.to_recording(x))
    assert not d.noise.details["station_interval"]["determined"]
    why = {f.name: f.get("not_separable") or "" for f in d.effects}
    for name in ("tracker_settling", "air_index_drift"):
        assert "station is not determined" in why.get(name, ""), (name, why.get(name))
    assert all("re-levelled and shifted" in f.get("where", "") for f in d.effects if f.name == "tracker_relevel"
               and f.evidence is not None)


def _wandering(x: np.ndarray) -> np.ndarray:
    """The readings (n, 3, 3) mm with the base's frame wandering smoothly, shared by the three reflectors: 12 um
    along Y one and a half periods of a sine over the record, a rise of 8 um along Z over the last third (tanh, a
    tenth of the record wide) -- a stand warming and cooling, no step anywhere."""
    s = np.linspace(0.0, 1.0, len(x))
    return x + np.stack([np.zeros_like(s), 12e-3 * np.sin(3 * np.pi * s), 4e-3 * (1 + np.tanh((s - 0.7) / 0.1))],
                        axis=1)[:, None, :]


SEED4_MERGE = ("issue 52, open: seed 4 of the replica since this session's merge of the change-point search with the "
               "station and law from the mutual distances: the located entry reads the place stepping (k >= 3 change "
               "points) where each branch alone read it as planted; which rule is wrong is not established")


@pytest.mark.slow
@pytest.mark.parametrize("seed", [3, pytest.param(4, marks=pytest.mark.xfail(strict=True, reason=SEED4_MERGE)), 6])
def test_a_frame_wandering_smoothly_is_located_at_the_tracker_not_named_as_knocks(seed):
    """Issue 34 ("one finding per mismatch"; icelinker's findings the same with and without --tracker): the
    replica's three reflectors moving together smoothly with time (_wandering) beside the pose-to-pose motion.  A
    step of the tracker's frame is named only where the frame moving smoothly in the order of the readings
    (places.frame_path) is not still needed beside it (selection._change_points); the wander is then one mismatch
    located at the tracker.  Before, steps were named wherever the frame moved most: tracker knocks, without the
    tracker's position and with it, 1 and 2 (seed 3), 2 and 4 (seed 4), 2 and 1 (seed 6), and the tool side
    "expanding" in three of the six runs; icelinker four and three knocks."""
    from mtcal.diagnose import diagnose

    x, planted_round = _replica(seed)
    x = _wandering(x)
    for t in (None, np.zeros(3)):
        d = diagnose(ri.to_recording(x), tracker=t)
        named = [ri.same_as(f) for f in d.effects if f.significant]
        assert set(named) <= _planted(planted_round), (t, named)
        at = [u for u in d.unexplained if u.by == "time (station frame)"]
        assert len(at) == 1 and "moving smoothly with time" in at[0].where, (t, [u.where for u in d.unexplained])


def _planted(planted_round: int) -> set[str]:
    """What the replica plants that a diagnosis may name: the drift shared by the three reflectors, the displaced
    reading (file line 150, in the pose numbering after the gross rows are left out)."""
    return {"name=thermal_drift variant=ramp over the record",
            f"name=offset variant=re-seated nest point=base_1 round={planted_round}"}


def _replica(seed: int, n: int = 300) -> tuple[np.ndarray, int]:
    """The replica's readings of ``n`` poses, its planted gross errors left out, and the planted reading's pose."""
    x, _ = _readings(n, np.random.default_rng(seed))
    ok = np.all(np.abs(x) > 1.0, axis=(1, 2))
    return x[ok], int(np.flatnonzero(ok).tolist().index(OUTLIER[0] - 1)) + 1


@pytest.mark.slow
@pytest.mark.parametrize("seed", [3, 4])
def test_a_nest_wandering_smoothly_is_located_at_the_nest_not_named_as_knocks(seed):
    """One base reflector (base_2) wandering smoothly against the other two, 10-15 um each way over the record: a
    nest's step is named only where the nest moving smoothly in the order of the readings (places.nest_path) is not
    still needed beside it (selection._change_points), and that path is then the one located mismatch.  Before,
    seed 3 had three knocks of base_2 named without the tracker's position and one with it (beside a side
    expanding), seed 4 two knocks without, one knock and a creep with."""
    from mtcal.diagnose import diagnose

    x, planted_round = _replica(seed)
    s = np.linspace(0.0, 1.0, len(x))
    x[:, 1] += np.stack([0.015 * np.sin(2 * np.pi * s), 0.010 * np.cos(3 * np.pi * s), 0.012 * np.sin(np.pi * s)], 1)
    for t in (None, np.zeros(3)):
        d = diagnose(ri.to_recording(x), tracker=t)
        named = [ri.same_as(f) for f in d.effects if f.significant]
        assert set(named) <= _planted(planted_round), (t, named)
        assert any(u.where.startswith("the nest of base_2") for u in d.unexplained), (t, [u.where for u in
                                                                                            d.unexplained])


@pytest.mark.slow
@pytest.mark.parametrize("seed", [3, 4, 5])
def test_a_pose_off_as_a_whole_is_not_a_reseated_nest(seed):
    """Pose 201's three readings displaced together, 64 um (the robot's pose moving the base, icelinker's pose
    976: 45 um, the three alike).  A re-seated nest must not be shared, the same way, by the other nests read at
    the same stop (selection.inadequate_because); before, "re-seated nest base_3 round 201" was named in five runs
    of these six."""
    from mtcal.diagnose import diagnose

    x, planted_round = _replica(seed)
    x[200] += np.array([0.04, -0.05, 0.0])
    for t in (None, np.zeros(3)):
        named = [ri.same_as(f) for f in diagnose(ri.to_recording(x), tracker=t).effects if f.significant]
        assert set(named) <= _planted(planted_round), (t, named)


def test_the_lever_arms_are_the_nests_not_the_readings():
    """A turn or a scale of the readings is built on each reading's nominal position (effects.Geometry.xyz), which
    every reading of a nest at one pose shares: built on the readings, a column carries their noise, and a few
    nearly equal columns fit the residual through their differences (icelinker with the tracker given: a tie of
    eight columns took the sigma ratio from 9.0 to 1.8, through combinations of the columns 1e-5 from the span of
    the others)."""
    from mtcal.diagnose.prepare import prepare
    from mtcal.kinematics.machine import load_machine

    x, _ = _replica(3)
    rec = ri.to_recording(x)
    g = prepare(rec, load_machine("dmu50"), None, np.zeros(3)).geometry
    for p in ri.NAMES:
        on = rec.point == p
        assert np.ptp(g.xyz[on], axis=0).max() < 1e-9, p  # one lever arm per nest, to a picometre
    assert np.abs(g.xyz - rec.xyz).max() > 1e-3  # the readings scatter 8 um about it


def _tilted(x: np.ndarray, poses: slice, um: float) -> np.ndarray:
    """The readings (n, 3, 3) mm with the base turned, for ``poses``, about the line through base_1 and base_3 so
    that base_2 moves ``um`` at right angles to the three's plane: every pose rigid (the mutual distances
    unchanged), the base tilted for a while and back."""
    u = (REF[2] - REF[0]) / np.linalg.norm(REF[2] - REF[0])
    angle = um * 1e-3 / np.linalg.norm(np.cross(REF[1] - REF[0], u))
    y = x.copy()
    y[poses] += angle * np.cross(u, x[poses] - REF[0])
    return y


@pytest.mark.slow
@pytest.mark.parametrize("seed", [3, 4, 5])
def test_a_base_tilted_for_a_while_is_not_named_a_knock(seed):
    """The replica's base tilted 80 um at base_2 for poses 101-122 and back (_tilted): icelinker's base_2 named
    knocked at pose 573 and back at 595 with the tracker given, nothing without.  A step that a second step along
    its own motion takes back gives way to its place displaced for a while (selection._change_points), and a nest's
    step that only turns the stops it is read at, where they move at random, is not the nest's
    (selection._stops_tilt).  Before: a knock of base_2 without the tracker (seed 4), a re-levelling of the tracker
    both ways (seed 5)."""
    from mtcal.diagnose import diagnose

    x, planted_round = _replica(seed)
    x = _tilted(x, slice(100, 122), 80.0)
    for t in (None, np.zeros(3)):
        named = [ri.same_as(f) for f in diagnose(ri.to_recording(x), tracker=t).effects if f.significant]
        assert set(named) <= _planted(planted_round), (t, named)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [3, pytest.param(4, marks=pytest.mark.xfail(strict=True, reason=SEED4_MERGE))])
def test_a_nest_displaced_for_a_while_and_back_is_located_not_named_twice(seed):
    """base_2 displaced 64 um for poses 101-125 and back (a nest bumped and re-seated): outside the grammar, it is
    located once, at the nest, with its interval (places.bump).  Before: base_2 named knocked at pose 101 and again
    at 126 in three runs of these four."""
    from mtcal.diagnose import diagnose

    x, planted_round = _replica(seed)
    x[100:125, 1] += np.array([0.04, -0.05, 0.0])
    for t in (None, np.zeros(3)):
        d = diagnose(ri.to_recording(x), tracker=t)
        named = [ri.same_as(f) for f in d.effects if f.significant]
        assert set(named) <= _planted(planted_round), (t, named)
        if t is not None:
            where = [u.where for u in d.unexplained if str(u.where).startswith("the nest of base_2")]
            assert any("displaced from axis X round 101 to round 125" in s for s in where), (t, where)


def test_the_return_scan_is_the_best_second_step_by_brute_force():
    """scans.return_scan (a step's second change point along its own motion, by running sums) on the replica with
    base_2 displaced for poses 101-125: every change point's reduction equals Engine.score of that step formed
    whole, and the scan returns the largest, at pose 126 (base_2's first step fitted at 101)."""
    from mtcal.diagnose import effects as fx
    from mtcal.diagnose.design import base_design, engine_for, whiten
    from mtcal.diagnose.places import step_rows
    from mtcal.diagnose.prepare import prepare
    from mtcal.diagnose.scans import return_scan
    from mtcal.kinematics.machine import load_machine

    x, _ = _replica(3)
    x[100:125, 1] += np.array([0.04, -0.05, 0.0])
    prep = prepare(ri.to_recording(x), load_machine("dmu50"), None, np.zeros(3))
    eng = engine_for(prep, base_design(prep, {a: 1 for a in prep.axes}), whiten(prep.W, prep.y))
    g = prep.geometry
    step = fx.nest_knock(g, "base_2", "tool", float(prep.rec.time_s[prep.rec.round == 101].min()) - 0.5,
                         {"from_axis": "X", "round": 101, "position": 0.0, "readings": 0})
    Gc = whiten(prep.W, step.G)
    eng.add(Gc)
    rows = step_rows(prep, step)
    pattern = np.where(rows[:, None], np.einsum("nij,j->ni", g.rotation.reshape(-1, 3, 3), [0.04, -0.05, 0.0]), 0.0)
    found, count = return_scan(prep, eng, rows, pattern)
    o = np.argsort(prep.order)
    o = o[rows[o]]
    deltas = []
    for j in range(1, len(o)):
        G = np.zeros((len(rows), 3, 1))
        G[o[j:], :, 0] = pattern[o[j:]]
        sc = eng.score(whiten(prep.W, G))
        deltas.append(sc.delta if sc.separable else -np.inf)
    assert count == sum(np.isfinite(deltas)), (count, len(deltas))
    assert abs(found["delta"] - max(deltas)) < 1e-9 * max(deltas), (found["delta"], max(deltas))
    assert int(prep.rec.round[found["rows"]].min()) == 126


# ----------------------------------------------------------------------------- icelinker's own readings (issue 52)
# The readings carry no licence and are not shipped: point MTCAL_ICELINKER at the folder that holds
# measured_base_{1,2,3}.txt (benchmarks/real_icelinker.py's docstring says how to fetch them); skipped without it.
ICELINKER = Path(os.environ.get("MTCAL_ICELINKER", "/nonexistent"))
TRUE_STATION_M = 2.82  # the FARO tracker at the files' origin, 2.82 m from the base readings' centre
needs_icelinker = pytest.mark.skipif(not (ICELINKER / "measured_base_1.txt").is_file(),
                                     reason="icelinker's readings are not shipped: set MTCAL_ICELINKER")


def _icelinker():
    rec = ri.to_recording(ri.load(ICELINKER))
    return rec.select(ri.screen(rec).keep)


def _holds(interval_mm, metres: float) -> bool:
    return interval_mm is not None and interval_mm[0] <= metres * 1e3 <= interval_mm[1]


@needs_icelinker
def test_icelinker_the_stations_interval_holds_where_the_tracker_stood():
    """Without --tracker the diagnosis stated the station "not determined" over 1.69-2.25 m from the readings
    (the rounds' scatter holds the base's shared motion), excluding the true 2.82 m."""
    from mtcal.diagnose import diagnose

    st = diagnose(_icelinker()).noise.details["station_interval"]
    assert _holds(st["interval_95_mm"], TRUE_STATION_M), st["interval_95_mm"]


@needs_icelinker
def test_icelinker_identify_states_no_plus_minus_that_excludes_the_station():
    """identify printed "tracker position estimated from the scatter: 869, -111, -588 +- 117, 42, 13 mm", the
    truth 45 sigma away in z: its statement now carries the profile's status and an interval that holds it."""
    from mtcal.identify.run import estimate_station, station_text

    est, _ = estimate_station(_icelinker())
    text = station_text(est)
    assert "+-" not in text or np.all(np.abs(est.position) <= 3 * est.sigma_mm), text
    assert _holds(est.interval["interval_95_mm"], TRUE_STATION_M), est.interval


@needs_icelinker
def test_icelinker_the_law_along_the_beam_is_not_determined_where_the_detrend_changes_it():
    """Each distance less a line gave "determined, 0.27-0.70 um" along the beam; any detrend that bends gives
    0-0.2 um: the law is not determined there, and its source is said the same way in every field."""
    from mtcal.measurement.tracker_position import estimate_shape, rigid_law

    rec = _icelinker()
    law = rigid_law(rec, np.zeros(3))
    assert not law["radial"]["determined"], law["radial"]
    assert set(law["radial"]["by_detrend"]) == {"line", "bending"}
    sh = estimate_shape(rec, np.zeros(3))
    report = sh.report()
    assert sh.source in report["obtained"] and "mutual distances" in sh.source, (sh.source, report)
    assert "repeated rounds" not in report["obtained"], report
