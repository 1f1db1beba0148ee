"""Nominal inverse kinematics of a machine spec: the tilt branch, the rotary angle's 360-degree multiple and the
linear axes, on the generated ``ik_tilt``, ``ik_rotary`` and ``ik_linear`` (derive/kinematics.py).  ``m`` is a
``mtcal.kinematics.machine.Machine``.

``Machine.inverse`` is the entry point; the branch rules are stated in its docstring.
"""
from __future__ import annotations

import numpy as np

from mtcal.errors import InputError


def _unit_tool_axis(pose) -> tuple[np.ndarray, np.ndarray]:
    """(pose (..., 6), its tool axis normalised (..., 3)); a wrong shape, NaN/inf or a non-unit axis is an error."""
    p = np.asarray(pose, dtype=float)
    if p.ndim == 0 or p.shape[-1] != 6:
        raise InputError(f"pose must have shape (..., 6) = [x, y, z, i, j, k], got {p.shape}")
    if not np.isfinite(p).all():
        raise InputError(f"pose contains NaN/inf at index {tuple(np.argwhere(~np.isfinite(p))[0])}")
    n = p[..., 3:]
    norm = np.linalg.norm(n, axis=-1)
    if np.any(np.abs(norm - 1) > 1e-3):
        idx = tuple(int(i) for i in np.argwhere(np.abs(norm - 1) > 1e-3)[0])
        raise InputError(f"tool axis at index {idx} has length {norm[idx]:.6g}, expected a unit vector")
    return p, n / norm[..., None]


def _reachable(m, n: np.ndarray) -> np.ndarray:
    """The tool axis with k clipped to the spec's reachable range (only rounding, <= 1e-12); beyond it an error."""
    k = n[..., 2]
    lo, hi = m.ik_info["k_range"]
    if np.any((k < lo - 1e-12) | (k > hi + 1e-12)):
        idx = tuple(int(i) for i in np.argwhere((k < lo - 1e-12) | (k > hi + 1e-12))[0])
        raise InputError(f"tool axis k = {k[idx]:.9g} at index {idx} is unreachable: "
                         f"{m.name} reaches k in [{lo:g}, {hi:g}]")
    return np.concatenate([n[..., :2], np.clip(k, lo, hi)[..., None]], axis=-1)


def _tilt(m, n: np.ndarray, h: np.ndarray, hinted: bool) -> np.ndarray:
    """The tilt angle: the preferred branch inside the limits, else the other, else the one closer to the hint."""
    info = m.ik_info
    ti = m.axes.index(info["tilt_axis"])
    cand = m._np.ik_tilt(n)  # (..., 2): [phi + t, phi - t]
    if info["preferred_branch"] < 0:
        cand = cand[..., ::-1]
    lim = m.limits[ti] or (-np.inf, np.inf)
    ok = (cand >= lim[0] - 1e-9) & (cand <= lim[1] + 1e-9)
    if not ok.any(axis=-1).all():
        idx = tuple(int(i) for i in np.argwhere(~ok.any(axis=-1))[0])
        raise InputError(f"no {info['tilt_axis']} within {lim} reaches the tool axis at index {idx} "
                         f"(candidates {cand[idx]})")
    closer = np.abs(cand[..., 1] - h[..., ti]) < np.abs(cand[..., 0] - h[..., ti])
    pick_second = ~ok[..., 0] | (ok[..., 1] & closer & hinted)
    return np.clip(np.where(pick_second, cand[..., 1], cand[..., 0]), *lim)


def inverse_kinematics(m, pose, hint=None, singular_tol: float = 1e-9,
                       tool_length: float = 0.0) -> np.ndarray:
    """Axes (..., n_axes) that reach ``pose`` nominally on machine ``m`` (the rules: ``Machine.inverse``)."""
    p, n = _unit_tool_axis(pose)
    info = m.ik_info
    ti, ri = m.axes.index(info["tilt_axis"]), m.axes.index(info["rotary_axis"])
    h = np.zeros(len(m.axes)) if hint is None else np.asarray(hint, dtype=float)
    h = np.broadcast_to(h, p.shape[:-1] + (len(m.axes),))
    n = _reachable(m, n)
    tilt = _tilt(m, n, h, hint is not None)
    rc = m._np.ik_rotary(tilt, n[..., :2])
    rot, sing = rc[..., 0], rc[..., 1] < singular_tol
    rot = np.where(sing, h[..., ri], rot + 360.0 * np.round((h[..., ri] - rot) / 360.0))
    lin = m._np.ik_linear(np.stack([tilt, rot], axis=-1), p[..., :3], tool_length)
    out = np.empty(p.shape[:-1] + (len(m.axes),))
    li = [i for i, kd in enumerate(m.axis_kinds) if kd == "linear"]
    out[..., li] = lin
    out[..., ti], out[..., ri] = tilt, rot
    return out
