"""Issue 21, items 2-4: each controller format read back by a reader that is not mtcal's: pyLSV2's table parser
(Heidenhain, a test dependency) and readers written here from the manuals' text (Siemens K3 / 808D, Beckhoff
TF5280); a wrong sign, index, unit or range fails these tests.  Models are written here (error functions in mm / rad
as ISO 230-1 names), the oracle is the model itself evaluated at the table positions."""
from __future__ import annotations

import re

import numpy as np
import pytest

from mtcal.errors import InputError
from mtcal.export import export_model
from mtcal.kinematics.machine import load_machine
from mtcal.model.errormodel import ErrorFunction, ErrorModel

M = load_machine("dmu50")
X = np.linspace(-250, 250, 11)
C = np.arange(0.0, 341.0, 20.0)


def model(**extra) -> ErrorModel:
    f = {"E_XX": ErrorFunction("X", X, 0.02 * (X / 250) ** 2 - 0.004 * X / 250),
         "E_YX": ErrorFunction("X", X, 0.003 * (X / 250) ** 3),
         "E_CC": ErrorFunction("C", C, 30e-6 * np.sin(np.radians(C)))}
    f.update(extra)
    return ErrorModel("dmu50", {"E_C0Y": 1.5e-5}, f, {"identified_from": "test"})


# ----------------------------------------------------------------------------- Siemens (K3 Compensations, 808D)
def read_k3(text: str, e: int = 0) -> dict:
    """LEC tables of measuring system ``e`` from `%_N_AX_EEC_INI` (K3 4.4.2): {AXn: (positions, values, modulo)};
    the section must open with CHANDATA(1) and end with M17 (K3's example)."""
    sec = re.search(r"%_N_AX_EEC_INI\nCHANDATA\(1\)\n(.*?)\nM17", text, re.S)
    assert sec, "no %_N_AX_EEC_INI ... M17 section"
    vals, par = {}, {}
    for line in sec.group(1).splitlines():
        line = line.split(";")[0].strip()
        if m := re.fullmatch(rf"\$AA_ENC_COMP\[{e},(\d+),(AX\d)\]=(\S+)", line):
            vals.setdefault(m[2], {})[int(m[1])] = float(m[3])
        elif m := re.fullmatch(rf"\$AA_ENC_COMP_(STEP|MIN|MAX|IS_MODULO)\[{e},(AX\d)\]=(\S+)", line):
            par.setdefault(m[2], {})[m[1]] = float(m[3])
    out = {}
    for ax, v in vals.items():
        p = par[ax]
        n = len(v)
        pos = p["MIN"] + p["STEP"] * np.arange(n)
        assert pos[-1] == pytest.approx(p["MAX"], abs=1e-9), "K3: MAX = MIN + (N - 1) STEP"
        out[ax] = (pos, np.array([v[i] for i in range(n)]), int(p["IS_MODULO"]))
    return out


def _siemens(tmp_path, mdl=None, **options) -> str:
    out = tmp_path / "c.ini"
    export_model(mdl or model(), M, "siemens", out, options=options)
    return out.read_text()


def test_siemens_lec_is_the_error_and_the_axis_moves_by_minus_the_value(tmp_path):
    """808D Function Manual: 'A positive compensation value causes the machine axis to move in the negative
    direction': the value is the error (actual - nominal) of X at the table positions."""
    lec = read_k3(_siemens(tmp_path))
    pos, val, modulo = lec["AX1"]
    truth = model().functions["E_XX"](pos)
    assert np.abs(val - truth).max() < 1e-9 and modulo == 0
    assert np.abs(-val - truth).max() > 1e-3  # the opposite sign would double the error: this test sees it


