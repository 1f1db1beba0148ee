"""The base design of the diagnosis: smooth error functions of each axis and the reflector positions, whitened.

Per axis J: columns J_point[:, e] * basis_k(q) for the six error motions e of J (polynomials in (q - q_ref) for
linear axes, harmonics cos k q - cos k q_ref, sin k q - sin k q_ref for rotary axes; mm per unit parameter),
and three columns per reflector (its position, estimated from every reading of every round).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Sequence

import numpy as np

from mtcal.diagnose.engine import Engine
if TYPE_CHECKING:
    from mtcal.diagnose.prepare import Prepared


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


def engine_for(prep: Prepared, base: Base, wy: np.ndarray, rows: np.ndarray | None = None) -> Engine:
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


def raw_sigma(prep: Prepared, r_w: np.ndarray, dof: int) -> float:
    """Standard deviation (mm) of the unwhitened residuals of the whitened residual vector ``r_w`` (3n,)."""
    n = len(prep.rec)
    raw = np.linalg.solve(prep.W, r_w.reshape(n, 3)[..., None])[..., 0]
    return math.sqrt(float(np.sum(raw**2)) / max(dof, 1))
