"""A nest displaced in the last sequence it is read in runs to the end of the recording (issue 52 item 1): no later
reading shows whether it came back (a bump, a round's offset) or stayed (a knock of the nest, or of the tracker
when no other nest is read after it), and these are the same columns, so none is named and the mismatch is located
at that nest (mtcal.diagnose.selection._to_its_end).  A knock with readings after it is still named.

Oracle: what is planted, in mm, on mtcal's simulator's campaigns (tests/campaigns.py); the displacement is written
on the recording here."""
from __future__ import annotations

from dataclasses import replace

import campaigns as C
import numpy as np
import pytest

from mtcal.diagnose import diagnose

pytestmark = pytest.mark.slow  # one or two diagnoses each: 5-15 s

STEPS = {"offset", "outlier", "nest_knock"}  # the members that displace a nest for a while or from t0 on
DESIGN = C.Design(rounds=4, axes=("X", "Y", "Z"))


def _last_sequence(rec, point: str) -> np.ndarray:
    """(n,) bool: the readings of ``point`` in the last (axis, round) it is read in."""
    on = rec.point == point
    last = np.flatnonzero(on)[np.argmax(rec.time_s[on])]
    return on & (rec.axis == rec.axis[last]) & (rec.round == rec.round[last])


@pytest.mark.parametrize("seed", [3, 4])
def test_a_nest_displaced_to_the_end_of_the_recording_is_located_not_named(seed):
    c = C.make(DESIGN, (), seed)
    rec = c.recording
    point = str(rec.point[-1])
    seq = _last_sequence(rec, point)
    t = rec.time_s[seq]
    moved = seq & (rec.time_s >= np.median(t))  # from the middle of its last sequence to its last reading
    xyz = rec.xyz.copy()
    xyz[moved] += [0.025, -0.012, 0.004]  # mm: 28 um, 20x the noise
    d = diagnose(replace(rec, xyz=xyz), tracker=c.tracker)
    named = [(f.name, f.get("where")) for f in d.effects if f.significant]
    assert not [n for n in named if n[0] in STEPS], named
    at = [x for x in d.unexplained + d.located if point in str(x.where) and x.axis == str(rec.axis[seq][0])]
    assert at, [(x.axis, x.by, x.where) for x in d.unexplained + d.located]


def test_a_knock_alone_is_named():
    """The rule's other side: the tracker knocked at the middle of the campaign, with readings of every nest after
    it, is still named a knock, within 3 um."""
    c = C.make(DESIGN, (), 1)
    rec = c.recording
    t0 = float(np.median(rec.time_s))
    xyz = rec.xyz.copy()
    xyz[rec.time_s >= t0] += [0.012, 0.0, 0.0]
    d = diagnose(replace(rec, xyz=xyz), tracker=c.tracker)
    knocks = [f for f in d.effects if f.significant and f.get("variant") == "tracker knock"]
    assert len(knocks) == 1, [(f.name, f.get("where")) for f in d.effects if f.significant]
    assert abs(1e3 * knocks[0].estimate - 12.0) < 3.0, knocks[0].estimate
