"""The fast G-code parser (byte-level ``scan_block`` with ``parse_chunk`` behind it, chunk by chunk as the
compensation streams a file) agrees with a plain, slow reference parser written here from the rules alone (issue 11).

The reference reads a program line by line: lines end at CR LF, lone CR or LF; comments are ``( ... )`` (to the
closing parenthesis or the line end) and ``; ...`` (to the line end); a block is words, each a letter, optional
blanks and one number ``[+-]digits[.digits]`` (at least one digit), words separated by optional blanks; a number
followed by a point, a sign, an exponent (``e``/``E`` and a digit) or, after blanks, another number is an error;
``/`` (block delete) and ``%`` are ignored.  Modal state: G0/G1 (motion), G90/G91 (absolute/incremental),
G20/G21 (inch/mm, linear axes only); X Y Z start unknown, B C at 0; an incremental word of an unknown axis is an
error.  A motion row is a line with an axis word; its absolute position in mm and deg is compared.
"""
from __future__ import annotations

import io
import random
import re

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mtcal.errors import InputError
from mtcal.nc import gcode

AXES = "XYZBC"  # this machine's axis words (the parser under test: gcode.words("dmu50").letters)
INCH = 25.4


class RefError(Exception):
    """The reference refuses the program; ``lines``: 1-based lines that are wrong (every syntax error, then the
    first semantic one)."""

    def __init__(self, lines):
        super().__init__(lines)
        self.lines = set(lines)


def ref_split(text):
    parts = re.split(r"\r\n|\r|\n", text)
    return parts[:-1] if parts and parts[-1] == "" else parts


def ref_strip_comments(line):
    out, i = [], 0
    while i < len(line):
        c = line[i]
        if c == ";":
            break
        if c == "(":
            j = line.find(")", i)
            i = len(line) if j < 0 else j + 1
            out.append(" ")
            continue
        out.append(c)
        i += 1
    return "".join(out)


def ref_words(code):
    """[(LETTER, value)] of a block, or None when it is not words."""
    words, i, n = [], 0, len(code)
    while True:
        while i < n and code[i] in " \t/%":
            i += 1
        if i == n:
            return words
        if not code[i].isalpha():
            return None
        letter = code[i].upper()
        i += 1
        while i < n and code[i] in " \t":
            i += 1
        j = i
        if j < n and code[j] in "+-":
            j += 1
        k = j
        while k < n and code[k].isdigit():
            k += 1
        if k < n and code[k] == ".":
            k += 1
            while k < n and code[k].isdigit():
                k += 1
        if not any(ch.isdigit() for ch in code[j:k]):
            return None
        value = float(code[i:k])
        # the number must end here: no point, sign or exponent next, no number after blanks
        b = k
        while b < n and code[b] in " \t":
            b += 1
        if b < n and (code[b] in "+-." or code[b].isdigit()):
            return None
        if k + 1 < n and code[k] in "eE" and (code[k + 1].isdigit() or code[k + 1] in "+-"):
            return None
        words.append((letter, value))
        i = k


def reference(text):
    """(rows: 0-based line indices, axes (m, 5) mm/deg, motion (m,)) or RefError."""
    lines = ref_split(text)
    blocks = [ref_words(ref_strip_comments(ln)) for ln in lines]
    bad = [i + 1 for i, b in enumerate(blocks) if b is None]
    try:
        out = modal(blocks)
    except RefError as err:
        raise RefError(bad + sorted(err.lines)) from None
    if bad:
        raise RefError(bad)
    return out


