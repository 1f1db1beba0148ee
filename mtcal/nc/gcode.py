"""G-code (ISO 6983 subset) and CL data of a five-axis machine: streaming, vectorised chunk parser and line writer.

The axis words are the machine's axis names (``Words``, from the Machine: the DMU 50's X Y Z B C, the trunnion's
X Y Z A C, ...); linear axes in mm or inch, rotary axes in deg.
Scope: G0/G1 moves with the axis words, modal values carried between blocks, G90/G91,
G20/G21, line numbers (N), comments ``( ... )`` and ``; ...``.  Every other word and every byte outside the
coordinate numbers is kept as it is: a line is stored as the list returned by ``re.split`` on the coordinate
numbers, ``[text, ws, number, text, ws, number, ..., tail]``, so writing it back is a ``"".join``.

What cannot be compensated raises ``InputError`` naming the file and line: arcs (G2/G3, I J K R words), axis
words this machine does not have (A B C U V W that are not its axes), parameters and expressions (``#``, ``=``, ``[``), coordinate
transformations and cycles (G28 with axis words, G53, G68, G51, G81.., G92, ...).  Files are read and written as
latin-1 with ``newline=""``, so any byte (including UTF-8 comments and CRLF line ends) passes through unchanged.
"""
from __future__ import annotations

import functools
import re
import warnings
from dataclasses import dataclass, field

import numpy as np

from mtcal.errors import InputError, InputWarning

INCH = 25.4  # mm
ENCODING = "latin-1"  # byte-transparent

_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)"
_COMMENT = re.compile(r"\([^)\r\n]*\)?|;[^\r\n]*")  # a comment ends at its line end (LF, CRLF or lone CR)
_GWORD = re.compile(r"[Gg][ \t]*(\d+(?:\.\d*)?)")
_NWORD = re.compile(r"^[ \t/]*[Nn][ \t]*(\d+)")
# checks run once per chunk on the comment-masked text (C speed); each names the offending line
_OTHER_AXES = "ABCUVW"  # axis letters of ISO 6983 a machine may not have
_NOT_AXES = "DEFGHIJKLMNOPQRST"  # ISO 6983 letters with other meanings: never an axis word here


@dataclass(frozen=True)
class Words:
    """The axis words of one machine's G-code (from its spec, via ``words``): ``letters`` in the machine's axis
    order, which of them are linear, and the patterns and byte table the parsers use for them."""

    machine: str
    letters: str
    linear: np.ndarray
    split: re.Pattern      # coordinate numbers: an axis letter, blanks, a number (the letter stays before)
    checks: tuple          # (pattern, message) run on suspect chunks, in order
    suspect: frozenset     # characters that send a chunk through the checks
    table: bytes           # byte codes of the fast path (see _byte_table)
    allow_subprograms: bool = False  # subprogram / macro calls passed with a warning instead of refused


@functools.cache
def _words(name: str, letters: str, kinds: tuple[str, ...]) -> Words:
    cls = letters + letters.lower()
    other = "".join(c for c in _OTHER_AXES if c not in letters)
    checks = (
        (re.compile(rf"[{other}{other.lower()}][ \t]*[-+.\d]"), "axis word {word!r}: the {machine} has no such axis"),
        (re.compile(r"[IJKRijkr][ \t]*[-+.\d]"),
         "word {word!r}: arcs (G2/G3 with I J K R) and tool-vector words cannot be compensated; "
         "linearise the toolpath (G1) in the CAM system"),
        (re.compile(rf"[{cls}](?![ \t]*[-+]?(?:\d|\.\d))\S*"),
         "{word!r}: an axis letter must be followed by a number (parameters, expressions and cycles are not "
         "supported)"),
        (re.compile(r"[=#\[]\S*"), "{word!r}: parameters and expressions are not supported"),
        (re.compile(r"[A-Za-z][ \t]*[A-Za-z]\S*"),
         "{word!r}: unsupported word (ISO 6983 words are one letter and a number)"),
    )
    suspect = frozenset(other + other.lower() + "IJKRijkr=#[")
    return Words(name, letters, np.array([k == "linear" for k in kinds]),
                 re.compile(rf"(?<=[{cls}])([ \t]*)(" + _NUM + ")"), checks, suspect, _byte_table(letters, suspect))


def words(machine=None) -> Words:
    """The axis words of a machine (mtcal.Machine or name; default: the default machine).  G-code needs five axes
    named by single letters that are not ISO 6983 words of another meaning (G, N, F, I, J, K, ...)."""
    from mtcal.kinematics.machine import DEFAULT_MACHINE, Machine, load_machine
    m = machine if isinstance(machine, Machine) else load_machine(machine or DEFAULT_MACHINE)
    letters = "".join(m.axes)
    if len(m.axes) != 5 or len(letters) != 5 or not letters.isascii() or not letters.isalpha() or any(
            c in _NOT_AXES for c in letters.upper()):
        raise InputError(f"machine {m.name}: G-code needs five axes named by single letters other than "
                         f"{', '.join(_NOT_AXES)}; its axes are {', '.join(m.axes)}")
    return _words(m.name, letters.upper(), tuple(m.axis_kinds))
_TCPM = ("tool centre point management (TCPM) moves the tool tip itself: axis commands of this program are not "
         "machine axis positions, so they cannot be compensated; post-process without TCPM (machine axes)")
_CYCLE = ("is a canned cycle: the controller generates its moves, which cannot be compensated; expand it into "
          "G0/G1 moves in the CAM system")
_FRAME = ("rotates, scales or shifts the coordinate system (tilted working plane): program coordinates are no "
          "longer machine axis positions; post-process to machine axes without it")
# multi-letter words and M codes with a meaning the compensation cannot follow (controller families: Heidenhain
# M128 / PLANE, Siemens TRAORI / CYCLE800 / CYCLEnn / ROT / TRANS, Fanuc G43.4 / G68.2 / G8x are G codes below)
_SPECIAL = re.compile(r"(?i)(?P<tcpm>TRAORI|(?<![A-Z])M[ \t]*0*128(?![\d.]))|(?P<frame>CYCLE[ \t]*800|PLANE|A?ROT|"
                      r"A?TRANS|A?SCALE|A?MIRROR)|(?P<cycle>CYCLE[ \t]*\d+)")
# a word's number must end where the word ends: not followed by a point, an exponent, a sign or (after blanks)
# another number; the number itself is matched atomically so that it cannot give back digits
_BADNUM = re.compile(r"[A-Za-z][ \t]*(?>[-+]?(?:\d+\.?\d*|\.\d+))(?:[ \t]*[-+.\d]|[eE][-+]?\d)\S*")


# subprogram calls: Fanuc / ISO M98 (call), M99 (return), Heidenhain CALL PGM / CALL LBL: the moves they run are in
# another program, which a compensation of this one does not reach (macro calls G65 / G66: _g_refusal)
_SUBPROGRAM = re.compile(r"(?i)(?<![A-Z])M[ \t]*0*9[89](?![\d.])|CALL[ \t]+(?:PGM|LBL)")
# the fast path's screen (a superset: a hit sends the block to parse_chunk, which decides)
_SUBPROGRAM_B = re.compile(rb"[Mm][ \t]*0*9[89]|[Cc][Aa][Ll][Ll][ \t]")


