"""Issue 53, bad input of `mtcal export --format linuxcnc-kins`: a model of another machine spec than the one
exported, a model the plausibility guard refuses, a --name that is not a C identifier or is a LinuxCNC module's,
an output folder holding a file mtcal did not write, a machine whose axes LinuxCNC's joint layout cannot take ->
one line, exit 2, nothing written.  And the valid export: the files, the INI/HAL lines in halcompile's spelling
(``_`` -> ``-``), the C compiled in from generated/ (derive/kins_c.py), and the one lock of LinuxCNC tests."""
from __future__ import annotations

import json
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import pytest
from linuxcnc_sim import LOCK, linuxcnc_lock

import mtcal
from mtcal.cli import main
from mtcal.data import path
from mtcal.errors import InputError
from mtcal.export.linuxcnc_kins import check_name, check_topology, export_kins
from mtcal.kinematics.machine import _generated_dir

DEMO = path("demo_truth.json")


@pytest.fixture(autouse=True)
def _ledger(tmp_path, monkeypatch):
    monkeypatch.setenv("MTCAL_STATE_DIR", str(tmp_path / "state"))


def _refused(argv, capsys, *words) -> str:
    code = main(argv)
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.strip() and "StaleGenerated" not in ln and "warn" not in ln]
    assert code == 2, err
    assert len(lines) == 1 and "Traceback" not in err, err
    assert any(w.lower() in lines[0].lower() for w in words), lines[0]
    return lines[0]


def test_valid_export_writes_the_component_and_prints_the_hal_spelling(tmp_path, capsys):
    out = tmp_path / "kins"
    assert main(["export", str(DEMO), "--format", "linuxcnc-kins", "-o", str(out), "--name", "dmu_kins"]) == 0
    text = capsys.readouterr().out
    assert sorted(p.name for p in out.iterdir()) == ["dmu_kins.comp", "dmu_kins.ini"]
    assert "KINEMATICS = dmu_kins" in text and "COORDINATES = XYZBC" in text
    assert "net mtcal-tool-length motion.tooloffset.z => dmu-kins.tool-length" in text
    assert "setp dmu-kins.max-iterations" in text
    comp = (out / "dmu_kins.comp").read_text()
    assert comp.startswith("component dmu_kins ") and 'license "GPL";' in comp
    assert "KINEMATICS_BOTH" in comp and "malloc" not in comp
    assert (_generated_dir() / "dmu50_kins.c").read_text() in comp  # the C is derive's, verbatim
    # a re-export into the folder it wrote is fine
    assert main(["export", str(DEMO), "--format", "linuxcnc-kins", "-o", str(out), "--name", "dmu_kins"]) == 0


def test_a_model_of_another_machine_is_refused(tmp_path, capsys):
    _refused(["export", str(DEMO), "--format", "linuxcnc-kins", "-o", str(tmp_path / "k"), "--machine", "headbc"],
             capsys, "machine dmu50, not headbc")
    assert not (tmp_path / "k").exists()


def test_an_implausible_model_is_refused(tmp_path, capsys):
    raw = json.loads(DEMO.read_text())
    raw["functions"]["E_XX"]["values"] = [v * 1000 for v in raw["functions"]["E_XX"]["values"]]  # um read as mm
    bad = tmp_path / "um.json"
    bad.write_text(json.dumps(raw))
    line = _refused(["export", str(bad), "--format", "linuxcnc-kins", "-o", str(tmp_path / "k")], capsys,
                    "plausibility")
    assert "um.json" in line and not (tmp_path / "k").exists()


@pytest.mark.parametrize("name,words", [("9kins", "identifier"), ("my-kins", "identifier"), ("my kins", "identifier"),
                                        ("double", "identifier"), ("trivkins", "LinuxCNC module"),
                                        ("motmod", "LinuxCNC module")])
def test_a_bad_name_is_refused(tmp_path, capsys, name, words):
    _refused(["export", str(DEMO), "--format", "linuxcnc-kins", "-o", str(tmp_path / "k"), "--name", name], capsys,
             words)
    assert not (tmp_path / "k").exists()


