# -----------------------------------------------------------------------------
# GENERATED FILE - DO NOT EDIT.
# Generator: python -m derive (headbc); source: derive/kinematics.py
# Target: NumPy (vectorised, broadcasting).  Regenerate with `python -m derive`; CI runs `python -m derive --check`.
# Inputs (machine spec, SymPy/CasADi versions, hash of derive/) are in manifest.json.
# -----------------------------------------------------------------------------
"""Head-table machine (XYZ, B swivel head about Y on the spindle side, C rotary table): kinematics generated from derive/machines/headbc.toml.

NumPy implementation."""
import numpy

from mtcal._gensupport import as_arg, out_array

MACHINE = 'headbc'
TITLE = 'Head-table machine (XYZ, B swivel head about Y on the spindle side, C rotary table)'
AXES = ('X', 'Y', 'Z', 'B', 'C')
AXIS_KINDS = ('linear', 'linear', 'linear', 'rotary', 'rotary')
AXIS_LIMITS = (None, None, None, (-110.0, 110.0), None)
ERRORS = ('E_XX', 'E_YX', 'E_ZX', 'E_AX', 'E_BX', 'E_CX', 'E_XY', 'E_YY', 'E_ZY', 'E_AY', 'E_BY', 'E_CY', 'E_XZ',
 'E_YZ', 'E_ZZ', 'E_AZ', 'E_BZ', 'E_CZ', 'E_C0Y', 'E_B0Z', 'E_A0Z', 'E_XB', 'E_YB', 'E_ZB', 'E_AB', 'E_BB',
 'E_CB', 'E_XC', 'E_YC', 'E_ZC', 'E_AC', 'E_BC', 'E_CC', 'E_X0B', 'E_Y0B', 'E_A0B', 'E_B0B', 'E_X0C', 'E_Y0C',
 'E_A0C', 'E_B0C')
ERROR_GROUPS = {'linear': ['E_XX', 'E_YX', 'E_ZX', 'E_AX', 'E_BX', 'E_CX', 'E_XY', 'E_YY', 'E_ZY', 'E_AY', 'E_BY', 'E_CY',
            'E_XZ', 'E_YZ', 'E_ZZ', 'E_AZ', 'E_BZ', 'E_CZ'],
 'location': ['E_X0B', 'E_Y0B', 'E_A0B', 'E_B0B', 'E_X0C', 'E_Y0C', 'E_A0C', 'E_B0C'],
 'rotary': ['E_XB', 'E_YB', 'E_ZB', 'E_AB', 'E_BB', 'E_CB', 'E_XC', 'E_YC', 'E_ZC', 'E_AC', 'E_BC', 'E_CC'],
 'squareness': ['E_C0Y', 'E_B0Z', 'E_A0Z']}
PARAMETERS = {'pivot': '150'}
AXIS_SIDES = {'B': 'tool', 'C': 'table', 'X': 'tool', 'Y': 'tool', 'Z': 'tool'}
POSITIONING_ERRORS = {'B': 'E_CB', 'C': 'E_CC', 'X': 'E_XX', 'Y': 'E_YY', 'Z': 'E_ZZ'}
CAMPAIGN = {'positions': [['X', 0.0, 500.0, 11], ['Y', 0.0, 400.0, 11], ['Z', 0.0, 400.0, 11], ['B', -90.0, 90.0, 19],
               ['C', 0.0, 340.0, 18]],
 'reflectors': {'table': [['P', [150.0, 0.0, 40.0]], ['Q', [-75.0, 130.0, 80.0]],
                          ['K', [-75.0, -130.0, 120.0]]],
                'tool': [['P', [70.0, 0.0, 10.0]], ['Q', [-35.0, 60.0, 40.0]], ['K', [-35.0, -60.0, 70.0]]]},
 'rounds': 4,
 'trackers': [['front', [250.0, -1500.0, 150.0]], ['side', [-1500.0, 200.0, 150.0]]]}
IK = {'branches': 'B = phi + t (branch +1) or phi - t (branch -1), cos t = (k - a)/rho; singular at k = 1 (tool '
             'axis parallel to C, which is then free)',
 'k_range': [-1.0, 1.0],
 'phi_deg': 0.0,
 'preferred_branch': 1,
 'rotary_axis': 'C',
 'rotary_sign': -1,
 'singular_k': 1.0,
 'tilt_axis': 'B',
 'tilt_side': 'tool'}
POSE = ('x', 'y', 'z', 'i', 'j', 'k')
FUNCTIONS = ('forward', 'jacobian_axes', 'forward_errors', 'forward_errors_with_jacobian', 'jacobian_errors', 'deviation_first_order', 'correction_first_order', 'tool_point', 'tool_point_jacobian_errors', 'table_point', 'table_point_jacobian_errors', 'ik_tilt', 'ik_rotary', 'ik_linear')


def forward(axes, tool_length):
    """Nominal pose [x, y, z (mm), i, j, k] of the tool in the workpiece frame.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    tool_length (...): tool length below the error reference point, mm
    returns (..., 6)
    """
    axes = as_arg(axes, 5, 'axes', 'forward')
    tool_length = as_arg(tool_length, 0, 'tool_length', 'forward')
    X = axes[..., 0]
    Y = axes[..., 1]
    Z = axes[..., 2]
    B = axes[..., 3]
    C = axes[..., 4]
    tool_length = tool_length
    _x0 = (1/180)*numpy.pi
    _x1 = C*_x0
    _x2 = numpy.sin(_x1)
    _x3 = numpy.cos(_x1)
    _x4 = tool_length + 150
    _x5 = B*_x0
    _x6 = numpy.sin(_x5)
    _x7 = X - _x4*_x6
    _x8 = numpy.cos(_x5)
    _out = out_array((axes.shape[:-1], tool_length.shape,), (6,))
    _out[..., 0] = -Y*_x2 + _x3*_x7
    _out[..., 1] = Y*_x3 + _x2*_x7
    _out[..., 2] = Z - _x4*_x8 + _x4
    _out[..., 3] = _x3*_x6
    _out[..., 4] = _x2*_x6
    _out[..., 5] = _x8
    return _out


def jacobian_axes(axes, tool_length):
    """d pose / d axes of the nominal pose; columns per mm (linear) and per degree (rotary).

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    tool_length (...): tool length below the error reference point, mm
    returns (..., 6, 5)
    """
    axes = as_arg(axes, 5, 'axes', 'jacobian_axes')
    tool_length = as_arg(tool_length, 0, 'tool_length', 'jacobian_axes')
    X = axes[..., 0]
    Y = axes[..., 1]
    B = axes[..., 3]
    C = axes[..., 4]
    tool_length = tool_length
    _x0 = (1/180)*numpy.pi
    _x1 = C*_x0
    _x2 = numpy.cos(_x1)
    _x3 = numpy.sin(_x1)
    _x4 = tool_length + 150
    _x5 = B*_x0
    _x6 = _x0*numpy.cos(_x5)
    _x7 = _x2*_x6
    _x8 = Y*_x0
    _x9 = numpy.sin(_x5)
    _x10 = _x4*_x9
    _x11 = X - _x10
    _x12 = _x3*_x6
    _x13 = _x0*_x9
    _out = out_array((axes.shape[:-1], tool_length.shape,), (6, 5))
    _out[..., 0, 0] = _x2
    _out[..., 0, 1] = -_x3
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = -_x4*_x7
    _out[..., 0, 4] = -_x0*_x11*_x3 - _x2*_x8
    _out[..., 1, 0] = _x3
    _out[..., 1, 1] = _x2
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = -_x12*_x4
    _out[..., 1, 4] = (1/180)*numpy.pi*_x11*_x2 - _x3*_x8
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = _x0*_x10
    _out[..., 2, 4] = 0
    _out[..., 3, 0] = 0
    _out[..., 3, 1] = 0
    _out[..., 3, 2] = 0
    _out[..., 3, 3] = _x7
    _out[..., 3, 4] = -_x13*_x3
    _out[..., 4, 0] = 0
    _out[..., 4, 1] = 0
    _out[..., 4, 2] = 0
    _out[..., 4, 3] = _x12
    _out[..., 4, 4] = _x13*_x2
    _out[..., 5, 0] = 0
    _out[..., 5, 1] = 0
    _out[..., 5, 2] = 0
    _out[..., 5, 3] = -_x13
    _out[..., 5, 4] = 0
    return _out