def _may_call(raw: bytes) -> bool:
    """Whether a block's bytes may hold a subprogram call (memchr screens first: most blocks have no M word)."""
    return (b"M" in raw or b"m" in raw or b"L" in raw or b"l" in raw) and _SUBPROGRAM_B.search(raw) is not None
_SUBPROGRAM_TEXT = "the moves it runs are in another program, which compensating this one does not reach"


def _subprograms(code: str, first_line: int, source: str, w: Words) -> None:
    """Refuse a subprogram / macro call naming its line, or (``w.allow_subprograms``) warn that its moves stay
    uncompensated."""
    for m in _SUBPROGRAM.finditer(code):
        line = _line_of(code, m.start(), first_line)
        if not w.allow_subprograms:
            raise _error(source, line, f"{m.group()!r} is a subprogram call: {_SUBPROGRAM_TEXT}; compensate the "
                                       f"called program too, or pass the call with `allow_subprograms` (its moves "
                                       f"stay uncompensated)")
        warnings.warn(InputWarning(f"{source}:{line}: {m.group()!r} is a subprogram call: passed unchanged "
                                   f"(`allow_subprograms`), its moves are NOT compensated"), stacklevel=2)


def _badnum_reason(word: str) -> str:
    tail = word.lstrip("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz \t+-")
    if re.match(r"[\d.]*[eE]", tail):
        return "exponent notation is not G-code"
    if re.match(r"[\d.]+[ \t]+[-+.\d]", tail):
        return ("blanks inside a number: Fanuc ignores them (X1 0.5 = X10.5), other controllers read a second "
                "number; write the number without blanks")
    if tail.count(".") > 1:
        return "more than one decimal point"
    return "stray characters after the number"


def _g_refusal(gs: str) -> str | None:
    """Why the G code ``gs`` (its number as written) is refused, or None when it is handled or passed through."""
    v = float(gs)
    if v in (2.0, 3.0):
        return f"G{gs}: circular arcs cannot be compensated; linearise the toolpath (G1) in the CAM system"
    if v in (43.4, 43.5):
        return f"G{gs}: {_TCPM}"
    if v in (73.0, 74.0, 76.0) or 81.0 <= v <= 89.0:
        return f"G{gs} {_CYCLE}"
    if v in (51.0, 51.1, 52.0, 92.0) or 68.0 <= v < 69.0:
        return f"G{gs} {_FRAME}"
    if v in (65.0, 66.0, 66.1):
        return (f"G{gs} is a macro call: {_SUBPROGRAM_TEXT}, and its arguments are address letters that may be "
                f"axis words here; expand the macro into G0/G1 moves (refused even with `allow_subprograms`)")
    if v in _HANDLED_G or v in _PASS_G:
        return None
    return f"G{gs} is not supported (it moves in another frame, runs a cycle or changes how coordinates are read)"


def _check(code: str, first_line: int, source: str, w: Words) -> None:
    """Raise for the first problem found in ``code`` (comments masked): words with a meaning the compensation
    cannot follow (TCPM, cycles, frames, refused G codes), numbers that are not one token, then the generic
    checks."""
    m = _SPECIAL.search(code)
    if m:
        msg = f": {_TCPM}" if m.group("tcpm") else f" {_CYCLE}" if m.group("cycle") else f" {_FRAME}"
        raise _error(source, _line_of(code, m.start(), first_line), f"{m.group()!r}{msg}")
    _subprograms(code, first_line, source, w)
    for g in _GWORD.finditer(code):
        msg = _g_refusal(g.group(1))
        if msg:
            raise _error(source, _line_of(code, g.start(), first_line), msg)
    m = _BADNUM.search(code)
    if m:
        raise _error(source, _line_of(code, m.start(), first_line),
                     f"{m.group()!r} is not one number ({_badnum_reason(m.group())})")
    for rx, msg in w.checks:
        m = rx.search(code)
        if m:
            raise _error(source, _line_of(code, m.start(), first_line), msg.format(word=m.group(), machine=w.machine))


# G codes that do not change how coordinates are interpreted (passed through)
_PASS_G = {9.0, 15.0, 17.0, 18.0, 19.0, 40.0, 41.0, 42.0, 43.0, 49.0, 50.0, 50.1, 54.0, 55.0, 56.0, 57.0, 58.0,
           59.0, 54.1, 61.0, 64.0, 69.0, 80.0, 94.0, 95.0, 96.0, 97.0}  # 49, 50, 50.1, 69, 80: cancels
# G codes parse_chunk handles: motion, G90/G91, G20/G21, dwell, reference-point return, machine coordinates,
# inverse-time feed
_HANDLED_G = {0.0, 1.0, 4.0, 20.0, 21.0, 28.0, 30.0, 53.0, 90.0, 91.0, 93.0}
_HOME_G = {28.0, 30.0}  # reference-point return: allowed without axis words, positions unknown afterwards


@dataclass
class ModalState:
    """Modal state carried between lines and chunks (values in mm and deg, NaN = not known yet)."""

    motion: int = 1          # 0 rapid, 1 feed (assumed G1 until a motion code is read)
    absolute: bool = True    # G90 / G91
    inch: bool = False       # G20 / G21
    # linear axes unknown until programmed, rotary axes at 0 (the default machine's words; ``for_words``: any)
    position: np.ndarray = field(default_factory=lambda: _start(words()))
    decimals: np.ndarray = field(default_factory=lambda: np.full(len(words().letters), -1, dtype=np.int64))
    inverse_time: bool = False  # G93 (F = 1 / minutes per block) until G94 / G95
    fresh: bool = False      # a machine-coordinate move (G28 / G30 / G53) since the last motion row


    @classmethod
    def for_words(cls, w: Words) -> "ModalState":
        return cls(position=_start(w), decimals=np.full(len(w.letters), -1, dtype=np.int64))


def _start(w: Words) -> np.ndarray:
    return np.where(w.linear, np.nan, 0.0)


@dataclass
class Chunk:
    """One chunk of lines, parsed.  Motion rows are the lines with axis words (in file order).

    ``pieces`` is the chunk text split at the coordinate numbers, ``[text, ws, number, text, ...]``; its join is
    the chunk, byte for byte.  Writing changes pieces: numbers at ``numidx`` and words inserted at ``tail``."""

    lines: list[str]
    first_line: int                      # 1-based number of lines[0] in the file
    pieces: list[str]
    numidx: np.ndarray                   # (m, n_axes) index into pieces of each axis number, -1 if the word is absent
    tail: np.ndarray                     # (m,) index of the text piece after the row's last number
    rows: np.ndarray                     # (m,) index into lines of each motion row
    axes: np.ndarray                     # (m, n_axes) absolute nominal axes, mm and deg (NaN: unknown)
    present: np.ndarray                  # (m, n_axes) bool: word present on the line
    given: np.ndarray                    # (m, n_axes) value as written (program units; increments under G91)
    decimals: np.ndarray                 # (m, n_axes) output decimals (running max of the input's, >= minimum)
    motion: np.ndarray                   # (m,) 0 rapid / 1 feed
    absolute: np.ndarray                 # (m,) bool
    inch: np.ndarray                     # (m,) bool
    fresh: np.ndarray | None = None      # (m,) bool: a machine-coordinate move before the row (start unknown)
    feed: np.ndarray | None = None       # (m,) F of inverse-time (G93) feed rows, NaN elsewhere; None: no G93
    letters: str = ""                    # the machine's axis words (Words.letters), for inserted words


