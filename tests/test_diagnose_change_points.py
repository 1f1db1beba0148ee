"""Issue 52 item 1, change points as one penalised search per place (mtcal.diagnose.scans.change_points): at one
place (a nest, a station's frame) the number of steps k = 0, 1, 2, ... is chosen by the scan's own max-statistic
calibration (each change point at the level over the change points scanned for it), every step's amplitude free;
a step and back is k = 2, a smooth drift is not read as steps.

The readings: three reflectors on a robot's base read 300 times from a tracker at the origin (icelinker's layout,
benchmarks/real_icelinker.py; tracker noise of an AT960-like spec, sigma 0.68 um along the beam, 3.1 um across),
nothing else moving, the changes planted at base_2 in mm, machine frame.  Oracle: the planted poses and amplitudes.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from mtcal.measurement import tracker as trk

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import real_icelinker as ri  # noqa: E402

REF = np.array([[2478.9, 547.7, -561.7], [2910.3, 825.2, -558.0], [2778.0, -5.6, -562.9]])  # mm
SPEC = trk.TrackerSpec(0.5, 0.3, 2.0, 1.5)
N = 300
LEVEL = 0.05


def _search(plant, seed: int, place: str = "nest"):
    """(change points, prep) of base_2's nest (or the station's frame) with ``plant(x)`` applied to the noisy
    readings (n, 3, 3) mm."""
    from mtcal.diagnose import effects as fx
    from mtcal.diagnose.design import base_design, engine_for, whiten
    from mtcal.diagnose.places import frame_path, nest_path, place_motion, step_rows
    from mtcal.diagnose.prepare import prepare
    from mtcal.diagnose.scans import change_points
    from mtcal.kinematics.machine import load_machine

    rng = np.random.default_rng(seed)
    x = np.repeat(REF[None], N, axis=0)
    x = x + trk.sample(x, np.zeros(3), rng, SPEC)
    plant(x)
    prep = prepare(ri.to_recording(x), load_machine("dmu50"), None, np.zeros(3))
    eng = engine_for(prep, base_design(prep, {a: 1 for a in prep.axes}), whiten(prep.W, prep.y))
    where = {"from_axis": "X", "round": 1, "position": 0.0, "readings": 0, "point": "base_2"}
    t0 = float(prep.rec.time_s.min()) + 0.5
    if place == "nest":
        c = fx.nest_knock(prep.geometry, "base_2", "tool", t0, where)
        path = nest_path(prep, c)
    else:
        c = fx.tracker_knock(prep.geometry, t0, where)
        path = frame_path(prep, c)
    cp = change_points(prep, eng, step_rows(prep, c), place_motion(prep, c), LEVEL, smooth=path.G)
    return cp, prep


def _rounds(cp, prep) -> list[int]:
    """The pose (round) each change point starts at, in time order."""
    return sorted(int(prep.rec.round[r].min()) for r in cp.rows)


SEEDS = range(10)
SPURIOUS = 2  # of 10 runs: at most this many with a change point (or a drift) more than planted.  Each further
#               change point enters at LEVEL over those scanned for it, so one is spurious in at most 5 % of runs
#               (binomial: 3 or more of 10 at 5 % is 1.2 %)


def _runs(plant, place: str = "nest"):
    return [_search(plant, seed, place) for seed in SEEDS]


def _found(cp, prep, planted: list[int]) -> bool:
    """Whether the strongest len(planted) change points are the planted ones (the poses they start at, to within
    one pose: a step between two readings of one pose starts at it)."""
    found = sorted(int(prep.rec.round[r].min()) for r in cp.rows[:len(planted)])
    return len(found) == len(planted) and all(abs(f - p) <= 1 for f, p in zip(found, planted))


def test_no_step_planted_reads_no_step():
    runs = _runs(lambda x: None)
    assert sum(cp.k > 0 for cp, _ in runs) + sum(cp.drift is not None for cp, _ in runs) <= SPURIOUS, [
        (cp.t0, cp.drift) for cp, _ in runs]


def test_one_step_is_one_change_point_where_it_was_planted():
    def plant(x):
        x[150:, 1] += [0.012, -0.008, 0.0]
    runs = _runs(plant)
    assert all(_found(cp, prep, [151]) for cp, prep in runs), [_rounds(cp, prep) for cp, prep in runs]
    assert all(np.allclose(cp.theta[0], [0.012, -0.008, 0.0], atol=2e-3) for cp, _ in runs if cp.k == 1)
    assert sum(cp.k != 1 or cp.drift is not None for cp, _ in runs) <= SPURIOUS, [cp.k for cp, _ in runs]


def test_a_step_and_back_is_two_change_points_that_cancel():
    def plant(x):
        x[100:180, 1] += [0.010, 0.0, 0.008]
    runs = _runs(plant)
    assert all(_found(cp, prep, [101, 181]) for cp, prep in runs), [_rounds(cp, prep) for cp, prep in runs]
    assert all(np.abs(cp.theta.sum(axis=0)).max() < 2e-3 for cp, _ in runs if cp.k == 2)  # nothing left after
    assert sum(cp.k != 2 or cp.drift is not None for cp, _ in runs) <= SPURIOUS, [cp.k for cp, _ in runs]


def test_two_steps_that_stay_are_two_change_points_with_their_amplitudes():
    def plant(x):
        x[80:, 1] += [0.012, 0.0, 0.0]
        x[200:, 1] += [0.0, 0.015, 0.0]
    runs = _runs(plant)
    assert all(_found(cp, prep, [81, 201]) for cp, prep in runs), [_rounds(cp, prep) for cp, prep in runs]
    for cp, _ in runs:
        if cp.k == 2:
            order = np.argsort(cp.t0)
            assert np.allclose(cp.theta[order], [[0.012, 0.0, 0.0], [0.0, 0.015, 0.0]], atol=2e-3), cp.theta
    assert sum(cp.k != 2 or cp.drift is not None for cp, _ in runs) <= SPURIOUS, [cp.k for cp, _ in runs]


def test_a_step_of_the_stations_frame_is_one_change_point():
    def plant(x):
        x[120:] += [0.0, 0.0, 0.006]
    runs = _runs(plant, place="frame")
    assert all(_found(cp, prep, [121]) for cp, prep in runs), [_rounds(cp, prep) for cp, prep in runs]
    assert sum(cp.k != 1 or cp.drift is not None for cp, _ in runs) <= SPURIOUS, [cp.k for cp, _ in runs]


def test_a_smooth_drift_is_not_read_as_steps():
    """base_2 wandering smoothly 10-15 um: a greedy search samples it with steps (as many as it may take); the
    place's smooth path beside them is still needed, so the search reads a drift, in every run."""
    def plant(x):
        s = np.linspace(0.0, 1.0, len(x))
        x[:, 1] += np.stack([0.015 * np.sin(2 * np.pi * s), 0.010 * np.cos(3 * np.pi * s),
                             0.012 * np.sin(np.pi * s)], 1)
    runs = _runs(plant)
    assert all(cp.drift is not None and cp.drift.logp < np.log(LEVEL) for cp, _ in runs), [
        (cp.k, cp.drift) for cp, _ in runs]


