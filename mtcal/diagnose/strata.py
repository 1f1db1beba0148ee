"""The error terms of the diagnosis' tests from the data's own strata (issue 52 item 2): the replicates' variance
components -- what the readings of a stop share over the rounds, and each reading's own scatter -- estimated on a
fit's residual (``pure_error``), and the F test of added columns against them (``against``), so that a member and
its place's free form are tested against one error term on the same degrees of freedom; ``lack_of_fit`` is the
classical lack-of-fit test built on both.  Functions of an :class:`mtcal.diagnose.engine.Engine` (its fit)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mtcal import _tails
from mtcal.diagnose.engine import Engine, Score


@dataclass(frozen=True)
class PureError:
    """The error term of replicates (strata.pure_error), as two variance components in whitened coordinates: ``B``
    (3 x 3) what the readings of one unit share (a stop landing off in one round), ``E`` (3 x 3) each reading's own
    scatter about its unit (zero where every unit is one reading); ``S`` = B + E / m the covariance of a unit's
    mean of m readings about its cell's, ``df`` the pure error's degrees of freedom (the units' columns less the
    cells'), ``nu`` and ``nu_e`` those of S's and E's estimates (units less cells; readings less units),
    ``units`` the replicates' rows of the whitened vector, ``outside`` the fit's residual variance (rows outside the
    units)."""

    B: np.ndarray
    E: np.ndarray
    S: np.ndarray
    df: int
    nu: int
    nu_e: int
    units: list
    outside: float


def lack_of_fit(eng: Engine, G: np.ndarray, units: list[tuple[np.ndarray, np.ndarray]],
                cells: list[tuple[np.ndarray, np.ndarray]], nests: np.ndarray | None = None) -> Score | None:
    """The lack-of-fit F test of the columns G (N, k) beside this fit, against the pure error of replicates:
    ``against(eng, G, pure_error(e, units, cells, nests))`` with ``e`` this fit and G (the error pure of both).
    Null: the fit is adequate, G adds no mean; alternative: G adds one; error term: PureError
    (strata.pure_error); the multiplicity is the caller's.  None where the units leave no pure error or G is
    not separable."""
    with_g = eng.copy()
    with_g.add(G)
    err = pure_error(with_g, units, cells, nests)
    return None if err is None else against(eng, G, err)

def pure_error(eng: Engine, units: list[tuple[np.ndarray, np.ndarray]], cells: list[tuple[np.ndarray, np.ndarray]],
               nests: np.ndarray | None = None) -> PureError | None:
    """The error term of replicates, from this fit's residual: pure of every column fitted (the caller fits
    what the error must not hold -- the columns under test, the selected effects in time).

    ``units`` and ``cells`` (as score_blocks: disjoint rows of the whitened vector, three per reading, and an
    orthonormal basis of each one's mean; mtcal.diagnose.places.replicate_strata): the replicates -- a stop in
    one round, or one reading -- and the cells they repeat (over the rounds).  SS_pe = what the units' means
    explain beyond the cells' on df_pe = their columns' difference; S, the 3 x 3 covariance of a unit's mean
    about its cell's (pooled over the cells on nu = units less cells), is scaled so that tr(S) = 3 SS_pe /
    (df_pe m), m the readings a unit holds on average (the mean of m readings varies 1/m of what their sum's
    projection explains): where the weights' law is off in shape (along against across the beam, an axis
    repeating worse along its motion), S says so.  The variance components by the method of moments (balanced
    nesting, the ANOVA estimator REML equals there): E, the readings' own scatter -- with ``nests`` (n,) codes
    of each reading's nest, their round x nest interaction within the cells (pure of every nest's mean at
    every cell), else their scatter about their unit's mean -- and B = S - E / m, its negative directions set
    to zero.  None where the units leave no pure error."""
    u_sc, c_sc = eng.score_blocks(units), eng.score_blocks(cells)
    df_pe = (u_sc.k if u_sc.separable else 0) - (c_sc.k if c_sc.separable else 0)
    ss_pe = (u_sc.delta if u_sc.separable else 0.0) - (c_sc.delta if c_sc.separable else 0.0)
    pooled = _pooled_scatter(eng.r, units, cells)
    if df_pe < 1 or ss_pe <= 0 or pooled is None:
        return None
    S, nu = pooled
    m = sum(len(rows) for rows, _ in units) / (3 * len(units))  # readings per unit, on average
    S *= 3.0 * (ss_pe / df_pe) / (m * np.trace(S))  # a unit's mean of m readings scatters 1/m of their sum
    E, nu_e = _within_scatter(eng.r, units, cells, nests)
    lam, V = np.linalg.eigh(S - E / m)
    B = (V * np.maximum(lam, 0.0)) @ V.T
    return PureError(B, E, S, df_pe, nu, nu_e, [rows for rows, _ in units], eng.rss / max(eng.dof, 1))

def against(eng: Engine, G: np.ndarray, err: PureError) -> Score | None:
    """The F test of adding the columns G (N, k) to this fit against the error term ``err`` (pure_error,
    estimated once on the fullest model of a place, so that a member and its place's free form beside it are
    tested against the same error on the same degrees of freedom).

    Null: G adds no mean to this fit; alternative: it adds one.  With u_i the rows of reading i of an
    orthonormal basis of G beside the fit (3 x k) and u = sum of u_i over a unit, the null expectation of what G
    explains is tr(M), M = sum over units of u^T B u + sum over readings of u_i^T E u_i (err.outside, the fit's
    residual variance, on rows outside the units): a contrast between units is set against what a unit's
    readings share, a contrast within them against each reading's own scatter.  F = delta_G / tr(M) is
    referred to F(h, d): Satterthwaite's h = tr(M)^2 / tr(M^2), and d the degrees of freedom of tr(M)'s
    estimate (Satterthwaite over S's and E's, each tr(X C) varying 2 tr(X C X C) / nu; no more than theirs):
    the scatter along one coordinate is estimated from nu units, not 3 nu.  With B = s^2 I, E = 0 and units of
    one reading this is the classical lack-of-fit test (delta_G / k) / (SS_pe / df_pe).  The multiplicity is
    the caller's.  None where G is not separable."""
    own = eng.score(G)
    if not own.separable:
        return None
    U = eng.residualized(G)
    inside = np.zeros(eng.N, bool)
    M = np.zeros((U.shape[1], U.shape[1]))
    Au, Ae = np.zeros((3, 3)), np.zeros((3, 3))  # tr(M) = tr(Au S) + tr(Ae E)
    for rows in err.units:
        inside[rows] = True
        ui = U[rows].reshape(-1, 3, U.shape[1])
        u = ui.sum(axis=0)
        M += u.T @ err.B @ u + np.einsum("mik,ij,mjl->kl", ui, err.E, ui)
        Au += u @ u.T
        Ae += np.einsum("mik,mjk->ij", ui, ui) - u @ u.T / len(ui)
    M += err.outside * (U[~inside].T @ U[~inside])
    c, c2 = float(np.trace(M)), float(np.sum(M * M))
    XS, XE = Au @ err.S, Ae @ err.E
    var = np.sum(XS * XS.T) / err.nu + (np.sum(XE * XE.T) / err.nu_e if err.nu_e else 0.0)
    d = min(float(err.df + 3 * err.nu_e), (float(np.trace(XS + XE))) ** 2 / max(float(var), 1e-300))
    F = own.delta / c
    logp = float(_tails.f_logsf(F, c * c / c2, d))
    if not math.isfinite(logp):
        logp = -0.5 * c * c / c2 * F
    return Score(True, own.sep, own.k, int(round(d)), own.delta, F, logp)