def _mask_comments(text: str) -> str:
    return _COMMENT.sub(lambda m: " " * len(m.group()), text)


def _line_of(text: str, pos: int, first_line: int) -> int:
    """1-based line of character ``pos`` (LF, CRLF and lone CR end a line)."""
    return first_line + count_lines(text[:pos]) - (pos > 0 and text[pos - 1] not in "\r\n")


def _error(source: str, line: int, msg: str) -> InputError:
    return InputError(f"{source}, line {line}: {msg}")


def _decimals(nums: list[str]) -> np.ndarray:
    """Digits after the decimal point of each number string (vectorised over the characters)."""
    if not nums:
        return np.zeros(0, dtype=np.int64)
    a = np.array(nums)
    codes = a.view(np.uint32).reshape(len(nums), -1)
    length = (codes != 0).sum(axis=1)
    isdot = codes == 46
    has = isdot.any(axis=1)
    dot = isdot.argmax(axis=1)
    return np.where(has, length - dot - 1, 0).astype(np.int64)


@dataclass
class _Modes:
    """Per-line modal changes of a chunk from its G words ({line index: value})."""

    motion: dict[int, int] = field(default_factory=dict)
    absolute: dict[int, bool] = field(default_factory=dict)
    inch: dict[int, bool] = field(default_factory=dict)
    inverse_time: dict[int, bool] = field(default_factory=dict)
    machine: dict[int, float] = field(default_factory=dict)  # G28 / G30 / G53 lines: their axis words are no move
    dwell: set[int] = field(default_factory=set)              # G4 lines: X is a time

    def plain(self) -> bool:
        return not (self.motion or self.absolute or self.inch or self.inverse_time or self.machine)


def _g_modes(code: str, starts: np.ndarray, first_line: int, source: str) -> _Modes:
    """The G words of a chunk (comments masked), line by line; a refused G code raises naming its line."""
    md = _Modes()
    if "G" not in code and "g" not in code:
        return md
    gm = list(_GWORD.finditer(code))
    gl = np.searchsorted(starts, [g.start() for g in gm], "right") - 1
    for g, i in zip(gm, gl.tolist()):
        v, gs = float(g.group(1)), g.group(1)
        if v == 0 or v == 1:
            md.motion[i] = int(v)
        elif v == 90 or v == 91:
            md.absolute[i] = v == 90
        elif v == 20 or v == 21:
            md.inch[i] = v == 20
        elif v in (93.0, 94.0, 95.0):
            md.inverse_time[i] = v == 93
        elif v == 4:
            md.dwell.add(i)
        elif v in _HOME_G or v == 53:
            md.machine[i] = v
        else:
            msg = _g_refusal(gs)
            if msg:
                raise _error(source, first_line + i, msg)
    return md


def _machine_move(g: float, words: list[tuple[int, float]], pos: np.ndarray, absolute: bool, source: str,
                  line: int, ww: Words) -> np.ndarray:
    """Position (mm, deg; NaN = unknown) after a machine-coordinate line, which is passed through uncompensated:
    G53 (a move in machine coordinates, this block only) or G28 / G30 (reference-point return).  The named axes (for
    G28 / G30 without axis words: X Y Z) are afterwards at a machine position whose workpiece coordinates this
    program does not tell: unknown until programmed again.  G28 / G30 words name an intermediate point; only
    zero increments (G91 G28 Z0: no intermediate move) are accepted, as the move to it could not be compensated."""
    name = f"G{g:g}"
    if g == 53 and not absolute:
        raise _error(source, line, "G53 under G91: machine coordinates are absolute; program G90 before G53")
    if g != 53 and words and (absolute or any(v != 0 for _, v in words)):
        w = " ".join(f"{ww.letters[a]}{v:g}" for a, v in words)
        raise _error(source, line, f"{name} {w} moves to an intermediate point first, which cannot be compensated; "
                                   f"write it with zero increments (e.g. G91 {name} Z0)")
    pos = pos.copy()
    if words:
        pos[[a for a, _ in words]] = np.nan
    elif g != 53:
        pos[ww.linear] = np.nan
    return pos


def parse_chunk(lines: list[str], state: ModalState, first_line: int, source: str,
                min_decimals: tuple[int, int, int] = (4, 5, 4), w: Words | None = None) -> Chunk:
    """Parse ``lines`` (with their line ends) starting from ``state``; ``state`` is advanced to the chunk end.
    ``w``: the machine's axis words (default: the default machine's).

    min_decimals = (mm, inch, deg): the least number of decimals written for a linear word in mm, in inch and a
    rotary word; more when the input carries more.
    """
    w = w or words()
    text = "".join(lines)
    commented = "(" in text or ";" in text
    code = _mask_comments(text) if commented else text
    _screen(code, first_line, source, w)
    n = len(lines)
    starts = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.fromiter(map(len, lines), np.int64, n), out=starts[1:])
    md = _g_modes(code, starts, first_line, source)
    t = _axis_words(text if commented else None, code, starts, md, first_line, source, w)
    if md.plain() and state.absolute and not state.inch and not state.inverse_time and not state.fresh:
        return _fill_plain(lines, first_line, t, state, min_decimals, w)
    return _fill_modal(lines, first_line, t, md, code, starts, state, min_decimals, source, w)


def _screen(code: str, first_line: int, source: str, w: Words) -> None:
    """Run the checks (``_check``, raising on the first refusal) on a chunk that contains anything suspect."""
    suspect = (bool(set(code) & w.suspect) or w.checks[-1][0].search(code) is not None or "128" in code
               or _BADNUM.search(code) is not None or _SUBPROGRAM.search(code) is not None)
    if suspect:  # find which check, for the message
        _check(code, first_line, source, w)


@dataclass
class _AxisWords:
    """The axis words of a chunk: its pieces (``Chunk.pieces``) and per motion row (the lines with axis words)
    the value written, whether present, its decimals and its number's piece (arrays (m, n_axes))."""

    pieces: list[str]
    rows: np.ndarray           # (m,) line index of each motion row
    tail: np.ndarray           # (m,) piece after the row's last number
    given: np.ndarray
    present: np.ndarray
    decimals: np.ndarray       # -1 where absent
    numidx: np.ndarray         # -1 where absent
    special: dict[int, list[tuple[int, float]]]  # axis words of machine-coordinate lines (G28 / G30 / G53)


