"""Error-model JSON schema (mtcal.model.errormodel.model_from_dict, mtcal.model.schema): every command that reads a
model refuses a
wrong shape, type, name, axis or unit in one line naming the file and the field."""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from mtcal.cli import main
from mtcal.errors import InputError
from mtcal.model.errormodel import load_model, model_from_dict

DATA = Path(__file__).resolve().parents[1] / "mtcal" / "data"
FUNC = {"axis": "X", "positions": [0, 100, 200], "values": [0.0, 0.001, 0.003]}
POLY = {"kind": "polynomial", "coefficients": [0.001, 0.002], "domain": [0, 200]}
HARM = {"kind": "harmonic", "period": 360, "a0": 0.0, "cos": [1e-6], "sin": [2e-6]}


def _m(**kw) -> dict:
    return {"machine": "dmu50", "units": {"length": "mm", "angle": "rad"}, "constants": {}, "functions": {}, **kw}


BAD = [
    ([1, 2], "the model must be an object {...}, got [1, 2]"),
    (_m(constants=[1, 2]), "constants must be an object"),
    (_m(functions="E_XX"), "functions must be an object"),
    (_m(constants={"E_XX": True}), "constants.E_XX must be a finite number, got True"),
    (_m(constants={"E_C0Y": "18"}), "constants.E_C0Y must be a finite number, got '18'"),
    (_m(constants={"E_C0Y": None}), "constants.E_C0Y must be a finite number, got None"),
    (_m(constants={"E_QQ": 1.0}), "constants: 'E_QQ' is not an error of machine dmu50"),
    (_m(functions={"E_XX": {**FUNC, "axis": "Y"}}),
     "functions.E_XX: axis must be 'X' (E_XX is a function of X), got 'Y'"),
    (_m(functions={"E_C0Y": {**FUNC, "axis": "Y"}}), "functions.E_C0Y: E_C0Y is a constant"),
    (_m(functions={"E_XX": {**FUNC, "values": [0, 1]}}), "functions.E_XX: 3 positions but 2 values"),
    (_m(functions={"E_XX": {**FUNC, "values": [0, True, 1]}}), "functions.E_XX.values[1] must be a finite number"),
    (_m(functions={"E_XX": {**FUNC, "positions": [0, 200, 100]}}), "functions.E_XX.positions must increase strictly"),
    (_m(functions={"E_XX": {**FUNC, "positions": "0..200"}}), "functions.E_XX.positions must be a list of at least 2"),
    (_m(functions={"E_XX": {**FUNC, "fit": {"kind": "polynomial", "domain": [0, 200]}}}),
     "functions.E_XX.fit: a polynomial fit needs coefficients, domain; missing coefficients"),
    (_m(functions={"E_CC": {**FUNC, "axis": "C", "fit": {"kind": "harmonic", "period": 360, "a0": 0}}}),
     "functions.E_CC.fit: a harmonic fit needs period, a0, cos, sin; missing cos, sin"),
    (_m(functions={"E_CC": {**FUNC, "axis": "C", "fit": {**HARM, "period": 0}}}),
     "functions.E_CC.fit.period must be a positive number"),
    (_m(functions={"E_XX": {**FUNC, "fit": {**POLY, "domain": [200, 0]}}}), "domain must be [lo, hi] with lo < hi"),
    (_m(functions={"E_XX": {**FUNC, "fit": {"kind": "spline"}}}), "functions.E_XX.fit.kind must be one of"),
    (_m(units={"length": "furlong", "angle": "rad"}), "units: length must be one of"),
    (_m(units={"length": "mm", "angle": "rad", "time": "s"}), "units: unknown key(s) ['time']"),
    (_m(machine="dmu60"), "machine: unknown machine 'dmu60'"),
]


@pytest.mark.parametrize("raw, message", BAD)
def test_bad_models_refused_naming_the_field(raw, message):
    with pytest.raises(InputError) as exc:
        model_from_dict(raw, "m.json")
    assert message in str(exc.value) and str(exc.value).startswith("m.json: ")


def test_json_nan_is_refused(tmp_path):
    f = tmp_path / "m.json"
    f.write_text('{"constants": {"E_C0Y": NaN}}')
    with pytest.raises(InputError, match=r"m\.json: constants\.E_C0Y must be a finite number, got nan"):
        load_model(f)


def test_bad_json_names_file_and_line(tmp_path):
    f = tmp_path / "m.json"
    f.write_text('{"constants": {\n  "E_C0Y": 1e-5,\n}}\n')
    with pytest.raises(InputError, match=r"m\.json:3: not valid JSON"):
        load_model(f)


def test_units_are_converted_to_mm_and_rad():
    """um, inch, urad, deg: values times 1e-3, 25.4, 1e-6, pi/180 (the definitions of the units)."""
    m = model_from_dict(_m(units={"length": "um", "angle": "urad"}, constants={"E_X0C": 12.5, "E_C0Y": 18.0},
                           functions={"E_XX": {**FUNC, "values": [0, 1, 3]}}))
    assert m.constants["E_X0C"] == pytest.approx(0.0125, rel=1e-15)
    assert m.constants["E_C0Y"] == pytest.approx(18e-6, rel=1e-15)
    assert m.functions["E_XX"].values.tolist() == pytest.approx([0.0, 0.001, 0.003], rel=1e-15)
    m = model_from_dict(_m(units={"length": "inch", "angle": "deg"}, constants={"E_X0C": 0.001, "E_C0Y": 0.01}))
    assert m.constants["E_X0C"] == pytest.approx(0.0254, rel=1e-15)
    assert m.constants["E_C0Y"] == pytest.approx(0.01 * math.pi / 180, rel=1e-15)