def forward_errors(axes, errors, tool_length):
    """Exact error-inclusive pose [x, y, z, i, j, k] (errors in mm, rad; see derive/kinematics.py).

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    errors (..., 41): error parameters, mm and rad (ISO 230-1 names)
        [E_XX, E_YX, E_ZX, E_AX, E_BX, E_CX, E_XY, E_YY, E_ZY, E_AY, E_BY, E_CY, E_XZ, E_YZ, E_ZZ, E_AZ, E_BZ, E_CZ, E_C0Y, E_B0Z, E_A0Z, E_XB, E_YB, E_ZB, E_AB, E_BB, E_CB, E_XC, E_YC, E_ZC, E_AC, E_BC, E_CC, E_X0B, E_Y0B, E_A0B, E_B0B, E_X0C, E_Y0C, E_A0C, E_B0C]
    tool_length (...): tool length below the error reference point, mm
    returns (..., 6)
    """
    axes = as_arg(axes, 5, 'axes', 'forward_errors')
    errors = as_arg(errors, 41, 'errors', 'forward_errors')
    tool_length = as_arg(tool_length, 0, 'tool_length', 'forward_errors')
    X = axes[..., 0]
    Y = axes[..., 1]
    Z = axes[..., 2]
    B = axes[..., 3]
    C = axes[..., 4]
    E_XX = errors[..., 0]
    E_YX = errors[..., 1]
    E_ZX = errors[..., 2]
    E_AX = errors[..., 3]
    E_BX = errors[..., 4]
    E_CX = errors[..., 5]
    E_XY = errors[..., 6]
    E_YY = errors[..., 7]
    E_ZY = errors[..., 8]
    E_AY = errors[..., 9]
    E_BY = errors[..., 10]
    E_CY = errors[..., 11]
    E_XZ = errors[..., 12]
    E_YZ = errors[..., 13]
    E_ZZ = errors[..., 14]
    E_AZ = errors[..., 15]
    E_BZ = errors[..., 16]
    E_CZ = errors[..., 17]
    E_C0Y = errors[..., 18]
    E_B0Z = errors[..., 19]
    E_A0Z = errors[..., 20]
    E_XB = errors[..., 21]
    E_YB = errors[..., 22]
    E_ZB = errors[..., 23]
    E_AB = errors[..., 24]
    E_BB = errors[..., 25]
    E_CB = errors[..., 26]
    E_XC = errors[..., 27]
    E_YC = errors[..., 28]
    E_ZC = errors[..., 29]
    E_AC = errors[..., 30]
    E_BC = errors[..., 31]
    E_CC = errors[..., 32]
    E_X0B = errors[..., 33]
    E_Y0B = errors[..., 34]
    E_A0B = errors[..., 35]
    E_B0B = errors[..., 36]
    E_X0C = errors[..., 37]
    E_Y0C = errors[..., 38]
    E_A0C = errors[..., 39]
    E_B0C = errors[..., 40]
    tool_length = tool_length
    _x0 = numpy.sin(E_A0C)
    _x1 = numpy.sin(E_AC)
    _x2 = numpy.cos(E_BC)
    _x3 = _x1*_x2
    _x4 = numpy.sin(E_BC)
    _x5 = numpy.sin(E_B0C)
    _x6 = numpy.cos(E_A0C)
    _x7 = _x5*_x6
    _x8 = numpy.cos(E_AC)
    _x9 = numpy.cos(E_B0C)
    _x10 = -_x0*_x3 + _x2*_x6*_x8*_x9 - _x4*_x7
    _x11 = (1/180)*numpy.pi
    _x12 = C*_x11
    _x13 = numpy.cos(_x12)
    _x14 = -_x2*_x5*_x8 - _x4*_x9
    _x15 = numpy.sin(_x12)
    _x16 = _x0*_x5
    _x17 = _x0*_x2*_x8*_x9 - _x16*_x4 + _x3*_x6
    _x18 = _x13*_x14 - _x15*_x17
    _x19 = _x18*_x9
    _x20 = _x13*_x17 + _x14*_x15
    _x21 = _x10*_x7 + _x16*_x20 + _x19
    _x22 = -E_X0C*_x7 + E_Y0C*_x0
    _x23 = -E_X0C*_x16 - E_Y0C*_x6
    _x24 = -E_X0C*_x19 - E_X0C*_x4 + E_Y0C*_x3 + E_ZC + _x10*_x22 + _x20*_x23
    _x25 = numpy.cos(E_CC)
    _x26 = _x2*_x25
    _x27 = numpy.sin(E_CC)
    _x28 = _x1*_x25
    _x29 = -_x27*_x8 + _x28*_x4
    _x30 = _x1*_x27
    _x31 = _x25*_x8
    _x32 = _x30 + _x31*_x4
    _x33 = _x32*_x9
    _x34 = -_x0*_x29 + _x26*_x7 + _x33*_x6
    _x35 = _x2*_x25*_x9 - _x32*_x5
    _x36 = _x0*_x33 + _x16*_x26 + _x29*_x6
    _x37 = _x13*_x35 - _x15*_x36
    _x38 = _x37*_x9
    _x39 = _x13*_x36 + _x15*_x35
    _x40 = _x16*_x39 + _x34*_x7 + _x38
    _x41 = E_X0C*_x2
    _x42 = -E_X0C*_x38 + E_XC + E_Y0C*_x29 + _x22*_x34 + _x23*_x39 + _x25*_x41
    _x43 = _x2*_x27
    _x44 = _x30*_x4 + _x31
    _x45 = _x27*_x4*_x8 - _x28
    _x46 = _x45*_x9
    _x47 = -_x0*_x44 + _x43*_x7 + _x46*_x6
    _x48 = _x2*_x27*_x9 - _x45*_x5
    _x49 = _x0*_x46 + _x16*_x43 + _x44*_x6
    _x50 = _x13*_x48 - _x15*_x49
    _x51 = _x50*_x9
    _x52 = _x13*_x49 + _x15*_x48
    _x53 = _x16*_x52 + _x47*_x7 + _x51
    _x54 = -E_X0C*_x51 + E_Y0C*_x44 + E_YC + _x22*_x47 + _x23*_x52 + _x27*_x41
    _x55 = tool_length + 150
    _x56 = -_x55
    _x57 = numpy.sin(E_A0B)
    _x58 = numpy.sin(E_AB)
    _x59 = numpy.cos(E_BB)
    _x60 = _x58*_x59
    _x61 = numpy.cos(E_A0B)
    _x62 = numpy.sin(E_B0B)
    _x63 = numpy.sin(E_BB)
    _x64 = _x62*_x63
    _x65 = numpy.cos(E_AB)
    _x66 = numpy.cos(E_B0B)
    _x67 = -_x57*_x60 + _x59*_x61*_x65*_x66 - _x61*_x64
    _x68 = B*_x11
    _x69 = numpy.sin(_x68)
    _x70 = _x59*_x62
    _x71 = -_x63*_x66 - _x65*_x70
    _x72 = numpy.cos(_x68)
    _x73 = _x57*_x59*_x65*_x66 - _x57*_x64 + _x60*_x61
    _x74 = -_x69*_x71 + _x72*_x73
    _x75 = -_x57*_x67 + _x61*_x74
    _x76 = numpy.sin(E_CZ)
    _x77 = numpy.cos(E_AZ)
    _x78 = numpy.sin(E_BZ)
    _x79 = numpy.sin(E_AZ)
    _x80 = numpy.cos(E_CZ)
    _x81 = _x79*_x80
    _x82 = -_x76*_x77 + _x78*_x81
    _x83 = numpy.sin(E_BX)
    _x84 = numpy.cos(E_CY)
    _x85 = numpy.cos(E_BY)
    _x86 = _x84*_x85
    _x87 = numpy.sin(E_BY)
    _x88 = numpy.cos(E_AX)
    _x89 = numpy.cos(E_BX)
    _x90 = _x88*_x89
    _x91 = numpy.sin(E_AX)
    _x92 = numpy.sin(E_CY)
    _x93 = -_x83*_x86 + _x85*_x89*_x91*_x92 - _x87*_x90
    _x94 = numpy.cos(E_AY)
    _x95 = _x85*_x90
    _x96 = numpy.sin(E_AY)
    _x97 = _x92*_x96
    _x98 = _x84*_x94
    _x99 = _x87*_x98 + _x97
    _x100 = _x84*_x96
    _x101 = -_x100 + _x87*_x92*_x94
    _x102 = _x89*_x91
    _x103 = _x101*_x102 - _x83*_x99 + _x94*_x95
    _x104 = numpy.cos(E_BZ)
    _x105 = _x103*_x104
    _x106 = _x77*_x80
    _x107 = _x76*_x79
    _x108 = _x106 + _x107*_x78
    _x109 = _x100*_x87 - _x92*_x94
    _x110 = _x87*_x97 + _x98
    _x111 = _x102*_x110 - _x109*_x83 + _x95*_x96
    _x112 = _x105*_x79 + _x108*_x111 + _x82*_x93
    _x113 = _x104*_x80
    _x114 = _x104*_x76
    _x115 = -_x103*_x78 + _x111*_x114 + _x113*_x93
    _x116 = numpy.cos(E_CB)
    _x117 = _x116*_x70
    _x118 = numpy.sin(E_CB)
    _x119 = _x116*_x58
    _x120 = -_x118*_x65 + _x119*_x63
    _x121 = _x118*_x58
    _x122 = _x116*_x65
    _x123 = _x121 + _x122*_x63
    _x124 = _x123*_x66
    _x125 = _x117*_x61 - _x120*_x57 + _x124*_x61
    _x126 = _x116*_x59*_x66 - _x123*_x62
    _x127 = _x117*_x57 + _x120*_x61 + _x124*_x57
    _x128 = -_x126*_x69 + _x127*_x72
    _x129 = -_x125*_x57 + _x128*_x61
    _x130 = _x118*_x70
    _x131 = _x121*_x63 + _x122
    _x132 = _x118*_x63*_x65 - _x119
    _x133 = _x132*_x66
    _x134 = _x130*_x61 - _x131*_x57 + _x133*_x61
    _x135 = _x118*_x59*_x66 - _x132*_x62
    _x136 = _x130*_x57 + _x131*_x61 + _x133*_x57
    _x137 = -_x135*_x69 + _x136*_x72
    _x138 = -_x134*_x57 + _x137*_x61
    _x139 = _x106*_x78 + _x107
    _x140 = _x76*_x77*_x78 - _x81
    _x141 = -_x105*_x77 - _x111*_x140 - _x139*_x93
    _x142 = -_x112*_x75 - _x115*_x129 - _x138*_x141
    _x143 = Z*numpy.cos(E_A0Z)
    _x144 = E_XZ + _x143*numpy.sin(E_B0Z)
    _x145 = E_YZ - Z*numpy.sin(E_A0Z)
    _x146 = E_ZZ + _x143*numpy.cos(E_B0Z)
    _x147 = E_X0B*_x62
    _x148 = E_Y0B*_x57 - _x147*_x61
    _x149 = E_X0B*_x66
    _x150 = -E_Y0B*_x61 - _x147*_x57
    _x151 = -E_X0B*_x63 + E_Y0B*_x60 + E_ZB + _x148*_x67 - _x149*(_x69*_x73 + _x71*_x72) + _x150*_x74
    _x152 = E_X0B*_x59
    _x153 = E_Y0B*_x131 + E_YB + _x118*_x152 + _x134*_x148 + _x137*_x150 - _x149*(_x135*_x72 + _x136*_x69)
    _x154 = E_XB + E_Y0B*_x120 + _x116*_x152 + _x125*_x148 + _x128*_x150 - _x149*(_x126*_x72 + _x127*_x69)
    _x155 = E_XY - Y*numpy.sin(E_C0Y)
    _x156 = E_YY + Y*numpy.cos(E_C0Y)
    _x157 = E_ZX + E_ZY*_x90 + _x102*_x156 + _x103*_x146 + _x111*_x145 + _x112*_x151 + _x115*_x154 + _x141*_x153 + _x142*_x56 + _x144*_x93 - _x155*_x83 + _x55
    _x158 = numpy.cos(E_CX)
    _x159 = _x158*_x89
    _x160 = numpy.sin(E_CX)
    _x161 = _x160*_x91
    _x162 = _x158*_x88
    _x163 = _x161 + _x162*_x83
    _x164 = _x158*_x91
    _x165 = -_x160*_x88 + _x164*_x83
    _x166 = _x85*_x92
    _x167 = _x159*_x86 - _x163*_x87 + _x165*_x166
    _x168 = _x163*_x85
    _x169 = _x109*_x159 + _x110*_x165 + _x168*_x96
    _x170 = _x101*_x165 + _x159*_x99 + _x168*_x94
    _x171 = _x104*_x170
    _x172 = _x108*_x169 + _x167*_x82 + _x171*_x79
    _x173 = _x113*_x167 + _x114*_x169 - _x170*_x78
    _x174 = -_x139*_x167 - _x140*_x169 - _x171*_x77
    _x175 = -_x129*_x173 - _x138*_x174 - _x172*_x75
    _x176 = E_XX + E_ZY*_x163 + X + _x144*_x167 + _x145*_x169 + _x146*_x170 + _x151*_x172 + _x153*_x174 + _x154*_x173 + _x155*_x159 + _x156*_x165 + _x175*_x56
    _x177 = _x160*_x89
    _x178 = _x160*_x83*_x88 - _x164
    _x179 = _x161*_x83 + _x162
    _x180 = _x166*_x179 + _x177*_x86 - _x178*_x87
    _x181 = _x178*_x85
    _x182 = _x109*_x177 + _x110*_x179 + _x181*_x96
    _x183 = _x101*_x179 + _x177*_x99 + _x181*_x94
    _x184 = _x104*_x183
    _x185 = _x108*_x182 + _x180*_x82 + _x184*_x79
    _x186 = _x113*_x180 + _x114*_x182 - _x183*_x78
    _x187 = -_x139*_x180 - _x140*_x182 - _x184*_x77
    _x188 = -_x129*_x186 - _x138*_x187 - _x185*_x75
    _x189 = E_YX + E_ZY*_x178 + _x144*_x180 + _x145*_x182 + _x146*_x183 + _x151*_x185 + _x153*_x187 + _x154*_x186 + _x155*_x177 + _x156*_x179 + _x188*_x56
    _x190 = -_x0*_x10 + _x20*_x6
    _x191 = -_x0*_x34 + _x39*_x6
    _x192 = -_x0*_x47 + _x52*_x6
    _x193 = _x6*_x9
    _x194 = _x0*_x9
    _x195 = _x10*_x193 - _x18*_x5 + _x194*_x20
    _x196 = _x193*_x34 + _x194*_x39 - _x37*_x5
    _x197 = _x193*_x47 + _x194*_x52 - _x5*_x50
    _out = out_array((axes.shape[:-1], errors.shape[:-1], tool_length.shape,), (6,))
    _out[..., 0] = _x157*_x21 + _x176*_x40 + _x189*_x53 - _x21*_x24 - _x40*_x42 - _x53*_x54
    _out[..., 1] = _x157*_x190 + _x176*_x191 + _x189*_x192 - _x190*_x24 - _x191*_x42 - _x192*_x54
    _out[..., 2] = _x157*_x195 + _x176*_x196 + _x189*_x197 - _x195*_x24 - _x196*_x42 - _x197*_x54
    _out[..., 3] = _x142*_x21 + _x175*_x40 + _x188*_x53
    _out[..., 4] = _x142*_x190 + _x175*_x191 + _x188*_x192
    _out[..., 5] = _x142*_x195 + _x175*_x196 + _x188*_x197
    return _out


