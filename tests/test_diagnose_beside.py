"""A name beside a located mismatch (selection.beside_a_mismatch): a name is kept only where it leads, as the
explanation of the readings it moves, the free form of the mean shifts still located among them, by the ties'
evidence ratio.  Campaigns of benchmarks/gen3 (a generator written from the physics, not from mtcal/diagnose) on
its development seed 1010, and mtcal's simulator for the backlash that must stay named."""
from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from mtcal.diagnose import diagnose
from mtcal.measurement.recordings import read_recording


def _gen3():
    spec = importlib.util.spec_from_file_location(
        "gen3", Path(__file__).resolve().parents[1] / "benchmarks" / "gen3" / "gen3.py")
    gen3 = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen3)
    return gen3


@pytest.mark.slow
def test_a_trackers_cyclic_distance_error_is_located_not_named_a_quadratic_and_a_knock(tmp_path):
    """gen3 1010/9: an AT960-like tracker's distance meter with a cyclic error of 2.0 um (every reading moved along
    its beam, a period of 29 mm of distance), on a five-axis campaign with the tracker given.  First "second_order
    C" and a "nest_knock" were named (each significant), beside C's nests located displaced position by position;
    then both were withdrawn, the quadratic beside those located shifts (lead -30, below 9.2), and the mismatch
    was located on C and B.  Now it is one entry where it is: the tracker reading its distance off as a function
    of it (effects.instrument_map), nothing named and nothing located on an axis beside it."""
    _gen3().write_campaign(1010, 9, str(tmp_path), 0.0, "all", ["adm_cyclic"])
    d = diagnose(read_recording(tmp_path / "campaign_0009.csv"))
    assert not [f.name for f in d.effects if f.significant], [(f.name, f.axis) for f in d.effects if f.significant]
    assert [(u.axis, u.by) for u in d.unexplained] == [(None, "tracker distance")], \
        [(u.axis, u.by, u.where) for u in d.unexplained]
