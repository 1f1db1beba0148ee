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

from mtcal.compensate.solver import MAX_CORRECTION_MM, MAX_ROTARY_CORRECTION_DEG, RESIDUAL_EVERY, Compensator, Stats
from mtcal.errors import InputError
from mtcal.io import atomic_open
from mtcal.nc import gcode

_P10 = 10.0 ** np.arange(23)
FEED_DECIMALS = 4  # inverse-time F (1/min) written on split G93 moves


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


class ProgramCompensator:
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

    def _compensate_rows(self, ch, first: int, exact: np.ndarray | None = None):
        """Corrected, rounded commands of the motion rows of a parsed chunk or block, the subdivisions and the
        report figures: (units, written mm, known, subdivisions, scale, 10**decimals), None without rows."""
        m = len(ch.rows)
        if m == 0:
            return None
        if exact is not None:  # CL data: the nominal axes from the inverse kinematics, unrounded
            ch.axes[:] = exact
        self.report.moves += m
        q_nom = ch.axes
        lines = self._cl_lines if self._cl_lines is not None else first + ch.rows
        known = self._known_rows(ch, q_nom, lines)
        if ch.inch.any():
            scale = np.where(ch.inch[:, None] & self.words.linear, gcode.INCH, 1.0)
        else:
            scale = np.ones((m, len(self.words.letters)))
        f = _P10[ch.decimals] if ch.decimals.max() < len(_P10) else 10.0 ** ch.decimals
        units, q_w = self._written(ch, q_nom, known, scale, f)
        self.guard.written(self.comp, q_w[known], q_nom[known], self._src, lines[known])
        # subdivision of feed moves whose mid-segment error exceeds the tolerance
        subs = self._subdivide(ch, q_nom, q_w, known, scale, f, lines)
        self._residuals(q_nom, q_w, np.flatnonzero(known), subs, lines)
        return units, q_w, known, subs, scale, f

    def _known_rows(self, ch, q_nom: np.ndarray, lines: np.ndarray) -> np.ndarray:
        """Rows whose every axis is known (bool (m,)): the others are rapids passed through as programmed (a feed
        move with an unknown axis is refused); a position outside the spec's soft limits is refused."""
        mach = self.comp.machine
        for i, lim in enumerate(mach.limits):  # the spec's soft limits (the tilt axis on the shipped specs)
            if lim is None:
                continue
            bad = (q_nom[:, i] < lim[0]) | (q_nom[:, i] > lim[1])
            if bad.any():
                r = int(np.flatnonzero(bad)[0])
                raise InputError(f"{self._src}, line {lines[r]}: {mach.axes[i]} = {q_nom[r, i]:.10g} "
                                 f"{mach.unit(mach.axes[i])} is outside its range [{lim[0]:g}, {lim[1]:g}]")
        unknown = np.isnan(q_nom).any(axis=1)
        if unknown.any():
            feed = unknown & (ch.motion == 1)
            if feed.any():
                r = int(np.flatnonzero(feed)[0])
                miss = "".join(a for a, u in zip(self.words.letters, np.isnan(q_nom[r])) if u)
                after = ch.fresh is not None and bool(ch.fresh[r])
                raise InputError(f"{self._src}, line {lines[r]}: feed move while {miss} is not known yet "
                                 + ("(the machine-coordinate move before it, G28 / G30 / G53, left them in machine "
                                    "coordinates: program them again before the G1)" if after else
                                    "(program every linear axis before the first G1)"))
            self.report.uncompensated_rapids.extend(lines[unknown].tolist())
        return ~unknown

    def _written(self, ch, q_nom: np.ndarray, known: np.ndarray, scale: np.ndarray,
                 f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(units, q_w): the corrected commands rounded as written (program units) and back in mm / deg; rows not
        known pass as programmed; a word missing from a block is only added when the correction moves that axis
        by half a digit or more from what the machine holds (``self._hold``)."""
        comp, rep = self.comp, self.report
        all_known = bool(known.all())
        if all_known:
            q_cmd, dev0 = comp.correct(q_nom, return_initial=True)
        else:
            q_cmd = q_nom.copy()
            dev0 = np.zeros((0, 2))
            if known.any():
                q_cmd[known], dev0 = comp.correct(q_nom[known], return_initial=True)
        rep.before_position.add(dev0[:, 0])
        rep.before_orientation.add(dev0[:, 1])
        mm = not ch.inch.any()  # scale 1: the same numbers without the divisions
        units = (np.round(q_cmd * f) if mm else np.round(q_cmd / scale * f)) / f + 0.0
        if not all_known:
            units[~known] = q_nom[~known] / scale[~known]  # passed through as programmed
        q_w = units.copy() if mm else units * scale
        # the held value stays (also across G20/G21 rounding)
        prev = np.vstack([self._prev_mm[None], q_w[:-1]])
        hold = ~ch.present & known[:, None] & (np.abs(q_cmd - prev) <= (0.5 / f if mm else 0.5 / f * scale))
        if hold.any():
            q_w[hold] = np.nan
            filled = np.vstack([self._prev_mm[None], q_w])
            ix = np.where(np.isnan(filled), 0, np.arange(len(q_w) + 1)[:, None])
            np.maximum.accumulate(ix, axis=0, out=ix)
            q_w = np.where(hold, filled[ix, np.arange(q_w.shape[1])][1:], q_w)
            units = np.where(hold, q_w / scale, units)
        self._hold = hold
        return units, q_w

    def _residuals(self, q_nom: np.ndarray, q_w: np.ndarray, kn: np.ndarray, subs: dict, lines: np.ndarray) -> None:
        """The exact residual of what is written, every k-th move (global count) and every inserted point, into
        the report (and the guard); with scope "full" the orientation figures and the cone counts."""
        comp, rep = self.comp, self.report
        k = rep.residual_every
        ev = kn if k == 1 else kn[(self._moves_seen + np.arange(len(kn))) % k == 0]
        self._moves_seen += len(kn)
        qw = np.concatenate([q_w[ev]] + [s[1] for s in subs.values()])
        qn = np.concatenate([q_nom[ev]] + [s[0] for s in subs.values()])
        if len(qw):
            dp, ang = comp.residual(qw, qn)
            err = np.sqrt(np.einsum("ij,ij->i", dp, dp))
            self.guard.residual(err, self._src, np.concatenate([lines[ev]] + [np.full(len(s[1]), lines[r])
                                                                            for r, s in subs.items()]), "tool-tip")
            rep.position.add(err)
            rep.orientation_all.add(ang)
        if comp.scope == "full" and (len(kn) or subs):
            qw_all = np.concatenate([q_w[kn]] + [s[1] for s in subs.values()])
            qn_all = np.concatenate([q_nom[kn]] + [s[0] for s in subs.values()])
            w_all = comp.weight(qn_all)
            rep.in_cone += int((w_all <= 0).sum())
            rep.blended += int(((w_all > 0) & (w_all < 1)).sum())
            dc = np.abs(qw_all[:, self._ri] - qn_all[:, self._ri]).max()
            rep.max_c_correction = max(rep.max_c_correction, float(dc))
            if len(qw):
                w = w_all if k == 1 else comp.weight(qn)
                rep.orientation.add(ang[w >= 1])

    def _subdivide(self, ch, q_nom, q_w, known, scale, f, lines
                   ) -> dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """{row: (nominal, written mm, written units, each (n, n_axes))} for feed moves split into n pieces
        (the last piece ends at the row's own point).  Moves that start after a machine-coordinate line (G28, G53:
        start unknown) are not split."""
        comp, rep = self.comp, self.report
        none = np.full((1, q_nom.shape[1]), np.nan)
        prev_n = np.vstack([self._prev[0][None] if self._prev else none, q_nom[:-1]])
        prev_w = np.vstack([self._prev[1][None] if self._prev else none, q_w[:-1]])
        self._prev = (q_nom[-1].copy(), q_w[-1].copy(), None)
        cand = (ch.motion == 1) & known & ~np.isnan(prev_n).any(axis=1)
        if ch.fresh is not None:
            cand &= ~ch.fresh
        subs: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
        if comp.zero or not cand.any():
            return subs
        idx = np.flatnonzero(cand)
        bound = comp.mid_bound(prev_n[idx], q_nom[idx])
        skip = bound <= self.tolerance
        rep.mid_bounded += int(skip.sum())
        idx = idx[~skip]
        if not len(idx):
            return subs
        dp, _ = comp.residual((prev_w[idx] + q_w[idx]) / 2, (prev_n[idx] + q_nom[idx]) / 2)
        err = np.linalg.norm(dp, axis=1)
        over = err > self.tolerance
        rep.mid_position.add(err[~over])
        # split moves: all moves of a round evaluated together; a move is done when its mid-segment errors are
        # within the tolerance, at max_subdivisions or after 6 rounds (then n doubles)
        rows = idx[over]
        ns = np.minimum(self.max_sub, np.maximum(2, np.ceil(np.sqrt(err[over] / self.tolerance)) + 1)).astype(np.int64)
        done: dict[int, tuple] = {}
        for round_ in range(6):
            if not len(rows):
                break
            mi = np.repeat(np.arange(len(rows)), ns)  # move of each piece
            first = np.cumsum(ns) - ns
            k = np.arange(len(mi)) - first[mi] + 1
            t = (k / ns[mi])[:, None]
            a, b = prev_n[rows][mi], q_nom[rows][mi]
            sn = a + t * (b - a)
            sc = comp.correct(sn)
            sc_scale, sc_f = scale[rows][mi], f[rows][mi]
            su = np.round(sc / sc_scale * sc_f) / sc_f + 0.0
            last = first + ns - 1
            su[last] = q_w[rows] / scale[rows]  # the row's own point, as already rounded
            sw = su * sc_scale
            an = np.empty_like(sn)
            aw = np.empty_like(sw)
            an[1:], aw[1:] = sn[:-1], sw[:-1]
            an[first], aw[first] = prev_n[rows], prev_w[rows]
            dpm, _ = comp.residual((aw + sw) / 2, (an + sn) / 2)
            em = np.sqrt(np.einsum("ij,ij->i", dpm, dpm))
            emax = np.maximum.reduceat(em, first)
            fin = (emax <= self.tolerance) | (ns >= self.max_sub) | (round_ == 5)
            for j in np.flatnonzero(fin).tolist():
                sl = slice(int(first[j]), int(first[j] + ns[j]))
                done[int(rows[j])] = (em[sl], sn[sl], sw[sl], su[sl])
            rows, ns = rows[~fin], np.minimum(self.max_sub, 2 * ns[~fin])
        for r in sorted(done):
            em, sn, sw, su = done[r]
            at = np.full(len(em), lines[r])
            self.guard.written(comp, sw, sn, self._src, at)
            self.guard.residual(em, self._src, at, f"mid-segment (move split into {len(em)} pieces)")
            rep.mid_position.add(em)
            rep.subdivided_moves += 1
            subs[r] = (sn[:-1], sw[:-1], su)
        return subs

    def _render(self, ch, units, q_w, known, subs, scale, f) -> str:
        """Output text of a chunk: changed numbers replaced, missing words added, continuation lines inserted."""
        rep = self.report
        prev_mm = np.vstack([self._prev_mm[None], q_w[:-1]])  # what the machine holds before each row, mm/deg
        given_r = np.round(ch.given * f) / f
        changed = ch.present & (units != given_r) & known[:, None]
        added = ~ch.present & known[:, None] & ~self._hold & ~np.isnan(q_w)
        need = changed.any(axis=1) | added.any(axis=1)
        slow = ~ch.absolute
        if subs:
            slow[list(subs)] = True
        pieces, numidx = ch.pieces, ch.numidx
        # common case (absolute, not subdivided): vectorised choice of cells, one format per changed number
        cells = changed & ~slow[:, None]
        if cells.any():
            r_, a_ = np.nonzero(cells)
            dec, val, idx = ch.decimals[r_, a_], units[r_, a_], numidx[r_, a_]
            for d in np.unique(dec).tolist():  # one %-format call per number of decimals (C loop)
                sel = dec == d
                strs = ((f"%.{d}f\n" * int(sel.sum())) % tuple(val[sel].tolist()))[:-1].split("\n")
                for j, s in zip(idx[sel].tolist(), strs):
                    pieces[j] = s
        rows_added = np.flatnonzero(added.any(axis=1) & ~slow).tolist()
        rows_slow = np.flatnonzero(slow).tolist()
        U = units.tolist() if rows_added or rows_slow else []
        D = ch.decimals.tolist() if rows_added or rows_slow else []
        for r in rows_added:
            d, u = D[r], U[r]
            line = ch.lines[int(ch.rows[r])]
            gcode.edit(ch, r, {}, [(a, "%.*f" % (d[a], u[a])) for a in np.flatnonzero(added[r]).tolist()],
                       " " if " " in line else "")
        rep.lines_changed += int((need & ~slow).sum())
        # incremental rows and subdivided moves: row by row
        Pm = prev_mm.tolist() if rows_slow else []
        HOLD = self._hold.tolist() if rows_slow else []
        for r in rows_slow:
            line = ch.lines[int(ch.rows[r])]
            new, add, cont, sep, feed = self._slow_row(ch, r, line, U, D, Pm, HOLD, scale, subs)
            if new or add or cont:
                gcode.edit(ch, r, new, add, sep, cont)
                if feed:
                    gcode.replace_feed(ch, r, feed)
                rep.lines_changed += 1
                rep.lines_inserted += len(cont)
        self._prev_mm = q_w[-1].copy()
        return "".join(pieces)

    def _slow_row(self, ch, r, line, U, D, Pm, HOLD, scale, subs):
        """Words of an incremental row or a subdivided move, row by row: (new numbers {axis: text}, added words,
        continuation lines, separator, new F of the row or None).  Inverse-time feed (G93, F = 1/minutes per
        block): the n pieces of a split move are equal fractions 1/n of it, so each block carries F * n (a piece
        merged into the next, having no word of its own, adds its fraction there)."""
        F = gcode.fmt
        sep = " " if " " in line else ""
        pts = [U[r]] if r not in subs else subs[r][2].tolist()
        dec, absolute = D[r], bool(ch.absolute[r])
        sc = scale[r].tolist()
        ref = [v / s for v, s in zip(Pm[r], sc)]  # previous written point in this row's units
        first_pt = pts[0]
        new, add = {}, []
        pres, g = ch.present[r].tolist(), ch.given[r].tolist()
        for a in range(len(self.words.letters)):
            v = first_pt[a] if absolute else first_pt[a] - ref[a]
            if v != v:  # NaN: axis not known (uncompensated rapid)
                continue
            v = round(v, dec[a]) + 0.0
            if pres[a]:
                if abs(v - round(g[a], dec[a])) > 0.5 * 10.0 ** -dec[a]:
                    new[a] = F(v, dec[a])
            elif r in subs:  # the first piece of a split move: add what differs from the held value
                if abs(first_pt[a] - ref[a]) > 0.5 * 10.0 ** -dec[a]:
                    add.append((a, F(v, dec[a])))
            elif not HOLD[r][a] and (absolute or v != 0):
                add.append((a, F(v, dec[a])))
        inv = ch.feed[r] if ch.feed is not None and r in subs and ch.feed[r] == ch.feed[r] else None
        cont, last, pieces = [], first_pt, 0
        for p in pts[1:]:
            words = []
            pieces += 1
            for a in range(len(self.words.letters)):
                if abs(p[a] - last[a]) > 0.5 * 10.0 ** -dec[a]:
                    v = p[a] if absolute else p[a] - last[a]
                    words.append(f"{self.words.letters[a]}{F(round(v, dec[a]) + 0.0, dec[a])}")
            last = p
            if words:
                if inv is not None:
                    words.append(f"F{F(inv * len(pts) / pieces, FEED_DECIMALS)}")
                    pieces = 0
                cont.append((sep or " ").join(words))
        return new, add, cont, sep, None if inv is None else F(inv * len(pts), FEED_DECIMALS)

    def _render_fast(self, blk, units, q_w, known, subs, scale, f) -> bytes:
        """Output bytes of a block (byte-level path): the same edits as ``_render``, changed numbers written from
        integer digits in one go, lines with added words or inserted pieces rewritten as text."""
        rep = self.report
        given_r = np.round(blk.given * f) / f
        kn = known[:, None]
        changed = blk.present & (units != given_r) & kn
        added = ~blk.present & kn & ~self._hold & ~np.isnan(q_w)
        add_rows = added.any(axis=1)
        need = changed.any(axis=1) | add_rows
        sub_rows = np.zeros(len(units), dtype=bool)
        if subs:
            sub_rows[list(subs)] = True
        special = add_rows | sub_rows
        rep.lines_changed += int((need & ~sub_rows).sum())
        num_text = []
        cells = changed
        if special.any():
            cells = changed & ~special[:, None]
        flat = np.flatnonzero(cells.ravel())
        if len(flat):
            dec, idx = blk.decimals.ravel()[flat], blk.numidx.ravel()[flat]
            kval = np.rint(units.ravel()[flat] * f.ravel()[flat]).astype(np.int64)  # the digits '%.{d}f' writes
            d0, d1 = int(dec.min()), int(dec.max())
            for d in range(d0, d1 + 1):
                sel = slice(None) if d0 == d1 else dec == d
                if d0 == d1 or sel.any():
                    txt, ln = gcode.format_fixed(kval[sel], d)
                    num_text.append((idx[sel], txt, ln))
        line_text: dict[int, str] = {}
        rows_special = np.flatnonzero(special).tolist()
        if rows_special:
            U, D = units.tolist(), blk.decimals.tolist()
            prev_mm = np.vstack([self._prev_mm[None], q_w[:-1]])
            Pm, HOLD = prev_mm.tolist(), self._hold.tolist()
            for r in rows_special:
                li = int(blk.rows[r])
                line = blk.line(li)
                if r in subs:
                    new, add, cont, sep, _ = self._slow_row(blk, r, line, U, D, Pm, HOLD, scale, subs)
                    if not (new or add or cont):
                        continue
                    rep.lines_changed += 1
                    rep.lines_inserted += len(cont)
                else:
                    d, u = D[r], U[r]
                    new = {a: "%.*f" % (d[a], u[a]) for a in np.flatnonzero(changed[r]).tolist()}
                    add = [(a, "%.*f" % (d[a], u[a])) for a in np.flatnonzero(added[r]).tolist()]
                    cont, sep = None, " " if " " in line else ""
                line_text[li] = gcode.edit_line(line, blk.code_line(li), new, add, sep, cont, self.words)
        self._prev_mm = q_w[-1].copy()
        return gcode.render_block(blk, num_text, line_text)

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
