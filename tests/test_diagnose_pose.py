"""A nest's motion in time against its displacement with the machine's pose (selection._moves_with_the_pose): a
step or a creep of a nest is named only where, with it fitted, the nest's own displacement with the pose -- the
same in every round and either direction, free at each pose and smooth in each axis' position -- is not still
needed beside it.  Campaigns of benchmarks/gen3 (a generator written from the physics, not from mtcal/diagnose) on
its development seed 1010."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from test_diagnose_beside import _gen3

from mtcal.diagnose import diagnose
from mtcal.diagnose import effects as fx
from mtcal.diagnose.prepare import prepare
from mtcal.measurement.recordings import read_recording


@pytest.mark.slow
@pytest.mark.parametrize("index, physics, points", [(71, "smr_incidence", {"P2"}),
                                                     (7, "table_sag", {"P5", "P6", "P7", "P8"})])
def test_a_nest_moving_with_the_pose_is_located_not_named_knocked(tmp_path, index, physics, points):
    """gen3 1010/71: a reflector whose apparent centre moves with its angle to the beam (incidence, 1-3 um at
    P2); 1010/7: the table sagging with B (every table nest, P8 most).  Before: "nest_knock" of a nest named
    (F = 14.3 and 29.6), nothing located.  A knock moves the nest from one time on whatever the pose; these move it
    with the pose in every round: the knock and the creep are withdrawn saying so, and the mismatch is located at
    a nest the physics moves."""
    _gen3().write_campaign(1010, index, str(tmp_path), 0.0, "all", [physics])
    d = diagnose(read_recording(tmp_path / f"campaign_{index:04d}.csv"))
    assert not [f.name for f in d.effects if f.significant], [(f.name, f.get("where")) for f in d.effects
                                                             if f.significant]
    withdrawn = {f.name for f in d.effects if "changes with the machine's pose" in (f.get("inadequate") or "")}
    assert "nest_knock" in withdrawn, withdrawn
    assert any(p in str(u.where) for u in d.unexplained for p in points), [(u.axis, u.by, u.where)
                                                                           for u in d.unexplained]


def test_the_pose_forms_are_the_nests_own_and_the_same_in_every_round():
    """fx.by_pose on the demo campaign: one translation per pose read more than once (station, axis, position;
    either direction), only on the nest's readings; the smooth member a polynomial per axis; both move no other
    nest and give every round of one pose the same column."""
    rec = read_recording(Path(__file__).resolve().parents[1] / "mtcal" / "data" / "demo_campaign.csv")
    g = prepare(rec).geometry
    point, side = str(g.point[0]), str(g.side[0])
    on = (g.point == point) & (g.side == side)
    smooth, free = fx.by_pose(g, point, side, 2)
    poses = {(a, p) for a, p in zip(g.axis[on].tolist(), g.position[on].tolist())}
    assert free.G.shape[-1] == 3 * len(poses)
    assert smooth.G.shape[-1] == 3 * 3 * len(set(g.axis[on].tolist()))
    for f in (free, smooth):
        assert not np.any(f.G[~on])
        for a, p in list(poses)[:5]:
            rows = np.flatnonzero(on & (g.axis == a) & (g.position == p))
            assert np.allclose(f.G[rows], f.G[rows[:1]]), (a, p)


@pytest.mark.slow
def test_a_motion_in_time_the_pose_explains_as_well_is_not_named(tmp_path):
    """gen3 1013/20: a reflector in spindle nest P3 reading long with its incidence, X measured from three stations
    one after another (each station sees the nest at its own angle).  Before: "nest_creep P3" named (F = 21.0): a
    creep and "P3 seen differently from each station" move P3 alike, the stations being read in turn.  Beside the
    nest's translation per station the creep adds nothing significant: it is withdrawn saying so."""
    _gen3().write_campaign(1013, 20, str(tmp_path), 0.0, "all", ["smr_incidence"])
    d = diagnose(read_recording(tmp_path / "campaign_0020.csv"))
    named = [(f.name, f.get("where")) for f in d.effects if f.significant]
    assert not [n for n in named if n[0] in ("nest_creep", "nest_knock")], named
    creep = [f for f in d.effects if f.name == "nest_creep"]
    assert creep and "as well the nest read differently from each station" in (creep[0].get("inadequate") or "")
