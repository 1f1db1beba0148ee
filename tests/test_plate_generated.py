"""generated/plate_*: symbolic vs numeric, Jacobian vs finite differences, NumPy vs CasADi, paper equations."""
from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from derive import plate as D
from mtcal.generated import plate_casadi as GC
from mtcal.generated import plate_numpy as G


@pytest.fixture(scope="module")
def module():
    return D.build()


def _random_args(f, rng):
    """Plate-like values: coordinates up to 15, small parameters, phi near a quarter turn, w in [0, 1]."""
    out = []
    for a in f.args:
        if a.name in ("p1", "pk"):
            out.append(rng.uniform(-15, 15, 2))
        elif a.name == "params":
            out.append(np.r_[rng.normal(0, 1e-3, 3), rng.normal(0, 1e-2, 2)])
        elif a.name == "phi":
            out.append(np.float64(rng.choice([0, 1, 2, 3]) * math.pi / 2 + rng.normal(0, 0.3)))
        elif a.name == "w":
            out.append(np.float64(rng.uniform(0, 1)))
        elif a.name == "sums":
            p = rng.uniform(-15, 15, (9, 2))
            uv = rng.normal(0, 1e-3, (9, 2))
            x, y, u, v = p[:, 0], p[:, 1], uv[:, 0], uv[:, 1]
            out.append(np.array([x @ x, y @ y, x @ y, x @ u, y @ u, x @ v, y @ v]))
    return out


def _flat_subs(f, vals):
    subs = {}
    for a, v in zip(f.args, vals):
        for s, x in zip(a.symbols, np.atleast_1d(v)):
            subs[s] = sp.Float(float(x), 30)
    return subs


@pytest.mark.slow
def test_generated_numpy_equals_direct_sympy(module):
    """Every generated function against SymPy's own evaluation (30 digits) of the derived expressions."""
    rng = np.random.default_rng(3)
    for f in module.functions:
        for _ in range(3):
            vals = _random_args(f, rng)
            got = np.asarray(getattr(G, f.name)(*vals), dtype=float)
            ref = np.array(f.outputs.evalf(30, subs=_flat_subs(f, vals)).tolist(), dtype=float)
            ref = ref.reshape(got.shape)
            np.testing.assert_allclose(got, ref, rtol=1e-11, atol=1e-12, err_msg=f.name)


@pytest.mark.slow
def test_numpy_equals_casadi(module):
    rng = np.random.default_rng(4)
    for f in module.functions:
        vals = _random_args(f, rng)
        got = np.asarray(getattr(G, f.name)(*vals))
        cas = np.array(getattr(GC, f.name)()(*[np.atleast_1d(v) for v in vals])).reshape(got.shape)
        np.testing.assert_allclose(got, cas, rtol=1e-13, atol=1e-13, err_msg=f.name)


def test_jacobian_exact_vs_central_differences():
    """d residual_exact / d params against central differences.

    Step h = 1e-5 on every parameter (alpha, beta, gamma dimensionless; offsets in the plate unit, coordinates
    up to 15): truncation h^2 |r'''| / 6 ~ 1e-10 * 15 ~ 2e-9, rounding eps |r| / h ~ 1e-16 * 15 / 1e-5 ~ 2e-10;
    tolerance 1e-7 on derivatives of size up to ~15, well above both and far below any wrong term.
    """
    rng = np.random.default_rng(5)
    h = 1e-5
    for _ in range(20):
        p1, pk = rng.uniform(-15, 15, 2), rng.uniform(-15, 15, 2)
        q = np.r_[rng.normal(0, 1e-3, 3), rng.normal(0, 1e-2, 2)]
        phi, w = rng.choice([0.5, 1.0, 1.5]) * math.pi + rng.normal(0, 0.1), rng.uniform(0, 1)
        jac = G.jacobian_exact(p1, pk, q, phi, w)
        for j in range(5):
            e = np.zeros(5)
            e[j] = h
            fd = (G.residual_exact(p1, pk, q + e, phi, w) - G.residual_exact(p1, pk, q - e, phi, w)) / (2 * h)
            np.testing.assert_allclose(jac[:, j], fd, atol=1e-7)


