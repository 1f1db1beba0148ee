"""ISO 230-2 exports whose header lies, and lab exports as they are (issue 54 item 3): the header's claims checked
against the values (a deviation beyond a tenth of the targets' span, a column that is its targets), thousands
separators in a decimal-comma export read as such, a row-per-reading export carrying both the laser reading and
its error read together and cross-checked.  Every file is the public real extract tests/data/iso230_2_b02_x.csv
rewritten; the figures are the independent oracle's (tests/iso230_2_oracle.py)."""
from __future__ import annotations

import pytest
from test_iso230_2_exports import _oracle_um, _readings, _run, _same_figures, _targets, _wide


def _long(path, header: str, cell, sep: str = ",", head=()) -> object:
    """A long export: ``header``, then ``cell(target, run, dir, reading)`` -> the row's fields after run."""
    lines = [*head, header] + [sep.join([str(j), *cell(t, j, d, v)]) for (t, j, d), v in _readings().items()]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def _refused(capsys, tmp_path, f, *words):
    code, err = _run(capsys, f, "-o", tmp_path / "rep")
    assert code == 2 and f"{f.name}:1:" in err and len(err.strip().splitlines()) == 1, err
    for w in words:
        assert w in err, (w, err)
    assert not (tmp_path / "rep").exists()


def test_readings_in_mm_under_a_um_header_are_refused_naming_the_column(tmp_path, capsys):
    """Main: E = M = A = 499,500 um, exit 0 (positions in mm read as um: every deviation ~ -target)."""
    f = _long(tmp_path / "l.csv", "Run,Target (mm),Direction,Laser reading (µm)",
              lambda t, j, d, v: [f"{t:g}", d, repr(v)])
    _refused(capsys, tmp_path, f, "'Laser reading (µm)'", "% of the targets' span", "another unit")


def test_an_error_column_holding_the_positions_reached_is_refused_naming_it(tmp_path, capsys):
    """Main: E = 500,005 um on the axis (the positions reached read as errors in mm)."""
    r = _readings()
    f = _wide(tmp_path / "w.csv", [], "Target (mm)", lambda j, d: f"Run {j} {'Fwd' if d == 'up' else 'Rev'} Error (mm)",
              value=lambda t, j, d: repr(r[(t, j, d)]))
    _refused(capsys, tmp_path, f, "Error (mm)'", "positions reached", "values=measured")
    code, _ = _run(capsys, f, "--columns", "values=measured")  # a header that says 'Error' is not overruled
    assert code == 2


def test_a_reading_column_that_is_its_targets_is_refused(tmp_path, capsys):
    f = _long(tmp_path / "copy.csv", "Run,Target (mm),Direction,Laser reading (mm)",
              lambda t, j, d, v: [f"{t:g}", d, f"{t:g}"])
    _refused(capsys, tmp_path, f, "'Laser reading (mm)'", "no deviation at any of the 90 readings", "copied")


def _thousands(x: float, decimals: int = 9) -> str:
    """x as a German spreadsheet writes it: '.' between thousands, ',' before the decimals."""
    sign, body = ("-" if x < 0 else ""), f"{abs(x):,.{decimals}f}"
    body = body.rstrip("0").rstrip(".") if "." in body else body
    return sign + body.replace(",", " ").replace(".", ",").replace(" ", ".")


def test_thousands_separators_in_a_decimal_comma_export_are_read_as_such(tmp_path, capsys):
    """The axis measured 980..1020 mm: '1.000' is 1000 mm and '1.004,972452381' 1004.972452381 mm (main read 1 mm
    and refused or mis-grouped).  The figures are the oracle's (a datum shift leaves them unchanged)."""
    f = _long(tmp_path / "de.csv", "Lauf;Sollposition [mm];Richtung;Messwert [mm]",
              lambda t, j, d, v: [_thousands(t + 1000.0, 0), "vorwärts" if d == "up" else "rückwärts",
                                  _thousands(v + 1000.0)], sep=";")
    assert "1.000;" in f.read_text() and "1.004,97245238" in f.read_text()
    code, out = _run(capsys, f)
    assert code == 0, out
    ev = out["axes"]["axis"]
    assert ev["positions"] == pytest.approx([t + 1000.0 for t in _targets()])
    shifted = {(t + 1000.0, j, d): v + 1000.0 for (t, j, d), v in _readings().items()}
    _same_figures(ev["parameters"], _oracle_um(shifted))
    assert any("thousands separators" in n and "1.000' = 1000" in n for n in ev["notes"]), ev["notes"]


def test_a_decimal_point_among_decimal_commas_is_refused_naming_the_line(tmp_path, capsys):
    f = _long(tmp_path / "mix.csv", "Lauf;Sollposition [mm];Richtung;Messwert [mm]",
              lambda t, j, d, v: [f"{t:g}", d, (f"{v:.6f}" if (t, j) == (0.0, 2) else f"{v:.6f}".replace(".", ","))],
              sep=";")
    code, err = _run(capsys, f)
    line = next(k for k, ln in enumerate(f.read_text().splitlines(), 1) if ln.startswith("2;0;"))
    assert code == 2 and f"mix.csv:{line}:" in err and "decimal point" in err and "decimal commas" in err, err


def test_a_lab_export_with_reading_and_error_is_read_and_cross_checked(tmp_path, capsys):
    """Main refused it ('both are present, which is ambiguous').  The reading in mm to 9 decimals, the error in um
    to 3 (as the laser software rounds them): they agree within half a last digit of each; the deviations are the
    readings', so the figures are the oracle's on the readings as written."""
    head = ["Machine: DMU 50", "Axis: X"]
    f = _long(tmp_path / "lab.csv", "Run,Target (mm),Direction,Laser reading (mm),Error (µm)",
              lambda t, j, d, v: [f"{t:g}", "Fwd" if d == "up" else "Rev", f"{v:.9f}", f"{(v - t) * 1e3:.3f}"],
              head=head)
    code, out = _run(capsys, f)
    assert code == 0, out
    ev = out["axes"]["X"]
    _same_figures(ev["parameters"], _oracle_um({k: round(v, 9) for k, v in _readings().items()}))
    said = " ".join(ev["notes"])
    assert "'Error (µm)' in um checked against them" in said and "agree" in said and "at all 90 readings" in said


@pytest.mark.parametrize("flip,words", [(False, ["disagree by 0.7 um"]), (True, ["target - reading?"])])
def test_reading_and_error_that_disagree_are_refused_naming_the_line(tmp_path, capsys, flip, words):
    r = _readings()
    bad = (10.0, 3, "down")

    def cell(t, j, d, v):
        e = (t - v if flip else v - t) * 1e3 + (0.7 if (t, j, d) == bad and not flip else 0.0)
        return [f"{t:g}", d, f"{v:.9f}", f"{e:.3f}"]
    f = _long(tmp_path / "lab.csv", "Run,Target (mm),Direction,Laser reading (mm),Error (µm)", cell)
    code, err = _run(capsys, f, "-o", tmp_path / "rep")
    line = 2 + (list(r).index(bad) if not flip else 0)
    assert code == 2 and f"lab.csv:{line}:" in err and "'Error (µm)'" in err and "'Laser reading (mm)'" in err, err
    assert all(w in err for w in words), err
    assert not (tmp_path / "rep").exists()
