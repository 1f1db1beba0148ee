"""Joint weighted identification (issue 14): derived station geometry, recording columns, and the estimator on
campaigns simulated physically through the exact kinematics (mtcal.campaign.stations: exact error-inclusive
reflector positions, rigid station misalignment, AT960 noise) -- never by adding the estimator's linear model."""
from __future__ import annotations

import numpy as np
import pytest

import mtcal
from mtcal.campaign.stations import simulate_stations
from mtcal.errors import InputError
from mtcal.generated import threepoint_numpy as tp
from mtcal.identify.joint import joint_fit
from mtcal.identify.run import identify
from mtcal.measurement.recordings import format_recording, parse_recording
from mtcal.model.errormodel import ErrorFunction, ErrorModel

M = mtcal.load_machine("dmu50")
FRONT, LEFT, FRONT_RIGHT, HIGH = (250, -1500, 150), (-1500, 0, 150), (1300, -1300, 150), (-1000, -1000, 1200)
SMALL = {"axes": {"X": {"start": -200, "stop": 200, "count": 5}, "Y": {"start": -200, "stop": 200, "count": 5},
                  "C": {"start": 0, "stop": 300, "count": 6}}, "bidirectional": False}


def _rz(c):
    return np.array([[np.cos(c), -np.sin(c), 0], [np.sin(c), np.cos(c), 0], [0, 0, 1]])


def _ry(b):
    return np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])


def _rx(a):
    return np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])


def test_rigid_point_is_translation_after_rz_ry_rx_and_its_derivative_is_point_rows():
    rng = np.random.default_rng(3)
    p = rng.uniform(-800, 800, (5, 3))
    a = np.concatenate([rng.normal(0, 0.05, 3), rng.normal(0, 0.2, 3)])  # large angles: exactness, not first order
    ref = np.array([a[:3] + _rz(a[5]) @ _ry(a[4]) @ _rx(a[3]) @ v for v in p])
    assert np.allclose(tp.rigid_point(p, a), ref, atol=1e-9)
    h = 1e-6
    fd = np.stack([(tp.rigid_point(p, h * e) - tp.rigid_point(p, -h * e)) / (2 * h) for e in np.eye(6)], axis=-1)
    assert np.allclose(fd, tp.point_rows(p), atol=1e-6)


def _truth() -> ErrorModel:
    """Smooth errors of thesis magnitude on X, Y, C; X and Y straightness out of the ISO frame's gauge have no
    linear part (the truth is expressed in the ISO frame of the linear axes, as the estimate is)."""
    x = np.linspace(-200, 200, 41)
    s = x / 200
    c = np.linspace(0, 300, 31)
    w = np.radians(c)
    f = {"E_XX": ErrorFunction("X", x, 0.015 * s**2 + 0.005 * s**3),
         "E_YX": ErrorFunction("X", x, 0.004 * (s**2 - 1 / 3)),
         "E_ZX": ErrorFunction("X", x, 0.003 * s**3 - 0.0018 * s), "E_CX": ErrorFunction("X", x, 2e-5 * s**2),
         "E_AX": ErrorFunction("X", x, 1.5e-5 * s), "E_YY": ErrorFunction("Y", x, 0.012 * s**2),
         "E_XY": ErrorFunction("Y", x, 0.004 * s), "E_ZY": ErrorFunction("Y", x, 0.003 * (s**2 - 1 / 3)),
         "E_BY": ErrorFunction("Y", x, 2e-5 * s**2), "E_XC": ErrorFunction("C", c, 0.004 * np.sin(w)),
         "E_CC": ErrorFunction("C", c, 1e-5 * (1 - np.cos(w))), "E_AC": ErrorFunction("C", c, 8e-6 * np.sin(2 * w))}
    return ErrorModel("dmu50", {}, f, {})


def _errors_at_keys(res, rec):
    return np.concatenate([res.errors(a)[1].ravel() for a in rec.axes()])