def test_a_valid_model_with_fits_loads():
    m = model_from_dict(_m(functions={"E_XX": {**FUNC, "fit": POLY},
                                      "E_CC": {"axis": "C", "positions": [0, 180, 340], "values": [0, 1e-6, 0],
                                               "fit": HARM}}))
    assert m.functions["E_XX"](100.0) == pytest.approx(0.001 + 0.002 * 0.0)  # domain [0, 200]: x = 100 -> 0
    assert m.functions["E_CC"](90.0) == pytest.approx(2e-6)  # sin(90 deg) * 2e-6


@pytest.mark.parametrize("command", ["compensate", "diagnose", "simulate"])
@pytest.mark.parametrize("raw, message", [BAD[0], BAD[3], BAD[7], BAD[13]])
def test_every_command_reading_a_model_refuses_it(tmp_path, capsys, command, raw, message):
    model = tmp_path / "bad.json"
    model.write_text(json.dumps(raw))
    argv = {"compensate": ["compensate", str(DATA / "sample_5axis.nc"), "--model", str(model), "-o",
                           str(tmp_path / "o.nc")],
            "diagnose": ["diagnose", str(DATA / "demo_campaign.csv"), "--model", str(model)],
            "simulate": ["simulate", "--model", str(model), "-o", str(tmp_path / "r.csv")]}[command]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err == f"mtcal {command}: error: {model}: {message}" + err.split(message, 1)[1]
    assert err.count("\n") == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.json"]


# ----------------------------------------------------------------------------- plan JSON (mtcal.campaign.simulate)
@pytest.mark.parametrize("raw, message", [
    ([1], "a plan must be a JSON object"),
    ({"tracker": [True, 0, 0]}, "tracker must be [x, y, z] in mm (three finite numbers), got [True, 0, 0]"),
    ({"tracker": [1, 2]}, "tracker must be [x, y, z] in mm"),
    ({"axes": {"X": {"positions": [0, "100"]}}}, "axes.X.positions[1] must be a finite number, got '100'"),
    ({"axes": {"X": {"start": 0, "stop": 500, "count": 1}}}, "axes.X.count must be a whole number >= 2, got 1"),
    ({"axes": {"X": {"start": 0, "stop": None, "count": 5}}}, "axes.X.stop must be a finite number, got None"),
    ({"axes": {"C": {"positions": [0, 90], "at": {"B": "12"}}}}, "axes.C.at.B must be a finite number, got '12'"),
    ({"points": {"tool": {"A": [0, 0, 0], "B": [1, 0, False], "C": [0, 1, 0]}}}, "point 'B' must be [x, y, z]"),
    ({"rounds": True}, "rounds must be a positive integer, got True"),
])
def test_bad_plans_refused_naming_the_field(raw, message):
    from mtcal.campaign.plans import plan_from_dict
    with pytest.raises(InputError) as exc:
        plan_from_dict(raw, "plan.json")
    assert str(exc.value).startswith("plan.json: ") and message in str(exc.value)


def test_plan_pose_outside_the_axis_limits_is_refused(tmp_path, capsys):
    """B = 270 held while C is measured: outside dmu50's B limits [0, 180] (derive/machines/dmu50.toml)."""
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({"axes": {"C": {"positions": [0, 90, 180], "at": {"B": 270}}}}))
    assert main(["simulate", "--plan", str(plan), "-o", str(tmp_path / "r.csv")]) == 2
    err = capsys.readouterr().err
    assert err == (f"mtcal simulate: error: {plan}: measuring axis C puts B at 270 deg, outside its range [0, 180] deg "
                   "on dmu50\n")
    assert not (tmp_path / "r.csv").exists()


@pytest.mark.parametrize("effect, message", [
    ("periodic:axis=X,pitch=0", "effect periodic: pitch='0': must be positive"),
    ("periodic:axis=X,amplitude=1e300", "simulated reading of axis X at"),
    ("thermal_drift:tau_s=-5", "effect thermal_drift: tau_s='-5': must be positive"),
])
def test_effects_that_would_write_nan_are_refused(tmp_path, capsys, effect, message):
    out = tmp_path / "r.csv"
    assert main(["simulate", "--effect", effect, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and err.startswith("mtcal simulate: error: ") and err.count("\n") == 1
    assert not out.exists()


def test_huge_effect_without_noise_is_refused(tmp_path, capsys):
    """Finite but absurd (1e300 mm): refused as well, not written."""
    out = tmp_path / "r.csv"
    assert main(["simulate", "--no-noise", "--effect", "periodic:axis=X,amplitude=1e300", "-o", str(out)]) == 2
    assert "beyond 1e+06 mm" in capsys.readouterr().err and not out.exists()
