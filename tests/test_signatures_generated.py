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


# ----------------------------------------------------------------------------- issue 13: new physics
def _central(f, x, h):
    """Central-difference Jacobian of f (-> (3,)) at the parameter vector x (k,): (3, k)."""
    x = np.asarray(x, dtype=float)
    cols = []
    for i in range(len(x)):
        e = np.zeros_like(x)
        e[i] = h
        cols.append((f(x + e) - f(x - e)) / (2 * h))
    return np.stack(cols, axis=-1)


def test_reversal_angular_is_the_reversal_law_on_an_angular_error():
    # angle(+ approach) - angle(- approach) = r; the point moves by column x increment, linear in r: a central
    # difference with h = 1e-6 rad is exact up to rounding
    col = np.array([0.0, -120.0, 35.0])  # mm per rad (e.g. an E_BX column of a point 120 mm off the axis)
    up, down = S.reversal_angular_model(1.0, [80e-6]), S.reversal_angular_model(-1.0, [80e-6])
    assert up - down == pytest.approx(80e-6, abs=1e-18) and up == pytest.approx(40e-6, abs=1e-18)
    for d in (1.0, -1.0):
        fd = _central(lambda r, d=d: col * S.reversal_angular_model(d, r)[0], [0.0], 1e-6)[:, 0]
        assert np.allclose(S.reversal_angular_signature(col, d), fd, rtol=1e-12, atol=1e-15)
        assert np.allclose(S.reversal_angular_signature(col, d), col * d / 2, rtol=1e-15)


def test_thermal_temperature_expansion_and_drift_are_derivatives():
    # expansion: increment 1e-6 k dT q (k ppm/K, dT K, q mm): 10 ppm/K x 2 K x 500 mm = 10 um; linear in k
    assert S.thermal_temperature_model(500.0, 2.0, [10.0])[0] == pytest.approx(0.010, rel=1e-14)
    col, q, dT = np.array([1.0, 0.02, -0.01]), 321.0, 1.7
    fd = _central(lambda k: col * S.thermal_temperature_model(q, dT, k)[0], [0.0], 1.0)[:, 0]
    assert np.allclose(S.thermal_temperature_signature(col, q, dT), fd, rtol=1e-12, atol=1e-15)
    c = np.array([0.002, -0.001, 0.004])  # mm/K
    assert np.allclose(S.thermal_temperature_displacement(c, dT), c * dT, rtol=1e-15)
    fd = _central(lambda cc: S.thermal_temperature_displacement(cc, dT), np.zeros(3), 1e-3)
    assert np.allclose(S.thermal_temperature_drift_signature(dT), fd, rtol=1e-12, atol=1e-15)


def test_warm_up_curve_closed_form_and_no_overflow():
    t = np.array([0.0, 900.0, 1800.0, 1e6])
    want = 20.0 + 2.0 * (1 - np.exp(-t / 1800.0))
    assert np.allclose(S.thermal_temperature_curve(20.0, 2.0, t, 1800.0)[:, 0], want, rtol=1e-15)
    assert S.thermal_temperature_curve(20.0, 2.0, 1e7, 1.0)[0] == 22.0  # dt >> tau: finite, the final value


def test_nest_creep_signature_is_the_rotated_time():
    # the reading is b + R (local + v dt): d/dv = R dt exactly (linear in v)
    c, s = np.cos(0.7), np.sin(0.7)
    R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    v, dt = np.array([1e-6, -2e-6, 3e-6]), 5400.0
    assert np.allclose(S.nest_creep_model(v, dt), v * dt, rtol=1e-15)
    sig = S.nest_creep_signature(R.reshape(9), dt)
    fd = _central(lambda vv: R @ S.nest_creep_model(vv, dt), np.zeros(3), 1e-6)
    assert np.allclose(sig, fd, rtol=1e-9, atol=1e-12) and np.allclose(sig, R * dt, rtol=1e-15)


def _rotation_about(u, theta):
    """Independent construction: Q Rz(theta) Q^T with Q an orthonormal basis whose third column is u."""
    u = np.asarray(u, dtype=float) / np.linalg.norm(u)
    a = np.array([1.0, 0, 0]) if abs(u[0]) < 0.9 else np.array([0, 1.0, 0])
    e1 = np.cross(u, a)
    e1 /= np.linalg.norm(e1)
    Q = np.column_stack([e1, np.cross(u, e1), u])
    rz = np.array([[np.cos(theta), -np.sin(theta), 0], [np.sin(theta), np.cos(theta), 0], [0, 0, 1]])
    return Q @ rz @ Q.T


def test_tracker_settling_reading_and_signature():
    p, T = np.array([300.0, 100.0, 200.0]), np.array([250.0, -1500.0, 150.0])
    u = np.array([0.6, 0.8, 0.0])  # horizontal
    theta = 3e-3
    want = T + _rotation_about(u, theta) @ (p - T)
    assert np.allclose(S.tracker_settling_reading(p, T, u, theta), want, rtol=0, atol=1e-10)
    dt, tau = 2500.0, 1800.0
    w_a = np.array([2e-9, 30e-6])
    assert S.tracker_settling_angle(w_a, dt, tau)[0] == pytest.approx(2e-9 * dt + 30e-6 * (1 - np.exp(-dt / tau)))
    f = lambda x: S.tracker_settling_reading(p, T, u, S.tracker_settling_angle(x, dt, tau)[0])  # noqa: E731
    # reading is smooth in theta (second derivative ~ |p - T| = 1.6e3 mm): with h = 1e-9 rad/s and 1e-6 rad the
    # truncation of the central difference is ~ h^2 |p - T| dt^2 ~ 1e-8 mm, against a signature of ~1e3 mm/rad
    fd = np.column_stack([_central(f, [0.0, 0.0], h)[:, i] for i, h in ((0, 1e-9), (1, 1e-6))])
    sig = S.tracker_settling_signature(p, T, u, dt, tau)
    assert np.allclose(sig, fd, rtol=1e-6, atol=1e-9)
    assert np.allclose(sig[:, 0], np.cross(u, p - T) * dt, rtol=1e-14)
    assert np.isfinite(S.tracker_settling_signature(p, T, u, 1e7, 1.0)).all()  # dt >> tau: no overflow
