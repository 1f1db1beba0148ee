"""G-code (ISO 6983 subset of the DMU 50) and CL data: streaming, vectorised chunk parser and line writer.

Scope: G0/G1 moves with X Y Z (mm or inch) and B C (deg) words, modal values carried between blocks, G90/G91,
G20/G21, line numbers (N), comments ``( ... )`` and ``; ...``.  Every other word and every byte outside the
coordinate numbers is kept as it is: a line is stored as the list returned by ``re.split`` on the coordinate
numbers, ``[text, ws, number, text, ws, number, ..., tail]``, so writing it back is a ``"".join``.

What cannot be compensated raises ``InputError`` naming the file and line: arcs (G2/G3, I J K R words), axis
words this machine does not have (A U V W), parameters and expressions (``#``, ``=``, ``[``), coordinate
transformations and cycles (G28 with axis words, G53, G68, G51, G81.., G92, ...).  Files are read and written as
latin-1 with ``newline=""``, so any byte (including UTF-8 comments and CRLF line ends) passes through unchanged.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from mtcal.errors import InputError

AXES = "XYZBC"
LINEAR = np.array([True, True, True, False, False])
INCH = 25.4  # mm
ENCODING = "latin-1"  # byte-transparent

_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)"
# coordinate numbers: an axis letter, optional blanks, a number; the letter stays in the preceding text piece
_SPLIT = re.compile(r"(?<=[XYZBCxyzbc])([ \t]*)(" + _NUM + ")")
_COMMENT = re.compile(r"\([^)\n]*\)?|;[^\n]*")
_GWORD = re.compile(r"[Gg][ \t]*(\d+(?:\.\d*)?)")
_NWORD = re.compile(r"^[ \t/]*[Nn][ \t]*(\d+)")
# checks run once per chunk on the comment-masked text (C speed); each names the offending line
_CHECKS = (
    (re.compile(r"[AUVWauvw][ \t]*[-+.\d]"), "axis word {word!r}: the {machine} has no such axis"),
    (re.compile(r"[IJKRijkr][ \t]*[-+.\d]"),
     "word {word!r}: arcs (G2/G3 with I J K R) and tool-vector words cannot be compensated; "
     "linearise the toolpath (G1) in the CAM system"),
    (re.compile(r"[XYZBCxyzbc](?![ \t]*[-+]?(?:\d|\.\d))\S*"),
     "{word!r}: an axis letter must be followed by a number (parameters, expressions and cycles are not supported)"),
    (re.compile(r"[=#\[]\S*"), "{word!r}: parameters and expressions are not supported"),
    (re.compile(r"[A-Za-z][ \t]*[A-Za-z]\S*"),
     "{word!r}: unsupported word (ISO 6983 words are one letter and a number)"),
)

_SUSPECT = set("AUVWIJKRauvwijkr=#[")


def _check(code: str, first_line: int, source: str, machine: str) -> None:
    for rx, msg in _CHECKS:
        m = rx.search(code)
        if m:
            raise _error(source, _line_of(code, m.start(), first_line), msg.format(word=m.group(), machine=machine))

# G codes that do not change how coordinates are interpreted (passed through)
_PASS_G = {4.0, 9.0, 15.0, 17.0, 18.0, 19.0, 40.0, 41.0, 42.0, 43.0, 49.0, 54.0, 55.0, 56.0, 57.0, 58.0, 59.0,
           54.1, 61.0, 64.0, 80.0, 93.0, 94.0, 95.0, 96.0, 97.0}
_HOME_G = {28.0, 30.0}  # reference-point return: allowed without axis words, positions unknown afterwards


@dataclass
class ModalState:
    """Modal state carried between lines and chunks (values in mm and deg, NaN = not known yet)."""

    motion: int = 1          # 0 rapid, 1 feed (assumed G1 until a motion code is read)
    absolute: bool = True    # G90 / G91
    inch: bool = False       # G20 / G21
    position: np.ndarray = field(default_factory=lambda: np.array([np.nan, np.nan, np.nan, 0.0, 0.0]))
    decimals: np.ndarray = field(default_factory=lambda: np.full(5, -1, dtype=np.int64))


@dataclass
class Chunk:
    """One chunk of lines, parsed.  Motion rows are the lines with axis words (in file order).

    ``pieces`` is the chunk text split at the coordinate numbers, ``[text, ws, number, text, ...]``; its join is
    the chunk, byte for byte.  Writing changes pieces: numbers at ``numidx`` and words inserted at ``tail``."""

    lines: list[str]
    first_line: int                      # 1-based number of lines[0] in the file
    pieces: list[str]
    numidx: np.ndarray                   # (m, 5) index into pieces of each axis number, -1 if the word is absent
    tail: np.ndarray                     # (m,) index of the text piece after the row's last number
    rows: np.ndarray                     # (m,) index into lines of each motion row
    axes: np.ndarray                     # (m, 5) absolute nominal axes, mm and deg (NaN: unknown)
    present: np.ndarray                  # (m, 5) bool: word present on the line
    given: np.ndarray                    # (m, 5) value as written (program units; increments under G91)
    decimals: np.ndarray                 # (m, 5) output decimals (running max of the input's, >= minimum)
    motion: np.ndarray                   # (m,) 0 rapid / 1 feed
    absolute: np.ndarray                 # (m,) bool
    inch: np.ndarray                     # (m,) bool


def _mask_comments(text: str) -> str:
    return _COMMENT.sub(lambda m: " " * len(m.group()), text)


def _line_of(text: str, pos: int, first_line: int) -> int:
    return first_line + text.count("\n", 0, pos)


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


def parse_chunk(lines: list[str], state: ModalState, first_line: int, source: str,
                min_decimals: tuple[int, int, int] = (4, 5, 4), machine: str = "dmu50") -> Chunk:
    """Parse ``lines`` (with their line ends) starting from ``state``; ``state`` is advanced to the chunk end.

    min_decimals = (mm, inch, deg): the least number of decimals written for a linear word in mm, in inch and a
    rotary word; more when the input carries more.
    """
    text = "".join(lines)
    commented = "(" in text or ";" in text
    code = _mask_comments(text) if commented else text
    chars = set(code)
    suspect = bool(chars & _SUSPECT) or _CHECKS[4][0].search(code) is not None
    if suspect:  # find which check, for the message
        _check(code, first_line, source, machine)
    n = len(lines)
    starts = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.fromiter(map(len, lines), np.int64, n), out=starts[1:])
    # per-line modal changes from the G words (C-speed search, Python only per G word)
    motion_set: dict[int, int] = {}
    abs_set: dict[int, bool] = {}
    inch_set: dict[int, bool] = {}
    home: set[int] = set()
    dwell: set[int] = set()
    if "G" in code or "g" in code:
        gm = list(_GWORD.finditer(code))
        gl = np.searchsorted(starts, [g.start() for g in gm], "right") - 1
        for g, i in zip(gm, gl.tolist()):
            v, gs = float(g.group(1)), g.group(1)
            if v == 0 or v == 1:
                motion_set[i] = int(v)
            elif v == 2 or v == 3:
                raise _error(source, first_line + i, f"G{gs}: circular arcs cannot be compensated; linearise the "
                                                     "toolpath (G1) in the CAM system")
            elif v == 90 or v == 91:
                abs_set[i] = v == 90
            elif v == 20 or v == 21:
                inch_set[i] = v == 20
            elif v == 4:
                dwell.add(i)
            elif v in _HOME_G:
                home.add(i)
            elif v not in _PASS_G:
                raise _error(source, first_line + i, f"G{gs} is not supported (it moves in another frame, runs a "
                                                     "cycle or changes how coordinates are read)")
    # one split of the whole chunk: [text, ws, number, text, ws, number, ..., text]
    pieces = _SPLIT.split(code)
    nn = (len(pieces) - 1) // 3
    lens = np.fromiter(map(len, pieces), np.int64, len(pieces))
    off = np.zeros(len(pieces) + 1, dtype=np.int64)
    np.cumsum(lens, out=off[1:])
    if commented:  # the same pieces of the original text (masking keeps lengths)
        o = off.tolist()
        pieces = [text[o[j]: o[j + 1]] for j in range(len(pieces))]
    if sum(code.count(c) for c in "XYZBCxyzbc") != nn:  # an axis letter without a number somewhere
        _check(code, first_line, source, machine)
    numpiece = np.arange(nn, dtype=np.int64) * 3 + 2
    line_of = np.searchsorted(starts, off[numpiece], "right") - 1
    nums = pieces[2::3]
    if dwell:  # G4 X...: a dwell time, not a coordinate
        keep = ~np.isin(line_of, list(dwell))
        numpiece, line_of = numpiece[keep], line_of[keep]
        nums = [nums[k] for k in np.flatnonzero(keep).tolist()]
    if home:
        bad = np.isin(line_of, list(home))
        if bad.any():
            raise _error(source, first_line + int(line_of[bad][0]), "a reference-point return (G28/G30) with axis "
                                                                    "words cannot be compensated")
    buf = np.frombuffer(code.encode(ENCODING), dtype=np.uint8)
    ax = buf[off[numpiece - 1] - 1] & 0xDF  # the letter before the blanks, upper case
    newrow = np.ones(len(line_of), dtype=bool)
    newrow[1:] = line_of[1:] != line_of[:-1]
    rows_a = line_of[newrow]
    rows = rows_a.tolist()
    m = len(rows)
    flat_rows = np.cumsum(newrow) - 1
    tail = np.empty(m, dtype=np.int64)
    if m:
        last = np.ones(len(line_of), dtype=bool)
        last[:-1] = newrow[1:]
        tail[:] = numpiece[last] + 1
    lut = np.full(256, -1, dtype=np.int64)
    for j, c in enumerate(AXES):
        lut[ord(c)] = j
    axi = lut[ax]
    vals = np.array(nums, dtype=np.float64) if nums else np.zeros(0)
    decs = _decimals(nums)

    given = np.full((m, 5), np.nan)
    given[flat_rows, axi] = vals
    present = np.zeros((m, 5), dtype=bool)
    present[flat_rows, axi] = True
    if present.sum() != len(axi):  # an axis twice on one line
        per = np.bincount(flat_rows * 5 + axi, minlength=5 * m).reshape(m, 5)
        r, a = (int(v[0]) for v in np.nonzero(per > 1))
        raise _error(source, first_line + rows[r], f"axis {AXES[a]} appears twice in one block")
    wdec = np.full((m, 5), -1, dtype=np.int64)
    wdec[flat_rows, axi] = decs
    numidx = np.full((m, 5), -1, dtype=np.int64)
    numidx[flat_rows, axi] = numpiece

    # modal state per motion row (lines are processed in order; G words on a line apply to that line)
    motion = np.empty(m, dtype=np.int64)
    absolute = np.empty(m, dtype=bool)
    inch = np.empty(m, dtype=bool)
    axes = np.empty((m, 5))
    decimals = np.empty((m, 5), dtype=np.int64)
    mins = np.array(min_decimals)
    simple = not (abs_set or inch_set or home or motion_set) and state.absolute and not state.inch
    if simple:  # the common case: one vectorised forward fill
        motion[:] = state.motion
        absolute[:] = True
        inch[:] = False
        mm = given
        filled = np.vstack([state.position[None, :], mm])
        idx = np.where(np.isnan(filled), 0, np.arange(m + 1)[:, None])
        np.maximum.accumulate(idx, axis=0, out=idx)
        axes[:] = filled[idx, np.arange(5)][1:]
        dfill = np.vstack([state.decimals[None, :], wdec])
        np.maximum.accumulate(dfill, axis=0, out=dfill)
        floor = np.where(LINEAR, mins[0], mins[2])
        decimals[:] = np.maximum(dfill[1:], floor)
        if m:
            state.position = axes[-1].copy()
            state.decimals = dfill[-1].copy()
        return Chunk(lines, first_line, pieces, numidx, tail, rows_a, axes, present, given, decimals, motion,
                     absolute, inch)

    # general case: a short Python loop over lines that change modes, rows in between in one go
    r = 0
    pos_ = state.position.copy()
    dmax = state.decimals.copy()
    for i in range(n):
        if i in motion_set:
            state.motion = motion_set[i]
        if i in abs_set:
            state.absolute = abs_set[i]
        if i in inch_set:
            if inch_set[i] != state.inch:
                dmax = np.where(LINEAR, -1, dmax)  # decimals of inch and mm words are not comparable
            state.inch = inch_set[i]
        if i in home:
            pos_ = np.array([np.nan, np.nan, np.nan, pos_[3], pos_[4]])
        if r < m and rows[r] == i:
            g = given[r]
            scale = np.where(LINEAR, INCH if state.inch else 1.0, 1.0)
            pres = present[r]
            if state.absolute:
                pos_ = np.where(pres, g * scale, pos_)
            else:
                if np.isnan(pos_[pres]).any():
                    j = int(np.flatnonzero(pres & np.isnan(pos_))[0])
                    raise _error(source, first_line + i, f"incremental move (G91) of {AXES[j]} before its absolute "
                                                         "position is known")
                pos_ = np.where(pres, pos_ + g * scale, pos_)
            dmax = np.maximum(dmax, wdec[r])
            floor = np.where(LINEAR, mins[1] if state.inch else mins[0], mins[2])
            axes[r] = pos_
            decimals[r] = np.maximum(dmax, floor)
            motion[r] = state.motion
            absolute[r] = state.absolute
            inch[r] = state.inch
            r += 1
    state.position = pos_
    state.decimals = dmax
    return Chunk(lines, first_line, pieces, numidx, tail, rows_a, axes, present, given, decimals, motion,
                     absolute, inch)


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
        ins = "".join(f"{sep}{AXES[a]}{s}" for a, s in added)
        if sep and tp[:1] not in (" ", "\t", "\r", "\n", ""):
            ins += sep  # keep the words after the inserted ones separated
        tp = ins + tp
    if cont:
        m = _EOL.search(tp)
        if m:
            eol = m.group()
            tp = tp[: m.end()] + "".join(c + eol for c in cont) + tp[m.end():]
        else:  # last line of the file without a line end
            tp = tp + "".join("\n" + c for c in cont)
    p[t] = tp


def parse_cl(lines: list[str], first_line: int, source: str) -> tuple[np.ndarray, np.ndarray]:
    """CL data, one point a line: ``x y z i j k`` (workpiece frame, mm; tool axis) separated by blanks or commas,
    optionally after ``GOTO/``; blank lines and lines starting with ``#``, ``(``, ``;`` or ``$$`` are skipped.
    Returns (poses (m, 6), 1-based line numbers (m,))."""
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
        poses.append(v)
        nos.append(first_line + i)
    return np.array(poses, dtype=float).reshape(-1, 6), np.array(nos, dtype=np.int64)


def line_number(line: str) -> str | None:
    """The N word of a line, if any (for messages)."""
    m = _NWORD.match(line)
    return m.group(1) if m else None


def read_moves(path, chunk_lines: int = 20000) -> np.ndarray:
    """Absolute nominal axes (n, 5) in mm and deg of every motion block of a G-code file whose X, Y, Z are known
    (blocks before the first full position are skipped), in file order."""
    out, state, first = [], ModalState(), 1
    with open(path, encoding=ENCODING, newline="") as fh:
        while True:
            lines = [ln for _, ln in zip(range(chunk_lines), fh)]
            if not lines:
                break
            ch = parse_chunk(lines, state, first, str(path))
            out.append(ch.axes[np.isfinite(ch.axes).all(axis=1)])
            first += len(lines)
    return np.concatenate(out) if out else np.zeros((0, 5))