def forward_errors_with_jacobian(axes, errors, tool_length):
    """Column 0: exact error-inclusive pose; columns 1..: its partial derivatives with respect to the axes at fixed error values (per mm, per degree).

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    errors (..., 41): error parameters, mm and rad (ISO 230-1 names)
        [E_XX, E_YX, E_ZX, E_AX, E_BX, E_CX, E_XY, E_YY, E_ZY, E_AY, E_BY, E_CY, E_XZ, E_YZ, E_ZZ, E_AZ, E_BZ, E_CZ, E_C0Y, E_B0Z, E_A0Z, E_XB, E_YB, E_ZB, E_AB, E_BB, E_CB, E_XC, E_YC, E_ZC, E_AC, E_BC, E_CC, E_X0B, E_Y0B, E_A0B, E_B0B, E_X0C, E_Y0C, E_A0C, E_B0C]
    tool_length (...): tool length below the error reference point, mm
    returns (..., 6, 6)
    """
    axes = as_arg(axes, 5, 'axes', 'forward_errors_with_jacobian')
    errors = as_arg(errors, 41, 'errors', 'forward_errors_with_jacobian')
    tool_length = as_arg(tool_length, 0, 'tool_length', 'forward_errors_with_jacobian')
    X = axes[..., 0]
    Y = axes[..., 1]
    Z = axes[..., 2]
    B = axes[..., 3]
    C = axes[..., 4]
    E_XX = errors[..., 0]
    E_YX = errors[..., 1]
    E_ZX = errors[..., 2]
    E_AX = errors[..., 3]
    E_BX = errors[..., 4]
    E_CX = errors[..., 5]
    E_XY = errors[..., 6]
    E_YY = errors[..., 7]
    E_ZY = errors[..., 8]
    E_AY = errors[..., 9]
    E_BY = errors[..., 10]
    E_CY = errors[..., 11]
    E_XZ = errors[..., 12]
    E_YZ = errors[..., 13]
    E_ZZ = errors[..., 14]
    E_AZ = errors[..., 15]
    E_BZ = errors[..., 16]
    E_CZ = errors[..., 17]
    E_C0Y = errors[..., 18]
    E_B0Z = errors[..., 19]
    E_A0Z = errors[..., 20]
    E_XB = errors[..., 21]
    E_YB = errors[..., 22]
    E_ZB = errors[..., 23]
    E_AB = errors[..., 24]
    E_BB = errors[..., 25]
    E_CB = errors[..., 26]
    E_XC = errors[..., 27]
    E_YC = errors[..., 28]
    E_ZC = errors[..., 29]
    E_AC = errors[..., 30]
    E_BC = errors[..., 31]
    E_CC = errors[..., 32]
    E_X0B = errors[..., 33]
    E_Y0B = errors[..., 34]
    E_A0B = errors[..., 35]
    E_B0B = errors[..., 36]
    E_X0C = errors[..., 37]
    E_Y0C = errors[..., 38]
    E_A0C = errors[..., 39]
    E_B0C = errors[..., 40]
    tool_length = tool_length
    _x0 = numpy.sin(E_A0C)
    _x1 = numpy.sin(E_AC)
    _x2 = numpy.cos(E_BC)
    _x3 = _x1*_x2
    _x4 = numpy.sin(E_BC)
    _x5 = numpy.sin(E_B0C)
    _x6 = numpy.cos(E_A0C)
    _x7 = _x5*_x6
    _x8 = numpy.cos(E_AC)
    _x9 = numpy.cos(E_B0C)
    _x10 = -_x0*_x3 + _x2*_x6*_x8*_x9 - _x4*_x7
    _x11 = (1/180)*numpy.pi
    _x12 = C*_x11
    _x13 = numpy.cos(_x12)
    _x14 = -_x2*_x5*_x8 - _x4*_x9
    _x15 = _x13*_x14
    _x16 = numpy.sin(_x12)
    _x17 = _x0*_x5
    _x18 = _x0*_x2*_x8*_x9 - _x17*_x4 + _x3*_x6
    _x19 = _x16*_x18
    _x20 = _x15 - _x19
    _x21 = _x20*_x9
    _x22 = _x14*_x16
    _x23 = _x13*_x18
    _x24 = _x22 + _x23
    _x25 = _x10*_x7 + _x17*_x24 + _x21
    _x26 = -_x25
    _x27 = -E_X0C*_x7 + E_Y0C*_x0
    _x28 = -E_X0C*_x17 - E_Y0C*_x6
    _x29 = -E_X0C*_x21 - E_X0C*_x4 + E_Y0C*_x3 + E_ZC + _x10*_x27 + _x24*_x28
    _x30 = numpy.cos(E_CC)
    _x31 = _x2*_x30
    _x32 = numpy.sin(E_CC)
    _x33 = _x1*_x30
    _x34 = -_x32*_x8 + _x33*_x4
    _x35 = _x1*_x32
    _x36 = _x30*_x8
    _x37 = _x35 + _x36*_x4
    _x38 = _x37*_x9
    _x39 = -_x0*_x34 + _x31*_x7 + _x38*_x6
    _x40 = _x2*_x30*_x9 - _x37*_x5
    _x41 = _x13*_x40
    _x42 = _x0*_x38 + _x17*_x31 + _x34*_x6
    _x43 = _x16*_x42
    _x44 = _x41 - _x43
    _x45 = _x44*_x9
    _x46 = _x16*_x40
    _x47 = _x13*_x42
    _x48 = _x46 + _x47
    _x49 = _x17*_x48 + _x39*_x7 + _x45
    _x50 = -_x49
    _x51 = E_X0C*_x2
    _x52 = -E_X0C*_x45 + E_XC + E_Y0C*_x34 + _x27*_x39 + _x28*_x48 + _x30*_x51
    _x53 = _x2*_x32
    _x54 = _x35*_x4 + _x36
    _x55 = _x32*_x4*_x8 - _x33
    _x56 = _x55*_x9
    _x57 = -_x0*_x54 + _x53*_x7 + _x56*_x6
    _x58 = _x2*_x32*_x9 - _x5*_x55
    _x59 = _x13*_x58
    _x60 = _x0*_x56 + _x17*_x53 + _x54*_x6
    _x61 = _x16*_x60
    _x62 = _x59 - _x61
    _x63 = _x62*_x9
    _x64 = _x16*_x58
    _x65 = _x13*_x60
    _x66 = _x64 + _x65
    _x67 = _x17*_x66 + _x57*_x7 + _x63
    _x68 = -_x67
    _x69 = -E_X0C*_x63 + E_Y0C*_x54 + E_YC + _x27*_x57 + _x28*_x66 + _x32*_x51
    _x70 = tool_length + 150
    _x71 = -_x70
    _x72 = numpy.sin(E_A0B)
    _x73 = numpy.sin(E_AB)
    _x74 = numpy.cos(E_BB)
    _x75 = _x73*_x74
    _x76 = numpy.cos(E_A0B)
    _x77 = numpy.sin(E_B0B)
    _x78 = numpy.sin(E_BB)
    _x79 = _x77*_x78
    _x80 = numpy.cos(E_AB)
    _x81 = numpy.cos(E_B0B)
    _x82 = -_x72*_x75 + _x74*_x76*_x80*_x81 - _x76*_x79
    _x83 = B*_x11
    _x84 = numpy.sin(_x83)
    _x85 = _x74*_x77
    _x86 = -_x78*_x81 - _x80*_x85
    _x87 = _x84*_x86
    _x88 = numpy.cos(_x83)
    _x89 = _x72*_x74*_x80*_x81 - _x72*_x79 + _x75*_x76
    _x90 = -_x87 + _x88*_x89
    _x91 = -_x72*_x82 + _x76*_x90
    _x92 = numpy.sin(E_CZ)
    _x93 = numpy.cos(E_AZ)
    _x94 = numpy.sin(E_BZ)
    _x95 = numpy.sin(E_AZ)
    _x96 = numpy.cos(E_CZ)
    _x97 = _x95*_x96
    _x98 = -_x92*_x93 + _x94*_x97
    _x99 = numpy.sin(E_BX)
    _x100 = numpy.cos(E_CY)
    _x101 = numpy.cos(E_BY)
    _x102 = _x100*_x101
    _x103 = numpy.sin(E_BY)
    _x104 = numpy.cos(E_AX)
    _x105 = numpy.cos(E_BX)
    _x106 = _x104*_x105
    _x107 = numpy.sin(E_AX)
    _x108 = numpy.sin(E_CY)
    _x109 = _x101*_x105*_x107*_x108 - _x102*_x99 - _x103*_x106
    _x110 = numpy.cos(E_AY)
    _x111 = _x101*_x106
    _x112 = numpy.sin(E_AY)
    _x113 = _x108*_x112
    _x114 = _x100*_x110
    _x115 = _x103*_x114 + _x113
    _x116 = _x100*_x112
    _x117 = _x103*_x108*_x110 - _x116
    _x118 = _x105*_x107
    _x119 = _x110*_x111 - _x115*_x99 + _x117*_x118
    _x120 = numpy.cos(E_BZ)
    _x121 = _x119*_x120
    _x122 = _x93*_x96
    _x123 = _x92*_x95
    _x124 = _x122 + _x123*_x94
    _x125 = _x103*_x116 - _x108*_x110
    _x126 = _x103*_x113 + _x114
    _x127 = _x111*_x112 + _x118*_x126 - _x125*_x99
    _x128 = _x109*_x98 + _x121*_x95 + _x124*_x127
    _x129 = _x120*_x96
    _x130 = _x120*_x92
    _x131 = _x109*_x129 - _x119*_x94 + _x127*_x130
    _x132 = numpy.cos(E_CB)
    _x133 = _x132*_x85
    _x134 = numpy.sin(E_CB)
    _x135 = _x132*_x73
    _x136 = -_x134*_x80 + _x135*_x78
    _x137 = _x134*_x73
    _x138 = _x132*_x80
    _x139 = _x137 + _x138*_x78
    _x140 = _x139*_x81
    _x141 = _x133*_x76 - _x136*_x72 + _x140*_x76
    _x142 = _x132*_x74*_x81 - _x139*_x77
    _x143 = _x142*_x84
    _x144 = _x133*_x72 + _x136*_x76 + _x140*_x72
    _x145 = -_x143 + _x144*_x88
    _x146 = -_x141*_x72 + _x145*_x76
    _x147 = _x134*_x85
    _x148 = _x137*_x78 + _x138
    _x149 = _x134*_x78*_x80 - _x135
    _x150 = _x149*_x81
    _x151 = _x147*_x76 - _x148*_x72 + _x150*_x76
    _x152 = _x134*_x74*_x81 - _x149*_x77
    _x153 = _x152*_x84
    _x154 = _x147*_x72 + _x148*_x76 + _x150*_x72
    _x155 = -_x153 + _x154*_x88
    _x156 = -_x151*_x72 + _x155*_x76
    _x157 = _x122*_x94 + _x123
    _x158 = _x92*_x93*_x94 - _x97
    _x159 = -_x109*_x157 - _x121*_x93 - _x127*_x158
    _x160 = -_x128*_x91 - _x131*_x146 - _x156*_x159
    _x161 = numpy.sin(E_B0Z)
    _x162 = numpy.cos(E_A0Z)
    _x163 = Z*_x162
    _x164 = E_XZ + _x161*_x163
    _x165 = numpy.sin(E_A0Z)
    _x166 = E_YZ - Z*_x165
    _x167 = numpy.cos(E_B0Z)
    _x168 = E_ZZ + _x163*_x167
    _x169 = E_X0B*_x77
    _x170 = E_Y0B*_x72 - _x169*_x76
    _x171 = _x86*_x88
    _x172 = _x84*_x89
    _x173 = E_X0B*_x81
    _x174 = -E_Y0B*_x76 - _x169*_x72
    _x175 = -E_X0B*_x78 + E_Y0B*_x75 + E_ZB + _x170*_x82 - _x173*(_x171 + _x172) + _x174*_x90
    _x176 = E_X0B*_x74
    _x177 = _x152*_x88
    _x178 = _x154*_x84
    _x179 = E_Y0B*_x148 + E_YB + _x134*_x176 + _x151*_x170 + _x155*_x174 - _x173*(_x177 + _x178)
    _x180 = _x142*_x88
    _x181 = _x144*_x84
    _x182 = E_XB + E_Y0B*_x136 + _x132*_x176 + _x141*_x170 + _x145*_x174 - _x173*(_x180 + _x181)
    _x183 = numpy.sin(E_C0Y)
    _x184 = E_XY - Y*_x183
    _x185 = numpy.cos(E_C0Y)
    _x186 = E_YY + Y*_x185
    _x187 = E_ZX + E_ZY*_x106 + _x109*_x164 + _x118*_x186 + _x119*_x168 + _x127*_x166 + _x128*_x175 + _x131*_x182 + _x159*_x179 + _x160*_x71 - _x184*_x99 + _x70
    _x188 = numpy.cos(E_CX)
    _x189 = _x105*_x188
    _x190 = numpy.sin(E_CX)
    _x191 = _x107*_x190
    _x192 = _x104*_x188
    _x193 = _x191 + _x192*_x99
    _x194 = _x107*_x188
    _x195 = -_x104*_x190 + _x194*_x99
    _x196 = _x101*_x108
    _x197 = _x102*_x189 - _x103*_x193 + _x195*_x196
    _x198 = _x101*_x193
    _x199 = _x112*_x198 + _x125*_x189 + _x126*_x195
    _x200 = _x110*_x198 + _x115*_x189 + _x117*_x195
    _x201 = _x120*_x200
    _x202 = _x124*_x199 + _x197*_x98 + _x201*_x95
    _x203 = _x129*_x197 + _x130*_x199 - _x200*_x94
    _x204 = -_x157*_x197 - _x158*_x199 - _x201*_x93
    _x205 = -_x146*_x203 - _x156*_x204 - _x202*_x91
    _x206 = E_XX + E_ZY*_x193 + X + _x164*_x197 + _x166*_x199 + _x168*_x200 + _x175*_x202 + _x179*_x204 + _x182*_x203 + _x184*_x189 + _x186*_x195 + _x205*_x71
    _x207 = _x105*_x190
    _x208 = _x104*_x190*_x99 - _x194
    _x209 = _x191*_x99 + _x192
    _x210 = _x102*_x207 - _x103*_x208 + _x196*_x209
    _x211 = _x101*_x208
    _x212 = _x112*_x211 + _x125*_x207 + _x126*_x209
    _x213 = _x110*_x211 + _x115*_x207 + _x117*_x209
    _x214 = _x120*_x213
    _x215 = _x124*_x212 + _x210*_x98 + _x214*_x95
    _x216 = _x129*_x210 + _x130*_x212 - _x213*_x94
    _x217 = -_x157*_x210 - _x158*_x212 - _x214*_x93
    _x218 = -_x146*_x216 - _x156*_x217 - _x215*_x91
    _x219 = E_YX + E_ZY*_x208 + _x164*_x210 + _x166*_x212 + _x168*_x213 + _x175*_x215 + _x179*_x217 + _x182*_x216 + _x184*_x207 + _x186*_x209 + _x218*_x71
    _x220 = _x118*_x185 + _x183*_x99
    _x221 = -_x183*_x189 + _x185*_x195
    _x222 = -_x183*_x207 + _x185*_x209
    _x223 = _x161*_x162
    _x224 = _x162*_x167
    _x225 = _x109*_x223 + _x119*_x224 - _x127*_x165
    _x226 = -_x165*_x199 + _x197*_x223 + _x200*_x224
    _x227 = -_x165*_x212 + _x210*_x223 + _x213*_x224
    _x228 = -_x11*_x171 - _x11*_x172
    _x229 = -_x173*(-_x11*_x87 + (1/180)*numpy.pi*_x88*_x89) + _x174*_x228
    _x230 = -_x11*_x180 - _x11*_x181
    _x231 = -_x173*(-_x11*_x143 + (1/180)*numpy.pi*_x144*_x88) + _x174*_x230
    _x232 = -_x11*_x177 - _x11*_x178
    _x233 = -_x173*(-_x11*_x153 + (1/180)*numpy.pi*_x154*_x88) + _x174*_x232
    _x234 = _x228*_x76
    _x235 = _x230*_x76
    _x236 = _x232*_x76
    _x237 = -_x128*_x234 - _x131*_x235 - _x159*_x236
    _x238 = _x128*_x229 + _x131*_x231 + _x159*_x233 + _x237*_x71
    _x239 = -_x202*_x234 - _x203*_x235 - _x204*_x236
    _x240 = _x202*_x229 + _x203*_x231 + _x204*_x233 + _x239*_x71
    _x241 = -_x215*_x234 - _x216*_x235 - _x217*_x236
    _x242 = _x215*_x229 + _x216*_x231 + _x217*_x233 + _x241*_x71
    _x243 = -_x11*_x22 - _x11*_x23
    _x244 = _x243*_x9
    _x245 = _x11*_x15 - _x11*_x19
    _x246 = -E_X0C*_x244 + _x245*_x28
    _x247 = _x17*_x245 + _x244
    _x248 = -_x11*_x46 - _x11*_x47
    _x249 = _x248*_x9
    _x250 = _x11*_x41 - _x11*_x43
    _x251 = -E_X0C*_x249 + _x250*_x28
    _x252 = -_x11*_x64 - _x11*_x65
    _x253 = _x252*_x9
    _x254 = _x11*_x59 - _x11*_x61
    _x255 = -E_X0C*_x253 + _x254*_x28
    _x256 = _x17*_x250 + _x249
    _x257 = _x17*_x254 + _x253
    _x258 = -_x0*_x10 + _x24*_x6
    _x259 = -_x258
    _x260 = -_x0*_x39 + _x48*_x6
    _x261 = -_x260
    _x262 = -_x0*_x57 + _x6*_x66
    _x263 = -_x262
    _x264 = _x245*_x6
    _x265 = _x250*_x6
    _x266 = _x254*_x6
    _x267 = _x6*_x9
    _x268 = _x0*_x9
    _x269 = _x10*_x267 - _x20*_x5 + _x24*_x268
    _x270 = -_x269
    _x271 = _x267*_x39 + _x268*_x48 - _x44*_x5
    _x272 = -_x271
    _x273 = _x267*_x57 + _x268*_x66 - _x5*_x62
    _x274 = -_x273
    _x275 = _x243*_x5 - _x245*_x268
    _x276 = _x248*_x5 - _x250*_x268
    _x277 = _x252*_x5 - _x254*_x268
    _x278 = -_x275
    _x279 = -_x276
    _x280 = -_x277
    _out = out_array((axes.shape[:-1], errors.shape[:-1], tool_length.shape,), (6, 6))
    _out[..., 0, 0] = _x187*_x25 + _x206*_x49 + _x219*_x67 + _x26*_x29 + _x50*_x52 + _x68*_x69
    _out[..., 0, 1] = _x49
    _out[..., 0, 2] = _x220*_x25 + _x221*_x49 + _x222*_x67
    _out[..., 0, 3] = _x225*_x25 + _x226*_x49 + _x227*_x67
    _out[..., 0, 4] = _x238*_x25 + _x240*_x49 + _x242*_x67
    _out[..., 0, 5] = _x187*_x247 + _x206*_x256 + _x219*_x257 + _x246*_x26 - _x247*_x29 + _x251*_x50 + _x255*_x68 - _x256*_x52 - _x257*_x69
    _out[..., 1, 0] = _x187*_x258 + _x206*_x260 + _x219*_x262 + _x259*_x29 + _x261*_x52 + _x263*_x69
    _out[..., 1, 1] = _x260
    _out[..., 1, 2] = _x220*_x258 + _x221*_x260 + _x222*_x262
    _out[..., 1, 3] = _x225*_x258 + _x226*_x260 + _x227*_x262
    _out[..., 1, 4] = _x238*_x258 + _x240*_x260 + _x242*_x262
    _out[..., 1, 5] = _x187*_x264 + _x206*_x265 + _x219*_x266 + _x246*_x259 + _x251*_x261 + _x255*_x263 - _x264*_x29 - _x265*_x52 - _x266*_x69
    _out[..., 2, 0] = _x187*_x269 + _x206*_x271 + _x219*_x273 + _x270*_x29 + _x272*_x52 + _x274*_x69
    _out[..., 2, 1] = _x271
    _out[..., 2, 2] = _x220*_x269 + _x221*_x271 + _x222*_x273
    _out[..., 2, 3] = _x225*_x269 + _x226*_x271 + _x227*_x273
    _out[..., 2, 4] = _x238*_x269 + _x240*_x271 + _x242*_x273
    _out[..., 2, 5] = _x187*_x278 + _x206*_x279 + _x219*_x280 + _x246*_x270 + _x251*_x272 + _x255*_x274 + _x275*_x29 + _x276*_x52 + _x277*_x69
    _out[..., 3, 0] = _x160*_x25 + _x205*_x49 + _x218*_x67
    _out[..., 3, 1] = 0
    _out[..., 3, 2] = 0
    _out[..., 3, 3] = 0
    _out[..., 3, 4] = _x237*_x25 + _x239*_x49 + _x241*_x67
    _out[..., 3, 5] = _x160*_x247 + _x205*_x256 + _x218*_x257
    _out[..., 4, 0] = _x160*_x258 + _x205*_x260 + _x218*_x262
    _out[..., 4, 1] = 0
    _out[..., 4, 2] = 0
    _out[..., 4, 3] = 0
    _out[..., 4, 4] = _x237*_x258 + _x239*_x260 + _x241*_x262
    _out[..., 4, 5] = _x160*_x264 + _x205*_x265 + _x218*_x266
    _out[..., 5, 0] = _x160*_x269 + _x205*_x271 + _x218*_x273
    _out[..., 5, 1] = 0
    _out[..., 5, 2] = 0
    _out[..., 5, 3] = 0
    _out[..., 5, 4] = _x237*_x269 + _x239*_x271 + _x241*_x273
    _out[..., 5, 5] = _x160*_x278 + _x205*_x279 + _x218*_x280
    return _out


