"""Nothing unsafe reaches a machine (issue 11): the plausibility guard on compensated programs, G93 feeds on split
moves, safe headers, empty and binary inputs.  Refusals go through the CLI: exit 2, one line naming the file and the
line, and no output file."""
from __future__ import annotations

import json
import re

import numpy as np
import pytest

import mtcal
from mtcal.cli import main
from mtcal.compensate.examples import example_model
from mtcal.compensate.program import ProgramCompensator
from mtcal.compensate.solver import Compensator
from mtcal.errors import InputError
from mtcal.model.errormodel import save_model

M = mtcal.load_machine("dmu50")
MODEL = example_model(M)


def model_file(tmp_path, constants, name="model.json"):
    path = tmp_path / name
    path.write_text(json.dumps({"machine": "dmu50", "units": {"length": "mm", "angle": "rad"},
                                "constants": constants, "functions": {}}))
    return path


def run_cli(tmp_path, capsys, text, model, *opts, name="prog.nc"):
    prog = tmp_path / name
    prog.write_bytes(text if isinstance(text, bytes) else text.encode())
    out = tmp_path / "out.nc"
    code = main(["compensate", str(prog), "--model", str(model), "-o", str(out), *opts])
    cap = capsys.readouterr()
    return code, cap.err.strip(), out


PROGRAM = "G90 G21\nG0 X0 Y0 Z10\nG1 X50 Y20 Z0 F300\nX80\n"


def test_model_typed_in_um_under_mm_is_refused(tmp_path, capsys):
    """Issue 11: E_XX 12.5 and E_C0Y 18 (um and urad typed under mm and rad) turned X50 into X-322.5 with exit 0."""
    model = model_file(tmp_path, {"E_XX": 12.5, "E_C0Y": 18})
    code, err, out = run_cli(tmp_path, capsys, PROGRAM, model)
    assert code == 2 and not out.exists() and not list(tmp_path.glob(".out.nc.*"))
    # issue 21: the model itself fails the plausibility guard (mtcal.model.plausibility)
    assert len(err.splitlines()) == 1
    assert "model.json: constant E_XX = 12500 um is beyond the plausibility bound 1000 um" in err
    # past that guard (--force), the guard on what is written still refuses it, line by line
    code, err, out = run_cli(tmp_path, capsys, PROGRAM, model, "--force")
    assert code == 2 and not out.exists() and not list(tmp_path.glob(".out.nc.*"))
    assert "prog.nc, line 2: the correction of X by -12.5000 mm" in err and "--max-correction" in err
    assert "E_C0Y = 18 rad" in err and "E_XX = 12.5 mm" in err


def test_sane_model_passes_and_the_bound_is_an_option(tmp_path, capsys):
    model = model_file(tmp_path, {"E_XX": 0.0125, "E_C0Y": 18e-6})
    code, err, out = run_cli(tmp_path, capsys, PROGRAM, model)
    assert code == 0 and err == ""
    # X50 Y20: E_XX = 12.5 um, squareness moves x by +y E_C0Y (actual Y = (-E_C0Y, 1, 0)): x - 0.0125 + 20 * 18e-6
    assert "G1 X49.9879 Y20 Z0 F300" in out.read_text()
    out.unlink()
    code, err, out = run_cli(tmp_path, capsys, PROGRAM, model, "--max-correction", "0.012")
    assert code == 2 and "line 2" in err and "exceeds the plausibility bound 0.012 mm" in err and not out.exists()


def test_rotary_correction_bound(tmp_path, capsys):
    """Full scope: B and C correct the tool axis; a 5 mrad tilt error of C (0.29 deg) exceeds the 0.1 deg default."""
    prog = "G90 G0 X10 Y10 Z10 B45 C30\nG1 X20 F100\n"
    model = model_file(tmp_path, {"E_A0C": 5e-3})
    code, err, out = run_cli(tmp_path, capsys, prog, model, "--scope", "full")
    assert code == 2 and "constant E_A0C = 5000 urad is beyond the plausibility bound 2000 urad" in err
    code, err, out = run_cli(tmp_path, capsys, prog, model, "--scope", "full", "--force")
    assert code == 2 and "line 1" in err and "--max-rotary-correction" in err and " deg " in err
    code, err, _ = run_cli(tmp_path, capsys, prog, model, "--scope", "full", "--max-rotary-correction", "1",
                             "--max-correction", "5", "--force")
    assert code == 0 and "FORCED past the plausibility guard" in err, err


