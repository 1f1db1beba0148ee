"""Issue 21, item 1: one plausibility guard (mtcal.model.plausibility) for everything that reaches a machine, and an
export that writes atomically, removes the stale tables of an earlier export and writes nothing on refusal.
Each case failed on the main before it: tables moved an axis by 23 mm (a model in um read as mm), 1e300 was
written as 1e+300, a B table over 0..270 deg was written for an axis that travels 0..180, other commands' JSON
was refused as `units: unknown key(s)` or gave an MPF without tables, a backlash in um was written as mm, earlier
tables stayed beside a re-export."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from mtcal.cli import main
from mtcal.demo.run import data_path
from mtcal.identify.run import identify
from mtcal.measurement.recordings import read_recording
from mtcal.model.errormodel import save_model

FORMATS = ["linuxcnc", "siemens", "heidenhain", "tf5280", "etalon"]


@pytest.fixture(scope="module")
def model_json(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("m")
    res = identify(read_recording(data_path("demo_campaign.csv")), method="three-point", worth=False)
    save_model(res.model, d / "model.json")
    return d / "model.json"


def _variant(src: Path, dst: Path, change) -> Path:
    m = json.loads(src.read_text())
    change(m)
    dst.write_text(json.dumps(m))
    return dst


def _um_as_mm(m):
    for n, f in m["functions"].items():
        if n[2] in "XYZ":
            f["values"] = [v * 1000 for v in f["values"]]
            f.pop("fit", None)


def _export(tmp_path, capsys, model, fmt, *extra):
    out = tmp_path / f"out_{fmt}"
    code = main(["export", str(model), "--format", fmt, "-o", str(out), *extra])
    return code, capsys.readouterr(), out


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("change,message", [
    (_um_as_mm, r"um at .* is beyond the plausibility bound 1000 um \(a model in um or urad read as mm"),
    (lambda m: m["constants"].update(E_C0Y=1e300), r"constant E_C0Y = 1e\+306 urad is beyond"),
    (lambda m: m["functions"]["E_XB"].update(positions=[p * 1.5 for p in m["functions"]["E_XB"]["positions"]],
                                             fit=None),
     r"E_XB: its table spans B = 0\.\.270 deg, outside the axis' travel \[0, 180\] deg"),
])
def test_an_implausible_model_is_refused_in_every_format_and_nothing_is_written(tmp_path, capsys, model_json, fmt,
                                                                                change, message):
    import re
    bad = _variant(model_json, tmp_path / "bad.json", change)
    code, cap, out = _export(tmp_path, capsys, bad, fmt)
    assert code == 2 and re.search(message, cap.err) and "bad.json" in cap.err, cap.err
    assert not out.exists() and not list(tmp_path.glob(".out_*"))
    code, cap, out = _export(tmp_path, capsys, bad, fmt, "--force")  # the user who knows better: loud warning
    if fmt == "heidenhain" and code == 2:  # 1e300 mm does not fit a 14-character TNC column: still refused
        assert "a TNC column holds 13" in cap.err and not out.exists()
        return
    assert code == 0 and "FORCED past the plausibility guard" in cap.err


@pytest.mark.parametrize("answer,cmd", [
    ({"base_sigma": 0.01, "effects": [], "located": []}, "diagnose"),
    ({"alpha": 1e-6, "beta": 0.0, "gamma": 0.0, "sigma": 1e-6}, "plate"),
    ({"axes": {}, "squareness": {}, "weighted": True, "source": "r.csv"}, "identify --json"),
    ({"program": "p.nc", "residual": {}, "lines": 3}, "compensate --json"),
])
def test_another_commands_answer_as_the_model_is_named(tmp_path, capsys, answer, cmd):
    f = tmp_path / "answer.json"
    f.write_text(json.dumps(answer))
    code, cap, out = _export(tmp_path, capsys, f, "siemens")
    assert code == 2 and f"this is the JSON answer of `mtcal {cmd}`, not an error model" in cap.err
    assert not out.exists()


@pytest.mark.parametrize("fmt", FORMATS)
def test_constants_only_or_empty_models_are_refused(tmp_path, capsys, fmt):
    for consts, words in (({}, "an empty model"), ({"E_C0Y": 1e-5}, None)):
        f = tmp_path / "m.json"
        f.write_text(json.dumps({"machine": "dmu50", "constants": consts, "functions": {}}))
        code, cap, out = _export(tmp_path, capsys, f, fmt)
        held = fmt in ("tf5280", "etalon") and consts  # their files hold the squareness itself
        assert (code == 0) if held else (code == 2 and "has nothing format" in cap.err), (fmt, cap.err)
        if words and code == 2:
            assert words in cap.err


def test_the_model_of_another_machine_is_refused(tmp_path, capsys, model_json):
    code, cap, out = _export(tmp_path, capsys, model_json, "linuxcnc", "--machine", "headbc")
    assert code == 2 and "the model is of machine dmu50, not headbc" in cap.err and not out.exists()


def _diag(tmp_path, unit="mm", amount=0.005, recording=None, machine="dmu50"):
    d = {"machine": machine, "recording": recording or str(data_path("demo_campaign.csv")), "base_sigma": 0.01,
         "effects": [{"name": "backlash", "axis": "X", "significant": True, "estimate": amount, "unit": unit}]}
    f = tmp_path / "diag.json"
    f.write_text(json.dumps(d))
    return f


def test_a_backlash_in_um_is_converted_and_its_double_compensation_is_warned(tmp_path, capsys, model_json):
    """5 um and 0.005 mm give the same direction-dependent table; the answer says to zero the controller's own
    backlash compensation ([JOINT_n]BACKLASH)."""
    texts = []
    for unit, amount in (("mm", 0.005), ("um", 5.0)):
        code, cap, out = _export(tmp_path / unit, capsys, model_json, "linuxcnc", "--diagnosis",
                                 str(_diag(tmp_path, unit, amount)), "--json")
        assert code == 0, cap.err
        texts.append((out / "joint0_X.comp").read_text())
        assert "[JOINT_n]BACKLASH" in cap.out  # the instruction, in the answer's warnings
    assert texts[0] == texts[1]
    rows = np.array([[float(v) for v in ln.split()] for ln in texts[0].splitlines()])
    assert np.allclose(rows[:, 2] - rows[:, 1], -0.005, atol=1e-9) or np.allclose(rows[:, 1] - rows[:, 2], 0.005)


def test_a_diagnosis_of_another_recording_or_machine_is_refused(tmp_path, capsys, model_json):
    code, cap, out = _export(tmp_path, capsys, model_json, "linuxcnc", "--diagnosis",
                             str(_diag(tmp_path, recording="other_campaign.csv")))
    assert code == 2 and "diagnoses other_campaign.csv" in cap.err and not out.exists()
    code, cap, out = _export(tmp_path, capsys, model_json, "linuxcnc", "--diagnosis",
                             str(_diag(tmp_path, machine="xyzac")))
    assert code == 2 and "a diagnosis of machine xyzac" in cap.err


@pytest.mark.parametrize("fmt,stale", [("linuxcnc", "joint1_Y.comp"), ("heidenhain", "Y.COM")])
def test_a_re_export_leaves_no_stale_table(tmp_path, capsys, model_json, fmt, stale):
    only_x = _variant(model_json, tmp_path / "x.json",
                      lambda m: m.update(functions={k: v for k, v in m["functions"].items() if k == "E_XX"},
                                         constants={}))
    code, cap, out = _export(tmp_path, capsys, model_json, fmt)
    assert code == 0 and (out / stale).exists()
    (out / "mine.txt").write_text("the user's own file")
    code, cap, out = _export(tmp_path, capsys, only_x, fmt)
    assert code == 0 and not (out / stale).exists() and f"{stale}: a table of an earlier export" in cap.err
    assert (out / "mine.txt").exists() and not list(tmp_path.glob(f".out_{fmt}.*"))


def test_an_output_over_an_input_is_refused(tmp_path, capsys, model_json):
    code = main(["export", str(model_json), "--format", "siemens", "-o", str(model_json)])
    assert code == 2 and "input" in capsys.readouterr().err


def test_compensate_shares_the_guard(tmp_path, capsys, model_json):
    bad = _variant(model_json, tmp_path / "bad.json", _um_as_mm)
    out = tmp_path / "o.nc"
    code = main(["compensate", str(data_path("sample_5axis.nc")), "--model", str(bad), "-o", str(out)])
    assert code == 2 and "beyond the plausibility bound" in capsys.readouterr().err and not out.exists()