def jacobian_errors(axes, tool_length):
    """d pose / d errors at zero error (exact first-order sensitivity; per mm and per rad).

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    tool_length (...): tool length below the error reference point, mm
    returns (..., 6, 41)
    """
    axes = as_arg(axes, 5, 'axes', 'jacobian_errors')
    tool_length = as_arg(tool_length, 0, 'tool_length', 'jacobian_errors')
    X = axes[..., 0]
    Y = axes[..., 1]
    Z = axes[..., 2]
    B = axes[..., 3]
    C = axes[..., 4]
    tool_length = tool_length
    _x0 = (1/180)*numpy.pi
    _x1 = C*_x0
    _x2 = numpy.cos(_x1)
    _x3 = numpy.sin(_x1)
    _x4 = -_x3
    _x5 = tool_length + 150
    _x6 = -_x5
    _x7 = B*_x0
    _x8 = numpy.cos(_x7)
    _x9 = _x6*_x8
    _x10 = Z + _x9
    _x11 = -_x10
    _x12 = -_x11*_x3
    _x13 = _x10*_x2
    _x14 = Y*_x2
    _x15 = numpy.sin(_x7)
    _x16 = _x15*_x6
    _x17 = _x16*_x3
    _x18 = -_x17
    _x19 = _x3*_x9
    _x20 = _x2*_x9
    _x21 = Z*_x2
    _x22 = Z*_x3
    _x23 = -_x2
    _x24 = _x10 + _x5
    _x25 = -_x24*_x3
    _x26 = _x2*_x24
    _x27 = X + _x16
    _x28 = _x27*_x3
    _x29 = _x8 - 1
    _x30 = -_x29
    _x31 = _x2*_x30
    _x32 = _x15*_x2
    _x33 = _x3*_x30
    _x34 = _x2 - 1
    _x35 = -_x34
    _x36 = -_x2*_x35 + _x3**2
    _x37 = _x2*_x3 + _x3*_x35
    _x38 = _x11*_x2
    _x39 = _x10*_x3
    _x40 = Y*_x3
    _x41 = _x16*_x2
    _x42 = -_x41
    _x43 = -_x20
    _x44 = _x15*_x3
    _x45 = -_x16
    _x46 = _x3*_x8
    _x47 = _x2*_x8
    _x48 = -_x44
    _x49 = -_x46
    _x50 = -_x47
    _x51 = -_x32
    _x52 = -_x15
    _out = out_array((axes.shape[:-1], tool_length.shape,), (6, 41))
    _out[..., 0, 0] = _x2
    _out[..., 0, 1] = _x4
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = _x12
    _out[..., 0, 4] = _x13
    _out[..., 0, 5] = -_x14 - _x17
    _out[..., 0, 6] = _x2
    _out[..., 0, 7] = _x4
    _out[..., 0, 8] = 0
    _out[..., 0, 9] = _x12
    _out[..., 0, 10] = _x13
    _out[..., 0, 11] = _x18
    _out[..., 0, 12] = _x2
    _out[..., 0, 13] = _x4
    _out[..., 0, 14] = 0
    _out[..., 0, 15] = _x19
    _out[..., 0, 16] = _x20
    _out[..., 0, 17] = _x18
    _out[..., 0, 18] = -_x14
    _out[..., 0, 19] = _x21
    _out[..., 0, 20] = _x22
    _out[..., 0, 21] = _x2
    _out[..., 0, 22] = 0
    _out[..., 0, 23] = _x4
    _out[..., 0, 24] = _x19
    _out[..., 0, 25] = _x17
    _out[..., 0, 26] = _x20
    _out[..., 0, 27] = _x23
    _out[..., 0, 28] = _x3
    _out[..., 0, 29] = 0
    _out[..., 0, 30] = _x25
    _out[..., 0, 31] = -_x26
    _out[..., 0, 32] = _x14 + _x28
    _out[..., 0, 33] = _x31
    _out[..., 0, 34] = _x32
    _out[..., 0, 35] = -_x33*_x6
    _out[..., 0, 36] = _x17
    _out[..., 0, 37] = _x36
    _out[..., 0, 38] = _x37
    _out[..., 0, 39] = _x25
    _out[..., 0, 40] = _x24*_x35
    _out[..., 1, 0] = _x3
    _out[..., 1, 1] = _x2
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = _x38
    _out[..., 1, 4] = _x39
    _out[..., 1, 5] = -_x40 - _x42
    _out[..., 1, 6] = _x3
    _out[..., 1, 7] = _x2
    _out[..., 1, 8] = 0
    _out[..., 1, 9] = _x38
    _out[..., 1, 10] = _x39
    _out[..., 1, 11] = _x41
    _out[..., 1, 12] = _x3
    _out[..., 1, 13] = _x2
    _out[..., 1, 14] = 0
    _out[..., 1, 15] = _x43
    _out[..., 1, 16] = _x19
    _out[..., 1, 17] = _x41
    _out[..., 1, 18] = -_x40
    _out[..., 1, 19] = _x22
    _out[..., 1, 20] = -_x21
    _out[..., 1, 21] = _x3
    _out[..., 1, 22] = 0
    _out[..., 1, 23] = _x2
    _out[..., 1, 24] = _x43
    _out[..., 1, 25] = _x42
    _out[..., 1, 26] = _x19
    _out[..., 1, 27] = _x4
    _out[..., 1, 28] = _x23
    _out[..., 1, 29] = 0
    _out[..., 1, 30] = _x26
    _out[..., 1, 31] = _x25
    _out[..., 1, 32] = -_x2*_x27 + _x40
    _out[..., 1, 33] = _x33
    _out[..., 1, 34] = _x44
    _out[..., 1, 35] = _x31*_x6
    _out[..., 1, 36] = _x42
    _out[..., 1, 37] = -_x37
    _out[..., 1, 38] = _x36
    _out[..., 1, 39] = _x24*_x34
    _out[..., 1, 40] = _x25
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = Y
    _out[..., 2, 4] = _x45
    _out[..., 2, 5] = 0
    _out[..., 2, 6] = 0
    _out[..., 2, 7] = 0
    _out[..., 2, 8] = 1
    _out[..., 2, 9] = 0
    _out[..., 2, 10] = _x45
    _out[..., 2, 11] = 0
    _out[..., 2, 12] = 0
    _out[..., 2, 13] = 0
    _out[..., 2, 14] = 1
    _out[..., 2, 15] = 0
    _out[..., 2, 16] = _x45
    _out[..., 2, 17] = 0
    _out[..., 2, 18] = 0
    _out[..., 2, 19] = 0
    _out[..., 2, 20] = 0
    _out[..., 2, 21] = 0
    _out[..., 2, 22] = -1
    _out[..., 2, 23] = 0
    _out[..., 2, 24] = 0
    _out[..., 2, 25] = 0
    _out[..., 2, 26] = _x45
    _out[..., 2, 27] = 0
    _out[..., 2, 28] = 0
    _out[..., 2, 29] = -1
    _out[..., 2, 30] = -Y
    _out[..., 2, 31] = _x27
    _out[..., 2, 32] = 0
    _out[..., 2, 33] = _x15
    _out[..., 2, 34] = _x29
    _out[..., 2, 35] = 0
    _out[..., 2, 36] = 0
    _out[..., 2, 37] = 0
    _out[..., 2, 38] = 0
    _out[..., 2, 39] = Y*_x34 + _x28
    _out[..., 2, 40] = _x27*_x35 + _x40
    _out[..., 3, 0] = 0
    _out[..., 3, 1] = 0
    _out[..., 3, 2] = 0
    _out[..., 3, 3] = _x46
    _out[..., 3, 4] = _x47
    _out[..., 3, 5] = _x48
    _out[..., 3, 6] = 0
    _out[..., 3, 7] = 0
    _out[..., 3, 8] = 0
    _out[..., 3, 9] = _x46
    _out[..., 3, 10] = _x47
    _out[..., 3, 11] = _x48
    _out[..., 3, 12] = 0
    _out[..., 3, 13] = 0
    _out[..., 3, 14] = 0
    _out[..., 3, 15] = _x46
    _out[..., 3, 16] = _x47
    _out[..., 3, 17] = _x48
    _out[..., 3, 18] = 0
    _out[..., 3, 19] = 0
    _out[..., 3, 20] = 0
    _out[..., 3, 21] = 0
    _out[..., 3, 22] = 0
    _out[..., 3, 23] = 0
    _out[..., 3, 24] = _x46
    _out[..., 3, 25] = _x44
    _out[..., 3, 26] = _x47
    _out[..., 3, 27] = 0
    _out[..., 3, 28] = 0
    _out[..., 3, 29] = 0
    _out[..., 3, 30] = _x49
    _out[..., 3, 31] = _x50
    _out[..., 3, 32] = _x44
    _out[..., 3, 33] = 0
    _out[..., 3, 34] = 0
    _out[..., 3, 35] = -_x33
    _out[..., 3, 36] = _x44
    _out[..., 3, 37] = 0
    _out[..., 3, 38] = 0
    _out[..., 3, 39] = _x49
    _out[..., 3, 40] = _x35*_x8
    _out[..., 4, 0] = 0
    _out[..., 4, 1] = 0
    _out[..., 4, 2] = 0
    _out[..., 4, 3] = _x50
    _out[..., 4, 4] = _x46
    _out[..., 4, 5] = _x32
    _out[..., 4, 6] = 0
    _out[..., 4, 7] = 0
    _out[..., 4, 8] = 0
    _out[..., 4, 9] = _x50
    _out[..., 4, 10] = _x46
    _out[..., 4, 11] = _x32
    _out[..., 4, 12] = 0
    _out[..., 4, 13] = 0
    _out[..., 4, 14] = 0
    _out[..., 4, 15] = _x50
    _out[..., 4, 16] = _x46
    _out[..., 4, 17] = _x32
    _out[..., 4, 18] = 0
    _out[..., 4, 19] = 0
    _out[..., 4, 20] = 0
    _out[..., 4, 21] = 0
    _out[..., 4, 22] = 0
    _out[..., 4, 23] = 0
    _out[..., 4, 24] = _x50
    _out[..., 4, 25] = _x51
    _out[..., 4, 26] = _x46
    _out[..., 4, 27] = 0
    _out[..., 4, 28] = 0
    _out[..., 4, 29] = 0
    _out[..., 4, 30] = _x47
    _out[..., 4, 31] = _x49
    _out[..., 4, 32] = _x51
    _out[..., 4, 33] = 0
    _out[..., 4, 34] = 0
    _out[..., 4, 35] = _x31
    _out[..., 4, 36] = _x51
    _out[..., 4, 37] = 0
    _out[..., 4, 38] = 0
    _out[..., 4, 39] = _x34*_x8
    _out[..., 4, 40] = _x49
    _out[..., 5, 0] = 0
    _out[..., 5, 1] = 0
    _out[..., 5, 2] = 0
    _out[..., 5, 3] = 0
    _out[..., 5, 4] = _x52
    _out[..., 5, 5] = 0
    _out[..., 5, 6] = 0
    _out[..., 5, 7] = 0
    _out[..., 5, 8] = 0
    _out[..., 5, 9] = 0
    _out[..., 5, 10] = _x52
    _out[..., 5, 11] = 0
    _out[..., 5, 12] = 0
    _out[..., 5, 13] = 0
    _out[..., 5, 14] = 0
    _out[..., 5, 15] = 0
    _out[..., 5, 16] = _x52
    _out[..., 5, 17] = 0
    _out[..., 5, 18] = 0
    _out[..., 5, 19] = 0
    _out[..., 5, 20] = 0
    _out[..., 5, 21] = 0
    _out[..., 5, 22] = 0
    _out[..., 5, 23] = 0
    _out[..., 5, 24] = 0
    _out[..., 5, 25] = 0
    _out[..., 5, 26] = _x52
    _out[..., 5, 27] = 0
    _out[..., 5, 28] = 0
    _out[..., 5, 29] = 0
    _out[..., 5, 30] = 0
    _out[..., 5, 31] = _x15
    _out[..., 5, 32] = 0
    _out[..., 5, 33] = 0
    _out[..., 5, 34] = 0
    _out[..., 5, 35] = 0
    _out[..., 5, 36] = 0
    _out[..., 5, 37] = 0
    _out[..., 5, 38] = 0
    _out[..., 5, 39] = _x44
    _out[..., 5, 40] = _x15*_x35
    return _out


