/* -----------------------------------------------------------------------------
 * GENERATED FILE - DO NOT EDIT.
 * Generator: python -m derive (dmu50); source: derive/kins_c.py, derive/kinematics.py
 * Target: C99 (a LinuxCNC kinematics component; mtcal export --format linuxcnc-kins).
 * Inputs (machine spec, SymPy version, hash of derive/) are in manifest.json.
 * ---------------------------------------------------------------------------*/
/* Deckel Maho DMU 50 eVolution (XYZ on the spindle side, B tilted 45 deg and C on the table): kinematics generated from derive/machines/dmu50.toml. */
#define MTK_N_AXES 5
#define MTK_N_ERRORS 41
#define MTK_TOOL_AXIS 2 /* Z */
#define MTK_TOLERANCE_MM 1e-10
#define MTK_TILT 3 /* B */
#define MTK_ROTARY 4 /* C */
#define MTK_TILT_LO 0.0
#define MTK_TILT_HI 180.0
#define MTK_PI 3.141592653589793
static const char mtk_axes[] = "XYZBC";
static const int mtk_linear[3] = {0, 1, 2};

/* Nominal pose [x, y, z (mm), i, j, k] of the tool in the workpiece frame.
 * out: 6 x 1, row-major */
static void mtk_forward(const double *axes, double tool_length, double *out)
{
    const double X = axes[0];
    const double Y = axes[1];
    const double Z = axes[2];
    const double B = axes[3];
    const double C = axes[4];
    (void)tool_length;
    const double _x0 = (1.0/180.0)*MTK_PI;
    const double _x1 = C*_x0;
    const double _x2 = sin(_x1);
    const double _x3 = (38749.0/500.0)*_x2;
    const double _x4 = (1.0/2.0)*Y;
    const double _x5 = _x2*_x4;
    const double _x6 = (1.0/2.0)*Z;
    const double _x7 = _x2*_x6;
    const double _x8 = B*_x0;
    const double _x9 = cos(_x8);
    const double _x10 = cos(_x1);
    const double _x11 = X*_x9;
    const double _x12 = (38749.0/500.0)*_x10;
    const double _x13 = sqrt(2);
    const double _x14 = sin(_x8);
    const double _x15 = _x13*_x14;
    const double _x16 = (1.0/2.0)*_x15;
    const double _x17 = X*_x16;
    const double _x18 = _x10*_x4;
    const double _x19 = _x10*_x6;
    const double _x20 = (1.0/2.0)*_x9 - 1.0/2.0;
    out[0] = _x10*_x11 - _x12*_x15 + _x15*_x18 + _x15*_x19 + _x17*_x2 + _x3*_x9 - _x3 - _x5*_x9 - _x5 - _x7*_x9 + _x7;
    out[1] = -_x10*_x17 + _x11*_x2 - _x12*_x9 + _x12 - _x15*_x3 + _x15*_x5 + _x15*_x7 + _x18*_x9 + _x18 + _x19*_x9 - _x19;
    out[2] = -_x17 + _x4*_x9 - _x4 + _x6*_x9 + _x6 - 38749.0/500.0*_x9 + 38749.0/500.0;
    out[3] = (1.0/2.0)*_x10*_x13*_x14 - _x2*_x20;
    out[4] = _x10*_x20 + _x16*_x2;
    out[5] = (1.0/2.0)*_x9 + 1.0/2.0;
}

/* d pose / d axes of the nominal pose; columns per mm (linear) and per degree (rotary).
 * out: 6 x 5, row-major */
static void mtk_jacobian_axes(const double *axes, double tool_length, double *out)
{
    const double X = axes[0];
    const double Y = axes[1];
    const double Z = axes[2];
    const double B = axes[3];
    const double C = axes[4];
    (void)tool_length;
    const double _x0 = (1.0/180.0)*MTK_PI;
    const double _x1 = B*_x0;
    const double _x2 = cos(_x1);
    const double _x3 = C*_x0;
    const double _x4 = cos(_x3);
    const double _x5 = _x2*_x4;
    const double _x6 = sin(_x3);
    const double _x7 = (1.0/2.0)*_x6;
    const double _x8 = sqrt(2);
    const double _x9 = sin(_x1);
    const double _x10 = _x8*_x9;
    const double _x11 = _x10*_x7;
    const double _x12 = _x2*_x7;
    const double _x13 = (1.0/2.0)*_x4;
    const double _x14 = _x10*_x13;
    const double _x15 = (38749.0/90000.0)*MTK_PI;
    const double _x16 = _x15*_x6;
    const double _x17 = X*_x0;
    const double _x18 = _x17*_x9;
    const double _x19 = (1.0/360.0)*MTK_PI;
    const double _x20 = _x19*_x9;
    const double _x21 = Y*_x20;
    const double _x22 = Z*_x20;
    const double _x23 = _x2*_x6;
    const double _x24 = _x19*_x23;
    const double _x25 = X*_x8;
    const double _x26 = _x19*_x5;
    const double _x27 = Y*_x26;
    const double _x28 = Z*_x26;
    const double _x29 = _x15*_x4;
    const double _x30 = _x19*_x4;
    const double _x31 = Y*_x30;
    const double _x32 = _x19*_x6;
    const double _x33 = Y*_x32;
    const double _x34 = Z*_x32;
    const double _x35 = _x11 + (1.0/2.0)*_x5;
    const double _x36 = _x15*_x23;
    const double _x37 = _x10*_x32;
    const double _x38 = (1.0/2.0)*_x2;
    const double _x39 = _x2 - 1;
    out[0] = _x11 + _x5;
    out[1] = -_x12 + _x14 - _x7;
    out[2] = -_x12 + _x14 + _x7;
    out[3] = -_x15*_x5*_x8 - _x16*_x9 - _x18*_x4 + _x21*_x6 + _x22*_x6 + _x24*_x25 + _x27*_x8 + _x28*_x8;
    out[4] = (1.0/360.0)*MTK_PI*X*_x4*_x8*_x9 + (1.0/360.0)*MTK_PI*Z*_x4 - _x10*_x33 - _x10*_x34 - _x17*_x23 + (38749.0/90000.0)*MTK_PI*_x2*_x4 - _x27 - _x28 - _x29 - _x31 + (38749.0/90000.0)*MTK_PI*_x6*_x8*_x9;
    out[5] = -_x14 + _x2*_x6;
    out[6] = _x13 + _x35;
    out[7] = -_x13 + _x35;
    out[8] = (1.0/360.0)*MTK_PI*Y*_x2*_x6*_x8 + (1.0/360.0)*MTK_PI*Z*_x2*_x6*_x8 - _x18*_x6 - _x21*_x4 - _x22*_x4 - _x25*_x26 - _x36*_x8 + (38749.0/90000.0)*MTK_PI*_x4*_x9;
    out[9] = X*_x37 - Y*_x24 + Z*_x10*_x30 - Z*_x24 - _x10*_x29 + _x10*_x31 - _x16 + _x17*_x5 - _x33 + _x34 + _x36;
    out[10] = -1.0/2.0*_x10;
    out[11] = _x38 - 1.0/2.0;
    out[12] = _x38 + 1.0/2.0;
    out[13] = -_x19*_x2*_x25 - _x21 - _x22 + (38749.0/90000.0)*MTK_PI*_x9;
    out[14] = 0;
    out[15] = 0;
    out[16] = 0;
    out[17] = 0;
    out[18] = _x20*_x6 + _x26*_x8;
    out[19] = -_x30*_x39 - _x37;
    out[20] = 0;
    out[21] = 0;
    out[22] = 0;
    out[23] = (1.0/360.0)*MTK_PI*_x2*_x6*_x8 - _x20*_x4;
    out[24] = -_x32*_x39 + (1.0/360.0)*MTK_PI*_x4*_x8*_x9;
    out[25] = 0;
    out[26] = 0;
    out[27] = 0;
    out[28] = -_x20;
    out[29] = 0;
}

/* Exact error-inclusive pose [x, y, z, i, j, k] (errors in mm, rad; see derive/kinematics.py).
 * out: 6 x 1, row-major */
