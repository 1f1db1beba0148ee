"""A column warming unevenly tilts the spindle side with time (benchmarks/gen3's column_tilt: every tool-side
reading turned theta f(t) about a horizontal axis through a pivot 0.6-1.2 m below the work zone; outside the
grammar, which has a side's drift and its expansion but no turn of a side in time).  At first order it is a drift
of the spindle side (the pivot's lever) and a turn that grows with the position of the axes while they are measured.

Before (main at 5ca5072) it was named a tool side expanding about a centre fitted 3-15 m from the reflectors, the
expansion itself not determined (18.7 +- 14 ppm; 1.5 +- 4.9 ppm/h), and, beside it, the tracker re-levelled: the
expansion about a far centre is the side's translation (its ``nested`` member, effects.side_expansion), and it
was tested for a misfit growing with an axis' position only as a translation
(selection._drift_grows_with_position).  gen3 1015/41, 1016/82: development cases."""
from __future__ import annotations

import numpy as np
import pytest
from test_diagnose_beside import _gen3

from mtcal.diagnose import diagnose
from mtcal.measurement.recordings import read_recording


@pytest.mark.slow  # a diagnosis each, 4 s
@pytest.mark.parametrize("seed, index", [(1015, 41), (1016, 82)])
def test_a_column_tilting_with_time_is_a_spindle_drift_not_an_expansion_about_a_far_centre(tmp_path, seed, index):
    """1015/41: +74 urad by the end, linear, pivot 642 mm below (one station, not given); 1016/82: -61 urad, a lag.
    Only a drift of the spindle side may be named (gen3 accepts it), its turn located on an axis or not seen."""
    truth = _gen3().write_campaign(seed, index, str(tmp_path), 0.3, "all", ["column_tilt"])
    assert [c["name"] for c in truth["classes"]] == ["column_tilt"]
    d = diagnose(read_recording(tmp_path / f"campaign_{index:04d}.csv"))
    named = [(f.name, f.get("target")) for f in d.effects if f.significant]
    assert named == [("thermal_drift", "spindle")], named


def test_an_expansion_about_a_fitted_centre_holds_its_sides_drift_as_its_nested_member():
    """With a centre fitted and a lag, the expansion's columns contain the side's drift with that law exactly (the
    drift's three columns lie in their span to rounding): the member _simplest tries first."""
    import campaigns as C

    from mtcal import load_machine
    from mtcal.diagnose import effects as fx
    from mtcal.diagnose.candidates import layout_offsets
    from mtcal.diagnose.prepare import TIE_POSITIONS, prepare
    from mtcal.diagnose.run import MAX_DEGREE
    from mtcal.measurement.tracker import AT960

    c = C.make(C.Design(rounds=2, axes=("X", "Y")), [], 3)
    prep = prepare(c.recording, load_machine("dmu50"), None, c.tracker, MAX_DEGREE, TIE_POSITIONS, AT960)
    g = prep.geometry
    t0 = float(prep.rec.time_s[g.side == "tool"].min())
    grown = fx.side_expansion(g, layout_offsets(prep), "tool", t0, 3600.0, centre=True)
    assert fx.side_expansion(g, layout_offsets(prep), "tool", t0, None, centre=True).nested is None  # a ramp: none
    assert fx.side_expansion(g, layout_offsets(prep), "tool", t0, 3600.0).nested is None  # about the centroid
    inner = grown.nested
    assert (inner.name, inner.extra["target"], inner.extra["tau_s"]) == ("thermal_drift", "spindle", 3600.0)
    A, B = grown.G.reshape(-1, grown.G.shape[2]), inner.G.reshape(-1, 3)
    coef, *_ = np.linalg.lstsq(A, B, rcond=None)
    assert np.linalg.norm(A @ coef - B) < 1e-9 * np.linalg.norm(B)
    assert grown.refine(5000.0).nested.extra["tau_s"] == 5000.0  # refined, the nested member follows
