"""No output replaces a file that mtcal did not write (or that was changed since) without --force, naming the file
(exit 2, nothing written): the rule is once, in mtcal/io.py (refuse_foreign; the ledger of files mtcal wrote), and
reaches every command that writes (issue 36: `export -o` onto the machine builder's X.COM replaced it with exit 0).
"""
from __future__ import annotations

from pathlib import Path

import pytest

from mtcal.cli import main

DATA = Path(__file__).resolve().parents[1] / "mtcal" / "data"
MODEL = DATA / "demo_truth.json"
B02 = Path(__file__).resolve().parent / "data" / "iso230_2_b02_x.csv"
FOREIGN = "; the machine builder's table, not mtcal's\n"


@pytest.fixture(autouse=True)
def _ledger(tmp_path, monkeypatch):
    monkeypatch.setenv("MTCAL_STATE_DIR", str(tmp_path / "state"))


def _run(capsys, *argv) -> tuple[int, str]:
    code = main([*map(str, argv), "-q"])
    return code, capsys.readouterr().err


def test_export_onto_a_file_mtcal_did_not_write_is_refused_naming_it(tmp_path, capsys):
    out = tmp_path / "COMP.MPF"
    out.write_text(FOREIGN)
    code, err = _run(capsys, "export", MODEL, "--format", "siemens", "-o", out)
    assert code == 2 and f"{out}: exists and was not written by mtcal" in err and "--replace" in err, err
    assert out.read_text() == FOREIGN
    code, err = _run(capsys, "export", MODEL, "--format", "siemens", "-o", out, "--replace")
    assert code == 0 and "mtcal export" in out.read_text()


def test_the_guards_force_and_replacing_a_file_are_separate_flags(tmp_path, capsys):
    """On export (and compensate) --force overrides the plausibility guard and --replace replaces a foreign file:
    one never grants the other (a wrong table with exit 0 is the worst outcome)."""
    import json
    bad = json.loads(Path(MODEL).read_text())
    bad["constants"]["E_C0Y"] = 0.5  # 0.5 rad of squareness: no machine
    bad_path = tmp_path / "bad.json"
    bad_path.write_text(json.dumps(bad))
    out = tmp_path / "COMP.MPF"
    out.write_text(FOREIGN)
    code, err = _run(capsys, "export", bad_path, "--format", "siemens", "-o", out, "--replace")
    assert code == 2 and "nothing was written" in err and out.read_text() == FOREIGN, err
    code, err = _run(capsys, "export", MODEL, "--format", "siemens", "-o", out, "--force")
    assert code == 2 and "exists and was not written by mtcal" in err and out.read_text() == FOREIGN, err


def test_a_re_export_replaces_mtcals_own_file_but_not_one_edited_since(tmp_path, capsys):
    out = tmp_path / "COMP.MPF"
    assert _run(capsys, "export", MODEL, "--format", "siemens", "-o", out)[0] == 0
    assert _run(capsys, "export", MODEL, "--format", "siemens", "-o", out)[0] == 0  # its own: replaced
    out.write_text(out.read_text() + "; edited by hand on the machine\n")
    code, err = _run(capsys, "export", MODEL, "--format", "siemens", "-o", out)
    assert code == 2 and "changed since" in err and out.read_text().endswith("edited by hand on the machine\n")


def test_heidenhain_folder_with_the_machine_builders_table_is_left_untouched(tmp_path, capsys):
    folder = tmp_path / "TNC"
    folder.mkdir()
    (folder / "X.COM").write_text(FOREIGN)
    code, err = _run(capsys, "export", MODEL, "--format", "heidenhain", "-o", folder)
    assert code == 2 and "X.COM: exists and was not written by mtcal" in err, err
    assert sorted(p.name for p in folder.iterdir()) == ["X.COM"] and (folder / "X.COM").read_text() == FOREIGN


@pytest.mark.parametrize("argv,name", [
    (["compensate", DATA / "sample_5axis.nc", "--model", MODEL, "-o", "{out}"], "out.nc"),
    (["simulate", "-o", "{out}"], "rec.csv"),
    (["identify", DATA / "demo_campaign.csv", "-o", "{out}"], "model.json"),
    (["iso230-2", B02, "-o", "{dir}"], "iso230-2_axis.md"),
    (["check", "predict", "--model", MODEL, "--circular", "XY,100", "--plot", "{out}"], "polar.png"),
])
def test_every_command_that_writes_refuses_a_foreign_file(tmp_path, capsys, argv, name):
    out = tmp_path / name
    out.write_text(FOREIGN)
    before = sorted(p.name for p in tmp_path.iterdir())
    args = [str(a).replace("{out}", str(out)).replace("{dir}", str(tmp_path)) for a in argv]
    code, err = _run(capsys, *args)
    assert code == 2 and f"{out}: exists and was not written by mtcal" in err, err
    assert out.read_text() == FOREIGN and sorted(p.name for p in tmp_path.iterdir()) == before


def test_the_library_writer_refuses_too_and_replace_allowed_lets_it(tmp_path):
    from mtcal.io import atomic_write_text, replace_allowed
    out = tmp_path / "part.nc"
    out.write_text("G0 X0\n")
    with pytest.raises(ValueError, match="not written by mtcal"):
        atomic_write_text(out, "G0 X1\n")
    assert out.read_text() == "G0 X0\n"
    with replace_allowed():
        atomic_write_text(out, "G0 X1\n")
    assert out.read_text() == "G0 X1\n"
    atomic_write_text(out, "G0 X2\n")  # now mtcal's
    assert out.read_text() == "G0 X2\n"