static void mtk_forward_errors(const double *axes, const double *errors, double tool_length, double *out)
{
    const double X = axes[0];
    const double Y = axes[1];
    const double Z = axes[2];
    const double B = axes[3];
    const double C = axes[4];
    const double E_XX = errors[0];
    const double E_YX = errors[1];
    const double E_ZX = errors[2];
    const double E_AX = errors[3];
    const double E_BX = errors[4];
    const double E_CX = errors[5];
    const double E_XY = errors[6];
    const double E_YY = errors[7];
    const double E_ZY = errors[8];
    const double E_AY = errors[9];
    const double E_BY = errors[10];
    const double E_CY = errors[11];
    const double E_XZ = errors[12];
    const double E_YZ = errors[13];
    const double E_ZZ = errors[14];
    const double E_AZ = errors[15];
    const double E_BZ = errors[16];
    const double E_CZ = errors[17];
    const double E_C0Y = errors[18];
    const double E_B0Z = errors[19];
    const double E_A0Z = errors[20];
    const double E_XB = errors[21];
    const double E_YB = errors[22];
    const double E_ZB = errors[23];
    const double E_AB = errors[24];
    const double E_BB = errors[25];
    const double E_CB = errors[26];
    const double E_XC = errors[27];
    const double E_YC = errors[28];
    const double E_ZC = errors[29];
    const double E_AC = errors[30];
    const double E_BC = errors[31];
    const double E_CC = errors[32];
    const double E_X0B = errors[33];
    const double E_Y0B = errors[34];
    const double E_A0B = errors[35];
    const double E_B0B = errors[36];
    const double E_X0C = errors[37];
    const double E_Y0C = errors[38];
    const double E_A0C = errors[39];
    const double E_B0C = errors[40];
    const double _x0 = E_XY - Y*sin(E_C0Y);
    const double _x1 = cos(E_CX);
    const double _x2 = cos(E_BX);
    const double _x3 = _x1*_x2;
    const double _x4 = sin(E_AX);
    const double _x5 = sin(E_CX);
    const double _x6 = _x4*_x5;
    const double _x7 = sin(E_BX);
    const double _x8 = cos(E_AX);
    const double _x9 = _x1*_x8;
    const double _x10 = _x6 + _x7*_x9;
    const double _x11 = E_YY + Y*cos(E_C0Y);
    const double _x12 = _x1*_x4;
    const double _x13 = _x12*_x7 - _x5*_x8;
    const double _x14 = Z*cos(E_A0Z);
    const double _x15 = E_XZ + _x14*sin(E_B0Z);
    const double _x16 = cos(E_CY);
    const double _x17 = cos(E_BY);
    const double _x18 = _x16*_x17;
    const double _x19 = sin(E_BY);
    const double _x20 = sin(E_CY);
    const double _x21 = _x17*_x20;
    const double _x22 = -_x10*_x19 + _x13*_x21 + _x18*_x3;
    const double _x23 = E_YZ - Z*sin(E_A0Z);
    const double _x24 = sin(E_AY);
    const double _x25 = _x10*_x17;
    const double _x26 = cos(E_AY);
    const double _x27 = _x16*_x24;
    const double _x28 = _x19*_x27 - _x20*_x26;
    const double _x29 = _x16*_x26;
    const double _x30 = _x20*_x24;
    const double _x31 = _x19*_x30 + _x29;
    const double _x32 = _x13*_x31 + _x24*_x25 + _x28*_x3;
    const double _x33 = E_ZZ + _x14*cos(E_B0Z);
    const double _x34 = _x19*_x29 + _x30;
    const double _x35 = _x19*_x20*_x26 - _x27;
    const double _x36 = _x13*_x35 + _x25*_x26 + _x3*_x34;
    const double _x37 = sin(E_AZ);
    const double _x38 = sin(E_CZ);
    const double _x39 = cos(E_CZ);
    const double _x40 = cos(E_AZ);
    const double _x41 = sin(E_BZ);
    const double _x42 = _x37*_x38 + _x39*_x40*_x41;
    const double _x43 = _x40*cos(E_BZ);
    const double _x44 = -_x37*_x39 + _x38*_x40*_x41;
    const double _x45 = _x22*_x42 + _x32*_x44 + _x36*_x43;
    const double _x46 = E_XX + E_ZY*_x10 + X + _x0*_x3 + _x11*_x13 + _x15*_x22 + _x23*_x32 + _x33*_x36 - _x45*tool_length;
    const double _x47 = sin(E_B0B);
    const double _x48 = cos(E_A0B);
    const double _x49 = cos(E_CB);
    const double _x50 = cos(E_BB);
    const double _x51 = _x47*_x50;
    const double _x52 = _x49*_x51;
    const double _x53 = sin(E_A0B);
    const double _x54 = sin(E_CB);
    const double _x55 = cos(E_AB);
    const double _x56 = sin(E_BB);
    const double _x57 = sin(E_AB);
    const double _x58 = _x49*_x57;
    const double _x59 = -_x54*_x55 + _x56*_x58;
    const double _x60 = _x54*_x57;
    const double _x61 = _x49*_x55;
    const double _x62 = _x56*_x61 + _x60;
    const double _x63 = cos(E_B0B);
    const double _x64 = _x62*_x63;
    const double _x65 = _x48*_x52 + _x48*_x64 - _x53*_x59;
    const double _x66 = _x48*_x65;
    const double _x67 = (1.0/180.0)*MTK_PI;
    const double _x68 = B*_x67;
    const double _x69 = cos(_x68);
    const double _x70 = -_x47*_x62 + _x49*_x50*_x63;
    const double _x71 = sin(_x68);
    const double _x72 = _x48*_x59 + _x52*_x53 + _x53*_x64;
    const double _x73 = _x69*_x70 + _x71*_x72;
    const double _x74 = _x63*_x73;
    const double _x75 = _x69*_x72 - _x70*_x71;
    const double _x76 = _x53*_x75;
    const double _x77 = _x47*_x66 + _x47*_x76 + _x74;
    const double _x78 = sin(E_B0C);
    const double _x79 = cos(E_A0C);
    const double _x80 = _x78*_x79;
    const double _x81 = cos(E_CC);
    const double _x82 = cos(E_BC);
    const double _x83 = _x81*_x82;
    const double _x84 = sin(E_A0C);
    const double _x85 = sin(E_CC);
    const double _x86 = cos(E_AC);
    const double _x87 = sin(E_BC);
    const double _x88 = sin(E_AC);
    const double _x89 = _x81*_x88;
    const double _x90 = -_x85*_x86 + _x87*_x89;
    const double _x91 = cos(E_B0C);
    const double _x92 = _x85*_x88;
    const double _x93 = _x81*_x86;
    const double _x94 = _x87*_x93 + _x92;
    const double _x95 = _x91*_x94;
    const double _x96 = _x79*_x95 + _x80*_x83 - _x84*_x90;
    const double _x97 = C*_x67;
    const double _x98 = cos(_x97);
    const double _x99 = -_x78*_x94 + _x81*_x82*_x91;
    const double _x100 = sin(_x97);
    const double _x101 = _x78*_x84;
    const double _x102 = _x101*_x83 + _x79*_x90 + _x84*_x95;
    const double _x103 = -_x100*_x102 + _x98*_x99;
    const double _x104 = _x103*_x91;
    const double _x105 = _x100*_x99 + _x102*_x98;
    const double _x106 = _x101*_x105 + _x104 + _x80*_x96;
    const double _x107 = _x82*_x88;
    const double _x108 = -_x107*_x84 + _x79*_x82*_x86*_x91 - _x80*_x87;
    const double _x109 = _x82*_x86;
    const double _x110 = -_x109*_x78 - _x87*_x91;
    const double _x111 = _x84*_x91;
    const double _x112 = -_x101*_x87 + _x107*_x79 + _x109*_x111;
    const double _x113 = -_x100*_x112 + _x110*_x98;
    const double _x114 = _x113*_x91;
    const double _x115 = _x100*_x110 + _x112*_x98;
    const double _x116 = _x101*_x115 + _x108*_x80 + _x114;
    const double _x117 = _x48*_x75 - _x53*_x65;
    const double _x118 = sqrt(2);
    const double _x119 = (1.0/2.0)*_x118;
    const double _x120 = _x117*_x119;
    const double _x121 = -_x47*_x73 + _x63*_x66 + _x63*_x76;
    const double _x122 = _x119*_x121;
    const double _x123 = _x120 + _x122;
    const double _x124 = _x82*_x85;
    const double _x125 = _x87*_x92 + _x93;
    const double _x126 = _x85*_x86*_x87 - _x89;
    const double _x127 = _x126*_x91;
    const double _x128 = _x124*_x80 - _x125*_x84 + _x127*_x79;
    const double _x129 = -_x126*_x78 + _x82*_x85*_x91;
    const double _x130 = _x101*_x124 + _x125*_x79 + _x127*_x84;
    const double _x131 = -_x100*_x130 + _x129*_x98;
    const double _x132 = _x131*_x91;
    const double _x133 = _x100*_x129 + _x130*_x98;
    const double _x134 = _x101*_x133 + _x128*_x80 + _x132;
    const double _x135 = _x120 - _x122;
    const double _x136 = _x106*_x77 + _x116*_x123 + _x134*_x135;
    const double _x137 = _x2*_x8;
    const double _x138 = _x2*_x4;
    const double _x139 = -_x137*_x19 + _x17*_x2*_x20*_x4 - _x18*_x7;
    const double _x140 = _x137*_x17;
    const double _x141 = _x138*_x31 + _x140*_x24 - _x28*_x7;
    const double _x142 = _x138*_x35 + _x140*_x26 - _x34*_x7;
    const double _x143 = _x139*_x42 + _x141*_x44 + _x142*_x43;
    const double _x144 = E_ZX + E_ZY*_x137 - _x0*_x7 + _x11*_x138 + _x139*_x15 + _x141*_x23 + _x142*_x33 - _x143*tool_length + tool_length;
    const double _x145 = _x50*_x57;
    const double _x146 = _x47*_x56;
    const double _x147 = -_x145*_x53 - _x146*_x48 + _x48*_x50*_x55*_x63;
    const double _x148 = _x47*_x48;
    const double _x149 = -_x51*_x55 - _x56*_x63;
    const double _x150 = _x145*_x48 - _x146*_x53 + _x50*_x53*_x55*_x63;
    const double _x151 = _x149*_x69 + _x150*_x71;
    const double _x152 = _x151*_x63;
    const double _x153 = -_x149*_x71 + _x150*_x69;
    const double _x154 = _x47*_x53;
    const double _x155 = _x119*(_x147*_x148 + _x152 + _x153*_x154);
    const double _x156 = _x51*_x54;
    const double _x157 = _x56*_x60 + _x61;
    const double _x158 = _x54*_x55*_x56 - _x58;
    const double _x159 = _x158*_x63;
    const double _x160 = _x156*_x48 - _x157*_x53 + _x159*_x48;
    const double _x161 = -_x158*_x47 + _x50*_x54*_x63;
    const double _x162 = _x156*_x53 + _x157*_x48 + _x159*_x53;
    const double _x163 = _x161*_x69 + _x162*_x71;
    const double _x164 = _x163*_x63;
    const double _x165 = -_x161*_x71 + _x162*_x69;
    const double _x166 = _x119*(_x148*_x160 + _x154*_x165 + _x164);
    const double _x167 = _x155 + _x166;
    const double _x168 = _x119*(-_x147*_x53 + _x153*_x48);
    const double _x169 = _x119*(-_x160*_x53 + _x165*_x48);
    const double _x170 = _x168 + _x169;
    const double _x171 = _x119*_x170;
    const double _x172 = _x48*_x63;
    const double _x173 = _x53*_x63;
    const double _x174 = _x119*(_x147*_x172 - _x151*_x47 + _x153*_x173);
    const double _x175 = _x119*(_x160*_x172 - _x163*_x47 + _x165*_x173);
    const double _x176 = _x174 + _x175;
    const double _x177 = _x119*_x176;
    const double _x178 = _x171 + _x177;
    const double _x179 = _x171 - _x177;
    const double _x180 = _x106*_x167 + _x116*_x178 + _x134*_x179;
    const double _x181 = _x2*_x5;
    const double _x182 = -_x12 + _x5*_x7*_x8;
    const double _x183 = _x6*_x7 + _x9;
    const double _x184 = _x18*_x181 - _x182*_x19 + _x183*_x21;
    const double _x185 = _x17*_x182;
    const double _x186 = _x181*_x28 + _x183*_x31 + _x185*_x24;
    const double _x187 = _x181*_x34 + _x183*_x35 + _x185*_x26;
    const double _x188 = _x184*_x42 + _x186*_x44 + _x187*_x43;
    const double _x189 = E_YX + E_ZY*_x182 + _x0*_x181 + _x11*_x183 + _x15*_x184 + _x186*_x23 + _x187*_x33 - _x188*tool_length;
    const double _x190 = -_x155 + _x166;
    const double _x191 = -_x168 + _x169;
    const double _x192 = _x119*_x191;
    const double _x193 = -_x174 + _x175;
    const double _x194 = _x119*_x193;
    const double _x195 = _x192 + _x194;
    const double _x196 = _x192 - _x194;
    const double _x197 = _x106*_x190 + _x116*_x195 + _x134*_x196;
    const double _x198 = E_X0B*_x50;
    const double _x199 = -E_X0B*_x148 + E_Y0B*_x53;
    const double _x200 = -E_X0B*_x154 - E_Y0B*_x48;
    const double _x201 = (38749.0/500.0)*_x118;
    const double _x202 = E_X0C*_x82;
    const double _x203 = -E_X0C*_x80 + E_Y0C*_x84;
    const double _x204 = -E_X0C*_x101 - E_Y0C*_x79;
    const double _x205 = -E_X0C*_x104 + E_XC + E_Y0C*_x90 + _x105*_x204 + _x202*_x81 + _x203*_x96;
    const double _x206 = -E_X0C*_x114 - E_X0C*_x87 + E_Y0C*_x107 + E_ZC + _x108*_x203 + _x115*_x204;
    const double _x207 = -E_X0C*_x132 + E_Y0C*_x125 + E_YC + _x128*_x203 + _x133*_x204 + _x202*_x85;
    const double _x208 = -E_X0B*_x74 + E_XB + E_Y0B*_x59 - _x117*_x201 - _x121*_x201 + _x123*_x206 + _x135*_x207 + _x198*_x49 + _x199*_x65 + _x200*_x75 + _x205*_x77;
    const double _x209 = _x119*(-E_X0B*_x152 - E_X0B*_x56 + E_Y0B*_x145 + E_ZB + _x147*_x199 + _x153*_x200);
    const double _x210 = _x119*(-E_X0B*_x164 + E_Y0B*_x157 + E_YB + _x160*_x199 + _x165*_x200 + _x198*_x54);
    const double _x211 = _x190*_x205 - _x191*_x201 - _x193*_x201 + _x195*_x206 + _x196*_x207 - _x209 + _x210;
    const double _x212 = _x167*_x205 - _x170*_x201 - _x176*_x201 + _x178*_x206 + _x179*_x207 + _x209 + _x210 + 38749.0/250.0;
    const double _x213 = _x105*_x79 - _x84*_x96;
    const double _x214 = -_x108*_x84 + _x115*_x79;
    const double _x215 = -_x128*_x84 + _x133*_x79;
    const double _x216 = _x123*_x214 + _x135*_x215 + _x213*_x77;
    const double _x217 = _x167*_x213 + _x178*_x214 + _x179*_x215;
    const double _x218 = _x190*_x213 + _x195*_x214 + _x196*_x215;
    const double _x219 = _x79*_x91;
    const double _x220 = -_x103*_x78 + _x105*_x111 + _x219*_x96;
    const double _x221 = _x108*_x219 + _x111*_x115 - _x113*_x78;
    const double _x222 = _x111*_x133 + _x128*_x219 - _x131*_x78;
    const double _x223 = _x123*_x221 + _x135*_x222 + _x220*_x77;
    const double _x224 = _x167*_x220 + _x178*_x221 + _x179*_x222;
    const double _x225 = _x190*_x220 + _x195*_x221 + _x196*_x222;
    out[0] = -_x136*_x208 + _x136*_x46 + _x144*_x180 - _x180*_x212 + _x189*_x197 - _x197*_x211;
    out[1] = _x144*_x217 + _x189*_x218 - _x208*_x216 - _x211*_x218 - _x212*_x217 + _x216*_x46;
    out[2] = _x144*_x224 + _x189*_x225 - _x208*_x223 - _x211*_x225 - _x212*_x224 + _x223*_x46;
    out[3] = _x136*_x45 + _x143*_x180 + _x188*_x197;
    out[4] = _x143*_x217 + _x188*_x218 + _x216*_x45;
    out[5] = _x143*_x224 + _x188*_x225 + _x223*_x45;
}

