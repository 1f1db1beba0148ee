"""The CLI error boundary (mtcal.cli): exit codes 0/1/2/130/143, one-line messages, --debug, options validated at
parse time, outputs never overwrite inputs, no temporary file left behind by Ctrl-C or SIGTERM."""
from __future__ import annotations

import glob
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from mtcal.cli import _main as cli
from mtcal.cli import main
from mtcal.errors import InputError

DATA = Path(__file__).resolve().parents[1] / "mtcal" / "data"
PROGRAM, MODEL, PLATE = DATA / "sample_5axis.nc", DATA / "demo_truth.json", DATA / "nbs_table2.csv"
COMP = ["compensate", str(PROGRAM), "--model", str(MODEL), "-o", "o.nc"]


def _err(capsys) -> str:
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err  # one line
    return err.strip()


# ----------------------------------------------------------------------------- InputError format
def test_input_error_carries_file_and_line():
    assert str(InputError("bad word", "p.nc", 12)) == "p.nc:12: bad word"
    assert str(InputError("empty", "p.nc")) == "p.nc: empty"
    assert str(InputError("plain")) == "plain"
    e = InputError("x", Path("a/b.csv"), 3)
    assert (e.file, e.line, e.problem) == ("a/b.csv", 3, "x") and isinstance(e, ValueError)


# ----------------------------------------------------------------------------- options
@pytest.mark.parametrize("argv, message", [
    ([*COMP, "--tool-length", "nan"],
     "argument --tool-length: expected a number in mm (finite), got 'nan'"),
    ([*COMP, "--tool-length", "-5"],
     "argument --tool-length: expected a number in mm >= 0, got '-5'"),
    ([*COMP, "--precision", "-1"],
     "argument --precision: expected a whole number in [0, 9], got '-1'"),
    ([*COMP, "--tolerance", "nan"],
     "argument --tolerance: expected a number in mm (finite), got 'nan'"),
    ([*COMP, "--tolerance", "0"],
     "argument --tolerance: expected a number in mm > 0, got '0'"),
    ([*COMP, "--cone", "nan"],
     "argument --cone: expected a number in deg (finite), got 'nan'"),
    ([*COMP, "--iterations", "0"],
     "argument --iterations: expected a whole number in [1, 50], got '0'"),
    (["plate", str(PLATE), "--level", "nan"], "argument --level: expected a number (finite), got 'nan'"),
    (["plate", str(PLATE), "--level", "1.5"], "argument --level: expected a number in (0, 1), got '1.5'"),
    (["identify", "r.csv", "--tracker", "1,2"], "argument --tracker: expected three numbers x,y,z in mm, got '1,2'"),
    (["identify", "r.csv", "--outlier-k", "-1"], "argument --outlier-k: expected a number >= 0, got '-1'"),
    (["diagnose", "r.csv", "--tracker", "1,2,inf"], "--tracker: expected three numbers x,y,z in mm, got '1,2,inf'"),
    (["simulate", "-o", "r.csv", "--rounds", "0"], "argument --rounds: expected a whole number >= 1, got '0'"),
    (["simulate", "-o", "r.csv", "--seed", "-3"], "argument --seed: expected a whole number >= 0, got '-3'"),
    (["plan", "--monte-carlo", "-2"], "argument --monte-carlo: expected a whole number >= 0, got '-2'"),
    (["export", str(MODEL), "--format", "linuxcnc", "-o", "o.nc", "--step", "0"],
     "argument --step: expected a number in mm or deg > 0, got '0'"),
    (["export", str(MODEL), "--format", "linuxcnc", "-o", "o.nc", "--max-points", "1"],
     "argument --max-points: expected a whole number >= 2, got '1'"),
    (["iso230-2", str(DATA / "demo_campaign.csv"), "--alpha", "nan"],
     "argument --alpha: expected a number in 1/K (finite), got 'nan'"),
    (["iso230-2", str(DATA / "demo_campaign.csv"), "--target-points", "0,x"],
     "--target-points must be finite numbers separated by commas, got '0,x'"),
])
def test_bad_options_one_line_exit_2(tmp_path, monkeypatch, capsys, argv, message):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = _err(capsys)
    assert err.startswith(f"mtcal {argv[0]}: error: ") and message in err
    assert not (tmp_path / "o.nc").exists() and not (tmp_path / "r.csv").exists()


