"""ISO 230-2:2014 evaluation: recordings built here with a known run structure and planted deviations; the
expected values are computed in this file by a plain loop over the standard's definitions, not by
mtcal.iso230_2.evaluation; plus end-to-end through `mtcal simulate` with planted scale and backlash."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from mtcal.cli import main
from mtcal.errors import InputError
from mtcal.iso230_2.evaluation import evaluate, infer_directions
from mtcal.measurement.recordings import format_recording, make_recording, parse_recording

D = 154.996  # mm, B/C intersection height of the DMU 50 (dmu50.toml)
ARCSEC = 180 / math.pi * 3600
SPINDLE = {"P": (70.0, 0.0, 10.0), "Q": (-35.0, 60.0, 40.0), "K": (-35.0, -60.0, 70.0)}
TABLE = {"P": (150.0, 0.0, 40.0), "Q": (-75.0, 130.0, 80.0), "K": (-75.0, -130.0, 120.0)}


# ----------------------------------------------------------------------------- independent oracle
def iso_oracle(runs):
    """ISO 230-2:2014 from its definitions: runs = [(target, direction, deviation)]; plain loops."""
    targets = sorted({r[0] for r in runs})
    per = {}
    for p in targets:
        row = {}
        for d, tag in ((1, "up"), (-1, "down")):
            xs = [x for (t, dd, x) in runs if t == p and dd == d]
            n = len(xs)
            mean = sum(xs) / n
            s = math.sqrt(sum((x - mean) ** 2 for x in xs) / (n - 1))
            row[f"mean_{tag}"], row[f"s_{tag}"], row[f"n_{tag}"] = mean, s, n
        row["mean"] = (row["mean_up"] + row["mean_down"]) / 2
        row["reversal"] = row["mean_up"] - row["mean_down"]
        row["R_up"], row["R_down"] = 4 * row["s_up"], 4 * row["s_down"]
        row["R"] = max(2 * row["s_up"] + 2 * row["s_down"] + abs(row["reversal"]), row["R_up"], row["R_down"])
        per[p] = row
    col = lambda k: [per[p][k] for p in targets]  # noqa: E731
    hi_u = [per[p]["mean_up"] + 2 * per[p]["s_up"] for p in targets]
    lo_u = [per[p]["mean_up"] - 2 * per[p]["s_up"] for p in targets]
    hi_d = [per[p]["mean_down"] + 2 * per[p]["s_down"] for p in targets]
    lo_d = [per[p]["mean_down"] - 2 * per[p]["s_down"] for p in targets]
    axis = {"B": max(abs(b) for b in col("reversal")), "B_mean": sum(col("reversal")) / len(targets),
            "E_up": max(col("mean_up")) - min(col("mean_up")), "E_down": max(col("mean_down")) - min(col("mean_down")),
            "E": max(col("mean_up") + col("mean_down")) - min(col("mean_up") + col("mean_down")),
            "M": max(col("mean")) - min(col("mean")),
            "R_up": max(col("R_up")), "R_down": max(col("R_down")), "R": max(col("R")),
            "A_up": max(hi_u) - min(lo_u), "A_down": max(hi_d) - min(lo_d), "A": max(hi_u + hi_d) - min(lo_u + lo_d)}
    return targets, per, axis


def _rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def _rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _passes(targets, rounds, skip=()):
    """ISO 230-2 runs: each round out (+) then back (-); ``skip``: (round, target, direction) not measured."""
    out = []
    for r in range(1, rounds + 1):
        for d, seq in ((1, targets), (-1, targets[::-1])):
            out += [(r, p, d) for p in seq if (r, p, d) not in skip]
    return out


def _build(axis, passes, dev, place, temperature=None, with_direction=True):
    """Recording of ``passes``; dev[(round, target, direction)] = planted deviation; place(point, q, dev)
    -> machine-frame reading (mm).  Readings are in time order (a pass reads P, Q, K)."""
    rows = {k: [] for k in ("axis", "round", "position", "point", "xyz", "time", "dir", "temp")}
    t = 0.0
    for (r, p, d) in passes:
        for pt in ("P", "Q", "K"):
            t += 5.0
            rows["axis"].append(axis), rows["round"].append(r), rows["position"].append(p)
            rows["point"].append(pt), rows["xyz"].append(place(pt, p, dev[(r, p, d)]))
            rows["time"].append(t), rows["dir"].append(d)
            rows["temp"].append(np.nan if temperature is None else temperature[(r, p, d)])
    rec = make_recording(rows["axis"], rows["round"], rows["position"], rows["point"], rows["xyz"], rows["time"],
                         rows["dir"] if with_direction else None, rows["temp"])
    return parse_recording(format_recording(rec, precision=9), "built.csv")  # through the file format


def _relative(passes, dev):
    """The deviations the evaluation must report: every run from one datum (ISO 230-2: x_ij = P_ij - P_i), the
    first pass at the position closest to zero (the datum reading is zero there by construction)."""
    q0 = min((q for (_, q, _) in passes), key=abs)
    first = next(k for k in passes if k[1] == q0)
    return [(p, d, dev[(r, p, d)] - dev[first]) for (r, p, d) in passes]


def _linear_x(pt, q, dev_um):
    """Spindle reflector on the DMU 50 (tool side: T_0^t = Trans(X, Y, Z)) with X at q + deviation."""
    return np.asarray(SPINDLE[pt]) + [q + dev_um * 1e-3, 0.0, 0.0]


def _check(ev, runs, tol):
    targets, per, axis = iso_oracle(runs)
    np.testing.assert_allclose(ev.positions, targets)
    for k in ("n_up", "n_down", "mean_up", "mean_down", "mean", "reversal", "s_up", "s_down", "R_up", "R_down", "R"):
        np.testing.assert_allclose(ev.targets[k], [per[p][k] for p in targets], atol=tol, err_msg=k)
    for k, v in axis.items():
        assert ev.parameters[k] == pytest.approx(v, abs=tol), k


def _planted(passes, rng, scale_um_per_mm=0.02, backlash_um=3.0, spread_um=1.5):
    return {(r, p, d): scale_um_per_mm * p + d * backlash_um / 2 + spread_um * rng.standard_normal()
            for (r, p, d) in passes}


# ----------------------------------------------------------------------------- statistics against the oracle
def test_linear_axis_matches_the_definitions_with_reversal():
    rng = np.random.default_rng(1)
    targets = [0.0, 60.0, 130.0, 250.0, 310.0, 400.0, 480.0]
    passes = _passes(targets, 5)
    dev = _planted(passes, rng)
    ev = evaluate(_build("X", passes, dev, _linear_x), axis="X").axes["X"]
    assert ev.unit == "um"
    _check(ev, _relative(passes, dev), 1e-5)  # readings written to 1e-9 mm
    assert ev.parameters["B_mean"] == pytest.approx(3.0, abs=1.5)  # the planted reversal, through the noise
    assert not any("fewer than 5 runs" in n for n in ev.notes)


def test_unequal_numbers_of_runs_and_a_warning_below_five():
    rng = np.random.default_rng(2)
    targets = [0.0, 100.0, 200.0, 300.0, 400.0]
    skip = {(2, 100.0, 1), (3, 100.0, -1), (3, 300.0, 1), (1, 400.0, -1), (3, 200.0, -1)}
    passes = _passes(targets, 4, skip)
    dev = _planted(passes, rng)
    ev = evaluate(_build("X", passes, dev, _linear_x), axis="X").axes["X"]
    runs = _relative(passes, dev)
    _check(ev, runs, 1e-5)  # readings written to 1e-9 mm
    assert ev.targets["n_up"].tolist() == [4, 3, 4, 3, 4] and ev.targets["n_down"].tolist() == [4, 3, 3, 4, 3]
    assert any("fewer than 5 runs" in n for n in ev.notes)


def test_directions_inferred_from_the_order_when_the_column_is_absent():
    rng = np.random.default_rng(3)
    targets = [0.0, 100.0, 200.0, 300.0, 400.0]
    passes = _passes(targets, 5)
    dev = _planted(passes, rng)
    ev = evaluate(_build("X", passes, dev, _linear_x, with_direction=False), axis="X").axes["X"]
    _check(ev, _relative(passes, dev), 1e-5)  # readings written to 1e-9 mm
    assert any("inferred" in n for n in ev.notes)
    # out and back with a repeated end point: + + + - - -; first reading takes the first move's sign
    assert infer_directions(np.array([0, 5, 10, 10, 5, 0.0]), np.arange(6.0)).tolist() == [1, 1, 1, -1, -1, -1]
    assert infer_directions(np.array([10, 5, 0, 0, 5.0]), np.arange(5.0)).tolist() == [-1, -1, -1, 1, 1]


def test_rotary_c_axis_angular_deviation_from_the_plane_geometry():
    """C on the DMU 50 at B = 0: a table point w sits at Rz(-C) w (docs/design.md, T_0^w); the table turned to
    C + delta, plus a radial drift of the axis (must not leak into the angle)."""
    rng = np.random.default_rng(4)
    targets = [0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0]
    passes = _passes(targets, 5)
    dev = {k: 8.0 * math.sin(math.radians(2 * k[1])) + k[2] * 2.0 + rng.standard_normal() for k in passes}  # arcsec

    def place(pt, c, d_arcsec):
        shift = [0.004 * math.cos(math.radians(c)), 0.003, 0.0]  # mm: radial motion of the axis line
        return _rz(-math.radians(c) - d_arcsec / ARCSEC) @ np.asarray(TABLE[pt]) + shift

    ev = evaluate(_build("C", passes, dev, place), axis="C").axes["C"]
    assert ev.unit == "arcsec" and ev.kind == "rotary"
    _check(ev, _relative(passes, dev), 2e-3)  # first order in a 1e-4 rad motion: 1e-4 arcsec level
    assert ev.parameters["B_mean"] == pytest.approx(4.0, abs=1.5)
    with pytest.raises(InputError, match=r"built\.csv: the angle of rotary axis C needs >= 3 reflectors"):
        evaluate(_build("C", passes, dev, place), axis="C", point="P")
    in_urad = evaluate(_build("C", passes, dev, place), axis="C", angle_unit="urad").axes["C"]
    assert in_urad.parameters["E"] == pytest.approx(ev.parameters["E"] / ARCSEC * 1e6, rel=1e-9)


def test_rotary_b_axis_tilted_45_degrees():
    """B on the DMU 50 at C = 0: Tz(d) Rx(45) Rz(B) Rx(-45) Tz(-d) w (docs/design.md)."""
    rng = np.random.default_rng(5)
    targets = [0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0]
    passes = _passes(targets, 5)
    dev = {k: 0.05 * k[1] + k[2] * 3.0 + rng.standard_normal() for k in passes}  # arcsec

    def place(pt, b, d_arcsec):
        r = _rx(math.pi / 4) @ _rz(math.radians(b) + d_arcsec / ARCSEC) @ _rx(-math.pi / 4)
        return r @ (np.asarray(TABLE[pt]) - [0, 0, D]) + [0, 0, D]

    ev = evaluate(_build("B", passes, dev, place), axis="B").axes["B"]
    _check(ev, _relative(passes, dev), 2e-3)


def test_temperature_normalisation_to_20_c():
    """Readings of an axis at T != 20 C carry alpha (T - 20) P on top of the machine's deviation; normalised
    they give the deviation back; not normalised they do not."""
    rng = np.random.default_rng(6)
    alpha = 11.5e-6
    targets = [0.0, 100.0, 200.0, 300.0, 400.0, 500.0]
    passes = _passes(targets, 5)
    dev = _planted(passes, rng, spread_um=0.5)
    temp = {k: 20.0 + 0.4 * k[0] + 0.002 * k[1] for k in passes}  # warming through the rounds, C
    seen = {k: dev[k] + alpha * (temp[k] - 20.0) * k[1] * 1e3 for k in passes}  # um
    rec = _build("X", passes, seen, _linear_x, temperature=temp)
    ev = evaluate(rec, axis="X", alpha=alpha).axes["X"]
    _check(ev, _relative(passes, dev), 1e-5)  # readings written to 1e-9 mm
    raw = evaluate(rec, axis="X").axes["X"]
    assert raw.parameters["E_up"] - ev.parameters["E_up"] > 5.0  # 11.5e-6 * ~2.4 K * 500 mm = 14 um
    no_temp = _build("X", passes, seen, _linear_x)
    with pytest.raises(InputError, match="temperature_c"):
        evaluate(no_temp, axis="X", alpha=alpha)


def test_one_reflector_or_the_centroid():
    """A yaw of X (E_CX) moves Q and K along X by -y E_CX (Abbe), P (y = 0) not: --point P sees the planted
    deviation alone, the default (centroid of P, Q, K, at y = 0) as well; Q alone sees the Abbe term too."""
    rng = np.random.default_rng(10)
    targets = [0.0, 100.0, 200.0, 300.0, 400.0]
    passes = _passes(targets, 5)
    dev = _planted(passes, rng)
    yaw = 2e-6  # rad per mm of travel

    def place(pt, q, d_um):
        return _linear_x(pt, q, d_um) + [-SPINDLE[pt][1] * yaw * q, 0.0, 0.0]

    rec = _build("X", passes, dev, place)
    for point in ("P", None):
        _check(evaluate(rec, axis="X", point=point).axes["X"], _relative(passes, dev), 1e-5)
    abbe = {k: dev[k] - SPINDLE["Q"][1] * yaw * k[1] * 1e3 for k in passes}
    _check(evaluate(rec, axis="X", point="Q").axes["X"], _relative(passes, abbe), 1e-5)


def test_unidirectional_runs_leave_bidirectional_values_undefined():
    rng = np.random.default_rng(9)
    targets = [0.0, 100.0, 200.0, 300.0, 400.0]
    passes = [(r, p, 1) for r in range(1, 6) for p in targets]
    dev = _planted(passes, rng)
    ev = evaluate(_build("X", passes, dev, _linear_x), axis="X").axes["X"]
    runs = _relative(passes, dev)
    means = [sum(x for (t, _, x) in runs if t == p) / 5 for p in targets]
    assert ev.parameters["E_up"] == pytest.approx(max(means) - min(means), abs=1e-5)
    assert all(math.isnan(ev.parameters[k]) for k in ("B", "B_mean", "E", "E_down", "M", "R", "A", "A_down", "R_down"))
    assert any("unidirectional runs only" in n for n in ev.notes)


def test_target_points_select_and_unknown_target_fails():
    rng = np.random.default_rng(7)
    targets = [0.0, 100.0, 200.0, 300.0, 400.0, 500.0]
    passes = _passes(targets, 5)
    dev = _planted(passes, rng)
    rec = _build("X", passes, dev, _linear_x)
    ev = evaluate(rec, axis="X", targets=[0, 200, 400]).axes["X"]
    _check(ev, [r for r in _relative(passes, dev) if r[0] in (0.0, 200.0, 400.0)], 1e-5)  # readings written to 1e-9 mm
    assert any("left out: 100, 300, 500" in n for n in ev.notes)
    with pytest.raises(InputError, match="250"):
        evaluate(rec, axis="X", targets=[0, 250])


def _without_line(rec, k: int, name: str):
    """The recording's file text with data row k (0-based, after the header) removed, read back as ``name``."""
    text = format_recording(rec, precision=9).splitlines()
    line = text.pop(k + 1)
    return parse_recording("\n".join(text) + "\n", name), line