def test_station_columns_round_trip_and_a_round_belongs_to_one_station():
    rec, truth = simulate_stations(_truth(), [FRONT, LEFT], machine=M, rounds=1, seed=1, plan=SMALL)
    back = parse_recording(format_recording(rec), "rec.csv")
    assert list(back.station[:1]) == ["S1"] and set(back.station) == {"S1", "S2"}
    assert np.allclose(back.tracker_xyz[back.station == "S2"], LEFT)
    assert [s["tracker"] for s in truth["stations"]] == [list(map(float, FRONT)), list(map(float, LEFT))]
    text = format_recording(rec).splitlines()
    i = next(k for k, ln in enumerate(text) if ",S2," in ln)
    text[i] = text[i].replace(",2,", ",1,", 1)  # a round-2 row claimed by round 1 of station S1
    with pytest.raises(InputError, match=r"rec.csv:\d+: round 1 is measured from stations"):
        parse_recording("\n".join(text), "rec.csv")


def test_alignment_errors_of_tens_of_um_and_urad_cost_nothing():
    """Noise-free: the estimate with stations misaligned by ~50 um / 100 urad equals the one without (to 1 nm /
    0.01 urad), and each station's alignment is recovered (translations centred: docs/design.md gauge)."""
    kw = dict(machine=M, rounds=1, plan=SMALL, noise=False)
    rec0, _ = simulate_stations(_truth(), [FRONT, LEFT, HIGH], alignment_um=0, alignment_urad=0, **kw)
    rec1, truth = simulate_stations(_truth(), [FRONT, LEFT, HIGH], alignment_um=50, alignment_urad=100, seed=4, **kw)
    j0, j1 = joint_fit(rec0, M, per_round=False), joint_fit(rec1, M, per_round=False)
    d = _errors_at_keys(j1, rec1) - _errors_at_keys(j0, rec0)
    assert np.abs(d).max() < 1e-6  # mm and rad alike: < 1 nm, < 1 urad
    for st in truth["stations"]:
        a_true = np.array(st["alignment"])
        assert np.abs(a_true).max() > 2e-5  # really misaligned
        a_hat = j1.alignment[st["label"]] - j0.alignment[st["label"]]
        assert np.allclose(a_hat[:3], a_true[:3], atol=1e-6) and np.allclose(a_hat[3:], a_true[3:], atol=1e-8)


@pytest.mark.slow
def test_scatter_over_seeds_matches_the_reported_covariance():
    """20 seeds of a noisy two-station campaign: the estimate minus the noise-free estimate, whitened by the
    reported covariance, has chi^2 / dof ~ 1 (mean of z^2 within 20 %) and the Birge ratio is ~1."""
    kw = dict(machine=M, rounds=1, plan=SMALL)
    z2, birge = [], []
    for seed in range(20):  # the same seed draws the same station misalignments, with and without noise
        j0 = joint_fit(simulate_stations(_truth(), [FRONT, FRONT_RIGHT], noise=False, seed=seed, **kw)[0], M,
                       per_round=False)
        rec, _ = simulate_stations(_truth(), [FRONT, FRONT_RIGHT], seed=seed, **kw)
        j = joint_fit(rec, M, per_round=False)
        d = j.x - j0.x
        sd = np.sqrt(np.diagonal(j.covariance))
        ok = sd > 0
        z2.append(np.mean((d[ok] / sd[ok]) ** 2))
        birge.append(j.birge)
    assert 0.8 < np.mean(z2) < 1.2
    assert 0.9 < np.mean(birge) < 1.1


def _vol(model, truth, grid):
    dt = M.deviation(grid, truth.errors_at(M, grid, "hold"), order=None)[:, :3]
    dm = M.deviation(grid, model.errors_at(M, grid, "hold"), order=None)[:, :3]
    return float(np.sqrt(np.mean(np.sum((dm - dt) ** 2, axis=1))) * 1e3)


