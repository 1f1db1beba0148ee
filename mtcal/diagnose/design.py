"""The base design of the diagnosis: smooth error functions of each axis and the reflector positions, whitened.

Per axis J: columns J_point[:, e] * basis_k(q) for the six error motions e of J (polynomials in (q - q_ref) for
linear axes, harmonics cos k q - cos k q_ref, sin k q - sin k q_ref for rotary axes; mm per unit parameter),
and three columns per reflector position (estimated from every reading of every round).  A reflector position
belongs to one (axis, reflector), or is shared by the axes measured from the same reference pose
(``Prepared.point_group``, mtcal.diagnose.prepare): a shared position's three columns span several axes and are
the base's shared columns (Engine ``shared``).  Each axis of a shared position keeps a free rigid motion of its
side (six columns, ``_parked_columns``): a parked axis sits in an error state that is not measured (a backlash or
a lateral play sits at the side of the last approach), and any error state moves the side rigidly; a knocked
tracker or a drift of the whole side between the axes is therefore still absorbed, but what moves one reflector
relative to the others (a creeping nest) is no longer absorbed per axis.

Several tracker stations (``Prepared.stations``): each station's readings are in the machine frame after its own
alignment, which leaves a small rigid error (docs/design.md).  The base carries it as six shared columns per station
(``_alignment_columns``: translation t, mm, and a small rotation w, rad, about the centroid of the station's
readings c, moving a reading x by t + w x (x - c)) for every station but the first: gauge, the first station's
alignment is the frame (the data tell only the alignments relative to each other, a common rigid motion being
the reflector positions and the machine frame; docs/design.md's "translations sum to zero" is the same fit, the
estimates shifted by their mean).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from mtcal.diagnose.engine import Engine
from mtcal.diagnose.prepared import Prepared

ROTARY_HARMONICS = 6  # rotary axes: harmonics up to 6 per turn; a higher one is a periodic error (a candidate)


def family_degrees(prep: Prepared, max_degree: int) -> dict[str, int]:
    """The quasi-static family's largest degree of every axis: polynomials up to ``max_degree`` on linear axes,
    harmonics up to min(``max_degree``, ROTARY_HARMONICS) on rotary axes; 0 (nothing fitted) on a given model."""
    if prep.given_model:
        return {a: 0 for a in prep.axes}
    return {a: max_degree if prep.geometry.linear(a) else min(max_degree, ROTARY_HARMONICS) for a in prep.axes}


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
    blocks: dict[str, np.ndarray]   # axis -> (n_axis, 3, p_axis) raw design of the axis' readings, mm per parameter
    degrees: dict[str, int]
    shared: np.ndarray              # (n, 3, s) raw design of the shared reflector positions (zero off their axes)
    #                                 and of the station alignments (several stations; module docstring)


def _position_columns(prep: Prepared, rows: np.ndarray, group: int) -> list[np.ndarray]:
    """Three (n_rows, 3) columns of one reflector position on the readings ``rows`` (bool (n,)): d nominal /
    d point = the rigid motion of the point (identity tool side, R(q) table side), zero off the position's
    readings."""
    m = prep.point_group[rows] == group
    cols = []
    for k in range(3):
        c = np.zeros((int(rows.sum()), 3))
        c[m] = prep.Aoff[rows][m][:, :, k]
        cols.append(c)
    return cols


def _parked_columns(prep: Prepared, rows: np.ndarray) -> list[np.ndarray]:
    """Six (n_rows, 3) columns of a rigid motion of the reflectors' side on the readings ``rows``: translation
    t (mm) and rotation w (rad, local frame) moving a point p by t + w x p.  It is the error state of an axis
    while parked (its reversal state after the last approach, unknown): whatever it is, it moves the side
    rigidly, so it is free per axis when the axis' reflector positions are shared."""
    A, p = prep.Aoff[rows], prep.local[rows]
    cols = [A[:, :, k] for k in range(3)]
    cols += [np.einsum("nij,nj->ni", A, np.cross(np.eye(3)[k], p)) for k in range(3)]
    return cols


