"""G-code parsing safety (issue 11): line ends, one-token numbers, refusals with their own message, safe headers,
inverse-time feed.  Every refusal names the file and the line; the byte-level path leaves such blocks to parse_chunk."""
from __future__ import annotations

import io

import numpy as np
import pytest

from mtcal.errors import InputError
from mtcal.nc import gcode

HEAD = "G90 G21\nG0 X0 Y0 Z0\n"  # lines 1-2; the line under test is line 3


def lines_of(text):
    return io.StringIO(text, newline="").readlines()


def parse(text, state=None):
    return gcode.parse_chunk(lines_of(text), state or gcode.ModalState(), 1, "prog.nc")


def refusal(text):
    """The message parse_chunk raises; the byte-level path must not accept the same block."""
    st = gcode.ModalState()
    assert gcode.scan_block(text, st, 1) is None
    with pytest.raises(InputError) as exc:
        parse(text)
    return str(exc.value)


@pytest.mark.parametrize("line, gist", [
    # numbers that are not one token
    ("G1 X1.2.3", "more than one decimal point"),
    ("G1 X1e2", "exponent"),
    ("G1 Y-1E-2", "exponent"),
    ("G1 X1 0.5", "blanks inside a number"),
    ("G1 X 1 0.5", "blanks inside a number"),
    ("G1 X1-2", "stray characters"),
    ("G1 X1 F1.2.3", "'F1.2.3'"),
    ("G1 X1 S100 0", "blanks inside a number"),
    # tool centre point management: Heidenhain, Fanuc, Siemens
    ("M128", "TCPM"),
    ("m 128", "TCPM"),
    ("G43.4 H1", "TCPM"),
    ("G43.5 H1", "TCPM"),
    ("TRAORI", "TCPM"),
    # canned cycles
    ("G81 X0 Y0 Z-5 R1", "canned cycle"),
    ("G83 X0 Y0 Z-5 Q1", "canned cycle"),
    ("G73 X0 Y0 Z-5", "canned cycle"),
    ("CYCLE81(10,0,1,-5)", "canned cycle"),
    # rotations, frames, tilted working planes
    ("G68 X0 Y0 R45", "rotates, scales or shifts"),
    ("G68.2 X0 Y0 Z0 I0 J45 K0", "rotates, scales or shifts"),
    ("CYCLE800(1,\"TC1\",0,57,0,0,0,45,0,0,0,0,0,1)", "rotates, scales or shifts"),
    ("PLANE SPATIAL SPA+0 SPB+45 SPC+0", "rotates, scales or shifts"),
    ("ROT Z45", "rotates, scales or shifts"),
    ("G51 X0 Y0 P2", "rotates, scales or shifts"),
    ("G92 X0 Y0", "rotates, scales or shifts"),
    # arcs keep theirs
    ("G2 X10 Y0 I5 J0", "circular arcs"),
    ("G03 X10 Y0 R5", "circular arcs"),
    # reference-point return with an intermediate point, machine coordinates under G91, G93 without F
    ("G90 G28 Z0", "intermediate point"),
    ("G91 G28 Z5", "intermediate point"),
    ("G91 G53 Z0", "G53 under G91"),
    ("G93 G1 X5", "G93"),
])
def test_refusals_have_their_own_message_and_name_the_line(line, gist):
    for eol in ("\n", "\r\n", "\r"):
        msg = refusal((HEAD + line + "\nG1 X1\n").replace("\n", eol))
        assert msg.startswith("prog.nc, line 3: ") and gist in msg, msg
        if "TCPM" in gist or "canned" in gist or "rotates" in gist:
            assert "arc" not in msg  # issue 11: G68 / G81 were refused with a message about arcs


