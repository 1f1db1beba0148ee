"""A model against a known truth over the work volume: how far the identified machine is from the true one, and
whether compensating with the model makes the true machine better or worse.

The tool tip's deviation (workpiece coordinates, mm) of each model is evaluated by the machine's generated
kinematics at the same poses.  ``compare_models`` is the one entry point (benchmarks, the demo's headline figures).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mtcal.kinematics.machine import Machine
from mtcal.model.errormodel import ErrorModel

WORSEN_RATIO = 0.5  # warn that compensating may make the machine worse from predicted error = this x correction


@dataclass(frozen=True)
class Comparison:
    """Model against truth over ``n`` poses (um), every figure after the re-setup gauge (the least-squares rigid
    motion of the workpiece t + w x p removed: what aligning the part on the machine absorbs, and what a turn of the
    measuring frame leaves).  ``truth_rms_um``: the true machine's tool-tip error, what the uncompensated machine
    shows; ``compensated_rms_um``: truth minus model, what it shows compensated with the model (first order);
    ``gauged_rms_um``: the model's error, the same figure."""

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
    diff = rigid_residual(p, d_true - d_model)
    return Comparison(len(poses), _rms_um(rigid_residual(p, d_true)), _rms_um(diff), _rms_um(diff))


@dataclass(frozen=True)
class Worth:
    """What a model corrects against the error it is predicted to carry, over ``n`` poses inside its measured
    ranges (um, both after the re-setup gauge): ``corrects_rms_um`` the RMS of the tool-tip deviation the model
    predicts (what compensation moves); ``predicted_error_rms_um`` the RMS of model minus truth that the data
    show (``split_half_worth``)."""

    n: int
    corrects_rms_um: float
    predicted_error_rms_um: float
    how: str

    @property
    def may_worsen(self) -> bool:
        """With model = truth + error, E|model|^2 = |truth|^2 + u^2: compensating leaves u^2 where the machine had
        |truth|^2 = c^2 - u^2, worse on average from u = c / sqrt(2) on.  Said from u = ``WORSEN_RATIO`` c on, as u
        comes from few rounds (benchmarks/identify_truth.py: the campaigns made worse and not warned)."""
        return self.predicted_error_rms_um > WORSEN_RATIO * self.corrects_rms_um

    def to_dict(self) -> dict:
        return {"corrects_rms_um": self.corrects_rms_um, "predicted_error_rms_um": self.predicted_error_rms_um,
                "may_worsen": self.may_worsen, "poses": self.n, "how": self.how}


def model_poses(machine: Machine, model: ErrorModel, n: int = 1000, seed: int = 0) -> np.ndarray:
    """Random poses (n, n_axes) inside the ranges the model's functions were measured over (zero for an axis it
    does not cover)."""
    rng = np.random.default_rng(seed)
    q = np.zeros((n, len(machine.axes)))
    for f in model.functions.values():
        q[:, machine.index(f.axis)] = rng.uniform(f.positions.min(), f.positions.max(), n)
    return q


def split_half_worth(machine: Machine, model: ErrorModel, half_a: ErrorModel, half_b: ErrorModel, n_a: int,
                     n_b: int, poses: np.ndarray | None = None) -> Worth:
    """``Worth`` of ``model`` (from n_a + n_b rounds) from the same estimator run on two halves of its rounds
    (n_a and n_b rounds): the halves' errors are independent, with variances n/n_a and n/n_b times the full
    model's, so the RMS of their difference over n (1/n_a + 1/n_b) is the full model's error.  Every correlation
    the estimator has (a round's shared reference reading, the six errors of one position) is in it; a bias of
    the fitted functions is not."""
    q = model_poses(machine, model) if poses is None else poses
    p = machine.forward(q)[:, :3]

    def dev(mdl: ErrorModel) -> np.ndarray:
        return machine.deviation(q, mdl.errors_at(machine, q, "hold"), order=1)[:, :3]
    diff = _rms_um(rigid_residual(p, dev(half_a) - dev(half_b)))
    n = n_a + n_b
    return Worth(len(q), _rms_um(rigid_residual(p, dev(model))), diff / float(np.sqrt(n * (1 / n_a + 1 / n_b))),
                 f"the same estimator on {n_a} and {n_b} of the {n} rounds: their difference over the volume")
