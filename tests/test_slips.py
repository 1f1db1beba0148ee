"""Unit and frame slips refused before every estimator (issue 35): identify's default path (the joint fit, tracker
estimated or given), --method three-point, and diagnose, each on readings in inch, linear positions in inch with
readings in mm, rotary positions in radians, the x and y columns swapped, and every reading the same point.

The slips are made here from a simulated campaign of the demo's true machine (mtcal/data: errors of tens of um),
so the right reading is known: 25.4 mm an inch (NIST SP 811, B.8), 180/pi deg a radian."""
from __future__ import annotations

import numpy as np
import pytest

import mtcal
from mtcal.cli import main
from mtcal.data import path
from mtcal.diagnose.run import diagnose
from mtcal.errors import InputError
from mtcal.measurement.recordings import format_recording

TRACKER = (250.0, -1500.0, 150.0)
PLAN = {"axes": {"X": {"start": -250, "stop": 250, "count": 6}, "C": {"start": 0, "stop": 300, "count": 6}},
        "tracker": list(TRACKER), "rounds": 3}


@pytest.fixture(scope="module")
def campaign():
    truth = mtcal.load_model(path("demo_truth.json"))
    rec, _ = mtcal.simulate(truth, plan=PLAN, rounds=None, seed=4)
    return rec


def _slipped(rec, slip):
    r = rec.select(np.ones(len(rec), bool))
    lin, rot = r.axis == "X", r.axis == "C"
    if slip == "readings_inch":
        r.xyz = r.xyz / 25.4
    elif slip == "positions_inch":
        r.position = np.where(lin, r.position / 25.4, r.position)
    elif slip == "radians":
        r.position = np.where(rot, np.radians(r.position), r.position)
    elif slip == "xy_swapped":
        r.xyz = r.xyz[:, [1, 0, 2]]
    elif slip == "identical":
        r.xyz = np.tile(r.xyz[:1], (len(r), 1))
    return r


WORDS = {"readings_inch": "readings are in inch", "positions_inch": "positions are in inch",
         "radians": "positions are in radians", "xy_swapped": "x and y columns are swapped",
         "identical": "same point"}
PATHS = {"joint_given": lambda r: mtcal.identify(r, tracker=TRACKER, worth=False),
         "joint_estimated": lambda r: mtcal.identify(r, worth=False),
         "three_point": lambda r: mtcal.identify(r, method="three-point", worth=False),
         "diagnose": lambda r: diagnose(r, tracker=TRACKER)}


@pytest.mark.parametrize("slip", list(WORDS))
@pytest.mark.parametrize("estimator", list(PATHS))
def test_a_slip_is_refused_before_every_estimator(campaign, estimator, slip):
    r = _slipped(campaign, slip)
    with pytest.raises(InputError, match=WORDS[slip]) as e:
        PATHS[estimator](r)
    assert "line" in str(e.value) and r.source in str(e.value)


def test_the_clean_campaign_passes_the_screen(campaign):
    res = mtcal.identify(campaign, worth=False)
    assert res.method == "joint" and abs(res.model.functions["E_XX"].values).max() < 0.05


def test_cli_default_path_refuses_inch_readings_and_writes_nothing(campaign, tmp_path, capsys):
    f = tmp_path / "rec.csv"
    f.write_text(format_recording(_slipped(campaign, "readings_inch")))
    assert main(["identify", str(f), "-o", str(tmp_path / "m.json")]) == 2
    err = capsys.readouterr().err
    assert "rec.csv:" in err and "readings are in inch" in err and "Traceback" not in err
    assert not (tmp_path / "m.json").exists()
