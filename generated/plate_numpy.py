# -----------------------------------------------------------------------------
# GENERATED FILE - DO NOT EDIT.
# Generator: python -m derive (plate); source: derive/plate.py
# Target: NumPy (vectorised, broadcasting).  Regenerate with `python -m derive`; CI runs `python -m derive --check`.
# Inputs (machine spec, SymPy/CasADi versions, hash of derive/) are in manifest.json.
# -----------------------------------------------------------------------------
"""Hocken-Borchardt 2-D plate reversal (NBSIR 79-1752): first-order and exact observational equations, closed-form normal equations, corrected coordinates.

NumPy implementation."""
import numpy

from mtcal._gensupport import as_arg, out_array

PARAMS = ('alpha', 'beta', 'gamma', 'ex', 'ey')
METRIC_SHARE = {'none': 0.5, 'split': 0.5, 'x': 1.0, 'y': 0.0}
SOURCE_PAPER = 'Hocken & Borchardt, NBSIR 79-1752 (1979)'
FUNCTIONS = ('predict_first_order', 'reduced_observation', 'design_first_order', 'predict_exact', 'residual_exact', 'jacobian_exact', 'normal_matrix', 'normal_inverse', 'normal_solve', 'estimate_first_order', 'estimate_exact', 'procrustes_terms')


def predict_first_order(pk, params, phi):
    """Position-1 coordinates predicted from position k, first order in alpha, beta, gamma (eq. 15).

    pk (..., 2): coordinates measured in position k (plate turned clockwise by phi + beta)
        [xk, yk]
    params (..., 5): parameters [alpha (rad), beta (rad), gamma (1), ex, ey (length unit)]
        [alpha, beta, gamma, ex, ey]
    phi (...): nominal clockwise turn of position k relative to position 1, rad
    returns (..., 2)
    """
    pk = as_arg(pk, 2, 'pk', 'predict_first_order')
    params = as_arg(params, 5, 'params', 'predict_first_order')
    phi = as_arg(phi, 0, 'phi', 'predict_first_order')
    xk = pk[..., 0]
    yk = pk[..., 1]
    alpha = params[..., 0]
    beta = params[..., 1]
    gamma = params[..., 2]
    ex = params[..., 3]
    ey = params[..., 4]
    phi = phi
    _x0 = numpy.sin(phi)
    _x1 = _x0*yk
    _x2 = numpy.cos(phi)
    _x3 = _x0*xk
    _x4 = _x2*yk
    _out = out_array((pk.shape[:-1], params.shape[:-1], phi.shape,), (2,))
    _out[..., 0] = -_x1*gamma - _x1 + _x2*xk - _x3*alpha - _x3*beta - _x4*beta + ex
    _out[..., 1] = _x1*alpha - _x1*beta + _x2*beta*xk - _x3*gamma + _x3 + _x4 + ey
    return _out


def reduced_observation(p1, pk, phi):
    """Reduced observation X1 - B(phi)^-1 Xk: the left side of the linear model (small numbers).

    p1 (..., 2): coordinates measured in position 1 (plate aligned with the machine axes)
        [x1, y1]
    pk (..., 2): coordinates measured in position k (plate turned clockwise by phi + beta)
        [xk, yk]
    phi (...): nominal clockwise turn of position k relative to position 1, rad
    returns (..., 2)
    """
    p1 = as_arg(p1, 2, 'p1', 'reduced_observation')
    pk = as_arg(pk, 2, 'pk', 'reduced_observation')
    phi = as_arg(phi, 0, 'phi', 'reduced_observation')
    x1 = p1[..., 0]
    y1 = p1[..., 1]
    xk = pk[..., 0]
    yk = pk[..., 1]
    phi = phi
    _x0 = numpy.sin(phi)
    _x1 = numpy.cos(phi)
    _out = out_array((p1.shape[:-1], pk.shape[:-1], phi.shape,), (2,))
    _out[..., 0] = _x0*yk - _x1*xk + x1
    _out[..., 1] = -_x0*xk - _x1*yk + y1
    return _out