def _pooled_scatter(r: np.ndarray, units: list[tuple[np.ndarray, np.ndarray]],
                    cells: list[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, int] | None:
    """The 3 x 3 covariance of the units' means of the whitened residual ``r`` (three rows per reading, averaged
    over a unit's readings) about their cells' means, pooled over the cells, and its degrees of freedom (units less
    cells); None where no cell holds two units."""
    cell_of = {}
    for k, (rows, _) in enumerate(cells):
        for i in rows[::3] // 3:
            cell_of[int(i)] = k
    means: dict[int, list[np.ndarray]] = {}
    for rows, _ in units:
        means.setdefault(cell_of[int(rows[0] // 3)], []).append(r[rows].reshape(-1, 3).mean(axis=0))
    S, df = np.zeros((3, 3)), 0
    for m in means.values():
        if len(m) > 1:
            d = np.array(m) - np.mean(m, axis=0)
            S += d.T @ d
            df += len(m) - 1
    return (S / df, df) if df and np.trace(S) > 0 else None


def _within_scatter(r: np.ndarray, units: list[tuple[np.ndarray, np.ndarray]],
                    cells: list[tuple[np.ndarray, np.ndarray]], nests: np.ndarray | None
                    ) -> tuple[np.ndarray, int]:
    """The 3 x 3 covariance of a reading's own scatter in the whitened residual ``r`` (three rows per reading) and
    its degrees of freedom: with ``nests`` (a code per reading), the round x nest interaction of the units' nest
    means within each cell (the nests every unit of the cell reads), (J - 1)(K - 1) degrees of freedom for J units
    of K nests; else the readings about their unit's mean (readings less units).  Zero where there is none."""
    E, df = np.zeros((3, 3)), 0
    if nests is not None:
        cell_of = {int(i): k for k, (rows, _) in enumerate(cells) for i in rows[::3] // 3}
        by_cell: dict[int, list[dict[int, np.ndarray]]] = {}
        for rows, _ in units:
            reads = rows[::3] // 3
            x = r[rows].reshape(-1, 3)
            means = {int(n): x[nests[reads] == n].mean(axis=0) for n in np.unique(nests[reads])}
            by_cell.setdefault(cell_of[int(reads[0])], []).append(means)
        for ms in by_cell.values():
            common = sorted(set.intersection(*(set(m) for m in ms)))
            if len(ms) < 2 or len(common) < 2:
                continue
            X = np.array([[m[n] for n in common] for m in ms])  # (J, K, 3)
            D = X - X.mean(axis=0) - X.mean(axis=1, keepdims=True) + X.mean(axis=(0, 1))
            E += np.einsum("jki,jkl->il", D, D)
            df += (len(ms) - 1) * (len(common) - 1)
        return (E / df if df else E), df
    for rows, _ in units:
        x = r[rows].reshape(-1, 3)
        if len(x) > 1:
            d = x - x.mean(axis=0)
            E += d.T @ d
            df += len(x) - 1
    return (E / df if df else E), df
