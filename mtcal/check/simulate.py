"""Measured check tests made by a physical simulator of a true machine (for tests, benchmarks and the demo): the
exact error-inclusive kinematics (generated from derive/) at the axes the machine really reaches, so nothing of
the first-order prediction is reused.

Physics beyond the geometric errors: backlash (lost motion b of an axis: its position error is +b/2 in the direction
of travel, as mtcal.campaign.effects plants it), servo lag (each axis follows its command late by tau_s: an error
of -tau * velocity; a mismatch of the two axes' tau makes the direction-dependent oval of a ballbar), and white
reading noise."""
from __future__ import annotations

import numpy as np

from mtcal.check import circular as circ
from mtcal.check import rtest as rt
from mtcal.check.files import MeasuredCheck
from mtcal.generated import signatures_numpy as S
from mtcal.model.errormodel import ErrorModel


def _actual_axes(machine, q: np.ndarray, velocity: np.ndarray, backlash: dict[str, float],
                 servo_lag_s: dict[str, float]) -> np.ndarray:
    """Axis positions reached (mm, deg) for commands ``q`` moving at ``velocity`` (per s)."""
    qa = q.copy()
    for a, b in backlash.items():  # the campaign simulator's formula (derive/signatures.py: + d b / 2)
        i = machine.index(a)
        qa[:, i] += S.backlash_model(np.sign(velocity[:, i]), [b])[:, 0]
    for a, tau in servo_lag_s.items():
        i = machine.index(a)
        qa[:, i] -= tau * velocity[:, i]
    return qa


def simulate_circular(truth: ErrorModel, setup: circ.CircleSetup, *, machine=None, backlash: dict | None = None,
                      servo_lag_s: dict | None = None, feed_mm_min: float = 1000.0, noise_mm: float = 0.0002,
                      seed: int = 0) -> MeasuredCheck:
    """A ballbar test of the true machine ``truth``: both directions of ``setup`` (or the one it names), the
    distance of the tool ball from the table ball set at the centre, minus the radius (mm), with noise."""
    m = machine or truth.kinematics
    rng = np.random.default_rng(seed)
    g = circ.geometry(m, setup)
    th, dr, dirs = [], [], []
    centre = g.centre_axes[None]
    p0 = m.forward(centre, truth.errors_at(m, centre, "hold"), setup.tool_length)[0, :3]
    for d in circ.DIRECTIONS[setup.direction]:
        order = np.arange(len(g.theta_deg)) if d > 0 else np.arange(len(g.theta_deg))[::-1]
        q = g.axes[order]
        t = np.radians(g.theta_deg[order])
        w = d * feed_mm_min / 60.0 / setup.radius_mm  # rad/s
        vel = np.zeros_like(q)
        vel[:, m.index(setup.plane[0])] = -setup.radius_mm * w * np.sin(t)
        vel[:, m.index(setup.plane[1])] = setup.radius_mm * w * np.cos(t)
        qa = _actual_axes(m, q, vel, backlash or {}, servo_lag_s or {})
        p = m.forward(qa, truth.errors_at(m, qa, "hold"), setup.tool_length, check=False)[:, :3]
        dr.append(np.linalg.norm(p - p0, axis=1) - setup.radius_mm + rng.normal(0, noise_mm, len(q)))
        th.append(g.theta_deg[order])
        dirs.append(np.full(len(q), d))
    centre_mm = tuple(float(g.centre_axes[m.index(a)]) for a in m.linear_axes)
    info = {"plane": setup.plane, "radius_mm": setup.radius_mm, "centre_mm": centre_mm, "fixed_deg": dict(setup.fixed)}
    return MeasuredCheck("circular", "<simulated circular test>", info,
                         {"angle_deg": np.concatenate(th), "deviation_mm": np.concatenate(dr),
                          "direction": np.concatenate(dirs).astype(float)})


def simulate_rtest(truth: ErrorModel, setup: rt.RTestSetup, *, machine=None, noise_mm: float = 0.0002,
                   seed: int = 0) -> MeasuredCheck:
    """An R-test sweep of the true machine: the sphere's centre relative to the tool ball in the machine frame,
    exact, with noise (mm)."""
    m = machine or truth.kinematics
    rng = np.random.default_rng(seed)
    q = rt.sweep_axes(m, setup)
    tip = m.forward(q, truth.errors_at(m, q, "hold"), setup.tool_length)[:, :3]  # the tool tip, workpiece frame
    R = m.rigid_motion("table", q)[1]
    d = np.einsum("nij,nj->ni", R, np.asarray(setup.sphere_mm, dtype=float) - tip)
    d += rng.normal(0, noise_mm, (len(q), 3))
    info = {"axis": setup.axis, "sphere_mm": tuple(setup.sphere_mm), "fixed_deg": dict(setup.fixed)}
    return MeasuredCheck("rtest", "<simulated R-test>", info,
                         {"position_deg": np.asarray(setup.positions_deg, dtype=float), "dx_mm": d[:, 0],
                          "dy_mm": d[:, 1], "dz_mm": d[:, 2]})
