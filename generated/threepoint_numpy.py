# -----------------------------------------------------------------------------
# GENERATED FILE - DO NOT EDIT.
# Generator: python -m derive (threepoint); source: derive/threepoint.py
# Target: NumPy (vectorised, broadcasting).  Regenerate with `python -m derive`; CI runs `python -m derive --check`.
# Inputs (machine spec, SymPy/CasADi versions, hash of derive/) are in manifest.json.
# -----------------------------------------------------------------------------
"""Three-point identification of the six error motions of one axis (Zhang & Hu), from derive/threepoint.py.

NumPy implementation."""
import numpy

from mtcal._gensupport import as_arg, out_array

POINTS = ('P', 'Q', 'K')
SELECTED_ROWS = ('P_x', 'P_y', 'Q_x', 'Q_z', 'K_y', 'K_z')
ERROR_PARTS = ('E_X', 'E_Y', 'E_Z', 'E_A', 'E_B', 'E_C')
FRAMES = {'dmu50_B': 'frame_dmu50_B',
 'dmu50_C': 'frame_dmu50_C',
 'dmu50_X': 'frame_dmu50_X',
 'dmu50_Y': 'frame_dmu50_Y',
 'dmu50_Z': 'frame_dmu50_Z',
 'headbc_B': 'frame_headbc_B',
 'headbc_C': 'frame_headbc_C',
 'headbc_X': 'frame_headbc_X',
 'headbc_Y': 'frame_headbc_Y',
 'headbc_Z': 'frame_headbc_Z',
 'xyzac_A': 'frame_xyzac_A',
 'xyzac_C': 'frame_xyzac_C',
 'xyzac_X': 'frame_xyzac_X',
 'xyzac_Y': 'frame_xyzac_Y',
 'xyzac_Z': 'frame_xyzac_Z'}
FRAME_SIDES = {'dmu50_B': 'table',
 'dmu50_C': 'table',
 'dmu50_X': 'tool',
 'dmu50_Y': 'tool',
 'dmu50_Z': 'tool',
 'headbc_B': 'tool',
 'headbc_C': 'table',
 'headbc_X': 'tool',
 'headbc_Y': 'tool',
 'headbc_Z': 'tool',
 'xyzac_A': 'table',
 'xyzac_C': 'table',
 'xyzac_X': 'tool',
 'xyzac_Y': 'tool',
 'xyzac_Z': 'tool'}
FUNCTIONS = ('rigid_point', 'point_rows', 'design_matrix', 'solve_selected', 'selected_denominator', 'ls_solve', 'ls_residuals', 'point_shape', 'frame_dmu50_X', 'frame_dmu50_Y', 'frame_dmu50_Z', 'frame_dmu50_B', 'frame_dmu50_C', 'frame_headbc_X', 'frame_headbc_Y', 'frame_headbc_Z', 'frame_headbc_B', 'frame_headbc_C', 'frame_xyzac_X', 'frame_xyzac_Y', 'frame_xyzac_Z', 'frame_xyzac_A', 'frame_xyzac_C')


def rigid_point(point, motion):
    """The point moved exactly by Trans(t) Rz(c) Ry(b) Rx(a) (mm): a station's alignment correction or error; its derivative at zero motion is point_rows.

    point (..., 3): point, mm
        [px, py, pz]
    motion (..., 6): small rigid motion (tx, ty, tz mm; rotations about x, y, z rad)
        [mx, my, mz, ma, mb, mc]
    returns (..., 3)
    """
    point = as_arg(point, 3, 'point', 'rigid_point')
    motion = as_arg(motion, 6, 'motion', 'rigid_point')
    px = point[..., 0]
    py = point[..., 1]
    pz = point[..., 2]
    mx = motion[..., 0]
    my = motion[..., 1]
    mz = motion[..., 2]
    ma = motion[..., 3]
    mb = motion[..., 4]
    mc = motion[..., 5]
    _x0 = numpy.cos(mc)
    _x1 = numpy.cos(mb)
    _x2 = _x1*px
    _x3 = numpy.sin(ma)
    _x4 = numpy.sin(mc)
    _x5 = _x3*_x4
    _x6 = numpy.sin(mb)
    _x7 = numpy.cos(ma)
    _x8 = _x0*_x7
    _x9 = _x0*_x3
    _out = out_array((point.shape[:-1], motion.shape[:-1],), (3,))
    _out[..., 0] = _x0*_x2 + mx + py*(-_x4*_x7 + _x6*_x9) + pz*(_x5 + _x6*_x8)
    _out[..., 1] = _x2*_x4 + my + py*(_x5*_x6 + _x8) + pz*(_x4*_x6*_x7 - _x9)
    _out[..., 2] = _x1*_x3*py + _x1*_x7*pz - _x6*px + mz
    return _out