def test_siemens_measuring_system_index_and_its_sizing_datum(tmp_path):
    """A machine whose tables sit on the second measuring system (a public archive: MD38000[0] = 0, [1] = 26):
    --measuring-system 1 writes $AA_ENC_COMP[1,N,AXi] and names MD38000[1,...]; index 0 has nothing then."""
    text = _siemens(tmp_path, measuring_system=1)
    assert read_k3(text, 0) == {} and set(read_k3(text, 1)) == {"AX1", "AX5"}
    assert "$MA_MM_ENC_COMP_MAX_POINTS[1,AX1] >=" in text and "MM_ENC_COMP_MAX_POINTS[0," not in text
    a, b = read_k3(_siemens(tmp_path), 0)["AX1"], read_k3(text, 1)["AX1"]
    assert np.array_equal(a[1], b[1])


def test_siemens_unlimited_rotary_axis_is_a_full_turn_modulo_table(tmp_path):
    """C measured 0..340 deg: the table spans 0..360 with IS_MODULO = 1 and first = last value (K3 modulo), the
    values between 340 and 360 interpolated towards the value at 0 (before: 0..340 with IS_MODULO = 0)."""
    pos, val, modulo = read_k3(_siemens(tmp_path))["AX5"]
    assert modulo == 1 and pos[0] == 0 and pos[-1] == pytest.approx(360.0) and val[0] == val[-1]
    inside = pos <= 340
    # the joint-equivalent error of C is -E_CC on the DMU 50: a rising C turns the table about -z (docs/design.md,
    # T_0^w = ... Rz(-C)), E_CC is a turn about +z
    assert np.abs(val[inside] + np.degrees(model().functions["E_CC"](pos[inside]))).max() < 1e-9


def test_siemens_header_names_every_machine_datum(tmp_path):
    text = _siemens(tmp_path, mdl=model(), control="840d")
    for datum in ("MD38000 $MA_MM_ENC_COMP_MAX_POINTS", "MD18342 $MN_MM_CEC_MAX_POINTS", "SD41300 $SN_CEC_TABLE_ENABLE",
                  "SD41310 $SN_CEC_TABLE_WEIGHT", "MD32700 $MA_ENC_COMP_ENABLE", "MD32710 $MA_CEC_ENABLE",
                  "BACK UP FIRST"):
        assert datum in text, datum
    assert "MD32450" not in text  # no backlash table: nothing to zero
    out = tmp_path / "b.ini"
    export_model(model(), M, "siemens", out,
                 diagnosis={"effects": [{"name": "backlash", "axis": "X", "significant": True, "estimate": 0.004}]})
    assert "MD32450 $MA_BACKLASH" in out.read_text() and "%_N_NC_CEC_INI\nCHANDATA(1)" in out.read_text()


@pytest.mark.parametrize("control", ["808d", "828d"])
def test_siemens_808d_828d_hold_200_points(tmp_path, control):
    text = _siemens(tmp_path, control=control)
    assert max(len(p) for p, _, _ in read_k3(text).values()) <= 200
    with pytest.raises(InputError, match=rf"{control.upper()} holds 200 interpolation points"):
        export_model(model(), M, "siemens", tmp_path / "x.ini", max_points=256, options={"control": control})


def test_siemens_828d_holds_at_most_8_cross_tables(tmp_path):
    """Six straightness tables and the two direction tables of each of two backlash findings: 10 CEC tables."""
    many = {f"E_{d}{a}": ErrorFunction(a, X, 0.002 * (X / 250) ** 2) for a in "XYZ" for d in "XYZ" if d != a}
    diag = {"effects": [{"name": "backlash", "axis": a, "significant": True, "estimate": 0.004} for a in "XY"]}
    with pytest.raises(InputError, match=r"828D holds at most 8 CEC \(sag / cross\) tables; this model needs 10"):
        export_model(model(**many), M, "siemens", tmp_path / "x.ini", diagnosis=diag, options={"control": "828d"})
    assert not (tmp_path / "x.ini").exists()
    export_model(model(**many), M, "siemens", tmp_path / "y.ini", diagnosis=diag, options={"control": "840d"})


