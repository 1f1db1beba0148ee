"""Writing corrected rows back into an NC program (a part of ``ProgramCompensator``, mtcal.compensate.program):
changed numbers replaced in place, missing words added, the pieces of subdivided moves inserted as continuation
lines, byte for byte apart from the new numbers, on the line-piece path (``gcode.parse_chunk``) and the byte-level
path (``gcode.scan_block``) alike."""
from __future__ import annotations

import numpy as np

from mtcal.nc import gcode

FEED_DECIMALS = 4  # inverse-time F (1/min) written on split G93 moves


class Rendering:
    """Renders corrected rows as program text or bytes.

    A mix-in of ``ProgramCompensator``, which holds the state it reads and updates: ``report``, ``words``,
    ``_prev_mm`` (what the machine holds before the chunk, mm / deg) and ``_hold`` (set by ``RowCorrection``).
    """

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