def _axis_words(text: str | None, code: str, starts: np.ndarray, md: _Modes, first_line: int, source: str,
                w: Words) -> _AxisWords:
    """Split a chunk (``code``: comments masked; ``text``: the original when it has comments) at its axis numbers
    and place each word in its motion row; the words of dwell and machine-coordinate lines are no move."""
    # one split of the whole chunk: [text, ws, number, text, ws, number, ..., text]
    pieces = w.split.split(code)
    nn = (len(pieces) - 1) // 3
    off = np.zeros(len(pieces) + 1, dtype=np.int64)
    np.cumsum(np.fromiter(map(len, pieces), np.int64, len(pieces)), out=off[1:])
    if text is not None:  # the same pieces of the original text (masking keeps lengths)
        o = off.tolist()
        pieces = [text[o[j]: o[j + 1]] for j in range(len(pieces))]
    if sum(code.count(c) for c in w.letters + w.letters.lower()) != nn:  # an axis letter without a number
        _check(code, first_line, source, w)
    numpiece = np.arange(nn, dtype=np.int64) * 3 + 2
    line_of = np.searchsorted(starts, off[numpiece], "right") - 1
    nums = pieces[2::3]
    special: dict[int, list[tuple[int, float]]] = {}
    if md.dwell or md.machine:  # G4 X...: a dwell time; G28 / G53 words: machine positions, not coordinates
        drop = np.isin(line_of, list(md.dwell | set(md.machine)))
        for k in np.flatnonzero(drop).tolist():
            i = int(line_of[k])
            if i in md.machine:
                a = w.letters.index(code[off[numpiece[k] - 1] - 1].upper())
                special.setdefault(i, []).append((a, float(nums[k])))
        keep = ~drop
        numpiece, line_of = numpiece[keep], line_of[keep]
        nums = [nums[k] for k in np.flatnonzero(keep).tolist()]
    buf = np.frombuffer(code.encode(ENCODING), dtype=np.uint8)
    lut = np.full(256, -1, dtype=np.int64)
    for j, c in enumerate(w.letters):
        lut[ord(c)] = j
    axi = lut[buf[off[numpiece - 1] - 1] & 0xDF]  # the letter before the blanks, upper case
    newrow = np.ones(len(line_of), dtype=bool)
    newrow[1:] = line_of[1:] != line_of[:-1]
    rows = line_of[newrow]
    last = np.ones(len(line_of), dtype=bool)
    last[:-1] = newrow[1:]
    vals = np.array(nums, dtype=np.float64) if nums else np.zeros(0)
    if not np.isfinite(vals).all():  # hundreds of digits read as inf
        k = int(np.flatnonzero(~np.isfinite(vals))[0])
        raise _error(source, first_line + int(line_of[k]), f"number {nums[k][:20]}... is too large")
    return _AxisWords(pieces, rows, numpiece[last] + 1,
                      *_row_tables(np.cumsum(newrow) - 1, axi, vals, _decimals(nums), numpiece, rows, first_line,
                                   source, w), special)


def _row_tables(flat_rows: np.ndarray, axi: np.ndarray, vals: np.ndarray, decs: np.ndarray, numpiece: np.ndarray,
                rows: np.ndarray, first_line: int, source: str, w: Words) -> tuple[np.ndarray, ...]:
    """(given, present, decimals, numidx), each (m, n_axes), from the words' rows and axes; an axis twice in a
    block is refused."""
    m, na = len(rows), len(w.letters)
    given = np.full((m, na), np.nan)
    given[flat_rows, axi] = vals
    present = np.zeros((m, na), dtype=bool)
    present[flat_rows, axi] = True
    if present.sum() != len(axi):  # an axis twice on one line
        per = np.bincount(flat_rows * na + axi, minlength=na * m).reshape(m, na)
        r, a = (int(v[0]) for v in np.nonzero(per > 1))
        raise _error(source, first_line + int(rows[r]), f"axis {w.letters[a]} appears twice in one block")
    wdec = np.full((m, na), -1, dtype=np.int64)
    wdec[flat_rows, axi] = decs
    numidx = np.full((m, na), -1, dtype=np.int64)
    numidx[flat_rows, axi] = numpiece
    return given, present, wdec, numidx


def _fill_plain(lines: list[str], first_line: int, t: _AxisWords, state: ModalState,
                min_decimals: tuple[int, int, int], w: Words) -> Chunk:
    """The common case (absolute mm, no mode changes): positions and decimals by one forward fill."""
    m = len(t.rows)
    axes, decimals = _forward_fill(state, t.given, t.decimals, np.where(w.linear, min_decimals[0], min_decimals[2]))
    return Chunk(lines, first_line, t.pieces, t.numidx, t.tail, t.rows, axes, t.present, t.given, decimals,
                 np.full(m, state.motion, dtype=np.int64), np.ones(m, dtype=bool), np.zeros(m, dtype=bool),
                 letters=w.letters)


