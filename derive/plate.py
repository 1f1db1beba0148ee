"""Hocken & Borchardt (NBSIR 79-1752) 2-D plate reversal: observational equations, normal equations, corrections.

Frames and conventions (re-derived here; the printed equations carry OCR and sign errors):
* plate coordinates in any length unit; position k is the plate turned clockwise (viewed from the top) by
  theta_k = phi_k + beta_k about the table normal, with phi_k the nominal angle (pi/2 for the paper's
  position 2) and beta_k the small difference (rad);
* true gage coordinates X, machine metric A (eqs. 3-5 as one family with the share w of gamma put on x):
      A = [[1 + w*gamma, -alpha], [0, 1 - (1 - w)*gamma]],  w = 1 (x, eq. 3), 0 (y, eq. 4), 1/2 (split, eq. 5);
* B(theta) = [[cos, sin], [-sin, cos]] (eq. 7, a clockwise turn), X1 = A X, Xk = A B(theta_k) X (eqs. 1, 6);
* observational equation (eq. 11): X1 = C Xk + eps with C = A B^-1 A^-1 (exact here, any theta).
  To first order in (alpha, beta, gamma) and phi = pi/2 this is
      x1 = -(alpha + beta) x2 - (1 + gamma) y2 + ex,   y1 = (1 - gamma) x2 + (alpha - beta) y2 + ey,
  the same for every w (Appendix B).  The printed eq. 15a has (1 - gamma) where (1 + gamma) belongs; the
  Fortran (Appendices C, D) and eq. B4 agree with the derivation.
* normal equations: the 3 x 3 system of (alpha, beta, gamma) in sums over the points of the position-2
  coordinates (x2, y2) and of the reduced observations u = x1 + y2, v = y1 - x2 (small numbers, so no
  cancellation of large sums).  ALBE2 (no offsets) uses raw sums; ALBE3 centres the data first, which
  projects the offsets out exactly (their columns are the indicator of each equation), then
  eps = mean(reduced obs) - J(mean x2) (alpha, beta, gamma).
* corrected coordinates (eq. 20): the mean of the estimates A^-1 X1 and B(theta_k)^-1 A^-1 Xk.
"""
from __future__ import annotations

import functools

import sympy as sp

from .codegen import Arg, Function, Module, symbols

alpha, beta, gamma, ex, ey = PARAMS = symbols(["alpha", "beta", "gamma", "ex", "ey"])
x1, y1, x2, y2 = symbols(["x1", "y1", "x2", "y2"])
xk, yk = symbols(["xk", "yk"])
phi, w = symbols(["phi", "w"])
SUMS = symbols(["Sxx", "Syy", "Sxy", "Sxu", "Syu", "Sxv", "Syv"])
u, v = symbols(["u", "v"])

SMALL = (alpha, beta, gamma)
METRIC_SHARE = {"x": 1.0, "y": 0.0, "split": 0.5, "none": 0.5}  # option 1, 2, 3, 4 (4: gamma not applied)


def metric(a=alpha, g=gamma, share=w) -> sp.Matrix:
    """Machine metric A (eqs. 3-5): share of gamma on the x scale (1: eq. 3, 0: eq. 4, 1/2: eq. 5)."""
    return sp.Matrix([[1 + share * g, -a], [0, 1 - (1 - share) * g]])


def turn(theta) -> sp.Matrix:
    """B(theta), eq. 7: the plate turned clockwise by theta (a point on +x goes to -y for theta = pi/2)."""
    return sp.Matrix([[sp.cos(theta), sp.sin(theta)], [-sp.sin(theta), sp.cos(theta)]])


def _first_order(expr: sp.Matrix) -> sp.Matrix:
    """Taylor polynomial of degree 1 in (alpha, beta, gamma) about zero."""
    z = {s: 0 for s in SMALL}
    out = expr.subs(z)
    for s in SMALL:
        out = out + sp.diff(expr, s).subs(z) * s
    return out.applyfunc(sp.expand)


