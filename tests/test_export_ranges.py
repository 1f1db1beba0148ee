"""Tables within what the machine has (issue 54 item 4): a modulo table within 0..360 deg in every format that has
one (Siemens IS_MODULO, Heidenhain's TNC modulo axes), and said; no table beyond an axis' travel (B: 0..180 deg on
the DMU 50); a given `--step` checked for range and for fitting the span -- refused or stated, never silently
changed.  Read back with pyLSV2's table parser (Heidenhain) and the K3 reader of tests/test_export_formats.py; the
oracle is the model evaluated at the table positions (tests/test_siemens_tables.py's expected_c)."""
from __future__ import annotations

import json

import numpy as np
import pytest
from test_export_formats import M, read_k3
from test_siemens_tables import expected_c, partial

from mtcal.cli import main
from mtcal.errors import InputError
from mtcal.export import export_model
from mtcal.model.errormodel import ErrorFunction, ErrorModel, save_model


def _com(path) -> tuple[np.ndarray, dict]:
    from pyLSV2.table_reader import NCTable
    t = NCTable.parse_table(path)
    pos = np.array([float(r["AXISPOS"]) for r in t.rows])
    return pos, {k: np.array([float(r[k]) for r in t.rows]) for k in t.rows[0] if k not in ("NR", "AXISPOS")}


@pytest.mark.parametrize("lo,hi", [(300.0, 420.0), (-60.0, 60.0)])
def test_heidenhain_modulo_axis_is_tabled_within_one_turn_and_said(tmp_path, lo, hi):
    """C measured over 300..420 deg: main wrote 120 rows beyond 360 deg and said nothing; the TNC's modulo C runs
    0..360 deg.  The COM table holds the error (-correction), the same number Siemens' LEC writes (expected_c)."""
    model = partial(lo, hi)
    res = export_model(model, M, "heidenhain", tmp_path / "tnc")
    pos, cols = _com(tmp_path / "tnc" / "C.COM")
    assert pos[0] == 0.0 and pos[-1] == pytest.approx(360.0) and len(pos) <= 256
    assert np.abs(cols["C"] - expected_c(model, lo, hi, pos)).max() < 2e-6  # 6 decimals written
    said = [t for t in res.tables if t["axis"] == "C"][0]
    assert (said["from"], said["to"]) == (0.0, 360.0) and "modulo" in said["note"]
    assert any("modulo" in w and "C" in w for w in res.warnings), res.warnings
    assert "modulo" in (tmp_path / "tnc" / "README.txt").read_text()


def test_heidenhain_kinematics_comp_of_a_modulo_axis_is_within_one_turn(tmp_path):
    model = partial(300.0, 420.0)
    export_model(model, M, "heidenhain", tmp_path / "tnc", kinematics_comp=True)
    pos, cols = _com(tmp_path / "tnc" / "KC_C.COM")
    assert pos.min() >= 0.0 and pos.max() == pytest.approx(360.0)
    # C6 = E_CC in deg, the model at the position of the measured arc each table position stands for
    assert np.abs(cols["C6"] + expected_c(model, 300.0, 420.0, pos)).max() < 1e-8


def _b_model(lo: float = 100.0, hi: float = 170.0) -> ErrorModel:
    b = np.arange(lo, hi + 1e-9, 10.0)
    return ErrorModel("dmu50", {}, {"E_CB": ErrorFunction("B", b, 4e-6 + 1e-7 * (b - lo))}, {"identified_from": "t"})