def point_rows(point):
    """d(displacement of the point) / d(E_X, E_Y, E_Z, E_A, E_B, E_C) in F: [I | -[p]x] (per mm, per rad).

    point (..., 3): nominal point in the axis frame F, mm
        [px, py, pz]
    returns (..., 3, 6)
    """
    point = as_arg(point, 3, 'point', 'point_rows')
    px = point[..., 0]
    py = point[..., 1]
    pz = point[..., 2]
    _out = out_array((point.shape[:-1],), (3, 6))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = 0
    _out[..., 0, 4] = pz
    _out[..., 0, 5] = -py
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 1
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = -pz
    _out[..., 1, 4] = 0
    _out[..., 1, 5] = px
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = py
    _out[..., 2, 4] = -px
    _out[..., 2, 5] = 0
    return _out


def design_matrix(points):
    """The nine three-point equations (rows P_x, P_y, P_z, Q_x, ..., K_z; thesis eq. 31 / 3.5): deltas = design_matrix @ (E_X, E_Y, E_Z, E_A, E_B, E_C).

    points (..., 9): nominal points P, Q, K in the axis frame F, mm
        [xP, yP, zP, xQ, yQ, zQ, xK, yK, zK]
    returns (..., 9, 6)
    """
    points = as_arg(points, 9, 'points', 'design_matrix')
    xP = points[..., 0]
    yP = points[..., 1]
    zP = points[..., 2]
    xQ = points[..., 3]
    yQ = points[..., 4]
    zQ = points[..., 5]
    xK = points[..., 6]
    yK = points[..., 7]
    zK = points[..., 8]
    _out = out_array((points.shape[:-1],), (9, 6))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = 0
    _out[..., 0, 4] = zP
    _out[..., 0, 5] = -yP
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 1
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = -zP
    _out[..., 1, 4] = 0
    _out[..., 1, 5] = xP
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = yP
    _out[..., 2, 4] = -xP
    _out[..., 2, 5] = 0
    _out[..., 3, 0] = 1
    _out[..., 3, 1] = 0
    _out[..., 3, 2] = 0
    _out[..., 3, 3] = 0
    _out[..., 3, 4] = zQ
    _out[..., 3, 5] = -yQ
    _out[..., 4, 0] = 0
    _out[..., 4, 1] = 1
    _out[..., 4, 2] = 0
    _out[..., 4, 3] = -zQ
    _out[..., 4, 4] = 0
    _out[..., 4, 5] = xQ
    _out[..., 5, 0] = 0
    _out[..., 5, 1] = 0
    _out[..., 5, 2] = 1
    _out[..., 5, 3] = yQ
    _out[..., 5, 4] = -xQ
    _out[..., 5, 5] = 0
    _out[..., 6, 0] = 1
    _out[..., 6, 1] = 0
    _out[..., 6, 2] = 0
    _out[..., 6, 3] = 0
    _out[..., 6, 4] = zK
    _out[..., 6, 5] = -yK
    _out[..., 7, 0] = 0
    _out[..., 7, 1] = 1
    _out[..., 7, 2] = 0
    _out[..., 7, 3] = -zK
    _out[..., 7, 4] = 0
    _out[..., 7, 5] = xK
    _out[..., 8, 0] = 0
    _out[..., 8, 1] = 0
    _out[..., 8, 2] = 1
    _out[..., 8, 3] = yK
    _out[..., 8, 4] = -xK
    _out[..., 8, 5] = 0
    return _out