def test_lone_cr_comment_does_not_swallow_the_rest_of_the_file():
    """Issue 11: after the first ';' comment with lone-CR line ends the rest was taken as comment."""
    body = "G90 G0 X0 Y0 Z0 ; start\nG1 X10 (cut) F100\n; note\nY20 ; side\nZ-1\n"
    ref = parse(body)
    for eol in ("\r\n", "\r"):
        ch = parse(body.replace("\n", eol))
        assert ch.rows.tolist() == ref.rows.tolist() == [0, 1, 3, 4]
        np.testing.assert_array_equal(ch.axes, ref.axes)
        np.testing.assert_array_equal(ch.axes[-1], [10, 20, -1, 0, 0])
        assert "".join(ch.pieces) == body.replace("\n", eol)  # byte for byte
    msg = refusal((body + "G2 X5 Y5 I1 J1\n").replace("\n", "\r"))
    assert msg.startswith("prog.nc, line 6: G2")


def test_line_numbers_count_every_kind_of_line_end():
    assert gcode.count_lines("a\rb\r\nc\nd") == 4
    text = "G0 X0 Y0 Z0\r(a)\r\n;b\nG1 X1 A2\r"
    assert refusal(text).startswith("prog.nc, line 4: ")


@pytest.mark.parametrize("header", ["G91 G28 Z0", "G28 G91 Z0", "G53 G0 Z0", "G91 G30 Z0", "G28"])
def test_safe_headers_pass_through_and_leave_the_named_axes_unknown(header):
    """Machine-coordinate moves are not compensated: afterwards the named axes (G28 without words: X Y Z) are at a
    machine position whose workpiece coordinates the program does not tell, until programmed again."""
    ch = parse(f"G90 G0 X1 Y2 Z3 B10 C20\n{header}\nG90 G0 X5 Y6\nZ7\nG1 X8 F100\n")
    assert ch.rows.tolist() == [0, 2, 3, 4]  # the header line is no move
    z_only = "Z" in header
    np.testing.assert_array_equal(ch.axes[1], [5, 6, np.nan if z_only or header == "G28" else 3, 10, 20])
    np.testing.assert_array_equal(ch.axes[3], [8, 6, 7, 10, 20])
    assert ch.fresh.tolist() == [False, True, False, False]  # the move after it starts from an unknown point
    assert ch.motion.tolist() == [0, 0, 0, 1]
    if header == "G28":
        np.testing.assert_array_equal(parse(f"G0 X1 Y2 Z3\n{header}\nG0 B1\n").axes[1], [np.nan] * 3 + [1, 0])


def test_g53_motion_word_is_modal_and_g91_after_g28_stays():
    ch = parse("G90 G1 X1 Y2 Z3 F100\nG53 G0 Z0\nX5\n")
    assert ch.motion.tolist() == [1, 0]  # G0 on the G53 line stays in force
    ch = parse("G90 G0 X1 Y2 Z3\nG91 G28 Z0\nX1\n")
    np.testing.assert_array_equal(ch.axes[1], [2, 2, np.nan, 0, 0])  # still G91: X1 is an increment
    assert not ch.absolute[1]


def test_inverse_time_feed_is_read_per_block():
    ch = parse("G90 G0 X0 Y0 Z0\nG93 G1 X5 F10\nX6 F20.5\nG0 X0\nG94 G1 X7 F300\n")
    np.testing.assert_array_equal(ch.feed, [np.nan, 10, 20.5, np.nan, np.nan])
    assert gcode.scan_block("G94 G1 X7 F300\n", gcode.ModalState(), 1) is not None  # G94: plain
    st = gcode.ModalState()
    parse("G0 X0 Y0 Z0\nG93\n", st)
    assert st.inverse_time and gcode.scan_block("G1 X1 F2\n", st, 3) is None  # G93 in force: parse_chunk


def test_replace_feed_skips_comments_and_other_lines():
    ch = parse("G90 G0 X0 Y0 Z0 F999\nG93 G1 (F1) X5 F10 Y1 ; F2\nF3\n")
    gcode.replace_feed(ch, 1, "30.0000")
    assert "".join(ch.pieces) == "G90 G0 X0 Y0 Z0 F999\nG93 G1 (F1) X5 F30.0000 Y1 ; F2\nF3\n"


