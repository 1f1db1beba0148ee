"""Diagnosis of recordings with station columns (docs/design.md): the recording's tracker position sets the noise
model; ``--station`` selects one station of several (several in one fit: tests/test_diagnose_multistation.py)."""
from __future__ import annotations

import numpy as np
import pytest

import mtcal
from mtcal.campaign.stations import simulate_stations
from mtcal.cli import main
from mtcal.diagnose import diagnose
from mtcal.errors import InputError
from mtcal.measurement.recordings import format_recording, read_recording

M = mtcal.load_machine("dmu50")
FRONT, LEFT = (250.0, -1500.0, 150.0), (-1500.0, 0.0, 150.0)
PLAN = {"axes": {"X": {"start": -200, "stop": 200, "count": 5}, "Y": {"start": -200, "stop": 200, "count": 5}},
        "bidirectional": False}


@pytest.fixture(scope="module")
def two_stations(tmp_path_factory):
    rec, _ = simulate_stations(None, [FRONT, LEFT], machine=M, rounds=3, seed=4, plan=PLAN)
    path = tmp_path_factory.mktemp("st") / "two.csv"
    path.write_text(format_recording(rec))
    return path


def test_several_stations_without_tracker_columns_are_refused_naming_them(two_stations):
    rec = read_recording(two_stations, M)
    rec.tracker_xyz = None
    with pytest.raises(InputError, match=r"2 tracker stations \(S1, S2\) but no tracker_x.*`station`"):
        diagnose(rec, machine=M)


def test_one_station_uses_the_recordings_tracker_columns(two_stations):
    rec = read_recording(two_stations, M)
    one = rec.select(rec.stations() == "S2")
    d = diagnose(one, machine=M)
    assert d.noise.kind.startswith("AT960")
    assert np.allclose(d.noise.tracker, LEFT)
    assert 0.8 < d.base_sigma_ratio < 1.25  # clean campaign weighted by the right covariance


def test_cli_station_option(two_stations, capsys):
    assert main(["diagnose", str(two_stations), "--json", "-q"]) == 0  # both stations in one fit
    assert '"AT960 (given trackers, per station)"' in capsys.readouterr().out
    assert main(["diagnose", str(two_stations), "--tracker", "0,-1500,0"]) == 2
    assert "one --tracker position cannot weigh them" in capsys.readouterr().err
    assert main(["diagnose", str(two_stations), "--station", "S9"]) == 2
    assert "no readings of station 'S9' (stations: S1, S2)" in capsys.readouterr().err
    assert main(["diagnose", str(two_stations), "--station", "S1", "--json", "-q"]) == 0