@pytest.mark.parametrize("fmt", ["siemens", "heidenhain", "linuxcnc", "tf5280"])
def test_no_table_beyond_the_axis_travel_and_the_step_that_does_not_fit_is_said(tmp_path, fmt):
    """B measured 100..170 deg, `--step 50`: main wrote 100, 150, 200 deg, beyond B's 180 deg travel, without a
    word.  Now 80, 130, 180 deg (the step kept, the grid moved back inside the travel), the ends beyond the
    measurement held at the measured end values, and said."""
    model = _b_model()
    out = tmp_path / ("o" if fmt in ("heidenhain", "linuxcnc") else "o.txt")
    res = export_model(model, M, fmt, out, step=50.0)
    assert any("travel" in w and "B" in w for w in res.warnings), res.warnings
    if fmt == "tf5280":
        rows = [ln.split() for ln in out.read_text().splitlines() if ln[:1].isdigit()]
        pos = np.array([float(r[0]) for r in rows])
    else:
        t = [t for t in res.tables if t["axis"] == "B"][0]
        pos = t["from"] + t["step"] * np.arange(t["points"])
        assert t["step"] == 50.0
    np.testing.assert_allclose(pos, [80.0, 130.0, 180.0])
    if fmt == "siemens":
        ks = read_k3(out.read_text())["AX4"]
        np.testing.assert_allclose(ks[0], [80.0, 130.0, 180.0])
        f = model.functions["E_CB"]
        held = -np.degrees(f(np.clip(ks[0], 100.0, 170.0)))  # K3 LEC: the error; B's E_CB factor +1 on the DMU 50
        assert np.abs(np.abs(ks[1]) - np.abs(held)).max() < 1e-9


def test_a_step_that_does_not_divide_the_span_is_said(tmp_path):
    x = np.linspace(-250, 250, 11)
    model = ErrorModel("dmu50", {}, {"E_XX": ErrorFunction("X", x, 1e-5 * x)}, {"identified_from": "t"})
    res = export_model(model, M, "linuxcnc", tmp_path / "lc", step=30.0)
    t = res.tables[0]
    assert (t["from"], t["to"], t["step"]) == (-250.0, 260.0, 30.0)
    assert any("does not divide" in w and "500" in w for w in res.warnings), res.warnings


@pytest.mark.parametrize("step,words", [(5e-324, "finer than 1e-06"),
                                        (600.0, "larger than the measured span")])
def test_a_step_out_of_range_is_one_line_and_nothing_is_written(tmp_path, capsys, step, words):
    """`--step 5e-324` ended in OverflowError (exit 1, "internal error") on main."""
    path = tmp_path / "m.json"
    x = np.linspace(-250, 250, 11)
    save_model(ErrorModel("dmu50", {}, {"E_XX": ErrorFunction("X", x, 1e-5 * x)}, {"identified_from": "t"}), path)
    for fmt, out in (("siemens", "c.mpf"), ("linuxcnc", "lc"), ("etalon", "e.txt"), ("heidenhain", "tnc")):
        code = main(["export", str(path), "--format", fmt, "-o", str(tmp_path / out), "--step", repr(step)])
        err = capsys.readouterr().err
        assert code == 2 and words in err and "step" in err and len(err.strip().splitlines()) == 1, err
        assert not (tmp_path / out).exists()


@pytest.mark.parametrize("fmt", ["siemens", "heidenhain"])
def test_a_modulo_step_that_does_not_divide_the_turn_is_refused_not_changed(tmp_path, capsys, fmt):
    """`--step 7` on the modulo table of C: main wrote 6 deg silently (Siemens).  360/7 is no whole number of steps:
    refused naming the nearest steps that are (6 and 7.2 deg); a step that divides the turn is kept."""
    path = tmp_path / "m.json"
    save_model(partial(0.0, 340.0), path)
    out = tmp_path / ("c.mpf" if fmt == "siemens" else "tnc")
    code = main(["export", str(path), "--format", fmt, "-o", str(out), "--step", "7"])
    err = capsys.readouterr().err
    assert code == 2 and "does not divide 360 deg" in err and "6 or 7.2 deg" in err and not out.exists(), err
    assert main(["export", str(path), "--format", fmt, "-o", str(out), "--step", "7.2", "--json"]) == 0
    c = [t for t in json.loads(capsys.readouterr().out)["tables"] if t["axis"] == "C"][0]
    assert c["step"] == pytest.approx(7.2) and (c["from"], c["to"], c["points"]) == (0.0, 360.0, 51)


def test_the_modulo_step_the_control_cannot_hold_is_still_refused_with_its_bound(tmp_path):
    with pytest.raises(InputError, match=r"a full turn at step 1 deg needs 361 points.*holds 256"):
        export_model(partial(300.0, 420.0, False), M, "heidenhain", tmp_path / "tnc", step=1.0)
    assert not (tmp_path / "tnc").exists()