def _diagnose(plant, seed: int, tracker):
    from mtcal.diagnose import diagnose

    rng = np.random.default_rng(seed)
    x = np.repeat(REF[None], N, axis=0)
    x = x + trk.sample(x, np.zeros(3), rng, SPEC)
    plant(x)
    return diagnose(ri.to_recording(x), tracker=tracker)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])
def test_a_nest_stepping_three_times_is_one_located_entry_not_three_knocks(seed):
    """base_2 stepping three times (12 um along x at pose 76; 12 um along y at 151; 12 um back along -x and 16 um
    along -y at 226): the place's search reads k = 3 steps, the nest stepping again and again (places.unsteady), one
    located entry at the nest; nothing named.  The levels have no linear trend in time, so a creep of the nest
    does not fit them (whether a creep is adequate beside its place's steps is not this test's).  On main, without
    the tracker, seed 0 had base_2 named knocked at pose 226; seed 1 located the nest moving smoothly.
    (Without the tracker, seed 1 also names a one-sequence offset of base_2 beside the located entry: the law
    estimated from the rounds, issue 52 item 2, not the change points.)"""
    def plant(x):
        x[75:, 1] += [0.012, 0.0, 0.0]
        x[150:, 1] += [0.0, 0.012, 0.0]
        x[225:, 1] += [-0.012, -0.016, 0.0]
    for t in (None, np.zeros(3)):
        d = _diagnose(plant, seed, t)
        steps = [f.get("where") for f in d.effects if f.significant and ("knocked" in str(f.get("where"))
                                                                          or "re-levelled" in str(f.get("where")))]
        assert steps == [], (t, steps)
        where = [u.where for u in d.unexplained if str(u.where).startswith("the nest of base_2")]
        assert any("stepping at" in s and s.count(",") >= 2 for s in where), (t, [u.where for u in d.unexplained])


def test_a_step_whose_late_readings_move_in_fewer_directions_is_not_a_crash(tmp_path):
    """gen3 (benchmarks/gen3) seed 1006 campaign 5, a tracker re-levelled before Z's last rounds: from a late t0 on,
    the re-levelling's five columns (a turn and a translation) span fewer directions, G^T G's smallest eigenvalue
    1e-20 of its largest but positive, and step_scan's solve raised LinAlgError ("internal error" from the
    command).  Such a change point is not counted (scans.RANK_TOL, as Engine.score); the re-levelling is named."""
    import importlib.util
    from pathlib import Path

    from mtcal.diagnose import diagnose
    from mtcal.measurement.recordings import read_recording

    spec = importlib.util.spec_from_file_location(
        "gen3", Path(__file__).resolve().parents[1] / "benchmarks" / "gen3" / "gen3.py")
    gen3 = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen3)
    gen3.write_campaign(1006, 5, str(tmp_path), 0.3, "all", None)
    d = diagnose(read_recording(tmp_path / "campaign_0005.csv"))
    assert [f.name for f in d.effects if f.significant] == ["tracker_relevel"], [
        (f.name, f.get("where")) for f in d.effects if f.significant]