/* Column 0: exact error-inclusive pose; columns 1..: its partial derivatives with respect to the axes at fixed error values (per mm, per degree).
 * out: 6 x 6, row-major */
static void mtk_forward_errors_with_jacobian(const double *axes, const double *errors, double tool_length, double *out)
{
    const double X = axes[0];
    const double Y = axes[1];
    const double Z = axes[2];
    const double B = axes[3];
    const double C = axes[4];
    const double E_XX = errors[0];
    const double E_YX = errors[1];
    const double E_ZX = errors[2];
    const double E_AX = errors[3];
    const double E_BX = errors[4];
    const double E_CX = errors[5];
    const double E_XY = errors[6];
    const double E_YY = errors[7];
    const double E_ZY = errors[8];
    const double E_AY = errors[9];
    const double E_BY = errors[10];
    const double E_CY = errors[11];
    const double E_XZ = errors[12];
    const double E_YZ = errors[13];
    const double E_ZZ = errors[14];
    const double E_AZ = errors[15];
    const double E_BZ = errors[16];
    const double E_CZ = errors[17];
    const double E_C0Y = errors[18];
    const double E_B0Z = errors[19];
    const double E_A0Z = errors[20];
    const double E_XB = errors[21];
    const double E_YB = errors[22];
    const double E_ZB = errors[23];
    const double E_AB = errors[24];
    const double E_BB = errors[25];
    const double E_CB = errors[26];
    const double E_XC = errors[27];
    const double E_YC = errors[28];
    const double E_ZC = errors[29];
    const double E_AC = errors[30];
    const double E_BC = errors[31];
    const double E_CC = errors[32];
    const double E_X0B = errors[33];
    const double E_Y0B = errors[34];
    const double E_A0B = errors[35];
    const double E_B0B = errors[36];
    const double E_X0C = errors[37];
    const double E_Y0C = errors[38];
    const double E_A0C = errors[39];
    const double E_B0C = errors[40];
    const double _x0 = sin(E_C0Y);
    const double _x1 = E_XY - Y*_x0;
    const double _x2 = cos(E_CX);
    const double _x3 = cos(E_BX);
    const double _x4 = _x2*_x3;
    const double _x5 = sin(E_AX);
    const double _x6 = sin(E_CX);
    const double _x7 = _x5*_x6;
    const double _x8 = sin(E_BX);
    const double _x9 = cos(E_AX);
    const double _x10 = _x2*_x9;
    const double _x11 = _x10*_x8 + _x7;
    const double _x12 = cos(E_C0Y);
    const double _x13 = E_YY + Y*_x12;
    const double _x14 = _x2*_x5;
    const double _x15 = _x14*_x8 - _x6*_x9;
    const double _x16 = sin(E_B0Z);
    const double _x17 = cos(E_A0Z);
    const double _x18 = Z*_x17;
    const double _x19 = E_XZ + _x16*_x18;
    const double _x20 = cos(E_CY);
    const double _x21 = cos(E_BY);
    const double _x22 = _x20*_x21;
    const double _x23 = sin(E_BY);
    const double _x24 = sin(E_CY);
    const double _x25 = _x21*_x24;
    const double _x26 = -_x11*_x23 + _x15*_x25 + _x22*_x4;
    const double _x27 = sin(E_A0Z);
    const double _x28 = E_YZ - Z*_x27;
    const double _x29 = sin(E_AY);
    const double _x30 = _x11*_x21;
    const double _x31 = cos(E_AY);
    const double _x32 = _x20*_x29;
    const double _x33 = _x23*_x32 - _x24*_x31;
    const double _x34 = _x20*_x31;
    const double _x35 = _x24*_x29;
    const double _x36 = _x23*_x35 + _x34;
    const double _x37 = _x15*_x36 + _x29*_x30 + _x33*_x4;
    const double _x38 = cos(E_B0Z);
    const double _x39 = E_ZZ + _x18*_x38;
    const double _x40 = _x23*_x34 + _x35;
    const double _x41 = _x23*_x24*_x31 - _x32;
    const double _x42 = _x15*_x41 + _x30*_x31 + _x4*_x40;
    const double _x43 = sin(E_AZ);
    const double _x44 = sin(E_CZ);
    const double _x45 = cos(E_CZ);
    const double _x46 = cos(E_AZ);
    const double _x47 = sin(E_BZ);
    const double _x48 = _x43*_x44 + _x45*_x46*_x47;
    const double _x49 = _x46*cos(E_BZ);
    const double _x50 = -_x43*_x45 + _x44*_x46*_x47;
    const double _x51 = _x26*_x48 + _x37*_x50 + _x42*_x49;
    const double _x52 = E_XX + E_ZY*_x11 + X + _x1*_x4 + _x13*_x15 + _x19*_x26 + _x28*_x37 + _x39*_x42 - _x51*tool_length;
    const double _x53 = sin(E_B0B);
    const double _x54 = cos(E_A0B);
    const double _x55 = cos(E_CB);
    const double _x56 = cos(E_BB);
    const double _x57 = _x53*_x56;
    const double _x58 = _x55*_x57;
    const double _x59 = sin(E_A0B);
    const double _x60 = sin(E_CB);
    const double _x61 = cos(E_AB);
    const double _x62 = sin(E_BB);
    const double _x63 = sin(E_AB);
    const double _x64 = _x55*_x63;
    const double _x65 = -_x60*_x61 + _x62*_x64;
    const double _x66 = _x60*_x63;
    const double _x67 = _x55*_x61;
    const double _x68 = _x62*_x67 + _x66;
    const double _x69 = cos(E_B0B);
    const double _x70 = _x68*_x69;
    const double _x71 = _x54*_x58 + _x54*_x70 - _x59*_x65;
    const double _x72 = _x54*_x71;
    const double _x73 = (1.0/180.0)*MTK_PI;
    const double _x74 = B*_x73;
    const double _x75 = cos(_x74);
    const double _x76 = -_x53*_x68 + _x55*_x56*_x69;
    const double _x77 = _x75*_x76;
    const double _x78 = sin(_x74);
    const double _x79 = _x54*_x65 + _x58*_x59 + _x59*_x70;
    const double _x80 = _x78*_x79;
    const double _x81 = _x77 + _x80;
    const double _x82 = _x69*_x81;
    const double _x83 = _x76*_x78;
    const double _x84 = _x75*_x79 - _x83;
    const double _x85 = _x59*_x84;
    const double _x86 = _x53*_x72 + _x53*_x85 + _x82;
    const double _x87 = sin(E_B0C);
    const double _x88 = cos(E_A0C);
    const double _x89 = _x87*_x88;
    const double _x90 = cos(E_CC);
    const double _x91 = cos(E_BC);
    const double _x92 = _x90*_x91;
    const double _x93 = sin(E_A0C);
    const double _x94 = sin(E_CC);
    const double _x95 = cos(E_AC);
    const double _x96 = sin(E_BC);
    const double _x97 = sin(E_AC);
    const double _x98 = _x90*_x97;
    const double _x99 = -_x94*_x95 + _x96*_x98;
    const double _x100 = cos(E_B0C);
    const double _x101 = _x94*_x97;
    const double _x102 = _x90*_x95;
    const double _x103 = _x101 + _x102*_x96;
    const double _x104 = _x100*_x103;
    const double _x105 = _x104*_x88 + _x89*_x92 - _x93*_x99;
    const double _x106 = C*_x73;
    const double _x107 = cos(_x106);
    const double _x108 = _x100*_x90*_x91 - _x103*_x87;
    const double _x109 = _x107*_x108;
    const double _x110 = sin(_x106);
    const double _x111 = _x87*_x93;
    const double _x112 = _x104*_x93 + _x111*_x92 + _x88*_x99;
    const double _x113 = _x110*_x112;
    const double _x114 = _x109 - _x113;
    const double _x115 = _x100*_x114;
    const double _x116 = _x108*_x110;
    const double _x117 = _x107*_x112;
    const double _x118 = _x116 + _x117;
    const double _x119 = _x105*_x89 + _x111*_x118 + _x115;
    const double _x120 = _x91*_x97;
    const double _x121 = _x100*_x88*_x91*_x95 - _x120*_x93 - _x89*_x96;
    const double _x122 = _x91*_x95;
    const double _x123 = -_x100*_x96 - _x122*_x87;
    const double _x124 = _x107*_x123;
    const double _x125 = _x100*_x93;
    const double _x126 = -_x111*_x96 + _x120*_x88 + _x122*_x125;
    const double _x127 = _x110*_x126;
    const double _x128 = _x124 - _x127;
    const double _x129 = _x100*_x128;
    const double _x130 = _x110*_x123;
    const double _x131 = _x107*_x126;
    const double _x132 = _x130 + _x131;
    const double _x133 = _x111*_x132 + _x121*_x89 + _x129;
    const double _x134 = _x54*_x84 - _x59*_x71;
    const double _x135 = sqrt(2);
    const double _x136 = (1.0/2.0)*_x135;
    const double _x137 = _x134*_x136;
    const double _x138 = -_x53*_x81 + _x69*_x72 + _x69*_x85;
    const double _x139 = _x136*_x138;
    const double _x140 = _x137 + _x139;
    const double _x141 = _x91*_x94;
    const double _x142 = _x101*_x96 + _x102;
    const double _x143 = _x94*_x95*_x96 - _x98;
    const double _x144 = _x100*_x143;
    const double _x145 = _x141*_x89 - _x142*_x93 + _x144*_x88;
    const double _x146 = _x100*_x91*_x94 - _x143*_x87;
    const double _x147 = _x107*_x146;
    const double _x148 = _x111*_x141 + _x142*_x88 + _x144*_x93;
    const double _x149 = _x110*_x148;
    const double _x150 = _x147 - _x149;
    const double _x151 = _x100*_x150;
    const double _x152 = _x110*_x146;
    const double _x153 = _x107*_x148;
    const double _x154 = _x152 + _x153;
    const double _x155 = _x111*_x154 + _x145*_x89 + _x151;
    const double _x156 = _x137 - _x139;
    const double _x157 = _x119*_x86 + _x133*_x140 + _x155*_x156;
    const double _x158 = _x3*_x9;
    const double _x159 = _x3*_x5;
    const double _x160 = -_x158*_x23 + _x21*_x24*_x3*_x5 - _x22*_x8;
    const double _x161 = _x158*_x21;
    const double _x162 = _x159*_x36 + _x161*_x29 - _x33*_x8;
    const double _x163 = _x159*_x41 + _x161*_x31 - _x40*_x8;
    const double _x164 = _x160*_x48 + _x162*_x50 + _x163*_x49;
    const double _x165 = E_ZX + E_ZY*_x158 - _x1*_x8 + _x13*_x159 + _x160*_x19 + _x162*_x28 + _x163*_x39 - _x164*tool_length + tool_length;
    const double _x166 = _x56*_x63;
    const double _x167 = _x53*_x62;
    const double _x168 = -_x166*_x59 - _x167*_x54 + _x54*_x56*_x61*_x69;
    const double _x169 = _x53*_x54;
    const double _x170 = -_x57*_x61 - _x62*_x69;
    const double _x171 = _x170*_x75;
    const double _x172 = _x166*_x54 - _x167*_x59 + _x56*_x59*_x61*_x69;
    const double _x173 = _x172*_x78;
    const double _x174 = _x171 + _x173;
    const double _x175 = _x174*_x69;
    const double _x176 = _x170*_x78;
    const double _x177 = _x172*_x75 - _x176;
    const double _x178 = _x53*_x59;
    const double _x179 = _x136*(_x168*_x169 + _x175 + _x177*_x178);
    const double _x180 = _x57*_x60;
    const double _x181 = _x62*_x66 + _x67;
    const double _x182 = _x60*_x61*_x62 - _x64;
    const double _x183 = _x182*_x69;
    const double _x184 = _x180*_x54 - _x181*_x59 + _x183*_x54;
    const double _x185 = -_x182*_x53 + _x56*_x60*_x69;
    const double _x186 = _x185*_x75;
    const double _x187 = _x180*_x59 + _x181*_x54 + _x183*_x59;
    const double _x188 = _x187*_x78;
    const double _x189 = _x186 + _x188;
    const double _x190 = _x189*_x69;
    const double _x191 = _x185*_x78;
    const double _x192 = _x187*_x75 - _x191;
    const double _x193 = _x136*(_x169*_x184 + _x178*_x192 + _x190);
    const double _x194 = _x179 + _x193;
    const double _x195 = _x136*(-_x168*_x59 + _x177*_x54);
    const double _x196 = _x136*(-_x184*_x59 + _x192*_x54);
    const double _x197 = _x195 + _x196;
    const double _x198 = _x136*_x197;
    const double _x199 = _x54*_x69;
    const double _x200 = _x59*_x69;
    const double _x201 = _x136*(_x168*_x199 - _x174*_x53 + _x177*_x200);
    const double _x202 = _x136*(_x184*_x199 - _x189*_x53 + _x192*_x200);
    const double _x203 = _x201 + _x202;
    const double _x204 = _x136*_x203;
    const double _x205 = _x198 + _x204;
    const double _x206 = _x198 - _x204;
    const double _x207 = _x119*_x194 + _x133*_x205 + _x155*_x206;
    const double _x208 = _x3*_x6;
    const double _x209 = -_x14 + _x6*_x8*_x9;
    const double _x210 = _x10 + _x7*_x8;
    const double _x211 = _x208*_x22 - _x209*_x23 + _x210*_x25;
    const double _x212 = _x209*_x21;
    const double _x213 = _x208*_x33 + _x210*_x36 + _x212*_x29;
    const double _x214 = _x208*_x40 + _x210*_x41 + _x212*_x31;
    const double _x215 = _x211*_x48 + _x213*_x50 + _x214*_x49;
    const double _x216 = E_YX + E_ZY*_x209 + _x1*_x208 + _x13*_x210 + _x19*_x211 + _x213*_x28 + _x214*_x39 - _x215*tool_length;
    const double _x217 = -_x179 + _x193;
    const double _x218 = -_x195 + _x196;
    const double _x219 = _x136*_x218;
    const double _x220 = -_x201 + _x202;
    const double _x221 = _x136*_x220;
    const double _x222 = _x219 + _x221;
    const double _x223 = _x219 - _x221;
    const double _x224 = _x119*_x217 + _x133*_x222 + _x155*_x223;
    const double _x225 = -_x157;
    const double _x226 = E_X0B*_x56;
    const double _x227 = -E_X0B*_x169 + E_Y0B*_x59;
    const double _x228 = -E_X0B*_x178 - E_Y0B*_x54;
    const double _x229 = (38749.0/500.0)*_x135;
    const double _x230 = E_X0C*_x91;
    const double _x231 = -E_X0C*_x89 + E_Y0C*_x93;
    const double _x232 = -E_X0C*_x111 - E_Y0C*_x88;
    const double _x233 = -E_X0C*_x115 + E_XC + E_Y0C*_x99 + _x105*_x231 + _x118*_x232 + _x230*_x90;
    const double _x234 = -E_X0C*_x129 - E_X0C*_x96 + E_Y0C*_x120 + E_ZC + _x121*_x231 + _x132*_x232;
    const double _x235 = -E_X0C*_x151 + E_Y0C*_x142 + E_YC + _x145*_x231 + _x154*_x232 + _x230*_x94;
    const double _x236 = -E_X0B*_x82 + E_XB + E_Y0B*_x65 - _x134*_x229 - _x138*_x229 + _x140*_x234 + _x156*_x235 + _x226*_x55 + _x227*_x71 + _x228*_x84 + _x233*_x86;
    const double _x237 = -_x224;
    const double _x238 = _x136*(-E_X0B*_x175 - E_X0B*_x62 + E_Y0B*_x166 + E_ZB + _x168*_x227 + _x177*_x228);
    const double _x239 = _x136*(-E_X0B*_x190 + E_Y0B*_x181 + E_YB + _x184*_x227 + _x192*_x228 + _x226*_x60);
    const double _x240 = _x217*_x233 - _x218*_x229 - _x220*_x229 + _x222*_x234 + _x223*_x235 - _x238 + _x239;
    const double _x241 = -_x207;
    const double _x242 = _x194*_x233 - _x197*_x229 - _x203*_x229 + _x205*_x234 + _x206*_x235 + _x238 + _x239 + 38749.0/250.0;
    const double _x243 = -_x0*_x4 + _x12*_x15;
    const double _x244 = _x0*_x8 + _x12*_x159;
    const double _x245 = -_x0*_x208 + _x12*_x210;
    const double _x246 = _x16*_x17;
    const double _x247 = _x17*_x38;
    const double _x248 = _x246*_x26 + _x247*_x42 - _x27*_x37;
    const double _x249 = _x160*_x246 - _x162*_x27 + _x163*_x247;
    const double _x250 = _x211*_x246 - _x213*_x27 + _x214*_x247;
    const double _x251 = -_x73*_x83 + (1.0/180.0)*MTK_PI*_x75*_x79;
    const double _x252 = _x251*_x69;
    const double _x253 = -_x73*_x77 - _x73*_x80;
    const double _x254 = _x178*_x253 + _x252;
    const double _x255 = _x136*_x54;
    const double _x256 = -_x251*_x53 + _x253*_x59*_x69;
    const double _x257 = _x136*_x256;
    const double _x258 = _x253*_x255 + _x257;
    const double _x259 = (1.0/2.0)*_x135*_x253*_x54 - _x257;
    const double _x260 = _x119*_x254 + _x133*_x258 + _x155*_x259;
    const double _x261 = (1.0/180.0)*MTK_PI*_x172*_x75 - _x176*_x73;
    const double _x262 = _x261*_x69;
    const double _x263 = -_x171*_x73 - _x173*_x73;
    const double _x264 = _x136*(_x178*_x263 + _x262);
    const double _x265 = (1.0/180.0)*MTK_PI*_x187*_x75 - _x191*_x73;
    const double _x266 = _x265*_x69;
    const double _x267 = -_x186*_x73 - _x188*_x73;
    const double _x268 = _x136*(_x178*_x267 + _x266);
    const double _x269 = _x264 + _x268;
    const double _x270 = _x255*_x263;
    const double _x271 = _x255*_x267;
    const double _x272 = _x270 + _x271;
    const double _x273 = _x136*(-_x261*_x53 + _x263*_x59*_x69);
    const double _x274 = _x136*(-_x265*_x53 + _x267*_x59*_x69);
    const double _x275 = _x273 + _x274;
    const double _x276 = _x136*_x275;
    const double _x277 = _x136*_x272 + _x276;
    const double _x278 = (1.0/2.0)*_x135*_x272 - _x276;
    const double _x279 = _x119*_x269 + _x133*_x277 + _x155*_x278;
    const double _x280 = -_x264 + _x268;
    const double _x281 = -_x270 + _x271;
    const double _x282 = -_x273 + _x274;
    const double _x283 = _x136*_x282;
    const double _x284 = _x136*_x281 + _x283;
    const double _x285 = (1.0/2.0)*_x135*_x281 - _x283;
    const double _x286 = _x119*_x280 + _x133*_x284 + _x155*_x285;
    const double _x287 = -E_X0B*_x252 + _x228*_x253 - _x229*_x253*_x54 - _x229*_x256 + _x233*_x254 + _x234*_x258 + _x235*_x259;
    const double _x288 = _x136*(-E_X0B*_x262 + _x228*_x263);
    const double _x289 = _x136*(-E_X0B*_x266 + _x228*_x267);
    const double _x290 = -_x229*_x281 - _x229*_x282 + _x233*_x280 + _x234*_x284 + _x235*_x285 - _x288 + _x289;
    const double _x291 = -_x229*_x272 - _x229*_x275 + _x233*_x269 + _x234*_x277 + _x235*_x278 + _x288 + _x289;
    const double _x292 = -_x116*_x73 - _x117*_x73;
    const double _x293 = _x100*_x292;
    const double _x294 = _x109*_x73 - _x113*_x73;
    const double _x295 = _x111*_x294 + _x293;
    const double _x296 = -_x130*_x73 - _x131*_x73;
    const double _x297 = _x100*_x296;
    const double _x298 = _x124*_x73 - _x127*_x73;
    const double _x299 = _x111*_x298 + _x297;
    const double _x300 = -_x152*_x73 - _x153*_x73;
    const double _x301 = _x100*_x300;
    const double _x302 = _x147*_x73 - _x149*_x73;
    const double _x303 = _x111*_x302 + _x301;
    const double _x304 = _x140*_x299 + _x156*_x303 + _x295*_x86;
    const double _x305 = _x194*_x295 + _x205*_x299 + _x206*_x303;
    const double _x306 = _x217*_x295 + _x222*_x299 + _x223*_x303;
    const double _x307 = -E_X0C*_x293 + _x232*_x294;
    const double _x308 = -E_X0C*_x297 + _x232*_x298;
    const double _x309 = -E_X0C*_x301 + _x232*_x302;
    const double _x310 = _x140*_x308 + _x156*_x309 + _x307*_x86;
    const double _x311 = _x217*_x307 + _x222*_x308 + _x223*_x309;
    const double _x312 = _x194*_x307 + _x205*_x308 + _x206*_x309;
    const double _x313 = -_x105*_x93 + _x118*_x88;
    const double _x314 = -_x121*_x93 + _x132*_x88;
    const double _x315 = -_x145*_x93 + _x154*_x88;
    const double _x316 = _x140*_x314 + _x156*_x315 + _x313*_x86;
    const double _x317 = _x194*_x313 + _x205*_x314 + _x206*_x315;
    const double _x318 = _x217*_x313 + _x222*_x314 + _x223*_x315;
    const double _x319 = -_x316;
    const double _x320 = -_x318;
    const double _x321 = -_x317;
    const double _x322 = _x254*_x313 + _x258*_x314 + _x259*_x315;
    const double _x323 = _x269*_x313 + _x277*_x314 + _x278*_x315;
    const double _x324 = _x280*_x313 + _x284*_x314 + _x285*_x315;
    const double _x325 = _x294*_x88;
    const double _x326 = _x298*_x88;
    const double _x327 = _x302*_x88;
    const double _x328 = _x140*_x326 + _x156*_x327 + _x325*_x86;
    const double _x329 = _x194*_x325 + _x205*_x326 + _x206*_x327;
    const double _x330 = _x217*_x325 + _x222*_x326 + _x223*_x327;
    const double _x331 = _x100*_x88;
    const double _x332 = _x105*_x331 - _x114*_x87 + _x118*_x125;
    const double _x333 = _x121*_x331 + _x125*_x132 - _x128*_x87;
    const double _x334 = _x125*_x154 + _x145*_x331 - _x150*_x87;
    const double _x335 = _x140*_x333 + _x156*_x334 + _x332*_x86;
    const double _x336 = _x194*_x332 + _x205*_x333 + _x206*_x334;
    const double _x337 = _x217*_x332 + _x222*_x333 + _x223*_x334;
    const double _x338 = -_x335;
    const double _x339 = -_x337;
    const double _x340 = -_x336;
    const double _x341 = _x254*_x332 + _x258*_x333 + _x259*_x334;
    const double _x342 = _x269*_x332 + _x277*_x333 + _x278*_x334;
    const double _x343 = _x280*_x332 + _x284*_x333 + _x285*_x334;
    const double _x344 = _x100*_x294*_x93 - _x292*_x87;
    const double _x345 = _x100*_x298*_x93 - _x296*_x87;
    const double _x346 = _x100*_x302*_x93 - _x300*_x87;
    const double _x347 = _x140*_x345 + _x156*_x346 + _x344*_x86;
    const double _x348 = _x194*_x344 + _x205*_x345 + _x206*_x346;
    const double _x349 = _x217*_x344 + _x222*_x345 + _x223*_x346;
    out[0] = _x157*_x52 + _x165*_x207 + _x216*_x224 + _x225*_x236 + _x237*_x240 + _x241*_x242;
    out[1] = _x157;
    out[2] = _x157*_x243 + _x207*_x244 + _x224*_x245;
    out[3] = _x157*_x248 + _x207*_x249 + _x224*_x250;
    out[4] = _x165*_x279 + _x216*_x286 + _x225*_x287 - _x236*_x260 + _x237*_x290 - _x240*_x286 + _x241*_x291 - _x242*_x279 + _x260*_x52;
    out[5] = _x165*_x305 + _x216*_x306 + _x225*_x310 - _x236*_x304 + _x237*_x311 - _x240*_x306 + _x241*_x312 - _x242*_x305 + _x304*_x52;
    out[6] = _x165*_x317 + _x216*_x318 + _x236*_x319 + _x240*_x320 + _x242*_x321 + _x316*_x52;
    out[7] = _x316;
    out[8] = _x243*_x316 + _x244*_x317 + _x245*_x318;
    out[9] = _x248*_x316 + _x249*_x317 + _x250*_x318;
    out[10] = _x165*_x323 + _x216*_x324 - _x236*_x322 - _x240*_x324 - _x242*_x323 + _x287*_x319 + _x290*_x320 + _x291*_x321 + _x322*_x52;
    out[11] = _x165*_x329 + _x216*_x330 - _x236*_x328 - _x240*_x330 - _x242*_x329 + _x310*_x319 + _x311*_x320 + _x312*_x321 + _x328*_x52;
    out[12] = _x165*_x336 + _x216*_x337 + _x236*_x338 + _x240*_x339 + _x242*_x340 + _x335*_x52;
    out[13] = _x335;
    out[14] = _x243*_x335 + _x244*_x336 + _x245*_x337;
    out[15] = _x248*_x335 + _x249*_x336 + _x250*_x337;
    out[16] = _x165*_x342 + _x216*_x343 - _x236*_x341 - _x240*_x343 - _x242*_x342 + _x287*_x338 + _x290*_x339 + _x291*_x340 + _x341*_x52;
    out[17] = _x165*_x348 + _x216*_x349 - _x236*_x347 - _x240*_x349 - _x242*_x348 + _x310*_x338 + _x311*_x339 + _x312*_x340 + _x347*_x52;
    out[18] = _x157*_x51 + _x164*_x207 + _x215*_x224;
    out[19] = 0;
    out[20] = 0;
    out[21] = 0;
    out[22] = _x164*_x279 + _x215*_x286 + _x260*_x51;
    out[23] = _x164*_x305 + _x215*_x306 + _x304*_x51;
    out[24] = _x164*_x317 + _x215*_x318 + _x316*_x51;
    out[25] = 0;
    out[26] = 0;
    out[27] = 0;
    out[28] = _x164*_x323 + _x215*_x324 + _x322*_x51;
    out[29] = _x164*_x329 + _x215*_x330 + _x328*_x51;
    out[30] = _x164*_x336 + _x215*_x337 + _x335*_x51;
    out[31] = 0;
    out[32] = 0;
    out[33] = 0;
    out[34] = _x164*_x342 + _x215*_x343 + _x341*_x51;
    out[35] = _x164*_x348 + _x215*_x349 + _x347*_x51;
}

