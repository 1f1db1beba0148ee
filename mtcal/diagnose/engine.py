"""The base design (smooth error functions vanishing at the reference, reflector positions) and the least-squares
engine of the diagnosis: projections (Frisch-Waugh), F tests, separability (see mtcal.diagnose)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from scipy import stats

from mtcal.diagnose.prepare import Prepared, whiten

ALIAS_TOL = 1e-4       # sin of the smallest angle between a candidate and the base below this: not separable
WEAK_TOL = 0.05        # ... below this: separable only weakly (estimate strongly correlated with the base)


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