@functools.cache
def observation_matrix_exact(share=w) -> sp.Matrix:
    """C = A B(phi + beta)^-1 A^-1 (eq. 10), exact."""
    A = metric(share=share)
    return (A * turn(phi + beta).T * A.inv()).applyfunc(sp.simplify)


@functools.cache
def observation_matrix_first_order() -> sp.Matrix:
    """C to first order; independent of the metric share w (Appendix B), asserted here."""
    c = _first_order(observation_matrix_exact())
    for share in (0, 1, sp.Rational(1, 2)):
        d = _first_order(observation_matrix_exact(share)) - c
        assert d.applyfunc(sp.simplify) == sp.zeros(2, 2), "Appendix B equivalence failed"
    return c


def check_paper_eq15(c1: sp.Matrix) -> None:
    """The derivation at phi = pi/2 against eq. 15 as corrected (and Fortran XC, YC of Appendix D)."""
    c = c1.subs(phi, sp.pi / 2)
    expect = sp.Matrix([[-(alpha + beta), -(1 + gamma)], [1 - gamma, alpha - beta]])
    assert (c - expect).applyfunc(sp.simplify) == sp.zeros(2, 2), "eq. 15 check failed"


def normal_equations() -> tuple[sp.Matrix, sp.Matrix]:
    """Normal matrix N and right-hand side b of the 3-parameter (alpha, beta, gamma) problem at phi = pi/2,
    written in the sums S.. over the points (x = x2, y = y2, u = x1 + y2, v = y1 - x2)."""
    c1 = observation_matrix_first_order().subs(phi, sp.pi / 2)
    p2 = sp.Matrix([x2, y2])
    pred = c1 * p2  # without offsets
    jac = pred.jacobian(sp.Matrix(SMALL))  # rows x, y; columns alpha, beta, gamma
    reduced = sp.Matrix([u, v])  # = X1 - C(0) X2
    assert (pred.subs({s: 0 for s in SMALL}) + reduced - sp.Matrix([x1, y1])).subs(
        {u: x1 + y2, v: y1 - x2}).applyfunc(sp.simplify) == sp.zeros(2, 1)
    n = (jac.T * jac).applyfunc(sp.expand)
    b = (jac.T * reduced).applyfunc(sp.expand)
    Sxx, Syy, Sxy, Sxu, Syu, Sxv, Syv = SUMS
    names = {x2**2: Sxx, y2**2: Syy, x2 * y2: Sxy, x2 * u: Sxu, y2 * u: Syu, x2 * v: Sxv, y2 * v: Syv}

    def to_sums(e: sp.Expr) -> sp.Expr:
        if e == 0:
            return sp.Integer(0)
        poly = sp.Poly(e, x2, y2, u, v)
        out = sp.Integer(0)
        for monom, coeff in poly.terms():
            m = sp.Mul(*[g**k for g, k in zip((x2, y2, u, v), monom)])
            out += coeff * names[m]
        return out

    return n.applyfunc(to_sums), b.applyfunc(to_sums)


