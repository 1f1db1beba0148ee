"""Diagnosis of laser-tracker recordings: fit a quasi-static base model, locate the mismatch, name the effect.

Base model (frames: machine frame = tracker frame, mm; positions mm or deg; errors mm and rad):
* every reflector reading of axis J is its nominal position plus the first-order effect of J's six error
  motions through the generated point Jacobian (Machine.point_jacobian_errors):
  d = J_point(q) e(q); the nominal position uses the point's position from the reference readings (design.md:
  each round's reading at the position closest to zero);
* the error motions are smooth functions that vanish at the reference position: polynomials in (q - q_ref) for
  X, Y, Z and harmonics (cos k q - cos k q_ref, sin k q - sin k q_ref) for B and C, the degree chosen per axis by
  BIC (1..3) with the selected effects in the fit (an unmodelled backlash inflates the residual and would make
  BIC choose too low a degree); the same in every round, direction and time;
* the reference reading is itself noisy (Hocken & Borchardt 1979: normalising to one reading biases every
  deviation of the round): the reference readings only start the fit; each reflector's position (three
  parameters per axis and reflector) is estimated from all its readings in all rounds, so no single reading is
  trusted.  A shift of one (round, reflector) sequence (a re-seated nest) is the candidate effect "offset",
  and so is a tracker knock (effects.py "offset": every reading from t0 on shifted by one vector; t0 scanned
  over the gaps between reading times, counted in the multiplicity);
* weights: the AT960 covariance (mtcal.tracker) of every reading when the tracker position is known (whitened
  least squares; sigma ratio 1 = the tracker's specification), else unweighted with sigma from the residuals;
* with ``model`` given, the base model is that model (readings minus its simulation) plus the offsets.

Diagnosis: studentized residuals grouped by axis x (direction, round, time, position, point) locate the misfit;
candidate effects (mtcal.diagnose_effects, signatures derived in derive/signatures.py) are tested by an F test on
the projected (Frisch-Waugh) columns, with a separability (aliasing) check, Bonferroni control over families x
members, forward selection, backward elimination and held-out-round cross-validation.  The null hypothesis of
every test is the quasi-static family itself (every axis at the largest degree, plus the effects selected
before), not the BIC-selected base: BIC may choose a degree below the truth's (a cubic error function fitted
as a quadratic), and a smooth candidate (a periodic error whose pitch is near the travel) would then be
"found" in the cubic misfit.  An effect is reported only if no error function of the family explains it; the
reported base (degrees, sigma before and after, estimates, cross-validation) is the BIC base with the selected
effects.  With ``model`` given the null is that model (plus offsets), as before.
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np
from scipy import optimize, stats

from mtcal import diagnose_effects as fx
from mtcal.errors import InputError
from mtcal.machine import DEFAULT_MACHINE, Machine, load_machine
from mtcal.recordings import Recording
from mtcal.tracker import covariance

log = logging.getLogger(__name__)
MAX_DEGREE = 3
ALIAS_TOL = 1e-4       # sin of the smallest angle between a candidate and the base below this: not separable
WEAK_TOL = 0.05        # ... below this: separable only weakly (estimate strongly correlated with the base)

NOT_SEPARABLE = {
    "scale": "a linear positioning error is part of the fitted error function E_JJ; compare with a reference model "
             "(--model) or measure a length standard / a second tracker station",
    "second_order": "a quadratic error term is part of the fitted smooth error function; compare with a reference "
                    "model (--model)",
    "squareness": "with each axis measured alone, a squareness is a linear straightness slope of the fitted "
                  "error functions; measure a diagonal or a plate reversal (mtcal plate) to separate it",
    "rotary_location": "with the reference at the zero position, a location error is a first harmonic of the fitted "
                       "rotary error motions; measure at several positions of the other rotary axis, or compare "
                       "with a reference model (--model)",
    "cross_axis": "the recording holds every axis with the other axes at zero; measure the axis again with the "
                  "other axis at a second position (plan 'at')",
    "offset": "one (round, reflector) sequence only: a shift of it is the reflector's position itself",
    "tracker_scale": "with one tracker station a radial scale of the tracker looks like axis scale and rotary "
                     "location errors; measure from a second tracker station or against a length standard",
    "backlash": "every target was approached from one direction; measure bidirectionally (ISO 230-2)",
    "thermal_drift": "the recording has no time_s column",
    "periodic": "the positions do not resolve a pitch shorter than the travel",
}


# ---------------------------------------------------------------------------------------------- preparation
@dataclass
class Prepared:
    rec: Recording
    machine: Machine
    geometry: fx.Geometry
    y: np.ndarray            # (n, 3) readings minus nominal (incl. the given model), mm
    W: np.ndarray            # (n, 3, 3) whitening: W^T W = covariance^-1 (1/mm), or identity
    weighted: bool
    axes: list[str]
    q_ref: dict[str, float]
    seq: np.ndarray          # (n,) index of the (axis, round, point) sequence of each reading
    seq_keys: list[tuple]    # (axis, round, point) per sequence
    order: np.ndarray        # (n,) reading order within the recording (time, else file line)
    given_model: bool
    Aoff: np.ndarray         # (n, 3, 3) d nominal / d point position (rigid motion of the reflector)


def _affine(m: Machine, side: str, axes: np.ndarray, errors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """b (n, 3), A (n, 3, 3) of the exact affine point map p -> m.points(side, axes, p, errors) (the rigid
    motion of a reflector on that side, with the errors)."""
    n = len(axes)
    b = m.points(side, axes, np.zeros((n, 3)), errors)
    A = np.stack([m.points(side, axes, np.broadcast_to(e, (n, 3)), errors) - b for e in np.eye(3)], axis=-1)
    return b, A


def prepare(rec: Recording, machine: Machine | str = DEFAULT_MACHINE, model=None, tracker=None) -> Prepared:
    """Nominal positions, point Jacobians and weights of every reading (see module docstring)."""
    m = machine if isinstance(machine, Machine) else load_machine(machine)
    n = len(rec)
    if n == 0:
        raise InputError(f"{rec.source}: no readings")
    axes = [a for a in m.axes if a in set(rec.axis.tolist())]
    unknown = sorted(set(rec.axis.tolist()) - set(m.axes))
    if unknown:
        raise InputError(f"{rec.source}: axis {unknown[0]!r} is not an axis of {m.name} ({', '.join(m.axes)})")
    order = np.lexsort((rec.line, np.where(np.isfinite(rec.time_s), rec.time_s, 0.0)))
    rank = np.empty(n, int)
    rank[order] = np.arange(n)
    av = np.zeros((n, len(m.axes)))
    for a in axes:
        av[rec.axis == a, m.index(a)] = rec.position[rec.axis == a]
    side = np.array([m.side(a) for a in rec.axis.tolist()])
    errors = model.errors_at(m, av, extrapolate="clamp") if model is not None else np.zeros((n, len(m.error_names)))

    local = np.zeros((n, 3))
    keys = list(zip(rec.axis.tolist(), rec.round.tolist(), rec.point.tolist()))
    seq_keys = sorted(set(keys), key=lambda k: (m.index(k[0]), k[1], k[2]))
    seq_index = {k: i for i, k in enumerate(seq_keys)}
    seq = np.array([seq_index[k] for k in keys])
    q_ref: dict[str, float] = {}
    for a in axes:
        on = rec.axis == a
        pos = rec.position[on]
        q_ref[a] = float(pos[np.argmin(np.abs(pos))])
        for label in sorted(set(rec.point[on].tolist())):
            sel = np.flatnonzero(on & (rec.point == label))
            refs = []
            for r in sorted(set(rec.round[sel].tolist())):
                rs = sel[rec.round[sel] == r]
                at = rs[np.isclose(rec.position[rs], q_ref[a], atol=1e-9)]
                if len(at) == 0:
                    raise InputError(f"{rec.source}: axis {a} round {r} point {label} has no reading at the "
                                     f"reference position {q_ref[a]:g}")
                refs.append(at[np.argmin(rank[at])])
            refs = np.array(refs)
            b, A = _affine(m, m.side(a), av[refs], errors[refs])
            p = np.linalg.solve(A, (rec.xyz[refs] - b)[..., None])[..., 0]
            local[sel] = p.mean(axis=0)
    nominal = np.empty((n, 3))
    Aoff = np.empty((n, 3, 3))
    J = np.empty((n, 3, len(m.error_names)))
    for s in ("tool", "table"):
        mask = side == s
        if mask.any():
            nominal[mask] = m.points(s, av[mask], local[mask], errors[mask])
            Aoff[mask] = m.rigid_motion(s, av[mask])[1]
            J[mask] = m.point_jacobian_errors(s, av[mask], local[mask])
    y = rec.xyz - nominal
    t = None if tracker is None else np.asarray(tracker, dtype=float).reshape(3)
    if t is not None:
        L = np.linalg.cholesky(covariance(rec.xyz, t))
        W = np.linalg.inv(L)
    else:
        W = np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
    g = fx.Geometry(rec.axis, rec.position, rec.direction, rec.time_s, side, rec.xyz, J, m, t)
    return Prepared(rec, m, g, y, W, t is not None, axes, q_ref, seq, seq_keys, rank, model is not None, Aoff)


# ---------------------------------------------------------------------------------------------- base design
def _basis(linear: bool, q: np.ndarray, q_ref: float, degree: int, span: float) -> np.ndarray:
    """(n, k) smooth functions of the position vanishing at the reference position."""
    if degree == 0:
        return np.zeros((len(q), 0))
    if linear:
        s = (q - q_ref) / max(span, 1e-9)
        return np.stack([s**k for k in range(1, degree + 1)], axis=1)
    th, t0 = np.deg2rad(q), np.deg2rad(q_ref)
    cols = []
    for k in range(1, degree + 1):
        cols += [np.cos(k * th) - np.cos(k * t0), np.sin(k * th) - np.sin(k * t0)]
    return np.stack(cols, axis=1)


@dataclass
class Base:
    blocks: dict[str, np.ndarray]   # axis -> (n, 3, p_axis) raw design, mm per parameter (zero off the axis)
    degrees: dict[str, int]


def base_design(prep: Prepared, degrees: dict[str, int], axes: Sequence[str] | None = None) -> Base:
    """Per axis: error-function columns J_point[:, e] * basis_k(q) and per-(round, point) offset columns."""
    g, rec = prep.geometry, prep.rec
    blocks = {}
    for a in (axes or prep.axes):
        on = rec.axis == a
        pos = rec.position[on]
        span = float(np.ptp(pos)) or 1.0
        B = _basis(prep.machine.kind(a) == "linear", rec.position[on], prep.q_ref[a], degrees.get(a, 0), span)
        cols = []
        for e in prep.machine.error_motions(a):
            c = g.col(e)[on]
            cols += [c * B[:, k:k + 1] for k in range(B.shape[1])]
        # point positions: d nominal / d point = the rigid motion of the point (identity tool side, R(q) table
        # side); estimated from every reading of every round, so no single reference reading is trusted
        for label in np.unique(rec.point[on]):
            m = rec.point[on] == label
            for k in range(3):
                c = np.zeros((int(on.sum()), 3))
                c[m] = prep.Aoff[on][m][:, :, k]
                cols.append(c)
        blocks[a] = np.stack(cols, axis=-1)
    return Base(blocks, dict(degrees))


def whiten(W: np.ndarray, v: np.ndarray) -> np.ndarray:
    """(n, 3) -> (3n,), or (n, 3, k) -> (3n, k)."""
    if v.ndim == 2:
        return np.einsum("nij,nj->ni", W, v).reshape(-1)
    return np.einsum("nij,njk->nik", W, v).reshape(-1, v.shape[-1])


# ---------------------------------------------------------------------------------------------- statistics
class Engine:
    """Least squares on a block-diagonal base (one block of rows per axis) plus global columns.

    Keeps an orthonormal basis of the fitted columns (per block, and ``E`` for columns added across blocks)
    and the residual; scores candidate columns by projection (Frisch-Waugh-Lovell), never forming normal
    equations of the base."""

    def __init__(self, blocks: list[tuple[np.ndarray, np.ndarray]], y: np.ndarray):
        self.N = len(y)
        self.y = y
        self.blocks = [(idx, self._orth(X)) for idx, X in blocks]
        self.E = np.zeros((self.N, 0))
        self.r = y - self.project(y[:, None])[:, 0]
        self.p = sum(q.shape[1] for _, q in self.blocks)

    @staticmethod
    def _orth(G: np.ndarray) -> np.ndarray:
        if G.shape[1] == 0:
            return np.zeros((G.shape[0], 0))
        scale = np.linalg.norm(G, axis=0)
        G = G[:, scale > 0] / scale[scale > 0]
        q, rr = np.linalg.qr(G)
        d = np.abs(np.diag(rr))
        keep = d > 1e-9 * max(1.0, float(d.max()) if len(d) else 1.0)
        if not keep.all():  # rank-deficient: fall back to the SVD
            u, sv, _ = np.linalg.svd(G, full_matrices=False)
            return u[:, sv > 1e-9 * sv[0]]
        return q

    def qt(self, G: np.ndarray) -> np.ndarray:
        """Q^T G (p, k)."""
        parts = [q.T @ G[idx] for idx, q in self.blocks]
        parts.append(self.E.T @ G)
        return np.vstack(parts)

    def project(self, G: np.ndarray) -> np.ndarray:
        """Q Q^T G (N, k)."""
        out = self.E @ (self.E.T @ G)
        for idx, q in self.blocks:
            out[idx] += q @ (q.T @ G[idx])
        return out

    def rows(self) -> np.ndarray:
        """Per reading, its three rows of Q padded to a common width (n, 3, P): enough for leverages and for
        sums over readings of one axis (the blocks have disjoint rows)."""
        pmax = max([q.shape[1] for _, q in self.blocks] + [0])
        out = np.zeros((self.N, pmax + self.E.shape[1]))
        for idx, q in self.blocks:
            out[idx, :q.shape[1]] = q
        out[:, pmax:] = self.E
        return out.reshape(self.N // 3, 3, -1)

    @property
    def rss(self) -> float:
        return float(self.r @ self.r)

    @property
    def dof(self) -> int:
        return self.N - self.p

    @property
    def sigma(self) -> float:
        return math.sqrt(self.rss / max(self.dof, 1))

    def score(self, G: np.ndarray) -> dict:
        """F test of adding the columns G (N, k) to the fit; separability = sin of the smallest angle to the base."""
        GtG = G.T @ G
        lam, V = np.linalg.eigh(GtG)
        if lam[-1] <= 0:
            return {"separable": False, "sep": 0.0, "k": 0}
        keep = lam > 1e-12 * lam[-1]
        T = V[:, keep] / np.sqrt(lam[keep])
        QtG = self.qt(G) @ T
        M = np.eye(T.shape[1]) - QtG.T @ QtG
        mu, U = np.linalg.eigh(M)
        sep = math.sqrt(max(mu[0], 0.0))
        ok = mu > ALIAS_TOL**2
        if not ok.any():
            return {"separable": False, "sep": sep, "k": 0}
        b = U[:, ok].T @ (T.T @ (G.T @ self.r))
        delta = float(np.sum(b**2 / mu[ok]))
        k = int(ok.sum())
        dof = self.dof - k
        rss1 = max(self.rss - delta, 1e-300)
        F = (delta / k) / (rss1 / max(dof, 1))
        return {"separable": True, "sep": sep, "k": k, "dof": max(dof, 1), "delta": delta, "F": F,
                "logp": float(stats.f.logsf(F, k, max(dof, 1)))}

    def add(self, G: np.ndarray) -> None:
        Gp = G - self.project(G)
        Gp = Gp - self.project(Gp)
        q = self._orth(Gp)
        self.E = np.hstack([self.E, q])
        self.r = self.r - q @ (q.T @ self.r)
        self.p += q.shape[1]

    def copy_base(self) -> "Engine":
        e = Engine.__new__(Engine)
        e.N, e.y, e.blocks, e.E = self.N, self.y, self.blocks, np.zeros((self.N, 0))
        e.r = self.y - e.project(self.y[:, None])[:, 0]
        e.p = sum(q.shape[1] for _, q in self.blocks)
        return e

    def estimate(self, Gs: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """Joint estimate and covariance of the columns Gs given the block base (Frisch-Waugh-Lovell);
        sigma from this engine's residual."""
        G = np.hstack(Gs)
        base = self.copy_base()
        Gp = G - base.project(G)
        theta, *_ = np.linalg.lstsq(Gp, base.r, rcond=None)
        cov = self.sigma**2 * np.linalg.pinv(Gp.T @ Gp)
        return theta, cov