def solve_selected(points, deltas):
    """Closed-form solution (E_X, E_Y, E_Z mm; E_A, E_B, E_C rad) of the six equations P_x, P_y, Q_x, Q_z, K_y, K_z (Zhang & Hu; thesis eqs. 32-34); infinite/NaN where selected_denominator is zero.

    points (..., 9): nominal points P, Q, K in the axis frame F, mm
        [xP, yP, zP, xQ, yQ, zQ, xK, yK, zK]
    deltas (..., 9): measured minus nominal position of P, Q, K, expressed in F, mm
        [dxP, dyP, dzP, dxQ, dyQ, dzQ, dxK, dyK, dzK]
    returns (..., 6)
    """
    points = as_arg(points, 9, 'points', 'solve_selected')
    deltas = as_arg(deltas, 9, 'deltas', 'solve_selected')
    xP = points[..., 0]
    yP = points[..., 1]
    zP = points[..., 2]
    xQ = points[..., 3]
    yQ = points[..., 4]
    zQ = points[..., 5]
    xK = points[..., 6]
    yK = points[..., 7]
    zK = points[..., 8]
    dxP = deltas[..., 0]
    dyP = deltas[..., 1]
    dxQ = deltas[..., 3]
    dzQ = deltas[..., 5]
    dyK = deltas[..., 7]
    dzK = deltas[..., 8]
    _x0 = xK*zP
    _x1 = _x0*yK
    _x2 = _x0*yP
    _x3 = xK*yQ
    _x4 = _x3*zK
    _x5 = _x3*zQ
    _x6 = yK*zQ
    _x7 = _x6*xP
    _x8 = yQ*zP
    _x9 = _x8*xP
    _x10 = yP*zK
    _x11 = _x10*xQ
    _x12 = _x8*xQ
    _x13 = _x6*xK
    _x14 = _x10*xK
    _x15 = xP*zP
    _x16 = _x15*yK
    _x17 = xP*zQ
    _x18 = _x17*yQ
    _x19 = xQ*yP
    _x20 = _x19*zP
    _x21 = xQ*yQ
    _x22 = _x21*zK
    _x23 = (-2*_x0*yQ + _x1 + _x11 + _x12 - _x13 - _x14 - _x16 - _x18 + _x2 - _x20 - _x22 + _x4 + _x5 + _x7 + _x9)**(-1.0)
    _x24 = _x0*dxP
    _x25 = _x0*dxQ
    _x26 = _x6*dyK
    _x27 = dyP*yK
    _x28 = dyP*yQ
    _x29 = _x28*yP
    _x30 = _x10*dzK
    _x31 = yP*zP
    _x32 = _x31*dzQ
    _x33 = _x8*dzQ
    _x34 = yQ**2
    _x35 = _x34*dyK
    _x36 = zP**2
    _x37 = _x36*dzK
    _x38 = dyK*yK
    _x39 = dyK*yQ
    _x40 = _x39*yP
    _x41 = _x6*dyP
    _x42 = _x31*dzK
    _x43 = _x8*dzK
    _x44 = _x10*dzQ
    _x45 = _x34*dyP
    _x46 = _x36*dzQ
    _x47 = dxP*xP
    _x48 = _x47*xQ
    _x49 = dxQ*xK
    _x50 = _x49*xP
    _x51 = _x17*dzK
    _x52 = _x0*dzQ
    _x53 = _x15*dzQ
    _x54 = xK**2
    _x55 = _x54*dxP
    _x56 = _x47*xK
    _x57 = dxP*xQ
    _x58 = dxQ*xP
    _x59 = _x58*xQ
    _x60 = _x0*dzK
    _x61 = _x15*dzK
    _x62 = _x17*dzQ
    _x63 = _x54*dxQ
    _x64 = _x49*xQ
    _x65 = _x3*dyK
    _x66 = _x21*dyK
    _x67 = _x19*dyP
    _x68 = dxP*xK
    _x69 = _x68*xQ
    _x70 = _x19*dyK
    _x71 = _x3*dyP
    _x72 = _x21*dyP
    _x73 = xK*yP
    _x74 = xK*zQ
    _x75 = yQ*zK
    _x76 = dxQ*xQ
    _x77 = dzK*zP
    _x78 = zK*zQ
    _x79 = dzQ*zP
    _out = out_array((points.shape[:-1], deltas.shape[:-1],), (6,))
    _out[..., 0] = -_x23*(-_x1*dxQ - _x11*dxQ - _x12*dxP + _x13*dxP + _x14*dxQ + _x16*dxQ + _x18*dxP - _x2*dxQ + _x20*dxQ + _x22*dxP + _x24*yQ + _x25*yQ + _x26*yP + _x27*_x8 + _x29*zQ + _x30*zQ + _x32*zQ + _x33*zK + _x35*zP + _x37*yQ - _x38*_x8 - _x4*dxP - _x40*zQ - _x41*yP - _x42*zQ - _x43*zK - _x44*zQ - _x45*zP - _x46*yQ - _x5*dxP - _x7*dxP - _x9*dxQ)
    _out[..., 1] = _x23*(-_x0*_x28 - _x0*_x39 - _x0*_x57 + _x1*dyP + _x11*dyP + _x12*dyK - _x13*dyP - _x14*dyP - _x16*dyK - _x18*dyK + _x2*dyK - _x20*dyK - _x22*dyP + _x25*xQ + _x37*xK + _x4*dyP - _x46*xK + _x48*zK + _x5*dyP + _x50*zK + _x51*zK + _x52*zQ + _x53*zK + _x55*zP - _x56*zK - _x59*zK - _x60*zQ - _x61*zK - _x62*zK - _x63*zP + _x7*dyK + _x9*dyK)
    _out[..., 2] = -_x23*(-_x1*dzQ - _x11*dzK - _x12*dzK + _x13*dzQ + _x14*dzQ + _x16*dzQ + _x18*dzK - _x2*dzQ + _x20*dzK + _x22*dzK - _x3*_x47 + _x3*_x58 - _x35*xK - _x4*dzQ + _x45*xK + _x48*yK - _x5*dzK + _x52*yQ + _x55*yQ - _x59*yK + _x60*yQ - _x63*yQ + _x64*yK + _x65*yP + _x66*yK + _x67*yK - _x69*yK - _x7*dzQ - _x70*yK - _x71*yP - _x72*yK - _x9*dzK)
    _out[..., 3] = _x23*(_x48 + _x50 + _x51 - _x52 + _x53 + _x55 - _x56 - _x59 + _x60 - _x61 - _x62 - _x63 + _x64 - _x65 + _x66 + _x67 - _x69 - _x70 + _x71 - _x72 + _x73*dyK - _x73*dyP - _x74*dzK + _x74*dzQ)
    _out[..., 4] = _x23*(-_x27*yP + _x28*yK + _x29 - _x3*dxP + _x3*dxQ + _x30 + _x32 - _x33 + _x35 + _x38*yP - _x38*yQ - _x40 - _x42 + _x43 - _x44 - _x45 - _x47*yK + _x47*yQ - _x49*yK + _x58*yK - _x58*yQ + _x68*yK - _x75*dzK + _x75*dzQ)
    _out[..., 5] = _x23*(-_x24 + _x25 - _x26 - _x27*zP - _x28*zQ - _x37 + _x38*zP + _x39*zQ + _x41 + _x46 - _x49*zK - _x57*zK + _x57*zP + _x68*zK + _x76*zK - _x76*zP + _x77*zK + _x77*zQ - _x78*dzK + _x78*dzQ - _x79*zK - _x79*zQ - _x8*dyK + _x8*dyP)
    return _out


