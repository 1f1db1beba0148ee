"""Preparation of a recording for the diagnosis: nominal positions, point Jacobians, reading sequences, weights.

Frames and units: machine frame (= tracker frame after alignment), mm; positions mm (linear) or deg (rotary).
The nominal position of every reflector reading uses the point's position estimated from the reference readings
(docs/design.md: each round's reading at the position closest to zero); y = reading - nominal (incl. a given model).

Reflector positions tied across axes (``tie_positions``): every axis is measured with the other axes parked, and
the base's error functions vanish at each axis' reference position, so a reflector read at the same full machine
pose must read the same whichever axis is being measured.  The reference pose of axis J is its reference position
with the other axes at their pos_<AXIS> columns (Recording.other_positions) or zero, taken from J's reference
readings (no single pose if they disagree: J is not tied).  Axes whose reference poses coincide (every axis within
1e-9 mm or deg) and that carry their reflectors on the same side (tool or table) share one position per reflector
label (``point_group``); otherwise each (axis, reflector) has its own.  The nominal position of a shared reflector
uses the reference readings of all its axes.  A parked axis still sits in an error state that is not measured
(the side of its backlash it was last approached from): the base gives each tied axis a free rigid motion of its
side (mtcal.diagnose.design), so only what moves one reflector relative to the others is no longer absorbed.

Several tracker stations (docs/design.md; ``tracker`` a dict label -> tracker position): every reading is weighted
by the prior law's covariance (the AT960's unless ``tracker_model`` names another) about its own station's tracker,
and the tracker-dependent candidates are per station (``Geometry.station``, ``Geometry.trackers``); the base adds
every station's alignment (mtcal.diagnose.design).

The weights (whitening W, W^T W = covariance^-1) come from mtcal.diagnose.noise.
"""
from __future__ import annotations

import numpy as np

from mtcal.diagnose import effects as fx
from mtcal.diagnose.noise import NoiseModel, noise_model, stations_model
from mtcal.diagnose.prepared import Prepared
from mtcal.diagnose.scatter import LEVEL as SCATTER_LEVEL
from mtcal.diagnose.scatter import axis_scatter
from mtcal.errors import InputError
from mtcal.kinematics.machine import DEFAULT_MACHINE, Machine, load_machine
from mtcal.measurement.passes import first_readings, position_key, reference_position
from mtcal.measurement.recordings import Recording
from mtcal.measurement.tracker import AT960, TrackerSpec

TIE_POSITIONS = True   # default: reflector positions shared by axes measured from the same reference pose


