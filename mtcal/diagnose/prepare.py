"""Preparation of a recording for the diagnosis: nominal reflector positions (reflectors estimated from all
readings), point Jacobians, the given model's simulation and the tracker weights (see mtcal.diagnose)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mtcal.diagnose import candidates as fx
from mtcal.errors import InputError
from mtcal.machine import DEFAULT_MACHINE, Machine, load_machine
from mtcal.recordings import Recording
from mtcal.tracker import covariance


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

    def white(self, c: fx.Candidate) -> np.ndarray:
        """The candidate's columns whitened by this recording's weights (computed once per candidate)."""
        if "_w" not in c.extra:
            c.extra["_w"] = whiten(self.W, c.G)
        return c.extra["_w"]


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


def whiten(W: np.ndarray, v: np.ndarray) -> np.ndarray:
    """(n, 3) -> (3n,), or (n, 3, k) -> (3n, k)."""
    if v.ndim == 2:
        return np.einsum("nij,nj->ni", W, v).reshape(-1)
    return np.einsum("nij,njk->nik", W, v).reshape(-1, v.shape[-1])