def selected_denominator(points):
    """Determinant of the six selected equations (N of eq. 34 up to sign), mm^3.

    points (..., 9): nominal points P, Q, K in the axis frame F, mm
        [xP, yP, zP, xQ, yQ, zQ, xK, yK, zK]
    returns (..., 1)
    """
    points = as_arg(points, 9, 'points', 'selected_denominator')
    xP = points[..., 0]
    yP = points[..., 1]
    zP = points[..., 2]
    xQ = points[..., 3]
    yQ = points[..., 4]
    zQ = points[..., 5]
    xK = points[..., 6]
    yK = points[..., 7]
    zK = points[..., 8]
    _x0 = xK*zP
    _x1 = xK*yQ
    _x2 = yK*zQ
    _x3 = yQ*zP
    _x4 = yP*zK
    _out = out_array((points.shape[:-1],), (1,))
    _out[..., 0] = _x0*yK + _x0*yP - 2*_x0*yQ + _x1*zK + _x1*zQ - _x2*xK + _x2*xP + _x3*xP + _x3*xQ - _x4*xK + _x4*xQ - xP*yK*zP - xP*yQ*zQ - xQ*yP*zP - xQ*yQ*zK
    return _out


def ls_solve(points, deltas):
    """Least-squares solution of all nine equations (E_X, E_Y, E_Z mm; E_A, E_B, E_C rad), centred closed form (see module doc).

    points (..., 9): nominal points P, Q, K in the axis frame F, mm
        [xP, yP, zP, xQ, yQ, zQ, xK, yK, zK]
    deltas (..., 9): measured minus nominal position of P, Q, K, expressed in F, mm
        [dxP, dyP, dzP, dxQ, dyQ, dzQ, dxK, dyK, dzK]
    returns (..., 6)
    """
    points = as_arg(points, 9, 'points', 'ls_solve')
    deltas = as_arg(deltas, 9, 'deltas', 'ls_solve')
    xP = points[..., 0]
    yP = points[..., 1]
    zP = points[..., 2]
    xQ = points[..., 3]
    yQ = points[..., 4]
    zQ = points[..., 5]
    xK = points[..., 6]
    yK = points[..., 7]
    zK = points[..., 8]
    dxP = deltas[..., 0]
    dyP = deltas[..., 1]
    dzP = deltas[..., 2]
    dxQ = deltas[..., 3]
    dyQ = deltas[..., 4]
    dzQ = deltas[..., 5]
    dxK = deltas[..., 6]
    dyK = deltas[..., 7]
    dzK = deltas[..., 8]
    _x0 = (1/3)*dxQ
    _x1 = (1/3)*yQ
    _x2 = (1/3)*yK
    _x3 = (1/3)*yP
    _x4 = _x2 + _x3
    _x5 = _x1 + _x4
    _x6 = (1/3)*xK
    _x7 = (1/3)*xP
    _x8 = _x6 + _x7
    _x9 = -_x8 + (2/3)*xQ
    _x10 = -_x4 + (2/3)*yQ
    _x11 = (1/3)*xQ
    _x12 = -_x11 - _x6 + (2/3)*xP
    _x13 = -_x1 - _x2 + (2/3)*yP
    _x14 = -_x11 - _x7 + (2/3)*xK
    _x15 = -_x1 - _x3 + (2/3)*yK
    _x16 = -_x10*_x9 - _x12*_x13 - _x14*_x15
    _x17 = _x16**2
    _x18 = _x12**2 + _x14**2 + _x9**2
    _x19 = _x10**2 + _x13**2 + _x15**2
    _x20 = _x18 + _x19
    _x21 = (1/3)*zK
    _x22 = (1/3)*zP
    _x23 = _x21 + _x22
    _x24 = -_x23 + (2/3)*zQ
    _x25 = (1/3)*zQ
    _x26 = -_x21 - _x25 + (2/3)*zP
    _x27 = -_x22 - _x25 + (2/3)*zK
    _x28 = -_x12*_x26 - _x14*_x27 - _x24*_x9
    _x29 = _x28**2
    _x30 = _x24**2 + _x26**2 + _x27**2
    _x31 = _x18 + _x30
    _x32 = -_x10*_x24 - _x13*_x26 - _x15*_x27
    _x33 = _x32**2
    _x34 = _x19 + _x30
    _x35 = (2*_x16*_x28*_x32 - _x17*_x20 + _x20*_x31*_x34 - _x29*_x31 - _x33*_x34)**(-1.0)
    _x36 = (1/3)*dxK
    _x37 = (1/3)*dxP
    _x38 = _x36 + _x37
    _x39 = -_x38 + (2/3)*dxQ
    _x40 = -_x0 - _x36 + (2/3)*dxP
    _x41 = -_x0 - _x37 + (2/3)*dxK
    _x42 = (1/3)*dyK
    _x43 = (1/3)*dyP
    _x44 = _x42 + _x43
    _x45 = -_x44 + (2/3)*dyQ
    _x46 = (1/3)*dyQ
    _x47 = -_x42 - _x46 + (2/3)*dyP
    _x48 = -_x43 - _x46 + (2/3)*dyK
    _x49 = -_x10*_x39 + _x12*_x47 - _x13*_x40 + _x14*_x48 - _x15*_x41 + _x45*_x9
    _x50 = (1/3)*dzK
    _x51 = (1/3)*dzP
    _x52 = _x50 + _x51
    _x53 = -_x52 + (2/3)*dzQ
    _x54 = (1/3)*dzQ
    _x55 = -_x50 - _x54 + (2/3)*dzP
    _x56 = -_x51 - _x54 + (2/3)*dzK
    _x57 = -_x12*_x55 - _x14*_x56 + _x24*_x39 + _x26*_x40 + _x27*_x41 - _x53*_x9
    _x58 = _x16*_x28 - _x32*_x34
    _x59 = _x10*_x53 + _x13*_x55 + _x15*_x56 - _x24*_x45 - _x26*_x47 - _x27*_x48
    _x60 = _x16*_x32 - _x28*_x31
    _x61 = _x35*(_x49*(-_x17 + _x31*_x34) + _x57*_x58 + _x59*_x60)
    _x62 = _x23 + _x25
    _x63 = -_x16*_x20 + _x28*_x32
    _x64 = _x35*(_x49*_x58 + _x57*(_x20*_x34 - _x29) + _x59*_x63)
    _x65 = _x35*(_x49*_x60 + _x57*_x63 + _x59*(_x20*_x31 - _x33))
    _x66 = _x11 + _x8
    _out = out_array((points.shape[:-1], deltas.shape[:-1],), (6,))
    _out[..., 0] = _x0 + _x38 + _x5*_x61 - _x62*_x64
    _out[..., 1] = _x44 + _x46 - _x61*_x66 + _x62*_x65
    _out[..., 2] = -_x5*_x65 + _x52 + _x54 + _x64*_x66
    _out[..., 3] = _x65
    _out[..., 4] = _x64
    _out[..., 5] = _x61
    return _out