def modal(blocks):
    """Rows of the word lists ``blocks`` (a None block, not words, counts as empty) under the modal rules."""
    motion, absolute, inch = 1, True, False
    pos = [float("nan")] * 3 + [0.0, 0.0]
    rows, axes, motions = [], [], []
    for i, words in enumerate(blocks):
        words = words or []
        for letter, v in words:
            if letter == "G":
                if v in (0, 1):
                    motion = int(v)
                elif v in (90, 91):
                    absolute = v == 90
                elif v in (20, 21):
                    inch = v == 20
        moved = False
        for letter, v in words:
            if letter in AXES:
                a = AXES.index(letter)
                val = v * (INCH if inch and a < 3 else 1.0)
                if absolute:
                    pos[a] = val
                elif pos[a] != pos[a]:
                    raise RefError([i + 1])
                else:
                    pos[a] = pos[a] + val
                moved = True
        if moved:
            rows.append(i)
            axes.append(list(pos))
            motions.append(motion)
    return rows, np.array(axes).reshape(-1, 5), motions


# ----------------------------------------------------------------------------------------------- generator
class Choices:
    """Choices made from one drawn list of integers, then from a generator seeded by them (cheaper than one
    Hypothesis draw per choice; shrinking the integers towards 0 shrinks the program's first choices towards
    their first options)."""

    def __init__(self, values):
        self.values, self.i = values, 0
        self.rng = random.Random(repr(values))

    def int(self, lo, hi):
        v = self.values[self.i] if self.i < len(self.values) else self.rng.randrange(2**20)
        self.i += 1
        return lo + v % (hi - lo + 1)

    def pick(self, options):
        return options[self.int(0, len(options) - 1)]

    def text(self, alphabet, most):
        return "".join(self.pick(alphabet) for _ in range(self.int(0, most)))


def number(c, integer=False):
    """A number as CAM systems and people write it: signs, no digits before or after the point, trailing zeros."""
    if integer:
        return str(c.int(0, 400))
    sign, whole, decimals, style = c.pick(["", "", "-", "+"]), c.int(0, 400), c.int(0, 5), c.int(0, 3)
    frac = str(c.int(0, 99999) % 10**decimals).zfill(decimals) if decimals else ""
    if style == 0 or not frac:
        body = str(whole) + ("." if style == 1 else "")
    elif style == 1 and whole == 0:
        body = "." + frac  # no digit before the point
    else:
        body = f"{whole}.{frac}"
    return sign + body


def case(c, letter):
    return letter.lower() if c.int(0, 3) == 0 else letter


COMMENT = "XYZBC015 .;-+abG"
MALFORMED = ["X1.2.3", "Y1e2", "Z1 0.5", "X1-2", "B1E+3", "C 2 5", "X.5.", "F1.2.3"]


def block(c, inject):
    """One line of words (N, G, axis, F S M T), comments of both kinds, odd spacing and case; ``inject``: one
    malformed word somewhere."""
    words = []
    if c.int(0, 1):
        words.append(case(c, "N") + number(c, integer=True))
    for _ in range(c.int(0, 2)):
        words.append(case(c, "G") + c.pick(["0", "1", "00", "01", "90", "91", "20", "21", "17", "94", "1.0"]))
    axes = list(AXES)
    for _ in range(c.int(0, 5)):
        words.append(case(c, axes.pop(c.int(0, len(axes) - 1))) + c.pick(["", "", " ", "  "]) + number(c))
    if c.int(0, 1):
        words.append(case(c, c.pick("FSMT")) + c.pick(["3", "8", "100", "1200.5"]))
    if inject:
        words.insert(c.int(0, len(words)), c.pick(MALFORMED))
    if c.int(0, 1):  # words in any order
        words = [words.pop(c.int(0, len(words) - 1)) for _ in range(len(words))]
    out = "/" if c.int(0, 9) == 0 else ""
    for w in words:
        out += c.pick(["", " ", " ", "\t", "  "]) + w
        if c.int(0, 6) == 0:
            out += "(" + c.text(COMMENT, 8)
            if c.int(0, 3) == 0:
                return out  # an unclosed comment runs to the line end
            out += ")"
    if c.int(0, 4) == 0:
        out += c.pick([" ", ""]) + ";" + c.text(COMMENT, 8) + c.pick(["", "(x)", ")"])
    return out if out.strip() else "%"