def test_first_order_design_vs_central_differences():
    """design_first_order is d predict_first_order / d params (linear: central differences are exact up to
    rounding, eps * 15 / h = 1.5e-10 with h = 1e-5; tolerance 1e-8)."""
    rng = np.random.default_rng(6)
    pk, q = rng.uniform(-15, 15, 2), rng.normal(0, 1e-3, 5)
    d = G.design_first_order(pk, math.pi / 2)
    for j in range(5):
        e = np.zeros(5)
        e[j] = 1e-5
        fd = (G.predict_first_order(pk, q + e, math.pi / 2) - G.predict_first_order(pk, q - e, math.pi / 2)) / 2e-5
        np.testing.assert_allclose(d[:, j], fd, atol=1e-8)


def test_eq15_as_corrected_and_fortran_xc_yc():
    """Eq. 15 with (1 + gamma) in 15a (as in eq. B4 and the Fortran XC of Appendices C/D), not the printed
    (1 - gamma): x1 = -(alpha + beta) x2 - (1 + gamma) y2 + ex, y1 = (1 - gamma) x2 + (alpha - beta) y2 + ey."""
    a, b, g, ex, ey = 3e-6, -1.3e-4, 1.4e-5, -1.4e-5, 9.6e-6
    x2, y2 = 7.2, -6.9
    got = G.predict_first_order([x2, y2], [a, b, g, ex, ey], math.pi / 2)
    xc = -(a + b) * x2 - (1 + g) * y2 + ex
    yc = (1 - g) * x2 + (a - b) * y2 + ey
    assert got[0] == pytest.approx(xc, abs=1e-14) and got[1] == pytest.approx(yc, abs=1e-14)
    printed_15a = -(b + a) * x2 - (1 - g) * y2 + ex  # the OCR/print sign: off by 2 gamma y2
    assert abs(got[0] - printed_15a) == pytest.approx(2 * g * abs(y2), rel=1e-9)


def test_appendix_b_metrics_agree_to_first_order_only():
    """Exact C for the x, y and split metrics differ by O(alpha gamma, gamma^2) only (Appendix B)."""
    p = np.array([12.0, 9.0])
    small = np.array([5e-6, -1.3e-4, 1.4e-5, 0, 0])
    big = np.array([5e-3, -1.3e-4, 1.4e-2, 0, 0])
    for q, bound in ((small, 1e-8), (big, 1e-2)):
        preds = [G.predict_exact(p, q, math.pi / 2, w) for w in (0.0, 0.5, 1.0)]
        spread = np.max(np.abs(np.array(preds) - preds[1]))
        assert spread < bound
    assert spread > 1e-4  # at 1e-2 parameters the metrics really differ at second order (test can fail)


def test_normal_equations_closed_form_vs_lstsq():
    rng = np.random.default_rng(7)
    p2 = rng.uniform(-15, 15, (30, 2))
    y = rng.normal(0, 1e-4, (30, 2))
    x, yy, u, v = p2[:, 0], p2[:, 1], y[:, 0], y[:, 1]
    sums = np.array([x @ x, yy @ yy, x @ yy, x @ u, yy @ u, x @ v, yy @ v])
    J = G.design_first_order(p2, math.pi / 2)[:, :, :3].reshape(-1, 3)
    ref, *_ = np.linalg.lstsq(J, y.ravel(), rcond=None)
    np.testing.assert_allclose(G.normal_solve(sums), ref, rtol=1e-10, atol=1e-18)
    np.testing.assert_allclose(G.normal_matrix(sums), J.T @ J, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(G.normal_inverse(sums) @ G.normal_matrix(sums), np.eye(3), atol=1e-12)


def test_estimate_inverts_the_measurement():
    """estimate_exact(A B X) = X for position k (the model of eqs. 1, 6) and any metric share."""
    X = np.array([[3.0, 4.0], [-12.5, 7.0]])
    q = np.array([4.8e-6, -1.31e-4, 1.37e-5, 0, 0])
    for w in (0.0, 0.5, 1.0):
        A = np.array([[1 + w * q[2], -q[0]], [0, 1 - (1 - w) * q[2]]])
        th = math.pi / 2 + q[1]
        B = np.array([[math.cos(th), math.sin(th)], [-math.sin(th), math.cos(th)]])
        meas = X @ (A @ B).T
        np.testing.assert_allclose(G.estimate_exact(meas, q, math.pi / 2, w), X, atol=1e-13)
        np.testing.assert_allclose(G.estimate_first_order(meas, q, math.pi / 2, w), X, atol=1e-7)
