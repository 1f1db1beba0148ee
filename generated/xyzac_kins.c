/* -----------------------------------------------------------------------------
 * GENERATED FILE - DO NOT EDIT.
 * Generator: python -m derive (xyzac); source: derive/kins_c.py, derive/kinematics.py
 * Target: C99 (a LinuxCNC kinematics component; mtcal export --format linuxcnc-kins).
 * Inputs (machine spec, SymPy version, hash of derive/) are in manifest.json.
 * ---------------------------------------------------------------------------*/
/* Trunnion five-axis machine (XYZ on the spindle side, A trunnion about X carrying the C table): kinematics generated from derive/machines/xyzac.toml. */
#define MTK_N_AXES 5
#define MTK_N_ERRORS 41
#define MTK_TOOL_AXIS 2 /* Z */
#define MTK_TOLERANCE_MM 1e-10
#define MTK_TILT 3 /* A */
#define MTK_ROTARY 4 /* C */
#define MTK_TILT_LO -120.0
#define MTK_TILT_HI 120.0
#define MTK_PI 3.141592653589793
static const char mtk_axes[] = "XYZAC";
static const int mtk_linear[3] = {0, 1, 2};

/* Nominal pose [x, y, z (mm), i, j, k] of the tool in the workpiece frame.
 * out: 6 x 1, row-major */
static void mtk_forward(const double *axes, double tool_length, double *out)
{
    const double X = axes[0];
    const double Y = axes[1];
    const double Z = axes[2];
    const double A = axes[3];
    const double C = axes[4];
    (void)tool_length;
    const double _x0 = (1.0/180.0)*MTK_PI;
    const double _x1 = C*_x0;
    const double _x2 = cos(_x1);
    const double _x3 = A*_x0;
    const double _x4 = sin(_x3);
    const double _x5 = sin(_x1);
    const double _x6 = _x4*_x5;
    const double _x7 = cos(_x3);
    const double _x8 = Y*_x7;
    const double _x9 = _x2*_x4;
    out[0] = X*_x2 + Z*_x6 - _x5*_x8 - 120*_x6;
    out[1] = X*_x5 - Z*_x9 + _x2*_x8 + 120*_x9;
    out[2] = Y*_x4 + Z*_x7 - 120*_x7 + 120;
    out[3] = _x6;
    out[4] = -_x9;
    out[5] = _x7;
}

/* d pose / d axes of the nominal pose; columns per mm (linear) and per degree (rotary).
 * out: 6 x 5, row-major */
static void mtk_jacobian_axes(const double *axes, double tool_length, double *out)
{
    const double X = axes[0];
    const double Y = axes[1];
    const double Z = axes[2];
    const double A = axes[3];
    const double C = axes[4];
    (void)tool_length;
    const double _x0 = (1.0/180.0)*MTK_PI;
    const double _x1 = C*_x0;
    const double _x2 = cos(_x1);
    const double _x3 = sin(_x1);
    const double _x4 = A*_x0;
    const double _x5 = cos(_x4);
    const double _x6 = _x3*_x5;
    const double _x7 = sin(_x4);
    const double _x8 = _x3*_x7;
    const double _x9 = (2.0/3.0)*MTK_PI;
    const double _x10 = Y*_x0;
    const double _x11 = _x0*_x6;
    const double _x12 = X*_x0;
    const double _x13 = _x2*_x7;
    const double _x14 = _x2*_x5;
    const double _x15 = _x0*_x14;
    const double _x16 = _x0*_x8;
    const double _x17 = _x0*_x7;
    out[0] = _x2;
    out[1] = -_x6;
    out[2] = _x8;
    out[3] = Z*_x11 + _x10*_x8 - _x6*_x9;
    out[4] = (1.0/180.0)*MTK_PI*Z*_x2*_x7 - _x10*_x14 - _x12*_x3 - _x13*_x9;
    out[5] = _x3;
    out[6] = _x14;
    out[7] = -_x13;
    out[8] = -Z*_x15 - _x10*_x13 + (2.0/3.0)*MTK_PI*_x2*_x5;
    out[9] = Z*_x16 - _x10*_x6 + _x12*_x2 - _x8*_x9;
    out[10] = 0;
    out[11] = _x7;
    out[12] = _x5;
    out[13] = -Z*_x17 + _x10*_x5 + _x7*_x9;
    out[14] = 0;
    out[15] = 0;
    out[16] = 0;
    out[17] = 0;
    out[18] = _x11;
    out[19] = _x0*_x13;
    out[20] = 0;
    out[21] = 0;
    out[22] = 0;
    out[23] = -_x15;
    out[24] = _x16;
    out[25] = 0;
    out[26] = 0;
    out[27] = 0;
    out[28] = -_x17;
    out[29] = 0;
}

/* Exact error-inclusive pose [x, y, z, i, j, k] (errors in mm, rad; see derive/kinematics.py).
 * out: 6 x 1, row-major */