def test_joint_beats_three_point_on_one_station_and_four_stations_beat_one():
    truth = _truth()
    rng = np.random.default_rng(0)
    grid = np.column_stack([rng.uniform(-200, 200, 500), rng.uniform(-200, 200, 500), np.zeros(500), np.zeros(500),
                            rng.uniform(0, 300, 500)])
    one, _ = simulate_stations(truth, [FRONT], machine=M, rounds=4, seed=2, plan=SMALL)
    four, _ = simulate_stations(truth, [FRONT, LEFT, FRONT_RIGHT, HIGH], machine=M, rounds=1, seed=2, plan=SMALL)
    v3 = _vol(identify(one, tracker=FRONT, machine=M, method="three-point").model, truth, grid)
    vj = _vol(identify(one, machine=M, method="joint").model, truth, grid)
    v4 = _vol(identify(four, machine=M).model, truth, grid)
    assert vj < v3
    assert v4 < 0.6 * vj


# ----------------------------------------------------------------------------- the demo machine, four stations
STATIONS4 = [("front", FRONT), ("left", LEFT), ("front-right", FRONT_RIGHT), ("elevated", HIGH)]
WIDE = {"tool": {"P": [210, 0, 30], "Q": [-105, 180, 120], "K": [-105, -180, 210]},  # 3x the spec's layout
        "table": {"P": [450, 0, 40], "Q": [-225, 390, 80], "K": [-225, -390, 120]}}


@pytest.fixture(scope="module")
def demo():
    """(ISO-framed demo truth, its campaign plan, 2000 poses over the demo's work volume, true deviations).
    The truth is the bundled demo truth with the linear part of E_YX, E_ZX and E_ZY removed: the estimate is in
    the ISO frame of the linear axes (docs/design.md gauge) and a tracker cannot see the frame's rotation relative to
    the table, so a truth outside that frame would differ from any estimate by it (2.6 um on this metric)."""
    from mtcal.data.make_demo_data import DEMO_PLAN
    from mtcal.demo.run import data_path
    from mtcal.model.errormodel import load_model
    truth = load_model(data_path("demo_truth.json"))
    for nm in ("E_YX", "E_ZX", "E_ZY"):
        f = truth.functions[nm]
        xs = np.linspace(f.positions.min(), f.positions.max(), 201)
        v = f(xs)
        slope = np.polyfit(xs, v, 1)[0]
        truth.functions[nm] = ErrorFunction(f.axis, xs, v - slope * xs)
    rng = np.random.default_rng(0)
    grid = np.column_stack([rng.uniform(-200, 200, 2000), rng.uniform(-180, 180, 2000),
                            rng.uniform(-150, 150, 2000), rng.uniform(0, 120, 2000), rng.uniform(0, 360, 2000)])
    return truth, DEMO_PLAN, grid


def _demo_vol(demo, stations, rounds, points=None, seed=1):
    truth, plan, grid = demo
    pl = {**plan, **({"points": points} if points else {})}
    rec, _ = simulate_stations(truth, stations, machine=M, rounds=rounds, seed=seed, plan=pl)
    return _vol(identify(rec, machine=M).model, truth, grid)


def test_four_stations_one_round_each_within_3_um_volumetric(demo):
    """Issue 14: front, left, front-right, elevated at 1.2 m; 1 round per station; stations misaligned by
    ~20 um / 30 urad (seeded): model - truth RMS over the work volume <= 3 um (measured 1.9 um)."""
    assert _demo_vol(demo, STATIONS4, 1) < 3.0


@pytest.mark.parametrize("rounds, points", [(2, None), (1, WIDE)], ids=["2-rounds", "wide-reflectors"])
@pytest.mark.slow
def test_four_stations_two_rounds_or_wide_reflectors_within_2_2_um(demo, rounds, points):
    assert _demo_vol(demo, STATIONS4, rounds, points) < 2.2


@pytest.mark.slow
def test_one_station_joint_no_worse_than_three_point(demo):
    """The thesis campaign (one station at Pos. 1, 4 rounds, mtcal.campaign.simulate): joint <= three-point."""
    from mtcal.campaign.simulate import simulate
    truth, plan, grid = demo
    rec, _ = simulate(truth, machine=M, seed=1, plan=plan, rounds=None)
    v3 = _vol(identify(rec, tracker=FRONT, machine=M, method="three-point").model, truth, grid)
    vj = _vol(identify(rec, tracker=FRONT, machine=M).model, truth, grid)
    assert vj <= v3


