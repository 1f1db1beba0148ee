"""The planted-campaign generator (tests/campaigns.py): seeded, varied designs, the issue's cases planted through
the physical simulator with the truth, each effect well above the tracker noise."""
from __future__ import annotations

import campaigns as C
import numpy as np
import pytest

from mtcal.measurement import tracker as trk


def test_seeded_and_varied():
    a, b, c = C.clean(3), C.clean(3), C.clean(4)
    assert np.array_equal(a.recording.xyz, b.recording.xyz) and a.design == b.design
    assert a.design != c.design
    designs = [C.clean(s).design for s in range(30)]
    assert {d.station for d in designs} == {"front", "side", "far"}
    assert {d.rounds for d in designs} == {3, 4, 5, 6}
    assert {len(d.axes) for d in designs} == {3, 5} and {d.tracker_given for d in designs} == {True, False}
    assert all(5 <= n <= 9 for d in designs for n in d.counts)


def test_planted_campaigns_carry_their_truth():
    for s in range(12):
        c = C.planted(s)
        names = [e["name"] for e in c.truth["effects"]]
        assert 1 <= len(names) <= 2 and names == [e["name"] for e in c.expect]
        for e in c.expect:
            if "axis" in e:
                assert e["axis"] in set(c.recording.axis)
        assert (c.tracker is None) == (not c.design.tracker_given)


@pytest.mark.parametrize("name", sorted(C.CASES))
def test_cases_are_planted_well_above_the_noise(name):
    c = C.CASES[name](11)
    assert [e["name"] for e in c.truth["effects"]] and c.expect
    # the same campaign and seed without the planted effects: the noise draws are the same, so the difference is
    # the effect (plus the change of the noise covariance with the moved points, < 1e-3 of it)
    base = C.make(c.design, (), 11, model=c.truth and c.model, positions={
        a: np.asarray(v["positions"]) for a, v in c.truth["axes"].items()})
    assert len(base.recording) == len(c.recording)
    d = c.recording.xyz - base.recording.xyz
    # signal to noise of the whole effect: sqrt(sum d^T C^-1 d) with C the AT960 covariance of each reading
    # (mtcal.measurement.tracker); > 10 means that a test of this one pattern would find it at z > 10
    cov = trk.covariance(base.recording.xyz, c.tracker_true)
    snr = np.sqrt(np.einsum("ni,ni->", d, np.linalg.solve(cov, d[..., None])[..., 0]))
    assert snr > 10, (name, snr)


def test_case_details():
    al = C.CASES["aliased_pitch"](0)
    x = np.unique(al.recording.position[al.recording.axis == "X"])
    step = np.diff(x).min()
    assert step == 25.0 and al.truth["effects"][0]["params"]["pitch"] == 30.0
    assert 1 / abs(1 / 30.0 - 1 / step) == pytest.approx(al.expect[0]["alias_pitch"])  # 150 mm
    cr = C.CASES["nest_creep"](0)
    assert 1.45 < cr.duration_s / 3600 < 1.55
    assert cr.truth["effects"][0]["rate_um_h"] == pytest.approx(10.0)
    assert cr.truth["effects"][0]["displacement_mm"] == pytest.approx(0.015, abs=0.0006)  # 10 um/h x 1.5 h
    kn = C.CASES["knock_at_c_start"](0)
    t0, rec = kn.expect[0]["t_from_s"], kn.recording
    assert rec.time_s[rec.axis != "C"].max() < t0 < rec.time_s[rec.axis == "C"].min()
    both = C.CASES["c_location_and_knock"](0)
    t = both.expect[1]["t_from_s"]
    b = both.recording.time_s[both.recording.axis == "B"]
    assert b.min() < t < b.max() < both.recording.time_s[both.recording.axis == "C"].min()
    assert both.model is not None and "E_X0C" in both.model.constants  # the reference model is given
    wu = C.CASES["warm_up"](0)
    assert np.ptp(wu.recording.temperature_c) > 1.5  # a temperature channel that rises with the warm-up
    assert C.without_tracker(wu).tracker is None and wu.tracker is not None
