"""The statistics engine of the diagnosis: least squares on a block-diagonal base, shared base columns and added
global columns.

The base is one block of columns per axis (rows of that axis only) plus shared columns spanning several blocks
(the reflector positions shared by axes measured from the same machine pose, mtcal.diagnose.design); the shared
columns are orthonormalised after the blocks' projection, so the base's basis stays orthonormal without normal
equations.  Candidate columns are scored by projection (Frisch-Waugh-Lovell): the F test of adding columns G
(whitened, N x k) to the fitted base, with the separability of G from the base (sin of the smallest principal
angle).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mtcal import _tails

ALIAS_TOL = 1e-4       # sin of the smallest angle between a candidate and the base below this: not separable
WEAK_TOL = 0.05        # ... below this: separable only weakly (estimate strongly correlated with the base)
ZERO_COLUMN = 1e-12   # a column this much smaller (norm) than its block's largest is rounding, not a column (scaled
#                      to unit norm it is noise, and the SVD of such a block can fail to converge)


@dataclass(frozen=True)
class Score:
    """F test of added columns: ``delta`` = RSS reduction (whitened), ``k`` = separable columns, ``dof`` = residual
    degrees of freedom with them, ``logp`` = natural log of the p value, ``sep`` = separability (0..1)."""

    separable: bool
    sep: float
    k: int = 0
    dof: int = 1
    delta: float = 0.0
    F: float = 0.0
    logp: float = 0.0


class Engine:
    """Least squares on a block-diagonal base (one block of rows per axis), shared base columns across blocks, plus
    added global columns.

    Keeps an orthonormal basis of the fitted columns (per block; ``S`` for the shared base columns, orthogonal to
    the blocks; ``E`` for columns added later, orthogonal to both) and the residual; scores candidate columns by
    projection (Frisch-Waugh-Lovell), never forming normal equations of the base.  The base (``copy_base``) is the
    blocks and ``S``."""

    def __init__(self, blocks: list[tuple[np.ndarray, np.ndarray]], y: np.ndarray,
                 shared: np.ndarray | None = None):
        self.N = len(y)
        self.y = y
        self.blocks = [(idx, self._orth(X)) for idx, X in blocks]
        self.E = np.zeros((self.N, 0))
        self.S = np.zeros((self.N, 0))
        if shared is not None and shared.shape[1]:
            self.S = self._shared_basis(shared)
        self.r = y - self.project(y[:, None])[:, 0]
        self.p = sum(q.shape[1] for _, q in self.blocks) + self.S.shape[1]

    def _shared_basis(self, G: np.ndarray) -> np.ndarray:
        """Orthonormal basis of the shared columns G (N, k) after the blocks' projection (columns scaled to unit
        norm first; directions inside the blocks' span are dropped)."""
        scale = np.linalg.norm(G, axis=0)
        G = G[:, scale > 0] / scale[scale > 0]
        Gp = G - self.project(G)
        Gp = Gp - self.project(Gp)
        if Gp.shape[1] == 0:
            return np.zeros((self.N, 0))
        u, sv, _ = np.linalg.svd(Gp, full_matrices=False)
        return u[:, sv > 1e-9 * math.sqrt(G.shape[1])]

    @staticmethod
    def _orth(G: np.ndarray) -> np.ndarray:
        if G.shape[1] == 0:
            return np.zeros((G.shape[0], 0))
        scale = np.linalg.norm(G, axis=0)
        live = scale > ZERO_COLUMN * scale.max()
        G = G[:, live] / scale[live]
        if G.shape[1] == 0:
            return np.zeros((G.shape[0], 0))
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
        parts += [self.S.T @ G, self.E.T @ G]
        return np.vstack(parts)

    def project(self, G: np.ndarray) -> np.ndarray:
        """Q Q^T G (N, k)."""
        out = self.S @ (self.S.T @ G) + self.E @ (self.E.T @ G)
        for idx, q in self.blocks:
            out[idx] += q @ (q.T @ G[idx])
        return out

    def rows(self) -> np.ndarray:
        """Per reading, its three rows of Q padded to a common width (n, 3, P): the blocks share the first columns,
        then S and E; enough for leverages and for sums over readings of one axis (the blocks have disjoint rows)."""
        pmax = max([q.shape[1] for _, q in self.blocks] + [0])
        out = np.zeros((self.N, pmax))
        for idx, q in self.blocks:
            out[idx, :q.shape[1]] = q
        out = np.hstack([out, self.S, self.E])
        return out.reshape(self.N // 3, 3, -1)

    def full_rows(self) -> np.ndarray:
        """Per reading, its three rows of the full Q (every block at its own columns, then S and E): (n, 3, P)."""
        widths = [q.shape[1] for _, q in self.blocks]
        Qf = np.zeros((self.N, sum(widths)))
        off = 0
        for (idx, q), w in zip(self.blocks, widths):
            Qf[idx, off:off + w] = q
            off += w
        Qf = np.hstack([Qf, self.S, self.E])
        return Qf.reshape(self.N // 3, 3, -1)

    @property
    def rss(self) -> float:
        return float(self.r @ self.r)

    @property
    def dof(self) -> int:
        return self.N - self.p

    @property
    def sigma(self) -> float:
        return math.sqrt(self.rss / max(self.dof, 1))

    def residualized(self, G: np.ndarray) -> np.ndarray:
        """An orthonormal basis (N, k) of G with the fitted columns projected out (empty if G is in the base)."""
        Gp = G - self.project(G)
        Gp = Gp - self.project(Gp)
        if not np.any(Gp):
            return np.zeros((self.N, 0))
        ref = max(float(np.linalg.norm(G)), 1e-300)
        u, sv, _ = np.linalg.svd(Gp, full_matrices=False)
        return u[:, sv > ALIAS_TOL * ref]

    def overlap(self, G1: np.ndarray, G2: np.ndarray) -> float:
        """|cos| of the smallest principal angle between two column spaces after the fitted base (0..1): near 1,
        the data cannot tell the two apart."""
        a, b = self.residualized(G1), self.residualized(G2)
        if a.shape[1] == 0 or b.shape[1] == 0:
            return 0.0
        return float(min(1.0, np.linalg.svd(a.T @ b, compute_uv=False)[0]))

    def shared_fit(self, G1: np.ndarray, G2: np.ndarray) -> float:
        """The share (0..1, a |cos|) of what G1 explains of the current residual that G2 explains as well: near 1,
        this campaign cannot tell the two explanations apart."""
        a, b = self.residualized(G1), self.residualized(G2)
        fit = a @ (a.T @ self.r)
        size = float(np.linalg.norm(fit))
        if a.shape[1] == 0 or b.shape[1] == 0 or size == 0:
            return 0.0
        return float(min(1.0, np.linalg.norm(b.T @ fit) / size))

    def score(self, G: np.ndarray) -> Score:
        """F test of adding the columns G (N, k) to the fit; separability = sin of the smallest angle to the base."""
        GtG = G.T @ G
        lam, V = np.linalg.eigh(GtG)
        if lam[-1] <= 0:
            return Score(False, 0.0)
        keep = lam > 1e-12 * lam[-1]
        T = V[:, keep] / np.sqrt(lam[keep])
        QtG = self.qt(G) @ T
        M = np.eye(T.shape[1]) - QtG.T @ QtG
        mu, U = np.linalg.eigh(M)
        sep = math.sqrt(max(mu[0], 0.0))
        ok = mu > ALIAS_TOL**2
        if not ok.any():
            return Score(False, sep)
        b = U[:, ok].T @ (T.T @ (G.T @ self.r))
        return self._f_test(float(np.sum(b**2 / mu[ok])), int(ok.sum()), sep)

    def score_blocks(self, blocks: list[tuple[np.ndarray, np.ndarray]]) -> Score:
        """score of columns that live on disjoint blocks of rows, without forming them as one matrix: ``blocks``
        holds, per block, its rows (of the whitened vector) and an orthonormal basis (rows, k_b) of its columns
        (every stop moving on its own as a step moves it: a thousand columns on a robot's recording).  With H the
        block-diagonal basis and B = Q^T H, the columns after the fit have the Gram I - B^T B, and what they explain
        of the residual is h^T (I - B^T B)^+ h, h = H^T r; directions of H within ALIAS_TOL of the fit are
        dropped."""
        Q = self.full_rows().reshape(self.N, -1)
        B = np.hstack([Q[rows].T @ H for rows, H in blocks])
        h = np.concatenate([H.T @ self.r[rows] for rows, H in blocks])
        _, sv, Vt = np.linalg.svd(B, full_matrices=False)
        a = Vt @ h
        mu = 1.0 - sv**2  # the Gram's eigenvalues along V; 1 on the rest of H's span
        ok = mu > ALIAS_TOL**2
        k = len(h) - int((~ok).sum())
        if k == 0:
            return Score(False, 0.0)
        delta = float(h @ h - a @ a + np.sum(a[ok] ** 2 / mu[ok]))
        return self._f_test(delta, k, math.sqrt(max(float(mu.min(initial=1.0)), 0.0)))

    def score_beside_blocks(self, G: np.ndarray, blocks: list[tuple[np.ndarray, np.ndarray]]) -> Score:
        """F test of adding the columns G (N, k) to the fit with the block columns ``blocks`` (as score_blocks:
        disjoint rows, an orthonormal basis each) fitted beside them, without forming the blocks as one matrix
        (Frisch-Waugh: the residual, the fit's basis and G with each block's span projected out, the blocks'
        columns counted in the degrees of freedom)."""
        def off(X: np.ndarray) -> np.ndarray:
            X = X.copy()
            for rows, H in blocks:
                X[rows] -= H @ (H.T @ X[rows])
            return X

        e = Engine([(np.arange(self.N), off(self.full_rows().reshape(self.N, -1)))], off(self.r[:, None])[:, 0])
        e.p += sum(H.shape[1] for _, H in blocks)
        return e.score(off(G))

    def _f_test(self, delta: float, k: int, sep: float) -> Score:
        """The F test of ``k`` added columns that explain ``delta`` of the residual sum of squares."""
        dof = max(self.dof - k, 1)
        rss1 = max(self.rss - delta, 1e-300)
        F = (delta / k) / (rss1 / dof)
        logp = float(_tails.f_logsf(F, k, dof))
        if not math.isfinite(logp):  # beyond the float range: the chi^2 tail exponent keeps the order finite
            logp = -0.5 * k * F
        return Score(True, sep, k, dof, delta, F, logp)

    def add(self, G: np.ndarray) -> None:
        Gp = G - self.project(G)
        Gp = Gp - self.project(Gp)
        q = self._orth(Gp)
        self.E = np.hstack([self.E, q])
        self.r = self.r - q @ (q.T @ self.r)
        self.p += q.shape[1]

    def copy_base(self) -> "Engine":
        """The base alone (blocks and shared columns), without the added columns."""
        e = Engine.__new__(Engine)
        e.N, e.y, e.blocks, e.S, e.E = self.N, self.y, self.blocks, self.S, np.zeros((self.N, 0))
        e.r = self.y - e.project(self.y[:, None])[:, 0]
        e.p = sum(q.shape[1] for _, q in self.blocks) + self.S.shape[1]
        return e

    def copy(self) -> "Engine":
        """This fit (base and added columns), to add to without changing this one."""
        e = self.copy_base()
        e.E, e.r, e.p = self.E.copy(), self.r.copy(), self.p
        return e

    def estimate(self, Gs: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """Joint estimate and covariance of the columns Gs given the base, blocks and shared columns
        (Frisch-Waugh-Lovell); sigma from this engine's residual."""
        G = np.hstack(Gs)
        base = self.copy_base()
        Gp = G - base.project(G)
        theta, *_ = np.linalg.lstsq(Gp, base.r, rcond=None)
        cov = self.sigma**2 * np.linalg.pinv(Gp.T @ Gp)
        return theta, cov
