"""An error motion of an axis moves the nests of each pose together (places._axis_poses): a named quadratic, scale,
periodic or constant error of an axis is adequate only where its nests, each free at every pose beside the axis'
error motions tabulated there, add nothing.  A tracker whose distance meter has a cyclic error moves each nest
along its own beam by a different amount at the same pose; without a station to map it (isotropic weights, the
tracker not given) it was named a quadratic of C.  Campaign of benchmarks/gen3 (a generator written from the
physics, not from mtcal/diagnose)."""
from __future__ import annotations

import csv

import pytest
from test_diagnose_beside import _gen3

from mtcal.diagnose import diagnose
from mtcal.measurement.recordings import read_recording


@pytest.mark.slow
def test_a_cyclic_distance_error_without_a_station_is_not_a_quadratic_of_c(tmp_path):
    """gen3 1017/94: a 2.6 um cyclic error of the distance meter (period 116 mm) under isotropic noise of 0.95 um,
    the tracker columns removed (benchmarks/diagnose_gen3_rates.py's defaults): before, "second_order C E_YC"
    named (F = 24.7, p_adj 1.7e-4), the nests of C located displaced at 336 deg; now not named (each nest free at
    every pose of C is still needed beside it, F = 3.6, p = 2e-13) and the mismatch located on C's nests by
    position x point, sized within 1.5x of the largest displacement planted."""
    _gen3().write_campaign(1017, 94, str(tmp_path), 0.0, "all", ["adm_cyclic"])
    with open(tmp_path / "campaign_0094.csv") as f:
        rows = list(csv.reader(f))
    keep = [i for i, k in enumerate(rows[0]) if not k.startswith("tracker_")]
    with open(tmp_path / "bare.csv", "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows([[r[i] for i in keep] for r in rows])
    d = diagnose(read_recording(tmp_path / "bare.csv"))
    assert not [f.name for f in d.effects if f.significant], [(f.name, f.axis) for f in d.effects if f.significant]
    withdrawn = {f.name: f.get("inadequate") or "" for f in d.effects if f.get("inadequate")}
    assert "move differently at its poses" in withdrawn.get("second_order", ""), withdrawn
    (u,) = d.to_dict()["unexplained"]
    assert (u["axis"], u["by"]) == ("C", "position x point"), u
    assert 0 < u["size_mm"] < 1.5 * 0.00258, u
