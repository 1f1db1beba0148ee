"""Files people export: byte-order mark, ';' with decimal commas, Windows-1252 comments, empty and binary files,
for the recording and plate readers (mtcal.io.read_text / read_csv_rows).  Oracle: the same data written as a
plain UTF-8, comma-separated file must read to identical numbers."""
from __future__ import annotations

import json
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from mtcal.cli import main
from mtcal.errors import InputError, InputWarning
from mtcal.measurement.recordings import read_recording
from mtcal.plate.reversal import read_plate_csv

DATA = Path(__file__).resolve().parents[1] / "mtcal" / "data"
REC = ("axis,round,position,point,x,y,z\n"
       "X,1,0,P,10.5,0.25,-3.125\nX,1,100,P,110.5,0.5,-3.0\nX,1,200,P,210.75,0.125,-2.5\n")


def _rec(path: Path):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        rec = read_recording(path)
    return rec, [str(x.message) for x in w if issubclass(x.category, InputWarning)]


def _german(text: str) -> str:
    """Excel (German locale) CSV: ';' separators, decimal commas."""
    return "\n".join(";".join(f.replace(".", ",") for f in line.split(",")) for line in text.splitlines()) + "\n"


def test_bom_and_plain_read_alike(tmp_path):
    plain, bom = tmp_path / "plain.csv", tmp_path / "bom.csv"
    plain.write_text(REC)
    bom.write_bytes(b"\xef\xbb\xbf" + REC.encode())
    a, wa = _rec(plain)
    b, wb = _rec(bom)
    assert wa == wb == []
    np.testing.assert_array_equal(a.xyz, b.xyz)
    assert b.axis.tolist() == ["X", "X", "X"]


def test_semicolon_decimal_comma_detected_and_said(tmp_path):
    f = tmp_path / "excel_de.csv"
    f.write_bytes(b"\xef\xbb\xbf" + _german(REC).encode("cp1252"))
    rec, said = _rec(f)
    np.testing.assert_array_equal(rec.xyz, [[10.5, 0.25, -3.125], [110.5, 0.5, -3.0], [210.75, 0.125, -2.5]])
    assert rec.position.tolist() == [0.0, 100.0, 200.0]
    assert len(said) == 1 and str(f) in said[0] and "';'-separated" in said[0] and "decimal comma" in said[0]


def test_cp1252_comment_is_read_with_a_warning(tmp_path):
    f = tmp_path / "win.csv"
    f.write_bytes("# probe 20 \u00b0C, \u00b5m resolution\n".encode("cp1252") + REC.encode())
    rec, said = _rec(f)
    assert len(rec) == 3
    assert len(said) == 1 and f"{f}:1: not UTF-8; read as cp1252" in said[0]


@pytest.mark.parametrize("content, message", [
    (b"", "empty recording file"),
    (b"\n  \n", "empty recording file"),
    (b"# only a comment\n", "empty recording file"),
    (b"axis,round,position,point,x,y,z\nX,1,0,P\x00,1,2,3\n", ":2: NUL byte: a binary file, not a recording file"),
    (b"axis,round,position,point,x,y,z\n", "header but no data rows"),
    (REC.replace("0.25", "1,25").encode(), "rec.csv:2: 8 fields, header has 7"),
    (REC.replace("110.5", "abc").encode(), "rec.csv:3: column 'x' is not a number: 'abc'"),
    (REC.replace("X,1,200", "W,1,200").encode(), "rec.csv:4: axis 'W' is not one of"),
])
def test_bad_recordings_name_file_and_line(tmp_path, content, message):
    f = tmp_path / "rec.csv"
    f.write_bytes(content)
    with pytest.raises(InputError, match=None) as exc:
        read_recording(f)
    assert str(f) in str(exc.value) and message in str(exc.value)


def test_missing_and_directory_inputs(tmp_path):
    with pytest.raises(InputError, match="recording file not found"):
        read_recording(tmp_path / "nope.csv")
    with pytest.raises(InputError, match="is a directory, expected a plate file"):
        read_plate_csv(tmp_path)


def test_plate_exports_read_like_the_original(tmp_path, capsys):
    """NBS Table 2 (inches) as a German Excel export with a BOM and a Latin-1 comment: same fit, warning said."""
    text = (DATA / "nbs_table2_corrected.csv").read_text()
    body = "\n".join(ln for ln in text.splitlines() if not ln.startswith("#"))
    f = tmp_path / "plate_de.csv"
    f.write_bytes(b"\xef\xbb\xbf" + "# Messung bei 20 \u00b0C\n".encode("latin-1") + _german(body).encode("latin-1"))
    assert main(["plate", str(f), "--json"]) == 0
    cap = capsys.readouterr()
    got = json.loads(cap.out)
    assert "read as cp1252" in cap.err and "';'-separated" in cap.err
    assert main(["plate", str(DATA / "nbs_table2_corrected.csv"), "--json"]) == 0
    ref = json.loads(capsys.readouterr().out)
    for k in ("alpha", "beta", "gamma", "ex", "ey", "sigma"):
        assert got[k] == ref[k], k


