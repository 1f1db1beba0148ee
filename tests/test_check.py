"""Check tests (issue 25): predicted ISO 230-4 circular tests and ISO 10791-6 R-test sweeps against textbook
closed forms and the standard's definitions computed here independently, measured checks of a simulated true
machine evaluated against an identified model, and verification after compensation.

Oracles, written in this file and not taken from mtcal.check:
- first-order ballbar signatures (e.g. Kakino et al., "Accuracy inspection of NC machine tools by double ball bar
  method", 1993; Renishaw ballbar diagnostics): a squareness E_C0Y in XY, with the design contract's convention
  (actual Y = (-E_C0Y, 1, 0)), gives deltaR = -R E_C0Y sin(theta) cos(theta) and G = R |E_C0Y|; a linear scale
  error s_x, s_y gives deltaR = R (s_x cos^2 + s_y sin^2) and G = R |s_x - s_y|;
- ISO 230-4:2005 definitions: G the radial range about the least-squares circle (here fitted to the Cartesian
  points by Kasa's algebraic method, not linearised), H the largest radial difference of the two directions at
  one angle, F the largest and smallest deviation about the nominal centre;
- an R-test sweep of C about an axis displaced by E_X0C = d: the sphere turns about the actual line, so it moves by
  (I - Rz(-C)) (d, 0, 0) = d (1 - cos C, sin C, 0) (the DMU 50's table chain T_0^w = ... Rz(-C), docs/design.md).
"""
from __future__ import annotations

import json

import numpy as np
import pytest

import mtcal
from mtcal.check import (
    CircleSetup,
    RTestSetup,
    evaluate_check,
    predict_circular,
    predict_circular_compensated,
    predict_rtest,
    read_check,
    simulate_circular,
    simulate_rtest,
    verify,
)
from mtcal.check.circular import figures
from mtcal.check.signatures import fit_signatures
from mtcal.cli import main
from mtcal.data.make_demo_data import DEMO_PLAN
from mtcal.errors import InputError
from mtcal.model.errormodel import ErrorFunction, ErrorModel

M = mtcal.load_machine("dmu50")
PLAN = DEMO_PLAN  # the demo's campaign layout (mtcal/data/make_demo_data.py): inside the true tables


def _truth() -> ErrorModel:
    from mtcal.data import path
    return mtcal.load_model(path("demo_truth.json"))


def _kasa_G(theta_deg, dr, radius):
    """ISO 230-4 G from the Cartesian path: the LSQ circle by Kasa's algebraic fit, G = max - min of the radial
    distances from its centre (independent of the linearised fit in mtcal.check.circular)."""
    th = np.radians(theta_deg)
    x, y = (radius + dr) * np.cos(th), (radius + dr) * np.sin(th)
    A = np.column_stack([x, y, np.ones_like(x)])
    D, E, F = np.linalg.lstsq(A, -(x**2 + y**2), rcond=None)[0]
    r = np.hypot(x + D / 2, y + E / 2)
    return r.max() - r.min()


# ----------------------------------------------------------------------------- textbook signatures
def test_squareness_gives_the_textbook_oval_and_G():
    e, R = 30e-6, 150.0
    p = predict_circular(ErrorModel("dmu50", {"E_C0Y": e}), CircleSetup("XY", R, (0.0, 0.0, 0.0)))
    th = np.radians(p.theta_deg)
    np.testing.assert_allclose(p.dr, -R * e * np.sin(th) * np.cos(th), atol=1e-12)
    assert p.figures["G_mm"] == pytest.approx(R * e, rel=1e-9)
    assert p.figures["G_mm"] == pytest.approx(_kasa_G(p.theta_deg, p.dr, R), abs=1e-8)
    assert p.figures["H_mm"] == pytest.approx(0.0, abs=1e-15)  # quasi-static: the same both ways
    assert list(p.contributions) == ["E_C0Y"] and p.contributions["E_C0Y"] == pytest.approx(R * e, rel=1e-9)