static void mtk_forward_errors(const double *axes, const double *errors, double tool_length, double *out)
{
    const double X = axes[0];
    const double Y = axes[1];
    const double Z = axes[2];
    const double A = axes[3];
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
    const double E_XA = errors[21];
    const double E_YA = errors[22];
    const double E_ZA = errors[23];
    const double E_AA = errors[24];
    const double E_BA = errors[25];
    const double E_CA = errors[26];
    const double E_XC = errors[27];
    const double E_YC = errors[28];
    const double E_ZC = errors[29];
    const double E_AC = errors[30];
    const double E_BC = errors[31];
    const double E_CC = errors[32];
    const double E_X0A = errors[33];
    const double E_Y0A = errors[34];
    const double E_A0A = errors[35];
    const double E_B0A = errors[36];
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
    const double _x47 = sin(E_A0C);
    const double _x48 = sin(E_AC);
    const double _x49 = cos(E_BC);
    const double _x50 = _x48*_x49;
    const double _x51 = sin(E_BC);
    const double _x52 = sin(E_B0C);
    const double _x53 = cos(E_A0C);
    const double _x54 = _x52*_x53;
    const double _x55 = cos(E_AC);
    const double _x56 = cos(E_B0C);
    const double _x57 = -_x47*_x50 + _x49*_x53*_x55*_x56 - _x51*_x54;
    const double _x58 = (1.0/180.0)*MTK_PI;
    const double _x59 = C*_x58;
    const double _x60 = cos(_x59);
    const double _x61 = -_x49*_x52*_x55 - _x51*_x56;
    const double _x62 = sin(_x59);
    const double _x63 = _x47*_x52;
    const double _x64 = _x47*_x49*_x55*_x56 + _x50*_x53 - _x51*_x63;
    const double _x65 = _x60*_x61 - _x62*_x64;
    const double _x66 = _x56*_x65;
    const double _x67 = _x60*_x64 + _x61*_x62;
    const double _x68 = _x54*_x57 + _x63*_x67 + _x66;
    const double _x69 = sin(E_B0A);
    const double _x70 = cos(E_A0A);
    const double _x71 = sin(E_A0A);
    const double _x72 = sin(E_AA);
    const double _x73 = cos(E_BA);
    const double _x74 = _x72*_x73;
    const double _x75 = sin(E_BA);
    const double _x76 = _x69*_x75;
    const double _x77 = cos(E_AA);
    const double _x78 = cos(E_B0A);
    const double _x79 = _x70*_x73*_x77*_x78 - _x70*_x76 - _x71*_x74;
    const double _x80 = _x70*_x79;
    const double _x81 = _x69*_x80;
    const double _x82 = A*_x58;
    const double _x83 = cos(_x82);
    const double _x84 = _x69*_x73;
    const double _x85 = -_x75*_x78 - _x77*_x84;
    const double _x86 = sin(_x82);
    const double _x87 = _x70*_x74 + _x71*_x73*_x77*_x78 - _x71*_x76;
    const double _x88 = _x83*_x85 - _x86*_x87;
    const double _x89 = _x78*_x88;
    const double _x90 = _x83*_x87 + _x85*_x86;
    const double _x91 = _x71*_x90;
    const double _x92 = _x69*_x91;
    const double _x93 = -_x81 - _x89 - _x92;
    const double _x94 = _x70*_x90 - _x71*_x79;
    const double _x95 = sin(E_CC);
    const double _x96 = _x49*_x95;
    const double _x97 = cos(E_CC);
    const double _x98 = _x55*_x97;
    const double _x99 = _x48*_x95;
    const double _x100 = _x51*_x99 + _x98;
    const double _x101 = _x48*_x97;
    const double _x102 = -_x101 + _x51*_x55*_x95;
    const double _x103 = _x102*_x56;
    const double _x104 = -_x100*_x47 + _x103*_x53 + _x54*_x96;
    const double _x105 = -_x102*_x52 + _x49*_x56*_x95;
    const double _x106 = _x100*_x53 + _x103*_x47 + _x63*_x96;
    const double _x107 = _x105*_x60 - _x106*_x62;
    const double _x108 = _x107*_x56;
    const double _x109 = _x105*_x62 + _x106*_x60;
    const double _x110 = _x104*_x54 + _x108 + _x109*_x63;
    const double _x111 = -_x69*_x88 + _x78*_x80 + _x78*_x91;
    const double _x112 = _x49*_x97;
    const double _x113 = _x101*_x51 - _x55*_x95;
    const double _x114 = _x51*_x98 + _x99;
    const double _x115 = _x114*_x56;
    const double _x116 = _x112*_x54 - _x113*_x47 + _x115*_x53;
    const double _x117 = -_x114*_x52 + _x49*_x56*_x97;
    const double _x118 = _x112*_x63 + _x113*_x53 + _x115*_x47;
    const double _x119 = _x117*_x60 - _x118*_x62;
    const double _x120 = _x119*_x56;
    const double _x121 = _x117*_x62 + _x118*_x60;
    const double _x122 = _x116*_x54 + _x120 + _x121*_x63;
    const double _x123 = _x110*_x94 + _x111*_x122 + _x68*_x93;
    const double _x124 = _x2*_x8;
    const double _x125 = _x2*_x4;
    const double _x126 = -_x124*_x19 + _x17*_x2*_x20*_x4 - _x18*_x7;
    const double _x127 = _x124*_x17;
    const double _x128 = _x125*_x31 + _x127*_x24 - _x28*_x7;
    const double _x129 = _x125*_x35 + _x127*_x26 - _x34*_x7;
    const double _x130 = _x126*_x42 + _x128*_x44 + _x129*_x43;
    const double _x131 = E_ZX + E_ZY*_x124 - _x0*_x7 + _x11*_x125 + _x126*_x15 + _x128*_x23 + _x129*_x33 - _x130*tool_length + tool_length;
    const double _x132 = cos(E_CA);
    const double _x133 = _x132*_x84;
    const double _x134 = sin(E_CA);
    const double _x135 = _x132*_x72;
    const double _x136 = -_x134*_x77 + _x135*_x75;
    const double _x137 = _x134*_x72;
    const double _x138 = _x132*_x77;
    const double _x139 = _x137 + _x138*_x75;
    const double _x140 = _x139*_x78;
    const double _x141 = _x133*_x70 - _x136*_x71 + _x140*_x70;
    const double _x142 = _x132*_x73*_x78 - _x139*_x69;
    const double _x143 = _x133*_x71 + _x136*_x70 + _x140*_x71;
    const double _x144 = _x142*_x86 + _x143*_x83;
    const double _x145 = _x141*_x71 - _x144*_x70;
    const double _x146 = _x141*_x70;
    const double _x147 = _x146*_x69;
    const double _x148 = _x142*_x83 - _x143*_x86;
    const double _x149 = _x148*_x78;
    const double _x150 = _x144*_x71;
    const double _x151 = _x150*_x69;
    const double _x152 = _x147 + _x149 + _x151;
    const double _x153 = -_x146*_x78 + _x148*_x69 - _x150*_x78;
    const double _x154 = _x110*_x145 + _x122*_x153 + _x152*_x68;
    const double _x155 = _x2*_x5;
    const double _x156 = -_x12 + _x5*_x7*_x8;
    const double _x157 = _x6*_x7 + _x9;
    const double _x158 = _x155*_x18 - _x156*_x19 + _x157*_x21;
    const double _x159 = _x156*_x17;
    const double _x160 = _x155*_x28 + _x157*_x31 + _x159*_x24;
    const double _x161 = _x155*_x34 + _x157*_x35 + _x159*_x26;
    const double _x162 = _x158*_x42 + _x160*_x44 + _x161*_x43;
    const double _x163 = E_YX + E_ZY*_x156 + _x0*_x155 + _x11*_x157 + _x15*_x158 + _x160*_x23 + _x161*_x33 - _x162*tool_length;
    const double _x164 = _x134*_x84;
    const double _x165 = _x137*_x75 + _x138;
    const double _x166 = _x134*_x75*_x77 - _x135;
    const double _x167 = _x166*_x78;
    const double _x168 = _x164*_x70 - _x165*_x71 + _x167*_x70;
    const double _x169 = _x134*_x73*_x78 - _x166*_x69;
    const double _x170 = _x164*_x71 + _x165*_x70 + _x167*_x71;
    const double _x171 = _x169*_x86 + _x170*_x83;
    const double _x172 = -_x168*_x71 + _x171*_x70;
    const double _x173 = _x168*_x70;
    const double _x174 = _x173*_x69;
    const double _x175 = _x169*_x83 - _x170*_x86;
    const double _x176 = _x175*_x78;
    const double _x177 = _x171*_x71;
    const double _x178 = _x177*_x69;
    const double _x179 = -_x174 - _x176 - _x178;
    const double _x180 = _x173*_x78 - _x175*_x69 + _x177*_x78;
    const double _x181 = _x110*_x172 + _x122*_x180 + _x179*_x68;
    const double _x182 = E_X0A*_x69;
    const double _x183 = E_Y0A*_x71 - _x182*_x70;
    const double _x184 = -E_Y0A*_x70 - _x182*_x71;
    const double _x185 = -E_X0C*_x54 + E_Y0C*_x47;
    const double _x186 = -E_X0C*_x63 - E_Y0C*_x53;
    const double _x187 = -E_X0C*_x51 - E_X0C*_x66 + E_Y0C*_x50 + E_ZC + _x185*_x57 + _x186*_x67;
    const double _x188 = E_X0C*_x49;
    const double _x189 = -E_X0C*_x108 + E_Y0C*_x100 + E_YC + _x104*_x185 + _x109*_x186 + _x188*_x95;
    const double _x190 = -E_X0C*_x120 + E_XC + E_Y0C*_x113 + _x116*_x185 + _x121*_x186 + _x188*_x97;
    const double _x191 = -E_X0A*_x75 - E_X0A*_x89 + E_Y0A*_x74 + E_ZA + _x111*_x190 + _x183*_x79 + _x184*_x90 + _x187*_x93 + _x189*_x94 + 120*_x81 + 120*_x89 + 120*_x92;
    const double _x192 = E_X0A*_x73;
    const double _x193 = E_X0A*_x148*_x78 - E_XA - E_Y0A*_x136 - _x132*_x192 - _x141*_x183 - _x144*_x184 + _x145*_x189 - 120*_x147 - 120*_x149 - 120*_x151 + _x152*_x187 + _x153*_x190 + 120;
    const double _x194 = -E_X0A*_x176 + E_Y0A*_x165 + E_YA + _x134*_x192 + _x168*_x183 + _x171*_x184 + _x172*_x189 + 120*_x174 + 120*_x176 + 120*_x178 + _x179*_x187 + _x180*_x190;
    const double _x195 = -_x104*_x47 + _x109*_x53;
    const double _x196 = -_x47*_x57 + _x53*_x67;
    const double _x197 = -_x116*_x47 + _x121*_x53;
    const double _x198 = _x111*_x197 + _x195*_x94 + _x196*_x93;
    const double _x199 = _x145*_x195 + _x152*_x196 + _x153*_x197;
    const double _x200 = _x172*_x195 + _x179*_x196 + _x180*_x197;
    const double _x201 = _x53*_x56;
    const double _x202 = _x47*_x56;
    const double _x203 = _x201*_x57 + _x202*_x67 - _x52*_x65;
    const double _x204 = _x104*_x201 - _x107*_x52 + _x109*_x202;
    const double _x205 = _x116*_x201 - _x119*_x52 + _x121*_x202;
    const double _x206 = _x111*_x205 + _x203*_x93 + _x204*_x94;
    const double _x207 = _x145*_x204 + _x152*_x203 + _x153*_x205;
    const double _x208 = _x172*_x204 + _x179*_x203 + _x180*_x205;
    out[0] = -_x123*_x191 + _x123*_x46 + _x131*_x154 - _x154*_x193 + _x163*_x181 - _x181*_x194;
    out[1] = _x131*_x199 + _x163*_x200 - _x191*_x198 - _x193*_x199 - _x194*_x200 + _x198*_x46;
    out[2] = _x131*_x207 + _x163*_x208 - _x191*_x206 - _x193*_x207 - _x194*_x208 + _x206*_x46;
    out[3] = _x123*_x45 + _x130*_x154 + _x162*_x181;
    out[4] = _x130*_x199 + _x162*_x200 + _x198*_x45;
    out[5] = _x130*_x207 + _x162*_x208 + _x206*_x45;
}