# ----------------------------------------------------------------------------- Heidenhain (pyLSV2 reads it)
def test_heidenhain_tables_are_read_by_pylsv2_and_are_fixed_width(tmp_path):
    from pyLSV2.table_reader import NCTable
    out = tmp_path / "tnc"
    export_model(model(), M, "heidenhain", out)
    t = NCTable.parse_table(out / "X.COM")
    pos = np.array([float(r["AXISPOS"]) for r in t.rows])
    x = np.array([float(r["X"]) for r in t.rows])
    assert np.abs(x - model().functions["E_XX"](pos)).max() < 2e-6  # the error, 6 decimals
    cma = NCTable.parse_table(out / "CONFIG.CMA")
    assert cma.rows[0]["C"] == "C.COM" and cma.rows[0]["ACTIVE"] == "*"
    for name in ("X.COM", "C.COM", "CONFIG.CMA"):
        lines = (out / name).read_text().splitlines()
        header, rows = lines[1], lines[2:-1]
        assert all(len(r) == len(header) for r in rows), name  # every row padded to the full width
        starts = [m.start() for m in re.finditer(r"\S+", header)]
        for r in rows:  # each value starts under its column name and leaves a blank before the next column
            fields = [m.start() for m in re.finditer(r"\S+", r)]
            assert set(fields) <= set(starts), (name, r)
        # the older parser keyed on the blank after each name: the last column ends where the line ends
        last = header.rstrip().split()[-1]
        assert len(header) - header.index(last) >= max(len(r[header.index(last):].rstrip()) for r in rows)
    assert "-0.000000" not in (out / "X.COM").read_text()


def test_heidenhain_value_wider_than_its_column_is_refused(tmp_path):
    wide = model(E_XX=ErrorFunction("X", X, np.full_like(X, 123456789.0)))
    with pytest.raises(InputError, match=r"a TNC column holds 13"):
        export_model(wide, M, "heidenhain", tmp_path / "tnc", force=True)
    assert not (tmp_path / "tnc").exists()


def test_heidenhain_readme_names_the_layout_and_the_notes(tmp_path):
    export_model(model(), M, "heidenhain", tmp_path / "tnc", kinematics_comp=True,
                 diagnosis={"effects": [{"name": "backlash", "axis": "X", "significant": True, "estimate": 0.004}]})
    text = (tmp_path / "tnc" / "README.txt").read_text()
    for words in ("TNC 6xx / MANUALplus 620", "256 compensation points", "MP_backLash", "COMPTAB"):
        assert words in text, words


# ----------------------------------------------------------------------------- TF5280 and LinuxCNC
def test_tf5280_numbers_are_fixed_point(tmp_path):
    """Every number in the TF5280 ISG CSV documentation's examples is fixed-point: no exponent notation."""
    out = tmp_path / "v.csv"
    export_model(model(E_AX=ErrorFunction("X", X, 1.8e-5 * X / 250)), M, "tf5280", out)
    numbers = [f for ln in out.read_text().splitlines() if not ln.startswith(("//", "#"))
               for f in ln.split() if re.match(r"^[-+\d.]", f)]
    assert numbers and not [f for f in numbers if re.search(r"[eE]", f)]
    assert not [f for f in numbers if re.fullmatch(r"-0(\.0*)?", f)]


def test_linuxcnc_tables_in_the_ini_linear_units(tmp_path):
    """[TRAJ]LINEAR_UNITS = inch: positions and trims of linear joints in inch (LinuxCNC takes machine units)."""
    mm, inch = tmp_path / "mm", tmp_path / "inch"
    export_model(model(), M, "linuxcnc", mm, file_type=1)
    export_model(model(), M, "linuxcnc", inch, file_type=1, options={"linear_units": "inch"})
    a = np.loadtxt(mm / "joint0_X.comp")
    b = np.loadtxt(inch / "joint0_X.comp")
    assert np.allclose(b * 25.4, a, atol=1e-6)
    assert np.array_equal(np.loadtxt(mm / "joint4_C.comp"), np.loadtxt(inch / "joint4_C.comp"))  # deg stay deg
    assert "linear joints in inch" in (inch / "linuxcnc_comp.ini").read_text()