def engine_for(prep: "Prepared", base: "Base", wy: np.ndarray, rows: np.ndarray | None = None) -> Engine:
    """Engine of the base design (blocks per axis), optionally on a subset of readings ``rows`` (bool (n,))."""
    n = len(prep.rec)
    keep = np.ones(n, bool) if rows is None else rows
    blocks = []
    sel3 = np.repeat(keep, 3)
    pos = np.cumsum(sel3) - 1
    for a, X in base.blocks.items():
        on = (prep.rec.axis == a) & keep
        if not on.any():
            continue
        Xw = whiten(prep.W[on], X[keep[prep.rec.axis == a]])
        Xw = Xw[:, np.any(Xw != 0, axis=0)]
        blocks.append((pos[np.repeat(on, 3)], Xw))
    return Engine(blocks, wy[sel3])


# ---------------------------------------------------------------------------------------------- locate
def locate(prep: Prepared, eng: Engine, level: float) -> tuple[list[dict], np.ndarray]:
    """Where the studentized residuals concentrate: groups by axis x (direction, round, time, position, point)."""
    n = len(prep.rec)
    r = eng.r.reshape(n, 3)
    Qi = eng.rows()
    H = np.einsum("nip,njp->nij", Qi, Qi)
    IH = np.eye(3) - H
    s2 = eng.sigma**2
    t2 = np.einsum("ni,ni->n", r, np.linalg.solve(IH + 1e-12 * np.eye(3), r[..., None])[..., 0]) / s2
    rec = prep.rec
    tests = []
    for a in prep.axes:
        on = rec.axis == a
        groups: list[tuple[str, Any, np.ndarray]] = []
        for d in (1, -1):
            groups.append(("direction", d, on & (rec.direction == d)))
        for rr in sorted(set(rec.round[on].tolist())):
            groups.append(("round", int(rr), on & (rec.round == rr)))
        for p in sorted(set(rec.position[on].tolist())):
            groups.append(("position", float(p), on & (rec.position == p)))
        for lab in sorted(set(rec.point[on].tolist())):
            groups.append(("point", str(lab), on & (rec.point == lab)))
        ts = rec.time_s[on]
        if np.isfinite(ts).all():
            edges = np.quantile(ts, [0, 1 / 3, 2 / 3, 1])
            for k in range(3):
                sel = on & (rec.time_s >= edges[k]) & ((rec.time_s < edges[k + 1]) if k < 2 else np.ones(n, bool))
                groups.append(("time", [round(float(edges[k]), 1), round(float(edges[k + 1]), 1)], sel))
        for by, where, sel in groups:
            ng = int(sel.sum())
            if ng < 2:
                continue
            mean = r[sel].sum(axis=0)
            T_shift = float(mean @ mean) / (ng * s2)
            p_shift = float(stats.chi2.sf(T_shift, 3))
            S = float(t2[sel].sum())
            p_disp = float(stats.chi2.sf(S, 3 * ng))
            tests.append((a, by, where, ng, min(p_shift, p_disp), "mean" if p_shift <= p_disp else "spread",
                          T_shift / 3, S / (3 * ng)))
    out = []
    for a, by, where, ng, p, kind, shift, disp in tests:
        padj = min(1.0, 2 * p * len(tests))  # Bonferroni over groups x (mean, spread)
        if padj < level:
            out.append({"axis": a, "by": by, "where": where, "score": float(-math.log10(max(padj, 1e-300))),
                        "p_adjusted": padj, "kind": kind, "readings": ng,
                        "mean_shift_chi2_per_dof": shift, "spread_chi2_per_dof": disp})
    out.sort(key=lambda d: -d["score"])
    return out, t2