def ls_residuals(points, deltas):
    """Residuals (mm) deltas - design_matrix @ ls_solve of the nine equations (P_x ... K_z).

    points (..., 9): nominal points P, Q, K in the axis frame F, mm
        [xP, yP, zP, xQ, yQ, zQ, xK, yK, zK]
    deltas (..., 9): measured minus nominal position of P, Q, K, expressed in F, mm
        [dxP, dyP, dzP, dxQ, dyQ, dzQ, dxK, dyK, dzK]
    returns (..., 9)
    """
    points = as_arg(points, 9, 'points', 'ls_residuals')
    deltas = as_arg(deltas, 9, 'deltas', 'ls_residuals')
    xP = points[..., 0]
    yP = points[..., 1]
    zP = points[..., 2]
    xQ = points[..., 3]
    yQ = points[..., 4]
    zQ = points[..., 5]
    xK = points[..., 6]
    yK = points[..., 7]
    zK = points[..., 8]
    dxP = deltas[..., 0]
    dyP = deltas[..., 1]
    dzP = deltas[..., 2]
    dxQ = deltas[..., 3]
    dyQ = deltas[..., 4]
    dzQ = deltas[..., 5]
    dxK = deltas[..., 6]
    dyK = deltas[..., 7]
    dzK = deltas[..., 8]
    _x0 = (1/3)*xK
    _x1 = (1/3)*xP
    _x2 = _x0 + _x1
    _x3 = -_x2 + (2/3)*xQ
    _x4 = (1/3)*yK
    _x5 = (1/3)*yP
    _x6 = _x4 + _x5
    _x7 = -_x6 + (2/3)*yQ
    _x8 = (1/3)*xQ
    _x9 = -_x0 - _x8 + (2/3)*xP
    _x10 = (1/3)*yQ
    _x11 = -_x10 - _x4 + (2/3)*yP
    _x12 = -_x1 - _x8 + (2/3)*xK
    _x13 = -_x10 - _x5 + (2/3)*yK
    _x14 = -_x11*_x9 - _x12*_x13 - _x3*_x7
    _x15 = _x14**2
    _x16 = _x12**2 + _x3**2 + _x9**2
    _x17 = _x11**2 + _x13**2 + _x7**2
    _x18 = _x16 + _x17
    _x19 = (1/3)*zK
    _x20 = (1/3)*zP
    _x21 = _x19 + _x20
    _x22 = -_x21 + (2/3)*zQ
    _x23 = (1/3)*zQ
    _x24 = -_x19 - _x23 + (2/3)*zP
    _x25 = -_x20 - _x23 + (2/3)*zK
    _x26 = -_x12*_x25 - _x22*_x3 - _x24*_x9
    _x27 = _x26**2
    _x28 = _x22**2 + _x24**2 + _x25**2
    _x29 = _x16 + _x28
    _x30 = -_x11*_x24 - _x13*_x25 - _x22*_x7
    _x31 = _x30**2
    _x32 = _x17 + _x28
    _x33 = (2*_x14*_x26*_x30 - _x15*_x18 + _x18*_x29*_x32 - _x27*_x29 - _x31*_x32)**(-1.0)
    _x34 = (1/3)*dxK
    _x35 = (1/3)*dxP
    _x36 = _x34 + _x35 - 2/3*dxQ
    _x37 = -_x36
    _x38 = (1/3)*dxQ
    _x39 = _x34 + _x38 - 2/3*dxP
    _x40 = -_x39
    _x41 = _x35 + _x38 - 2/3*dxK
    _x42 = -_x41
    _x43 = (1/3)*dzK
    _x44 = (1/3)*dzP
    _x45 = _x43 + _x44 - 2/3*dzQ
    _x46 = -_x45
    _x47 = (1/3)*dzQ
    _x48 = _x43 + _x47 - 2/3*dzP
    _x49 = -_x48
    _x50 = _x44 + _x47 - 2/3*dzK
    _x51 = -_x50
    _x52 = -_x12*_x51 + _x22*_x37 + _x24*_x40 + _x25*_x42 - _x3*_x46 - _x49*_x9
    _x53 = (1/3)*dyK
    _x54 = (1/3)*dyP
    _x55 = _x53 + _x54 - 2/3*dyQ
    _x56 = -_x55
    _x57 = (1/3)*dyQ
    _x58 = _x53 + _x57 - 2/3*dyP
    _x59 = -_x58
    _x60 = _x54 + _x57 - 2/3*dyK
    _x61 = -_x60
    _x62 = -_x11*_x40 + _x12*_x61 - _x13*_x42 + _x3*_x56 - _x37*_x7 + _x59*_x9
    _x63 = _x14*_x26 - _x30*_x32
    _x64 = _x11*_x49 + _x13*_x51 - _x22*_x56 - _x24*_x59 - _x25*_x61 + _x46*_x7
    _x65 = -_x14*_x18 + _x26*_x30
    _x66 = _x52*(_x18*_x32 - _x27) + _x62*_x63 + _x64*_x65
    _x67 = _x33*_x66
    _x68 = _x14*_x30 - _x26*_x29
    _x69 = _x52*_x63 + _x62*(-_x15 + _x29*_x32) + _x64*_x68
    _x70 = _x10 + _x6
    _x71 = _x33*_x69
    _x72 = _x21 + _x23
    _x73 = -_x33*_x66*_x72 + _x70*_x71
    _x74 = _x52*_x65 + _x62*_x68 + _x64*(_x18*_x29 - _x31)
    _x75 = _x33*_x74
    _x76 = _x2 + _x8
    _x77 = -_x33*_x69*_x76 + _x72*_x75
    _x78 = -_x33*_x70*_x74 + _x67*_x76
    _out = out_array((points.shape[:-1], deltas.shape[:-1],), (9,))
    _out[..., 0] = _x33*_x69*yP - _x39 - _x67*zP - _x73
    _out[..., 1] = _x33*_x74*zP - _x58 - _x71*xP - _x77
    _out[..., 2] = _x33*_x66*xP - _x48 - _x75*yP - _x78
    _out[..., 3] = _x33*_x69*yQ - _x36 - _x67*zQ - _x73
    _out[..., 4] = _x33*_x74*zQ - _x55 - _x71*xQ - _x77
    _out[..., 5] = _x33*_x66*xQ - _x45 - _x75*yQ - _x78
    _out[..., 6] = _x33*_x69*yK - _x41 - _x67*zK - _x73
    _out[..., 7] = _x33*_x74*zK - _x60 - _x71*xK - _x77
    _out[..., 8] = _x33*_x66*xK - _x50 - _x75*yK - _x78
    return _out