def build(progress=lambda m: None) -> Module:
    """The plate target: first-order and exact models, closed-form normal equations, corrections."""
    P = Arg("params", PARAMS, "parameters [alpha (rad), beta (rad), gamma (1), ex, ey (length unit)]")
    Pk = Arg("pk", (xk, yk), "coordinates measured in position k (plate turned clockwise by phi + beta)")
    P1 = Arg("p1", (x1, y1), "coordinates measured in position 1 (plate aligned with the machine axes)")
    Phi = Arg("phi", (phi,), "nominal clockwise turn of position k relative to position 1, rad", vector=False)
    W = Arg("w", (w,), "share of gamma on the x scale: 1 (option 1), 0 (option 2), 1/2 (options 3, 4)",
            vector=False)
    S = Arg("sums", SUMS, "sums over points of x2^2, y2^2, x2 y2, x2 u, y2 u, x2 v, y2 v with "
            "u = x1 + y2, v = y1 - x2 (centred for ALBE3)")
    eps = sp.Matrix([ex, ey])

    progress("observational equations")
    c_exact = observation_matrix_exact()
    c1 = observation_matrix_first_order()
    check_paper_eq15(c1)
    c0 = c1.subs({s: 0 for s in SMALL})
    pk = sp.Matrix([xk, yk])
    p1 = sp.Matrix([x1, y1])

    pred1 = (c1 * pk).applyfunc(sp.expand) + eps
    pred_exact = c_exact * pk + eps
    design = pred1.jacobian(sp.Matrix(PARAMS))
    res_exact = (p1 - pred_exact).applyfunc(sp.simplify)
    jac_exact = res_exact.jacobian(sp.Matrix(PARAMS))

    progress("normal equations")
    n, b = normal_equations()
    n_inv = n.inv().applyfunc(sp.factor)
    sol = (n_inv * b).applyfunc(sp.factor)

    progress("corrections")
    # estimate of the gage coordinates from position k (position 1: phi = 0, beta = 0)
    A = metric()
    est_exact = turn(phi + beta).T * A.inv() * pk
    est1 = _first_order(est_exact)

    # Procrustes terms for the measured turn: theta = atan2(sum(x2 y1 - y2 x1), sum(x2 x1 + y2 y1))
    procrustes = sp.Matrix([xk * y1 - yk * x1, xk * x1 + yk * y1])

    fns = [
        Function("predict_first_order", (Pk, P, Phi), pred1,
                 "Position-1 coordinates predicted from position k, first order in alpha, beta, gamma (eq. 15).",
                 vector_output=True),
        Function("reduced_observation", (P1, Pk, Phi), p1 - c0 * pk,
                 "Reduced observation X1 - B(phi)^-1 Xk: the left side of the linear model (small numbers).",
                 vector_output=True),
        Function("design_first_order", (Pk, Phi), design,
                 "Design matrix d(prediction)/d(alpha, beta, gamma, ex, ey) of the first-order model (eq. 15)."),
        Function("predict_exact", (Pk, P, Phi, W), pred_exact,
                 "Position-1 coordinates predicted from position k, exact: A B(phi + beta)^-1 A^-1 Xk + eps.",
                 vector_output=True),
        Function("residual_exact", (P1, Pk, P, Phi, W), res_exact,
                 "Residual X1 - (A B(phi + beta)^-1 A^-1 Xk + eps) of the exact model (any turn angle).",
                 vector_output=True),
        Function("jacobian_exact", (P1, Pk, P, Phi, W), jac_exact,
                 "Jacobian d(residual_exact)/d(alpha, beta, gamma, ex, ey)."),
        Function("normal_matrix", (S,), n,
                 "Normal matrix of (alpha, beta, gamma) at phi = pi/2 in the point sums (ALBE2/ALBE3)."),
        Function("normal_inverse", (S,), n_inv,
                 "Inverse of normal_matrix in closed form (covariance / sigma^2 of alpha, beta, gamma)."),
        Function("normal_solve", (S,), sol,
                 "Closed-form solution (alpha, beta, gamma) of the normal equations at phi = pi/2.",
                 vector_output=True),
        Function("estimate_first_order", (Pk, P, Phi, W), est1,
                 "Gage coordinates estimated from position k, first order: B(phi + beta)^-1 A^-1 Xk "
                 "(position 1: phi = 0 and beta = 0); eq. 20 is the mean over positions.", vector_output=True),
        Function("estimate_exact", (Pk, P, Phi, W), est_exact,
                 "Gage coordinates estimated from position k, exact: B(phi + beta)^-1 A^-1 Xk.",
                 vector_output=True),
        Function("procrustes_terms", (P1, Pk), procrustes,
                 "Per-point terms whose sums give the measured clockwise turn atan2(s0, s1) of centred data.",
                 vector_output=True),
    ]
    meta = {"PARAMS": tuple(str(s) for s in PARAMS), "METRIC_SHARE": dict(METRIC_SHARE),
            "SOURCE_PAPER": "Hocken & Borchardt, NBSIR 79-1752 (1979)"}
    return Module("plate", "plate.py", "Hocken-Borchardt 2-D plate reversal (NBSIR 79-1752): first-order and "
                  "exact observational equations, closed-form normal equations, corrected coordinates.", fns, meta)