@st.composite
def program(draw):
    """(text, split): a program of 1-20 lines with LF, CR LF and lone CR line ends (mixed or one kind), maybe a
    header, maybe a malformed word, and where the stream is cut into two blocks of whole lines."""
    c = Choices(draw(st.lists(st.integers(0, 2**20), min_size=1, max_size=200)))
    n = c.int(1, 20)
    bad_line = c.int(0, n - 1) if c.int(0, 5) == 0 else -1
    head = [c.pick(["G90 G0 X0 Y0 Z0", "G90 G21 G0 X10 Y-5 Z50 B0 C0", "%"])] if c.int(0, 1) else []
    lines = head + [block(c, i == bad_line) for i in range(n)]
    ends = [c.pick(["\n", "\r\n", "\r"]) for _ in lines]
    if c.int(0, 1):  # one kind of line end for the whole file
        ends = [ends[0]] * len(lines)
    if c.int(0, 4) == 0:
        ends[-1] = ""  # the last line without a line end
    text = "".join(ln + e for ln, e in zip(lines, ends))
    return text, c.int(0, len(lines))


# ----------------------------------------------------------------------------------------------- the parser under test
def fast(text, split):
    """The compensation's way through a file: blocks of whole lines, the byte-level path first, parse_chunk when it
    declines; the modal state carried across blocks."""
    lines = io.StringIO(text, newline="").readlines()
    state, rows, axes, motion = gcode.ModalState(), [], [], []
    for first, part in ((1, lines[:split]), (split + 1, lines[split:])):
        if not part:
            continue
        blk = gcode.scan_block("".join(part), state, first)
        ch = blk if blk is not None else gcode.parse_chunk(part, state, first, "prog.nc")
        rows += (ch.rows + first - 1).tolist()
        axes.append(ch.axes)
        motion += ch.motion.tolist()
    return rows, np.concatenate(axes).reshape(-1, 5) if axes else np.zeros((0, 5)), motion


def whole(text):
    lines = io.StringIO(text, newline="").readlines()
    ch = gcode.parse_chunk(lines, gcode.ModalState(), 1, "prog.nc")
    return ch.rows.tolist(), ch.axes, ch.motion.tolist()


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(program())
def test_fast_parser_agrees_with_the_reference(prog):
    text, split = prog
    assert gcode.count_lines(text) == len(ref_split(text))
    try:
        want = reference(text)
    except RefError as err:
        for parse in (lambda: fast(text, split), lambda: whole(text)):
            try:
                parse()
            except InputError as exc:
                line = int(re.match(r"prog\.nc, line (\d+): ", str(exc)).group(1))
                assert line in err.lines, (str(exc), err.lines)
            else:
                raise AssertionError(f"accepted a program the reference refuses (lines {sorted(err.lines)})")
        return
    for got in (fast(text, split), whole(text)):
        assert got[0] == want[0]
        np.testing.assert_array_equal(got[1], want[1])
        assert got[2] == want[2]


def test_the_reference_itself_on_hand_worked_cases():
    """The oracle checked by hand before it judges: CR/CRLF/LF, both comments, modal carry-over, inch, G91."""
    rows, axes, motion = reference("G90 g0 x1 (X9) Y2 Z3\rG91 G1 X1 ; Y7\r\n(all comment)\nG20 G90 Y1\nN5 Z.5")
    assert rows == [0, 1, 3, 4] and motion == [0, 1, 1, 1]
    np.testing.assert_array_equal(axes, [[1, 2, 3, 0, 0], [2, 2, 3, 0, 0], [2, 25.4, 3, 0, 0], [2, 25.4, 12.7, 0, 0]])
    for bad in ("X1.2.3", "X1e2", "X1 0.5", "X1-2", "10 X1", "G91 X1"):
        try:
            reference(bad)
        except RefError as err:
            assert err.lines == {1}
        else:
            raise AssertionError(bad)