def _affine(m: Machine, side: str, axes: np.ndarray, errors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """b (n, 3), A (n, 3, 3) of the exact affine point map p -> m.points(side, axes, p, errors) (the rigid
    motion of a reflector on that side, with the errors)."""
    n = len(axes)
    b = m.points(side, axes, np.zeros((n, 3)), errors)
    A = np.stack([m.points(side, axes, np.broadcast_to(e, (n, 3)), errors) - b for e in np.eye(3)], axis=-1)
    return b, A


def reference_pose(rec: Recording, m: Machine, axis: str, q_ref: float) -> np.ndarray | None:
    """The full machine pose (n_axes,) mm or deg of ``axis``' reference readings: its reference position, the
    other axes at their pos_<AXIS> columns or zero; None when its reference readings are not at one pose."""
    at = (rec.axis == axis) & (position_key(rec.position) == position_key(q_ref))  # as _reference_readings
    pose = np.zeros((int(at.sum()), len(m.axes)))
    for b, v in (rec.other_positions or {}).items():
        if b in m.axes and b != axis:
            pose[:, m.index(b)] = v[at]
    pose[:, m.index(axis)] = q_ref
    if len(pose) == 0 or np.ptp(pose, axis=0).max() > 1e-9:
        return None
    return pose[0]


def position_groups(rec: Recording, m: Machine, axes: list[str], q_ref: dict[str, float],
                    tie: bool) -> np.ndarray:
    """(n,) index of the reflector position of each reading: one per (axis, point), or with ``tie`` one per
    (side, point) among axes whose reference poses coincide (module docstring)."""
    classes: list[tuple[str, np.ndarray | None]] = []   # (side, pose) of each class of tied axes
    cls = {}
    for a in axes:
        pose = reference_pose(rec, m, a, q_ref[a]) if tie else None
        match = [i for i, (side, p) in enumerate(classes) if pose is not None and p is not None
                 and side == m.side(a) and np.max(np.abs(p - pose)) <= 1e-9]
        if not match:
            classes.append((m.side(a), pose))
        cls[a] = match[0] if match else len(classes) - 1
    keys = [(cls[a], str(p)) for a, p in zip(rec.axis.tolist(), rec.point.tolist())]
    index = {k: i for i, k in enumerate(dict.fromkeys(keys))}
    return np.array([index[k] for k in keys], dtype=int)


def shared_axes(prep: "Prepared") -> list[list[str]]:
    """The classes of axes sharing their reflector positions (two or more axes each, in the machine's order)."""
    rec, m = prep.rec, prep.machine
    classes = {tuple(sorted(set(rec.axis[prep.point_group == k].tolist()), key=m.index))
               for k in np.unique(prep.point_group)}
    return sorted([list(c) for c in classes if len(c) > 1], key=lambda c: m.index(c[0]))


def _reference_readings(rec: Recording, sel: np.ndarray, q_ref: float, rank: np.ndarray) -> np.ndarray:
    """Indices of the reference readings of the readings ``sel`` of one (axis, point): per round, the first reading
    at the reference position ``q_ref``."""
    first = first_readings(rec, sel, q_ref, rank, by=("round",))
    refs = []
    for r in sorted(set(rec.round[sel].tolist())):
        if (r,) not in first:
            rs = sel[rec.round[sel] == r]
            raise InputError(f"{rec.source}: axis {rec.axis[rs[0]]} round {r} point {rec.point[rs[0]]} has no "
                             f"reading at the reference position {q_ref:g}")
        refs.append(first[(r,)])
    return np.array(refs, dtype=int)


def axis_values(rec: Recording, m: Machine, axes: list[str]) -> np.ndarray:
    """(n, machine axes) mm or deg: every reading's measured axis at its position, the other axes at zero (the
    pose the diagnosis' Jacobians are taken at)."""
    av = np.zeros((len(rec), len(m.axes)))
    for a in axes:
        av[rec.axis == a, m.index(a)] = rec.position[rec.axis == a]
    return av


def prepare(rec: Recording, machine: Machine | str = DEFAULT_MACHINE, model=None, tracker=None,
            max_degree: int = 3, tie_positions: bool = TIE_POSITIONS, tracker_model: TrackerSpec = AT960,
            scatter_level: float = SCATTER_LEVEL) -> Prepared:
    """Nominal positions, point Jacobians and weights of every reading (see module docstring); ``tracker`` (3,)
    mm, a dict station label -> (3,) mm (several stations: the recording's station column labels the rows), or
    None (then the noise model is estimated from the scatter of the repeated rounds, mtcal.diagnose.noise, with
    the base family at ``max_degree``); ``tie_positions``: one reflector position shared by the axes measured
    from the same reference pose (module docstring), else one per (axis, reflector); ``tracker_model``: the prior
    noise law (mtcal.measurement.tracker, default the AT960's); ``scatter_level``: the family-wise level of the
    per-stop scatter test (mtcal.diagnose.scatter)."""
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
    av = axis_values(rec, m, axes)
    side = np.array([m.side(a) for a in rec.axis.tolist()])
    errors = model.errors_at(m, av, extrapolate="clamp") if model is not None else np.zeros((n, len(m.error_names)))

    local = np.zeros((n, 3))
    keys = list(zip(rec.axis.tolist(), rec.round.tolist(), rec.point.tolist()))
    seq_keys = sorted(set(keys), key=lambda k: (m.index(k[0]), k[1], k[2]))
    seq_index = {k: i for i, k in enumerate(seq_keys)}
    seq = np.array([seq_index[k] for k in keys])
    q_ref: dict[str, float] = {}
    for a in axes:
        q_ref[a] = reference_position(rec.position[rec.axis == a])
    group = position_groups(rec, m, axes, q_ref, tie_positions)
    for k in range(int(group.max()) + 1):
        sel = np.flatnonzero(group == k)
        refs = np.concatenate([_reference_readings(rec, sel[rec.axis[sel] == a], q_ref[a], rank)
                               for a in dict.fromkeys(rec.axis[sel].tolist())])
        b, A = _affine(m, side[sel[0]], av[refs], errors[refs])
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
    several = isinstance(tracker, dict)
    t = None if tracker is None or several else np.asarray(tracker, dtype=float).reshape(3)
    g = fx.Geometry(rec.axis, rec.point, rec.position, rec.direction, rec.time_s, side, nominal, J, m, t,
                    rotation=Aoff, temperature_c=rec.temperature_c)
    if several:
        g.station = rec.stations()
        g.trackers = {k: np.asarray(v, dtype=float).reshape(3) for k, v in tracker.items()}
    prep = Prepared(rec, m, g, y, axes, q_ref, seq, seq_keys, rank, model is not None, Aoff, group, local,
                    NoiseModel.isotropic(n))
    prep.noise = (stations_model(prep, max_degree, tracker_model) if several
                  else noise_model(prep, t, max_degree, tracker_model))
    if t is None and prep.noise.tracker is not None:
        prep.geometry.tracker = np.asarray(prep.noise.tracker, dtype=float)
    prep.noise = axis_scatter(prep, scatter_level)  # one axis repeating worse than the others: its readings re-weighted
    return prep