def test_non_finite_corrections_are_refused_by_the_guard_itself(tmp_path):
    """--tool-length nan wrote 'Xnan': the Compensator refuses it, and the guard refuses a non-finite number even
    when it gets past (here forced) before anything is written."""
    with pytest.raises(InputError, match="tool_length must be a finite number"):
        Compensator(MODEL, M, tool_length=float("nan"))
    comp = Compensator(MODEL, M)
    comp.tool_length = float("nan")
    prog, out = tmp_path / "p.nc", tmp_path / "o.nc"
    prog.write_text(PROGRAM)
    with pytest.raises(InputError, match=r"p.nc, line 2: the corrected X would be nan \(not a finite number"):
        ProgramCompensator(comp).run(prog, out)
    assert not out.exists() and not list(tmp_path.glob(".o.nc.*"))


def test_residual_above_the_tolerance_is_refused(tmp_path, capsys):
    """--precision -1 split a move into 15 pieces with a 3.7 mm residual: negative precision is refused, and a
    precision that cannot hold the tolerance (1 decimal = 50 um rounding vs 1 um) is refused by the residual guard."""
    model = tmp_path / "m.json"
    save_model(MODEL, model)
    code, err, out = run_cli(tmp_path, capsys, PROGRAM, model, "--precision", "-1")
    assert code == 2 and "precision" in err and not out.exists()
    code, err, out = run_cli(tmp_path, capsys, PROGRAM, model, "--precision", "1")
    assert code == 2 and not out.exists()
    m = re.search(r"prog.nc, line (\d): the predicted (tool-tip|mid-segment \(move split into \d+ pieces\)) error "
                  r".* would be ([\d.]+) um, above the tolerance 1 um", err)
    assert m and 1 < float(m.group(3)) <= 100  # rounding to 0.1 mm: up to sqrt(3) * 50 um at a point
    code, err, out = run_cli(tmp_path, capsys, PROGRAM, model, "--precision", "1", "--tolerance", "0.1")
    assert code == 0, err


def test_mid_segment_residual_beyond_max_subdivisions_is_refused(tmp_path):
    prog, out = tmp_path / "long.nc", tmp_path / "o.nc"
    prog.write_text("G90 G0 X-200 Y-150 Z-100 B20 C0\nG1 X200 Y150 Z100 B60 C90 F500\n")
    with pytest.raises(InputError, match=r"long.nc, line 2: the predicted mid-segment \(move split into 2 pieces\)"):
        ProgramCompensator(Compensator(MODEL, M, "full"), tolerance=1e-4, max_subdivisions=2).run(prog, out)
    assert not out.exists()
    ProgramCompensator(Compensator(MODEL, M, "full"), tolerance=1e-3).run(prog, out)  # the default limit is enough
    assert out.exists()


def test_inverse_time_split_moves_carry_their_share_of_f(tmp_path):
    """G93: F = 1 / (minutes per block).  Each inserted block must carry F, and the pieces must take the time of
    the move between them in proportion to their length: sum of 1/F over the blocks = 1/F of the move, and each
    block's 1/F share = its share of the nominal displacement (pieces are equal steps of the nominal move)."""
    prog, out = tmp_path / "g93.nc", tmp_path / "o.nc"
    prog.write_text("G90 G21 G0 X-200 Y-150 Z-100 B20 C0\nG93 G1 X200 Y150 Z100 B60 C90 F2.5\nG94 G0 Z120\n")
    rep = ProgramCompensator(Compensator(MODEL, M, "full"), tolerance=5e-4, precision=6).run(prog, out)
    assert rep.subdivided_moves == 1 and rep.lines_inserted >= 3
    lines = out.read_text().splitlines()
    blocks = lines[1:-1]
    assert blocks[0].startswith("G93 G1 ") and lines[-1].startswith("G94 G0")
    feeds = np.array([float(re.search(r"F([\d.]+)", b).group(1)) for b in blocks])
    assert len(feeds) == len(blocks) == rep.lines_inserted + 1  # every block carries F
    assert np.sum(1 / feeds) == pytest.approx(1 / 2.5, rel=1e-6)  # the move takes as long as programmed
    pos = [np.array([-200, -150, -100, 20, 0.0])]
    for b in blocks:  # absolute words, modal
        p = pos[-1].copy()
        for ax, v in re.findall(r"([XYZBC])(-?[\d.]+)", b):
            p["XYZBC".index(ax)] = float(v)
        pos.append(p)
    step = np.abs(np.diff(np.array(pos)[:, 0]))  # X: 400 mm over the move, corrections of a few um
    np.testing.assert_allclose(step / 400, (1 / feeds) * 2.5, atol=1e-4)