# ---------------------------------------------------------------------------------------------- candidates
def candidates(prep: Prepared, max_degree: int) -> tuple[list[fx.Candidate], list[dict]]:
    """All candidates that can be tested, and notes on the ones this recording cannot show."""
    g, rec = prep.geometry, prep.rec
    out: list[fx.Candidate] = []
    notes: list[dict] = []
    for a in prep.axes:
        on = rec.axis == a
        dirs = set(rec.direction[on].tolist())
        if {1, -1} <= dirs:
            out.append(fx.backlash(g, a))
        else:
            notes.append({"name": "backlash", "axis": a, "not_separable": NOT_SEPARABLE["backlash"]})
        grid, span = fx.pitch_grid(rec.position[on], g.linear(a), max_degree)
        for pitch in grid:
            out.append(fx.periodic(g, a, pitch, span))
        out.append(fx.scale(g, a))
        for e in prep.machine.error_motions(a):
            out.append(fx.second_order(g, a, e))
        notes.append({"name": "cross_axis", "axis": a, "not_separable": NOT_SEPARABLE["cross_axis"]})
    for e, (name, a) in fx.constants(prep.machine).items():
        if a in prep.axes:
            out.append(fx.constant(g, name, e))
    if np.isfinite(rec.time_s).all():
        t0 = float(np.min(rec.time_s))
        sides = set(g.side.tolist())
        targets = (["spindle"] if "tool" in sides else []) + (["table"] if "table" in sides else []) + (
            ["tracker"] if len(sides) > 1 else [])
        for target in targets:
            for tau in fx.TAUS_S:
                out.append(fx.thermal_drift(g, target, tau, t0))
    else:
        notes.append({"name": "thermal_drift", "axis": None, "not_separable": NOT_SEPARABLE["thermal_drift"]})
    if g.tracker is not None:
        out.append(fx.tracker_scale(g))
    for s, (a, r, label) in enumerate(prep.seq_keys):
        rows = np.flatnonzero(prep.seq == s)
        out.append(fx.offset(g, rows, {"round": int(r), "point": str(label)}))
    return out, notes