def deviation_first_order(axes, errors, tool_length):
    """First-order pose deviation jacobian_errors(axes) @ errors.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    errors (..., 41): error parameters, mm and rad (ISO 230-1 names)
        [E_XX, E_YX, E_ZX, E_AX, E_BX, E_CX, E_XY, E_YY, E_ZY, E_AY, E_BY, E_CY, E_XZ, E_YZ, E_ZZ, E_AZ, E_BZ, E_CZ, E_C0Y, E_B0Z, E_A0Z, E_XB, E_YB, E_ZB, E_AB, E_BB, E_CB, E_XC, E_YC, E_ZC, E_AC, E_BC, E_CC, E_X0B, E_Y0B, E_A0B, E_B0B, E_X0C, E_Y0C, E_A0C, E_B0C]
    tool_length (...): tool length below the error reference point, mm
    returns (..., 6)
    """
    axes = as_arg(axes, 5, 'axes', 'deviation_first_order')
    errors = as_arg(errors, 41, 'errors', 'deviation_first_order')
    tool_length = as_arg(tool_length, 0, 'tool_length', 'deviation_first_order')
    X = axes[..., 0]
    Y = axes[..., 1]
    Z = axes[..., 2]
    B = axes[..., 3]
    C = axes[..., 4]
    E_XX = errors[..., 0]
    E_YX = errors[..., 1]
    E_ZX = errors[..., 2]
    E_AX = errors[..., 3]
    E_BX = errors[..., 4]
    E_CX = errors[..., 5]
    E_XY = errors[..., 6]
    E_YY = errors[..., 7]
    E_ZY = errors[..., 8]
    E_AY = errors[..., 9]
    E_BY = errors[..., 10]
    E_CY = errors[..., 11]
    E_XZ = errors[..., 12]
    E_YZ = errors[..., 13]
    E_ZZ = errors[..., 14]
    E_AZ = errors[..., 15]
    E_BZ = errors[..., 16]
    E_CZ = errors[..., 17]
    E_C0Y = errors[..., 18]
    E_B0Z = errors[..., 19]
    E_A0Z = errors[..., 20]
    E_XB = errors[..., 21]
    E_YB = errors[..., 22]
    E_ZB = errors[..., 23]
    E_AB = errors[..., 24]
    E_BB = errors[..., 25]
    E_CB = errors[..., 26]
    E_XC = errors[..., 27]
    E_YC = errors[..., 28]
    E_ZC = errors[..., 29]
    E_AC = errors[..., 30]
    E_BC = errors[..., 31]
    E_CC = errors[..., 32]
    E_X0B = errors[..., 33]
    E_Y0B = errors[..., 34]
    E_A0B = errors[..., 35]
    E_B0B = errors[..., 36]
    E_X0C = errors[..., 37]
    E_Y0C = errors[..., 38]
    E_A0C = errors[..., 39]
    E_B0C = errors[..., 40]
    tool_length = tool_length
    _x0 = (1/180)*numpy.pi
    _x1 = C*_x0
    _x2 = numpy.cos(_x1)
    _x3 = numpy.sin(_x1)
    _x4 = Z*_x3
    _x5 = Z*_x2
    _x6 = Y*_x2
    _x7 = B*_x0
    _x8 = numpy.sin(_x7)
    _x9 = E_Y0B*_x8
    _x10 = numpy.cos(_x7)
    _x11 = _x10 - 1
    _x12 = -_x11
    _x13 = E_X0B*_x12
    _x14 = tool_length + 150
    _x15 = -_x14
    _x16 = _x10*_x15
    _x17 = _x16*_x3
    _x18 = _x15*_x8
    _x19 = _x18*_x3
    _x20 = _x16*_x2
    _x21 = Z + _x16
    _x22 = _x2*_x21
    _x23 = E_A0B*_x12
    _x24 = _x23*_x3
    _x25 = _x14 + _x21
    _x26 = _x25*_x3
    _x27 = _x2*_x25
    _x28 = -_x21
    _x29 = _x28*_x3
    _x30 = _x2 - 1
    _x31 = -_x30
    _x32 = -_x2*_x31 + _x3**2
    _x33 = E_B0C*_x25
    _x34 = X + _x18
    _x35 = _x3*_x34
    _x36 = _x2*_x3 + _x3*_x31
    _x37 = Y*_x3
    _x38 = _x18*_x2
    _x39 = _x21*_x3
    _x40 = _x2*_x23
    _x41 = _x2*_x28
    _x42 = E_A0C*_x30
    _x43 = _x10*_x3
    _x44 = _x3*_x8
    _x45 = _x10*_x2
    _x46 = _x2*_x8
    _out = out_array((axes.shape[:-1], errors.shape[:-1], tool_length.shape,), (6,))
    _out[..., 0] = -E_A0C*_x26 + E_A0Z*_x4 + E_AB*_x17 - E_AC*_x26 - E_AX*_x29 - E_AY*_x29 + E_AZ*_x17 + E_B0B*_x19 + E_B0Z*_x5 + E_BB*_x19 - E_BC*_x27 + E_BX*_x22 + E_BY*_x22 + E_BZ*_x20 - E_C0Y*_x6 + E_CB*_x20 + E_CC*(_x35 + _x6) + E_CX*(-_x19 - _x6) - E_CY*_x19 - E_CZ*_x19 + E_X0C*_x32 + E_XB*_x2 - E_XC*_x2 + E_XX*_x2 + E_XY*_x2 + E_XZ*_x2 + E_Y0C*_x36 + E_YC*_x3 - E_YX*_x3 - E_YY*_x3 - E_YZ*_x3 - E_ZB*_x3 + _x13*_x2 - _x15*_x24 + _x2*_x9 + _x31*_x33
    _out[..., 1] = -E_A0Z*_x5 - E_AB*_x20 + E_AC*_x27 + E_AX*_x41 + E_AY*_x41 - E_AZ*_x20 - E_B0B*_x38 + E_B0Z*_x4 - E_BB*_x38 - E_BC*_x26 + E_BX*_x39 + E_BY*_x39 + E_BZ*_x17 - E_C0Y*_x37 + E_CB*_x17 + E_CC*(-_x2*_x34 + _x37) + E_CX*(_x15*_x2*_x8 - _x37) + E_CY*_x38 + E_CZ*_x38 - E_X0C*_x36 + E_XB*_x3 - E_XC*_x3 + E_XX*_x3 + E_XY*_x3 + E_XZ*_x3 + E_Y0C*_x32 - E_YC*_x2 + E_YX*_x2 + E_YY*_x2 + E_YZ*_x2 + E_ZB*_x2 + _x13*_x3 + _x15*_x40 + _x25*_x42 - _x3*_x33 + _x3*_x9
    _out[..., 2] = E_A0C*(Y*_x30 + _x35) - E_AC*Y + E_AX*Y + E_B0C*(_x31*_x34 + _x37) + E_BC*_x34 - E_BX*_x18 - E_BY*_x18 - E_BZ*_x18 - E_CB*_x18 + E_X0B*_x8 + E_Y0B*_x11 - E_YB - E_ZC + E_ZX + E_ZY + E_ZZ
    _out[..., 3] = -E_A0C*_x43 + E_AB*_x43 - E_AC*_x43 + E_AX*_x43 + E_AY*_x43 + E_AZ*_x43 + E_B0B*_x44 + E_B0C*_x10*_x31 + E_BB*_x44 - E_BC*_x45 + E_BX*_x45 + E_BY*_x45 + E_BZ*_x45 + E_CB*_x45 + E_CC*_x44 - E_CX*_x44 - E_CY*_x44 - E_CZ*_x44 - _x24
    _out[..., 4] = -E_AB*_x45 + E_AC*_x45 - E_AX*_x45 - E_AY*_x45 - E_AZ*_x45 - E_B0B*_x46 - E_B0C*_x43 - E_BB*_x46 - E_BC*_x43 + E_BX*_x43 + E_BY*_x43 + E_BZ*_x43 + E_CB*_x43 - E_CC*_x46 + E_CX*_x46 + E_CY*_x46 + E_CZ*_x46 + _x10*_x42 + _x40
    _out[..., 5] = E_A0C*_x3*_x8 + E_B0C*_x31*_x8 + E_BC*_x8 - E_BX*_x8 - E_BY*_x8 - E_BZ*_x8 - E_CB*_x8
    return _out


