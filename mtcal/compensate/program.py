"""Streaming compensation of NC programs (G-code, CL data) in blocks: the rows parsed by mtcal.nc.gcode,
corrected by a Compensator (mtcal.compensate.solver), feed moves subdivided where the predicted mid-segment error
exceeds the tolerance, the program written back byte for byte apart from the new numbers; the plausibility guard
of every written command (Guard) and the run's Report."""
from __future__ import annotations

import io
import itertools
import os
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable

import numpy as np

from mtcal.compensate.render import Rendering
from mtcal.compensate.rows import RowCorrection
from mtcal.compensate.solver import MAX_CORRECTION_MM, MAX_ROTARY_CORRECTION_DEG, RESIDUAL_EVERY, Compensator, Stats
from mtcal.errors import InputError
from mtcal.io import atomic_open
from mtcal.nc import gcode


# ---------------------------------------------------------------------------------------------- NC programs
def _read_blocks(fin, size: int):
    """("text", block, lines, characters) for blocks of whole lines of about ``size`` characters."""
    while True:
        text = fin.read(size)
        if not text:
            return
        if text[-1] != "\n":  # complete the last line (also a CR LF cut after the CR)
            text += fin.readline()
        yield "text", text, gcode.count_lines(text), len(text)


@dataclass
class Guard:
    """Plausibility guard on what is written (nothing implausible reaches a machine): every written axis value is
    finite, every correction (written minus nominal command) is within ``max_mm`` on a linear axis (mm) and
    ``max_deg`` on a rotary axis (deg), and every evaluated predicted residual of the exact model (tool tip at the
    written points, mid-segment of feed moves after subdivision) is finite and within ``tolerance`` (mm).  A
    violation raises InputError naming the file, the line and the values; the caller raises it before the output
    is renamed into place, so no output file appears.  Defaults: ``MAX_CORRECTION_MM``,
    ``MAX_ROTARY_CORRECTION_DEG`` (justified there)."""

    max_mm: float
    max_deg: float
    tolerance: float

    def written(self, comp: Compensator, q_w: np.ndarray, q_nom: np.ndarray, src: str, lines: np.ndarray) -> None:
        """Refuse non-finite written axes or corrections beyond the bounds (q_w, q_nom (n, n_axes), mm and deg;
        ``lines``: the 1-based line of each row in ``src``)."""
        m = comp.machine
        linear = np.array([k == "linear" for k in m.axis_kinds])
        bound = np.where(linear, self.max_mm, self.max_deg)
        bad = ~(np.abs(q_w - q_nom) <= bound)  # NaN and inf included
        if not bad.any():
            return
        r, a = (int(v[0]) for v in np.nonzero(bad))
        ax, unit = m.axes[a], "mm" if linear[a] else "deg"
        if not np.isfinite(q_w[r, a]):
            msg = f"the corrected {ax} would be {q_w[r, a]} (not a finite number; tool length {comp.tool_length})"
        else:
            opt = "`max_correction`" if linear[a] else "`max_rotary_correction`"
            msg = (f"the correction of {ax} by {q_w[r, a] - q_nom[r, a]:+.4f} {unit} ({ax}{q_nom[r, a]:.4f} -> "
                   f"{ax}{q_w[r, a]:.4f}) exceeds the plausibility bound {bound[a]:g} {unit} ({opt})")
        errs = comp.largest_errors(q_nom[r]) if np.isfinite(q_nom[r]).all() else ""
        raise InputError(f"{src}, line {lines[r]}: {msg}; largest model errors there: {errs or 'none'} (are the "
                         "model's values in its stated units?); nothing written")

    def residual(self, err: np.ndarray, src: str, lines: np.ndarray, what: str) -> None:
        """Refuse a predicted residual (mm, (n,)) above the tolerance or not finite."""
        bad = ~(err <= self.tolerance)
        if not bad.any():
            return
        r = int(np.flatnonzero(bad)[0])
        raise InputError(f"{src}, line {lines[r]}: the predicted {what} error of the compensated program would be "
                         f"{err[r] * 1e3:.4g} um, above the tolerance {self.tolerance * 1e3:g} um (too few decimals "
                         "written (`precision`), a tolerance below what they can hold, or an implausible model); "
                         "nothing written")