def point_shape(points):
    """32 det(J) / tr(J)^3 of the centred points' inertia tensor J: 1 for an equilateral triangle, 0 for collinear points (dimensionless).

    points (..., 9): nominal points P, Q, K in the axis frame F, mm
        [xP, yP, zP, xQ, yQ, zQ, xK, yK, zK]
    returns (..., 1)
    """
    points = as_arg(points, 9, 'points', 'point_shape')
    xP = points[..., 0]
    yP = points[..., 1]
    zP = points[..., 2]
    xQ = points[..., 3]
    yQ = points[..., 4]
    zQ = points[..., 5]
    xK = points[..., 6]
    yK = points[..., 7]
    zK = points[..., 8]
    _x0 = (1/3)*xK
    _x1 = (1/3)*xP
    _x2 = -_x0 - _x1 + (2/3)*xQ
    _x3 = _x2**2
    _x4 = (1/3)*xQ
    _x5 = -_x0 - _x4 + (2/3)*xP
    _x6 = _x5**2
    _x7 = -_x1 - _x4 + (2/3)*xK
    _x8 = _x7**2
    _x9 = (1/3)*yK
    _x10 = (1/3)*yP
    _x11 = -_x10 - _x9 + (2/3)*yQ
    _x12 = _x11**2
    _x13 = (1/3)*yQ
    _x14 = -_x13 - _x9 + (2/3)*yP
    _x15 = _x14**2
    _x16 = -_x10 - _x13 + (2/3)*yK
    _x17 = _x16**2
    _x18 = (1/3)*zK
    _x19 = (1/3)*zP
    _x20 = -_x18 - _x19 + (2/3)*zQ
    _x21 = _x20**2
    _x22 = (1/3)*zQ
    _x23 = -_x18 - _x22 + (2/3)*zP
    _x24 = _x23**2
    _x25 = -_x19 - _x22 + (2/3)*zK
    _x26 = _x25**2
    _x27 = -_x11*_x2 - _x14*_x5 - _x16*_x7
    _x28 = _x3 + _x6 + _x8
    _x29 = _x12 + _x15 + _x17
    _x30 = _x28 + _x29
    _x31 = -_x2*_x20 - _x23*_x5 - _x25*_x7
    _x32 = _x21 + _x24 + _x26
    _x33 = _x28 + _x32
    _x34 = -_x11*_x20 - _x14*_x23 - _x16*_x25
    _x35 = _x29 + _x32
    _out = out_array((points.shape[:-1],), (1,))
    _out[..., 0] = (-32*_x27**2*_x30 + 64*_x27*_x31*_x34 + 32*_x30*_x33*_x35 - 32*_x31**2*_x33 - 32*_x34**2*_x35)/(2*_x12 + 2*_x15 + 2*_x17 + 2*_x21 + 2*_x24 + 2*_x26 + 2*_x3 + 2*_x6 + 2*_x8)**3
    return _out