/* First-order pose deviation jacobian_errors(axes) @ errors.
 * out: 6 x 1, row-major */
static void mtk_deviation_first_order(const double *axes, const double *errors, double tool_length, double *out)
{
    const double X = axes[0];
    const double Y = axes[1];
    const double Z = axes[2];
    const double B = axes[3];
    const double C = axes[4];
    const double E_XX = errors[0];
    const double E_YX = errors[1];
    const double E_ZX = errors[2];
    const double E_AX = errors[3];
    const double E_BX = errors[4];
    const double E_CX = errors[5];
    const double E_XY = errors[6];
    const double E_YY = errors[7];
    const double E_ZY = errors[8];
    const double E_AY = errors[9];
    const double E_BY = errors[10];
    const double E_XZ = errors[12];
    const double E_YZ = errors[13];
    const double E_ZZ = errors[14];
    const double E_AZ = errors[15];
    const double E_BZ = errors[16];
    const double E_C0Y = errors[18];
    const double E_B0Z = errors[19];
    const double E_A0Z = errors[20];
    const double E_XB = errors[21];
    const double E_YB = errors[22];
    const double E_ZB = errors[23];
    const double E_AB = errors[24];
    const double E_BB = errors[25];
    const double E_CB = errors[26];
    const double E_XC = errors[27];
    const double E_YC = errors[28];
    const double E_ZC = errors[29];
    const double E_AC = errors[30];
    const double E_BC = errors[31];
    const double E_CC = errors[32];
    const double E_X0B = errors[33];
    const double E_Y0B = errors[34];
    const double E_A0B = errors[35];
    const double E_B0B = errors[36];
    const double E_X0C = errors[37];
    const double E_Y0C = errors[38];
    const double E_A0C = errors[39];
    const double E_B0C = errors[40];
    const double _x0 = (1.0/180.0)*MTK_PI;
    const double _x1 = B*_x0;
    const double _x2 = cos(_x1);
    const double _x3 = C*_x0;
    const double _x4 = cos(_x3);
    const double _x5 = sqrt(2);
    const double _x6 = sin(_x1);
    const double _x7 = sin(_x3);
    const double _x8 = _x6*_x7;
    const double _x9 = (1.0/2.0)*_x8;
    const double _x10 = _x5*_x9;
    const double _x11 = _x10 + _x2*_x4;
    const double _x12 = -_x11;
    const double _x13 = E_B0Z*Z;
    const double _x14 = E_BZ*_x11;
    const double _x15 = Y*_x11;
    const double _x16 = (1.0/2.0)*_x2;
    const double _x17 = _x16 + 1.0/2.0;
    const double _x18 = _x17*_x7;
    const double _x19 = _x4*_x6;
    const double _x20 = (1.0/2.0)*_x5;
    const double _x21 = _x19*_x20;
    const double _x22 = -_x21;
    const double _x23 = _x18 + _x22;
    const double _x24 = -_x23;
    const double _x25 = _x16 - 1.0/2.0;
    const double _x26 = _x25*_x7;
    const double _x27 = _x22 + _x26;
    const double _x28 = -_x27;
    const double _x29 = Z - tool_length;
    const double _x30 = E_BX*_x11;
    const double _x31 = E_BY*_x11;
    const double _x32 = E_AZ*tool_length;
    const double _x33 = Z*_x24;
    const double _x34 = -_x29;
    const double _x35 = _x24*_x34;
    const double _x36 = _x20*_x27;
    const double _x37 = _x20*_x23;
    const double _x38 = pow(_x6, 2);
    const double _x39 = (38749.0/500.0)*_x38;
    const double _x40 = _x39*_x7;
    const double _x41 = X*_x10;
    const double _x42 = (38749.0/500.0)*_x2;
    const double _x43 = 38749.0/500.0 - _x42;
    const double _x44 = -Y*_x26 - Z*_x18 + _x18*_x43 + _x26*_x43 - _x40 + _x41;
    const double _x45 = _x17*_x4;
    const double _x46 = _x25*_x4;
    const double _x47 = X*_x20;
    const double _x48 = _x19*_x47 - _x39*_x4;
    const double _x49 = -Y*_x46 - Z*_x45 + _x43*_x45 + _x43*_x46 + _x48;
    const double _x50 = _x36*_x6 + _x37*_x6;
    const double _x51 = _x2 - 1;
    const double _x52 = -_x51;
    const double _x53 = _x12*_x6;
    const double _x54 = -_x20*_x53;
    const double _x55 = _x4 - 1;
    const double _x56 = -_x55;
    const double _x57 = _x47*_x6;
    const double _x58 = _x25*_x56;
    const double _x59 = _x17*_x56;
    const double _x60 = -_x10;
    const double _x61 = _x2*_x56 + _x60;
    const double _x62 = _x20*_x6;
    const double _x63 = _x56*_x62;
    const double _x64 = _x26 + _x63;
    const double _x65 = _x18 + _x63;
    const double _x66 = _x2*_x7;
    const double _x67 = -_x63 - _x66;
    const double _x68 = _x58 + _x60;
    const double _x69 = _x59 + _x60;
    const double _x70 = -_x66;
    const double _x71 = _x21 + _x70;
    const double _x72 = -_x71;
    const double _x73 = _x10 + _x45;
    const double _x74 = _x10 + _x46;
    const double _x75 = _x6*_x71;
    const double _x76 = (38749.0/500.0)*_x5;
    const double _x77 = _x75*_x76;
    const double _x78 = -_x73;
    const double _x79 = -_x74;
    const double _x80 = _x43*_x78 + _x43*_x79;
    const double _x81 = _x52*_x7;
    const double _x82 = _x21 + _x81;
    const double _x83 = (38749.0/250.0)*_x2;
    const double _x84 = 38749.0/250.0 - _x83;
    const double _x85 = -_x25;
    const double _x86 = _x21 + _x7*_x85;
    const double _x87 = _x42 + 38749.0/500.0;
    const double _x88 = _x4*_x52;
    const double _x89 = _x20*_x88;
    const double _x90 = (38749.0/500.0)*_x6;
    const double _x91 = -_x8 + _x89;
    const double _x92 = (38749.0/250.0)*_x6;
    const double _x93 = _x16*_x5;
    const double _x94 = _x4*_x93;
    const double _x95 = _x9 + _x94;
    const double _x96 = -_x95;
    const double _x97 = _x43*_x96;
    const double _x98 = _x27*_x90;
    const double _x99 = Y*_x95 + _x23*_x90;
    const double _x100 = -1.0/2.0*_x2*_x5*_x7;
    const double _x101 = _x100 + _x19;
    const double _x102 = _x6*_x76;
    const double _x103 = _x42*_x5;
    const double _x104 = E_BZ*_x72;
    const double _x105 = Y*_x72;
    const double _x106 = E_BX*_x72;
    const double _x107 = E_BY*_x72;
    const double _x108 = Z*_x73;
    const double _x109 = _x34*_x73;
    const double _x110 = _x20*_x79;
    const double _x111 = _x20*_x78;
    const double _x112 = _x110*_x6 + _x111*_x6;
    const double _x113 = -_x20*_x75;
    const double _x114 = _x25*_x55;
    const double _x115 = _x17*_x55;
    const double _x116 = _x60 + _x88;
    const double _x117 = _x4*_x85 + _x60;
    const double _x118 = _x20*_x81;
    const double _x119 = (38749.0/500.0)*_x19;
    const double _x120 = _x118 + _x19;
    const double _x121 = _x100 + (1.0/2.0)*_x19;
    const double _x122 = _x121*_x43;
    const double _x123 = -_x121;
    const double _x124 = _x79*_x90;
    const double _x125 = Y*_x123 + _x78*_x90;
    const double _x126 = _x8 + _x94;
    const double _x127 = E_BZ*_x62;
    const double _x128 = Y*_x6;
    const double _x129 = _x128*_x20;
    const double _x130 = Z*_x25;
    const double _x131 = _x25*_x34;
    const double _x132 = E_BX*_x62;
    const double _x133 = E_BY*_x62;
    const double _x134 = _x20*_x85;
    const double _x135 = -_x17;
    const double _x136 = _x135*_x20;
    const double _x137 = (1.0/2.0)*_x38;
    const double _x138 = -_x137;
    const double _x139 = _x134*_x6 + _x136*_x6;
    const double _x140 = (1.0/2.0)*_x6;
    const double _x141 = Z*_x140;
    const double _x142 = _x135*_x90;
    const double _x143 = -1.0/2.0*_x128 + _x85*_x90;
    const double _x144 = _x43*_x6;
    const double _x145 = Y*_x135 + _x17*_x43;
    const double _x146 = _x55*_x62 + _x70;
    const double _x147 = _x10 + _x115;
    const double _x148 = _x10 + _x114;
    out[0] = E_A0B*(-Y*_x82 + Z*_x21 - _x21*_x43 + _x27*_x84 + _x40 - _x41 + _x43*_x82 + _x53*_x76) + E_A0C*_x44 - E_A0Z*_x33 + E_AB*(-Y*_x86 + _x23*_x43 + _x23*_x87 + _x27*_x43 + _x33 + _x43*_x86) + E_AC*_x44 + E_AX*(Y*_x28 + _x35) + E_AY*_x35 + E_B0B*(-Y*_x89 + Z*_x91 - _x12*_x52*_x76 + _x23*_x92 + _x43*_x89 - _x43*_x91 + _x47*_x81 - _x81*_x90) + E_B0C*(Y*_x25*_x56 + Z*_x17*_x56 + (38749.0/500.0)*_x38*_x56 - _x43*_x58 - _x43*_x59 - _x56*_x57) + E_BB*(Z*_x96 - _x12*_x76 + _x43*_x95 + _x47*_x7 - 38749.0/500.0*_x8 + _x97 - _x98 + _x99) + E_BC*_x49 - E_C0Y*_x15 + E_CB*(-X*_x101 + Z*_x95 + _x101*_x102 + _x103*_x12 + 2*_x97 + _x98 + _x99) + E_CC*(X*_x72 + Y*_x73 + Z*_x74 + _x77 + _x80) - E_CX*_x15 + E_X0B*(_x12*_x52 - _x50) + E_X0C*(_x12*_x61 + _x23*_x65 + _x27*_x64) + E_XB*_x12 + E_XC*(_x12*_x2 + _x50) + E_XX*_x11 + E_XY*_x11 + E_XZ*_x11 + E_Y0B*(_x36*_x52 + _x37*_x52 + _x53) + E_Y0C*(_x12*_x67 + _x23*_x69 + _x27*_x68) + E_YB*(_x36 + _x37) + E_YC*(_x17*_x23 + _x25*_x27 + _x54) + E_YX*_x24 + E_YY*_x24 + E_YZ*_x24 + E_ZB*(_x36 - _x37) + E_ZC*(_x17*_x27 + _x23*_x25 + _x54) + E_ZX*_x28 + E_ZY*_x28 + E_ZZ*_x28 + _x11*_x13 - _x14*tool_length + _x24*_x32 + _x29*_x30 + _x29*_x31;
    out[1] = E_A0B*(Y*_x116 + Z*_x10 - _x10*_x43 - _x116*_x43 + _x48 + _x77 + _x79*_x84) + E_A0C*(Y*_x25*_x55 + Z*_x17*_x55 - _x114*_x43 - _x115*_x43 + (38749.0/500.0)*_x38*_x55 - _x55*_x57) - E_A0Z*_x108 + E_AB*(Y*_x117 + _x108 - _x117*_x43 + _x78*_x87 + _x80) - E_AC*_x49 + E_AX*(Y*_x74 + _x109) + E_AY*_x109 + E_B0B*(-Y*_x118 + Z*_x120 + _x118*_x43 + _x119*_x52 - _x120*_x43 - _x47*_x88 - _x52*_x71*_x76 + _x78*_x92) + E_B0C*_x44 + E_BB*(Z*_x121 + _x119 + _x122 + _x123*_x43 - _x124 + _x125 - _x4*_x47 - _x71*_x76) + E_BC*_x44 - E_C0Y*_x105 + E_CB*(-X*_x126 + Z*_x123 + _x102*_x126 + _x103*_x71 + 2*_x122 + _x124 + _x125) + E_CC*(X*_x12 + Y*_x23 + Z*_x27 + _x102*_x11 + _x24*_x43 + _x28*_x43) - E_CX*_x105 + E_X0B*(-_x112 + _x52*_x71) + E_X0C*(_x61*_x71 + _x64*_x79 + _x65*_x78) + E_XB*_x71 + E_XC*(_x112 + _x2*_x71) + E_XX*_x72 + E_XY*_x72 + E_XZ*_x72 + E_Y0B*(_x110*_x52 + _x111*_x52 + _x75) + E_Y0C*(_x67*_x71 + _x68*_x79 + _x69*_x78) + E_YB*(_x110 + _x111) + E_YC*(_x113 + _x17*_x78 + _x25*_x79) + E_YX*_x73 + E_YY*_x73 + E_YZ*_x73 + E_ZB*(_x110 - _x111) + E_ZC*(_x113 + _x17*_x79 + _x25*_x78) + E_ZX*_x74 + E_ZY*_x74 + E_ZZ*_x74 - _x104*tool_length + _x106*_x29 + _x107*_x29 + _x13*_x72 + _x32*_x73;
    out[2] = E_A0B*(Z*_x51 + _x135*_x84 + (38749.0/250.0)*_x38 + _x43*_x52 - _x57) + E_A0C*(-X*_x146 + Y*_x147 + Z*_x148 + _x102*_x146 - _x147*_x43 - _x148*_x43) - E_A0Z*_x130 + E_AB*(_x130 + _x135*_x43 + _x145 + _x43*_x85 + _x85*_x87) + E_AC*(Z*_x85 + _x145 + _x25*_x43 - _x39 + _x57) + E_AX*(Y*_x17 + _x131) + E_AY*_x131 + E_B0B*(-_x128 + _x144 + _x47*_x52 - _x52*_x92 + _x85*_x92) + E_B0C*(X*_x61 + Y*_x65 + Z*_x64 - _x102*_x61 - _x43*_x64 - _x43*_x65) + E_BB*(_x141 - _x142 + _x143 + _x47 - _x92) + E_BC*(X*_x2 + Z*_x62 - _x103*_x6 + _x129 - _x144*_x5) + E_C0Y*_x129 + E_CB*(-X*_x93 - _x141 + _x142 + _x143 + _x144 + _x6*_x83) + E_CX*_x129 + E_X0B*(-_x139 + (1.0/2.0)*_x5*_x52*_x6) + E_X0C*(_x135*_x64 + _x61*_x62 + _x65*_x85) + E_XB*_x62 + E_XC*(_x139 + _x6*_x93) - E_XX*_x62 - E_XY*_x62 - E_XZ*_x62 + E_Y0B*(_x134*_x52 + _x136*_x52 + _x137*_x5) + E_Y0C*(_x135*_x68 + _x62*_x67 + _x69*_x85) + E_YB*(_x134 + _x136) + E_YC*(_x135*_x25 + _x138 + _x17*_x85) + E_YX*_x25 + E_YY*_x25 + E_YZ*_x25 + E_ZB*(-_x134 + (1.0/2.0)*_x135*_x5) + E_ZC*(_x135*_x17 + _x138 + _x25*_x85) + E_ZX*_x17 + E_ZY*_x17 + E_ZZ*_x17 + _x127*tool_length - _x13*_x62 - _x132*_x29 - _x133*_x29 + _x25*_x32;
    out[3] = E_A0B*_x21 - E_A0C*_x18 + E_AB*_x24 - E_AC*_x18 + E_AX*_x23 + E_AY*_x23 + E_AZ*_x23 + E_B0B*_x91 + E_B0C*_x59 + E_BB*_x96 - E_BC*_x45 + E_CB*_x95 + E_CC*_x74 + _x14 + _x30 + _x31;
    out[4] = E_A0B*_x10 + E_A0C*_x115 + E_AB*_x73 + E_AC*_x45 + E_AX*_x78 + E_AY*_x78 + E_AZ*_x78 + E_B0B*_x120 - E_B0C*_x18 + E_BB*_x121 - E_BC*_x18 + E_CB*_x123 + E_CC*_x27 + _x104 + _x106 + _x107;
    out[5] = E_A0B*_x51 + E_A0C*_x148 + E_AB*_x25 + E_AC*_x85 + E_AX*_x85 + E_AY*_x85 + E_AZ*_x85 + E_B0C*_x64 + E_BB*_x140 + E_BC*_x62 - E_CB*_x140 - _x127 - _x132 - _x133;
}