def test_a_folder_holding_a_file_mtcal_did_not_write_is_refused(tmp_path, capsys):
    out = tmp_path / "k"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    line = _refused(["export", str(DEMO), "--format", "linuxcnc-kins", "-o", str(out)], capsys, "not written by mtcal")
    assert "notes.txt" in line and sorted(p.name for p in out.iterdir()) == ["notes.txt"]


def test_name_is_an_option_of_linuxcnc_kins_only(tmp_path, capsys):
    _refused(["export", str(DEMO), "--format", "siemens", "-o", str(tmp_path / "C.MPF"), "--name", "k"], capsys,
             "linuxcnc-kins")
    assert not (tmp_path / "C.MPF").exists()


@pytest.mark.parametrize("option", [["--step", "5"], ["--diagnosis", "d.json"], ["--linear-units", "inch"],
                                    ["--comp-file-type", "1"]])
def test_table_options_are_refused_for_the_module(tmp_path, capsys, option):
    _refused(["export", str(DEMO), "--format", "linuxcnc-kins", "-o", str(tmp_path / "k"), *option], capsys,
             option[0])
    assert not (tmp_path / "k").exists()


def test_a_module_installed_by_an_earlier_export_may_be_replaced(tmp_path):
    (tmp_path / "theirs.so").write_bytes(b"\x7fELF component:theirs")
    (tmp_path / "ours.so").write_bytes(b"\x7fELF author:mtcal export (generated)")
    with pytest.raises(InputError, match="LinuxCNC module"):
        check_name("theirs", tmp_path)
    check_name("ours", tmp_path)


class _Layout:
    """A machine's joint layout as check_topology reads it."""

    def __init__(self, m, axes, kinds):
        self.name, self.axes, self.axis_kinds = m.name, axes, kinds
        self.linear_axes = tuple(a for a, k in zip(axes, kinds) if k == "linear")


@pytest.mark.parametrize("axes,kinds", [(("X", "Y", "Z", "B", "Q"), ("linear",) * 3 + ("rotary",) * 2),
                                        (("X", "Y", "A", "B", "C"), ("linear",) * 2 + ("rotary",) * 3),
                                        (("X", "Y", "Z", "B", "B"), ("linear",) * 3 + ("rotary",) * 2),
                                        (("X", "Y", "C", "B", "Z"), ("linear", "linear", "linear", "rotary",
                                                                     "rotary"))])
def test_a_machine_linuxcnc_cannot_lay_out_is_refused(tmp_path, axes, kinds):
    m = mtcal.load_machine("dmu50")
    for spec in ("dmu50", "headbc", "xyzac"):  # every shipped spec fits
        check_topology(mtcal.load_machine(spec))
    with pytest.raises(InputError, match="does not fit LinuxCNC's joint layout"):
        export_kins(mtcal.load_model(DEMO), _Layout(m, axes, kinds), tmp_path / "k")
    assert not (tmp_path / "k").exists()


def test_an_empty_model_is_refused(tmp_path):
    model = replace(mtcal.load_model(DEMO), constants={}, functions={})
    with pytest.raises(InputError, match="no non-zero error"):
        export_kins(model, model.kinematics, tmp_path / "k")
    assert not (tmp_path / "k").exists()


def test_the_linuxcnc_lock_serialises_processes(tmp_path):
    """A second process waits for the first's lock (the flock every LinuxCNC test holds, tests/linuxcnc_sim.py)."""
    code = ("import fcntl, sys, time; f = open(sys.argv[1], 'a'); fcntl.flock(f, fcntl.LOCK_EX); "
            "print('held', flush=True); time.sleep(1.0); print(time.time(), flush=True)")
    p = subprocess.Popen([sys.executable, "-c", code, str(LOCK)], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "held"
    with linuxcnc_lock():
        got = time.time()
    released = float(p.stdout.readline())
    p.wait(10)
    assert got >= released - 0.05
    assert Path(LOCK).exists()
