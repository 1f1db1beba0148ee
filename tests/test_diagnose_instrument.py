"""The tracker's own error map (effects.instrument_map): a distance meter or an angle encoder reading off by a
function of its own coordinate, the same in every round, is one located mismatch at the tracker, sized by the
displacement it adds beyond the base -- not a quadratic of a rotary axis, a knock or a scale named beside it.
The errors are planted here from the physics (tests/campaigns.py's simulator and the readings' geometry about the
given tracker), not from the diagnosis' columns; the size beyond the base is computed as in test_diagnose_sizes."""
from __future__ import annotations

import campaigns as C
import numpy as np
import pytest
from test_diagnose_sizes import _planted_beyond_the_base

from mtcal.diagnose import diagnose


def _cyclic(c, kind: str, amplitude: float, period: float) -> np.ndarray:
    """(n, 3) mm: a distance meter's error along each beam (``amplitude`` mm, ``period`` mm of distance), or the
    azimuth encoder's about the tracker's vertical (``amplitude`` rad, ``period`` rad of azimuth)."""
    v = c.recording.xyz - np.array(c.tracker)
    if kind == "distance":
        dist = np.linalg.norm(v, axis=1)
        return (amplitude * np.sin(2 * np.pi * dist / period + 0.4))[:, None] * v / dist[:, None]
    az = np.arctan2(v[:, 1], v[:, 0])
    return (amplitude * np.sin(2 * np.pi * az / period + 0.4))[:, None] * np.c_[-v[:, 1], v[:, 0], 0 * az]


def _diagnosed(kind: str, amplitude: float, period: float, seed: int):
    """The linear axes at twelve positions each, four rounds, the tracker given: the tool's nests at their several
    distances from the tracker see the error map along every axis' travel (on a rotary axis alone, its nests'
    poses explain it as well: the data cannot then say the tracker's, and the scans locate it on that axis)."""
    c = C.make(C.Design(rounds=4, axes=("X", "Y", "Z"), counts=(12, 12, 12)), (), seed)
    delta = _cyclic(c, kind, amplitude, period)
    c.recording.xyz = c.recording.xyz + delta
    d = diagnose(c.recording, tracker=c.tracker)
    return d, _planted_beyond_the_base(d, delta)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("kind, amplitude, period", [("distance", 0.003, 30.0), ("azimuth", 8e-6, np.deg2rad(6.0))])
def test_a_trackers_cyclic_error_is_located_at_the_tracker_and_sized_beyond_the_base(kind, amplitude, period, seed):
    """A distance error of 3 um with a period of 30 mm of distance, or an azimuth encoder's 8 urad every 6 degrees
    of azimuth: before, nothing was claimed for the distance error, and for the encoder a nest's knock was named or
    a shift of one nest located on X; now nothing is named and one entry says the tracker reads its distance (its
    azimuth) off, sized between 0.7x and 1.5x the displacement the base cannot take (the largest over many readings
    of a 35-column fit leans high by about its standard uncertainty: 4.2-4.8 um for 3.6)."""
    d, planted = _diagnosed(kind, amplitude, period, seed)
    named = [(f.name, f.axis) for f in d.effects if f.significant]
    assert not named, named
    at = [u for u in d.to_dict()["unexplained"] if u["by"] == f"tracker {kind}"]
    assert len(at) == 1, d.to_dict()["unexplained"]
    u = at[0]
    assert u["axis"] is None and 0.7 * planted < u["size_mm"] < 1.5 * planted, (u["size_mm"], planted)
    assert 0 < u["size_sd_mm"] < 0.3 * u["size_mm"], (u["size_mm"], u["size_sd_mm"])