def test_numbers_that_look_unusual_but_are_one_token_pass():
    ch = parse("G0 X.5 Y-.25 Z+3. B0 C0\nG1 x 1.5 y-0 F100 S12000 M3\nN10G1X2Y3\n")
    np.testing.assert_array_equal(ch.axes[:, :3], [[0.5, -0.25, 3], [1.5, 0, 3], [2, 3, 3]])
    st = gcode.ModalState()
    blk = gcode.scan_block("G0 X.5 Y-.25 Z+3. B0 C0\nG1 x 1.5 y-0 F100 S12000 M3\nN10G1X2Y3\n", st, 1)
    assert blk is not None and np.array_equal(blk.axes, ch.axes)
    assert gcode.scan_block("G1 X128.5 M3\n", gcode.ModalState(), 1) is not None  # 128 is not M128


def test_huge_number_is_refused_not_read_as_infinity():
    assert "too large" in refusal("G0 X" + "9" * 400 + " Y0 Z0\n")


@pytest.mark.parametrize("line, gist", [
    ("1 2 3 0 0 nan\n", "finite"),
    ("inf 2 3 0 0 1\n", "finite"),
    ("1 2 3 0 0 0\n", "not a unit vector (length 0)"),
    ("1 2 3 0.5 0 0.5\n", "not a unit vector (length 0.707107)"),
    ("GOTO/1,2,3,0,0,1,4\n", "needs 6 numbers"),
])
def test_cl_points_must_be_finite_with_a_unit_tool_axis(line, gist):
    with pytest.raises(InputError) as exc:
        gcode.parse_cl(lines_of("$$ cam\r\n" + line), 1, "a.cl")
    assert str(exc.value).startswith("a.cl, line 2") and gist in str(exc.value)


def test_cl_tool_axis_written_to_three_decimals_is_normalised():
    poses, nos = gcode.parse_cl(lines_of("1 2 3 0.707 0 0.707\r"), 1, "a.cl")
    np.testing.assert_allclose(poses, [[1, 2, 3, 0.5 ** 0.5, 0, 0.5 ** 0.5]], rtol=1e-15)
    assert nos.tolist() == [1]


# ----------------------------------------------------------------------------- issue 20: subprogram calls
@pytest.mark.parametrize("call", ["M98 P1000", "M99", "CALL PGM TNC:\\SUB.H", "CALL LBL 5"])
def test_a_subprogram_call_is_refused_or_passed_with_a_warning(tmp_path, capsys, call):
    """Its moves are in another program: refused naming the line (it passed with exit 0 and no word); with
    --allow-subprograms passed unchanged with a warning naming the line."""
    from mtcal.cli import main
    from mtcal.model.errormodel import ErrorModel, save_model
    prog = tmp_path / "sub.nc"
    prog.write_text(f"G90 G21\nG0 X10 Y10 Z10 B0 C0\n{call}\nG1 X20 Y10 Z10 B0 C0 F100\n")
    model = tmp_path / "m.json"
    save_model(ErrorModel("dmu50", {"E_C0Y": 1e-5}, {}), model)
    out = tmp_path / "o.nc"
    assert main(["compensate", str(prog), "--model", str(model), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "sub.nc, line 3:" in err and "subprogram call" in err and not out.exists()
    if call.startswith("CALL"):
        return  # Heidenhain conversational: named, but no ISO G-code to pass it through
    assert main(["compensate", str(prog), "--model", str(model), "-o", str(out), "--allow-subprograms"]) == 0
    err = capsys.readouterr().err
    assert "sub.nc:3:" in err and "NOT compensated" in err
    assert out.read_text().splitlines()[2] == call


def test_a_macro_call_is_refused_even_when_subprograms_are_allowed(tmp_path, capsys):
    from mtcal.cli import main
    from mtcal.model.errormodel import ErrorModel, save_model
    prog = tmp_path / "g65.nc"
    prog.write_text("G90 G21\nG0 X10 Y10 Z10 B0 C0\nG65 P9010 A1 B2\n")
    model = tmp_path / "m.json"
    save_model(ErrorModel("dmu50", {"E_C0Y": 1e-5}, {}), model)
    assert main(["compensate", str(prog), "--model", str(model), "-o", str(tmp_path / "o"), "--allow-subprograms"]) == 2
    assert "g65.nc, line 3: G65 is a macro call" in capsys.readouterr().err