def _outlier_scan(prep: Prepared, eng: Engine) -> tuple[dict, int]:
    """Best single-reading and bumped-nest (rest of the round) displacement; returns (best, family size)."""
    n = len(prep.rec)
    W = prep.W
    r = eng.r.reshape(n, 3)
    Qi = eng.rows()
    # one reading: span of the three whitened unit columns
    M = np.eye(3) - np.einsum("nip,njp->nij", Qi, Qi)
    ok = np.linalg.eigvalsh(M)[:, 0] > ALIAS_TOL**2
    delta = np.zeros(n)
    delta[ok] = np.einsum("ni,ni->n", r[ok], np.linalg.solve(M[ok], r[ok][..., None])[..., 0])
    i = int(np.argmax(delta))
    best = {"delta": float(delta[i]), "rows": np.array([i]), "mode": "reading"}
    count = int(ok.sum())
    # bumped nest: readings s.. of one (axis, round, point) sequence in time order
    for s in range(len(prep.seq_keys)):
        idx = np.flatnonzero(prep.seq == s)
        idx = idx[np.argsort(prep.order[idx])]
        if len(idx) < 3:
            continue
        Wi = W[idx]
        A = np.cumsum((Wi.transpose(0, 2, 1) @ Wi)[::-1], axis=0)[::-1]          # sum W^T W
        B = np.cumsum(np.einsum("npk,nkj->npj", Qi[idx].transpose(0, 2, 1), Wi)[::-1], axis=0)[::-1]  # Q^T G
        b = np.cumsum(np.einsum("nki,nk->ni", Wi, r[idx])[::-1], axis=0)[::-1]   # G^T r
        for j in range(1, len(idx) - 1):
            GpGp = A[j] - B[j].T @ B[j]
            lam = np.linalg.eigvalsh(GpGp)
            if lam[0] <= ALIAS_TOL**2 * np.linalg.eigvalsh(A[j])[-1]:
                continue
            d = float(b[j] @ np.linalg.solve(GpGp, b[j]))
            count += 1
            if d > best["delta"]:
                best = {"delta": d, "rows": idx[j:], "mode": "bump"}
    return best, count


def _knock_scan(prep: Prepared, eng: Engine) -> tuple[dict | None, int]:
    """Change point of a tracker knock: every reading from t0 on (all axes, all reflectors) shifted by one
    vector.  t0 is scanned over the gaps between distinct reading times; each step column (whitened W_i on the
    readings after t0) is scored by running sums in time order (Frisch-Waugh: G^T G, Q^T G and G^T r), across
    the base blocks.  Returns (best {"delta", "t0", "rows"}, number of separable change points scanned)."""
    rec = prep.rec
    n = len(rec)
    if n < 3 or not np.isfinite(rec.time_s).all():
        return None, 0
    W = prep.W
    r = eng.r.reshape(n, 3)
    # per reading, its three rows of the full Q (every block at its own columns, then E)
    widths = [q.shape[1] for _, q in eng.blocks]
    P = sum(widths) + eng.E.shape[1]
    Qf = np.zeros((3 * n, P))
    off = 0
    for (idx, q), w in zip(eng.blocks, widths):
        Qf[idx, off:off + w] = q
        off += w
    Qf[:, off:] = eng.E
    Qf = Qf.reshape(n, 3, P)
    o = np.argsort(prep.order)
    t = rec.time_s[o]
    Wo = W[o]
    A = np.cumsum((Wo.transpose(0, 2, 1) @ Wo)[::-1], axis=0)[::-1]                  # G^T G
    B = np.cumsum(np.einsum("nkp,nkj->npj", Qf[o], Wo)[::-1], axis=0)[::-1]          # Q^T G
    b = np.cumsum(np.einsum("nki,nk->ni", Wo, r[o])[::-1], axis=0)[::-1]             # G^T r
    j = np.flatnonzero(np.diff(t) > 0) + 1       # the step starts at reading j (distinct times only)
    if len(j) == 0:
        return None, 0
    M = A[j] - np.einsum("npi,npj->nij", B[j], B[j])
    # separability as in Engine.score: sin^2 of the angles between G and the base, relative to G^T G
    L = np.linalg.cholesky(A[j])
    Li = np.linalg.inv(L)
    mu = np.linalg.eigvalsh(Li @ M @ Li.transpose(0, 2, 1))
    ok = mu[:, 0] > ALIAS_TOL**2
    if not ok.any():
        return None, 0
    delta = np.full(len(j), -np.inf)
    delta[ok] = np.einsum("ni,ni->n", b[j][ok], np.linalg.solve(M[ok], b[j][ok][..., None])[..., 0])
    k = int(np.argmax(delta))
    jj = int(j[k])
    return {"delta": float(delta[k]), "t0": 0.5 * float(t[jj - 1] + t[jj]), "rows": o[jj:],
            "before_s": float(t[jj - 1]), "after_s": float(t[jj])}, int(ok.sum())