@pytest.mark.parametrize("form", [["--tracker", "-2000,0,300"], ["--tracker=-2000,0,300"]])
def test_negative_tracker_coordinate_is_a_value(capsys, form):
    assert main(["plan", *form, "--axes", "X", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["tracker"] == [-2000.0, 0.0, 300.0]


def test_join_negative_values_only_for_listed_options():
    from mtcal.cli._options import join_negative_values
    assert join_negative_values(["plan", "--tracker", "-1,2,3", "--seed", "4"]) == ["plan", "--tracker=-1,2,3",
                                                                                    "--seed", "4"]
    assert join_negative_values(["--tracker", "--json"]) == ["--tracker", "--json"]


# ----------------------------------------------------------------------------- operating-system errors
def test_os_errors_are_one_line_naming_the_path(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "d").mkdir()
    (tmp_path / "f").write_text("x")
    base = ["compensate", str(PROGRAM), "--model", str(MODEL)]
    cases = [
        (base + ["-o", "d"], "d: is a directory; give an output file name"),
        (base + ["-o", "f/x.nc"], "f/x.nc: cannot write here:"),
        (base + ["-o", "x.nc", "--tables", "f"], "f: exists and is not a directory"),
        (["compensate", str(PROGRAM), "--model", "d", "-o", "x.nc"], "d: is a directory, expected a model file"),
        (["compensate", str(PROGRAM), "--model", "missing.json", "-o", "x.nc"], "missing.json: model file not found"),
        (["plate", str(PLATE), "--plot", "f/p.png"], "f/p.png: cannot write here:"),
        (["identify", "d", "-o", "m.json"], "d: is a directory, expected a recording file"),
        (["demo", "--out", "f"], "f: exists and is not a directory"),
    ]
    for argv, message in cases:
        assert main(argv) == 2, argv
        err = _err(capsys)
        assert err.startswith(f"mtcal {argv[0]}: error: ") and message in err, (argv, err)
    assert sorted(os.listdir(tmp_path)) == ["d", "f"]  # nothing written, no temporaries


@pytest.mark.parametrize("exc, words", [
    (PermissionError(13, "Permission denied", "/ro/out.nc"), "/ro/out.nc: permission denied"),
    (OSError(30, "Read-only file system", "/ro/out.nc"), "/ro/out.nc: read-only file system"),
    (OSError(28, "No space left on device", "out.nc"), "out.nc: no space left on device"),
])
def test_os_error_words(monkeypatch, capsys, exc, words):
    """Read-only and full disks cannot be made here (tests run as root): the boundary's wording is checked."""
    from mtcal.cli import plan
    monkeypatch.setattr(plan, "run", lambda args: (_ for _ in ()).throw(exc))
    assert main(["plan"]) == 2
    assert _err(capsys) == f"mtcal plan: error: {words}"


# ----------------------------------------------------------------------------- bugs, interrupts
def _raise(exc):
    def run(args):
        raise exc
    return run


@pytest.mark.parametrize("exc", [np.linalg.LinAlgError("Singular matrix"), ValueError("shapes do not match"),
                                 KeyError("E_XX")])
def test_a_bug_is_not_bad_input(monkeypatch, capsys, exc):
    """LinAlgError is a ValueError: neither it nor a bare ValueError may pass as the user's fault (exit 2)."""
    from mtcal.cli import plan
    monkeypatch.setattr(plan, "run", _raise(exc))
    assert main(["plan"]) == 1
    err = capsys.readouterr().err
    assert "internal error" in err and "bug in mtcal" in err and "--debug" in err
    assert "Traceback" not in err and err.count("\n") == 1
    assert main(["--debug", "plan"]) == 1
    err = capsys.readouterr().err
    assert "Traceback (most recent call last)" in err and type(exc).__name__ in err
    assert main(["plan", "--debug"]) == 1 and "Traceback" in capsys.readouterr().err


def test_keyboard_interrupt_exits_130_quietly(monkeypatch, capsys):
    from mtcal.cli import plan
    monkeypatch.setattr(plan, "run", _raise(KeyboardInterrupt()))
    assert main(["plan"]) == 130
    assert _err(capsys) == "mtcal plan: interrupted"


def test_input_error_from_library_is_exit_2(monkeypatch, capsys):
    from mtcal.cli import plan
    monkeypatch.setattr(plan, "run", _raise(InputError("word X1.2.3 is not a number", "p.nc", 7)))
    assert main(["plan"]) == 2
    assert _err(capsys) == "mtcal plan: error: p.nc:7: word X1.2.3 is not a number"


def test_help_exits_0(capsys):
    assert main(["plan", "--help"]) == 0
    assert "--tracker" in capsys.readouterr().out


def test_exit_codes_documented():
    assert (cli.EXIT_OK, cli.EXIT_BUG, cli.EXIT_INPUT, cli.EXIT_INTERRUPT, cli.EXIT_TERMINATED) == (0, 1, 2, 130, 143)
    readme = (Path(__file__).resolve().parents[1] / "docs" / "reference" / "safety.md").read_text()
    for code in ("130", "143", "--debug"):
        assert code in readme.split("# Safety guarantees")[1]


# ----------------------------------------------------------------------------- never overwrite an input
def test_outputs_never_overwrite_inputs(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    model = tmp_path / "constants.csv"  # a model JSON that happens to carry a table's name
    model.write_bytes(MODEL.read_bytes())
    prog = tmp_path / "p.nc"
    prog.write_bytes(PROGRAM.read_bytes())
    plate = tmp_path / "plate.csv"
    plate.write_bytes(PLATE.read_bytes())
    before = {p.name: p.read_bytes() for p in (model, prog, plate)}
    cases = [
        (["compensate", "p.nc", "--model", "constants.csv", "-o", "out.nc", "--tables", "."],
         "output directory . would overwrite the input constants.csv"),
        (["compensate", "p.nc", "--model", "constants.csv", "-o", "p.nc"], "output p.nc is also an input"),
        (["compensate", "p.nc", "--model", "constants.csv", "-o", "./sub/../constants.csv"], "is also an input"),
        (["plate", "plate.csv", "--plot", "plate.csv"], "output plate.csv is also an input"),
        (["simulate", "--model", "constants.csv", "-o", "constants.csv"], "is also an input"),
    ]
    (tmp_path / "sub").mkdir()
    for argv, message in cases:
        assert main(argv) == 2, argv
        assert message in _err(capsys)
    assert {p.name: p.read_bytes() for p in (model, prog, plate)} == before
    assert not (tmp_path / "out.nc").exists()


def test_plots_directory_holding_an_input_is_refused(tmp_path, capsys):
    rec = tmp_path / "residuals_before.png"  # a recording saved under a plot's name
    rec.write_text("axis,round,position,point,x,y,z\n")
    assert main(["diagnose", str(rec), "--plots", str(tmp_path)]) == 2
    assert "would overwrite the input" in _err(capsys)


def test_hard_link_to_an_input_is_the_input(tmp_path):
    from mtcal.io import refuse_overwrite
    src = tmp_path / "m.json"
    src.write_text("{}")
    os.link(src, tmp_path / "alias.json")
    with pytest.raises(InputError, match="is also an input"):
        refuse_overwrite([tmp_path / "alias.json"], src)
    refuse_overwrite([tmp_path / "new.json", None], src, None)  # fine


# ----------------------------------------------------------------------------- signals (subprocess)
def _default_sigint() -> None:
    """The child's SIGINT at its default even when the suite runs as a background job (a shell starts those with
    SIGINT ignored, which a child inherits and Python then leaves ignored)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.mark.parametrize("sig, code, word", [(signal.SIGTERM, 143, "terminated"), (signal.SIGINT, 130, "interrupted")])
def test_signal_leaves_no_temporary(tmp_path, sig, code, word):
    """A long compensation is stopped while its output is being streamed into .out.nc.XXXX: exit code, one line,
    no temporary and no output file left."""
    moves = [f"X{(i * 7) % 400}.5 Y{(i * 13) % 400}.25 Z{(i * 3) % 300}.125 B{(i * 11) % 90}.5 C{(i * 17) % 360}.5"
             for i in range(60000)]
    (tmp_path / "p.nc").write_text("G90 G0 X0 Y0 Z0 B0 C0\nG1 F1000\n" + "\n".join(moves) + "\n")
    proc = subprocess.Popen([sys.executable, "-m", "mtcal.cli", "compensate", "p.nc", "--model", str(MODEL),
                             "-o", "out.nc"], cwd=tmp_path, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL,
                            text=True, preexec_fn=_default_sigint)
    deadline = time.monotonic() + 120
    while not glob.glob(str(tmp_path / ".out.nc.*")) and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.005)
    assert proc.poll() is None, "finished before the temporary file was seen; make the program longer"
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == code
    assert err.strip().splitlines()[-1] == f"mtcal compensate: {word}" and "Traceback" not in err
    assert sorted(os.listdir(tmp_path)) == ["p.nc"]


# A command busy comparing the readings' labels (np.str_): NumPy drops the exception a signal handler raises there
_LABEL_LOOP = """
import sys, numpy as np
import mtcal.cli.plan as cmd
def run(args):
    labels = np.array(["table", "spindle"] * 5000)
    print("busy", flush=True)
    while True:
        [lab == "table" for lab in labels]
cmd.run = run
from mtcal.cli import main
sys.exit(main(["plan"]))
"""


@pytest.mark.parametrize("sig, code, word", [(signal.SIGINT, 130, "interrupted"), (signal.SIGTERM, 143, "terminated")])
def test_one_signal_stops_a_command_that_numpy_would_let_run_on(sig, code, word):
    """One Ctrl-C (or SIGTERM) stops the command even where NumPy drops the exception its handler raises (the
    handler's repeat, mtcal.cli._signals): one signal, exit code and one line within 30 s.  Without the repeat
    the loop ran on (`mtcal plan --monte-carlo 2000000` hung after a Ctrl-C in CI)."""
    proc = subprocess.Popen([sys.executable, "-c", _LABEL_LOOP], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, preexec_fn=_default_sigint)
    assert proc.stdout.readline().strip() == "busy"
    time.sleep(0.2)
    proc.send_signal(sig)
    try:
        _, err = proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        pytest.fail(f"{sig.name} was lost: the command ran on for 30 s")
    assert proc.returncode == code, err
    assert err.strip().splitlines() == [f"mtcal plan: {word}"]


_DATA = Path(__file__).resolve().parent.parent / "mtcal" / "data"


@pytest.mark.parametrize("name", ["plate", "threepoint", "signatures", "nosuch"])
@pytest.mark.parametrize("argv", [["identify", str(_DATA / "demo_campaign.csv")], ["plan"], ["simulate", "-o", "{out}"],
                                  ["diagnose", str(_DATA / "demo_campaign.csv")],
                                  ["iso230-2", str(_DATA / "demo_campaign.csv")], ["demo", "--out", "{out}"]])
def test_a_name_that_is_no_machine_exits_2_listing_the_machines(tmp_path, capsys, argv, name):
    """Issue 20: `--machine plate` (a generated module that is not a machine) ended in exit 1 with an
    AttributeError; every command that takes --machine names the machines there are."""
    out = tmp_path / "out"
    assert main([a.format(out=out) for a in argv] + ["--machine", name]) == 2
    err = capsys.readouterr().err
    assert f"unknown machine {name!r}; available: dmu50, headbc, xyzac" in err and "Traceback" not in err
    assert not out.exists()


# ----------------------------------------------------------------------------- option names at the boundary
def test_library_names_options_by_keyword_and_the_cli_by_flag(tmp_path, capsys, monkeypatch):
    """The library says `max_points` (its keyword); the command line says --max-points (issue 23: the CLI only
    parses and formats, flags translated at the boundary)."""
    from mtcal.export import export_model
    from mtcal.model.errormodel import load_model
    with pytest.raises(InputError, match=r"got `max_points` 100000$"):
        export_model(load_model(MODEL), load_model(MODEL).kinematics, "linuxcnc", tmp_path / "a", max_points=100000)
    monkeypatch.chdir(tmp_path)
    assert main(["export", str(MODEL), "--format", "linuxcnc", "-o", "b", "--max-points", "100000"]) == 2
    err = _err(capsys)
    assert err.endswith("got --max-points 100000") and "`" not in err, err
    assert cli.to_flags("give `tracker` x,y,z or `nothing`", {"tracker": "--tracker"}) == \
        "give --tracker x,y,z or `nothing`"