def test_safe_header_program_is_compensated_and_the_header_passed_through(tmp_path, capsys):
    model = tmp_path / "m.json"
    save_model(MODEL, model)
    prog, out = tmp_path / "h.nc", tmp_path / "o.nc"
    text = "%\nG91 G28 Z0\nG90 G54 G0 X10 Y20\nZ50\nG1 Z5 F200\nX30\nG53 G0 Z0\nG0 X0 Y0\nM30\n%\n"
    prog.write_text(text)
    assert main(["compensate", str(prog), "--model", str(model), "-o", str(out), "--json"]) == 0
    res = json.loads(capsys.readouterr().out)
    got, src = out.read_text().splitlines(), text.splitlines()
    assert got[1] == "G91 G28 Z0" and got[6] == "G53 G0 Z0"  # machine-coordinate lines untouched
    # Z unknown after G28 and after G53: those rapids pass as programmed and are reported
    assert got[2] == src[2] and got[7] == src[7]
    assert res["warnings"]["uncompensated_rapids"] == [3, 8]
    assert all(got[i] != src[i] for i in (3, 4, 5))  # known again from Z50 on: compensated
    assert res["moves"] == 5  # the G28 and G53 lines are no moves


def test_feed_move_from_an_unknown_axis_after_g53_is_refused(tmp_path, capsys):
    model = tmp_path / "m.json"
    save_model(MODEL, model)
    code, err, out = run_cli(tmp_path, capsys, "G90 G0 X0 Y0 Z10\nG53 G0 Z0\nG1 X5 F100\n", model)
    assert code == 2 and "line 3: feed move while Z is not known" in err and not out.exists()


@pytest.mark.parametrize("name, data, gist", [
    ("empty.nc", b"", "prog: no moves"),
    ("blank.nc", b"%\n(only a header)\nM30\n%\n", "no moves"),
    ("empty.cl", b"", "no CL points"),
    ("comments.cl", b"# nothing\n$$ here\n", "no CL points"),
    ("nul.nc", b"G90 G0 X0 Y0 Z0\nG1 X1\x00\x00\x01\n", "line 2: NUL byte"),
    ("nul.cl", b"1 2 3 0 0 1\n\x00\x7fELF\n", "line 2: NUL byte"),
])
def test_empty_and_binary_inputs_are_errors_naming_the_file(tmp_path, capsys, name, data, gist):
    model = tmp_path / "m.json"
    save_model(MODEL, model)
    code, err, out = run_cli(tmp_path, capsys, data, model, name=name)
    assert code == 2 and not out.exists()
    assert name in err and gist.replace("prog", name) in err.replace(str(tmp_path) + "/", ""), err


def test_lone_cr_program_is_compensated_like_the_lf_program(tmp_path, capsys):
    """Issue 11: with lone-CR line ends, everything after the first ';' comment passed uncompensated."""
    model = tmp_path / "m.json"
    save_model(MODEL, model)
    text = "G90 G0 X0 Y0 Z10 ; start\nG1 X50 F300\n(cut)\nY40 ; side\nX-20 Z5\n"
    outs = []
    for eol in ("\n", "\r"):
        code, err, out = run_cli(tmp_path, capsys, text.replace("\n", eol), model, "--json")
        assert code == 0, err
        outs.append(out.read_bytes())
    assert outs[1] == outs[0].replace(b"\n", b"\r")
    assert outs[0].count(b"X") == 4 and b"X-20 " not in outs[0]  # every move rewritten
    code, err, out = run_cli(tmp_path, capsys, (text + "G2 X0 Y0 I5 J5\n").replace("\n", "\r"), model)
    assert code == 2 and "line 6: G2" in err


def test_cl_data_refusal_names_the_cl_file_line(tmp_path, capsys):
    """CL data is compensated as generated G-code: a refusal still names the line of the CL file."""
    cl = b"$$ header\n# comment\n\n10 20 30 0 0 1\nGOTO/50,20,30,0,0,1\n"
    code, err, out = run_cli(tmp_path, capsys, cl, model_file(tmp_path, {"E_XX": 12.5}), "--force", name="part.cl")
    assert code == 2 and "part.cl, line 4: the correction of X by -12.5000 mm" in err and not out.exists()


def test_split_last_line_without_line_end_keeps_the_files_line_ends(tmp_path):
    prog, out = tmp_path / "cr.nc", tmp_path / "o.nc"
    prog.write_bytes(b"G90 G0 X-200 Y-150 Z-100 B20 C0 ; start\rG1 X200 Y150 Z100 B60 C90 F500")
    rep = ProgramCompensator(Compensator(MODEL, M, "full"), tolerance=5e-4).run(prog, out)
    data = out.read_bytes()
    assert rep.subdivided_moves == 1 and b"\n" not in data and data.count(b"\r") == 1 + rep.lines_inserted
