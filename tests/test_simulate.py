"""Virtual laser tracker: exact kinematics, AT960 noise statistics, planted effects, schedule, CLI, bad input."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from mtcal import load_machine
from mtcal.campaign.effects import Effect, parse_effect
from mtcal.campaign.plans import Plan, plan_from_dict, schedule
from mtcal.campaign.simulate import simulate, simulate_campaign
from mtcal.cli import main
from mtcal.errors import InputError
from mtcal.measurement import tracker as trk
from mtcal.measurement.recordings import read_recording
from mtcal.model.errormodel import ErrorFunction, ErrorModel

M = load_machine("dmu50")
_DEFAULT = Plan(M)  # the spec's campaign (derive/machines/dmu50.toml [campaign])
DEFAULT_TOOL_POINTS, DEFAULT_TABLE_POINTS, DEFAULT_TRACKER = (_DEFAULT.tool_points, _DEFAULT.table_points,
                                                              _DEFAULT.tracker)
D = 154.996  # mm, B/C intersection height (dmu50.toml)


def _rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def _nominal_table(b_deg, c_deg, p):
    """Independent nominal table kinematics (docs/design.md): Tz(d) Rx(45) Rz(B) Rx(-45) Tz(-d) Rz(-C) p."""
    r = _rx(math.pi / 4) @ _rz(math.radians(b_deg)) @ _rx(-math.pi / 4)
    q = _rz(-math.radians(c_deg)) @ np.asarray(p)
    return r @ (q - [0, 0, D]) + [0, 0, D]


def _local(rec, i):
    pts = DEFAULT_TOOL_POINTS if rec.axis[i] in "XYZ" else DEFAULT_TABLE_POINTS
    return np.array(pts[rec.point[i]])


@pytest.fixture(scope="module")
def exact():
    return simulate_campaign(noise=False)


def test_zero_model_no_noise_is_nominal_kinematics_exactly(exact):
    assert len(exact) == 3 * 4 * 2 * (11 * 3 + 19 + 18)  # points x rounds x directions x positions = 1680
    for i in range(len(exact)):
        a, q, p = exact.axis[i], exact.position[i], _local(exact, i)
        if a in "XYZ":
            want = p + q * np.eye(3)["XYZ".index(a)]
        else:
            want = _nominal_table(q if a == "B" else 0.0, q if a == "C" else 0.0, p)
        np.testing.assert_allclose(exact.xyz[i], want, rtol=0, atol=1e-9)
    assert np.all(exact.temperature_c == 20.0)


def test_schedule_out_and_back_reference_first_and_times():
    rec = simulate_campaign(noise=False)
    assert np.all(np.diff(rec.time_s) > 0)
    for a, n in (("X", 11), ("Y", 11), ("Z", 11), ("B", 19), ("C", 18)):
        for r in (1, 4):
            for pt in "PQK":
                m = (rec.axis == a) & (rec.round == r) & (rec.point == pt)
                assert m.sum() == 2 * n
                pos, d = rec.position[m], rec.direction[m]
                # first reading = the position closest to zero (the reference), approached in + direction
                assert pos[0] == 0.0 and d[0] == 1
                assert np.array_equal(pos[:n], np.sort(pos[:n])) and np.array_equal(pos[n:], pos[:n][::-1])
                assert set(d[:n]) == {1} and set(d[n:]) == {-1}
    assert rec.position[rec.axis == "X"].max() == 500 and rec.position[rec.axis == "Y"].max() == 450
    assert rec.position[rec.axis == "Z"].max() == 400 and rec.position[rec.axis == "B"].max() == 180
    assert rec.position[rec.axis == "C"].max() == 340
    assert 2.5 * 3600 < rec.time_s.max() < 5 * 3600  # a realistic half day on the machine


def test_noise_has_the_at960_covariance():
    """Whitened noise (L^-1 e with C = L L^T from mtcal.measurement.tracker) must be N(0, I): 20 rounds -> n = 8400
    points.

    Sample covariance entries of N(0, I) have sd 1/sqrt(n) (off-diagonal) and sqrt(2/n) (diagonal): 5 sd bounds.
    The sum of squares is chi^2(3n): mean 3n, sd sqrt(6n)."""
    kw = dict(rounds=20, seed=7)
    rec, exact = simulate_campaign(**kw), simulate_campaign(noise=False, **kw)
    e = rec.xyz - exact.xyz
    cov = trk.covariance(exact.xyz, DEFAULT_TRACKER)
    w = np.linalg.solve(np.linalg.cholesky(cov), e[..., None])[..., 0]
    n = len(w)
    s = w.T @ w / n
    off = s[~np.eye(3, dtype=bool)]
    assert np.all(np.abs(off) < 5 / math.sqrt(n))
    assert np.all(np.abs(np.diag(s) - 1) < 5 * math.sqrt(2 / n))
    chi2 = float((w ** 2).sum())
    assert abs(chi2 - 3 * n) < 5 * math.sqrt(6 * n)
    # placement matters: along the beam (Pos. 1 looks along +Y) the noise is ~30x smaller than across it
    u = exact.xyz - DEFAULT_TRACKER
    u /= np.linalg.norm(u, axis=1)[:, None]
    radial = np.einsum("ij,ij->i", e, u)
    across = e - radial[:, None] * u
    assert np.std(radial) < 0.002 and 0.008 < np.sqrt((across ** 2).sum(1).mean() / 2) < 0.020  # mm
    s_r, s_t = trk.AT960.sigmas(np.linalg.norm(exact.xyz - DEFAULT_TRACKER, axis=1))
    assert abs(np.std(radial) / np.sqrt(np.mean(s_r ** 2)) - 1) < 5 / math.sqrt(2 * n)


def test_reproducible_with_seed():
    a, b, c = simulate_campaign(seed=3), simulate_campaign(seed=3), simulate_campaign(seed=4)
    assert np.array_equal(a.xyz, b.xyz) and not np.array_equal(a.xyz, c.xyz)


def _planted(effects, **kw):
    return simulate_campaign(noise=False, effects=effects, **kw)


def test_backlash_appears_as_the_reversal_value(exact):
    rec = _planted([("backlash", {"axis": "X", "amount": 0.004})])
    d = rec.xyz - exact.xyz
    x = rec.axis == "X"
    np.testing.assert_allclose(d[x, 0], 0.002 * rec.direction[x], atol=1e-9)
    np.testing.assert_allclose(d[~x], 0, atol=1e-12)
    up = x & (rec.direction == 1)
    down = x & (rec.direction == -1)
    assert abs(rec.xyz[up, 0].mean() - rec.xyz[down, 0].mean() - 0.004) < 1e-9  # same targets both ways


def test_scale_periodic_second_order_on_positioning(exact):
    for eff, want in ((("scale", {"axis": "Y", "ppm": 20}), lambda q: 20e-6 * q),
                      (("periodic", {"axis": "Y", "amplitude": 0.002, "pitch": 200}),
                       lambda q: 0.002 * np.sin(2 * np.pi * q / 200)),
                      (("second_order", {"error": "E_YY", "coefficient": 2e-8}), lambda q: 2e-8 * q ** 2)):
        rec = _planted([eff])
        y = rec.axis == "Y"
        np.testing.assert_allclose((rec.xyz - exact.xyz)[y, 1], want(rec.position[y]), atol=1e-9)
        np.testing.assert_allclose((rec.xyz - exact.xyz)[y][:, [0, 2]], 0, atol=1e-9)


def test_squareness_tilts_the_y_motion(exact):
    """ISO right-hand convention: the actual Y direction is Rz(E_C0Y) y = (-sin, cos, 0)."""
    v = 50e-6
    rec = _planted([("squareness", {"error": "E_C0Y", "value": v})])
    y = rec.axis == "Y"
    q = rec.position[y]
    np.testing.assert_allclose((rec.xyz - exact.xyz)[y], np.c_[-q * math.sin(v), q * (math.cos(v) - 1), 0 * q],
                               atol=1e-9)
    np.testing.assert_allclose((rec.xyz - exact.xyz)[rec.axis == "X"], 0, atol=1e-12)


def test_rotary_location_rotates_about_the_displaced_line(exact):
    """C turns the table by Rz(-C) about the line through (E_X0C, E_Y0C): Delta = (I - Rz(-C)) c exactly."""
    rec = _planted([("rotary_location", {"error": "E_X0C", "value": 0.02})])
    c = rec.axis == "C"
    want = np.array([(np.eye(3) - _rz(-math.radians(q))) @ [0.02, 0, 0] for q in rec.position[c]])
    np.testing.assert_allclose((rec.xyz - exact.xyz)[c], want, atol=1e-9)
    np.testing.assert_allclose((rec.xyz - exact.xyz)[rec.axis != "C"], 0, atol=1e-12)


def test_cross_axis_needs_the_other_axis_away_from_zero(exact):
    eff = [("cross_axis", {"error": "E_ZX", "on": "Y", "coefficient": 1e-7})]
    np.testing.assert_allclose(_planted(eff).xyz, exact.xyz, atol=1e-12)  # invisible at Y = 0
    plan = {"axes": {"X": {"start": 0, "stop": 500, "count": 11, "at": {"Y": 200}}}}
    rec, ref = _planted(eff, plan=plan), simulate_campaign(noise=False, plan=plan)
    np.testing.assert_allclose((rec.xyz - ref.xyz)[:, 2], 1e-7 * rec.position * 200, atol=1e-9)


def test_thermal_drift_exponential_warm_up_and_temperature(exact):
    rec = _planted([("thermal_drift", {"amplitude": 0.010, "tau_s": 1800, "direction": "Z"})])
    tool = np.isin(rec.axis, ["X", "Y", "Z"])
    f = 1 - np.exp(-rec.time_s / 1800)
    np.testing.assert_allclose((rec.xyz - exact.xyz)[tool, 2], 0.010 * f[tool], atol=1e-9)
    np.testing.assert_allclose((rec.xyz - exact.xyz)[~tool], 0, atol=1e-12)  # the table does not grow
    np.testing.assert_allclose(rec.temperature_c, 20 + 2.0 * f, atol=1e-12)


def test_outlier_offset_and_tracker_scale(exact):
    rec, truth = simulate(effects=["outlier:axis=Z,round=2,point=Q,size=0.05,direction=-X"], noise=False)
    d = np.abs(rec.xyz - exact.xyz).sum(axis=1)
    (i,) = np.flatnonzero(d > 1e-9)
    assert (rec.axis[i], rec.round[i], rec.point[i], rec.position[i], rec.direction[i]) == ("Z", 2, "Q", 200.0, 1)
    assert rec.xyz[i, 0] - exact.xyz[i, 0] == pytest.approx(-0.05, abs=1e-9)
    assert truth["effects"][0]["rows"] == [{"axis": "Z", "round": 2, "position": 200.0, "point": "Q", "direction": 1}]
    bump = _planted(["outlier:axis=Z,round=2,point=Q,mode=bump"])
    assert (np.abs(bump.xyz - exact.xyz).sum(1) > 1e-9).sum() == 17  # 200 up .. 400, back to 0: 6 + 11 readings
    off = _planted([("offset", {"size": 0.02, "direction": "-Y", "t_from_s": 5000})])
    moved = exact.time_s >= 5000
    np.testing.assert_allclose((off.xyz - exact.xyz)[moved], np.tile([0, -0.02, 0], (moved.sum(), 1)), atol=1e-9)
    np.testing.assert_allclose((off.xyz - exact.xyz)[~moved], 0, atol=1e-12)
    rec = _planted([("tracker_scale", {"dt_c": 2.0})])  # 1 ppm/K, warmer air reads short: -2 ppm
    r1 = np.linalg.norm(rec.xyz - DEFAULT_TRACKER, axis=1)
    r0 = np.linalg.norm(exact.xyz - DEFAULT_TRACKER, axis=1)
    np.testing.assert_allclose(r1 / r0 - 1, -2e-6, atol=1e-12)


def test_error_model_drives_exact_kinematics():
    """A model's E_XX table is interpolated at each reading and pushed through tool_point exactly."""
    model = ErrorModel(functions={"E_XX": ErrorFunction("X", np.array([0.0, 500.0]), np.array([0.0, 0.020]))})
    rec, ref = simulate_campaign(model, noise=False), simulate_campaign(noise=False)
    x = rec.axis == "X"
    np.testing.assert_allclose((rec.xyz - ref.xyz)[x, 0], 0.020 * rec.position[x] / 500, atol=1e-9)
    with pytest.raises(InputError, match="machine"):
        simulate_campaign(ErrorModel(machine="xyzac"), machine="dmu50", noise=False)