def test_a_missing_reading_is_a_missing_run_not_an_error_nor_a_re_reference():
    """One reflector's reading of round 1 at 100 mm (up) is missing: that run is missing at that target (the
    target's statistics use the other runs, and a note names it); nothing else moves."""
    rng = np.random.default_rng(8)
    passes = _passes([0.0, 100.0, 200.0], 3)
    dev = _planted(passes, rng)
    rec = _build("X", passes, dev, _linear_x)
    k = 3 * passes.index((1, 100.0, 1)) + 1  # its Q reading
    cut, _ = _without_line(rec, k, "cut.csv")
    ev = evaluate(cut, axis="X").axes["X"]
    kept = [q for q in passes if q != (1, 100.0, 1)]
    _check(ev, [r for r, q in zip(_relative(passes, dev), passes) if q in kept], 1e-5)
    assert ev.targets["n_up"].tolist() == [3, 2, 3]
    assert any("1 run(s) left out" in n and "round 1 at 100 (up: Q missing" in n for n in ev.notes), ev.notes


def test_drift_per_run_shows_in_the_repeatability():
    """ISO 230-2 takes every run from one datum, so a drift of 3 um per run is what R shows (re-zeroing each run at
    its own reading near 0 hid it: R of a few um).  Expected values by the standard's definitions in this file."""
    passes = _passes([-200.0, -100.0, 0.0, 100.0, 200.0], 5)
    dev = {(r, p, d): 0.01 * p + 3.0 * (r - 1) for (r, p, d) in passes}
    ev = evaluate(_build("X", passes, dev, _linear_x), axis="X").axes["X"]
    _check(ev, _relative(passes, dev), 1e-5)
    assert ev.parameters["R"] == pytest.approx(iso_oracle(_relative(passes, dev))[2]["R"], abs=1e-6)
    assert ev.parameters["R"] == pytest.approx(4 * np.std([0, 3, 6, 9, 12], ddof=1), abs=1e-5)  # 18.97 um


