"""Preparation of a recording for the diagnosis: nominal positions, point Jacobians, reading sequences, weights.

Frames and units: machine frame (= tracker frame after alignment), mm; positions mm (linear) or deg (rotary).
The nominal position of every reflector reading uses the point's position estimated from the reference readings
(design.md: each round's reading at the position closest to zero); y = reading - nominal (incl. a given model).
The weights (whitening W, W^T W = covariance^-1) come from mtcal.diagnose.noise.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mtcal.diagnose import effects as fx
from mtcal.diagnose.noise import NoiseModel, noise_model
from mtcal.errors import InputError
from mtcal.machine import DEFAULT_MACHINE, Machine, load_machine
from mtcal.recordings import Recording


@dataclass
class Prepared:
    rec: Recording
    machine: Machine
    geometry: fx.Geometry
    y: np.ndarray            # (n, 3) readings minus nominal (incl. the given model), mm
    axes: list[str]
    q_ref: dict[str, float]
    seq: np.ndarray          # (n,) index of the (axis, round, point) sequence of each reading
    seq_keys: list[tuple]    # (axis, round, point) per sequence
    order: np.ndarray        # (n,) reading order within the recording (time, else file line)
    given_model: bool
    Aoff: np.ndarray         # (n, 3, 3) d nominal / d point position (rigid motion of the reflector)
    noise: NoiseModel        # the weights: W (n, 3, 3), W^T W = covariance^-1 (1/mm), and how they were obtained

    @property
    def W(self) -> np.ndarray:
        return self.noise.W

    @property
    def weighted(self) -> bool:
        return self.noise.weighted


def _affine(m: Machine, side: str, axes: np.ndarray, errors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """b (n, 3), A (n, 3, 3) of the exact affine point map p -> m.points(side, axes, p, errors) (the rigid
    motion of a reflector on that side, with the errors)."""
    n = len(axes)
    b = m.points(side, axes, np.zeros((n, 3)), errors)
    A = np.stack([m.points(side, axes, np.broadcast_to(e, (n, 3)), errors) - b for e in np.eye(3)], axis=-1)
    return b, A


def prepare(rec: Recording, machine: Machine | str = DEFAULT_MACHINE, model=None, tracker=None,
            max_degree: int = 3) -> Prepared:
    """Nominal positions, point Jacobians and weights of every reading (see module docstring); ``tracker`` (3,)
    mm or None (then the noise model is estimated from the scatter of the repeated rounds, mtcal.diagnose.noise,
    with the base family at ``max_degree``)."""
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
    g = fx.Geometry(rec.axis, rec.point, rec.position, rec.direction, rec.time_s, side, rec.xyz, J, m, t,
                    rotation=Aoff, temperature_c=rec.temperature_c)
    prep = Prepared(rec, m, g, y, axes, q_ref, seq, seq_keys, rank, model is not None, Aoff,
                    NoiseModel.isotropic(n))
    prep.noise = noise_model(prep, t, max_degree)
    if t is None and prep.noise.tracker is not None:
        prep.geometry.tracker = np.asarray(prep.noise.tracker, dtype=float)
    return prep

