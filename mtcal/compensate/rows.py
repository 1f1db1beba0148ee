"""The correction of an NC program's motion rows (a part of ``ProgramCompensator``, mtcal.compensate.program):
which rows are known, the corrected commands rounded as written, the exact residual of what is written, and the
subdivision of feed moves whose mid-segment error exceeds the tolerance."""
from __future__ import annotations

import numpy as np

from mtcal.errors import InputError
from mtcal.nc import gcode

_P10 = 10.0 ** np.arange(23)


class RowCorrection:
    """Corrects the motion rows of a parsed chunk or block (G-code or CL data rendered as G-code).

    A mix-in of ``ProgramCompensator``, which holds the state it reads and updates: ``comp`` (the Compensator),
    ``guard``, ``report``, ``words``, ``tolerance``, ``max_sub``, the modal ``_prev`` / ``_prev_mm`` points, the
    source's name ``_src`` and its line numbers (``_cl_lines`` for CL data), and ``_hold`` (the words left out
    because the machine holds them).
    """

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
        rows = idx[over]
        ns = np.minimum(self.max_sub, np.maximum(2, np.ceil(np.sqrt(err[over] / self.tolerance)) + 1)).astype(np.int64)
        done = self._split_moves(rows, ns, (prev_n, prev_w), (q_nom, q_w), scale, f)
        for r in sorted(done):
            em, sn, sw, su = done[r]
            at = np.full(len(em), lines[r])
            self.guard.written(comp, sw, sn, self._src, at)
            self.guard.residual(em, self._src, at, f"mid-segment (move split into {len(em)} pieces)")
            rep.mid_position.add(em)
            rep.subdivided_moves += 1
            subs[r] = (sn[:-1], sw[:-1], su)
        return subs

    def _split_moves(self, rows, ns, prev, at, scale, f) -> dict[int, tuple]:
        """{row: (mid-segment errors, nominal, written mm, written units)} of feed moves ``rows`` split into ``ns``
        pieces: all moves of a round evaluated together; a move is done when its mid-segment errors are within the
        tolerance, at max_subdivisions or after 6 rounds (until then its n doubles).  ``prev``: (nominal, written)
        start points of every row, ``at``: (nominal, written) end points."""
        comp = self.comp
        (prev_n, prev_w), (q_nom, q_w) = prev, at
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
        return done