def test_a_missing_reference_reading_is_not_re_referenced():
    """Round 2's reading of P at the reference target (0 mm) is missing: only that run at 0 is missing; round 2's
    other runs keep the one datum (before: round 2 was re-referenced to another reading, R 56 -> 100 um on the
    public data)."""
    rng = np.random.default_rng(9)
    passes = _passes([0.0, 100.0, 200.0, 300.0], 3)
    dev = _planted(passes, rng, spread_um=4.0)
    rec = _build("X", passes, dev, _linear_x)
    cut, _ = _without_line(rec, 3 * passes.index((2, 0.0, 1)), "cut.csv")
    ev = evaluate(cut, axis="X").axes["X"]
    _check(ev, [r for r, q in zip(_relative(passes, dev), passes) if q != (2, 0.0, 1)], 1e-5)


def test_an_outlier_on_the_reference_target_stays_in_its_own_run():
    """A 10 um outlier in round 3 at the reference target: it is that run's deviation there, nothing else (a
    re-zero of round 3 on it moved all of round 3 by -10 um)."""
    rng = np.random.default_rng(10)
    passes = _passes([0.0, 100.0, 200.0], 5)
    dev = _planted(passes, rng, spread_um=0.5)
    dev[(3, 0.0, 1)] += 10.0
    ev = evaluate(_build("X", passes, dev, _linear_x), axis="X").axes["X"]
    _check(ev, _relative(passes, dev), 1e-5)
    assert ev.targets["s_up"][1] < 1.5 and ev.targets["s_up"][0] > 3.0  # 100 mm untouched; 0 mm holds it


