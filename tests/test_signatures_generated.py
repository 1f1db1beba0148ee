"""generated/signatures_*: symbolic vs numeric, and the signatures as derivatives (central differences)."""
from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from derive.signatures import build
from mtcal.generated import signatures_casadi as C
from mtcal.generated import signatures_numpy as S

MOD = build()
FUNCS = {f.name: f for f in MOD.functions}
RNG = np.random.default_rng(7)


def _args(f):
    vals = []
    for a in f.args:
        v = RNG.uniform(0.5, 2.0, len(a.symbols)) if a.vector else float(RNG.uniform(0.5, 2.0))
        vals.append(v)
    return vals


@pytest.mark.parametrize("name", sorted(FUNCS))
def test_symbolic_equals_numpy_and_casadi(name):
    f = FUNCS[name]
    vals = _args(f)
    subs = {}
    for a, v in zip(f.args, vals):
        subs.update(zip(a.symbols, np.atleast_1d(v)))
    want = np.array(f.outputs.subs(subs).evalf(), dtype=float)
    got = np.asarray(getattr(S, name)(*vals))
    assert np.allclose(got.reshape(want.shape), want, rtol=1e-13, atol=1e-15)
    cas = np.array(getattr(C, name)()(*[np.atleast_1d(v) for v in vals]))
    assert np.allclose(cas.reshape(want.shape), want, rtol=1e-13, atol=1e-15)


def test_vectorised_over_readings():
    col = RNG.normal(size=(50, 3))
    d = RNG.choice([-1.0, 1.0], 50)
    assert S.backlash_signature(col, d).shape == (50, 3)
    assert S.periodic_signature(col, np.linspace(0, 500, 50), 200.0).shape == (50, 3, 2)
    assert S.thermal_drift_signature(np.linspace(0, 5000, 50), 1800.0).shape == (50, 3, 3)


def test_thermal_drift_signature_and_dtau_are_derivatives():
    # the displacement is linear in A (signature exact) and smooth in tau: a central difference with
    # h = 1e-3 tau has truncation error ~ h^2 |d3/dtau3| ~ 1e-7 relative, far below the 1e-6 tolerance
    A, dt, tau = np.array([0.004, -0.002, 0.01]), 1234.0, 1800.0
    sig = S.thermal_drift_signature(dt, tau)
    assert np.allclose(sig @ A, S.thermal_drift_displacement(A, dt, tau), rtol=1e-14)
    h = 1e-3 * tau
    fd = (S.thermal_drift_displacement(A, dt, tau + h) - S.thermal_drift_displacement(A, dt, tau - h)) / (2 * h)
    assert np.allclose(S.thermal_drift_dtau(A, dt, tau), fd, rtol=1e-6, atol=1e-14)


def test_tracker_scale_signature_is_radial_derivative():
    # reading = T + (1 + 1e-6 ppm)(p - T) is linear in ppm, so one central difference (h = 1 ppm) is exact up to
    # rounding ~1e-16 * 1500 mm; tolerance 1e-12 mm
    p, t = np.array([300.0, 100.0, 200.0]), np.array([250.0, -1500.0, 150.0])
    def f(ppm):
        return t + (1 + 1e-6 * ppm) * (p - t)
    assert np.allclose(S.tracker_scale_signature(p, t), (f(1.0) - f(-1.0)) / 2, atol=1e-12)


def test_periodic_signature_matches_amplitude_phase_model():
    # amplitude sin(2 pi q / pitch + phase) = a_s sin + a_c cos with a_s = amp cos(phase), a_c = amp sin(phase)
    col, q, pitch, amp, ph = np.array([1.0, 0.2, -0.1]), 137.0, 200.0, 0.002, 0.7
    sig = S.periodic_signature(col, q, pitch)
    assert np.allclose(sig @ [amp * np.cos(ph), amp * np.sin(ph)], col * amp * np.sin(2 * np.pi * q / pitch + ph))


def test_signatures_derived_not_typed():
    f = FUNCS["backlash_signature"]
    c = sp.Matrix(f.args[0].symbols)
    assert (f.outputs - c * f.args[1].symbols[0] / 2).applyfunc(sp.simplify) == sp.zeros(3, 1)
