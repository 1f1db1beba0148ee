"""A model against a known truth over the work volume: how far the identified machine is from the true one, and
whether compensating with the model makes the true machine better or worse.

The tool tip's deviation (workpiece coordinates, mm) of each model is evaluated by the machine's generated
kinematics at the same poses.  ``compare_models`` is the one entry point (benchmarks, the demo's headline figures).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mtcal.machine import Machine
from mtcal.model import ErrorModel


@dataclass(frozen=True)
class Comparison:
    """Model against truth over ``n`` poses (um).  ``truth_rms_um``: the true machine's tool-tip error, what the
    uncompensated machine shows; ``compensated_rms_um``: truth minus model, what the machine shows compensated
    with the model (first order); ``gauged_rms_um``: the same after the re-setup gauge (a rigid motion of the
    workpiece t + w x p, what re-aligning the part absorbs and what a turn of the measuring frame leaves)."""

    n: int
    truth_rms_um: float
    compensated_rms_um: float
    gauged_rms_um: float

    @property
    def worse(self) -> bool:
        """Whether compensating with the model leaves the true machine further off than no compensation."""
        return self.compensated_rms_um > self.truth_rms_um


def _rms_um(d: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum(d**2, axis=1))) * 1e3)


def rigid_residual(p: np.ndarray, d: np.ndarray) -> np.ndarray:
    """``d`` (n, 3) mm minus its least-squares rigid part t + w x p (p (n, 3) mm, centred here)."""
    pc = p - p.mean(axis=0)
    a = np.zeros((len(p), 3, 6))
    a[:, :, :3] = np.eye(3)
    a[:, 0, 4], a[:, 0, 5] = pc[:, 2], -pc[:, 1]
    a[:, 1, 3], a[:, 1, 5] = -pc[:, 2], pc[:, 0]
    a[:, 2, 3], a[:, 2, 4] = pc[:, 1], -pc[:, 0]
    a = a.reshape(-1, 6)
    sol = np.linalg.lstsq(a, d.ravel(), rcond=None)[0]
    return (d.ravel() - a @ sol).reshape(-1, 3)


def compare_models(machine: Machine, model: ErrorModel, truth: ErrorModel, poses: np.ndarray) -> Comparison:
    """Compare ``model`` with ``truth`` at axis positions ``poses`` (n, n_axes; mm, deg); functions outside their
    tables are held at their end values."""
    p = machine.forward(poses)[:, :3]
    d_true = machine.deviation(poses, truth.errors_at(machine, poses, "hold"), order=1)[:, :3]
    d_model = machine.deviation(poses, model.errors_at(machine, poses, "hold"), order=1)[:, :3]
    diff = d_true - d_model
    return Comparison(len(poses), _rms_um(d_true), _rms_um(diff), _rms_um(rigid_residual(p, diff)))