def _where(prep: Prepared, rows: np.ndarray) -> dict:
    rec = prep.rec
    i = rows[np.argmin(prep.order[rows])]
    return {"round": int(rec.round[i]), "position": float(rec.position[i]), "point": str(rec.point[i]),
            "approach": int(rec.direction[i]), "line": int(rec.line[i]), "readings": int(len(rows))}


# ---------------------------------------------------------------------------------------------- diagnosis
@dataclass
class Diagnosis:
    base_sigma: float
    base_sigma_ratio: float
    sigma_after: float
    sigma_ratio_after: float
    effects: list[dict]
    located: list[dict]
    base: dict
    notes: list[str] = field(default_factory=list)
    residuals_before: np.ndarray | None = None
    residuals_after: np.ndarray | None = None
    prep: Prepared | None = None

    def to_dict(self) -> dict:
        return {"base_sigma": self.base_sigma, "base_sigma_ratio": self.base_sigma_ratio,
                "sigma_after": self.sigma_after, "sigma_ratio_after": self.sigma_ratio_after,
                "effects": self.effects, "located": self.located, "base_model": self.base,
                "units": {"length": "mm", "angle": "rad", "position": "mm (linear axes) or deg (rotary axes)",
                          "sigma_ratio": "1 = the tracker's specification (AT960) when --tracker is given"},
                "notes": self.notes}


def _raw_sigma(prep: Prepared, r_w: np.ndarray, dof: int) -> float:
    n = len(prep.rec)
    raw = np.linalg.solve(prep.W, r_w.reshape(n, 3)[..., None])[..., 0]
    return math.sqrt(float(np.sum(raw**2)) / max(dof, 1))


def _select_degrees(prep: Prepared, wy: np.ndarray, max_degree: int, progress,
                    effects: Sequence[np.ndarray] = ()) -> dict[str, int]:
    """Per axis, the degree (1..max) with the least BIC of the axis' own whitened fit, with the whitened
    columns ``effects`` (N, k) of the selected effects in the fit (restricted to the axis' readings): an
    unmodelled effect (backlash) inflates the residual and would make BIC choose too low a degree."""
    out = {}
    for a in prep.axes:
        on = prep.rec.axis == a
        G = None
        if len(effects):
            G = np.hstack(effects)[np.repeat(on, 3)]
            G = G[:, np.any(G != 0, axis=0)]
        best = None
        for d in range(1, max_degree + 1):
            e = engine_for(prep, base_design(prep, {a: d}, [a]), wy, on)
            if G is not None and G.shape[1]:
                e.add(G)
            na = e.N
            bic = na * math.log(e.rss / na) + e.p * math.log(na)
            if best is None or bic < best[0]:
                best = (bic, d)
        out[a] = best[1]
        progress(f"axis {a}: degree {best[1]} by BIC" + (" (with the selected effects)" if G is not None else ""))
    return out


def _headline(c: fx.Candidate, theta: np.ndarray, cov: np.ndarray) -> dict:
    """The reported estimate (one number with its unit and standard uncertainty) and all parameters."""
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    params = {p: float(v) for p, v in zip(c.params, theta)}
    if c.name == "periodic":
        amp = float(np.hypot(*theta))
        g = theta / amp if amp > 0 else np.zeros(2)
        u = float(math.sqrt(max(g @ cov @ g, 0.0)))
        params["phase_deg"] = float(np.degrees(np.arctan2(theta[1], theta[0])))
        return {"estimate": amp, "uncertainty": u, "unit": c.extra["amplitude_unit"],
                "parameters": params, "direction": None}
    if c.extra.get("variant") == "tracker knock":  # the step: its size (mm) along its direction, from t0 on
        size = float(np.linalg.norm(theta))
        g = theta / size if size > 0 else np.zeros(3)
        k = int(np.argmax(np.abs(theta)))
        return {"estimate": size, "uncertainty": float(math.sqrt(max(g @ cov @ g, 0.0))), "unit": "mm",
                "parameters": params, "direction": ("+" if theta[k] >= 0 else "-") + "XYZ"[k],
                "unit_vector": [float(v) for v in g], "t0_s": c.extra["t0_s"],
                "vector": [float(v) for v in theta], "vector_uncertainty": [float(v) for v in sd]}
    if c.name in ("thermal_drift", "outlier", "offset"):
        k = int(np.argmax(np.abs(theta) / np.maximum(sd, 1e-300)))  # the best-determined component
        return {"estimate": float(abs(theta[k])), "uncertainty": float(sd[k]), "unit": "mm", "parameters": params,
                "direction": ("+" if theta[k] >= 0 else "-") + "XYZ"[k],
                "vector": [float(v) for v in theta], "vector_uncertainty": [float(v) for v in sd]}
    unit = c.params[0].split("(")[-1].rstrip(")") if "(" in c.params[0] else c.params[0]
    return {"estimate": float(theta[0]), "uncertainty": float(sd[0]), "unit": unit, "parameters": params,
            "direction": None}


def _refine(c: fx.Candidate, eng: Engine, s: dict) -> tuple[fx.Candidate, dict]:
    """Refine a continuous parameter (pitch, tau) of the family winner by a bounded 1-D search."""
    if c.refine is None:
        return c, s
    lo, hi = c.refine_range
    v = c.refine_value
    a, b = max(lo, v / 1.5), min(hi, v * 1.5)
    if b <= a:
        return c, s

    def f(logv: float) -> float:
        cc = c.refine(math.exp(logv))
        sc = eng.score(_w(cc))
        return -sc.get("delta", 0.0)
    res = optimize.minimize_scalar(f, bounds=(math.log(a), math.log(b)), method="bounded",
                                   options={"xatol": 1e-3})
    cc = c.refine(math.exp(res.x))
    sc = eng.score(_w(cc))
    if sc.get("separable") and sc["delta"] > s["delta"]:
        return cc, sc
    return c, s


_PREP: Prepared | None = None  # the recording being diagnosed: whitens candidate columns once (cached)


def _w(c: fx.Candidate) -> np.ndarray:
    assert _PREP is not None
    if "_w" not in c.extra:
        c.extra["_w"] = whiten(_PREP.W, c.G)
    return c.extra["_w"]