def test_a_reflector_never_read_at_the_datum_is_named():
    rng = np.random.default_rng(8)
    passes = _passes([0.0, 100.0], 1)
    rec = _build("X", passes, _planted(passes, rng), _linear_x)
    rows = [i for i in range(len(rec)) if rec.position[i] == 0.0 and rec.point[i] == "K"]
    text = format_recording(rec, precision=9).splitlines()
    for i in sorted(rows, reverse=True):
        del text[i + 1]
    with pytest.raises(InputError, match=r"cut\.csv: axis X: reflector\(s\) \['K'\] never read at the datum"):
        evaluate(parse_recording("\n".join(text) + "\n", "cut.csv"), axis="X")


# ----------------------------------------------------------------------------- end to end through simulate
@pytest.mark.parametrize("noise", [False, True])
def test_planted_scale_and_backlash_show_up_as_E_and_B(tmp_path, capsys, noise):
    """mtcal simulate with a 20 ppm scale error and 4 um backlash of X, 20 urad backlash of C (effects.py:
    positioning error + ppm q and + d amount / 2): E_up = 20e-6 * 500 mm = 10 um, B_i = 4 um; |B| of C =
    20 urad = 4.125 arcsec with B_i = -4.125 arcsec: the effect adds + d amount / 2 to E_CC, a turn about +z of
    C's stator, while a rising C turns the table about -z (T_0^w = ... Rz(-C), docs/design.md), so the table lags
    (ISO 230-2: actual - commanded C) when approached from below.  Tracker beside the machine (beam along X)."""
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({"rounds": 5, "tracker": [-1500, 225, 150],
                                "axes": {"X": {"start": 0, "stop": 500, "count": 6},
                                         "C": {"start": 0, "stop": 300, "count": 6}}}))
    rec = tmp_path / "rec.csv"
    args = ["simulate", "--plan", str(plan), "--seed", "4", "-o", str(rec), "--effect", "scale:axis=X,ppm=20",
            "--effect", "backlash:axis=X,amount=0.004", "--effect", "backlash:axis=C,amount=20e-6"]
    assert main(args + ([] if noise else ["--no-noise"])) == 0
    capsys.readouterr()
    assert main(["iso230-2", str(rec), "--json", "-o", str(tmp_path / "report")]) == 0
    out = json.loads(capsys.readouterr().out)
    x, c = out["axes"]["X"]["parameters"], out["axes"]["C"]["parameters"]
    b_c = 20e-6 * ARCSEC
    if not noise:
        assert x["E_up"] == pytest.approx(10.0, abs=1e-4) and x["E_down"] == pytest.approx(10.0, abs=1e-4)
        assert x["B"] == pytest.approx(4.0, abs=1e-4) and x["B_mean"] == pytest.approx(4.0, abs=1e-4)
        assert x["E"] == pytest.approx(14.0, abs=1e-4) and x["M"] == pytest.approx(10.0, abs=1e-4)
        assert c["B_mean"] == pytest.approx(-b_c, abs=1e-3) and c["E_up"] == pytest.approx(0.0, abs=1e-3)
        assert x["R"] == pytest.approx(4.0, abs=1e-4)  # no scatter: R_i = |B_i|
    else:  # AT960 noise, ~1.5 um per X run (the beam is not exactly along X); seeds 1-6 gave B_mean 3.64-3.99,
        # E_up 8.9-10.7 um.  C is not checked: ~10 arcsec per run across the beam at 150 mm radius
        assert x["B_mean"] == pytest.approx(4.0, abs=1.0) and x["E_up"] == pytest.approx(10.0, abs=2.5)
    files = sorted(p.name for p in (tmp_path / "report").iterdir())
    assert files == ["iso230-2_C.csv", "iso230-2_C.md", "iso230-2_C.png", "iso230-2_C_parameters.csv",
                     "iso230-2_X.csv", "iso230-2_X.md", "iso230-2_X.png", "iso230-2_X_parameters.csv"]
    table = (tmp_path / "report" / "iso230-2_X.csv").read_text().splitlines()
    assert table[0].startswith("position_mm,n_up,n_down,mean_up_um") and len(table) == 7


