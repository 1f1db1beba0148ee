"""Siemens rotary tables as the controls take them and as the command prints them (issue 36, Siemens): a rotary
axis measured over less than a turn becomes a full 0..360 modulo table with the unmeasured arc held at the nearer
measured end and said; the file's MIN / MAX / STEP / points equal what is printed; 828D / 808D limits as their
manuals state them (K3 03/2013 sec. 4.4.4.3 note on 828D; 808D Function Manual 01/2017 p. 109 on modulo tables).
Read back with the K3 reader of tests/test_export_formats.py (written from the manual's text)."""
from __future__ import annotations

import json
import re

import numpy as np
import pytest
from test_export_formats import M, X, read_k3

from mtcal.cli import main
from mtcal.errors import InputError
from mtcal.export import export_model
from mtcal.model.errormodel import ErrorFunction, ErrorModel, save_model

SLOPE = 2e-7  # rad per deg: a linear E_CC, so that resampling the table is exact


def partial(lo: float, hi: float, with_x: bool = True, **extra) -> ErrorModel:
    c = np.arange(lo, hi + 1e-9, 10.0)
    f = {"E_CC": ErrorFunction("C", c, 5e-6 + SLOPE * (c - lo))}
    if with_x:
        f["E_XX"] = ErrorFunction("X", X, 0.01 * (X / 250) ** 2)
    f.update(extra)
    return ErrorModel("dmu50", {}, f, {"identified_from": "test"})


def expected_c(model: ErrorModel, lo: float, hi: float, pos: np.ndarray) -> np.ndarray:
    """The LEC value of C (deg; -E_CC on the DMU 50, test_export_formats) at table positions 0..360: the model at
    the position of the measured arc it stands for, the unmeasured arc held at the nearer measured end."""
    u = np.mod(pos - lo, 360.0)
    span = hi - lo
    inside = u <= span + 1e-9
    nearer_hi = (u - span) <= (360.0 - u)
    at = np.where(inside, lo + u, np.where(nearer_hi, hi, lo))
    return -np.degrees(model.functions["E_CC"](at))


@pytest.mark.parametrize("lo,hi", [(300.0, 420.0), (-60.0, 60.0)])
def test_a_partial_turn_is_a_full_modulo_table_with_the_unmeasured_arc_held_and_said(tmp_path, lo, hi):
    model = partial(lo, hi)
    res = export_model(model, M, "siemens", tmp_path / "c.mpf")
    text = (tmp_path / "c.mpf").read_text()
    pos, val, modulo = read_k3(text)["AX5"]
    assert modulo == 1 and pos[0] == 0 and pos[-1] == pytest.approx(360.0) and val[0] == val[-1]
    assert np.abs(val - expected_c(model, lo, hi, pos)).max() < 1e-9
    said = [t for t in res.tables if t["axis"] == "C"][0]
    assert (said["points"], said["from"], said["to"]) == (len(pos), 0.0, 360.0)
    assert said["step"] == pytest.approx(pos[1] - pos[0])
    assert "60" in said["note"] and "300" in said["note"] and "held" in said["note"], said
    assert "not measured" in text and "held" in text


def test_the_printed_table_is_the_table_in_the_file(tmp_path, capsys):
    path = tmp_path / "m.json"
    save_model(partial(300.0, 420.0), path)
    out = tmp_path / "c.mpf"
    assert main(["export", str(path), "--format", "siemens", "-o", str(out), "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)["tables"]
    text = out.read_text()
    names = dict(reversed(p.split(" = ")) for p in re.search(r"; axes: (.*?) \(", text)[1].split(", "))
    assert len(read_k3(text)) == 2  # X and C
    for ax, (pos, _, _) in read_k3(text).items():
        t = next(t for t in printed if t["axis"] == names[ax])
        m_min = float(re.search(rf"\$AA_ENC_COMP_MIN\[0,{ax}\]=(\S+)", text)[1])
        m_max = float(re.search(rf"\$AA_ENC_COMP_MAX\[0,{ax}\]=(\S+)", text)[1])
        m_step = float(re.search(rf"\$AA_ENC_COMP_STEP\[0,{ax}\]=(\S+)", text)[1])
        assert (t["points"], t["from"], t["to"]) == (len(pos), m_min, m_max), (ax, t)
        assert t["step"] == pytest.approx(m_step, abs=1e-9)


@pytest.mark.parametrize("control", ["828d", "808d"])
def test_default_export_on_the_smaller_controls_fits_a_full_turn(tmp_path, control):
    res = export_model(partial(300.0, 420.0), M, "siemens", tmp_path / "c.mpf", options={"control": control})
    pos, _, modulo = read_k3((tmp_path / "c.mpf").read_text())["AX5"]
    assert modulo == 1 and len(pos) <= 200 and pos[-1] == pytest.approx(360.0)
    assert [t["points"] for t in res.tables if t["axis"] == "C"] == [len(pos)]
    with pytest.raises(InputError, match=r"a full turn at step 1 deg needs 361 points.*holds 200.*at least 1\.875 deg"):
        export_model(partial(300.0, 420.0, False), M, "siemens", tmp_path / "d.mpf", step=1.0,
                     options={"control": control})


def cross_model() -> ErrorModel:
    many = {f"E_{d}{a}": ErrorFunction(a, X, 0.002 * (X / 250) ** 2) for a in "XYZ" for d in "XYZ" if d != a}
    return partial(0.0, 340.0, **many)


def test_md32711_and_the_metric_basic_system_are_named(tmp_path):
    export_model(cross_model(), M, "siemens", tmp_path / "c.mpf")
    text = (tmp_path / "c.mpf").read_text()
    assert "MD32711 $MA_CEC_SCALING_SYSTEM_METRIC" in text and "MD10240 $MN_SCALING_SYSTEM_IS_METRIC" in text


def test_828d_tables_said_as_they_are_and_its_refusal_true(tmp_path):
    diag = {"effects": [{"name": "backlash", "axis": "X", "significant": True, "estimate": 0.004}]}
    model = partial(0.0, 340.0, **{k: v for k, v in cross_model().functions.items() if k in ("E_YX", "E_ZX")})
    export_model(model, M, "siemens", tmp_path / "c.mpf", diagnosis=diag, options={"control": "828d"})
    text = (tmp_path / "c.mpf").read_text()
    assert "MD18342" not in text and "8 tables of 200 interpolation points" in text
    diag["effects"].append({"name": "backlash", "axis": "Y", "significant": True, "estimate": 0.004})
    with pytest.raises(InputError) as err:  # 6 straightness and 2 x 2 reversal tables
        export_model(cross_model(), M, "siemens", tmp_path / "x.mpf", diagnosis=diag, options={"control": "828d"})
    assert "holds at most 8 CEC" in str(err.value) and "require" not in str(err.value)
    assert "mtcal compensate" in str(err.value)


def test_808d_writes_no_cec_table_its_manual_does_not_describe(tmp_path):
    res = export_model(cross_model(), M, "siemens", tmp_path / "c.mpf", options={"control": "808d"})
    text = (tmp_path / "c.mpf").read_text()
    assert "%_N_NC_CEC_INI" not in text and "$AN_CEC" not in text
    assert "E_YX" in res.not_held and any("808D" in w and "CEC" in w for w in res.warnings)
    with pytest.raises(InputError, match="cannot hold E_YX"):
        export_model(cross_model(), M, "siemens", tmp_path / "y.mpf", require=["E_YX"], options={"control": "808d"})