def test_cli_round_trip(tmp_path, capsys):
    out = tmp_path / "rec.csv"
    assert main(["simulate", "-o", str(out), "--rounds", "2", "--seed", "5", "--effect", "backlash:axis=Y,amount=0.006",
                 "--effect", "periodic", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    rec = read_recording(out)
    assert len(rec) == summary["rows"] == 840 and rec.axes() == ["X", "Y", "Z", "B", "C"]
    assert set(np.unique(rec.direction)) == {-1, 1} and np.isfinite(rec.time_s).all()
    api = simulate_campaign(rounds=2, seed=5, effects=[("backlash", {"axis": "Y", "amount": 0.006}), ("periodic", {})])
    np.testing.assert_allclose(rec.xyz, api.xyz, atol=5e-7)  # the CSV keeps 1 nm
    truth = json.loads((tmp_path / "rec.truth.json").read_text())
    assert [e["name"] for e in truth["effects"]] == ["backlash", "periodic"]
    assert truth["effects"][0]["reversal"] == 0.006 and truth["effects"][0]["error"] == "E_YY"
    assert truth["tracker"] == list(DEFAULT_TRACKER) and truth["rounds"] == 2


def test_cli_plan_file(tmp_path):
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({"rounds": 1, "axes": {"Z": {"positions": [0, -100, -200]}},
                                "points": {"tool": {"A": [50, 0, 0], "B": [0, 50, 10], "C": [-50, 0, 20]}},
                                "tracker": [0, -2000, 0], "bidirectional": False}))
    out = tmp_path / "z.csv"
    assert main(["simulate", "--plan", str(plan), "-o", str(out), "--no-noise"]) == 0
    rec = read_recording(out)
    assert len(rec) == 9 and set(rec.point) == {"A", "B", "C"} and np.all(rec.direction == -1)
    assert rec.position[0] == 0 and rec.xyz[0].tolist() == [50, 0, 0]
    assert main(["simulate", "--plan", str(plan), "-o", str(plan)]) == 2  # never overwrite an input


@pytest.mark.parametrize("args, message", [
    (["--effect", "bogus"], "unknown effect 'bogus'"),
    (["--effect", "backlash:amont=0.1"], "unknown key(s) ['amont']"),
    (["--effect", "backlash:axis=W"], "axis must be one of"),
    (["--effect", "scale:ppm=abc"], "ppm='abc'"),
    (["--effect", "scale:ppm"], "expected key=value"),
    (["--effect", "squareness:error=E_XX"], "must be one of E_C0Y"),
    (["--tracker", "1,2"], "--tracker: expected three numbers x,y,z in mm, got '1,2'"),
    (["--tracker", "a,b,c"], "x,y,z in mm"),
])
def test_cli_bad_input(tmp_path, capsys, args, message):
    assert main(["simulate", "-o", str(tmp_path / "r.csv"), *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mtcal simulate: error:") and message in err
    assert not (tmp_path / "r.csv").exists()


def test_bad_plans_and_effects():
    with pytest.raises(InputError, match="unknown key"):
        plan_from_dict({"rouns": 3})
    with pytest.raises(InputError, match="collinear"):
        plan_from_dict({"points": {"tool": {"A": [0, 0, 0], "B": [1, 0, 0], "C": [2, 0, 0]}}})
    with pytest.raises(InputError, match=r"axes.B: positions must lie in \[0, 180\]"):
        plan_from_dict({"axes": {"B": {"positions": [0, 190]}}})
    with pytest.raises(InputError, match="no reading of axis X round 9"):
        simulate_campaign(effects=[("outlier", {"round": 9})])
    with pytest.raises(InputError, match="an effect must be"):
        simulate_campaign(effects=[42])
    assert parse_effect("scale:axis=c,ppm=-3").params == {"axis": "C", "ppm": -3.0}
    assert Effect("tracker_scale", {"dt_c": 1, "dp_hpa": 10}).tracker_ppm() == pytest.approx(2.0)
    assert len(schedule(Plan(rounds=1))) == 420


# ----------------------------------------------------------------------------- issue 36: --extrapolate hold
def test_cli_extrapolate_hold_simulates_a_model_over_a_wider_plan(tmp_path, capsys):
    """The bundled demo truth covers X in [-250, 250] (mtcal/data/make_demo_data.py TRAVEL); the default plan runs X
    to 500 (dmu50.toml [campaign]).  Refused by default, naming the option; with --extrapolate hold each table's end
    value is held: between X = 450 and 500 every reflector then moves exactly the commanded 50 mm."""
    from mtcal.data import path
    out = tmp_path / "r.csv"
    model = str(path("demo_truth.json"))
    assert main(["simulate", "--model", model, "-o", str(out), "--no-noise", "--rounds", "1"]) == 2
    err = capsys.readouterr().err
    assert "X = 300 is outside the measured range [-250, 250] of E_AX (give --extrapolate hold" in err
    assert not out.exists()
    assert main(["simulate", "--model", model, "-o", str(out), "--no-noise", "--rounds", "1",
                 "--extrapolate", "hold", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    # X at 300, 350, 400, 450, 500: 5 positions x 3 reflectors x 2 directions x 1 round for each error of X
    assert summary["model_held"]["E_XX"] == 30 and summary["model_held"]["E_AX"] == 30
    assert json.loads((tmp_path / "r.truth.json").read_text())["model_held"] == summary["model_held"]
    rec = read_recording(out)
    for a, b, held in ((450, 500, True), (150, 200, False)):
        pa, pb = ((rec.axis == "X") & (rec.position == p) & (rec.direction == 1) for p in (a, b))
        step = rec.xyz[pb] - rec.xyz[pa]
        moved = np.abs(step - [50.0, 0.0, 0.0]).max()
        assert (moved < 1e-9) if held else (moved > 1e-4), (a, b, moved)


def test_simulate_extrapolate_is_checked():
    with pytest.raises(InputError, match="extrapolate must be 'error' or 'hold', got 'clamp'"):
        simulate(ErrorModel(), extrapolate="clamp")