def _cv(prep: Prepared, base: Base, wy: np.ndarray, Gs: list[np.ndarray]) -> tuple[float, float]:
    """Held-out-round gain of the effects Gs: estimated on the other rounds, applied to the held-out round
    after the base model (all its parameters) is fitted to that round alone.  Returns 1 - RSS_with / RSS_without
    summed over rounds: returns (RSS with, RSS without), both whitened."""
    rounds = sorted(set(prep.rec.round.tolist()))
    if len(rounds) < 2 or not Gs:
        return float("nan"), float("nan")
    G = np.hstack(Gs)
    r3 = np.repeat(prep.rec.round, 3)
    with_, without = 0.0, 0.0
    for k in rounds:
        tr = prep.rec.round != k
        e_tr = engine_for(prep, base, wy, tr)
        Gtr = G[np.repeat(tr, 3)]
        if not np.any(Gtr):
            continue
        theta, _ = e_tr.estimate([Gtr])
        te = ~tr
        e_te = engine_for(prep, base, wy, te)
        pred = G[r3 == k] @ theta
        res = e_te.r - (pred - e_te.project(pred[:, None])[:, 0])
        with_ += float(res @ res)
        without += e_te.rss
    return with_, without


def diagnose(rec: Recording, model=None, *, machine: Machine | str = DEFAULT_MACHINE, tracker=None, level: float = 0.01,
             max_degree: int = MAX_DEGREE, max_effects: int = 8) -> Diagnosis:
    """Diagnose a recording (see module docstring).  ``level``: family-wise significance level."""
    global _PREP
    say = log.info
    if not 0 < level < 1:
        raise InputError(f"level must be in (0, 1), got {level}")
    prep = prepare(rec, machine, model, tracker)
    _PREP = prep
    wy = whiten(prep.W, prep.y)
    # the null hypothesis of every test: the quasi-static family itself (every axis at the largest degree), not
    # the BIC-selected base: an effect is reported only if no smooth error function of the family explains it
    # (a cubic misfit of a degree-2 base is not a long-pitch periodic error); BIC picks the reported base after
    test_degrees = {a: 0 if prep.given_model else max_degree for a in prep.axes}
    eng = engine_for(prep, base_design(prep, test_degrees), wy)
    say(f"null model of the tests: {eng.p} parameters (quasi-static family"
        f"{', given model' if prep.given_model else f' at degree {max_degree}'}), sigma ratio {eng.sigma:.3f}")

    cands, notes = candidates(prep, max_degree)
    effects_out: list[dict] = []
    if not prep.given_model:  # quasi-static effects against the base family at its largest degree: aliased?
        keep, seen = [], set()
        for c in cands:
            if c.name in fx.QUASI_STATIC or c.name == "tracker_scale":
                sc = eng.score(_w(c))
                if not sc["separable"] or (c.name == "tracker_scale" and sc["sep"] < WEAK_TOL):
                    if (c.name, c.axis) not in seen:
                        seen.add((c.name, c.axis))
                        notes.append({"name": c.name, "axis": c.axis, "not_separable": NOT_SEPARABLE[c.name],
                                      "separability": sc["sep"]})
                    continue
            keep.append(c)
        cands = keep
    say(f"{len(cands)} candidate effects")

    selected: list[tuple[fx.Candidate, dict, float]] = []
    last_scores: dict[str, tuple[fx.Candidate, dict, float]] = {}
    for step in range(max_effects):
        fams: dict[str, list[tuple[fx.Candidate, dict]]] = {}
        for c in cands:
            sc = eng.score(_w(c))
            if sc["separable"]:
                fams.setdefault(c.family, []).append((c, sc))
        oscan, ocount = _outlier_scan(prep, eng)
        kscan, kcount = _knock_scan(prep, eng)
        n_fam = len(fams) + (1 if ocount else 0) + (1 if kcount else 0)
        last_scores = {}
        for fam_name, members in fams.items():
            c, sc = min(members, key=lambda cs: cs[1]["logp"])
            c, sc = _refine(c, eng, sc)
            last_scores[fam_name] = (c, sc, sc["logp"] + math.log(len(members) * n_fam))
        scanned = []  # (family, best member, members scanned): penalised for the whole scan
        if ocount:
            scanned.append(("outlier", fx.outlier(prep.geometry, oscan["rows"], oscan["mode"],
                                                  _where(prep, oscan["rows"])), ocount))
        if kcount:  # tracker knock: the change point t0 scanned over the reading times (kcount members)
            first = kscan["rows"][np.argmin(prep.order[kscan["rows"]])]
            where = {"from_axis": str(prep.rec.axis[first]), **_where(prep, kscan["rows"]),
                     "last_reading_before_s": kscan["before_s"], "first_reading_after_s": kscan["after_s"]}
            scanned.append(("offset", fx.tracker_knock(prep.geometry, kscan["t0"], where), kcount))
        for fam_name, cand, count in scanned:
            sc = eng.score(_w(cand))
            if sc["separable"]:
                last_scores[fam_name] = (cand, sc, sc["logp"] + math.log(count * n_fam))
        if not last_scores or min(v[2] for v in last_scores.values()) >= math.log(level):
            break
        # among the significant candidates, the strongest evidence (raw p) names the effect: the multiplicity
        # penalty decides significance, not which of two correlated explanations wins
        # exact ties (a knock just after a reflector's first sequence is the same column space as that nest's
        # offset) go to the smaller family: the adjusted p breaks them
        sig_c = [v for v in last_scores.values() if v[2] < math.log(level)]
        top_lp = min(v[1]["logp"] for v in sig_c)
        tol = 1e-9 * max(1.0, abs(top_lp)) if math.isfinite(top_lp) else 0.0
        tied = [v for v in sig_c if v[1]["logp"] <= top_lp + tol]
        c, sc, lp = min(tied, key=lambda v: v[2])
        sig_before = eng.sigma
        eng.add(_w(c))
        say(f"step {step + 1}: {c.name} {c.axis or ''} {c.label}: F = {sc['F']:.1f}, "
            f"sigma ratio {sig_before:.3f} -> {eng.sigma:.3f}")
        selected.append((c, sc, lp))
        if c.family not in ("outlier", "offset"):  # one member per family (a second periodic pitch: a new step;
            # outliers and tracker knocks are scanned afresh every step)
            cands = [x for x in cands if x.family != c.family]

    # backward elimination: drop a selected effect that the others have made insignificant
    while len(selected) > 1:
        worst = None
        for j, (c, sc, lp) in enumerate(selected):
            e = eng.copy_base()
            for i, (o, _, _) in enumerate(selected):
                if i != j:
                    e.add(_w(o))
            s2 = e.score(_w(c))
            lp2 = (s2["logp"] + lp - sc["logp"]) if s2["separable"] else 0.0
            if worst is None or lp2 > worst[1]:
                worst = (j, lp2)
        if worst[1] < math.log(level):
            break
        c = selected.pop(worst[0])[0]
        say(f"backward: {c.name} {c.axis or ''} {c.label} dropped (explained by the other effects)")
        eng = eng.copy_base()
        for o, _, _ in selected:
            eng.add(_w(o))

    null_model = ("the given model" if prep.given_model else
                  f"the quasi-static family at degree {max_degree} on every axis") + " + the effects selected before"
    # the reported base model: degrees by BIC with the selected effects in the fit (an unmodelled effect would
    # bias BIC low), then the base alone (sigma before, located) and with the effects (estimates, sigma after)
    degrees = (dict(test_degrees) if prep.given_model
               else _select_degrees(prep, wy, max_degree, say, [_w(c) for c, _, _ in selected]))
    base = base_design(prep, degrees)
    eng = engine_for(prep, base, wy)
    base_sigma = _raw_sigma(prep, eng.r, eng.dof)
    base_ratio = eng.sigma
    say(f"base model: {eng.p} parameters, sigma {base_sigma * 1e3:.3f} um (ratio {base_ratio:.3f})")
    located, _ = locate(prep, eng, level)
    r_before = eng.r.copy()
    for c, _, _ in selected:
        eng.add(_w(c))

    # final joint estimates, cumulative sigma and held-out-round cross-validation
    theta_all, cov_all = (eng.estimate([_w(c) for c, _, _ in selected]) if selected
                          else (np.zeros(0), np.zeros((0, 0))))
    cum = eng.copy_base()
    Gs: list[np.ndarray] = []
    off = 0
    prev_cv = None
    for c, sc, lp in selected:
        k = c.G.shape[-1]
        th, cv = theta_all[off:off + k], cov_all[off:off + k, off:off + k]
        off += k
        cum.add(_w(c))
        Gs.append(_w(c))
        with_, without = _cv(prep, base, wy, Gs)
        if prev_cv is None:
            prev_cv = without
        gain = 1.0 - with_ / prev_cv if prev_cv and prev_cv > 0 else float("nan")
        prev_cv = with_
        h = _headline(c, th, cv)
        ev = {"test": "F", "F": sc["F"], "dof": [sc["k"], sc["dof"]], "p_value": math.exp(sc["logp"]),
              "p_adjusted": min(1.0, math.exp(lp)), "log10_p_adjusted": lp / math.log(10),
              "cv_gain": gain, "cv": "held-out rounds", "separability": sc["sep"],
              "multiplicity": "Bonferroni over families x members", "null": null_model}
        item_dir = h.pop("direction")
        item = {"name": c.name, "axis": c.axis, "direction": item_dir, "significant": True,
                "estimate": h.pop("estimate"), "uncertainty": h.pop("uncertainty"), "unit": h.pop("unit"),
                "sigma_after": _raw_sigma(prep, cum.r, cum.dof), "sigma_ratio_after": cum.sigma,
                "evidence": ev, "where": (f"step along {item_dir}, {c.label}" if "t0_s" in h else c.label),
                **{k2: v for k2, v in c.extra.items() if not k2.startswith("_") and k2 != "rows"}, **h}
        if sc["sep"] < WEAK_TOL:
            item["note"] = "weakly separable from the base model: the estimate is correlated with the fitted errors"
        if c.name not in ("outlier", "offset") and not (gain > 0):  # round-specific: nothing to predict
            item["significant"] = False
            item["note"] = "significant in the F test but no gain on held-out rounds"
        effects_out.append(item)
    effects_out.sort(key=lambda d: (not d["significant"], -d["evidence"]["F"] * d["evidence"]["dof"][0]))
    chosen = {c.family for c, _, _ in selected}
    for fam_name, (c, sc, lp) in sorted(last_scores.items(), key=lambda kv: kv[1][2]):
        if fam_name in chosen:
            continue
        effects_out.append({"name": c.name, "axis": c.axis, "direction": None, "significant": False,
                            "estimate": None, "sigma_after": None, "where": c.label,
                            "evidence": {"test": "F", "F": sc["F"], "p_value": math.exp(sc["logp"]),
                                         "p_adjusted": min(1.0, math.exp(lp)), "cv_gain": None,
                                         "separability": sc["sep"]}})
    for nt in notes:
        effects_out.append({"name": nt["name"], "axis": nt["axis"], "direction": None, "significant": False,
                            "estimate": None, "sigma_after": None, "evidence": None,
                            "not_separable": nt["not_separable"],
                            **({"separability": nt["separability"]} if "separability" in nt else {})})
    base_info = {"kind": "given model" if prep.given_model else "fitted quasi-static",
                 "degrees": degrees, "parameters": int(cum.copy_base().p), "readings": len(rec),
                 "tests_against": null_model if prep.given_model else
                 f"the quasi-static family at degree {max_degree} on every axis (degrees above: BIC with the "
                 f"selected effects in the fit)",
                 "weighted": prep.weighted,
                 "basis": "polynomials in (q - q_ref) for X, Y, Z; harmonics for B, C; per-(round, point) offsets"}
    return Diagnosis(base_sigma, base_ratio, _raw_sigma(prep, eng.r, eng.dof), eng.sigma, effects_out, located,
                     base_info, residuals_before=r_before, residuals_after=eng.r.copy(), prep=prep)