/* ----------------------------------------------------------------- the error model as data */
struct mtk_table {      /* tables of one axis on the same positions: value = a_j + s_j x on segment j */
    int axis, rows, points;
    double step;        /* uniform grid spacing, 0 when not uniform (then a binary search) */
    const double *xp;   /* points positions (mm or deg) */
    const int *cols;    /* rows error indices */
    const double *coef; /* (2 rows) x (points - 1): rows of a, then rows of s */
};
struct mtk_harmonic {   /* a0 + sum_h ca_h cos(h w) + sa_h sin(h w), w = 2 pi x / period */
    int axis, rows, terms;
    double period;
    const int *cols;
    const double *a0, *ca, *sa; /* rows; rows x terms; rows x terms */
};
struct mtk_polynomial { /* sum_k c_k u^k, u = off + scl x, x held within [lo, hi] (the table's range) */
    int axis, col, terms;
    double lo, hi, off, scl;
    const double *c;
};
struct mtk_model {
    int full;                /* scope: 0 "position", 1 "full" (the rotary axes correct the tool axis too) */
    double cone_deg;         /* scope "full": no orientation correction within this angle of the singular pose */
    const double *constants; /* MTK_N_ERRORS */
    int n_tables, n_harmonics, n_polynomials;
    const struct mtk_table *tables;
    const struct mtk_harmonic *harmonics;
    const struct mtk_polynomial *polynomials;
};

