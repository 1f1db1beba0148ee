"""Located entries taken one at a time (mtcal.diagnose.scans.one_at_a_time): a misfit at one place leaks through the
base's shared freedoms into the readings of other places; each entry is reported only where it is still located
beside the ones before it, the first the group whose readings, freed in every cell, explain the misfit best.
Campaigns of benchmarks/gen3 (written from the physics, not from mtcal/diagnose) on its development seeds."""
from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from test_diagnose_beside import _gen3

from mtcal.diagnose import diagnose
from mtcal.diagnose import effects as fx
from mtcal.diagnose.prepare import prepare
from mtcal.measurement.recordings import read_recording


def _places(u) -> tuple[str, set[str]]:
    """An unexplained entry's axis and the reflector labels it names."""
    return u.axis, set(re.findall(r"\bP\d+\b", str(u.where)))


@pytest.mark.slow
@pytest.mark.parametrize("seed, index, physics", [(1012, 28, "smr_incidence"), (1011, 65, "table_sag")])
def test_a_misfit_is_located_where_it_is_not_where_it_leaks(tmp_path, seed, index, physics):
    """gen3 1012/28: the reflector in spindle nest P4 reads long with its incidence (up to 6.5 um, X, Y and Z);
    1011/65: the table sagging with B (B's readings only, P8 most).  Before: beside the right entries, one at
    another nest ("axis Z by point = P3", p_adj 9e-11) or another axis ("axis C by point = P7", 6e-11), which
    nothing planted moves: the base's shared freedoms (a reflector's position fitted from every axis it is read
    on, an axis' error motions from every nest) carried part of the misfit there.  Now every unexplained entry is
    at an axis and a nest the physics moves."""
    _gen3().write_campaign(seed, index, str(tmp_path), 0.0, "all", [physics])
    truth = json.loads((tmp_path / f"campaign_{index:04d}.truth.json").read_text())
    shows = truth["classes"][0]["shows_at"]
    d = diagnose(read_recording(tmp_path / f"campaign_{index:04d}.csv"))
    assert d.unexplained, "nothing located"
    for u in d.unexplained:
        axis, labels = _places(u)
        assert axis in shows["axes"] and labels <= set(shows["points"]), (axis, u.by, u.where, shows)


def test_a_cell_is_one_nest_at_one_pose_and_direction_over_the_rounds():
    """fx.by_cell on the demo campaign's first axis: one 3-vector per (nest, station, axis, position, direction),
    the same column for every round of a cell, nothing on readings outside the group."""
    rec = read_recording(Path(__file__).resolve().parents[1] / "mtcal" / "data" / "demo_campaign.csv")
    prep = prepare(rec)
    g = prep.geometry
    a = g.axis[0]
    rows = np.flatnonzero(g.axis == a)
    c = fx.by_cell(g, rows)
    cells = {(p, q, d) for p, q, d in zip(g.point[rows], g.position[rows], g.direction[rows])}
    assert c.G.shape == (len(g.axis), 3, 3 * len(cells))
    outside = np.setdiff1d(np.arange(len(g.axis)), rows)
    assert not np.any(c.G[outside])
    for j in range(0, c.G.shape[2], 3):
        on = np.flatnonzero(c.G[:, 0, j])
        assert len({(g.point[i], g.position[i], g.direction[i]) for i in on}) == 1
        assert len(set(prep.rec.round[on].tolist())) == len(on)  # one reading per round
        assert np.allclose(c.G[on, :, j:j + 3], np.eye(3))