def test_cli_simulate_several_stations_then_identify(tmp_path, capsys):
    """mtcal simulate --tracker repeated writes station and tracker columns and the stations' alignment truth;
    mtcal identify fits them jointly (default) and estimates each station's alignment within 4 sigma."""
    import json

    from mtcal.cli import main
    rec = tmp_path / "ms.csv"
    assert main(["simulate", "--tracker", "250,-1500,150", "--tracker=-1500,0,150", "--tracker=-1000,-1000,1200",
                 "--seed", "3", "-o", str(rec), "--json"]) == 0
    truth = json.loads((tmp_path / "ms.truth.json").read_text())
    capsys.readouterr()
    assert main(["identify", str(rec), "-o", str(tmp_path / "m.json"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["method"] == "joint" and 0.9 < out["joint"]["birge_ratio"] < 1.1
    sq, sq_sd = out["squareness"], out["joint"]["squareness_sigma"]
    assert set(sq_sd) == {"E_C0Y", "E_B0Z", "E_A0Z"}  # truth: square machine (no model)
    assert all(0 < sq_sd[k] < 2e-5 and abs(sq[k]) < 4 * sq_sd[k] for k in sq_sd), (sq, sq_sd)
    for st in truth["stations"]:
        est = out["joint"]["stations"][st["label"]]
        z = (np.array(est["alignment"]) - st["alignment"]) / np.maximum(est["alignment_sigma"], 1e-12)
        assert np.all(np.abs(z[np.array(est["alignment_sigma"]) > 0]) < 4), z


def test_other_axes_positions_move_the_carrier():
    """pos_<AXIS> columns: a C campaign simulated with B at 30 deg (its table reflectors carried by both) writes
    pos_B and is fitted with it; read as if B were at zero it is rejected by chi^2 (Birge ratio >> 1)."""
    plan = {"axes": {"C": {"start": 0, "stop": 300, "count": 6, "at": {"B": 30}}}, "bidirectional": False}
    rec, _ = simulate_stations(None, [FRONT, LEFT], machine=M, rounds=1, seed=2, plan=plan)
    assert "pos_B" in format_recording(rec).splitlines()[0]
    back = parse_recording(format_recording(rec), "rec.csv")
    assert np.allclose(back.other_positions["B"], 30.0)
    assert joint_fit(back, M, per_round=False).birge < 1.3
    back.other_positions = None
    assert joint_fit(back, M, per_round=False).birge > 10


def test_plan_json_stations_and_their_bad_values():
    from mtcal.campaign.plans import plan_from_dict
    pl = plan_from_dict({"stations": {"front": [250, -1500, 150], "left": [-1500, 0, 150]}}, "p.json", M)
    assert list(pl.stations) == ["front", "left"] and pl.stations["left"] == (-1500.0, 0.0, 150.0)
    with pytest.raises(InputError, match=r"p.json: stations.left must be \[x, y, z\] in mm"):
        plan_from_dict({"stations": {"left": [1, 2]}}, "p.json", M)


def test_reference_row_is_zero_with_zero_variance_and_the_other_rows_are_the_truth():
    """Issue 22: ``JointResult.errors`` took the reference position's six components from columns -1..4 (another
    position's values and variances).  Noise-free: the reference row is exactly zero with zero variance (the gauge),
    and every other row is the same whether or not the reference row is looked at."""
    rec, _ = simulate_stations(_truth(), [FRONT, LEFT], machine=M, rounds=1, seed=2, plan=SMALL, noise=False)
    res = joint_fit(rec, M, per_round=False)
    assert res.x[:6].any()  # the first position's columns (which the old lookup read) are not zero
    for axis in rec.axes():
        keys, vals, cov = res.errors(axis)
        i = keys.index(res.layout.reference[axis])
        assert np.all(vals[i] == 0.0) and np.all(cov[i] == 0.0) and np.all(cov[:, :, i] == 0.0)
        for k, key in enumerate(keys):
            if k != i:
                first = res.layout.err_index[(axis, *key)]
                assert np.array_equal(vals[k], res.x[first:first + 6])
