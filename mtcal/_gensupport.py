"""Argument handling shared by the generated NumPy modules (kept out of generated/ so it is never emitted)."""
from __future__ import annotations

import numpy as np


def as_arg(value, n: int, name: str, func: str) -> np.ndarray:
    """Float array for a generated function; ``n`` > 0 means shape (..., n), 0 means any shape (scalar per pose)."""
    a = np.asarray(value, dtype=float)
    if n and (a.ndim == 0 or a.shape[-1] != n):
        raise ValueError(f"{func}: argument {name!r} must have shape (..., {n}), got {a.shape}")
    return a


def out_array(shapes: tuple[tuple[int, ...], ...], out_shape: tuple[int, ...]) -> np.ndarray:
    """Uninitialised output of the broadcast leading shape of all arguments."""
    try:
        lead = np.broadcast_shapes(*shapes)
    except ValueError as exc:
        raise ValueError(f"leading shapes {shapes} of the arguments do not broadcast") from exc
    return np.empty(lead + out_shape)