/* ----------------------------------------------------------------- the evaluator (ErrorEvaluator's steps) */
static void mtk_errors(const struct mtk_model *m, const double *q, double *e)
{
    int i, r, h;
    for (i = 0; i < MTK_N_ERRORS; i++) e[i] = m->constants[i];
    for (i = 0; i < m->n_tables; i++) {
        const struct mtk_table *t = &m->tables[i];
        const int n = t->points - 1;
        double x = q[t->axis];
        int j;
        if (x < t->xp[0]) x = t->xp[0];
        if (x > t->xp[n]) x = t->xp[n];
        if (t->step > 0) {
            j = (int)((x - t->xp[0]) * (1.0 / t->step));
        } else {            /* the last j with xp[j] <= x */
            int lo = 0, hi = n + 1;
            while (hi - lo > 1) {
                const int mid = (lo + hi) / 2;
                if (t->xp[mid] <= x) lo = mid; else hi = mid;
            }
            j = lo;
        }
        if (j < 0) j = 0;
        if (j > n - 1) j = n - 1;
        for (r = 0; r < t->rows; r++)
            e[t->cols[r]] = t->coef[r * n + j] + t->coef[(t->rows + r) * n + j] * x;
    }
    for (i = 0; i < m->n_harmonics; i++) {
        const struct mtk_harmonic *s = &m->harmonics[i];
        const double w = (2 * MTK_PI / s->period) * q[s->axis];
        const double c1 = cos(w), s1 = sin(w);
        for (r = 0; r < s->rows; r++) {
            const double *ca = s->ca + r * s->terms, *sa = s->sa + r * s->terms;
            double acc = s->a0[r], ch = c1, sh = s1;
            if (s->terms > 0) acc = s->a0[r] + (ca[0] * c1 + sa[0] * s1);
            for (h = 1; h < s->terms; h++) {
                const double cn = ch * c1 - sh * s1, sn = sh * c1 + ch * s1;
                ch = cn;
                sh = sn;
                acc += ca[h] * ch + sa[h] * sh;
            }
            e[s->cols[r]] = acc;
        }
    }
    for (i = 0; i < m->n_polynomials; i++) {
        const struct mtk_polynomial *p = &m->polynomials[i];
        double x = q[p->axis], u, acc;
        if (x < p->lo) x = p->lo;
        if (x > p->hi) x = p->hi;
        u = p->off + p->scl * x;
        acc = p->c[p->terms - 1];
        for (h = p->terms - 2; h >= 0; h--) acc = p->c[h] + acc * u;
        e[p->col] += acc;
    }
}

