"""G-code / CL parsing and writing (issue 6): byte-exact round trip, modal values, refusals naming the line."""
from __future__ import annotations

import numpy as np
import pytest

from mtcal.errors import InputError
from mtcal.nc import gcode

PROGRAM = [
    "%\n",
    "O1234 (PART 7; ROUGH)\r\n",
    "N10 G90 G21 G17 ; set up\n",
    "N20 G0 X10. Y-2.5 Z50 B0 C0 (approach)\n",
    "N30 g1 z1.25 f300\n",
    "N40X12.5Y-3.0001\n",
    "N50 (only a comment with X99 in it) M8\n",
    "/N60 Y  4.0 F1200 M3 S8000\n",
    "N70 B12.5 C-30\n",
]


def parse(lines, state=None, **kw):
    return gcode.parse_chunk(lines, state or gcode.ModalState(), 1, "prog.nc", **kw)


def test_round_trip_is_byte_exact_and_only_coordinates_change():
    ch = parse(PROGRAM)
    assert ch.rows.tolist() == [3, 4, 5, 7, 8]  # comment-only and set-up lines are not moves
    # no changes: the pieces join to the original, byte for byte (CRLF, comments, '/', N, F, lower case)
    assert "".join(ch.pieces) == "".join(PROGRAM)
    gcode.edit(ch, 2, {0: "12.5013", 1: "-3.0002"}, [(2, "1.2504")], "")  # N40X12.5Y-3.0001: no blanks
    gcode.edit(ch, 3, {1: "4.0007"}, [(0, "12.5001")], " ", cont=["X12.6 Y4.1", "X12.7"])
    out = "".join(ch.pieces).splitlines(keepends=True)
    assert out[5] == "N40X12.5013Y-3.0002Z1.2504\n"
    assert out[7:10] == ["/N60 Y  4.0007 X12.5001 F1200 M3 S8000\n", "X12.6 Y4.1\n", "X12.7\n"]  # blanks kept
    assert out[:5] + out[6:7] + out[10:] == PROGRAM[:5] + PROGRAM[6:7] + PROGRAM[8:]


def test_modal_values_are_carried_and_decimals_follow_the_input():
    ch = parse(PROGRAM)
    np.testing.assert_allclose(ch.axes, [[10, -2.5, 50, 0, 0], [10, -2.5, 1.25, 0, 0], [12.5, -3.0001, 1.25, 0, 0],
                                         [12.5, 4.0, 1.25, 0, 0], [12.5, 4.0, 1.25, 12.5, -30]])
    assert ch.motion.tolist() == [0, 1, 1, 1, 1]
    assert ch.decimals[2].tolist() == [4, 4, 4, 4, 4]  # at least 4 (0.1 um, 0.0001 deg)
    ch = parse(["G1 X1.123456 Y2\n", "X2\n"], min_decimals=(3, 4, 3))
    assert ch.decimals.tolist() == [[6, 3, 3, 3, 3], [6, 3, 3, 3, 3]]  # running maximum per axis


def test_state_carries_across_chunks_incremental_and_inch():
    st = gcode.ModalState()
    parse(["G90 G0 X10 Y20 Z30\n"], st)
    ch = gcode.parse_chunk(["G91 G1 X1.5\n", "Y-2 Z0.5\n", "G90 G20 X1\n", "G21 Z3\n"], st, 2, "p.nc")
    np.testing.assert_allclose(ch.axes, [[11.5, 20, 30, 0, 0], [11.5, 18, 30.5, 0, 0], [25.4, 18, 30.5, 0, 0],
                                         [25.4, 18, 3, 0, 0]])
    assert ch.absolute.tolist() == [False, False, True, True] and ch.inch.tolist() == [False, False, True, False]
    assert ch.decimals[2, 0] == 5  # inch words: one decimal more


@pytest.mark.parametrize("line, words", [
    ("N30 G2 X10 Y10 I5 J0\n", ["line 3", "G2", "arc"]),
    ("N30 G1 X10 I5\n", ["line 3", "'I5'"]),
    ("N30 G1 X10 A5\n", ["line 3", "'A5'", "no such axis"]),
    ("N30 G1 X#1\n", ["line 3", "parameters"]),
    ("N30 G68 X0 Y0 R45\n", ["line 3"]),
    ("N30 G1 X1 X2\n", ["line 3", "twice"]),
    ("N30 CYCLE800(1)\n", ["line 3", "CYCLE800"]),
    ("N30 G28 X0\n", ["line 3", "G28"]),
    ("N30 G81 X0 Y0 Z-5\n", ["line 3", "G81"]),
])
def test_what_cannot_be_compensated_is_refused_naming_the_line(line, words):
    with pytest.raises(InputError) as exc:
        parse(["G90\n", "G0 X0 Y0 Z0\n", line])
    for w in words:
        assert w in str(exc.value)
    assert "prog.nc" in str(exc.value)


def test_incremental_before_known_position_is_refused():
    with pytest.raises(InputError, match="line 2: incremental move"):
        parse(["G91\n", "G1 X1\n"])