def design_first_order(pk, phi):
    """Design matrix d(prediction)/d(alpha, beta, gamma, ex, ey) of the first-order model (eq. 15).

    pk (..., 2): coordinates measured in position k (plate turned clockwise by phi + beta)
        [xk, yk]
    phi (...): nominal clockwise turn of position k relative to position 1, rad
    returns (..., 2, 5)
    """
    pk = as_arg(pk, 2, 'pk', 'design_first_order')
    phi = as_arg(phi, 0, 'phi', 'design_first_order')
    xk = pk[..., 0]
    yk = pk[..., 1]
    phi = phi
    _x0 = numpy.sin(phi)
    _x1 = _x0*xk
    _x2 = -_x1
    _x3 = numpy.cos(phi)
    _x4 = _x0*yk
    _x5 = -_x4
    _out = out_array((pk.shape[:-1], phi.shape,), (2, 5))
    _out[..., 0, 0] = _x2
    _out[..., 0, 1] = -_x1 - _x3*yk
    _out[..., 0, 2] = _x5
    _out[..., 0, 3] = 1
    _out[..., 0, 4] = 0
    _out[..., 1, 0] = _x4
    _out[..., 1, 1] = _x3*xk + _x5
    _out[..., 1, 2] = _x2
    _out[..., 1, 3] = 0
    _out[..., 1, 4] = 1
    return _out


def predict_exact(pk, params, phi, w):
    """Position-1 coordinates predicted from position k, exact: A B(phi + beta)^-1 A^-1 Xk + eps.

    pk (..., 2): coordinates measured in position k (plate turned clockwise by phi + beta)
        [xk, yk]
    params (..., 5): parameters [alpha (rad), beta (rad), gamma (1), ex, ey (length unit)]
        [alpha, beta, gamma, ex, ey]
    phi (...): nominal clockwise turn of position k relative to position 1, rad
    w (...): share of gamma on the x scale: 1 (option 1), 0 (option 2), 1/2 (options 3, 4)
    returns (..., 2)
    """
    pk = as_arg(pk, 2, 'pk', 'predict_exact')
    params = as_arg(params, 5, 'params', 'predict_exact')
    phi = as_arg(phi, 0, 'phi', 'predict_exact')
    w = as_arg(w, 0, 'w', 'predict_exact')
    xk = pk[..., 0]
    yk = pk[..., 1]
    alpha = params[..., 0]
    beta = params[..., 1]
    gamma = params[..., 2]
    ex = params[..., 3]
    ey = params[..., 4]
    phi = phi
    w = w
    _x0 = beta + phi
    _x1 = numpy.sin(_x0)
    _x2 = _x1*alpha
    _x3 = numpy.cos(_x0)
    _x4 = gamma*w
    _x5 = _x4 + 1
    _x6 = _x5**(-1.0)
    _x7 = _x6*xk
    _x8 = gamma**2
    _x9 = 2*_x4 + _x8*w**2 + 1
    _x10 = -gamma
    _out = out_array((pk.shape[:-1], params.shape[:-1], phi.shape, w.shape,), (2,))
    _out[..., 0] = _x1*yk*(-_x9 - alpha**2)/(_x10 - _x8*w + _x9) + _x7*(-_x2 + _x3*_x5) + ex
    _out[..., 1] = _x1*_x7*(_x10 + _x5) + _x6*yk*(_x2 + _x3*_x4 + _x3) + ey
    return _out


def residual_exact(p1, pk, params, phi, w):
    """Residual X1 - (A B(phi + beta)^-1 A^-1 Xk + eps) of the exact model (any turn angle).

    p1 (..., 2): coordinates measured in position 1 (plate aligned with the machine axes)
        [x1, y1]
    pk (..., 2): coordinates measured in position k (plate turned clockwise by phi + beta)
        [xk, yk]
    params (..., 5): parameters [alpha (rad), beta (rad), gamma (1), ex, ey (length unit)]
        [alpha, beta, gamma, ex, ey]
    phi (...): nominal clockwise turn of position k relative to position 1, rad
    w (...): share of gamma on the x scale: 1 (option 1), 0 (option 2), 1/2 (options 3, 4)
    returns (..., 2)
    """
    p1 = as_arg(p1, 2, 'p1', 'residual_exact')
    pk = as_arg(pk, 2, 'pk', 'residual_exact')
    params = as_arg(params, 5, 'params', 'residual_exact')
    phi = as_arg(phi, 0, 'phi', 'residual_exact')
    w = as_arg(w, 0, 'w', 'residual_exact')
    x1 = p1[..., 0]
    y1 = p1[..., 1]
    xk = pk[..., 0]
    yk = pk[..., 1]
    alpha = params[..., 0]
    beta = params[..., 1]
    gamma = params[..., 2]
    ex = params[..., 3]
    ey = params[..., 4]
    phi = phi
    w = w
    _x0 = gamma*w
    _x1 = _x0 + 1
    _x2 = _x1**(-1.0)
    _x3 = beta + phi
    _x4 = numpy.sin(_x3)
    _x5 = _x4*alpha
    _x6 = numpy.cos(_x3)
    _x7 = gamma**2
    _x8 = 2*_x0 + _x7*w**2 + 1
    _x9 = -gamma
    _out = out_array((p1.shape[:-1], pk.shape[:-1], params.shape[:-1], phi.shape, w.shape,), (2,))
    _out[..., 0] = _x2*xk*(-_x1*_x6 + _x5) + _x4*yk*(_x8 + alpha**2)/(-_x7*w + _x8 + _x9) - ex + x1
    _out[..., 1] = _x2*(_x1*(-ey + y1) - _x4*xk*(_x1 + _x9) - yk*(_x0*_x6 + _x5 + _x6))
    return _out