@dataclass
class Report:
    """What a compensation run did and the predicted (model) accuracy of the written commands."""

    lines: int = 0
    moves: int = 0
    lines_changed: int = 0
    lines_inserted: int = 0
    subdivided_moves: int = 0
    uncompensated_rapids: list[int] = field(default_factory=list)
    position: Stats = field(default_factory=Stats)       # |tool-tip residual|, mm (exact model, evaluated points)
    orientation: Stats = field(default_factory=Stats)    # tool-axis residual, rad (controllable points)
    orientation_all: Stats = field(default_factory=Stats)
    before_position: Stats = field(default_factory=Stats)     # first order, every move
    before_orientation: Stats = field(default_factory=Stats)
    mid_position: Stats = field(default_factory=Stats)   # mid-segment residual of feed moves (after subdivision)
    mid_bounded: int = 0  # feed moves whose mid-segment error is below the tolerance by the Lipschitz bound
    in_cone: int = 0
    blended: int = 0
    max_c_correction: float = 0.0
    residual_every: int = 1  # the exact residual is evaluated on every k-th move (and every inserted point)

    def residual_evaluated_on(self) -> str:
        if self.residual_every <= 1:
            return "all moves"
        return f"every {self.residual_every}th move (and every point of a subdivided move)"


class ProgramCompensator(RowCorrection, Rendering):
    """Streams an NC program (G-code or CL data) through a Compensator, block by block (memory stays flat).

    G-code blocks of whole lines take a vectorised byte-level path (``gcode.scan_block`` / ``render_block``) when
    their meaning is plain (absolute mm coordinates, G0/G1, comments, other words passed through), else the general
    line-piece path (``gcode.parse_chunk``); both write the same bytes.  The exact error-inclusive residual of what is
    written is evaluated on every ``residual_every``-th move (counted through the whole program, so the sample does
    not depend on the block size) and on every point of a subdivided move; the uncompensated deviation (first order)
    on every move."""

    def __init__(self, comp: Compensator, tolerance: float = 0.001, precision: int | None = None,
                 chunk_lines: int = 20000, max_subdivisions: int = 256,
                 progress: Callable[[int, int], None] | None = None, residual_every: int = RESIDUAL_EVERY,
                 max_correction: float = MAX_CORRECTION_MM, max_rotary_correction: float = MAX_ROTARY_CORRECTION_DEG,
                 allow_subprograms: bool = False):
        self.comp = comp
        self.tolerance = float(tolerance)
        p = 4 if precision is None else int(precision)
        for name, v in (("tolerance", self.tolerance), ("max_correction", max_correction),
                        ("max_rotary_correction", max_rotary_correction)):
            if not (np.isfinite(v) and v > 0):
                raise InputError(f"{name} must be a positive finite number, got {v}")
        if p < 0:
            raise InputError(f"precision must be >= 0 decimals, got {p}")
        self.guard = Guard(float(max_correction), float(max_rotary_correction), self.tolerance)
        self.min_decimals = (p, p + 1, p)  # mm, inch, deg
        self.chunk_lines = int(chunk_lines)
        self.chunk_chars = max(1024, 48 * self.chunk_lines)  # G-code blocks: about chunk_lines lines
        self.max_sub = int(max_subdivisions)
        self.progress = progress
        if int(residual_every) < 1:
            raise InputError(f"residual_every must be >= 1, got {residual_every}")
        self.report = Report(residual_every=int(residual_every))
        self.fast = True  # byte-level path for plain blocks (False: every block through parse_chunk)
        m = comp.machine
        self.words = replace(gcode.words(m), allow_subprograms=allow_subprograms)  # the machine's axis words
        self._ti, self._ri = m.index(m.ik_info["tilt_axis"]), m.index(m.ik_info["rotary_axis"])

    # ---------------------------------------------------------------- driver
    def run(self, src: str | os.PathLike, dst: str | os.PathLike, kind: str = "auto") -> Report:
        src, dst = Path(src), Path(dst)
        if kind == "auto":
            kind = "cl" if src.suffix.lower() in (".cl", ".cls", ".apt") else "gcode"
        if kind not in ("gcode", "cl"):
            raise InputError(f"input kind must be gcode or cl, got {kind!r}")
        total = src.stat().st_size
        enc = gcode.ENCODING
        with open(src, encoding=enc, newline="") as fin, atomic_open(dst, "wb") as fout:
            self._state = gcode.ModalState.for_words(self.words)
            self._prev: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # nominal, written mm, units
            self._prev_mm = self._state.position.copy()  # linear axes unknown, rotary at 0
            self._src, self._done, self._moves_seen = str(src), 0, 0
            self._cl_lines: np.ndarray | None = None  # CL data: the file line of each generated block
            first = 1
            if kind == "cl":
                fout.write(f"%\n(mtcal compensate: CL data {src.name}, scope {self.comp.scope})\nG90 G21\n"
                           .encode(enc))
                self._first_cl = True
                while True:
                    lines = list(itertools.islice(fin, self.chunk_lines))
                    if not lines:
                        break
                    self._refuse_binary("".join(lines), first)
                    fout.write(self._cl_chunk(lines, first).encode(enc))
                    first += len(lines)
                    self.report.lines += len(lines)
                    self._done += sum(map(len, lines))
                    if self.progress:
                        self.progress(self._done, total)
                fout.write(b"M30\n%\n")
            else:
                for _, text, n, size in _read_blocks(fin, self.chunk_chars):
                    self._refuse_binary(text, first)
                    fout.write(self._gcode_block(text, first))
                    first += n
                    self.report.lines += n
                    self._done += size
                    if self.progress:
                        self.progress(self._done, total)
            if self.report.moves == 0:  # raised before the output is renamed into place: no file appears
                what = "CL points (x y z i j k)" if kind == "cl" else "moves (G0/G1 blocks with axis words)"
                raise InputError(f"{src}: no {what} found{' (empty file)' if total == 0 else ''}; nothing to "
                                 "compensate, nothing written")
        return self.report

    def _refuse_binary(self, text: str, first: int) -> None:
        """A NUL byte: not a text program (a binary or corrupted file)."""
        k = text.find("\x00")
        if k >= 0:
            raise InputError(f"{self._src}, line {first + gcode.count_lines(text[:k + 1]) - 1}: NUL byte: not a text "
                             "NC program (binary or corrupted file)")

    # ---------------------------------------------------------------- G-code
    def _gcode_block(self, text: str, first: int) -> bytes:
        """Output bytes of a block of whole lines: the byte-level path when the block is plain, else by lines."""
        blk = gcode.scan_block(text, self._state, first, self.min_decimals, self.words) if self.fast else None
        if blk is None:
            return self._gcode_chunk(io.StringIO(text, newline="").readlines(), first).encode(gcode.ENCODING)
        out = self._compensate_rows(blk, first)
        if out is None:
            return blk.buf.tobytes()
        return self._render_fast(blk, *out)

    def _gcode_chunk(self, lines: list[str], first: int, exact: np.ndarray | None = None) -> str:
        ch = gcode.parse_chunk(lines, self._state, first, self._src, self.min_decimals, self.words)
        out = self._compensate_rows(ch, first, exact)
        if out is None:
            return "".join(lines)
        return self._render(ch, *out)

    # ---------------------------------------------------------------- CL data
    def _cl_chunk(self, lines: list[str], first: int) -> str:
        comp = self.comp
        poses, nos = gcode.parse_cl(lines, first, self._src)
        if len(poses) == 0:
            return ""
        m = comp.machine
        try:
            q0 = m.inverse(poses)
        except InputError as exc:  # name the first pose the machine cannot reach by its file line
            for r in range(len(poses)):
                try:
                    m.inverse(poses[r:r + 1])
                except InputError as one:
                    raise InputError(f"{self._src}:{int(nos[r])}: {str(one).replace(' at index (0,)', '')}") from None
            raise InputError(f"{self._src}: {exc}") from None
        # C continuity: at the singularity take the previous C, elsewhere the 360-deg multiple nearest the previous
        sing = np.hypot(poses[:, 3], poses[:, 4]) < 1e-9
        ri = self._ri
        c = q0[:, ri].copy()
        prev_c = self._prev[0][ri] if self._prev else 0.0
        seq = np.concatenate([[prev_c], c])
        for i in np.flatnonzero(sing):
            seq[i + 1] = seq[i]
        seq = np.unwrap(seq, period=360.0)
        hint = q0.copy()
        hint[:, ri] = seq[1:]
        q_nom = m.inverse(poses, hint=hint)
        # render as G-code, all five words a block, and compensate it with the unrounded nominal axes
        p = self.min_decimals[0]
        text = []
        for q in q_nom.tolist():
            words = " ".join(f"{a}{gcode.fmt(v, p)}" for a, v in zip(self.words.letters, q))
            text.append(("G1 " if self._first_cl else "") + words + "\n")
            self._first_cl = False
        self._cl_lines = nos
        try:
            return self._gcode_chunk(text, first, exact=q_nom)
        finally:
            self._cl_lines = None