def correction_first_order(axes, errors, tool_length):
    """First order, for compensation: rows 0-2 the linear-axis step (mm) -J_lin^-1 dev[:3] that cancels the tool-tip deviation dev = deviation_first_order (J_lin = d tip / d linear axes, nominal, so |dev[:3]| = |J_lin step|); rows 3-5 the tool-axis deviation dev[3:] turned into the machine (base) frame by the nominal table rotation (same norm).

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    errors (..., 41): error parameters, mm and rad (ISO 230-1 names)
        [E_XX, E_YX, E_ZX, E_AX, E_BX, E_CX, E_XY, E_YY, E_ZY, E_AY, E_BY, E_CY, E_XZ, E_YZ, E_ZZ, E_AZ, E_BZ, E_CZ, E_C0Y, E_B0Z, E_A0Z, E_XB, E_YB, E_ZB, E_AB, E_BB, E_CB, E_XC, E_YC, E_ZC, E_AC, E_BC, E_CC, E_X0B, E_Y0B, E_A0B, E_B0B, E_X0C, E_Y0C, E_A0C, E_B0C]
    tool_length (...): tool length below the error reference point, mm
    returns (..., 6)
    """
    axes = as_arg(axes, 5, 'axes', 'correction_first_order')
    errors = as_arg(errors, 41, 'errors', 'correction_first_order')
    tool_length = as_arg(tool_length, 0, 'tool_length', 'correction_first_order')
    X = axes[..., 0]
    Y = axes[..., 1]
    Z = axes[..., 2]
    B = axes[..., 3]
    C = axes[..., 4]
    E_XX = errors[..., 0]
    E_YX = errors[..., 1]
    E_ZX = errors[..., 2]
    E_AX = errors[..., 3]
    E_BX = errors[..., 4]
    E_CX = errors[..., 5]
    E_XY = errors[..., 6]
    E_YY = errors[..., 7]
    E_ZY = errors[..., 8]
    E_AY = errors[..., 9]
    E_BY = errors[..., 10]
    E_CY = errors[..., 11]
    E_XZ = errors[..., 12]
    E_YZ = errors[..., 13]
    E_ZZ = errors[..., 14]
    E_AZ = errors[..., 15]
    E_BZ = errors[..., 16]
    E_CZ = errors[..., 17]
    E_C0Y = errors[..., 18]
    E_B0Z = errors[..., 19]
    E_A0Z = errors[..., 20]
    E_XB = errors[..., 21]
    E_YB = errors[..., 22]
    E_ZB = errors[..., 23]
    E_AB = errors[..., 24]
    E_BB = errors[..., 25]
    E_CB = errors[..., 26]
    E_XC = errors[..., 27]
    E_YC = errors[..., 28]
    E_ZC = errors[..., 29]
    E_AC = errors[..., 30]
    E_BC = errors[..., 31]
    E_CC = errors[..., 32]
    E_X0B = errors[..., 33]
    E_Y0B = errors[..., 34]
    E_A0B = errors[..., 35]
    E_B0B = errors[..., 36]
    E_X0C = errors[..., 37]
    E_Y0C = errors[..., 38]
    E_A0C = errors[..., 39]
    E_B0C = errors[..., 40]
    tool_length = tool_length
    _x0 = (1/180)*numpy.pi
    _x1 = B*_x0
    _x2 = numpy.sin(_x1)
    _x3 = C*_x0
    _x4 = numpy.sin(_x3)
    _x5 = numpy.cos(_x1)
    _x6 = _x5 - 1
    _x7 = tool_length + 150
    _x8 = _x5*_x7
    _x9 = numpy.cos(_x3)
    _x10 = _x9 - 1
    _x11 = -_x10
    _x12 = -_x8
    _x13 = Z + _x12
    _x14 = -_x13
    _x15 = _x13 + _x7
    _x16 = _x15*_x4
    _x17 = _x9*tool_length + 150*_x9 - tool_length - 150
    _x18 = Z + _x7
    _x19 = -_x18*_x9 + _x18
    _x20 = _x2*_x7
    _x21 = X - _x20
    _x22 = -_x17
    _x23 = -_x6
    _x24 = E_B0C*_x5
    _out = out_array((axes.shape[:-1], errors.shape[:-1], tool_length.shape,), (6,))
    _out[..., 0] = E_A0C*_x16 + E_B0C*(_x17*_x5 + _x19) - E_B0Z*Z + E_BC*_x15 + E_BX*_x14 + E_BY*_x14 + E_BZ*_x8 + E_C0Y*Y + E_CB*_x8 - E_CC*Y + E_CX*Y + E_X0B*_x6 + E_X0C*_x11 - E_XB + E_XC - E_XX - E_XY - E_XZ - E_Y0B*_x2 - E_Y0C*_x4
    _out[..., 1] = E_A0B*(_x12 + _x7) + E_A0C*(-_x19 + _x22*_x5) + E_A0Z*Z - E_AB*_x8 - E_AC*_x15 + E_AX*_x13 + E_AY*_x13 - E_AZ*_x8 - E_B0B*_x20 + E_B0C*_x16 - E_BB*_x20 + E_CC*_x21 + E_CX*_x20 + E_CY*_x20 + E_CZ*_x20 + E_X0C*_x4 + E_Y0C*_x11 + E_YC - E_YX - E_YY - E_YZ - E_ZB
    _out[..., 2] = E_A0C*(-X*_x4 - Y*_x9 + Y + _x2*_x4*_x7) + E_AC*Y - E_AX*Y + E_B0C*(X*_x9 - X - Y*_x4 + _x2*_x22) - E_BC*_x21 - E_BX*_x20 - E_BY*_x20 - E_BZ*_x20 - E_CB*_x20 - E_X0B*_x2 + E_Y0B*_x23 + E_YB + E_ZC - E_ZX - E_ZY - E_ZZ
    _out[..., 3] = -E_A0C*_x4*_x5 - E_BC*_x5 + E_BX*_x5 + E_BY*_x5 + E_BZ*_x5 + E_CB*_x5 + _x10*_x24
    _out[..., 4] = E_A0B*_x23 + E_A0C*_x11*_x5 - E_AB*_x5 + E_AC*_x5 - E_AX*_x5 - E_AY*_x5 - E_AZ*_x5 - E_B0B*_x2 - E_BB*_x2 - E_CC*_x2 + E_CX*_x2 + E_CY*_x2 + E_CZ*_x2 - _x24*_x4
    _out[..., 5] = E_A0C*_x2*_x4 + E_B0C*_x11*_x2 + E_BC*_x2 - E_BX*_x2 - E_BY*_x2 - E_BZ*_x2 - E_CB*_x2
    return _out


def tool_point(axes, errors, point):
    """Machine-frame position (mm) of a point fixed to the tool, exact error-inclusive.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    errors (..., 41): error parameters, mm and rad
        [E_XX, E_YX, E_ZX, E_AX, E_BX, E_CX, E_XY, E_YY, E_ZY, E_AY, E_BY, E_CY, E_XZ, E_YZ, E_ZZ, E_AZ, E_BZ, E_CZ, E_C0Y, E_B0Z, E_A0Z, E_XB, E_YB, E_ZB, E_AB, E_BB, E_CB, E_XC, E_YC, E_ZC, E_AC, E_BC, E_CC, E_X0B, E_Y0B, E_A0B, E_B0B, E_X0C, E_Y0C, E_A0C, E_B0C]
    point (..., 3): point fixed to the tool, mm, relative to the error reference point (spindle gauge point, tool_length = 0)
        [px, py, pz]
    returns (..., 3)
    """
    axes = as_arg(axes, 5, 'axes', 'tool_point')
    errors = as_arg(errors, 41, 'errors', 'tool_point')
    point = as_arg(point, 3, 'point', 'tool_point')
    X = axes[..., 0]
    Y = axes[..., 1]
    Z = axes[..., 2]
    B = axes[..., 3]
    E_XX = errors[..., 0]
    E_YX = errors[..., 1]
    E_ZX = errors[..., 2]
    E_AX = errors[..., 3]
    E_BX = errors[..., 4]
    E_CX = errors[..., 5]
    E_XY = errors[..., 6]
    E_YY = errors[..., 7]
    E_ZY = errors[..., 8]
    E_AY = errors[..., 9]
    E_BY = errors[..., 10]
    E_CY = errors[..., 11]
    E_XZ = errors[..., 12]
    E_YZ = errors[..., 13]
    E_ZZ = errors[..., 14]
    E_AZ = errors[..., 15]
    E_BZ = errors[..., 16]
    E_CZ = errors[..., 17]
    E_C0Y = errors[..., 18]
    E_B0Z = errors[..., 19]
    E_A0Z = errors[..., 20]
    E_XB = errors[..., 21]
    E_YB = errors[..., 22]
    E_ZB = errors[..., 23]
    E_AB = errors[..., 24]
    E_BB = errors[..., 25]
    E_CB = errors[..., 26]
    E_X0B = errors[..., 33]
    E_Y0B = errors[..., 34]
    E_A0B = errors[..., 35]
    E_B0B = errors[..., 36]
    px = point[..., 0]
    py = point[..., 1]
    pz = point[..., 2]
    _x0 = E_XY - Y*numpy.sin(E_C0Y)
    _x1 = numpy.cos(E_CX)
    _x2 = numpy.cos(E_BX)
    _x3 = _x1*_x2
    _x4 = numpy.sin(E_AX)
    _x5 = numpy.sin(E_CX)
    _x6 = _x4*_x5
    _x7 = numpy.sin(E_BX)
    _x8 = numpy.cos(E_AX)
    _x9 = _x1*_x8
    _x10 = _x6 + _x7*_x9
    _x11 = E_YY + Y*numpy.cos(E_C0Y)
    _x12 = _x1*_x4
    _x13 = _x12*_x7 - _x5*_x8
    _x14 = Z*numpy.cos(E_A0Z)
    _x15 = E_XZ + _x14*numpy.sin(E_B0Z)
    _x16 = numpy.cos(E_CY)
    _x17 = numpy.cos(E_BY)
    _x18 = _x16*_x17
    _x19 = numpy.sin(E_BY)
    _x20 = numpy.sin(E_CY)
    _x21 = _x17*_x20
    _x22 = -_x10*_x19 + _x13*_x21 + _x18*_x3
    _x23 = E_YZ - Z*numpy.sin(E_A0Z)
    _x24 = numpy.sin(E_AY)
    _x25 = _x10*_x17
    _x26 = numpy.cos(E_AY)
    _x27 = _x16*_x24
    _x28 = _x19*_x27 - _x20*_x26
    _x29 = _x16*_x26
    _x30 = _x20*_x24
    _x31 = _x19*_x30 + _x29
    _x32 = _x13*_x31 + _x24*_x25 + _x28*_x3
    _x33 = E_ZZ + _x14*numpy.cos(E_B0Z)
    _x34 = _x19*_x29 + _x30
    _x35 = _x19*_x20*_x26 - _x27
    _x36 = _x13*_x35 + _x25*_x26 + _x3*_x34
    _x37 = numpy.sin(E_A0B)
    _x38 = numpy.sin(E_AB)
    _x39 = numpy.cos(E_BB)
    _x40 = _x38*_x39
    _x41 = numpy.sin(E_BB)
    _x42 = numpy.sin(E_B0B)
    _x43 = numpy.cos(E_A0B)
    _x44 = _x42*_x43
    _x45 = numpy.cos(E_AB)
    _x46 = numpy.cos(E_B0B)
    _x47 = -_x37*_x40 + _x39*_x43*_x45*_x46 - _x41*_x44
    _x48 = (1/180)*numpy.pi*B
    _x49 = numpy.sin(_x48)
    _x50 = -_x39*_x42*_x45 - _x41*_x46
    _x51 = numpy.cos(_x48)
    _x52 = _x37*_x42
    _x53 = _x37*_x39*_x45*_x46 + _x40*_x43 - _x41*_x52
    _x54 = -_x49*_x50 + _x51*_x53
    _x55 = -_x37*_x47 + _x43*_x54
    _x56 = numpy.sin(E_CZ)
    _x57 = numpy.cos(E_AZ)
    _x58 = numpy.sin(E_BZ)
    _x59 = numpy.sin(E_AZ)
    _x60 = numpy.cos(E_CZ)
    _x61 = _x59*_x60
    _x62 = -_x56*_x57 + _x58*_x61
    _x63 = numpy.cos(E_BZ)
    _x64 = _x36*_x63
    _x65 = _x57*_x60
    _x66 = _x56*_x59
    _x67 = _x58*_x66 + _x65
    _x68 = _x22*_x62 + _x32*_x67 + _x59*_x64
    _x69 = _x55*_x68
    _x70 = numpy.cos(E_CB)
    _x71 = _x39*_x70
    _x72 = numpy.sin(E_CB)
    _x73 = _x38*_x70
    _x74 = _x41*_x73 - _x45*_x72
    _x75 = _x38*_x72
    _x76 = _x45*_x70
    _x77 = _x41*_x76 + _x75
    _x78 = _x46*_x77
    _x79 = -_x37*_x74 + _x43*_x78 + _x44*_x71
    _x80 = _x39*_x46*_x70 - _x42*_x77
    _x81 = _x37*_x78 + _x43*_x74 + _x52*_x71
    _x82 = -_x49*_x80 + _x51*_x81
    _x83 = -_x37*_x79 + _x43*_x82
    _x84 = _x60*_x63
    _x85 = _x56*_x63
    _x86 = _x22*_x84 + _x32*_x85 - _x36*_x58
    _x87 = _x83*_x86
    _x88 = _x39*_x72
    _x89 = _x41*_x75 + _x76
    _x90 = _x41*_x45*_x72 - _x73
    _x91 = _x46*_x90
    _x92 = -_x37*_x89 + _x43*_x91 + _x44*_x88
    _x93 = _x39*_x46*_x72 - _x42*_x90
    _x94 = _x37*_x91 + _x43*_x89 + _x52*_x88
    _x95 = -_x49*_x93 + _x51*_x94
    _x96 = -_x37*_x92 + _x43*_x95
    _x97 = _x58*_x65 + _x66
    _x98 = _x56*_x57*_x58 - _x61
    _x99 = -_x22*_x97 - _x32*_x98 - _x57*_x64
    _x100 = _x96*_x99
    _x101 = -E_X0B*_x44 + E_Y0B*_x37
    _x102 = _x49*_x53 + _x50*_x51
    _x103 = _x102*_x46
    _x104 = -E_X0B*_x52 - E_Y0B*_x43
    _x105 = -E_X0B*_x103 - E_X0B*_x41 + E_Y0B*_x40 + E_ZB + _x101*_x47 + _x104*_x54
    _x106 = E_X0B*_x39
    _x107 = _x49*_x81 + _x51*_x80
    _x108 = _x107*_x46
    _x109 = -E_X0B*_x108 + E_XB + E_Y0B*_x74 + _x101*_x79 + _x104*_x82 + _x106*_x70
    _x110 = _x49*_x94 + _x51*_x93
    _x111 = _x110*_x46
    _x112 = -E_X0B*_x111 + E_Y0B*_x89 + E_YB + _x101*_x92 + _x104*_x95 + _x106*_x72
    _x113 = _x103 + _x44*_x47 + _x52*_x54
    _x114 = _x108 + _x44*_x79 + _x52*_x82
    _x115 = _x111 + _x44*_x92 + _x52*_x95
    _x116 = _x43*_x46
    _x117 = _x37*_x46
    _x118 = -_x102*_x42 + _x116*_x47 + _x117*_x54
    _x119 = -_x107*_x42 + _x116*_x79 + _x117*_x82
    _x120 = -_x110*_x42 + _x116*_x92 + _x117*_x95
    _x121 = _x2*_x5
    _x122 = -_x12 + _x5*_x7*_x8
    _x123 = _x6*_x7 + _x9
    _x124 = _x121*_x18 - _x122*_x19 + _x123*_x21
    _x125 = _x122*_x17
    _x126 = _x121*_x28 + _x123*_x31 + _x125*_x24
    _x127 = _x121*_x34 + _x123*_x35 + _x125*_x26
    _x128 = _x127*_x63
    _x129 = _x124*_x62 + _x126*_x67 + _x128*_x59
    _x130 = _x129*_x55
    _x131 = _x124*_x84 + _x126*_x85 - _x127*_x58
    _x132 = _x131*_x83
    _x133 = -_x124*_x97 - _x126*_x98 - _x128*_x57
    _x134 = _x133*_x96
    _x135 = _x2*_x8
    _x136 = _x2*_x4
    _x137 = -_x135*_x19 + _x17*_x2*_x20*_x4 - _x18*_x7
    _x138 = _x135*_x17
    _x139 = _x136*_x31 + _x138*_x24 - _x28*_x7
    _x140 = _x136*_x35 + _x138*_x26 - _x34*_x7
    _x141 = _x140*_x63
    _x142 = _x137*_x62 + _x139*_x67 + _x141*_x59
    _x143 = _x142*_x55
    _x144 = _x137*_x84 + _x139*_x85 - _x140*_x58
    _x145 = _x144*_x83
    _x146 = -_x137*_x97 - _x139*_x98 - _x141*_x57
    _x147 = _x146*_x96
    _out = out_array((axes.shape[:-1], errors.shape[:-1], point.shape[:-1],), (3,))
    _out[..., 0] = E_XX + E_ZY*_x10 + X + _x0*_x3 + 150*_x100 + _x105*_x68 + _x109*_x86 + _x11*_x13 + _x112*_x99 + _x15*_x22 + _x23*_x32 + _x33*_x36 + 150*_x69 + 150*_x87 + px*(_x113*_x68 + _x114*_x86 + _x115*_x99) + py*(_x118*_x68 + _x119*_x86 + _x120*_x99) + pz*(-_x100 - _x69 - _x87)
    _out[..., 1] = E_YX + E_ZY*_x122 + _x0*_x121 + _x105*_x129 + _x109*_x131 + _x11*_x123 + _x112*_x133 + _x124*_x15 + _x126*_x23 + _x127*_x33 + 150*_x130 + 150*_x132 + 150*_x134 + px*(_x113*_x129 + _x114*_x131 + _x115*_x133) + py*(_x118*_x129 + _x119*_x131 + _x120*_x133) + pz*(-_x130 - _x132 - _x134)
    _out[..., 2] = E_ZX + E_ZY*_x135 - _x0*_x7 + _x105*_x142 + _x109*_x144 + _x11*_x136 + _x112*_x146 + _x137*_x15 + _x139*_x23 + _x140*_x33 + 150*_x143 + 150*_x145 + 150*_x147 + px*(_x113*_x142 + _x114*_x144 + _x115*_x146) + py*(_x118*_x142 + _x119*_x144 + _x120*_x146) + pz*(-_x143 - _x145 - _x147) + 150
    return _out