/* Column 0: exact error-inclusive pose; columns 1..: its partial derivatives with respect to the axes at fixed error values (per mm, per degree).
 * out: 6 x 6, row-major */
static void mtk_forward_errors_with_jacobian(const double *axes, const double *errors, double tool_length, double *out)
{
    const double X = axes[0];
    const double Y = axes[1];
    const double Z = axes[2];
    const double A = axes[3];
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
    const double E_XA = errors[21];
    const double E_YA = errors[22];
    const double E_ZA = errors[23];
    const double E_AA = errors[24];
    const double E_BA = errors[25];
    const double E_CA = errors[26];
    const double E_XC = errors[27];
    const double E_YC = errors[28];
    const double E_ZC = errors[29];
    const double E_AC = errors[30];
    const double E_BC = errors[31];
    const double E_CC = errors[32];
    const double E_X0A = errors[33];
    const double E_Y0A = errors[34];
    const double E_A0A = errors[35];
    const double E_B0A = errors[36];
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
    const double _x53 = sin(E_A0C);
    const double _x54 = sin(E_AC);
    const double _x55 = cos(E_BC);
    const double _x56 = _x54*_x55;
    const double _x57 = sin(E_BC);
    const double _x58 = sin(E_B0C);
    const double _x59 = cos(E_A0C);
    const double _x60 = _x58*_x59;
    const double _x61 = cos(E_AC);
    const double _x62 = cos(E_B0C);
    const double _x63 = -_x53*_x56 + _x55*_x59*_x61*_x62 - _x57*_x60;
    const double _x64 = (1.0/180.0)*MTK_PI;
    const double _x65 = C*_x64;
    const double _x66 = cos(_x65);
    const double _x67 = -_x55*_x58*_x61 - _x57*_x62;
    const double _x68 = _x66*_x67;
    const double _x69 = sin(_x65);
    const double _x70 = _x53*_x58;
    const double _x71 = _x53*_x55*_x61*_x62 + _x56*_x59 - _x57*_x70;
    const double _x72 = _x69*_x71;
    const double _x73 = _x68 - _x72;
    const double _x74 = _x62*_x73;
    const double _x75 = _x67*_x69;
    const double _x76 = _x66*_x71;
    const double _x77 = _x75 + _x76;
    const double _x78 = _x60*_x63 + _x70*_x77 + _x74;
    const double _x79 = sin(E_B0A);
    const double _x80 = cos(E_A0A);
    const double _x81 = sin(E_A0A);
    const double _x82 = sin(E_AA);
    const double _x83 = cos(E_BA);
    const double _x84 = _x82*_x83;
    const double _x85 = sin(E_BA);
    const double _x86 = _x79*_x85;
    const double _x87 = cos(E_AA);
    const double _x88 = cos(E_B0A);
    const double _x89 = _x80*_x83*_x87*_x88 - _x80*_x86 - _x81*_x84;
    const double _x90 = _x80*_x89;
    const double _x91 = _x79*_x90;
    const double _x92 = A*_x64;
    const double _x93 = cos(_x92);
    const double _x94 = _x79*_x83;
    const double _x95 = -_x85*_x88 - _x87*_x94;
    const double _x96 = _x93*_x95;
    const double _x97 = sin(_x92);
    const double _x98 = _x80*_x84 + _x81*_x83*_x87*_x88 - _x81*_x86;
    const double _x99 = _x97*_x98;
    const double _x100 = _x96 - _x99;
    const double _x101 = _x100*_x88;
    const double _x102 = _x95*_x97;
    const double _x103 = _x93*_x98;
    const double _x104 = _x102 + _x103;
    const double _x105 = _x104*_x81;
    const double _x106 = _x105*_x79;
    const double _x107 = -_x101 - _x106 - _x91;
    const double _x108 = _x104*_x80 - _x81*_x89;
    const double _x109 = sin(E_CC);
    const double _x110 = _x109*_x55;
    const double _x111 = cos(E_CC);
    const double _x112 = _x111*_x61;
    const double _x113 = _x109*_x54;
    const double _x114 = _x112 + _x113*_x57;
    const double _x115 = _x111*_x54;
    const double _x116 = _x109*_x57*_x61 - _x115;
    const double _x117 = _x116*_x62;
    const double _x118 = _x110*_x60 - _x114*_x53 + _x117*_x59;
    const double _x119 = _x109*_x55*_x62 - _x116*_x58;
    const double _x120 = _x119*_x66;
    const double _x121 = _x110*_x70 + _x114*_x59 + _x117*_x53;
    const double _x122 = _x121*_x69;
    const double _x123 = _x120 - _x122;
    const double _x124 = _x123*_x62;
    const double _x125 = _x119*_x69;
    const double _x126 = _x121*_x66;
    const double _x127 = _x125 + _x126;
    const double _x128 = _x118*_x60 + _x124 + _x127*_x70;
    const double _x129 = -_x100*_x79 + _x105*_x88 + _x88*_x90;
    const double _x130 = _x111*_x55;
    const double _x131 = -_x109*_x61 + _x115*_x57;
    const double _x132 = _x112*_x57 + _x113;
    const double _x133 = _x132*_x62;
    const double _x134 = _x130*_x60 - _x131*_x53 + _x133*_x59;
    const double _x135 = _x111*_x55*_x62 - _x132*_x58;
    const double _x136 = _x135*_x66;
    const double _x137 = _x130*_x70 + _x131*_x59 + _x133*_x53;
    const double _x138 = _x137*_x69;
    const double _x139 = _x136 - _x138;
    const double _x140 = _x139*_x62;
    const double _x141 = _x135*_x69;
    const double _x142 = _x137*_x66;
    const double _x143 = _x141 + _x142;
    const double _x144 = _x134*_x60 + _x140 + _x143*_x70;
    const double _x145 = _x107*_x78 + _x108*_x128 + _x129*_x144;
    const double _x146 = _x3*_x9;
    const double _x147 = _x3*_x5;
    const double _x148 = -_x146*_x23 + _x21*_x24*_x3*_x5 - _x22*_x8;
    const double _x149 = _x146*_x21;
    const double _x150 = _x147*_x36 + _x149*_x29 - _x33*_x8;
    const double _x151 = _x147*_x41 + _x149*_x31 - _x40*_x8;
    const double _x152 = _x148*_x48 + _x150*_x50 + _x151*_x49;
    const double _x153 = E_ZX + E_ZY*_x146 - _x1*_x8 + _x13*_x147 + _x148*_x19 + _x150*_x28 + _x151*_x39 - _x152*tool_length + tool_length;
    const double _x154 = cos(E_CA);
    const double _x155 = _x154*_x94;
    const double _x156 = sin(E_CA);
    const double _x157 = _x154*_x82;
    const double _x158 = -_x156*_x87 + _x157*_x85;
    const double _x159 = _x156*_x82;
    const double _x160 = _x154*_x87;
    const double _x161 = _x159 + _x160*_x85;
    const double _x162 = _x161*_x88;
    const double _x163 = _x155*_x80 - _x158*_x81 + _x162*_x80;
    const double _x164 = _x154*_x83*_x88 - _x161*_x79;
    const double _x165 = _x164*_x97;
    const double _x166 = _x155*_x81 + _x158*_x80 + _x162*_x81;
    const double _x167 = _x166*_x93;
    const double _x168 = _x165 + _x167;
    const double _x169 = _x163*_x81 - _x168*_x80;
    const double _x170 = _x163*_x80;
    const double _x171 = _x170*_x79;
    const double _x172 = _x164*_x93;
    const double _x173 = _x166*_x97;
    const double _x174 = _x172 - _x173;
    const double _x175 = _x174*_x88;
    const double _x176 = _x168*_x81;
    const double _x177 = _x176*_x79;
    const double _x178 = _x171 + _x175 + _x177;
    const double _x179 = -_x170*_x88 + _x174*_x79 - _x176*_x88;
    const double _x180 = _x128*_x169 + _x144*_x179 + _x178*_x78;
    const double _x181 = _x3*_x6;
    const double _x182 = -_x14 + _x6*_x8*_x9;
    const double _x183 = _x10 + _x7*_x8;
    const double _x184 = _x181*_x22 - _x182*_x23 + _x183*_x25;
    const double _x185 = _x182*_x21;
    const double _x186 = _x181*_x33 + _x183*_x36 + _x185*_x29;
    const double _x187 = _x181*_x40 + _x183*_x41 + _x185*_x31;
    const double _x188 = _x184*_x48 + _x186*_x50 + _x187*_x49;
    const double _x189 = E_YX + E_ZY*_x182 + _x1*_x181 + _x13*_x183 + _x184*_x19 + _x186*_x28 + _x187*_x39 - _x188*tool_length;
    const double _x190 = _x156*_x94;
    const double _x191 = _x159*_x85 + _x160;
    const double _x192 = _x156*_x85*_x87 - _x157;
    const double _x193 = _x192*_x88;
    const double _x194 = _x190*_x80 - _x191*_x81 + _x193*_x80;
    const double _x195 = _x156*_x83*_x88 - _x192*_x79;
    const double _x196 = _x195*_x97;
    const double _x197 = _x190*_x81 + _x191*_x80 + _x193*_x81;
    const double _x198 = _x197*_x93;
    const double _x199 = _x196 + _x198;
    const double _x200 = -_x194*_x81 + _x199*_x80;
    const double _x201 = _x194*_x80;
    const double _x202 = _x201*_x79;
    const double _x203 = _x195*_x93;
    const double _x204 = _x197*_x97;
    const double _x205 = _x203 - _x204;
    const double _x206 = _x205*_x88;
    const double _x207 = _x199*_x81;
    const double _x208 = _x207*_x79;
    const double _x209 = -_x202 - _x206 - _x208;
    const double _x210 = _x201*_x88 - _x205*_x79 + _x207*_x88;
    const double _x211 = _x128*_x200 + _x144*_x210 + _x209*_x78;
    const double _x212 = -_x145;
    const double _x213 = E_X0A*_x79;
    const double _x214 = E_Y0A*_x81 - _x213*_x80;
    const double _x215 = -E_Y0A*_x80 - _x213*_x81;
    const double _x216 = -E_X0C*_x60 + E_Y0C*_x53;
    const double _x217 = -E_X0C*_x70 - E_Y0C*_x59;
    const double _x218 = -E_X0C*_x57 - E_X0C*_x74 + E_Y0C*_x56 + E_ZC + _x216*_x63 + _x217*_x77;
    const double _x219 = E_X0C*_x55;
    const double _x220 = -E_X0C*_x124 + E_Y0C*_x114 + E_YC + _x109*_x219 + _x118*_x216 + _x127*_x217;
    const double _x221 = -E_X0C*_x140 + E_XC + E_Y0C*_x131 + _x111*_x219 + _x134*_x216 + _x143*_x217;
    const double _x222 = -E_X0A*_x101 - E_X0A*_x85 + E_Y0A*_x84 + E_ZA + 120*_x101 + _x104*_x215 + 120*_x106 + _x107*_x218 + _x108*_x220 + _x129*_x221 + _x214*_x89 + 120*_x91;
    const double _x223 = -_x180;
    const double _x224 = E_X0A*_x83;
    const double _x225 = E_X0A*_x174*_x88 - E_XA - E_Y0A*_x158 - _x154*_x224 - _x163*_x214 - _x168*_x215 + _x169*_x220 - 120*_x171 - 120*_x175 - 120*_x177 + _x178*_x218 + _x179*_x221 + 120;
    const double _x226 = -_x211;
    const double _x227 = -E_X0A*_x206 + E_Y0A*_x191 + E_YA + _x156*_x224 + _x194*_x214 + _x199*_x215 + _x200*_x220 + 120*_x202 + 120*_x206 + 120*_x208 + _x209*_x218 + _x210*_x221;
    const double _x228 = -_x0*_x4 + _x12*_x15;
    const double _x229 = _x0*_x8 + _x12*_x147;
    const double _x230 = -_x0*_x181 + _x12*_x183;
    const double _x231 = _x16*_x17;
    const double _x232 = _x17*_x38;
    const double _x233 = _x231*_x26 + _x232*_x42 - _x27*_x37;
    const double _x234 = _x148*_x231 - _x150*_x27 + _x151*_x232;
    const double _x235 = _x184*_x231 - _x186*_x27 + _x187*_x232;
    const double _x236 = -_x102*_x64 - _x103*_x64;
    const double _x237 = _x236*_x88;
    const double _x238 = _x64*_x96 - _x64*_x99;
    const double _x239 = _x238*_x79*_x81;
    const double _x240 = -_x237 - _x239;
    const double _x241 = _x128*_x80;
    const double _x242 = -_x236*_x79 + _x238*_x81*_x88;
    const double _x243 = _x144*_x242 + _x238*_x241 + _x240*_x78;
    const double _x244 = _x172*_x64 - _x173*_x64;
    const double _x245 = -_x165*_x64 - _x167*_x64;
    const double _x246 = _x245*_x88;
    const double _x247 = _x244*_x81;
    const double _x248 = _x247*_x79;
    const double _x249 = _x246 + _x248;
    const double _x250 = _x245*_x79 - _x247*_x88;
    const double _x251 = _x144*_x250 - _x241*_x244 + _x249*_x78;
    const double _x252 = _x203*_x64 - _x204*_x64;
    const double _x253 = -_x196*_x64 - _x198*_x64;
    const double _x254 = _x253*_x88;
    const double _x255 = _x252*_x79*_x81;
    const double _x256 = -_x254 - _x255;
    const double _x257 = _x252*_x81*_x88 - _x253*_x79;
    const double _x258 = _x144*_x257 + _x241*_x252 + _x256*_x78;
    const double _x259 = _x220*_x80;
    const double _x260 = -E_X0A*_x237 + _x215*_x238 + _x218*_x240 + _x221*_x242 + 120*_x237 + _x238*_x259 + 120*_x239;
    const double _x261 = E_X0A*_x245*_x88 - _x215*_x244 + _x218*_x249 + _x221*_x250 - _x244*_x259 - 120*_x246 - 120*_x248;
    const double _x262 = -E_X0A*_x254 + _x215*_x252 + _x218*_x256 + _x221*_x257 + _x252*_x259 + 120*_x254 + 120*_x255;
    const double _x263 = -_x125*_x64 - _x126*_x64;
    const double _x264 = _x263*_x62;
    const double _x265 = _x120*_x64 - _x122*_x64;
    const double _x266 = _x264 + _x265*_x70;
    const double _x267 = -_x64*_x75 - _x64*_x76;
    const double _x268 = _x267*_x62;
    const double _x269 = _x64*_x68 - _x64*_x72;
    const double _x270 = _x268 + _x269*_x70;
    const double _x271 = -_x141*_x64 - _x142*_x64;
    const double _x272 = _x271*_x62;
    const double _x273 = _x136*_x64 - _x138*_x64;
    const double _x274 = _x272 + _x273*_x70;
    const double _x275 = _x107*_x270 + _x108*_x266 + _x129*_x274;
    const double _x276 = _x169*_x266 + _x178*_x270 + _x179*_x274;
    const double _x277 = _x200*_x266 + _x209*_x270 + _x210*_x274;
    const double _x278 = -E_X0C*_x264 + _x217*_x265;
    const double _x279 = -E_X0C*_x268 + _x217*_x269;
    const double _x280 = -E_X0C*_x272 + _x217*_x273;
    const double _x281 = _x107*_x279 + _x108*_x278 + _x129*_x280;
    const double _x282 = _x169*_x278 + _x178*_x279 + _x179*_x280;
    const double _x283 = _x200*_x278 + _x209*_x279 + _x210*_x280;
    const double _x284 = -_x118*_x53 + _x127*_x59;
    const double _x285 = -_x53*_x63 + _x59*_x77;
    const double _x286 = -_x134*_x53 + _x143*_x59;
    const double _x287 = _x107*_x285 + _x108*_x284 + _x129*_x286;
    const double _x288 = _x169*_x284 + _x178*_x285 + _x179*_x286;
    const double _x289 = _x200*_x284 + _x209*_x285 + _x210*_x286;
    const double _x290 = -_x287;
    const double _x291 = -_x288;
    const double _x292 = -_x289;
    const double _x293 = _x284*_x80;
    const double _x294 = _x238*_x293 + _x240*_x285 + _x242*_x286;
    const double _x295 = -_x244*_x293 + _x249*_x285 + _x250*_x286;
    const double _x296 = _x252*_x293 + _x256*_x285 + _x257*_x286;
    const double _x297 = _x265*_x59;
    const double _x298 = _x269*_x59;
    const double _x299 = _x273*_x59;
    const double _x300 = _x107*_x298 + _x108*_x297 + _x129*_x299;
    const double _x301 = _x169*_x297 + _x178*_x298 + _x179*_x299;
    const double _x302 = _x200*_x297 + _x209*_x298 + _x210*_x299;
    const double _x303 = _x59*_x62;
    const double _x304 = _x53*_x62;
    const double _x305 = _x303*_x63 + _x304*_x77 - _x58*_x73;
    const double _x306 = _x118*_x303 - _x123*_x58 + _x127*_x304;
    const double _x307 = _x134*_x303 - _x139*_x58 + _x143*_x304;
    const double _x308 = _x107*_x305 + _x108*_x306 + _x129*_x307;
    const double _x309 = _x169*_x306 + _x178*_x305 + _x179*_x307;
    const double _x310 = _x200*_x306 + _x209*_x305 + _x210*_x307;
    const double _x311 = -_x308;
    const double _x312 = -_x309;
    const double _x313 = -_x310;
    const double _x314 = _x306*_x80;
    const double _x315 = _x238*_x314 + _x240*_x305 + _x242*_x307;
    const double _x316 = -_x244*_x314 + _x249*_x305 + _x250*_x307;
    const double _x317 = _x252*_x314 + _x256*_x305 + _x257*_x307;
    const double _x318 = -_x263*_x58 + _x265*_x53*_x62;
    const double _x319 = -_x267*_x58 + _x269*_x53*_x62;
    const double _x320 = -_x271*_x58 + _x273*_x53*_x62;
    const double _x321 = _x107*_x319 + _x108*_x318 + _x129*_x320;
    const double _x322 = _x169*_x318 + _x178*_x319 + _x179*_x320;
    const double _x323 = _x200*_x318 + _x209*_x319 + _x210*_x320;
    out[0] = _x145*_x52 + _x153*_x180 + _x189*_x211 + _x212*_x222 + _x223*_x225 + _x226*_x227;
    out[1] = _x145;
    out[2] = _x145*_x228 + _x180*_x229 + _x211*_x230;
    out[3] = _x145*_x233 + _x180*_x234 + _x211*_x235;
    out[4] = _x153*_x251 + _x189*_x258 + _x212*_x260 - _x222*_x243 + _x223*_x261 - _x225*_x251 + _x226*_x262 - _x227*_x258 + _x243*_x52;
    out[5] = _x153*_x276 + _x189*_x277 + _x212*_x281 - _x222*_x275 + _x223*_x282 - _x225*_x276 + _x226*_x283 - _x227*_x277 + _x275*_x52;
    out[6] = _x153*_x288 + _x189*_x289 + _x222*_x290 + _x225*_x291 + _x227*_x292 + _x287*_x52;
    out[7] = _x287;
    out[8] = _x228*_x287 + _x229*_x288 + _x230*_x289;
    out[9] = _x233*_x287 + _x234*_x288 + _x235*_x289;
    out[10] = _x153*_x295 + _x189*_x296 - _x222*_x294 - _x225*_x295 - _x227*_x296 + _x260*_x290 + _x261*_x291 + _x262*_x292 + _x294*_x52;
    out[11] = _x153*_x301 + _x189*_x302 - _x222*_x300 - _x225*_x301 - _x227*_x302 + _x281*_x290 + _x282*_x291 + _x283*_x292 + _x300*_x52;
    out[12] = _x153*_x309 + _x189*_x310 + _x222*_x311 + _x225*_x312 + _x227*_x313 + _x308*_x52;
    out[13] = _x308;
    out[14] = _x228*_x308 + _x229*_x309 + _x230*_x310;
    out[15] = _x233*_x308 + _x234*_x309 + _x235*_x310;
    out[16] = _x153*_x316 + _x189*_x317 - _x222*_x315 - _x225*_x316 - _x227*_x317 + _x260*_x311 + _x261*_x312 + _x262*_x313 + _x315*_x52;
    out[17] = _x153*_x322 + _x189*_x323 - _x222*_x321 - _x225*_x322 - _x227*_x323 + _x281*_x311 + _x282*_x312 + _x283*_x313 + _x321*_x52;
    out[18] = _x145*_x51 + _x152*_x180 + _x188*_x211;
    out[19] = 0;
    out[20] = 0;
    out[21] = 0;
    out[22] = _x152*_x251 + _x188*_x258 + _x243*_x51;
    out[23] = _x152*_x276 + _x188*_x277 + _x275*_x51;
    out[24] = _x152*_x288 + _x188*_x289 + _x287*_x51;
    out[25] = 0;
    out[26] = 0;
    out[27] = 0;
    out[28] = _x152*_x295 + _x188*_x296 + _x294*_x51;
    out[29] = _x152*_x301 + _x188*_x302 + _x300*_x51;
    out[30] = _x152*_x309 + _x188*_x310 + _x308*_x51;
    out[31] = 0;
    out[32] = 0;
    out[33] = 0;
    out[34] = _x152*_x316 + _x188*_x317 + _x315*_x51;
    out[35] = _x152*_x322 + _x188*_x323 + _x321*_x51;
}

