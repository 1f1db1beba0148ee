"""A recording written to CSV and read back keeps its positions: positions are commanded values, and a rounding
of them (0.43 um at 71.4286 mm with 6 significant digits) is a misfit the diagnosis sees as a periodic error."""
from __future__ import annotations

import campaigns as C
import numpy as np

from mtcal.diagnose import diagnose
from mtcal.measurement.recordings import read_recording, write_recording


def test_positions_survive_the_csv(tmp_path):
    c = C.make(C.Design(rounds=3, axes=("X", "Y", "Z"), counts=(8, 8, 8)), (), 502)  # X every 500/7 mm
    write_recording(c.recording, tmp_path / "r.csv")
    back = read_recording(tmp_path / "r.csv")
    assert np.max(np.abs(back.position - c.recording.position)) < 1e-9
    assert np.max(np.abs(back.xyz - c.recording.xyz)) <= 5e-7   # readings: 6 decimals of mm (write_recording)


def test_no_false_periodic_after_the_csv(tmp_path):
    # the case that showed it: a nest creep campaign, positions every 500/7 mm, read back from its CSV
    c = C.nest_creep(502)
    write_recording(c.recording, tmp_path / "r.csv")
    d = diagnose(read_recording(tmp_path / "r.csv"), machine="dmu50", tracker=c.tracker)
    assert not [f.name for f in d.effects if f.significant and f.name == "periodic"]