# ---------------------------------------------------------------------------------------------- plots
def plot_residuals(diag: Diagnosis, directory) -> list[str]:
    """PNG of the raw residuals (um) of every axis before and after the selected effects."""
    import os

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    prep = diag.prep
    os.makedirs(directory, exist_ok=True)
    n = len(prep.rec)
    paths = []
    for tag, rw in (("before", diag.residuals_before), ("after", diag.residuals_after)):
        if prep.weighted:  # whitened: every component has unit variance at the tracker's specification
            raw, ylab, labels = rw.reshape(n, 3), "whitened", ("w1", "w2", "w3")
        else:
            raw, ylab, labels = rw.reshape(n, 3) * 1e3, "residual, um", ("x", "y", "z")
        fig, axs = plt.subplots(len(prep.axes), 1, figsize=(9, 2.2 * len(prep.axes)), squeeze=False)
        for ax, a in zip(axs[:, 0], prep.axes):
            idx = np.flatnonzero(prep.rec.axis == a)
            idx = idx[np.argsort(prep.order[idx])]
            for k, c in enumerate(labels):
                ax.plot(np.arange(len(idx)), raw[idx, k], ".", ms=2, label=c)
            ax.set_ylabel(f"{a} {ylab}")
            ax.legend(loc="upper right", fontsize=7, ncol=3)
        axs[-1, 0].set_xlabel("reading (time order within the axis)")
        fig.suptitle(f"residuals {tag} the diagnosed effects ({prep.rec.source})")
        fig.tight_layout()
        p = os.path.join(str(directory), f"residuals_{tag}.png")
        fig.savefig(p, dpi=110)
        plt.close(fig)
        paths.append(p)
    return paths


# ---------------------------------------------------------------------------------------------- plate
PLATE_NAMES = {"gamma": "scale", "alpha": "squareness", "ex": "offset", "ey": "offset", "beta": "rotation"}