def tool_point_jacobian_errors(axes, point):
    """d tool_point / d errors at zero error (3 x n_errors), per mm and per rad.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    point (..., 3): point fixed to the tool, mm, relative to the error reference point (spindle gauge point, tool_length = 0)
        [px, py, pz]
    returns (..., 3, 41)
    """
    axes = as_arg(axes, 5, 'axes', 'tool_point_jacobian_errors')
    point = as_arg(point, 3, 'point', 'tool_point_jacobian_errors')
    Y = axes[..., 1]
    Z = axes[..., 2]
    B = axes[..., 3]
    px = point[..., 0]
    py = point[..., 1]
    pz = point[..., 2]
    _x0 = (1/180)*numpy.pi*B
    _x1 = numpy.cos(_x0)
    _x2 = _x1*pz
    _x3 = 150*_x1
    _x4 = numpy.sin(_x0)
    _x5 = _x4*px
    _x6 = Z + _x2 - _x3 - _x5
    _x7 = Y + py
    _x8 = -py
    _x9 = _x3 + _x5
    _x10 = -_x2 + _x9
    _x11 = -_x10
    _x12 = _x1 - 1
    _x13 = -_x12
    _x14 = _x4*py
    _x15 = _x13*py
    _x16 = -_x6
    _x17 = _x4*pz
    _x18 = 150*_x4
    _x19 = _x1*px + _x17 - _x18
    _x20 = -_x19
    _out = out_array((axes.shape[:-1], point.shape[:-1],), (3, 41))
    _out[..., 0, 0] = 1
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = 0
    _out[..., 0, 4] = _x6
    _out[..., 0, 5] = -_x7
    _out[..., 0, 6] = 1
    _out[..., 0, 7] = 0
    _out[..., 0, 8] = 0
    _out[..., 0, 9] = 0
    _out[..., 0, 10] = _x6
    _out[..., 0, 11] = _x8
    _out[..., 0, 12] = 1
    _out[..., 0, 13] = 0
    _out[..., 0, 14] = 0
    _out[..., 0, 15] = 0
    _out[..., 0, 16] = _x11
    _out[..., 0, 17] = _x8
    _out[..., 0, 18] = -Y
    _out[..., 0, 19] = Z
    _out[..., 0, 20] = 0
    _out[..., 0, 21] = 1
    _out[..., 0, 22] = 0
    _out[..., 0, 23] = 0
    _out[..., 0, 24] = 0
    _out[..., 0, 25] = py
    _out[..., 0, 26] = _x11
    _out[..., 0, 27] = 0
    _out[..., 0, 28] = 0
    _out[..., 0, 29] = 0
    _out[..., 0, 30] = 0
    _out[..., 0, 31] = 0
    _out[..., 0, 32] = 0
    _out[..., 0, 33] = _x13
    _out[..., 0, 34] = _x4
    _out[..., 0, 35] = -_x14
    _out[..., 0, 36] = _x15
    _out[..., 0, 37] = 0
    _out[..., 0, 38] = 0
    _out[..., 0, 39] = 0
    _out[..., 0, 40] = 0
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 1
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = _x16
    _out[..., 1, 4] = 0
    _out[..., 1, 5] = _x19
    _out[..., 1, 6] = 0
    _out[..., 1, 7] = 1
    _out[..., 1, 8] = 0
    _out[..., 1, 9] = _x16
    _out[..., 1, 10] = 0
    _out[..., 1, 11] = _x19
    _out[..., 1, 12] = 0
    _out[..., 1, 13] = 1
    _out[..., 1, 14] = 0
    _out[..., 1, 15] = _x10
    _out[..., 1, 16] = 0
    _out[..., 1, 17] = _x19
    _out[..., 1, 18] = 0
    _out[..., 1, 19] = 0
    _out[..., 1, 20] = -Z
    _out[..., 1, 21] = 0
    _out[..., 1, 22] = 0
    _out[..., 1, 23] = 1
    _out[..., 1, 24] = _x10
    _out[..., 1, 25] = _x20
    _out[..., 1, 26] = 0
    _out[..., 1, 27] = 0
    _out[..., 1, 28] = 0
    _out[..., 1, 29] = 0
    _out[..., 1, 30] = 0
    _out[..., 1, 31] = 0
    _out[..., 1, 32] = 0
    _out[..., 1, 33] = 0
    _out[..., 1, 34] = 0
    _out[..., 1, 35] = _x13*pz + _x9 - 150
    _out[..., 1, 36] = _x13*px - _x17 + _x18
    _out[..., 1, 37] = 0
    _out[..., 1, 38] = 0
    _out[..., 1, 39] = 0
    _out[..., 1, 40] = 0
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 1
    _out[..., 2, 3] = _x7
    _out[..., 2, 4] = _x20
    _out[..., 2, 5] = 0
    _out[..., 2, 6] = 0
    _out[..., 2, 7] = 0
    _out[..., 2, 8] = 1
    _out[..., 2, 9] = py
    _out[..., 2, 10] = _x20
    _out[..., 2, 11] = 0
    _out[..., 2, 12] = 0
    _out[..., 2, 13] = 0
    _out[..., 2, 14] = 1
    _out[..., 2, 15] = py
    _out[..., 2, 16] = _x20
    _out[..., 2, 17] = 0
    _out[..., 2, 18] = 0
    _out[..., 2, 19] = 0
    _out[..., 2, 20] = 0
    _out[..., 2, 21] = 0
    _out[..., 2, 22] = -1
    _out[..., 2, 23] = 0
    _out[..., 2, 24] = py
    _out[..., 2, 25] = 0
    _out[..., 2, 26] = _x20
    _out[..., 2, 27] = 0
    _out[..., 2, 28] = 0
    _out[..., 2, 29] = 0
    _out[..., 2, 30] = 0
    _out[..., 2, 31] = 0
    _out[..., 2, 32] = 0
    _out[..., 2, 33] = _x4
    _out[..., 2, 34] = _x12
    _out[..., 2, 35] = _x15
    _out[..., 2, 36] = _x14
    _out[..., 2, 37] = 0
    _out[..., 2, 38] = 0
    _out[..., 2, 39] = 0
    _out[..., 2, 40] = 0
    return _out