/* x = A^-1 b for a 3 x 3 A (row-major) by Cramer's rule: the linear axes' block is a rotation (cond 1) */
static int mtk_solve3(const double *a, const double *b, double *x)
{
    const double c0 = a[4] * a[8] - a[5] * a[7], c1 = a[5] * a[6] - a[3] * a[8], c2 = a[3] * a[7] - a[4] * a[6];
    const double det = a[0] * c0 + a[1] * c1 + a[2] * c2;
    if (!(fabs(det) > 1e-12)) return -1;
    x[0] = (b[0] * c0 + b[1] * (a[2] * a[7] - a[1] * a[8]) + b[2] * (a[1] * a[5] - a[2] * a[4])) / det;
    x[1] = (b[0] * c1 + b[1] * (a[0] * a[8] - a[2] * a[6]) + b[2] * (a[2] * a[3] - a[0] * a[5])) / det;
    x[2] = (b[0] * c2 + b[1] * (a[1] * a[6] - a[0] * a[7]) + b[2] * (a[0] * a[4] - a[1] * a[3])) / det;
    return 0;
}

/* world -> joints: the axis commands that put the tool tip where the nominal machine puts it at `world`
 * (scope "position"); returns the Newton steps taken, or -1 when not converged within max_iterations. */
static int mtk_inverse_position(const struct mtk_model *m, const double *world, double tool_length,
                                int max_iterations, double *joints)
{
    double q0[MTK_N_AXES], q[MTK_N_AXES], target[6], e[MTK_N_ERRORS], fj[6 * (MTK_N_AXES + 1)];
    double jl[9], r[3], d[3];
    int i, k, it;
    for (i = 0; i < MTK_N_AXES; i++) q0[i] = q[i] = world[i];
    q0[MTK_TOOL_AXIS] -= tool_length;
    q[MTK_TOOL_AXIS] -= tool_length;
    mtk_forward(q0, tool_length, target);
    for (it = 1; it <= max_iterations; it++) {
        double size = 0;
        mtk_errors(m, q, e);
        mtk_forward_errors_with_jacobian(q, e, tool_length, fj);
        for (k = 0; k < 3; k++) {
            r[k] = fj[k * (MTK_N_AXES + 1)] - target[k];
            for (i = 0; i < 3; i++) jl[3 * k + i] = fj[k * (MTK_N_AXES + 1) + 1 + mtk_linear[i]];
        }
        if (mtk_solve3(jl, r, d)) return -1;
        for (i = 0; i < 3; i++) {
            q[mtk_linear[i]] -= d[i];
            if (fabs(d[i]) > size) size = fabs(d[i]);
        }
        if (!(size == size) || size > 1e3) return -1; /* NaN or a runaway: refused */
        if (size <= MTK_TOLERANCE_MM) {
            for (i = 0; i < MTK_N_AXES; i++) joints[i] = q[i];
            joints[MTK_TOOL_AXIS] += tool_length;
            return it;
        }
    }
    return -1;
}

