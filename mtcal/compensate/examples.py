"""Example error models for demos, tests and benchmarks: a synthetic model of the thesis' magnitudes and the
thesis' own compensation model (angular errors of the linear axes neglected)."""
from __future__ import annotations

import numpy as np

from mtcal.kinematics.machine import Machine, load_machine
from mtcal.model.errormodel import ErrorFunction, ErrorModel
from mtcal.model.iso_types import iso_16907_types


def thesis_model(model: ErrorModel) -> ErrorModel:
    """The thesis' compensation model (sec. 3.5): the angular errors of the linear axes neglected."""
    drop = set(iso_16907_types(model.kinematics)["L-ANG"])
    return ErrorModel(model.machine, {k: v for k, v in model.constants.items() if k not in drop},
                      {k: f for k, f in model.functions.items() if k not in drop}, dict(model.meta))


def example_model(machine: Machine | None = None, seed: int = 6) -> ErrorModel:
    """A synthetic error model of the thesis' magnitudes (tens of um, tens of urad) for demos, tests, benchmarks.

    Linear axes: tables over [-400, 400] mm every 25 mm (smooth random curves, zero at 0); a rotary axis with
    limits: a table over its limits every 15 deg; one without: harmonic fits (periodic); the machine's
    squareness and location constants.  (DMU 50: B table over [0, 180], C harmonic.)
    """
    m = machine or load_machine()
    rng = np.random.default_rng(seed)
    funcs, consts = {}, {}
    parts = "XYZABC"  # ISO components of the six error motions

    def curve(x, amp, period):
        ph = rng.uniform(0, 2 * np.pi, 3)
        y = sum(a * np.sin(2 * np.pi * x / (period / (h + 1)) + p) for h, (a, p) in
                enumerate(zip(amp * rng.uniform(0.3, 1.0, 3) / np.arange(1, 4), ph)))
        y = y + amp * rng.uniform(-1, 1) * x / np.abs(x).max()
        return y - np.interp(0.0, x, y)

    xl = np.arange(-400.0, 400.0 + 1e-9, 25.0)
    for ax in m.linear_axes:
        own = m.positioning_errors[ax][2]
        for c in parts[:3]:
            funcs[f"E_{c}{ax}"] = ErrorFunction(ax, xl, curve(xl, 0.015 if c == own else 0.008, 900.0))
        for c in parts[3:]:
            funcs[f"E_{c}{ax}"] = ErrorFunction(ax, xl, curve(xl, 30e-6, 900.0))
    for ax in m.rotary_axes:
        lim = m.limits[m.index(ax)]
        if lim:
            xb = np.arange(lim[0], lim[1] + 1e-9, 15.0)
            for c, amp in zip(parts, (0.012, 0.012, 0.008, 30e-6, 30e-6, 40e-6)):
                funcs[f"E_{c}{ax}"] = ErrorFunction(ax, xb, curve(xb, amp, 360.0))
            continue
        xc = np.arange(0.0, 360.0 + 1e-9, 15.0)
        for c, amp in zip(parts, (0.010, 0.010, 0.006, 25e-6, 25e-6, 35e-6)):
            a0 = float(rng.normal(0, amp / 3))
            cos, sin = (amp * rng.uniform(-0.5, 0.5, 3)).tolist(), (amp * rng.uniform(-0.5, 0.5, 3)).tolist()
            fit = {"kind": "harmonic", "period": 360.0, "a0": a0, "cos": cos, "sin": sin}
            f = ErrorFunction(ax, xc, np.zeros_like(xc), fit)
            f.values = f(xc)
            funcs[f"E_{c}{ax}"] = f
    sizes = {"E_C0Y": 25e-6, "E_B0Z": -18e-6, "E_A0Z": 12e-6}  # the DMU 50's; others by their place in the group
    for i, n in enumerate(m.error_groups["squareness"]):
        consts[n] = sizes.get(n, (25e-6, -18e-6, 12e-6)[i % 3])
    for i, n in enumerate(m.error_groups["location"]):  # E_X0R, E_Y0R (mm), E_A0R, E_B0R (rad) per rotary axis
        k, r = i % 4, i // 4
        consts[n] = ((0.008, -0.006, 20e-6, -15e-6), (0.010, 0.007, -12e-6, 18e-6))[r % 2][k]
    return ErrorModel(m.name, consts, funcs, {"source": f"mtcal.compensate.examples.example_model(seed={seed})"})