def test_cli_options_checked(tmp_path, capsys):
    rec = tmp_path / "r.csv"
    passes = _passes([0.0, 100.0], 2)
    rec.write_text(format_recording(_build("X", passes, {k: 0.0 for k in passes}, _linear_x)))
    assert main(["iso230-2", str(rec), "--alpha", "11.5e-6"]) == 2
    assert "--temperature-normalise" in capsys.readouterr().err
    assert main(["iso230-2", str(rec), "--axis", "Y"]) == 2
    assert "no readings of axis Y" in capsys.readouterr().err
    assert main(["iso230-2", str(rec)]) == 0
    assert "| 100 | 2 | 2 | 0.00 |" in capsys.readouterr().out


def test_tracker_results_in_the_unit_asked(tmp_path, capsys):
    """--result-unit on a tracker recording: the same evaluation in mm (um / 1000) and inch (um / 25400)."""
    rng = np.random.default_rng(11)
    passes = _passes([0.0, 100.0, 200.0], 3)
    f = tmp_path / "rec.csv"
    f.write_text(format_recording(_build("X", passes, _planted(passes, rng), _linear_x), precision=9))
    out = {}
    for unit in ("um", "mm", "inch"):
        assert main(["iso230-2", str(f), "--axis", "X", "--json", "--result-unit", unit]) == 0
        out[unit] = json.loads(capsys.readouterr().out)["axes"]["X"]
    assert out["mm"]["unit"] == "mm" and out["inch"]["unit"] == "inch"
    for k in ("A", "R", "E", "B_mean"):
        assert out["mm"]["parameters"][k] == pytest.approx(out["um"]["parameters"][k] / 1000)
        assert out["inch"]["parameters"][k] == pytest.approx(out["um"]["parameters"][k] / 25400)