/* First-order pose deviation jacobian_errors(axes) @ errors.
 * out: 6 x 1, row-major */
static void mtk_deviation_first_order(const double *axes, const double *errors, double tool_length, double *out)
{
    const double X = axes[0];
    const double Y = axes[1];
    const double Z = axes[2];
    const double A = axes[3];
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
    const double E_XA = errors[21];
    const double E_YA = errors[22];
    const double E_ZA = errors[23];
    const double E_AA = errors[24];
    const double E_BA = errors[25];
    const double E_CA = errors[26];
    const double E_XC = errors[27];
    const double E_YC = errors[28];
    const double E_ZC = errors[29];
    const double E_AC = errors[30];
    const double E_BC = errors[31];
    const double E_CC = errors[32];
    const double E_X0A = errors[33];
    const double E_Y0A = errors[34];
    const double E_A0A = errors[35];
    const double E_B0A = errors[36];
    const double E_X0C = errors[37];
    const double E_Y0C = errors[38];
    const double E_A0C = errors[39];
    const double E_B0C = errors[40];
    const double _x0 = (1.0/180.0)*MTK_PI;
    const double _x1 = C*_x0;
    const double _x2 = cos(_x1);
    const double _x3 = Z*_x2;
    const double _x4 = E_BZ*_x2;
    const double _x5 = Y*_x2;
    const double _x6 = Z - tool_length;
    const double _x7 = E_BX*_x2;
    const double _x8 = E_BY*_x2;
    const double _x9 = sin(_x1);
    const double _x10 = A*_x0;
    const double _x11 = sin(_x10);
    const double _x12 = _x11*_x9;
    const double _x13 = cos(_x10);
    const double _x14 = _x13*_x9;
    const double _x15 = Z*_x9;
    const double _x16 = _x13*_x15;
    const double _x17 = E_AZ*_x14;
    const double _x18 = -_x6;
    const double _x19 = _x14*_x18;
    const double _x20 = X*_x9;
    const double _x21 = pow(_x11, 2);
    const double _x22 = _x21*_x9;
    const double _x23 = pow(_x13, 2);
    const double _x24 = _x23*_x9;
    const double _x25 = Y*_x9;
    const double _x26 = _x11*_x25;
    const double _x27 = _x13 - 1;
    const double _x28 = -_x27;
    const double _x29 = pow(_x9, 2);
    const double _x30 = _x2 - 1;
    const double _x31 = -_x30;
    const double _x32 = _x2*_x31;
    const double _x33 = 120*_x13;
    const double _x34 = _x2*_x33;
    const double _x35 = _x11*_x20;
    const double _x36 = 120 - _x33;
    const double _x37 = _x2*_x36;
    const double _x38 = _x2*_x9;
    const double _x39 = 120*_x22;
    const double _x40 = -_x13*_x36*_x9 + _x16 + _x26;
    const double _x41 = -_x39 - _x40;
    const double _x42 = _x11*_x5;
    const double _x43 = _x2*_x21;
    const double _x44 = _x42 + 120*_x43;
    const double _x45 = _x13*_x3;
    const double _x46 = -_x13*_x37 + _x45;
    const double _x47 = _x44 + _x46;
    const double _x48 = -_x11*_x3 + _x11*_x37;
    const double _x49 = Y*_x11;
    const double _x50 = _x13*_x31;
    const double _x51 = 120*_x21;
    const double _x52 = 120*_x11;
    const double _x53 = _x2*_x52;
    const double _x54 = _x13*_x2;
    const double _x55 = _x11*_x2;
    const double _x56 = E_AZ*_x54;
    const double _x57 = X*_x2;
    const double _x58 = _x2*_x23;
    const double _x59 = _x11*_x13;
    const double _x60 = _x11*_x57;
    const double _x61 = _x36*_x9;
    const double _x62 = _x13*_x30;
    const double _x63 = -_x11*_x15 + _x11*_x61;
    const double _x64 = _x12*_x33 + _x13*_x25 + _x63;
    const double _x65 = _x52*_x9;
    const double _x66 = X*_x11;
    const double _x67 = E_AZ*_x11;
    const double _x68 = Z*_x11;
    const double _x69 = E_B0A*_x27;
    const double _x70 = _x11*_x18;
    const double _x71 = Y*_x13;
    const double _x72 = _x11*_x33;
    const double _x73 = _x11*_x36;
    const double _x74 = Z*_x11 - _x71 - _x72 - _x73;
    out[0] = E_A0A*(-_x20*_x27 + _x27*_x5 + _x27*_x53 + _x48 + _x53) + E_A0C*_x41 + E_A0Z*_x16 + E_AA*(-_x13*_x20 - _x5) + E_AC*_x41 + E_AX*(-_x19 + _x26) - E_AY*_x19 + E_B0A*(_x27*_x3 - _x27*_x37 + _x35 - _x37 + _x44) + E_B0C*(Z*_x50 + _x31*_x49 + _x31*_x51 - _x36*_x50) + E_B0Z*_x3 + E_BA*(-_x3 + _x34 + _x35 + _x37) - E_BC*_x47 - E_C0Y*_x5 + E_CA*(120*_x23*_x9 - _x40) + E_CC*(_x11*_x34 + _x13*_x5 + _x20 + _x48) - E_CX*_x5 + E_X0A*(_x11*_x13*_x9 - _x12*_x27) + E_X0C*(_x21*_x29 + _x23*_x29 - _x32) + E_XA*_x12 - E_XC*_x2 + E_XX*_x2 + E_XY*_x2 + E_XZ*_x2 + E_Y0A*(_x14*_x28 - _x22) + E_Y0C*(_x22*_x31 + _x24*_x31 + _x38) + E_YA*_x14 + E_YC*(_x22 + _x24) - E_YX*_x14 - E_YY*_x14 - E_YZ*_x14 - E_ZA*_x2 + E_ZX*_x12 + E_ZY*_x12 + E_ZZ*_x12 - _x17*tool_length - _x4*tool_length + _x6*_x7 + _x6*_x8;
    out[1] = E_A0A*(_x25*_x27 + _x27*_x57 + _x27*_x65 + _x63 + _x65) + E_A0C*(Z*_x62 + _x30*_x49 + _x30*_x51 - _x36*_x62) - E_A0Z*_x45 + E_AA*(_x13*_x57 - _x25) + E_AC*_x47 + E_AX*(_x13*_x18*_x2 - _x42) + E_AY*_x18*_x54 + E_B0A*(Z*_x27*_x9 + _x26 - _x27*_x61 + _x39 - _x60 - _x61) + E_B0C*_x41 + E_B0Z*_x15 + E_BA*(120*_x13*_x9 - _x15 - _x60 + _x61) + E_BC*_x41 + E_BX*_x6*_x9 + E_BY*_x6*_x9 - E_BZ*_x9*tool_length - E_C0Y*_x25 + E_CA*(_x42 + _x46 - 120*_x58) + E_CC*(-_x57 + _x64) - E_CX*_x25 + E_X0A*(-_x2*_x59 + _x27*_x55) + E_X0C*(-_x2*_x22 - _x23*_x38 - _x31*_x9) - E_XA*_x55 - E_XC*_x9 + E_XX*_x9 + E_XY*_x9 + E_XZ*_x9 + E_Y0A*(-_x28*_x54 + _x43) + E_Y0C*(-_x21*_x32 - _x23*_x32 + _x29) - E_YA*_x54 + E_YC*(-_x43 - _x58) + E_YX*_x54 + E_YY*_x54 + E_YZ*_x54 - E_ZA*_x9 - E_ZX*_x55 - E_ZY*_x55 - E_ZZ*_x55 + _x56*tool_length;
    out[2] = E_A0A*_x66 + E_A0C*(_x20 - _x30*_x68 + _x30*_x71 + _x30*_x72 + _x30*_x73) - E_A0Z*_x68 + E_AA*_x66 + E_AC*_x74 + E_AX*(_x70 + _x71) + E_AY*_x70 + E_B0C*(X*_x31 + _x64) + E_BA*X*_x13 + E_BC*X + E_CA*_x74 + E_X0A*(-_x13*_x27 - _x21) + E_XA*_x13 + E_Y0A*(-_x11*_x28 - _x59) - E_YA*_x11 + E_YX*_x11 + E_YY*_x11 + E_YZ*_x11 + E_ZC*(-_x21 - _x23) + E_ZX*_x13 + E_ZY*_x13 + E_ZZ*_x13 + X*_x69 + _x67*tool_length;
    out[3] = -E_A0A*_x55 - E_A0C*_x14 - E_AC*_x14 + E_AX*_x14 + E_AY*_x14 + E_B0C*_x50 - E_BA*_x2 - E_BC*_x54 - E_CA*_x14 - E_CC*_x55 + _x17 + _x2*_x69 + _x4 + _x7 + _x8;
    out[4] = -E_A0A*_x12 + E_A0C*_x13*_x30 + E_AC*_x13*_x2 - E_AX*_x54 - E_AY*_x54 + E_B0A*_x27*_x9 - E_B0C*_x14 - E_BA*_x9 - E_BC*_x14 + E_BX*_x9 + E_BY*_x9 + E_BZ*_x9 + E_CA*_x13*_x2 - E_CC*_x12 - _x56;
    out[5] = -E_A0C*_x11*_x30 + E_AC*_x11 - E_AX*_x11 - E_AY*_x11 - E_B0C*_x12 + E_CA*_x11 - _x67;
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