def _alignment_columns(prep: Prepared, rows: np.ndarray) -> list[np.ndarray]:
    """Six (n, 3) columns per station but the first (module docstring), zero off the station's readings and off
    ``rows`` (bool (n,))."""
    g, cols = prep.geometry, []
    for label in prep.stations[1:]:
        on = g.station == label
        d = g.xyz - g.xyz[on].mean(axis=0)
        for c in [np.broadcast_to(e, d.shape) for e in np.eye(3)] + [np.cross(e, d) for e in np.eye(3)]:
            cols.append(np.where((on & rows)[:, None], c, 0.0))
    return cols


def base_design(prep: Prepared, degrees: dict[str, int], axes: Sequence[str] | None = None) -> Base:
    """Per axis: error-function columns J_point[:, e] * basis_k(q) and the columns of the reflector positions of
    that axis alone; shared: the reflector positions shared by several of ``axes`` and the station alignments
    (module docstring)."""
    g, rec = prep.geometry, prep.rec
    axes = list(axes or prep.axes)
    inside = np.isin(rec.axis, axes)
    groups = {k: set(rec.axis[inside & (prep.point_group == k)].tolist())
              for k in np.unique(prep.point_group[inside])}    # position -> the axes (of ``axes``) reading it
    blocks = {}
    for a in axes:
        on = rec.axis == a
        pos = rec.position[on]
        span = float(np.ptp(pos)) or 1.0
        B = _basis(prep.machine.kind(a) == "linear", rec.position[on], prep.q_ref[a], degrees.get(a, 0), span)
        cols = []
        for e in prep.machine.error_motions(a):
            c = g.col(e)[on]
            cols += [c * B[:, k:k + 1] for k in range(B.shape[1])]
        # reflector positions estimated from every reading of every round: no single reference reading is trusted
        tied = False
        for k in np.unique(prep.point_group[on]):
            if groups[k] == {a}:
                cols += _position_columns(prep, on, k)
            else:
                tied = True
        if tied:
            cols += _parked_columns(prep, on)
        blocks[a] = np.stack(cols, axis=-1) if cols else np.zeros((int(on.sum()), 3, 0))
    shared = [c for k, ax in groups.items() if len(ax) > 1 for c in _position_columns(prep, inside, k)]
    S = np.zeros((len(rec), 3, len(shared)))
    if shared:
        S[inside] = np.stack(shared, axis=-1)
    align = _alignment_columns(prep, inside)
    if align:
        S = np.concatenate([S, np.stack(align, axis=-1)], axis=-1)
    return Base(blocks, dict(degrees), S)


def whiten(W: np.ndarray, v: np.ndarray) -> np.ndarray:
    """(n, 3) -> (3n,), or (n, 3, k) -> (3n, k)."""
    if v.ndim == 2:
        return np.einsum("nij,nj->ni", W, v).reshape(-1)
    return np.einsum("nij,njk->nik", W, v).reshape(3 * len(v), v.shape[-1])


def engine_for(prep: Prepared, base: Base, wy: np.ndarray, rows: np.ndarray | None = None) -> Engine:
    """Engine of the base design (blocks per axis, shared columns), optionally on a subset of readings ``rows``
    (bool (n,))."""
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
    Sw = whiten(prep.W[keep], base.shared[keep])
    return Engine(blocks, wy[sel3], Sw[:, np.any(Sw != 0, axis=0)])


def raw_sigma(prep: Prepared, r_w: np.ndarray, dof: int) -> float:
    """Standard deviation (mm) of the unwhitened residuals of the whitened residual vector ``r_w`` (3n,)."""
    n = len(prep.rec)
    raw = np.linalg.solve(prep.W, r_w.reshape(n, 3)[..., None])[..., 0]
    return math.sqrt(float(np.sum(raw**2)) / max(dof, 1))