/* joints -> world, scope "position": the nominal axes whose nominal tool tip is the error-inclusive one */
static int mtk_forward_position(const struct mtk_model *m, const double *joints, double tool_length,
                                double *world)
{
    double q[MTK_N_AXES], e[MTK_N_ERRORS], p[6], p0[6], jn[6 * MTK_N_AXES], jl[9], r[3], d[3];
    int i, k;
    for (i = 0; i < MTK_N_AXES; i++) q[i] = joints[i];
    q[MTK_TOOL_AXIS] -= tool_length;
    mtk_errors(m, q, e);
    mtk_forward_errors(q, e, tool_length, p);
    mtk_forward(q, tool_length, p0);
    mtk_jacobian_axes(q, tool_length, jn);
    for (k = 0; k < 3; k++) {
        r[k] = p[k] - p0[k];
        for (i = 0; i < 3; i++) jl[3 * k + i] = jn[k * MTK_N_AXES + mtk_linear[i]];
    }
    if (mtk_solve3(jl, r, d)) return -1;
    for (i = 0; i < MTK_N_AXES; i++) world[i] = q[i];
    for (i = 0; i < 3; i++) world[mtk_linear[i]] += d[i];
    world[MTK_TOOL_AXIS] += tool_length;
    return 0;
}

/* scope "full", Compensator._correct_block step by step: per step the tilt and rotary axes first cancel the tool-axis
 * residual by least squares (the first step from the first-order deviation and the nominal Jacobian, blended by
 * the weight w of the pose; later steps on the exact model, only where w = 1), the tilt axis held within its
 * limits; then the linear axes cancel the exact tool-tip residual (nominal Jacobian).  w = smoothstep(s / sin(cone)
 * - 1), s the smaller singular value of d(tool axis)/d(tilt, rotary) per rad (Compensator.weight). */
static double mtk_weight(const struct mtk_model *m, const double *jn)
{
    double g[3] = {0, 0, 0}, smin, sc, x;
    int k;
    if (m->cone_deg <= 0) return 1;
    for (k = 3; k < 6; k++) {
        const double a = jn[k * MTK_N_AXES + MTK_TILT], b = jn[k * MTK_N_AXES + MTK_ROTARY];
        g[0] += a * a;
        g[1] += a * b;
        g[2] += b * b;
    }
    x = 0.5 * (g[0] - g[2]);
    smin = 0.5 * (g[0] + g[2]) - sqrt(x * x + g[1] * g[1]);
    smin = sqrt(smin > 0 ? smin : 0) / (MTK_PI / 180);
    sc = sin(m->cone_deg * MTK_PI / 180);
    x = (smin - sc) / sc;
    x = x < 0 ? 0 : (x > 1 ? 1 : x);
    return x * x * (3 - 2 * x);
}

/* the (tilt, rotary) step of least squares for the tool-axis residual r[3..5] under the Jacobian j (6 x n) */
static int mtk_orientation_step(const double *j, int stride, const double *r, double *d)
{
    double g0 = 0, g1 = 0, g2 = 0, h0 = 0, h1 = 0, det;
    int k;
    for (k = 3; k < 6; k++) {
        const double a = j[k * stride + MTK_TILT], b = j[k * stride + MTK_ROTARY];
        g0 += a * a;
        g1 += a * b;
        g2 += b * b;
        h0 -= a * r[k];
        h1 -= b * r[k];
    }
    det = g0 * g2 - g1 * g1;
    if (!(det > 0)) return -1;
    d[0] = (g2 * h0 - g1 * h1) / det;
    d[1] = (g0 * h1 - g1 * h0) / det;
    return 0;
}

static int mtk_inverse_full(const struct mtk_model *m, const double *world, double tool_length, int max_iterations,
                            double *joints)
{
    double q0[MTK_N_AXES], q[MTK_N_AXES], target[6], p[6], r[6], e[MTK_N_ERRORS], fj[6 * (MTK_N_AXES + 1)];
    double jn[6 * MTK_N_AXES], jl[9], d[3], bc[2], w, size;
    int i, k, it;
    for (i = 0; i < MTK_N_AXES; i++) q0[i] = q[i] = world[i];
    q0[MTK_TOOL_AXIS] -= tool_length;
    q[MTK_TOOL_AXIS] -= tool_length;
    mtk_forward(q0, tool_length, target);
    mtk_jacobian_axes(q0, tool_length, jn);
    w = mtk_weight(m, jn);
    for (it = 0; it < max_iterations; it++) {
        const double wi = it == 0 ? w : (w >= 1 ? 1 : 0);
        double nb;
        bc[0] = bc[1] = 0;
        if (it == 0) {
            mtk_errors(m, q0, e);
            mtk_deviation_first_order(q0, e, tool_length, r);
            if (wi > 0 && mtk_orientation_step(jn, MTK_N_AXES, r, bc)) return -1;
        } else {
            mtk_errors(m, q, e);
            mtk_forward_errors_with_jacobian(q, e, tool_length, fj);
            for (k = 0; k < 6; k++) r[k] = fj[k * (MTK_N_AXES + 1)] - target[k];
            if (wi > 0 && mtk_orientation_step(fj + 1, MTK_N_AXES + 1, r, bc)) return -1;
        }
        nb = q[MTK_TILT] + bc[0] * wi;
        if (nb < MTK_TILT_LO) nb = MTK_TILT_LO;
        if (nb > MTK_TILT_HI) nb = MTK_TILT_HI;
        size = fabs(nb - q[MTK_TILT]) + fabs(bc[1] * wi);
        q[MTK_TILT] = nb;
        q[MTK_ROTARY] += bc[1] * wi;
        mtk_errors(m, q, e);                         /* the exact tool-tip residual at the new angles */
        mtk_forward_errors(q, e, tool_length, p);
        mtk_jacobian_axes(q, tool_length, jn);
        for (k = 0; k < 3; k++) {
            r[k] = p[k] - target[k];
            for (i = 0; i < 3; i++) jl[3 * k + i] = jn[k * MTK_N_AXES + mtk_linear[i]];
        }
        if (mtk_solve3(jl, r, d)) return -1;
        for (i = 0; i < 3; i++) {
            q[mtk_linear[i]] -= d[i];
            size += fabs(d[i]);
        }
        if (!(size == size) || size > 1e3) return -1;
        if (it > 0 && size <= MTK_TOLERANCE_MM) {
            for (i = 0; i < MTK_N_AXES; i++) joints[i] = q[i];
            joints[MTK_TOOL_AXIS] += tool_length;
            return it + 1;
        }
    }
    return -1;
}

/* joints -> world, scope "full": the world whose inverse is `joints`, by fixed-point steps (the inverse is the
 * identity plus corrections whose slope is ~1e-4: each step gains four digits) */
static int mtk_forward_full(const struct mtk_model *m, const double *joints, double tool_length, int max_iterations,
                            double *world)
{
    double qi[MTK_N_AXES], size;
    int i, it;
    for (i = 0; i < MTK_N_AXES; i++) world[i] = joints[i];
    for (it = 0; it < 8; it++) {
        if (mtk_inverse_full(m, world, tool_length, max_iterations, qi) < 0) return -1;
        size = 0;
        for (i = 0; i < MTK_N_AXES; i++) {
            world[i] -= qi[i] - joints[i];
            size += fabs(qi[i] - joints[i]);
        }
        if (size <= MTK_TOLERANCE_MM) return 0;
    }
    return -1;
}

static int mtk_inverse(const struct mtk_model *m, const double *world, double tool_length, int max_iterations,
                       double *joints)
{
    return m->full ? mtk_inverse_full(m, world, tool_length, max_iterations, joints)
                   : mtk_inverse_position(m, world, tool_length, max_iterations, joints);
}

static int mtk_forward_kins(const struct mtk_model *m, const double *joints, double tool_length, int max_iterations,
                            double *world)
{
    return m->full ? mtk_forward_full(m, joints, tool_length, max_iterations, world)
                   : mtk_forward_position(m, joints, tool_length, world);
}