def jacobian_exact(p1, pk, params, phi, w):
    """Jacobian d(residual_exact)/d(alpha, beta, gamma, ex, ey).

    p1 (..., 2): coordinates measured in position 1 (plate aligned with the machine axes)
        [x1, y1]
    pk (..., 2): coordinates measured in position k (plate turned clockwise by phi + beta)
        [xk, yk]
    params (..., 5): parameters [alpha (rad), beta (rad), gamma (1), ex, ey (length unit)]
        [alpha, beta, gamma, ex, ey]
    phi (...): nominal clockwise turn of position k relative to position 1, rad
    w (...): share of gamma on the x scale: 1 (option 1), 0 (option 2), 1/2 (options 3, 4)
    returns (..., 2, 5)
    """
    p1 = as_arg(p1, 2, 'p1', 'jacobian_exact')
    pk = as_arg(pk, 2, 'pk', 'jacobian_exact')
    params = as_arg(params, 5, 'params', 'jacobian_exact')
    phi = as_arg(phi, 0, 'phi', 'jacobian_exact')
    w = as_arg(w, 0, 'w', 'jacobian_exact')
    y1 = p1[..., 1]
    xk = pk[..., 0]
    yk = pk[..., 1]
    alpha = params[..., 0]
    beta = params[..., 1]
    gamma = params[..., 2]
    ey = params[..., 4]
    phi = phi
    w = w
    _x0 = beta + phi
    _x1 = numpy.sin(_x0)
    _x2 = gamma*w
    _x3 = _x2 + 1
    _x4 = _x3**(-1.0)
    _x5 = _x4*xk
    _x6 = -gamma
    _x7 = gamma**2
    _x8 = w**2
    _x9 = 2*_x2 + _x7*_x8 + 1
    _x10 = _x6 - _x7*w + _x9
    _x11 = _x10**(-1.0)
    _x12 = _x1*alpha
    _x13 = numpy.cos(_x0)
    _x14 = _x9 + alpha**2
    _x15 = _x13*yk
    _x16 = w/_x3**2
    _x17 = 2*_x8*gamma + 2*w
    _x18 = xk*(_x3 + _x6)
    _x19 = -ey + y1
    _out = out_array((p1.shape[:-1], pk.shape[:-1], params.shape[:-1], phi.shape, w.shape,), (2, 5))
    _out[..., 0, 0] = _x1*_x5 + 2*_x11*_x12*yk
    _out[..., 0, 1] = _x11*_x14*_x15 + _x5*(_x1*_x3 + _x13*alpha)
    _out[..., 0, 2] = _x1*_x11*_x17*yk + _x1*_x14*yk*(-_x17 + 2*gamma*w + 1)/_x10**2 - _x13*_x5*w - _x16*xk*(_x12 - _x13*_x3)
    _out[..., 0, 3] = -1
    _out[..., 0, 4] = 0
    _out[..., 1, 0] = -_x1*_x4*yk
    _out[..., 1, 1] = _x4*(-_x13*_x18 - yk*(-_x1*_x2 - _x1 + _x13*alpha))
    _out[..., 1, 2] = -_x16*(-_x1*_x18 + _x19*_x3 - yk*(_x12 + _x13*_x2 + _x13)) + _x4*(-_x1*xk*(w - 1) - _x15*w + _x19*w)
    _out[..., 1, 3] = 0
    _out[..., 1, 4] = -_x3*_x4
    return _out