def frame_dmu50_X(axes):
    """dmu50: frame of axis X after its nominal translation in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; tool side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_dmu50_X')
    X = axes[..., 0]
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = X
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 1
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = 0
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = 0
    return _out


def frame_dmu50_Y(axes):
    """dmu50: frame of axis Y after its nominal translation in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; tool side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_dmu50_Y')
    X = axes[..., 0]
    Y = axes[..., 1]
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = X
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 1
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = Y
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = 0
    return _out


def frame_dmu50_Z(axes):
    """dmu50: frame of axis Z after its nominal translation in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; tool side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_dmu50_Z')
    X = axes[..., 0]
    Y = axes[..., 1]
    Z = axes[..., 2]
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = X
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 1
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = Y
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = Z
    return _out


def frame_dmu50_B(axes):
    """dmu50: frame of axis B (stator frame) in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; table side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_dmu50_B')
    _x0 = (1/2)*numpy.sqrt(2)
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = 0
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = _x0
    _out[..., 1, 2] = -_x0
    _out[..., 1, 3] = 0
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = _x0
    _out[..., 2, 2] = _x0
    _out[..., 2, 3] = 38749/250
    return _out


def frame_dmu50_C(axes):
    """dmu50: frame of axis C (stator frame) in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; table side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_dmu50_C')
    B = axes[..., 3]
    _x0 = (1/180)*numpy.pi*B
    _x1 = numpy.cos(_x0)
    _x2 = numpy.sqrt(2)*numpy.sin(_x0)
    _x3 = (1/2)*_x2
    _x4 = -_x3
    _x5 = (1/2)*_x1
    _x6 = _x5 + 1/2
    _x7 = _x5 - 1/2
    _x8 = 38749/500 - 38749/500*_x1
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = _x1
    _out[..., 0, 1] = _x4
    _out[..., 0, 2] = _x4
    _out[..., 0, 3] = (38749/500)*_x2
    _out[..., 1, 0] = _x3
    _out[..., 1, 1] = _x6
    _out[..., 1, 2] = _x7
    _out[..., 1, 3] = _x8
    _out[..., 2, 0] = _x3
    _out[..., 2, 1] = _x7
    _out[..., 2, 2] = _x6
    _out[..., 2, 3] = _x8
    return _out


def frame_headbc_X(axes):
    """headbc: frame of axis X after its nominal translation in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; tool side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_headbc_X')
    X = axes[..., 0]
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = X
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 1
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = 0
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = 150
    return _out