def test_cli_warning_is_one_line_naming_the_file(tmp_path, capsys):
    text = (DATA / "nbs_table2_corrected.csv").read_text()
    f = tmp_path / "p.csv"
    f.write_text(_german("\n".join(ln for ln in text.splitlines() if not ln.startswith("#"))))
    assert main(["plate", str(f)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    # 13 points x 4 coordinates with decimals
    assert err == [f"mtcal plate: warning: {f}: ';'-separated (spreadsheet export); 52 decimal comma(s) read as "
                   "decimal points"]


@pytest.mark.parametrize("content, message", [
    (b"", "empty plate file"),
    (b"point,x1,y1,x2,y2\n1,0,0,\x00,0\n", "plate.csv:2: NUL byte"),
    (b"point,x1,y1,x2,y2\n1,0,0,0,0\n2,1e400,0,0,0\n", "plate.csv:3: column x1: '1e400' is not a finite number"),
])
def test_bad_plates_name_file_and_line(tmp_path, capsys, content, message):
    f = tmp_path / "plate.csv"
    f.write_bytes(content)
    assert main(["plate", str(f)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("mtcal plate: error: ") and message in err and err.count("\n") == 1


# ----------------------------------------------------------------------------- issue 20: messages that name the problem
def _write(path, data):
    path.write_bytes(data if isinstance(data, bytes) else data.encode())
    return path


def _demo_rows(pattern: str) -> str:
    from mtcal.demo.run import data_path
    lines = data_path("demo_campaign.csv").read_text().splitlines()
    return "\n".join([lines[0]] + [ln for ln in lines[1:] if re.match(pattern, ln)]) + "\n"


def test_an_axis_measured_at_one_position_is_named_with_the_file(tmp_path, capsys):
    from mtcal.cli import main
    f = tmp_path / "one.csv"
    f.write_text(_demo_rows(r"X,[12],0,"))
    assert main(["identify", str(f), "--method", "three-point"]) == 2
    assert f"{f}: axis X is measured at one position only (0, lines 2" in capsys.readouterr().err


def test_tab_separated_and_utf16_recordings_are_read(tmp_path):
    from mtcal.measurement.recordings import read_recording
    text = _demo_rows(r"X,1,")
    ref = read_recording(_write(tmp_path / "c.csv", text))
    for name, data, said in (("t.csv", text.replace(",", "\t").encode(), "tab-separated"),
                             ("u.csv", text.encode("utf-16"), "UTF-16"),
                             ("v.csv", text.replace(",", "\t").encode("utf-16-le"), "read as utf-16-le")):
        with pytest.warns(UserWarning) as got:  # read, and said (a tab CSV was "missing column(s)", UTF-16
            rec = read_recording(_write(tmp_path / name, data))  # "a binary file")
        assert any(said in str(w.message) for w in got), [str(w.message) for w in got]
        np.testing.assert_array_equal(rec.xyz, ref.xyz)


def test_a_value_just_outside_an_axis_range_is_printed_as_given(capsys):
    from mtcal import load_machine
    from mtcal.errors import InputError
    with pytest.raises(InputError, match=r"B = 180\.0001 deg"):
        load_machine("dmu50").check_axes(np.array([[0, 0, 0, 180.0001, 0]]))


def test_inspire_axis_that_is_no_axis_is_named(tmp_path, capsys):
    from mtcal.cli import main
    f = _write(tmp_path / "r1.csv", "K,1,2,3\n")
    assert main(["identify", str(f), "--layout", "inspire", "--axis", "Q"]) == 2
    assert "--axis Q: not an axis of machine dmu50 (X, Y, Z, B, C)" in capsys.readouterr().err


def test_a_feed_move_after_g53_names_the_machine_coordinate_move(tmp_path, capsys):
    from mtcal.cli import main
    from mtcal.model.errormodel import ErrorModel, save_model
    prog = _write(tmp_path / "p.nc", "G90 G21\nG53 X10 Y10 Z10 B0 C0\nG1 X20 F100\n")
    save_model(ErrorModel("dmu50", {"E_C0Y": 1e-5}, {}), tmp_path / "m.json")
    assert main(["compensate", str(prog), "--model", str(tmp_path / "m.json"), "-o", str(tmp_path / "o.nc")]) == 2
    assert "p.nc, line 3:" in (err := capsys.readouterr().err) and "G28 / G30 / G53" in err