def test_dwell_and_comments_are_not_coordinates():
    ch = parse(["G0 X1 Y1 Z1\n", "G4 X2.5\n", "(X5 Y5)\n", "M3 ; B90\n"])
    assert ch.rows.tolist() == [0]


def test_fmt_never_writes_negative_zero():
    assert gcode.fmt(-0.0, 3) == "0.000" and gcode.fmt(-0.00004, 4) == "0.0000" and gcode.fmt(-1.23456, 4) == "-1.2346"


def test_parse_cl():
    poses, nos = gcode.parse_cl(["# header\n", "1 2 3 0 0 1\n", "GOTO/4,5,6,0.6,0,0.8\n", "\n"], 1, "a.cl")
    np.testing.assert_allclose(poses, [[1, 2, 3, 0, 0, 1], [4, 5, 6, 0.6, 0, 0.8]])
    assert nos.tolist() == [2, 3]
    with pytest.raises(InputError, match="a.cl, line 1: CL data needs 6 numbers"):
        gcode.parse_cl(["1 2 3\n"], 1, "a.cl")


def _varied_program(rng, n=400, nl="\n"):
    """Plain lines of every kind the byte-level path takes: comments, lower case, blanks after letters, signs,
    missing words, G0/G1/G01/G90/G21/G17, N/F/M/S/T words, no digits before or after the point."""
    lines = ["%" + nl, "O0007 (BENCH; X1 Y2)" + nl, "N1 G90 G21 G17 ; set up B90" + nl, "N2 G0 X0 Y0 Z50 B0 C0" + nl]
    for k in range(n):
        words = []
        for a, name in enumerate("XYZBC"):
            if rng.random() < 0.8:
                v = rng.uniform(-300, 300) if a < 3 else rng.uniform(0, 180) if a == 3 else rng.uniform(-360, 360)
                s = f"{v:.{int(rng.integers(0, 6))}f}"
                if k % 17 == 0:
                    s = s.rstrip("0") or "0"
                if k % 19 == 0 and v > 0:
                    s = "+" + s
                if k % 23 == 0 and s.startswith("0."):
                    s = s[1:]
                words.append((name.lower() if k % 13 == 0 else name) + ("  " if k % 11 == 0 else "") + s)
        head = [f"N{k + 10}"] + (["G0"] if k % 29 == 0 else ["G01"] if k % 29 == 1 else [])
        line = " ".join(head + words) + (" F800" if k % 31 == 0 else "") + (" (X5)" if k % 37 == 0 else "")
        lines.append(line + (" ; c" if k % 41 == 0 else "") + nl)
        if k % 97 == 50:
            lines.append("M8 S8000 T1" + nl)
    lines += ["M30" + nl, "%"]
    return lines


@pytest.mark.parametrize("nl", ["\n", "\r\n"])
def test_byte_level_scan_equals_parse_chunk(nl):
    rng = np.random.default_rng(8)
    lines = _varied_program(rng, nl=nl)
    ref = parse(lines, min_decimals=(4, 5, 4))
    st = gcode.ModalState()
    blk = gcode.scan_block("".join(lines), st, 1, (4, 5, 4))
    assert blk is not None and blk.n_lines == len(lines) == gcode.count_lines("".join(lines))
    for name in ("rows", "axes", "present", "given", "decimals", "motion"):
        np.testing.assert_array_equal(getattr(blk, name), getattr(ref, name), err_msg=name)
    # numbers exactly as float() reads them, spans as the line-piece split has them
    num = [p for p in ref.pieces[2::3]]
    text = "".join(lines)
    assert [text[a:b] for a, b in zip(blk.num_start.tolist(), blk.num_end.tolist())] == num
    # nothing to change: the block is written back byte for byte
    assert gcode.render_block(blk, [], {}) == text.encode("latin-1")


@pytest.mark.parametrize("text", ["G91\nX1\n", "G20 X1\n", "G4 X2\nX1\n", "G2 X1 Y1 I1\n", "X1 X2\n", "X1 A2\n",
                                  "X1.2.3\n", "X12345678901234567\n", "G28 X0\n", "a\rb\n", "CYCLE800\n", "G-1 X1\n"])
def test_byte_level_scan_leaves_the_rest_to_parse_chunk(text):
    st = gcode.ModalState()
    assert gcode.scan_block(text, st, 1) is None
    assert st.position[0] != st.position[0] and st.motion == 1  # state untouched (NaN X)


def test_format_fixed_writes_what_percent_f_writes():
    rng = np.random.default_rng(3)
    for d in (0, 1, 3, 4, 7):
        k = np.concatenate([rng.integers(-10**9, 10**9, 3000), np.arange(-150, 150), [10**d, -10**d, 10**d - 1]])
        txt, ln = gcode.format_fixed(k, d)
        got = [bytes(txt[i, txt.shape[1] - ln[i]:]).decode() for i in range(len(k))]
        assert got == ["%.*f" % (d, int(x) / 10**d) for x in k]