def diagnose_plate(fit, leave_out: Sequence[str] = (), level: float = 0.01) -> dict:
    """Diagnosis of a plate fit (mtcal.plate.PlateFit) in the form of ``mtcal diagnose``.

    Base model: the plate fit's design (``fit.design`` (N, m, p): the generated first-order design of
    derive/plate.py, or the Jacobian of the exact residual) without the columns named in ``leave_out``; the
    observations are rebuilt from the fit (residuals + design @ values).  Candidates: every parameter the fit
    held at zero (e.g. gamma with ``scale=False``, Reeve's model without the scale term) or left out here, with
    its generated column (alpha: squareness, gamma: scale, ex/ey: offset), and one outlier per plate point (its
    m observation rows).  Lengths in the plate's unit, angles in rad.
    """
    from mtcal.generated import plate_numpy as PG
    from mtcal.plate import NOMINAL_TURN

    J = np.asarray(fit.design, dtype=float)
    if getattr(fit, "method", "first_order") == "exact":
        J = -J  # the exact fit's design is d residual / d params = -d prediction / d params
    N, m, p = J.shape
    y = (np.asarray(fit.residuals) + np.einsum("nmp,p->nm", J, np.asarray(fit.values))).reshape(-1)
    names = list(fit.names)
    unknown = [c for c in leave_out if c not in names]
    if unknown:
        raise InputError(f"plate diagnosis: unknown parameter(s) {unknown}; fitted: {names}")
    base_cols = [i for i, n in enumerate(names) if n not in leave_out]
    X = J.reshape(-1, p)
    eng = Engine([(np.arange(len(y)), X[:, base_cols])], y)
    base_sigma = eng.sigma
    cands = []
    for nme in leave_out:
        i = names.index(nme)
        cands.append((PLATE_NAMES.get(nme, nme), nme, X[:, [i]]))
    # parameters the fit held at zero: their generated first-order columns
    gen = ("alpha", "beta", "gamma", "ex", "ey")
    data = fit.data
    kk = len(data.positions)
    if m == 2 * (kk - 1):
        D = np.zeros((N, m, 5))
        per_pos = []
        for k in range(1, kk):
            d = PG.design_first_order(data.positions[k], NOMINAL_TURN[k])
            D[:, 2 * (k - 1):2 * k, :] += d
            per_pos.append(d)
        for g, nme in enumerate(gen):
            if nme in names or nme == "beta" or any(n.startswith(nme) and n != nme for n in names if n != "beta"):
                continue
            if nme in ("ex", "ey"):
                if "ex" in names or "ex2" in names:
                    continue
                G = np.zeros((N * m, kk - 1))
                for k in range(kk - 1):
                    blk = np.zeros((N, m))
                    blk[:, 2 * k:2 * k + 2] = per_pos[k][:, :, g]
                    G[:, k] = blk.reshape(-1)
                cands.append(("offset", nme, G))
            else:
                cands.append((PLATE_NAMES[nme], nme, D[:, :, g].reshape(-1, 1)))
    for k in range(N):
        G = np.zeros((N * m, m))
        G[k * m:(k + 1) * m] = np.eye(m)
        cands.append(("outlier", str(fit.data.ids[k]), G))
    effects, selected = [], []
    remaining = list(cands)
    while remaining:
        scored = [(c, eng.score(c[2])) for c in remaining]
        scored = [(c, s) for c, s in scored if s["separable"]]
        if not scored:
            break
        fams = {}
        for c, s in scored:
            fams.setdefault(c[0] if c[0] == "outlier" else c[1], []).append((c, s))
        best = None
        for fam, mem in fams.items():
            c, s = min(mem, key=lambda cs: cs[1]["logp"])
            lp = s["logp"] + math.log(len(mem) * len(fams))
            if best is None or lp < best[2]:
                best = (c, s, lp)
        c, s, lp = best
        if lp >= math.log(level) or s["k"] >= eng.dof:
            effects.append({"name": c[0], "axis": None, "direction": None, "significant": False, "estimate": None,
                            "sigma_after": None, "where": c[1],
                            "evidence": {"test": "F", "F": s["F"], "p_value": math.exp(s["logp"]),
                                         "p_adjusted": min(1.0, math.exp(lp)), "cv_gain": None}})
            break
        eng.add(c[2])
        selected.append((c, s, lp, eng.sigma))
        remaining = [x for x in remaining if x is not c]
    if selected:
        th, cov = eng.estimate([c[2] for c, _, _, _ in selected])
    out, off = [], 0
    for c, s, lp, sig in selected:
        k = c[2].shape[1]
        est = th[off:off + k]
        u = np.sqrt(np.maximum(np.diag(cov[off:off + k, off:off + k]), 0.0))
        off += k
        out.append({"name": c[0], "axis": None, "direction": None, "significant": True,
                    "estimate": float(est[0]) if k == 1 else float(np.linalg.norm(est)),
                    "uncertainty": float(u[0]) if k == 1 else float(np.linalg.norm(u)),
                    "parameter": c[1], "sigma_after": sig,
                    "evidence": {"test": "F", "F": s["F"], "dof": [s["k"], eng.dof],
                                 "p_value": math.exp(s["logp"]), "p_adjusted": min(1.0, math.exp(lp)),
                                 "cv_gain": None, "multiplicity": "Bonferroni over families x members"},
                    **({"vector": [float(v) for v in est]} if k > 1 else {})})
    located = [{"axis": None, "by": "point", "where": f.get("point"), "score": float(f.get("F", 0.0)),
                "p_adjusted": f.get("p_bonferroni")} for f in getattr(fit, "flagged", [])]
    held = [c[1] for c in cands if c[0] != "outlier" and c[1] not in leave_out]
    return {"base_sigma": base_sigma, "left_out": list(leave_out) + held, "effects": out + effects,
            "located": located,
            "sigma_after": eng.sigma, "units": {"length": "plate input unit", "angle": "rad", "gamma": "1"}}


def format_plate_diagnosis(d: dict) -> str:
    """Text lines of a plate diagnosis (lengths in the plate's unit)."""
    lines = [f"diagnosis: sigma {d['base_sigma']:.4g} -> {d['sigma_after']:.4g} (input unit); held at zero / "
             f"left out: {', '.join(d['left_out']) or 'none'}"]
    sig = [e for e in d["effects"] if e["significant"]]
    for e in sig:
        lines.append(f"  {e['name']} ({e.get('parameter')}): {e['estimate']:.4g} +- {e['uncertainty']:.2g}, "
                     f"F = {e['evidence']['F']:.1f}, p_adj = {e['evidence']['p_adjusted']:.2g}, "
                     f"sigma after {e['sigma_after']:.4g}")
    if not sig:
        lines.append("  nothing left out at this level")
    return "\n".join(lines)
