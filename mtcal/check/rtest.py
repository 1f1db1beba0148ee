"""ISO 10791-6 rotary-axis tests predicted from an error model: a precision sphere on the table, an R-test (or a
ballbar, a touch probe as KinematicsOpt and AxiSet use) on the spindle, one rotary axis sweeping while the linear
axes keep the tool nominally on the sphere's centre (the other rotary axes held).

Frame and signs: the deviation is where the sphere's centre is relative to the tool ball, in the machine frame
(mm), actual minus nominal (nominal: zero).  The sphere is fixed in the workpiece frame, so d = -R(q) dp(q): dp the
tool tip's deviation in the workpiece frame (the generated error Jacobian at zero error, derive/, with the tool
length's lever arm as ``Machine.forward`` takes it: the axes place the tool tip, the errors act ``tool_length`` mm
above it at the spindle gauge point), R(q) the table side's nominal rotation into the machine frame.  s: the
sphere in workpiece coordinates (mm).  Figures: for each machine direction the largest difference of the readings over
the sweep (ISO 10791-6's "maximum difference"), mm.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mtcal.errors import InputError
from mtcal.model.errormodel import ErrorEvaluator, ErrorModel

COMPONENTS = ("X", "Y", "Z")


@dataclass(frozen=True)
class RTestSetup:
    """An ISO 10791-6 R-test sweep to predict: a rotary axis turned over positions with a sphere on the table.

    Parameters
    ----------
    axis : str
        The rotary axis swept.
    positions_deg : tuple of float
        Its positions, deg.
    sphere_mm : tuple of float, optional
        The sphere's centre in workpiece coordinates, mm (default the origin).
    fixed : dict of str to float, optional
        The other rotary axes' positions, deg (missing: 0).
    tool_length : float, optional
        The tool ball below the spindle gauge point, mm (default 0).

    Examples
    --------
    >>> import mtcal
    >>> mtcal.RTestSetup("C", (0.0, 90.0, 180.0, 270.0), (100.0, 50.0, 0.0)).axis
    'C'
    """

    axis: str
    positions_deg: tuple[float, ...]
    sphere_mm: tuple[float, float, float] = (0.0, 0.0, 0.0)
    fixed: dict[str, float] = field(default_factory=dict)
    tool_length: float = 0.0


def sweep_axes(machine, s: RTestSetup) -> np.ndarray:
    """Nominal axis positions (n, n_axes) of the sweep: the rotary axis at each position, the linear axes where
    the tool tip is on the sphere (solved exactly: at fixed rotary axes the tool tip is affine in the linear axes)."""
    if s.axis not in machine.rotary_axes:
        raise InputError(f"axis {s.axis!r}: an R-test sweeps a rotary axis of machine {machine.name} "
                         f"({', '.join(machine.rotary_axes)})")
    q = np.repeat(machine.axis_vector(s.fixed)[None], len(s.positions_deg), axis=0)
    q[:, machine.index(s.axis)] = s.positions_deg
    lin = [machine.index(a) for a in machine.linear_axes]
    target = np.asarray(s.sphere_mm, dtype=float)
    for _ in range(2):  # the second step only removes rounding
        p = machine.forward(q, tool_length=s.tool_length, check=False)[:, :3]
        J = machine.jacobian_axes(q, tool_length=s.tool_length, check=False)[:, :3, :][:, :, lin]
        q[:, lin] += np.linalg.solve(J, (target - p)[..., None])[..., 0]
    machine.check_axes(q)
    return q


def deviation_sensitivity(machine, q: np.ndarray, s: RTestSetup) -> np.ndarray:
    """d (sphere - tool ball) / d errors (n, 3, n_errors) in the machine frame at the sweep's axes."""
    R = machine.rigid_motion("table", q)[1]
    return -np.einsum("nij,nje->nie", R, machine.jacobian_errors(q, s.tool_length)[:, :3, :])


@dataclass
class RTestPrediction:
    """A predicted R-test sweep: the deviations of the sphere from the tool ball and each error's share.

    Attributes
    ----------
    setup : RTestSetup
        The sweep.
    positions_deg : numpy.ndarray, shape (n,)
        The rotary axis' positions, deg.
    deviation : numpy.ndarray, shape (n, 3)
        Sphere - tool ball in machine X, Y, Z, mm.
    ranges : dict of str to float
        The largest difference per direction (X, Y, Z), mm.
    contributions : dict of str to float
        Each error's share: {ISO name: its largest difference over X, Y, Z, mm}, largest first.
    outside : dict of str to int
        Error evaluations beyond an error function's measured range (end values held): {name: count}.
    """

    setup: RTestSetup
    positions_deg: np.ndarray
    deviation: np.ndarray
    ranges: dict[str, float]
    contributions: dict[str, float]
    outside: dict[str, int] = field(default_factory=dict)

    def to_dict(self) -> dict:
        s = self.setup
        return {"kind": "rtest", "axis": s.axis, "sphere_mm": list(s.sphere_mm), "fixed_deg": dict(s.fixed),
                "range_mm": self.ranges,
                "trace": [[float(p), *map(float, d)] for p, d in zip(self.positions_deg, self.deviation)],
                "contributions": self.contributions, "outside_range": dict(self.outside)}


def ranges(dev: np.ndarray) -> dict[str, float]:
    """The largest difference of the readings over the sweep per machine direction, mm."""
    return {c: float(np.ptp(dev[:, k])) for k, c in enumerate(COMPONENTS)}


def predict_rtest(model: ErrorModel, setup: RTestSetup, machine=None) -> RTestPrediction:
    """The R-test sweep ``setup`` as the model predicts it (first order through the generated kinematics).

    Parameters
    ----------
    model : ErrorModel
        The error model (mm, rad); positions beyond an error function's measured range hold its end values,
        counted in the prediction's ``outside`` (as compensate does).
    setup : RTestSetup
        The sweep.
    machine : Machine, optional
        Default: the model's.

    Returns
    -------
    RTestPrediction
        Deviations per position (mm), their ranges per direction, each error's share.

    Raises
    ------
    mtcal.errors.InputError
        An axis that is not a rotary axis of the machine, a sweep beyond the travel.

    Examples
    --------
    >>> import mtcal
    >>> from mtcal.data import path
    >>> model = mtcal.load_model(path("demo_truth.json"))
    >>> r = mtcal.predict_rtest(model, mtcal.RTestSetup("C", tuple(range(0, 360, 30)), (100.0, 50.0, 0.0)))
    >>> r.deviation.shape, {k: round(v * 1e3, 1) for k, v in r.ranges.items()}  # um
    ((12, 3), {'X': 26.8, 'Y': 20.2, 'Z': 20.7})
    """
    m = machine or model.kinematics
    q = sweep_axes(m, setup)
    J = deviation_sensitivity(m, q, setup)
    ev = ErrorEvaluator(model, m, "hold")
    e = ev(q)
    parts = np.einsum("nke,ne->nke", J, e)
    dev = parts.sum(axis=2)
    contrib = {n: float(np.ptp(parts[:, :, k], axis=0).max()) for k, n in enumerate(m.error_names)
               if np.any(parts[:, :, k])}
    contrib = dict(sorted(((n, v) for n, v in contrib.items() if v > 0), key=lambda kv: -kv[1]))
    return RTestPrediction(setup, np.asarray(setup.positions_deg, dtype=float), dev, ranges(dev), contrib,
                           dict(ev.outside_counts))
