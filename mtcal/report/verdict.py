"""What the report's first page says, computed from the stored results: the volumetric error of an identified
model over its work volume (each error's share of it, for the ranking), and what to do next.

The volumetric error is computed as ``mtcal.identify.compare`` computes what a model corrects (its ``worth``,
which identify draws over its own poses, so the two differ by a few per cent): the tool tip's first-order deviation
at ``model_poses`` (1000 poses inside the ranges the model's functions were measured over, at the spindle gauge
point), the least-squares rigid motion of the workpiece removed (what setting the part up absorbs), RMS and
largest length, µm.  An error's share is the same figure with that error alone (the errors' shares do not add
up: they overlap)."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class Volume:
    """The volumetric error of a model: over ``poses`` poses inside the measured ranges of ``axes``, RMS and
    largest length (µm), and each error's alone (µm RMS), largest first; ``zero``: the error functions whose
    fitted function is zero (the data do not tell them from zero: the model, and a compensation, hold none)."""

    poses: int
    axes: tuple[str, ...]
    rms_um: float
    max_um: float
    by_error: list[tuple[str, float]] = field(default_factory=list)
    zero: frozenset[str] = frozenset()


def volume(spec: str | None, document: dict | None) -> Volume | None:
    """The ``Volume`` of the model ``document`` on machine ``spec``; None when it cannot be evaluated (no spec, a
    model the loader refuses)."""
    from mtcal.errors import InputError
    from mtcal.identify.compare import model_poses, rigid_residual
    from mtcal.kinematics.machine import load_machine
    from mtcal.model.errormodel import model_from_dict
    try:
        model = model_from_dict(document)
        m = load_machine(spec or model.machine)
    except (InputError, TypeError, ValueError, KeyError, AttributeError):
        return None
    q = model_poses(m, model)
    p = m.forward(q)[:, :3]
    e = model.errors_at(m, q, "hold")

    def lengths(errors: np.ndarray) -> np.ndarray:
        return np.linalg.norm(rigid_residual(p, m.deviation(q, errors, order=1)[:, :3]), axis=1) * 1e3

    total = lengths(e)
    shares = []
    for k, name in enumerate(m.error_names):
        if np.any(e[:, k] != 0):
            alone = np.zeros_like(e)
            alone[:, k] = e[:, k]
            shares.append((name, float(np.sqrt(np.mean(lengths(alone) ** 2)))))
    axes = tuple(a for a in m.axes if np.ptp(q[:, m.index(a)]) > 0)
    zero = frozenset(n for n, f in model.functions.items() if f.fit is not None and f.fit.is_zero())
    return Volume(len(q), axes, float(np.sqrt(np.mean(total**2))), float(total.max()),
                  sorted(shares, key=lambda s: -s[1]), zero)