def frame_headbc_Y(axes):
    """headbc: frame of axis Y after its nominal translation in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; tool side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_headbc_Y')
    X = axes[..., 0]
    Y = axes[..., 1]
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = X
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 1
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = Y
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = 150
    return _out


def frame_headbc_Z(axes):
    """headbc: frame of axis Z after its nominal translation in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; tool side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_headbc_Z')
    X = axes[..., 0]
    Y = axes[..., 1]
    Z = axes[..., 2]
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = X
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 1
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = Y
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = Z + 150
    return _out


def frame_headbc_B(axes):
    """headbc: frame of axis B (stator frame) in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; tool side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_headbc_B')
    X = axes[..., 0]
    Y = axes[..., 1]
    Z = axes[..., 2]
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = X
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 0
    _out[..., 1, 2] = 1
    _out[..., 1, 3] = Y
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = -1
    _out[..., 2, 2] = 0
    _out[..., 2, 3] = Z + 150
    return _out


def frame_headbc_C(axes):
    """headbc: frame of axis C (stator frame) in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; table side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_headbc_C')
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = 0
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 1
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = 0
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = 0
    return _out


def frame_xyzac_X(axes):
    """xyzac: frame of axis X after its nominal translation in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; tool side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, A, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_xyzac_X')
    X = axes[..., 0]
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = X
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 1
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = 0
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = 0
    return _out


def frame_xyzac_Y(axes):
    """xyzac: frame of axis Y after its nominal translation in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; tool side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, A, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_xyzac_Y')
    X = axes[..., 0]
    Y = axes[..., 1]
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = X
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 1
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = Y
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = 0
    return _out


def frame_xyzac_Z(axes):
    """xyzac: frame of axis Z after its nominal translation in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; tool side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, A, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_xyzac_Z')
    X = axes[..., 0]
    Y = axes[..., 1]
    Z = axes[..., 2]
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = X
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 1
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = Y
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = Z
    return _out


def frame_xyzac_A(axes):
    """xyzac: frame of axis A (stator frame) in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; table side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, A, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_xyzac_A')
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = 0
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 1
    _out[..., 0, 3] = 0
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 1
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = 0
    _out[..., 2, 0] = -1
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 0
    _out[..., 2, 3] = 120
    return _out


def frame_xyzac_C(axes):
    """xyzac: frame of axis C (stator frame) in which its error motion acts, as [R | o] (rotation, origin in mm) in the machine frame; table side, tool_length = 0.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, A, C]
    returns (..., 3, 4)
    """
    axes = as_arg(axes, 5, 'axes', 'frame_xyzac_C')
    A = axes[..., 3]
    _x0 = (1/180)*numpy.pi*A
    _x1 = numpy.cos(_x0)
    _x2 = numpy.sin(_x0)
    _out = out_array((axes.shape[:-1],), (3, 4))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = 0
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = _x1
    _out[..., 1, 2] = _x2
    _out[..., 1, 3] = -120*_x2
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = -_x2
    _out[..., 2, 2] = _x1
    _out[..., 2, 3] = 120 - 120*_x1
    return _out
