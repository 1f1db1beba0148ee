"""One rule once (issue 23): passes and reference readings (mtcal.measurement.passes) used alike by the
three-point method, the joint fit, ISO 230-2 and the diagnosis; typed fits (mtcal.model.fits) that read and
write the model JSON unchanged and evaluate as the batched evaluator does."""
from __future__ import annotations

import json

import numpy as np
import pytest

from mtcal.data import path
from mtcal.diagnose.prepare import _reference_readings
from mtcal.errors import InputError
from mtcal.identify.threepoint import _passes
from mtcal.iso230_2.evaluation import _datum
from mtcal.kinematics.machine import load_machine
from mtcal.measurement.passes import first_readings, group_passes, position_key, reading_order, reference_position
from mtcal.measurement.recordings import make_recording
from mtcal.model.errormodel import ErrorEvaluator, ErrorFunction, ErrorModel, load_model, model_from_dict
from mtcal.model.fits import Harmonic, Polynomial, fit_from_dict


def _rec(shuffle: bool):
    """X at 0, 50, 100 (out and back, 2 rounds, points P Q K); the file lists the rows in reverse time order when
    ``shuffle``, so only time_s says which reading came first."""
    rows = []
    t = 0.0
    for r in (1, 2):
        for q, d in ((0.0, 1), (50.0, 1), (100.0, 1), (100.0, -1), (50.0, -1), (0.0, -1)):
            for k, pt in enumerate("PQK"):
                t += 2.0
                rows.append((r, q + 1e-9 * k, pt, d, t))  # positions equal to 1e-9: one position
    if shuffle:
        rows = rows[::-1]
    xyz = np.array([[q, 10.0 * i, 5.0] for i, (_, q, _, _, _) in enumerate(rows)])
    return make_recording(["X"] * len(rows), [r[0] for r in rows], [r[1] for r in rows], [r[2] for r in rows], xyz,
                          time_s=[r[4] for r in rows], direction=[r[3] for r in rows])


def test_position_key_and_reading_order():
    assert position_key([0.0, 1e-9, 50.0000004]).tolist() == [0.0, 0.0, 50.0]
    assert reference_position(np.array([-50.0, 1e-8, 50.0])) == 0.0
    rec = _rec(True)
    rows = np.arange(len(rec))
    assert np.array_equal(reading_order(rec, rows), rec.time_s)  # every row has a time: time decides
    no_time = make_recording(["X"] * 2, [1, 1], [0.0, 50.0], ["P", "P"], np.zeros((2, 3)))
    assert np.array_equal(reading_order(no_time, np.arange(2)), no_time.line.astype(float))


def test_the_reference_reading_is_the_first_in_time_in_every_user():
    """Rows listed in reverse time order: every user takes the first reading *in time* at the position closest to
    zero (round 1's outbound P, Q, K), whatever the file order."""
    rec = _rec(True)
    idx = np.arange(len(rec))
    first = first_readings(rec, idx, 0.0, reading_order(rec, idx), by=("round", "point"))
    want = {k: i for k, i in first.items() if k[0] == 1}
    assert all(rec.time_s[i] <= 6.0 for i in want.values())
    ps = _passes(rec, "X")  # three-point
    assert {int(i) for i in ps["ref_rows"][ps["round"] == 1].ravel()} == set(want.values())
    q0, datum = _datum(rec, idx, reading_order(rec, idx), "X")  # ISO 230-2: one datum for every run
    assert q0 == 0.0 and set(datum.values()) == set(want.values())
    for pt in "PQK":  # diagnosis: per (axis, point), one per round
        sel = idx[rec.point == pt]
        refs = _reference_readings(rec, sel, 0.0, reading_order(rec, idx))
        assert refs[0] == want[(1, pt)]


def test_a_point_read_twice_in_one_pass_is_refused_naming_both_lines():
    rec = _rec(False)
    dup = make_recording(["X"] * 2, [1, 1], [0.0, 0.0], ["P", "P"], np.zeros((2, 3)), direction=[1, 1])
    with pytest.raises(InputError, match=r"point P read twice \(first at line 2\).*not averaged silently"):
        group_passes(dup, [0, 1], [1, 1], "X")
    assert len(group_passes(rec, np.arange(len(rec)), rec.direction, "X")) == 12  # 2 rounds x 6 stops


def test_model_json_round_trip_is_byte_identical(tmp_path):
    """The bundled truth (harmonic fits of C) read into typed fits and written back: the same bytes."""
    from mtcal.model.errormodel import save_model

    src = path("demo_truth.json")
    save_model(load_model(src), tmp_path / "m.json")
    assert json.loads((tmp_path / "m.json").read_text()) == json.loads(src.read_text())
    fits = [f.fit for f in load_model(src).functions.values() if f.fit is not None]
    assert fits and all(isinstance(f, (Polynomial, Harmonic)) for f in fits)


def test_typed_fits_evaluate_as_their_formula_and_as_the_batched_evaluator():
    h = fit_from_dict({"kind": "harmonic", "period": 360, "a0": 1e-3, "cos": [2e-3, -1e-3], "sin": [5e-4, 0.0],
                       "harmonics": 2})
    x = np.linspace(0.0, 360.0, 37)
    w = np.deg2rad(x)
    closed = 1e-3 + 2e-3 * np.cos(w) + 5e-4 * np.sin(w) - 1e-3 * np.cos(2 * w)
    np.testing.assert_allclose(h(x), closed, rtol=0, atol=1e-15)
    assert h.harmonics == 2 and h.to_dict()["harmonics"] == 2 and h.to_dict()["period"] == 360
    p = fit_from_dict({"kind": "polynomial", "coefficients": [0.0, 1e-3, 2e-3], "domain": [-250.0, 250.0]})
    u = np.linspace(-250, 250, 11) / 250.0
    np.testing.assert_allclose(p(u * 250.0), 1e-3 * u + 2e-3 * u**2, rtol=0, atol=1e-15)
    m = load_machine("dmu50")
    model = ErrorModel("dmu50", functions={"E_CC": ErrorFunction("C", x, np.zeros_like(x), h),
                                           "E_XX": ErrorFunction("X", u * 250.0, np.zeros_like(u), p)})
    q = np.zeros((37, len(m.axes)))
    q[:, m.index("C")], q[:, m.index("X")] = x, np.linspace(-250, 250, 37)
    e = ErrorEvaluator(model, m)(q)
    np.testing.assert_allclose(e[:, m.error_names.index("E_CC")], h(x), rtol=0, atol=1e-15)
    np.testing.assert_allclose(e[:, m.error_names.index("E_XX")], p(q[:, m.index("X")]), rtol=0, atol=1e-15)
    assert model_from_dict(model.to_dict(), "<m>").functions["E_CC"].fit == h