def test_scale_mismatch_gives_the_textbook_oval():
    sx, sy, R = 20e-6, -5e-6, 120.0
    x = np.linspace(-500.0, 500.0, 11)
    model = ErrorModel("dmu50", {}, {"E_XX": ErrorFunction("X", x, sx * x), "E_YY": ErrorFunction("Y", x, sy * x)})
    p = predict_circular(model, CircleSetup("XY", R, (0.0, 0.0, 0.0), direction="ccw"))
    th = np.radians(p.theta_deg)
    np.testing.assert_allclose(p.dr, R * (sx * np.cos(th) ** 2 + sy * np.sin(th) ** 2), atol=1e-12)
    assert p.figures["G_mm"] == pytest.approx(R * abs(sx - sy), rel=1e-9)
    assert p.figures["F_max_mm"] == pytest.approx(R * sx, rel=1e-9)
    assert p.figures["F_min_mm"] == pytest.approx(R * sy, rel=1e-9)


def test_figures_follow_the_standard_definitions():
    """H, G(b), F from the definitions on two synthetic paths (a step between the directions, an offset centre)."""
    th = np.arange(0.0, 360.0, 2.0)
    rng = np.random.default_rng(1)
    ccw = 2e-3 * np.cos(np.radians(th)) + 1e-4 * rng.standard_normal(len(th))
    cw = ccw + np.where((th > 90) & (th < 180), 7e-4, 0.0)
    f = figures(np.concatenate([th, th[::-1]]), np.concatenate([ccw, cw[::-1]]),
                np.concatenate([np.ones(len(th)), -np.ones(len(th))]))
    assert f["H_mm"] == pytest.approx(np.abs(cw - ccw).max(), rel=1e-12)
    assert f["G_ccw_mm"] == pytest.approx(_kasa_G(th, ccw, 100.0), abs=1e-7)
    assert f["G_cw_mm"] == pytest.approx(_kasa_G(th, cw, 100.0), abs=1e-7)
    both = np.concatenate([ccw, cw])
    assert f["G_mm"] == pytest.approx(_kasa_G(np.concatenate([th, th]), both, 100.0), abs=1e-7)
    assert f["F_max_mm"] == both.max() and f["F_min_mm"] == both.min()


def test_backlash_makes_half_steps_at_the_reversals_and_is_found():
    b, R = 0.004, 100.0
    s = CircleSetup("XY", R, (0.0, 0.0, 0.0), points=720)
    meas = simulate_circular(ErrorModel("dmu50"), s, backlash={"X": b}, noise_mm=0.0)
    th, dr, d = (meas.data[k] for k in ("angle_deg", "deviation_mm", "direction"))
    ccw = d > 0
    # X reverses at theta = 0 and 180 deg: deltaR = cos(theta) * (+b/2 in the direction of travel)
    near0 = lambda a: dr[ccw][np.argmin(np.abs(((th[ccw] - a + 180) % 360) - 180))]  # noqa: E731
    assert near0(2.0) - near0(-2.0) == pytest.approx(-b, rel=0.01)     # ccw passes 0 deg: X turns from + to -
    assert near0(182.0) - near0(178.0) == pytest.approx(-b, rel=0.01)  # at 180 deg: - to +, cos = -1
    found, noise = fit_signatures(th, dr, d, "XY", R)
    names = {f.name: f for f in found}
    assert "backlash_X" in names and names["backlash_X"].size == pytest.approx(b, rel=0.02)
    assert "backlash_Y" not in names and "servo_mismatch" not in names


# ----------------------------------------------------------------------------- R-test
def test_rtest_of_a_c_axis_location_error_has_the_closed_form():
    d = 0.010
    C = np.arange(0.0, 360.0, 15.0)
    p = predict_rtest(ErrorModel("dmu50", {"E_X0C": d}), RTestSetup("C", tuple(C), (120.0, 40.0, 30.0)))
    c = np.radians(C)
    np.testing.assert_allclose(p.deviation, np.column_stack([d * (1 - np.cos(c)), d * np.sin(c), 0 * c]), atol=1e-12)
    assert p.ranges["X"] == pytest.approx(2 * d, rel=1e-12) and p.ranges["Y"] == pytest.approx(2 * d, rel=1e-3)