def table_point(axes, errors, point):
    """Machine-frame position (mm) of a point fixed to the table, exact error-inclusive.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    errors (..., 41): error parameters, mm and rad
        [E_XX, E_YX, E_ZX, E_AX, E_BX, E_CX, E_XY, E_YY, E_ZY, E_AY, E_BY, E_CY, E_XZ, E_YZ, E_ZZ, E_AZ, E_BZ, E_CZ, E_C0Y, E_B0Z, E_A0Z, E_XB, E_YB, E_ZB, E_AB, E_BB, E_CB, E_XC, E_YC, E_ZC, E_AC, E_BC, E_CC, E_X0B, E_Y0B, E_A0B, E_B0B, E_X0C, E_Y0C, E_A0C, E_B0C]
    point (..., 3): point fixed to the table, mm, in workpiece (table) coordinates
        [px, py, pz]
    returns (..., 3)
    """
    axes = as_arg(axes, 5, 'axes', 'table_point')
    errors = as_arg(errors, 41, 'errors', 'table_point')
    point = as_arg(point, 3, 'point', 'table_point')
    C = axes[..., 4]
    E_XC = errors[..., 27]
    E_YC = errors[..., 28]
    E_ZC = errors[..., 29]
    E_AC = errors[..., 30]
    E_BC = errors[..., 31]
    E_CC = errors[..., 32]
    E_X0C = errors[..., 37]
    E_Y0C = errors[..., 38]
    E_A0C = errors[..., 39]
    E_B0C = errors[..., 40]
    px = point[..., 0]
    py = point[..., 1]
    pz = point[..., 2]
    _x0 = numpy.cos(E_CC)
    _x1 = numpy.cos(E_BC)
    _x2 = _x0*_x1
    _x3 = numpy.sin(E_CC)
    _x4 = numpy.cos(E_AC)
    _x5 = numpy.sin(E_BC)
    _x6 = numpy.sin(E_AC)
    _x7 = _x0*_x6
    _x8 = -_x3*_x4 + _x5*_x7
    _x9 = numpy.sin(E_A0C)
    _x10 = numpy.cos(E_A0C)
    _x11 = numpy.sin(E_B0C)
    _x12 = E_X0C*_x11
    _x13 = E_Y0C*_x9 - _x10*_x12
    _x14 = _x10*_x11
    _x15 = _x3*_x6
    _x16 = _x0*_x4
    _x17 = _x15 + _x16*_x5
    _x18 = numpy.cos(E_B0C)
    _x19 = _x17*_x18
    _x20 = _x10*_x19 + _x14*_x2 - _x8*_x9
    _x21 = (1/180)*numpy.pi*C
    _x22 = numpy.cos(_x21)
    _x23 = _x0*_x1*_x18 - _x11*_x17
    _x24 = numpy.sin(_x21)
    _x25 = _x11*_x9
    _x26 = _x10*_x8 + _x19*_x9 + _x2*_x25
    _x27 = _x22*_x23 - _x24*_x26
    _x28 = _x18*_x27
    _x29 = -E_Y0C*_x10 - _x12*_x9
    _x30 = _x22*_x26 + _x23*_x24
    _x31 = _x10*_x20
    _x32 = _x30*_x9
    _x33 = _x1*_x3
    _x34 = _x15*_x5 + _x16
    _x35 = _x3*_x4*_x5 - _x7
    _x36 = _x18*_x35
    _x37 = _x10*_x36 + _x14*_x33 - _x34*_x9
    _x38 = _x1*_x18*_x3 - _x11*_x35
    _x39 = _x10*_x34 + _x25*_x33 + _x36*_x9
    _x40 = _x22*_x38 - _x24*_x39
    _x41 = _x18*_x40
    _x42 = _x22*_x39 + _x24*_x38
    _x43 = _x10*_x37
    _x44 = _x42*_x9
    _x45 = _x1*_x6
    _x46 = _x1*_x10*_x18*_x4 - _x14*_x5 - _x45*_x9
    _x47 = _x1*_x4
    _x48 = -_x11*_x47 - _x18*_x5
    _x49 = _x18*_x9
    _x50 = _x10*_x45 - _x25*_x5 + _x47*_x49
    _x51 = _x22*_x48 - _x24*_x50
    _x52 = _x18*_x51
    _x53 = _x22*_x50 + _x24*_x48
    _out = out_array((axes.shape[:-1], errors.shape[:-1], point.shape[:-1],), (3,))
    _out[..., 0] = E_X0C*_x2 - E_X0C*_x28 + E_XC + E_Y0C*_x8 + _x13*_x20 + _x29*_x30 + px*(_x11*_x31 + _x11*_x32 + _x28) + py*(_x10*_x30 - _x20*_x9) + pz*(-_x11*_x27 + _x18*_x31 + _x18*_x32)
    _out[..., 1] = E_X0C*_x33 - E_X0C*_x41 + E_Y0C*_x34 + E_YC + _x13*_x37 + _x29*_x42 + px*(_x11*_x43 + _x11*_x44 + _x41) + py*(_x10*_x42 - _x37*_x9) + pz*(-_x11*_x40 + _x18*_x43 + _x18*_x44)
    _out[..., 2] = -E_X0C*_x5 - E_X0C*_x52 + E_Y0C*_x45 + E_ZC + _x13*_x46 + _x29*_x53 + px*(_x14*_x46 + _x25*_x53 + _x52) + py*(_x10*_x53 - _x46*_x9) + pz*(_x10*_x18*_x46 - _x11*_x51 + _x49*_x53)
    return _out


def table_point_jacobian_errors(axes, point):
    """d table_point / d errors at zero error (3 x n_errors), per mm and per rad.

    axes (..., 5): axis positions: linear mm, rotary deg
        [X, Y, Z, B, C]
    point (..., 3): point fixed to the table, mm, in workpiece (table) coordinates
        [px, py, pz]
    returns (..., 3, 41)
    """
    axes = as_arg(axes, 5, 'axes', 'table_point_jacobian_errors')
    point = as_arg(point, 3, 'point', 'table_point_jacobian_errors')
    C = axes[..., 4]
    px = point[..., 0]
    py = point[..., 1]
    pz = point[..., 2]
    _x0 = (1/180)*numpy.pi*C
    _x1 = numpy.sin(_x0)
    _x2 = _x1*px
    _x3 = numpy.cos(_x0)
    _x4 = _x2 - _x3*py
    _x5 = _x3 - 1
    _x6 = -_x5
    _x7 = _x1*pz
    _x8 = _x1*py
    _x9 = _x3*px + _x8
    _out = out_array((axes.shape[:-1], point.shape[:-1],), (3, 41))
    _out[..., 0, 0] = 0
    _out[..., 0, 1] = 0
    _out[..., 0, 2] = 0
    _out[..., 0, 3] = 0
    _out[..., 0, 4] = 0
    _out[..., 0, 5] = 0
    _out[..., 0, 6] = 0
    _out[..., 0, 7] = 0
    _out[..., 0, 8] = 0
    _out[..., 0, 9] = 0
    _out[..., 0, 10] = 0
    _out[..., 0, 11] = 0
    _out[..., 0, 12] = 0
    _out[..., 0, 13] = 0
    _out[..., 0, 14] = 0
    _out[..., 0, 15] = 0
    _out[..., 0, 16] = 0
    _out[..., 0, 17] = 0
    _out[..., 0, 18] = 0
    _out[..., 0, 19] = 0
    _out[..., 0, 20] = 0
    _out[..., 0, 21] = 0
    _out[..., 0, 22] = 0
    _out[..., 0, 23] = 0
    _out[..., 0, 24] = 0
    _out[..., 0, 25] = 0
    _out[..., 0, 26] = 0
    _out[..., 0, 27] = 1
    _out[..., 0, 28] = 0
    _out[..., 0, 29] = 0
    _out[..., 0, 30] = 0
    _out[..., 0, 31] = pz
    _out[..., 0, 32] = _x4
    _out[..., 0, 33] = 0
    _out[..., 0, 34] = 0
    _out[..., 0, 35] = 0
    _out[..., 0, 36] = 0
    _out[..., 0, 37] = _x6
    _out[..., 0, 38] = -_x1
    _out[..., 0, 39] = _x7
    _out[..., 0, 40] = _x6*pz
    _out[..., 1, 0] = 0
    _out[..., 1, 1] = 0
    _out[..., 1, 2] = 0
    _out[..., 1, 3] = 0
    _out[..., 1, 4] = 0
    _out[..., 1, 5] = 0
    _out[..., 1, 6] = 0
    _out[..., 1, 7] = 0
    _out[..., 1, 8] = 0
    _out[..., 1, 9] = 0
    _out[..., 1, 10] = 0
    _out[..., 1, 11] = 0
    _out[..., 1, 12] = 0
    _out[..., 1, 13] = 0
    _out[..., 1, 14] = 0
    _out[..., 1, 15] = 0
    _out[..., 1, 16] = 0
    _out[..., 1, 17] = 0
    _out[..., 1, 18] = 0
    _out[..., 1, 19] = 0
    _out[..., 1, 20] = 0
    _out[..., 1, 21] = 0
    _out[..., 1, 22] = 0
    _out[..., 1, 23] = 0
    _out[..., 1, 24] = 0
    _out[..., 1, 25] = 0
    _out[..., 1, 26] = 0
    _out[..., 1, 27] = 0
    _out[..., 1, 28] = 1
    _out[..., 1, 29] = 0
    _out[..., 1, 30] = -pz
    _out[..., 1, 31] = 0
    _out[..., 1, 32] = _x9
    _out[..., 1, 33] = 0
    _out[..., 1, 34] = 0
    _out[..., 1, 35] = 0
    _out[..., 1, 36] = 0
    _out[..., 1, 37] = _x1
    _out[..., 1, 38] = _x6
    _out[..., 1, 39] = _x5*pz
    _out[..., 1, 40] = _x7
    _out[..., 2, 0] = 0
    _out[..., 2, 1] = 0
    _out[..., 2, 2] = 0
    _out[..., 2, 3] = 0
    _out[..., 2, 4] = 0
    _out[..., 2, 5] = 0
    _out[..., 2, 6] = 0
    _out[..., 2, 7] = 0
    _out[..., 2, 8] = 0
    _out[..., 2, 9] = 0
    _out[..., 2, 10] = 0
    _out[..., 2, 11] = 0
    _out[..., 2, 12] = 0
    _out[..., 2, 13] = 0
    _out[..., 2, 14] = 0
    _out[..., 2, 15] = 0
    _out[..., 2, 16] = 0
    _out[..., 2, 17] = 0
    _out[..., 2, 18] = 0
    _out[..., 2, 19] = 0
    _out[..., 2, 20] = 0
    _out[..., 2, 21] = 0
    _out[..., 2, 22] = 0
    _out[..., 2, 23] = 0
    _out[..., 2, 24] = 0
    _out[..., 2, 25] = 0
    _out[..., 2, 26] = 0
    _out[..., 2, 27] = 0
    _out[..., 2, 28] = 0
    _out[..., 2, 29] = 1
    _out[..., 2, 30] = -_x4
    _out[..., 2, 31] = -_x9
    _out[..., 2, 32] = 0
    _out[..., 2, 33] = 0
    _out[..., 2, 34] = 0
    _out[..., 2, 35] = 0
    _out[..., 2, 36] = 0
    _out[..., 2, 37] = 0
    _out[..., 2, 38] = 0
    _out[..., 2, 39] = -_x2 + _x5*py
    _out[..., 2, 40] = _x6*px - _x8
    return _out


def ik_tilt(n):
    """Both candidate B angles (deg) for the tool axis: phi +/- t with cos t = (k - a)/rho (a = 0, rho = 1, phi = 0); reachable k in [-1, 1].

    n (..., 3): unit tool axis in the workpiece frame
        [i, j, k]
    returns (..., 2)
    """
    n = as_arg(n, 3, 'n', 'ik_tilt')
    i = n[..., 0]
    j = n[..., 1]
    k = n[..., 2]
    _x0 = 180*numpy.arctan2(numpy.sqrt(i**2 + j**2), k)/numpy.pi
    _out = out_array((n.shape[:-1],), (2,))
    _out[..., 0] = _x0
    _out[..., 1] = -_x0
    return _out


def ik_rotary(tilt, ij):
    """[C in (-180, 180] deg, |u_xy|]: the C angle that turns the tilted tool axis onto (i, j), and sin of the angle between tool axis and C axis (0 at the singularity, where C is free).

    tilt (...): B angle, deg
    ij (..., 2): tool-axis x, y components in the workpiece frame
        [i, j]
    returns (..., 2)
    """
    tilt = as_arg(tilt, 0, 'tilt', 'ik_rotary')
    ij = as_arg(ij, 2, 'ij', 'ik_rotary')
    B = tilt
    i = ij[..., 0]
    j = ij[..., 1]
    _x0 = numpy.sin((1/180)*numpy.pi*B)
    _out = out_array((tilt.shape, ij.shape[:-1],), (2,))
    _out[..., 0] = 180*numpy.arctan2(_x0*j, _x0*i)/numpy.pi
    _out[..., 1] = abs(_x0)
    return _out


def ik_linear(rot, tip, tool_length):
    """Linear axes (mm) that put the tool tip at `tip` for the given rotary angles and tool.

    rot (..., 2): [B, C] in deg
        [B, C]
    tip (..., 3): tool tip in the workpiece frame, mm
        [x, y, z]
    tool_length (...): tool length below the error reference point, mm
    returns (..., 3)
    """
    rot = as_arg(rot, 2, 'rot', 'ik_linear')
    tip = as_arg(tip, 3, 'tip', 'ik_linear')
    tool_length = as_arg(tool_length, 0, 'tool_length', 'ik_linear')
    B = rot[..., 0]
    C = rot[..., 1]
    x = tip[..., 0]
    y = tip[..., 1]
    z = tip[..., 2]
    tool_length = tool_length
    _x0 = (1/180)*numpy.pi
    _x1 = B*_x0
    _x2 = numpy.sin(_x1)
    _x3 = C*_x0
    _x4 = numpy.cos(_x3)
    _x5 = numpy.sin(_x3)
    _x6 = numpy.cos(_x1)
    _out = out_array((rot.shape[:-1], tip.shape[:-1], tool_length.shape,), (3,))
    _out[..., 0] = _x2*tool_length + 150*_x2 + _x4*x + _x5*y
    _out[..., 1] = _x4*y - _x5*x
    _out[..., 2] = _x6*tool_length + 150*_x6 - tool_length + z - 150
    return _out