def normal_matrix(sums):
    """Normal matrix of (alpha, beta, gamma) at phi = pi/2 in the point sums (ALBE2/ALBE3).

    sums (..., 7): sums over points of x2^2, y2^2, x2 y2, x2 u, y2 u, x2 v, y2 v with u = x1 + y2, v = y1 - x2 (centred for ALBE3)
        [Sxx, Syy, Sxy, Sxu, Syu, Sxv, Syv]
    returns (..., 3, 3)
    """
    sums = as_arg(sums, 7, 'sums', 'normal_matrix')
    Sxx = sums[..., 0]
    Syy = sums[..., 1]
    Sxy = sums[..., 2]
    _x0 = Sxx + Syy
    _x1 = Sxx - Syy
    _x2 = 2*Sxy
    _out = out_array((sums.shape[:-1],), (3, 3))
    _out[..., 0, 0] = _x0
    _out[..., 0, 1] = _x1
    _out[..., 0, 2] = 0
    _out[..., 1, 0] = _x1
    _out[..., 1, 1] = _x0
    _out[..., 1, 2] = _x2
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = _x2
    _out[..., 2, 2] = _x0
    return _out


def normal_inverse(sums):
    """Inverse of normal_matrix in closed form (covariance / sigma^2 of alpha, beta, gamma).

    sums (..., 7): sums over points of x2^2, y2^2, x2 y2, x2 u, y2 u, x2 v, y2 v with u = x1 + y2, v = y1 - x2 (centred for ALBE3)
        [Sxx, Syy, Sxy, Sxu, Syu, Sxv, Syv]
    returns (..., 3, 3)
    """
    sums = as_arg(sums, 7, 'sums', 'normal_inverse')
    Sxx = sums[..., 0]
    Syy = sums[..., 1]
    Sxy = sums[..., 2]
    _x0 = Sxx + Syy
    _x1 = _x0**(-1.0)
    _x2 = 2*Sxy
    _x3 = Sxx*Syy
    _x4 = (-Sxy**2 + _x3)**(-1.0)
    _x5 = (1/4)*_x4
    _x6 = Sxx - Syy
    _x7 = -_x5*_x6
    _x8 = (1/2)*Sxy*_x4
    _x9 = _x1*_x6*_x8
    _x10 = -_x8
    _out = out_array((sums.shape[:-1],), (3, 3))
    _out[..., 0, 0] = _x1*_x5*(_x0 - _x2)*(_x0 + _x2)
    _out[..., 0, 1] = _x7
    _out[..., 0, 2] = _x9
    _out[..., 1, 0] = _x7
    _out[..., 1, 1] = _x0*_x5
    _out[..., 1, 2] = _x10
    _out[..., 2, 0] = _x9
    _out[..., 2, 1] = _x10
    _out[..., 2, 2] = _x1*_x3*_x4
    return _out


def normal_solve(sums):
    """Closed-form solution (alpha, beta, gamma) of the normal equations at phi = pi/2.

    sums (..., 7): sums over points of x2^2, y2^2, x2 y2, x2 u, y2 u, x2 v, y2 v with u = x1 + y2, v = y1 - x2 (centred for ALBE3)
        [Sxx, Syy, Sxy, Sxu, Syu, Sxv, Syv]
    returns (..., 3)
    """
    sums = as_arg(sums, 7, 'sums', 'normal_solve')
    Sxx = sums[..., 0]
    Syy = sums[..., 1]
    Sxy = sums[..., 2]
    Sxu = sums[..., 3]
    Syu = sums[..., 4]
    Sxv = sums[..., 5]
    Syv = sums[..., 6]
    _x0 = (Sxx + Syy)**(-1.0)
    _x1 = Sxx*Syy
    _x2 = Sxv*Sxy
    _x3 = Sxy*Syu
    _x4 = Sxy**2
    _x5 = 2*_x4
    _x6 = (_x1 - _x4)**(-1.0)
    _x7 = (1/2)*_x6
    _x8 = Sxu*Syy
    _x9 = Sxx*Syv
    _out = out_array((sums.shape[:-1],), (3,))
    _out[..., 0] = -_x0*_x7*(Sxu*Syy**2 + Sxu*_x1 - Sxu*_x5 - Sxx**2*Syv + Sxx*_x2 + Sxx*_x3 - Syv*_x1 + Syv*_x5 - Syy*_x2 - Syy*_x3)
    _out[..., 1] = -_x7*(-_x2 - _x3 + _x8 + _x9)
    _out[..., 2] = _x0*_x6*(-Sxv*_x1 + Sxy*_x8 + Sxy*_x9 - Syu*_x1)
    return _out