def test_rtest_nominal_is_zero_and_exact_agrees_with_first_order():
    truth = _truth()
    s = RTestSetup("B", tuple(np.arange(0.0, 181.0, 15.0)), (80.0, -50.0, 60.0), {"C": 30.0}, 50.0)
    zero = simulate_rtest(ErrorModel("dmu50"), s, noise_mm=0.0)
    assert max(np.abs(zero.data[k]).max() for k in ("dx_mm", "dy_mm", "dz_mm")) < 1e-9  # the tool on the sphere
    exact = simulate_rtest(truth, s, noise_mm=0.0)
    pred = predict_rtest(truth, s)
    meas = np.column_stack([exact.data[k] for k in ("dx_mm", "dy_mm", "dz_mm")])
    assert np.abs(meas - pred.deviation).max() < 0.01 * np.abs(pred.deviation).max()


def test_first_order_prediction_agrees_with_the_exact_simulator():
    truth = _truth()
    for plane, centre in (("XY", (0.0, 0.0, 0.0)), ("YZ", (50.0, -30.0, 20.0)), ("ZX", (0.0, 0.0, 0.0))):
        s = CircleSetup(plane, 150.0, centre, fixed={"B": 20.0, "C": 45.0})
        p = predict_circular(truth, s)
        meas = simulate_circular(truth, s, noise_mm=0.0)
        assert np.abs(meas.data["deviation_mm"] - p.dr).max() < 0.01 * p.figures["G_mm"], plane
        assert sum(p.contributions.values()) >= p.figures["G_mm"] * 0.999  # G is subadditive over the shares


def test_compensation_removes_the_predicted_circular_error():
    truth = _truth()
    s = CircleSetup("XY", 150.0, (0.0, 0.0, 0.0))
    before, after = predict_circular(truth, s), predict_circular_compensated(truth, s)
    assert before.figures["G_mm"] > 0.003 and after.figures["G_mm"] < 1e-3 * before.figures["G_mm"]


# ----------------------------------------------------------------------------- measured checks of a true machine
@pytest.fixture(scope="module")
def identified():
    """A model identified from a simulated campaign of the demo's true machine (AT960 noise, tracker known)."""
    truth = _truth()
    rec, _ = mtcal.simulate(truth, plan=PLAN, rounds=None, seed=11)
    return truth, mtcal.identify(rec, tracker=PLAN["tracker"]).model


def test_a_clean_measured_test_agrees_with_the_identified_model(identified):
    truth, model = identified
    agree = 0
    for seed in range(6):
        s = CircleSetup(("XY", "YZ", "ZX")[seed % 3], 150.0, (0.0, 0.0, 0.0))
        ev = evaluate_check(simulate_circular(truth, s, seed=seed), model)
        assert ev.prediction_u95_mm > 0 and ev.predicted["G_mm"] > 0
        agree += ev.agrees
        assert not any(f.name == "servo_mismatch" for f in ev.findings)
    assert agree >= 5, agree


def test_backlash_and_servo_mismatch_are_named_in_the_residual(identified):
    truth, model = identified
    s = CircleSetup("XY", 150.0, (0.0, 0.0, 0.0), points=720)
    meas = simulate_circular(truth, s, backlash={"X": 0.003}, servo_lag_s={"X": 0.0100, "Y": 0.0101},
                             feed_mm_min=2000.0, seed=3)
    ev = evaluate_check(meas, model)
    names = {f.name: f for f in ev.findings}
    assert names["backlash_X"].size == pytest.approx(0.003, rel=0.1) and names["backlash_X"].quasi_static
    servo = names["servo_mismatch"]
    assert not servo.quasi_static and "outside the quasi-static model" in servo.text
    v = 2000.0 / 60.0  # mm/s; radial part of the lag mismatch: R w (tau_Y - tau_X) / 2 sin 2theta
    assert servo.size_mm == pytest.approx(v * 0.0001, rel=0.1)


# ----------------------------------------------------------------------------- verification
def _remaining(truth: ErrorModel, model: ErrorModel, factor: float) -> ErrorModel:
    """The true machine after a compensation that applied ``factor`` times the model's correction."""
    consts = {k: truth.constants.get(k, 0.0) - factor * model.constants.get(k, 0.0)
              for k in set(truth.constants) | set(model.constants)}
    funcs = {}
    for n, f in truth.functions.items():
        g = model.functions.get(n)
        funcs[n] = ErrorFunction(f.axis, f.positions, f(f.positions, "hold") - (
            factor * g(f.positions, "hold") if g is not None else 0.0))
    return ErrorModel(truth.machine, consts, funcs)