def _forward_fill(state: ModalState, given: np.ndarray, wdec: np.ndarray, floor: np.ndarray,
                  complete: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """(axes, decimals) (m, n_axes) of rows in absolute mm with no mode change: every axis at its last written
    value (from ``state`` before the first), decimals the running maximum (at least ``floor``); ``state`` advanced.
    ``complete``: the caller knows every row has every word (nothing to fill)."""
    m = len(given)
    if m and complete:
        axes = given.copy()
    else:
        filled = np.vstack([state.position[None, :], given])
        idx = np.where(np.isnan(filled), 0, np.arange(m + 1)[:, None])
        np.maximum.accumulate(idx, axis=0, out=idx)
        axes = np.take_along_axis(filled, idx, axis=0)[1:]
    dfill = np.vstack([state.decimals[None, :], wdec])
    np.maximum.accumulate(dfill, axis=0, out=dfill)
    if m:
        state.position = axes[-1].copy()
        state.decimals = dfill[-1].copy()
    return axes, np.maximum(dfill[1:], floor)


def _fill_modal(lines: list[str], first_line: int, t: _AxisWords, md: _Modes, code: str, starts: np.ndarray,
                state: ModalState, min_decimals: tuple[int, int, int], source: str, w: Words) -> Chunk:
    """The general case: a short Python loop over the lines, modes changed where their G words are, each motion
    row's absolute position from the state (G91 increments, G20 inch, machine-coordinate moves)."""
    m, na = len(t.rows), len(w.letters)
    motion, absolute, inch = np.empty(m, dtype=np.int64), np.empty(m, dtype=bool), np.empty(m, dtype=bool)
    axes, decimals = np.empty((m, na)), np.empty((m, na), dtype=np.int64)
    fresh, inverse = np.zeros(m, dtype=bool), np.zeros(m, dtype=bool)
    rows = t.rows.tolist()
    r, pos_, dmax = 0, state.position.copy(), state.decimals.copy()
    for i in range(len(lines)):
        if i in md.motion:
            state.motion = md.motion[i]
        if i in md.absolute:
            state.absolute = md.absolute[i]
        if i in md.inch:
            if md.inch[i] != state.inch:
                dmax = np.where(w.linear, -1, dmax)  # decimals of inch and mm words are not comparable
            state.inch = md.inch[i]
        if i in md.inverse_time:
            state.inverse_time = md.inverse_time[i]
        if i in md.machine:
            pos_ = _machine_move(md.machine[i], t.special.get(i, []), pos_, state.absolute, source, first_line + i, w)
            state.fresh = True
        if r < m and rows[r] == i:
            pos_ = _move(pos_, t.given[r], t.present[r], state, first_line + i, source, w)
            dmax = np.maximum(dmax, t.decimals[r])
            floor = np.where(w.linear, min_decimals[1] if state.inch else min_decimals[0], min_decimals[2])
            axes[r], decimals[r] = pos_, np.maximum(dmax, floor)
            motion[r], absolute[r], inch[r] = state.motion, state.absolute, state.inch
            fresh[r], state.fresh = state.fresh, False
            inverse[r] = state.inverse_time
            r += 1
    state.position = pos_
    state.decimals = dmax
    feed = _inverse_feeds(code, starts, t.rows, inverse & (motion == 1), first_line, source) if inverse.any() else None
    return Chunk(lines, first_line, t.pieces, t.numidx, t.tail, t.rows, axes, t.present, t.given, decimals, motion,
                 absolute, inch, fresh, feed, w.letters)


def _move(pos: np.ndarray, given: np.ndarray, present: np.ndarray, state: ModalState, line: int, source: str,
          w: Words) -> np.ndarray:
    """Absolute position (mm, deg) after one motion row's words (program units; increments under G91)."""
    g = given * np.where(w.linear, INCH if state.inch else 1.0, 1.0)
    if state.absolute:
        return np.where(present, g, pos)
    if np.isnan(pos[present]).any():
        j = int(np.flatnonzero(present & np.isnan(pos))[0])
        raise _error(source, line, f"incremental move (G91) of {w.letters[j]} before its absolute position is known")
    return np.where(present, pos + g, pos)


_FWORD = re.compile(r"[Ff][ \t]*(" + _NUM + ")")


def _inverse_feeds(code: str, starts: np.ndarray, rows: np.ndarray, sel: np.ndarray, first_line: int,
                   source: str) -> np.ndarray:
    """F (1/min) of the inverse-time (G93) feed rows ``sel`` (NaN elsewhere); every such block needs its own F
    (ISO 6983 / Fanuc / LinuxCNC: inverse-time F is not modal)."""
    feed = np.full(len(rows), np.nan)
    for r in np.flatnonzero(sel).tolist():
        i = int(rows[r])
        f = _FWORD.search(code, int(starts[i]), int(starts[i + 1]))
        if f is None or not float(f.group(1)) > 0:
            raise _error(source, first_line + i, "inverse-time feed (G93) move without a positive F word: each G93 "
                                                 "feed block needs its own F (1/min)")
        feed[r] = float(f.group(1))
    return feed


def fmt(value: float, decimals: int) -> str:
    """Fixed-point number with ``decimals`` digits; never '-0.000'."""
    s = "%.*f" % (decimals, value)
    if s[0] == "-" and not s.strip("-0."):
        s = s[1:]
    return s


def line_end(line: str) -> str:
    if line.endswith("\r\n"):
        return "\r\n"
    if line.endswith("\n"):
        return "\n"
    if line.endswith("\r"):
        return "\r"
    return ""


_EOL = re.compile(r"\r\n|\n|\r")


def edit(ch: Chunk, r: int, new: dict[int, str], added: list[tuple[int, str]], sep: str,
         cont: list[str] | None = None) -> None:
    """Change motion row r of a chunk in place: numbers of the axes in ``new`` replaced, ``added`` words
    inserted after the last axis word, ``cont`` lines (text without line end) inserted after the line."""
    p = ch.pieces
    for a, s in new.items():
        p[int(ch.numidx[r, a])] = s
    t = int(ch.tail[r])
    tp = p[t]
    if added:
        ins = "".join(f"{sep}{ch.letters[a]}{s}" for a, s in added)
        if sep and tp[:1] not in (" ", "\t", "\r", "\n", ""):
            ins += sep  # keep the words after the inserted ones separated
        tp = ins + tp
    if cont:
        m = _EOL.search(tp)
        if m:
            eol = m.group()
            tp = tp[: m.end()] + "".join(c + eol for c in cont) + tp[m.end():]
        else:  # last line of the file without a line end: the file's own line end
            eol = next((e for e in map(line_end, ch.lines) if e), "\n")
            tp = tp + "".join(eol + c for c in cont)
    p[t] = tp


_FEED_SCAN = re.compile(r"\([^)\r\n]*\)?|;[^\r\n]*|[Ff][ \t]*(" + _NUM + ")")


def replace_feed(ch: Chunk, r: int, value: str) -> None:
    """Replace the number of motion row r's F word (outside comments) by ``value``, in place."""
    p = ch.pieces
    idx = ch.numidx[r][ch.numidx[r] >= 0]
    head, tail = int(idx.min()) - 2, int(ch.tail[r])
    for j in range(head, tail + 1, 3):  # the row's text pieces: before, between and after its numbers
        t = p[j]
        a = max(t.rfind("\n"), t.rfind("\r")) + 1 if j == head else 0
        e = _EOL.search(t) if j == tail else None
        for m in _FEED_SCAN.finditer(t, a, e.start() if e else len(t)):
            if m.group(1):
                p[j] = t[: m.start(1)] + value + t[m.end(1):]
                return
    raise RuntimeError(f"row {r} has no F word")  # parse_chunk refuses G93 feed rows without F: a bug


CL_UNIT_TOLERANCE = 1e-3  # allowed |(i, j, k)| - 1: unit vectors written to 3 decimals or more


def parse_cl(lines: list[str], first_line: int, source: str) -> tuple[np.ndarray, np.ndarray]:
    """CL data, one point a line: ``x y z i j k`` (workpiece frame, mm; tool axis) separated by blanks or commas,
    optionally after ``GOTO/``; blank lines and lines starting with ``#``, ``(``, ``;`` or ``$$`` are skipped;
    numbers must be finite and (i, j, k) a unit vector within ``CL_UNIT_TOLERANCE`` (then normalised: the digits
    written are the only error; a longer or shorter vector is not a tool axis).  Returns (poses (m, 6), 1-based line numbers (m,))."""
    poses, nos = [], []
    for i, ln in enumerate(lines):
        s = ln.strip()
        if not s or s[0] in "#(;" or s.startswith("$$"):
            continue
        if s[:5].upper() == "GOTO/":
            s = s[5:]
        f = s.replace(",", " ").split()
        try:
            v = [float(x) for x in f]
        except ValueError:
            raise _error(source, first_line + i, f"CL data must be 'x y z i j k' numbers, got {ln.strip()!r}") from None
        if len(v) != 6:
            raise _error(source, first_line + i, f"CL data needs 6 numbers (x y z i j k), got {len(v)}")
        if not np.isfinite(v).all():
            raise _error(source, first_line + i, f"CL data must be finite numbers, got {ln.strip()!r}")
        norm = float(np.linalg.norm(v[3:]))
        if abs(norm - 1) > CL_UNIT_TOLERANCE:
            raise _error(source, first_line + i, f"tool axis (i, j, k) = {tuple(v[3:])} is not a unit vector "
                                                 f"(length {norm:.6g})")
        poses.append(v[:3] + [c / norm for c in v[3:]])
        nos.append(first_line + i)
    return np.array(poses, dtype=float).reshape(-1, 6), np.array(nos, dtype=np.int64)


def line_number(line: str) -> str | None:
    """The N word of a line, if any (for messages)."""
    m = _NWORD.match(line)
    return m.group(1) if m else None


def read_moves(path, chunk_lines: int = 20000, machine=None) -> np.ndarray:
    """Absolute nominal axes (n, n_axes) in mm and deg of every motion block of a G-code file of ``machine`` (default:
    the default machine) whose linear axes are known (blocks before the first full position are skipped)."""
    w = words(machine)
    out, state, first = [], ModalState.for_words(w), 1
    with open(path, encoding=ENCODING, newline="") as fh:
        while True:
            lines = [ln for _, ln in zip(range(chunk_lines), fh)]
            if not lines:
                break
            ch = parse_chunk(lines, state, first, str(path), w=w)
            out.append(ch.axes[np.isfinite(ch.axes).all(axis=1)])
            first += len(lines)
    return np.concatenate(out) if out else np.zeros((0, len(w.letters)))


# ---------------------------------------------------------------------------------------------- fast path
# A block of whole lines is scanned at the byte level with NumPy: letters, the numbers after them and the line of
# each are found with a few vectorised passes, numbers are converted from their digits (exactly: an integer
# mantissa of <= 15 digits over a power of ten is the correctly rounded value, as float() gives), and the output is
# assembled from the input bytes and the new numbers with one gather.  Only blocks whose meaning is plain take this
# path: absolute mm coordinates (G90/G21 as the state already is), G0/G1 and the G codes that do not change how
# coordinates are read, comments, any other words.  Everything else (G91, G20, G28, G4, arcs, unsupported words,
# lone CR line ends, numbers of more than 15 digits, ...) makes ``scan_block`` return None and the block goes
# through ``parse_chunk`` (which also raises the errors), so both paths give the same result.
# byte codes: 0-9 digit value, 10 dot, 11 minus, 22 plus, 12 blank, 13-17 the five axis letters (either case), 18 G,
# 19 other letter, 20 a character that cannot be compensated (parse_chunk names it), 23 line feed, 21 anything else
def _byte_table(letters: str, suspect) -> bytes:
    """The byte codes above for a machine's five axis letters (``bytes.translate`` table)."""
    v = np.full(256, 21, dtype=np.uint8)
    for c in range(256):
        ch = chr(c)
        if "0" <= ch <= "9":
            v[c] = c - 48
        elif ch == ".":
            v[c] = 10
        elif ch == "-":
            v[c] = 11
        elif ch == "+":
            v[c] = 22
        elif ch in " \t":
            v[c] = 12
        elif ch.isascii() and ch.upper() in letters:
            v[c] = 13 + letters.index(ch.upper())
        elif ch in "Gg":
            v[c] = 18
        elif ch in suspect:
            v[c] = 20
        elif ch.isascii() and ch.isalpha():
            v[c] = 19
        elif ch == "\n":
            v[c] = 23
    return bytes(v.tolist())
_P10 = 10.0 ** np.arange(23)
_PASS_G_ARR = np.array(sorted(_PASS_G))
_PAD = 48  # bytes after a block: two 8-byte words past any letter and its blanks
_PAD_BYTES = bytes([21]) * _PAD  # codes past the end: "anything else"


@dataclass
class Block:
    """A block of whole lines parsed by ``scan_block``: the attributes of ``Chunk`` used for the numerics (rows,
    axes, present, given, decimals, motion, absolute, inch) and what ``render_block`` needs to write it."""

    buf: np.ndarray                      # the block's bytes (latin-1)
    code: np.ndarray                     # the same with comments blanked
    first_line: int
    line_start: np.ndarray               # (n_lines + 1,) byte offset of each line, then len(buf)
    num_start: np.ndarray                # (k,) byte span of each axis number (sign included, blanks before not)
    num_end: np.ndarray
    numidx: np.ndarray                   # (m, n_axes) index into num_start/num_end, -1 if the word is absent
    rows: np.ndarray                     # (m,) line index of each motion row
    axes: np.ndarray
    present: np.ndarray
    given: np.ndarray
    decimals: np.ndarray
    motion: np.ndarray
    absolute: np.ndarray
    inch: np.ndarray
    fresh = None                         # never on this path (G28 / G53 / G93 go through parse_chunk)
    feed = None

    @property
    def n_lines(self) -> int:
        return len(self.line_start) - 1

    def line(self, i: int) -> str:
        return self.buf[int(self.line_start[i]): int(self.line_start[i + 1])].tobytes().decode(ENCODING)

    def code_line(self, i: int) -> str:
        return self.code[int(self.line_start[i]): int(self.line_start[i + 1])].tobytes().decode(ENCODING)


def count_lines(text: str) -> int:
    """Lines of a text as a file object with newline='' splits it (LF, CRLF and lone CR end a line)."""
    if not text:
        return 0
    n = text.count("\n") + text.count("\r") - text.count("\r\n")
    return n + (text[-1] not in "\r\n")


def _comment_spans(text: str) -> list[tuple[int, int]]:
    """Spans of the comments ``_COMMENT`` matches, found with str.find (the regex scan costs ~6 ns a character)."""
    spans: list[tuple[int, int]] = []
    n, i = len(text), 0
    find = text.find

    def eol(k: int) -> int:  # where the line of character k ends (its CR of a CR LF; no lone CR here)
        e = find("\n", k)
        return n if e < 0 else e - (text[e - 1] == "\r")

    a, b = find("("), find(";")
    while a >= 0 or b >= 0:
        if b < 0 or 0 <= a < b:  # ( ... ) or ( ... to the line end
            e = eol(a)
            c = find(")", a, e)
            end = c + 1 if c >= 0 else e
            spans.append((a, end))
        else:  # ; ... to the line end
            end = eol(b)
            spans.append((b, end))
        i = end
        if a >= 0 and a < i:
            a = find("(", i)
        if b >= 0 and b < i:
            b = find(";", i)
    return spans


_U1, _U7, _U8, _U16, _U32 = (np.uint64(k) for k in (1, 7, 8, 16, 32))
_M80 = np.uint64(0x8080808080808080)
_M01 = np.uint64(0x0101010101010101)
_M0A = np.uint64(0x0A0A0A0A0A0A0A0A)
_M75 = np.uint64(0x7575757575757575)
_LO8 = np.uint64(0x00FF00FF00FF00FF)
_LO16 = np.uint64(0x0000FFFF0000FFFF)
_LO32 = np.uint64(0x00000000FFFFFFFF)
_KEEP = np.array([(1 << (8 * r)) - 1 for r in range(9)], dtype=np.uint64)  # the low r bytes
_P10I = 10 ** np.arange(20, dtype=np.uint64)


def _word(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Eight byte codes at a time (uint64, byte 0 first): (run, ndot, dotpos, xn) with run the leading number
    bytes (digits and points; 8 = all eight), ndot the points among them, dotpos the first one's index (8 if none)
    and xn the number's bytes, later bytes 0 (SWAR: a few integer operations for all eight bytes)."""
    nonnum = (x + _M75) & _M80  # high bit of each byte > 10
    run = np.bitwise_count((nonnum & (~nonnum + _U1)) - _U1) >> 3
    xn = x & _KEEP[run]
    y = xn ^ _M0A
    dotf = (y - _M01) & ~y & _M80  # exact: the point is the only 0 byte of y and no byte of y is 1
    ndot = np.bitwise_count(dotf)
    dotpos = np.bitwise_count((dotf & (~dotf + _U1)) - _U1) >> 3
    return run, ndot, dotpos, xn


def _horner8(x: np.ndarray) -> np.ndarray:
    """sum of byte c times 10**(7 - c) (bytes 0-9)."""
    x = (x & _LO8) * np.uint64(10) + ((x >> _U8) & _LO8)
    x = (x & _LO16) * np.uint64(100) + ((x >> _U16) & _LO16)
    return (x & _LO32) * np.uint64(10000) + (x >> _U32)


def _numbers(v: np.ndarray, words: np.ndarray, start: np.ndarray, signed: bool) -> tuple | None:
    """Numbers starting at byte offsets ``start`` (``v``: byte codes, padded; ``words``: the same as unaligned
    uint64, element i = bytes i..i+7): (value, decimals, end), or None when one is not a plain decimal of <= 15
    characters (a sign only if ``signed``).

    Exact: with the point taken out, the digits read as an integer h = mantissa * 10**(8 - digits) < 2**53, so
    h / 10**(8 - digits + decimals) is the correctly rounded value, as float() gives."""
    vs = v[start]
    neg = vs == 11
    sign = neg | (vs == 22)
    if not signed and sign.any():
        return None
    body = start + sign
    n = len(start)
    run, ndot, dotpos, xn = _word(words[body])
    keep = _KEEP[dotpos]  # take the point out: the bytes after it move down one
    xn = (xn & keep) | ((xn >> _U8) & ~keep)
    h = _horner8(xn).astype(np.float64)
    expo = np.full(n, 8, dtype=np.int64)
    over = np.flatnonzero(run == 8)
    if len(over):  # eight number bytes and more: the next word too (exact in integers)
        r0, d0, p0 = run[over], ndot[over], dotpos[over]
        r1, d1, p1, x1 = _word(words[body[over] + 8])
        x0 = words[body[over]]
        x0 = x0 & _KEEP[np.minimum(r0, 8)]
        in0 = d0 > 0
        k0 = _KEEP[p0]
        x0p = np.where(in0, (x0 & k0) | ((x0 >> _U8) & ~k0) | (x1 << np.uint64(56)), x0)
        k1 = _KEEP[p1]
        x1p = np.where(in0, x1 >> _U8, (x1 & k1) | ((x1 >> _U8) & ~k1))
        hi = _horner8(x0p) * np.uint64(10**8) + _horner8(x1p)  # mantissa * 10**(16 - digits)
        run[over] = r0 + r1
        ndot[over] = d0 + d1
        dotpos[over] = np.where(in0, p0, 8 + p1)
        dig = (r0 + r1).astype(np.int64) - (d0 + d1)
        if (dig < 1).any() or (dig > 15).any():
            return None
        h[over] = (hi // _P10I[16 - dig]).astype(np.float64)
        expo[over] = dig  # h is the mantissa there
    run = run.astype(np.int64)
    ndot = ndot.astype(np.int64)
    if n and (ndot.max() > 1 or run.max() > 15 or (run - ndot).min() < 1):
        return None
    dec = np.where(ndot > 0, run - dotpos.astype(np.int64) - 1, 0)
    val = h / _P10[expo - (run - ndot) + dec]
    if neg.any():
        val = np.where(neg, -val, val)
    return val, dec, body + run


def _ends_clean(v: np.ndarray, code: np.ndarray, end: np.ndarray) -> bool:
    """No number ends in a sign, a point or (after blanks) another number, and none runs on into an exponent
    (``v``: byte codes, padded; ``code``: the bytes; ``end``: where each number ends)."""
    nb = end.copy()
    blank = v[nb] == 12
    while blank.any():
        nb += blank
        blank = v[nb] == 12
    c = v[nb]
    if ((c <= 11) | (c == 22)).any():
        return False
    e = end[end < len(code)]
    return not (((code[e] | 0x20) == ord("e")) & ((v[e + 1] <= 11) | (v[e + 1] == 22))).any()


def scan_block(text: str, state: ModalState, first_line: int, min_decimals: tuple[int, int, int] = (4, 5, 4),
               w: Words | None = None) -> Block | None:
    """Parse a block of whole lines on the fast path, or None if it needs ``parse_chunk`` (see above).  ``state``
    is advanced only when a Block is returned."""
    if not state.absolute or state.inch or state.inverse_time or state.fresh or not text:
        return None
    if "\r" in text and text.count("\r") != text.count("\r\n"):
        return None  # lone CR line ends
    w = w or words()
    raw = text.encode(ENCODING)
    buf = np.frombuffer(raw, dtype=np.uint8)
    code_b, craw = _blank_comments(text, buf) if "(" in text or ";" in text else (buf, raw)
    vraw = craw.translate(w.table)
    if b"\x14" in vraw or _may_call(craw):
        return None  # words that cannot be compensated: parse_chunk names them
    vpad = vraw + _PAD_BYTES
    v = np.frombuffer(vpad, dtype=np.uint8)
    word8 = np.ndarray((len(vpad) - 7,), dtype="<u8", buffer=vpad, strides=(1,))
    lt = _letters(v, len(raw), raw[-1] != 10)
    if lt is None:
        return None
    line_start, pos, line_no, nxt = lt
    lc = v[pos]
    gsel, asel, osel = lc == 18, lc <= 17, lc == 19
    g = _g_words(v, word8, nxt[gsel], line_no[gsel]) if gsel.any() else (None, None, nxt[:0])
    nums = _numbers(v, word8, nxt[asel], True)
    other = _numbers(v, word8, nxt[osel], True) if osel.any() else (None, None, nxt[:0])
    if g is None or nums is None or other is None:
        return None
    vals, decs, nend = nums
    # every word's number ends where the word ends (no 'X1.2.3', 'X1e2', 'X1 0.5', 'X1-2'): else parse_chunk refuses
    if not _ends_clean(v, code_b, np.concatenate([nend, other[2], g[2]])):
        return None
    if osel.any() and (((code_b[pos[osel]] | 0x20) == ord("m")) & (other[0] == 128)).any():
        return None  # M128 (TCPM): parse_chunk refuses it
    tables = _block_tables(line_no[asel], lc[asel] - np.uint8(13), vals, decs, len(w.letters))
    if tables is None:
        return None  # an axis twice on one line: parse_chunk refuses it
    rows, given, present, wdec, numidx = tables
    axes, decimals = _forward_fill(state, given, wdec, np.where(w.linear, min_decimals[0], min_decimals[2]),
                                   complete=len(vals) == given.size)
    motion = np.full(len(rows), state.motion, dtype=np.int64)
    if g[0] is not None:
        j = np.searchsorted(g[0], rows, "right") - 1
        motion = np.where(j >= 0, g[1][np.maximum(j, 0)], state.motion)
        state.motion = int(g[1][-1])
    return Block(buf, code_b, first_line, line_start, nxt[asel], nend, numidx, rows, axes, present, given,
                 decimals, motion, np.ones(len(rows), dtype=bool), np.zeros(len(rows), dtype=bool))


def _blank_comments(text: str, buf: np.ndarray) -> tuple[np.ndarray, bytes]:
    """The block's bytes with its comments blanked (``_comment_spans``), as an array and as bytes."""
    spans = np.array(_comment_spans(text), dtype=np.int64).reshape(-1, 2)
    mark = np.zeros(len(buf) + 1, dtype=np.int8)
    mark[spans[:, 0]] += 1
    mark[spans[:, 1]] -= 1
    code_b = buf.copy()
    code_b[np.cumsum(mark[:-1], dtype=np.int8) > 0] = 32
    return code_b, code_b.tobytes()


def _letters(v: np.ndarray, n: int, open_end: bool) -> tuple[np.ndarray, ...] | None:
    """(line_start, pos, line_no, nxt) of a block's ``n`` byte codes ``v``: each line's first byte (then n), and
    of every letter its byte, its line and where its number starts (after blanks); ``open_end``: the last line has
    no line feed.  None when two letters follow each other (an unsupported word)."""
    vl = v[:n]
    sel = np.flatnonzero(((vl - np.uint8(13)) <= 6) | (vl == 23))  # letters and line feeds
    isnl = v[sel] == 23
    line_no = np.cumsum(isnl)  # of a letter: its line
    nl = sel[isnl]
    line_start = np.empty(len(nl) + 1 + open_end, dtype=np.int64)
    line_start[0] = 0
    line_start[1: len(nl) + 1] = nl + 1
    line_start[-1] = n
    pos = sel[~isnl]
    nxt = pos + 1
    blank = v[nxt] == 12
    while blank.any():  # blanks between a letter and its number
        nxt += blank
        blank = v[nxt] == 12
    if ((v[nxt] - np.uint8(13)) <= 7).any():
        return None
    return line_start, pos, line_no[~isnl], nxt


def _g_words(v: np.ndarray, word8: np.ndarray, start: np.ndarray, line_no: np.ndarray) -> tuple | None:
    """(lines of G0 / G1 words or None, their values, end of every G number) of a block's G words, or None when
    one is not plain: G90 / G21 (the state already) and the codes that do not change how coordinates are read pass;
    G4 (its X is a time) and everything else go the general way."""
    g = _numbers(v, word8, start, False)
    if g is None:
        return None
    gv = g[0]
    is_motion = (gv == 0) | (gv == 1)
    if not ((is_motion | np.isin(gv, _PASS_G_ARR) | (gv == 90) | (gv == 21)) & (gv != 4)).all():
        return None
    if not is_motion.any():
        return None, None, g[2]
    return line_no[is_motion], gv[is_motion].astype(np.int64), g[2]


def _block_tables(line_of: np.ndarray, axi: np.ndarray, vals: np.ndarray, decs: np.ndarray,
                  na: int) -> tuple[np.ndarray, ...] | None:
    """(rows, given, present, decimals, numidx) of a block's axis words (tables (m, na) as ``_row_tables``), or
    None when an axis appears twice in a block."""
    k = len(line_of)
    newrow = np.empty(k, dtype=bool)
    newrow[:1] = True
    np.not_equal(line_of[1:], line_of[:-1], out=newrow[1:])
    rows = line_of[newrow]
    m = len(rows)
    cell = (np.cumsum(newrow) - 1) * na + axi
    present = np.zeros(m * na, dtype=bool)
    present[cell] = True
    if np.count_nonzero(present) != k:
        return None
    given = np.full(m * na, np.nan)
    given[cell] = vals
    wdec = np.full(m * na, -1, dtype=np.int64)
    wdec[cell] = decs
    numidx = np.full(m * na, -1, dtype=np.int64)
    numidx[cell] = np.arange(k)
    return rows, given.reshape(m, na), present.reshape(m, na), wdec.reshape(m, na), numidx.reshape(m, na)


def edit_line(line: str, code_line: str, new: dict[int, str], added: list[tuple[int, str]], sep: str,
              cont: list[str] | None = None, w: Words | None = None) -> str:
    """``edit`` for one line of its own (``code_line``: the line with comments blanked)."""
    w = w or words()
    pieces = w.split.split(code_line)
    if line != code_line:
        o = np.concatenate([[0], np.cumsum([len(p) for p in pieces])]).tolist()
        pieces = [line[o[j]: o[j + 1]] for j in range(len(pieces))]
    nn = (len(pieces) - 1) // 3
    na = len(w.letters)
    numidx = np.full((1, na), -1, dtype=np.int64)
    for t in range(nn):
        numidx[0, w.letters.index(code_line[sum(len(p) for p in pieces[: 3 * t + 1]) - 1].upper())] = 3 * t + 2
    ch = Chunk([line], 0, pieces, numidx, np.array([3 * nn], dtype=np.int64), np.zeros(1, dtype=np.int64),
               np.zeros((1, na)), numidx >= 0, np.zeros((1, na)), np.zeros((1, na), dtype=np.int64),
               np.zeros(1, dtype=np.int64), np.ones(1, dtype=bool), np.zeros(1, dtype=bool), letters=w.letters)
    edit(ch, 0, new, added, sep, cont)
    return "".join(ch.pieces)


def format_fixed(k: np.ndarray, d: int) -> tuple[np.ndarray, np.ndarray]:
    """Fixed-point text of the integers ``k`` (value k / 10**d) with d decimals, as '%.{d}f' % (k / 10**d) writes
    it: (bytes (n, w) right aligned, lengths (n,))."""
    n = len(k)
    neg = k < 0
    a = np.abs(k)
    top = int(a.max()) if n else 0
    if top < 2**31 - 1:
        a = a.astype(np.int32)  # integer division by a constant is several times faster on 32 bits
    nd = np.full(n, d + 1, dtype=np.int64)  # digits: at least one before the point
    p = 10 ** (d + 1)
    while p <= top:
        nd += a >= p
        p *= 10
    length = nd + (d > 0) + neg
    w = int(length.max()) if n else 1
    out = np.empty((n, w), dtype=np.uint8)
    ten = a.dtype.type(10)
    for c in range(w):  # from the right; columns left of a number's length are not used
        j = w - 1 - c
        if d and c == d:
            out[:, j] = 46
        else:
            q = a // ten
            out[:, j] = a - q * ten
            out[:, j] += 48
            a = q
    if neg.any():
        r = np.flatnonzero(neg)
        out[r, w - length[r]] = 45
    return out, length


def render_block(blk: Block, num_text: list[tuple[np.ndarray, np.ndarray, np.ndarray]],
                 line_text: dict[int, str]) -> bytes:
    """The block's bytes with numbers replaced and whole lines rewritten: ``num_text`` is a list of (number index
    (n,), text (n, w) right aligned, lengths (n,)); ``line_text`` {line index: new text of the whole line}."""
    L = len(blk.buf)
    starts, ends, src, lens = [], [], [], []
    parts = [blk.buf]
    base = L
    for idx, txt, ln in num_text:
        if not len(idx):
            continue
        w = txt.shape[1]
        starts.append(blk.num_start[idx])
        ends.append(blk.num_end[idx])
        src.append(base + np.arange(len(idx), dtype=np.int64) * w + (w - ln))
        lens.append(ln)
        parts.append(txt.ravel())
        base += txt.size
    if line_text:
        ls = sorted(line_text)
        enc = [line_text[i].encode(ENCODING) for i in ls]
        li = np.array(ls, dtype=np.int64)
        starts.append(blk.line_start[li])
        ends.append(blk.line_start[li + 1])
        el = np.array([len(e) for e in enc], dtype=np.int64)
        src.append(base + np.concatenate([[0], np.cumsum(el)[:-1]]))
        lens.append(el)
        parts.append(np.frombuffer(b"".join(enc), dtype=np.uint8))
    if not starts:
        return blk.buf.tobytes()
    s, e, sr, ln = (np.concatenate(x) for x in (starts, ends, src, lens))
    if len(starts) > 1:
        o = np.argsort(s, kind="stable")
        s, e, sr, ln = s[o], e[o], sr[o], ln[o]
    n = len(s)
    seg_src = np.empty(2 * n + 1, dtype=np.int64)
    seg_len = np.empty(2 * n + 1, dtype=np.int64)
    seg_src[0] = 0
    seg_src[2::2] = e
    seg_len[0:-1:2] = s - seg_src[0:-1:2]
    seg_len[-1] = L - e[-1]
    seg_src[1::2] = sr
    seg_len[1::2] = ln
    nz = seg_len > 0
    if not nz.all():
        seg_src, seg_len = seg_src[nz], seg_len[nz]
    end = np.cumsum(seg_len)
    total = int(end[-1])
    # source index of every output byte: +1 inside a segment, a jump where the next one starts (one cumsum)
    step = np.ones(total, dtype=np.int64)
    step[0] = seg_src[0]
    step[end[:-1]] = seg_src[1:] - (seg_src[:-1] + seg_len[:-1]) + 1
    np.cumsum(step, out=step)
    return np.concatenate(parts).take(step).tobytes()