def estimate_first_order(pk, params, phi, w):
    """Gage coordinates estimated from position k, first order: B(phi + beta)^-1 A^-1 Xk (position 1: phi = 0 and beta = 0); eq. 20 is the mean over positions.

    pk (..., 2): coordinates measured in position k (plate turned clockwise by phi + beta)
        [xk, yk]
    params (..., 5): parameters [alpha (rad), beta (rad), gamma (1), ex, ey (length unit)]
        [alpha, beta, gamma, ex, ey]
    phi (...): nominal clockwise turn of position k relative to position 1, rad
    w (...): share of gamma on the x scale: 1 (option 1), 0 (option 2), 1/2 (options 3, 4)
    returns (..., 2)
    """
    pk = as_arg(pk, 2, 'pk', 'estimate_first_order')
    params = as_arg(params, 5, 'params', 'estimate_first_order')
    phi = as_arg(phi, 0, 'phi', 'estimate_first_order')
    w = as_arg(w, 0, 'w', 'estimate_first_order')
    xk = pk[..., 0]
    yk = pk[..., 1]
    alpha = params[..., 0]
    beta = params[..., 1]
    gamma = params[..., 2]
    phi = phi
    w = w
    _x0 = numpy.sin(phi)
    _x1 = _x0*yk
    _x2 = numpy.cos(phi)
    _x3 = _x0*xk
    _x4 = _x2*yk
    _x5 = _x2*xk
    _x6 = gamma*w
    _x7 = _x4*gamma
    _out = out_array((pk.shape[:-1], params.shape[:-1], phi.shape, w.shape,), (2,))
    _out[..., 0] = _x0*gamma*w*yk - _x1*gamma - _x1 + _x2*alpha*yk + _x2*xk - _x3*beta - _x4*beta - _x5*_x6
    _out[..., 1] = _x1*alpha - _x1*beta - _x3*_x6 + _x3 + _x4 + _x5*beta - _x7*w + _x7
    return _out


def estimate_exact(pk, params, phi, w):
    """Gage coordinates estimated from position k, exact: B(phi + beta)^-1 A^-1 Xk.

    pk (..., 2): coordinates measured in position k (plate turned clockwise by phi + beta)
        [xk, yk]
    params (..., 5): parameters [alpha (rad), beta (rad), gamma (1), ex, ey (length unit)]
        [alpha, beta, gamma, ex, ey]
    phi (...): nominal clockwise turn of position k relative to position 1, rad
    w (...): share of gamma on the x scale: 1 (option 1), 0 (option 2), 1/2 (options 3, 4)
    returns (..., 2)
    """
    pk = as_arg(pk, 2, 'pk', 'estimate_exact')
    params = as_arg(params, 5, 'params', 'estimate_exact')
    phi = as_arg(phi, 0, 'phi', 'estimate_exact')
    w = as_arg(w, 0, 'w', 'estimate_exact')
    xk = pk[..., 0]
    yk = pk[..., 1]
    alpha = params[..., 0]
    beta = params[..., 1]
    gamma = params[..., 2]
    phi = phi
    w = w
    _x0 = beta + phi
    _x1 = numpy.cos(_x0)
    _x2 = gamma*w
    _x3 = _x2 + 1
    _x4 = xk/_x3
    _x5 = numpy.sin(_x0)
    _x6 = -gamma
    _x7 = (_x3 + _x6)**(-1.0)
    _x8 = gamma**2
    _x9 = alpha/(2*_x2 + _x6 + _x8*w**2 - _x8*w + 1)
    _out = out_array((pk.shape[:-1], params.shape[:-1], phi.shape, w.shape,), (2,))
    _out[..., 0] = _x1*_x4 + yk*(_x1*_x9 - _x5*_x7)
    _out[..., 1] = _x4*_x5 + yk*(_x1*_x7 + _x5*_x9)
    return _out


def procrustes_terms(p1, pk):
    """Per-point terms whose sums give the measured clockwise turn atan2(s0, s1) of centred data.

    p1 (..., 2): coordinates measured in position 1 (plate aligned with the machine axes)
        [x1, y1]
    pk (..., 2): coordinates measured in position k (plate turned clockwise by phi + beta)
        [xk, yk]
    returns (..., 2)
    """
    p1 = as_arg(p1, 2, 'p1', 'procrustes_terms')
    pk = as_arg(pk, 2, 'pk', 'procrustes_terms')
    x1 = p1[..., 0]
    y1 = p1[..., 1]
    xk = pk[..., 0]
    yk = pk[..., 1]
    _out = out_array((p1.shape[:-1], pk.shape[:-1],), (2,))
    _out[..., 0] = -x1*yk + xk*y1
    _out[..., 1] = x1*xk + y1*yk
    return _out