@pytest.mark.slow
def test_verify_passes_a_good_compensation_and_names_what_went_wrong(identified):
    """The true machine after a compensation with the identified model: applied (passes), not applied (share ~1),
    applied with the wrong sign (share ~2), each a fresh simulated campaign."""
    truth, model = identified
    verdicts = {}
    for factor, seed in ((1.0, 21), (0.0, 22), (-1.0, 23)):
        rec, _ = mtcal.simulate(_remaining(truth, model, factor), plan=PLAN, rounds=None, seed=seed)
        verdicts[factor] = verify(rec, model, tracker=PLAN["tracker"])
    assert verdicts[1.0].passed and all(e.within for e in verdicts[1.0].errors)
    for factor, share, words in ((0.0, 1.0, "not applied"), (-1.0, 2.0, "wrong sign")):
        v = verdicts[factor]
        worst = v.errors[0]  # the largest z: E_YY, the largest error of the demo's machine
        assert not v.passed and worst.name == "E_YY" and not worst.within
        assert worst.share == pytest.approx(share, abs=0.1) and words in worst.text


# ----------------------------------------------------------------------------- CLI contract and files
def test_cli_predict_contract(tmp_path, capsys):
    from mtcal.data import path
    assert main(["check", "predict", "--model", str(path("demo_truth.json")), "--circular", "XY,100,0,0,0",
                 "--direction", "both", "--json", "--plot", str(tmp_path / "p.png")]) == 0
    out = json.loads(capsys.readouterr().out)
    t = out["tests"][0]
    assert {"kind", "plane", "radius_mm", "centre_mm", "G_mm", "H_mm", "F_mm", "trace", "contributions"} <= set(t)
    assert t["kind"] == "circular" and t["plane"] == "XY" and t["centre_mm"] == [0, 0, 0]
    tr = np.array(t["trace"])
    assert tr.shape == (720, 3) and set(tr[:, 2]) == {1.0, -1.0}
    assert (tmp_path / "p.png").stat().st_size > 10000
    assert max(t["contributions"].values()) <= t["G_mm"] * 1.0001 or len(t["contributions"]) > 1


def test_cli_evaluate_reads_a_measured_file(tmp_path, capsys):
    from mtcal.data import path
    truth = _truth()
    meas = simulate_circular(truth, CircleSetup("XY", 100.0, (0.0, 0.0, 0.0)), backlash={"Y": 0.004}, seed=5)
    f = tmp_path / "ballbar.csv"
    rows = "\n".join(f"{a:.3f},{r:.7f},{int(d)}" for a, r, d in zip(*(meas.data[k] for k in
                                                                       ("angle_deg", "deviation_mm", "direction"))))
    f.write_text("# plane: XY\n# radius_mm: 100\n# centre_mm: 0,0,0\nangle_deg,deviation_mm,direction\n" + rows + "\n")
    assert read_check(f).info["radius_mm"] == 100.0
    assert main(["check", "evaluate", str(f), "--model", str(path("demo_truth.json")), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert [x["signature"] for x in out["findings"]][0] == "backlash_Y"
    bad = tmp_path / "bad.csv"
    bad.write_text("# plane: XY\n# radius_mm: 100\nangle_deg,deviation_mm,direction\n0,0.001,1\n1,x,1\n2,0,1\n")
    assert main(["check", "evaluate", str(bad), "--model", str(path("demo_truth.json"))]) == 2
    assert "bad.csv, line 5: deviation_mm must be a number" in capsys.readouterr().err


def test_bad_setups_are_refused():
    with pytest.raises(InputError, match="plane 'XB'"):
        predict_circular(ErrorModel("dmu50"), CircleSetup("XB", 100.0))
    with pytest.raises(InputError, match="radius must be a positive"):
        predict_circular(ErrorModel("dmu50"), CircleSetup("XY", -1.0))
    with pytest.raises(InputError, match="R-test sweeps a rotary axis"):
        predict_rtest(ErrorModel("dmu50"), RTestSetup("X", (0.0, 1.0, 2.0)))
