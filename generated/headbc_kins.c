/* -----------------------------------------------------------------------------
 * GENERATED FILE - DO NOT EDIT.
 * Generator: python -m derive (headbc); source: derive/kins_c.py, derive/kinematics.py
 * Target: C99 (a LinuxCNC kinematics component; mtcal export --format linuxcnc-kins).
 * Inputs (machine spec, SymPy version, hash of derive/) are in manifest.json.
 * ---------------------------------------------------------------------------*/
/* Head-table machine (XYZ, B swivel head about Y on the spindle side, C rotary table): kinematics generated from derive/machines/headbc.toml. */
#define MTK_N_AXES 5
#define MTK_N_ERRORS 41
#define MTK_TOOL_AXIS 2 /* Z */
#define MTK_TOLERANCE_MM 1e-10
#define MTK_TILT 3 /* B */
#define MTK_ROTARY 4 /* C */
#define MTK_TILT_LO -110.0
#define MTK_TILT_HI 110.0
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
    const double _x0 = (1.0/180.0)*MTK_PI;
    const double _x1 = C*_x0;
    const double _x2 = sin(_x1);
    const double _x3 = cos(_x1);
    const double _x4 = tool_length + 150;
    const double _x5 = B*_x0;
    const double _x6 = sin(_x5);
    const double _x7 = X - _x4*_x6;
    const double _x8 = cos(_x5);
    out[0] = -Y*_x2 + _x3*_x7;
    out[1] = Y*_x3 + _x2*_x7;
    out[2] = Z - _x4*_x8 + _x4;
    out[3] = _x3*_x6;
    out[4] = _x2*_x6;
    out[5] = _x8;
}

/* d pose / d axes of the nominal pose; columns per mm (linear) and per degree (rotary).
 * out: 6 x 5, row-major */
static void mtk_jacobian_axes(const double *axes, double tool_length, double *out)
{
    const double X = axes[0];
    const double Y = axes[1];
    const double B = axes[3];
    const double C = axes[4];
    const double _x0 = (1.0/180.0)*MTK_PI;
    const double _x1 = C*_x0;
    const double _x2 = cos(_x1);
    const double _x3 = sin(_x1);
    const double _x4 = tool_length + 150;
    const double _x5 = B*_x0;
    const double _x6 = _x0*cos(_x5);
    const double _x7 = _x2*_x6;
    const double _x8 = Y*_x0;
    const double _x9 = sin(_x5);
    const double _x10 = _x4*_x9;
    const double _x11 = X - _x10;
    const double _x12 = _x3*_x6;
    const double _x13 = _x0*_x9;
    out[0] = _x2;
    out[1] = -_x3;
    out[2] = 0;
    out[3] = -_x4*_x7;
    out[4] = -_x0*_x11*_x3 - _x2*_x8;
    out[5] = _x3;
    out[6] = _x2;
    out[7] = 0;
    out[8] = -_x12*_x4;
    out[9] = (1.0/180.0)*MTK_PI*_x11*_x2 - _x3*_x8;
    out[10] = 0;
    out[11] = 0;
    out[12] = 1;
    out[13] = _x0*_x10;
    out[14] = 0;
    out[15] = 0;
    out[16] = 0;
    out[17] = 0;
    out[18] = _x7;
    out[19] = -_x13*_x3;
    out[20] = 0;
    out[21] = 0;
    out[22] = 0;
    out[23] = _x12;
    out[24] = _x13*_x2;
    out[25] = 0;
    out[26] = 0;
    out[27] = 0;
    out[28] = -_x13;
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
    const double _x0 = sin(E_A0C);
    const double _x1 = sin(E_AC);
    const double _x2 = cos(E_BC);
    const double _x3 = _x1*_x2;
    const double _x4 = sin(E_BC);
    const double _x5 = sin(E_B0C);
    const double _x6 = cos(E_A0C);
    const double _x7 = _x5*_x6;
    const double _x8 = cos(E_AC);
    const double _x9 = cos(E_B0C);
    const double _x10 = -_x0*_x3 + _x2*_x6*_x8*_x9 - _x4*_x7;
    const double _x11 = (1.0/180.0)*MTK_PI;
    const double _x12 = C*_x11;
    const double _x13 = cos(_x12);
    const double _x14 = -_x2*_x5*_x8 - _x4*_x9;
    const double _x15 = sin(_x12);
    const double _x16 = _x0*_x5;
    const double _x17 = _x0*_x2*_x8*_x9 - _x16*_x4 + _x3*_x6;
    const double _x18 = _x13*_x14 - _x15*_x17;
    const double _x19 = _x18*_x9;
    const double _x20 = _x13*_x17 + _x14*_x15;
    const double _x21 = _x10*_x7 + _x16*_x20 + _x19;
    const double _x22 = -E_X0C*_x7 + E_Y0C*_x0;
    const double _x23 = -E_X0C*_x16 - E_Y0C*_x6;
    const double _x24 = -E_X0C*_x19 - E_X0C*_x4 + E_Y0C*_x3 + E_ZC + _x10*_x22 + _x20*_x23;
    const double _x25 = cos(E_CC);
    const double _x26 = _x2*_x25;
    const double _x27 = sin(E_CC);
    const double _x28 = _x1*_x25;
    const double _x29 = -_x27*_x8 + _x28*_x4;
    const double _x30 = _x1*_x27;
    const double _x31 = _x25*_x8;
    const double _x32 = _x30 + _x31*_x4;
    const double _x33 = _x32*_x9;
    const double _x34 = -_x0*_x29 + _x26*_x7 + _x33*_x6;
    const double _x35 = _x2*_x25*_x9 - _x32*_x5;
    const double _x36 = _x0*_x33 + _x16*_x26 + _x29*_x6;
    const double _x37 = _x13*_x35 - _x15*_x36;
    const double _x38 = _x37*_x9;
    const double _x39 = _x13*_x36 + _x15*_x35;
    const double _x40 = _x16*_x39 + _x34*_x7 + _x38;
    const double _x41 = E_X0C*_x2;
    const double _x42 = -E_X0C*_x38 + E_XC + E_Y0C*_x29 + _x22*_x34 + _x23*_x39 + _x25*_x41;
    const double _x43 = _x2*_x27;
    const double _x44 = _x30*_x4 + _x31;
    const double _x45 = _x27*_x4*_x8 - _x28;
    const double _x46 = _x45*_x9;
    const double _x47 = -_x0*_x44 + _x43*_x7 + _x46*_x6;
    const double _x48 = _x2*_x27*_x9 - _x45*_x5;
    const double _x49 = _x0*_x46 + _x16*_x43 + _x44*_x6;
    const double _x50 = _x13*_x48 - _x15*_x49;
    const double _x51 = _x50*_x9;
    const double _x52 = _x13*_x49 + _x15*_x48;
    const double _x53 = _x16*_x52 + _x47*_x7 + _x51;
    const double _x54 = -E_X0C*_x51 + E_Y0C*_x44 + E_YC + _x22*_x47 + _x23*_x52 + _x27*_x41;
    const double _x55 = tool_length + 150;
    const double _x56 = -_x55;
    const double _x57 = sin(E_A0B);
    const double _x58 = sin(E_AB);
    const double _x59 = cos(E_BB);
    const double _x60 = _x58*_x59;
    const double _x61 = cos(E_A0B);
    const double _x62 = sin(E_B0B);
    const double _x63 = sin(E_BB);
    const double _x64 = _x62*_x63;
    const double _x65 = cos(E_AB);
    const double _x66 = cos(E_B0B);
    const double _x67 = -_x57*_x60 + _x59*_x61*_x65*_x66 - _x61*_x64;
    const double _x68 = B*_x11;
    const double _x69 = sin(_x68);
    const double _x70 = _x59*_x62;
    const double _x71 = -_x63*_x66 - _x65*_x70;
    const double _x72 = cos(_x68);
    const double _x73 = _x57*_x59*_x65*_x66 - _x57*_x64 + _x60*_x61;
    const double _x74 = -_x69*_x71 + _x72*_x73;
    const double _x75 = -_x57*_x67 + _x61*_x74;
    const double _x76 = sin(E_CZ);
    const double _x77 = cos(E_AZ);
    const double _x78 = sin(E_BZ);
    const double _x79 = sin(E_AZ);
    const double _x80 = cos(E_CZ);
    const double _x81 = _x79*_x80;
    const double _x82 = -_x76*_x77 + _x78*_x81;
    const double _x83 = sin(E_BX);
    const double _x84 = cos(E_CY);
    const double _x85 = cos(E_BY);
    const double _x86 = _x84*_x85;
    const double _x87 = sin(E_BY);
    const double _x88 = cos(E_AX);
    const double _x89 = cos(E_BX);
    const double _x90 = _x88*_x89;
    const double _x91 = sin(E_AX);
    const double _x92 = sin(E_CY);
    const double _x93 = -_x83*_x86 + _x85*_x89*_x91*_x92 - _x87*_x90;
    const double _x94 = cos(E_AY);
    const double _x95 = _x85*_x90;
    const double _x96 = sin(E_AY);
    const double _x97 = _x92*_x96;
    const double _x98 = _x84*_x94;
    const double _x99 = _x87*_x98 + _x97;
    const double _x100 = _x84*_x96;
    const double _x101 = -_x100 + _x87*_x92*_x94;
    const double _x102 = _x89*_x91;
    const double _x103 = _x101*_x102 - _x83*_x99 + _x94*_x95;
    const double _x104 = cos(E_BZ);
    const double _x105 = _x103*_x104;
    const double _x106 = _x77*_x80;
    const double _x107 = _x76*_x79;
    const double _x108 = _x106 + _x107*_x78;
    const double _x109 = _x100*_x87 - _x92*_x94;
    const double _x110 = _x87*_x97 + _x98;
    const double _x111 = _x102*_x110 - _x109*_x83 + _x95*_x96;
    const double _x112 = _x105*_x79 + _x108*_x111 + _x82*_x93;
    const double _x113 = _x104*_x80;
    const double _x114 = _x104*_x76;
    const double _x115 = -_x103*_x78 + _x111*_x114 + _x113*_x93;
    const double _x116 = cos(E_CB);
    const double _x117 = _x116*_x70;
    const double _x118 = sin(E_CB);
    const double _x119 = _x116*_x58;
    const double _x120 = -_x118*_x65 + _x119*_x63;
    const double _x121 = _x118*_x58;
    const double _x122 = _x116*_x65;
    const double _x123 = _x121 + _x122*_x63;
    const double _x124 = _x123*_x66;
    const double _x125 = _x117*_x61 - _x120*_x57 + _x124*_x61;
    const double _x126 = _x116*_x59*_x66 - _x123*_x62;
    const double _x127 = _x117*_x57 + _x120*_x61 + _x124*_x57;
    const double _x128 = -_x126*_x69 + _x127*_x72;
    const double _x129 = -_x125*_x57 + _x128*_x61;
    const double _x130 = _x118*_x70;
    const double _x131 = _x121*_x63 + _x122;
    const double _x132 = _x118*_x63*_x65 - _x119;
    const double _x133 = _x132*_x66;
    const double _x134 = _x130*_x61 - _x131*_x57 + _x133*_x61;
    const double _x135 = _x118*_x59*_x66 - _x132*_x62;
    const double _x136 = _x130*_x57 + _x131*_x61 + _x133*_x57;
    const double _x137 = -_x135*_x69 + _x136*_x72;
    const double _x138 = -_x134*_x57 + _x137*_x61;
    const double _x139 = _x106*_x78 + _x107;
    const double _x140 = _x76*_x77*_x78 - _x81;
    const double _x141 = -_x105*_x77 - _x111*_x140 - _x139*_x93;
    const double _x142 = -_x112*_x75 - _x115*_x129 - _x138*_x141;
    const double _x143 = Z*cos(E_A0Z);
    const double _x144 = E_XZ + _x143*sin(E_B0Z);
    const double _x145 = E_YZ - Z*sin(E_A0Z);
    const double _x146 = E_ZZ + _x143*cos(E_B0Z);
    const double _x147 = E_X0B*_x62;
    const double _x148 = E_Y0B*_x57 - _x147*_x61;
    const double _x149 = E_X0B*_x66;
    const double _x150 = -E_Y0B*_x61 - _x147*_x57;
    const double _x151 = -E_X0B*_x63 + E_Y0B*_x60 + E_ZB + _x148*_x67 - _x149*(_x69*_x73 + _x71*_x72) + _x150*_x74;
    const double _x152 = E_X0B*_x59;
    const double _x153 = E_Y0B*_x131 + E_YB + _x118*_x152 + _x134*_x148 + _x137*_x150 - _x149*(_x135*_x72 + _x136*_x69);
    const double _x154 = E_XB + E_Y0B*_x120 + _x116*_x152 + _x125*_x148 + _x128*_x150 - _x149*(_x126*_x72 + _x127*_x69);
    const double _x155 = E_XY - Y*sin(E_C0Y);
    const double _x156 = E_YY + Y*cos(E_C0Y);
    const double _x157 = E_ZX + E_ZY*_x90 + _x102*_x156 + _x103*_x146 + _x111*_x145 + _x112*_x151 + _x115*_x154 + _x141*_x153 + _x142*_x56 + _x144*_x93 - _x155*_x83 + _x55;
    const double _x158 = cos(E_CX);
    const double _x159 = _x158*_x89;
    const double _x160 = sin(E_CX);
    const double _x161 = _x160*_x91;
    const double _x162 = _x158*_x88;
    const double _x163 = _x161 + _x162*_x83;
    const double _x164 = _x158*_x91;
    const double _x165 = -_x160*_x88 + _x164*_x83;
    const double _x166 = _x85*_x92;
    const double _x167 = _x159*_x86 - _x163*_x87 + _x165*_x166;
    const double _x168 = _x163*_x85;
    const double _x169 = _x109*_x159 + _x110*_x165 + _x168*_x96;
    const double _x170 = _x101*_x165 + _x159*_x99 + _x168*_x94;
    const double _x171 = _x104*_x170;
    const double _x172 = _x108*_x169 + _x167*_x82 + _x171*_x79;
    const double _x173 = _x113*_x167 + _x114*_x169 - _x170*_x78;
    const double _x174 = -_x139*_x167 - _x140*_x169 - _x171*_x77;
    const double _x175 = -_x129*_x173 - _x138*_x174 - _x172*_x75;
    const double _x176 = E_XX + E_ZY*_x163 + X + _x144*_x167 + _x145*_x169 + _x146*_x170 + _x151*_x172 + _x153*_x174 + _x154*_x173 + _x155*_x159 + _x156*_x165 + _x175*_x56;
    const double _x177 = _x160*_x89;
    const double _x178 = _x160*_x83*_x88 - _x164;
    const double _x179 = _x161*_x83 + _x162;
    const double _x180 = _x166*_x179 + _x177*_x86 - _x178*_x87;
    const double _x181 = _x178*_x85;
    const double _x182 = _x109*_x177 + _x110*_x179 + _x181*_x96;
    const double _x183 = _x101*_x179 + _x177*_x99 + _x181*_x94;
    const double _x184 = _x104*_x183;
    const double _x185 = _x108*_x182 + _x180*_x82 + _x184*_x79;
    const double _x186 = _x113*_x180 + _x114*_x182 - _x183*_x78;
    const double _x187 = -_x139*_x180 - _x140*_x182 - _x184*_x77;
    const double _x188 = -_x129*_x186 - _x138*_x187 - _x185*_x75;
    const double _x189 = E_YX + E_ZY*_x178 + _x144*_x180 + _x145*_x182 + _x146*_x183 + _x151*_x185 + _x153*_x187 + _x154*_x186 + _x155*_x177 + _x156*_x179 + _x188*_x56;
    const double _x190 = -_x0*_x10 + _x20*_x6;
    const double _x191 = -_x0*_x34 + _x39*_x6;
    const double _x192 = -_x0*_x47 + _x52*_x6;
    const double _x193 = _x6*_x9;
    const double _x194 = _x0*_x9;
    const double _x195 = _x10*_x193 - _x18*_x5 + _x194*_x20;
    const double _x196 = _x193*_x34 + _x194*_x39 - _x37*_x5;
    const double _x197 = _x193*_x47 + _x194*_x52 - _x5*_x50;
    out[0] = _x157*_x21 + _x176*_x40 + _x189*_x53 - _x21*_x24 - _x40*_x42 - _x53*_x54;
    out[1] = _x157*_x190 + _x176*_x191 + _x189*_x192 - _x190*_x24 - _x191*_x42 - _x192*_x54;
    out[2] = _x157*_x195 + _x176*_x196 + _x189*_x197 - _x195*_x24 - _x196*_x42 - _x197*_x54;
    out[3] = _x142*_x21 + _x175*_x40 + _x188*_x53;
    out[4] = _x142*_x190 + _x175*_x191 + _x188*_x192;
    out[5] = _x142*_x195 + _x175*_x196 + _x188*_x197;
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
    const double _x0 = sin(E_A0C);
    const double _x1 = sin(E_AC);
    const double _x2 = cos(E_BC);
    const double _x3 = _x1*_x2;
    const double _x4 = sin(E_BC);
    const double _x5 = sin(E_B0C);
    const double _x6 = cos(E_A0C);
    const double _x7 = _x5*_x6;
    const double _x8 = cos(E_AC);
    const double _x9 = cos(E_B0C);
    const double _x10 = -_x0*_x3 + _x2*_x6*_x8*_x9 - _x4*_x7;
    const double _x11 = (1.0/180.0)*MTK_PI;
    const double _x12 = C*_x11;
    const double _x13 = cos(_x12);
    const double _x14 = -_x2*_x5*_x8 - _x4*_x9;
    const double _x15 = _x13*_x14;
    const double _x16 = sin(_x12);
    const double _x17 = _x0*_x5;
    const double _x18 = _x0*_x2*_x8*_x9 - _x17*_x4 + _x3*_x6;
    const double _x19 = _x16*_x18;
    const double _x20 = _x15 - _x19;
    const double _x21 = _x20*_x9;
    const double _x22 = _x14*_x16;
    const double _x23 = _x13*_x18;
    const double _x24 = _x22 + _x23;
    const double _x25 = _x10*_x7 + _x17*_x24 + _x21;
    const double _x26 = -_x25;
    const double _x27 = -E_X0C*_x7 + E_Y0C*_x0;
    const double _x28 = -E_X0C*_x17 - E_Y0C*_x6;
    const double _x29 = -E_X0C*_x21 - E_X0C*_x4 + E_Y0C*_x3 + E_ZC + _x10*_x27 + _x24*_x28;
    const double _x30 = cos(E_CC);
    const double _x31 = _x2*_x30;
    const double _x32 = sin(E_CC);
    const double _x33 = _x1*_x30;
    const double _x34 = -_x32*_x8 + _x33*_x4;
    const double _x35 = _x1*_x32;
    const double _x36 = _x30*_x8;
    const double _x37 = _x35 + _x36*_x4;
    const double _x38 = _x37*_x9;
    const double _x39 = -_x0*_x34 + _x31*_x7 + _x38*_x6;
    const double _x40 = _x2*_x30*_x9 - _x37*_x5;
    const double _x41 = _x13*_x40;
    const double _x42 = _x0*_x38 + _x17*_x31 + _x34*_x6;
    const double _x43 = _x16*_x42;
    const double _x44 = _x41 - _x43;
    const double _x45 = _x44*_x9;
    const double _x46 = _x16*_x40;
    const double _x47 = _x13*_x42;
    const double _x48 = _x46 + _x47;
    const double _x49 = _x17*_x48 + _x39*_x7 + _x45;
    const double _x50 = -_x49;
    const double _x51 = E_X0C*_x2;
    const double _x52 = -E_X0C*_x45 + E_XC + E_Y0C*_x34 + _x27*_x39 + _x28*_x48 + _x30*_x51;
    const double _x53 = _x2*_x32;
    const double _x54 = _x35*_x4 + _x36;
    const double _x55 = _x32*_x4*_x8 - _x33;
    const double _x56 = _x55*_x9;
    const double _x57 = -_x0*_x54 + _x53*_x7 + _x56*_x6;
    const double _x58 = _x2*_x32*_x9 - _x5*_x55;
    const double _x59 = _x13*_x58;
    const double _x60 = _x0*_x56 + _x17*_x53 + _x54*_x6;
    const double _x61 = _x16*_x60;
    const double _x62 = _x59 - _x61;
    const double _x63 = _x62*_x9;
    const double _x64 = _x16*_x58;
    const double _x65 = _x13*_x60;
    const double _x66 = _x64 + _x65;
    const double _x67 = _x17*_x66 + _x57*_x7 + _x63;
    const double _x68 = -_x67;
    const double _x69 = -E_X0C*_x63 + E_Y0C*_x54 + E_YC + _x27*_x57 + _x28*_x66 + _x32*_x51;
    const double _x70 = tool_length + 150;
    const double _x71 = -_x70;
    const double _x72 = sin(E_A0B);
    const double _x73 = sin(E_AB);
    const double _x74 = cos(E_BB);
    const double _x75 = _x73*_x74;
    const double _x76 = cos(E_A0B);
    const double _x77 = sin(E_B0B);
    const double _x78 = sin(E_BB);
    const double _x79 = _x77*_x78;
    const double _x80 = cos(E_AB);
    const double _x81 = cos(E_B0B);
    const double _x82 = -_x72*_x75 + _x74*_x76*_x80*_x81 - _x76*_x79;
    const double _x83 = B*_x11;
    const double _x84 = sin(_x83);
    const double _x85 = _x74*_x77;
    const double _x86 = -_x78*_x81 - _x80*_x85;
    const double _x87 = _x84*_x86;
    const double _x88 = cos(_x83);
    const double _x89 = _x72*_x74*_x80*_x81 - _x72*_x79 + _x75*_x76;
    const double _x90 = -_x87 + _x88*_x89;
    const double _x91 = -_x72*_x82 + _x76*_x90;
    const double _x92 = sin(E_CZ);
    const double _x93 = cos(E_AZ);
    const double _x94 = sin(E_BZ);
    const double _x95 = sin(E_AZ);
    const double _x96 = cos(E_CZ);
    const double _x97 = _x95*_x96;
    const double _x98 = -_x92*_x93 + _x94*_x97;
    const double _x99 = sin(E_BX);
    const double _x100 = cos(E_CY);
    const double _x101 = cos(E_BY);
    const double _x102 = _x100*_x101;
    const double _x103 = sin(E_BY);
    const double _x104 = cos(E_AX);
    const double _x105 = cos(E_BX);
    const double _x106 = _x104*_x105;
    const double _x107 = sin(E_AX);
    const double _x108 = sin(E_CY);
    const double _x109 = _x101*_x105*_x107*_x108 - _x102*_x99 - _x103*_x106;
    const double _x110 = cos(E_AY);
    const double _x111 = _x101*_x106;
    const double _x112 = sin(E_AY);
    const double _x113 = _x108*_x112;
    const double _x114 = _x100*_x110;
    const double _x115 = _x103*_x114 + _x113;
    const double _x116 = _x100*_x112;
    const double _x117 = _x103*_x108*_x110 - _x116;
    const double _x118 = _x105*_x107;
    const double _x119 = _x110*_x111 - _x115*_x99 + _x117*_x118;
    const double _x120 = cos(E_BZ);
    const double _x121 = _x119*_x120;
    const double _x122 = _x93*_x96;
    const double _x123 = _x92*_x95;
    const double _x124 = _x122 + _x123*_x94;
    const double _x125 = _x103*_x116 - _x108*_x110;
    const double _x126 = _x103*_x113 + _x114;
    const double _x127 = _x111*_x112 + _x118*_x126 - _x125*_x99;
    const double _x128 = _x109*_x98 + _x121*_x95 + _x124*_x127;
    const double _x129 = _x120*_x96;
    const double _x130 = _x120*_x92;
    const double _x131 = _x109*_x129 - _x119*_x94 + _x127*_x130;
    const double _x132 = cos(E_CB);
    const double _x133 = _x132*_x85;
    const double _x134 = sin(E_CB);
    const double _x135 = _x132*_x73;
    const double _x136 = -_x134*_x80 + _x135*_x78;
    const double _x137 = _x134*_x73;
    const double _x138 = _x132*_x80;
    const double _x139 = _x137 + _x138*_x78;
    const double _x140 = _x139*_x81;
    const double _x141 = _x133*_x76 - _x136*_x72 + _x140*_x76;
    const double _x142 = _x132*_x74*_x81 - _x139*_x77;
    const double _x143 = _x142*_x84;
    const double _x144 = _x133*_x72 + _x136*_x76 + _x140*_x72;
    const double _x145 = -_x143 + _x144*_x88;
    const double _x146 = -_x141*_x72 + _x145*_x76;
    const double _x147 = _x134*_x85;
    const double _x148 = _x137*_x78 + _x138;
    const double _x149 = _x134*_x78*_x80 - _x135;
    const double _x150 = _x149*_x81;
    const double _x151 = _x147*_x76 - _x148*_x72 + _x150*_x76;
    const double _x152 = _x134*_x74*_x81 - _x149*_x77;
    const double _x153 = _x152*_x84;
    const double _x154 = _x147*_x72 + _x148*_x76 + _x150*_x72;
    const double _x155 = -_x153 + _x154*_x88;
    const double _x156 = -_x151*_x72 + _x155*_x76;
    const double _x157 = _x122*_x94 + _x123;
    const double _x158 = _x92*_x93*_x94 - _x97;
    const double _x159 = -_x109*_x157 - _x121*_x93 - _x127*_x158;
    const double _x160 = -_x128*_x91 - _x131*_x146 - _x156*_x159;
    const double _x161 = sin(E_B0Z);
    const double _x162 = cos(E_A0Z);
    const double _x163 = Z*_x162;
    const double _x164 = E_XZ + _x161*_x163;
    const double _x165 = sin(E_A0Z);
    const double _x166 = E_YZ - Z*_x165;
    const double _x167 = cos(E_B0Z);
    const double _x168 = E_ZZ + _x163*_x167;
    const double _x169 = E_X0B*_x77;
    const double _x170 = E_Y0B*_x72 - _x169*_x76;
    const double _x171 = _x86*_x88;
    const double _x172 = _x84*_x89;
    const double _x173 = E_X0B*_x81;
    const double _x174 = -E_Y0B*_x76 - _x169*_x72;
    const double _x175 = -E_X0B*_x78 + E_Y0B*_x75 + E_ZB + _x170*_x82 - _x173*(_x171 + _x172) + _x174*_x90;
    const double _x176 = E_X0B*_x74;
    const double _x177 = _x152*_x88;
    const double _x178 = _x154*_x84;
    const double _x179 = E_Y0B*_x148 + E_YB + _x134*_x176 + _x151*_x170 + _x155*_x174 - _x173*(_x177 + _x178);
    const double _x180 = _x142*_x88;
    const double _x181 = _x144*_x84;
    const double _x182 = E_XB + E_Y0B*_x136 + _x132*_x176 + _x141*_x170 + _x145*_x174 - _x173*(_x180 + _x181);
    const double _x183 = sin(E_C0Y);
    const double _x184 = E_XY - Y*_x183;
    const double _x185 = cos(E_C0Y);
    const double _x186 = E_YY + Y*_x185;
    const double _x187 = E_ZX + E_ZY*_x106 + _x109*_x164 + _x118*_x186 + _x119*_x168 + _x127*_x166 + _x128*_x175 + _x131*_x182 + _x159*_x179 + _x160*_x71 - _x184*_x99 + _x70;
    const double _x188 = cos(E_CX);
    const double _x189 = _x105*_x188;
    const double _x190 = sin(E_CX);
    const double _x191 = _x107*_x190;
    const double _x192 = _x104*_x188;
    const double _x193 = _x191 + _x192*_x99;
    const double _x194 = _x107*_x188;
    const double _x195 = -_x104*_x190 + _x194*_x99;
    const double _x196 = _x101*_x108;
    const double _x197 = _x102*_x189 - _x103*_x193 + _x195*_x196;
    const double _x198 = _x101*_x193;
    const double _x199 = _x112*_x198 + _x125*_x189 + _x126*_x195;
    const double _x200 = _x110*_x198 + _x115*_x189 + _x117*_x195;
    const double _x201 = _x120*_x200;
    const double _x202 = _x124*_x199 + _x197*_x98 + _x201*_x95;
    const double _x203 = _x129*_x197 + _x130*_x199 - _x200*_x94;
    const double _x204 = -_x157*_x197 - _x158*_x199 - _x201*_x93;
    const double _x205 = -_x146*_x203 - _x156*_x204 - _x202*_x91;
    const double _x206 = E_XX + E_ZY*_x193 + X + _x164*_x197 + _x166*_x199 + _x168*_x200 + _x175*_x202 + _x179*_x204 + _x182*_x203 + _x184*_x189 + _x186*_x195 + _x205*_x71;
    const double _x207 = _x105*_x190;
    const double _x208 = _x104*_x190*_x99 - _x194;
    const double _x209 = _x191*_x99 + _x192;
    const double _x210 = _x102*_x207 - _x103*_x208 + _x196*_x209;
    const double _x211 = _x101*_x208;
    const double _x212 = _x112*_x211 + _x125*_x207 + _x126*_x209;
    const double _x213 = _x110*_x211 + _x115*_x207 + _x117*_x209;
    const double _x214 = _x120*_x213;
    const double _x215 = _x124*_x212 + _x210*_x98 + _x214*_x95;
    const double _x216 = _x129*_x210 + _x130*_x212 - _x213*_x94;
    const double _x217 = -_x157*_x210 - _x158*_x212 - _x214*_x93;
    const double _x218 = -_x146*_x216 - _x156*_x217 - _x215*_x91;
    const double _x219 = E_YX + E_ZY*_x208 + _x164*_x210 + _x166*_x212 + _x168*_x213 + _x175*_x215 + _x179*_x217 + _x182*_x216 + _x184*_x207 + _x186*_x209 + _x218*_x71;
    const double _x220 = _x118*_x185 + _x183*_x99;
    const double _x221 = -_x183*_x189 + _x185*_x195;
    const double _x222 = -_x183*_x207 + _x185*_x209;
    const double _x223 = _x161*_x162;
    const double _x224 = _x162*_x167;
    const double _x225 = _x109*_x223 + _x119*_x224 - _x127*_x165;
    const double _x226 = -_x165*_x199 + _x197*_x223 + _x200*_x224;
    const double _x227 = -_x165*_x212 + _x210*_x223 + _x213*_x224;
    const double _x228 = -_x11*_x171 - _x11*_x172;
    const double _x229 = -_x173*(-_x11*_x87 + (1.0/180.0)*MTK_PI*_x88*_x89) + _x174*_x228;
    const double _x230 = -_x11*_x180 - _x11*_x181;
    const double _x231 = -_x173*(-_x11*_x143 + (1.0/180.0)*MTK_PI*_x144*_x88) + _x174*_x230;
    const double _x232 = -_x11*_x177 - _x11*_x178;
    const double _x233 = -_x173*(-_x11*_x153 + (1.0/180.0)*MTK_PI*_x154*_x88) + _x174*_x232;
    const double _x234 = _x228*_x76;
    const double _x235 = _x230*_x76;
    const double _x236 = _x232*_x76;
    const double _x237 = -_x128*_x234 - _x131*_x235 - _x159*_x236;
    const double _x238 = _x128*_x229 + _x131*_x231 + _x159*_x233 + _x237*_x71;
    const double _x239 = -_x202*_x234 - _x203*_x235 - _x204*_x236;
    const double _x240 = _x202*_x229 + _x203*_x231 + _x204*_x233 + _x239*_x71;
    const double _x241 = -_x215*_x234 - _x216*_x235 - _x217*_x236;
    const double _x242 = _x215*_x229 + _x216*_x231 + _x217*_x233 + _x241*_x71;
    const double _x243 = -_x11*_x22 - _x11*_x23;
    const double _x244 = _x243*_x9;
    const double _x245 = _x11*_x15 - _x11*_x19;
    const double _x246 = -E_X0C*_x244 + _x245*_x28;
    const double _x247 = _x17*_x245 + _x244;
    const double _x248 = -_x11*_x46 - _x11*_x47;
    const double _x249 = _x248*_x9;
    const double _x250 = _x11*_x41 - _x11*_x43;
    const double _x251 = -E_X0C*_x249 + _x250*_x28;
    const double _x252 = -_x11*_x64 - _x11*_x65;
    const double _x253 = _x252*_x9;
    const double _x254 = _x11*_x59 - _x11*_x61;
    const double _x255 = -E_X0C*_x253 + _x254*_x28;
    const double _x256 = _x17*_x250 + _x249;
    const double _x257 = _x17*_x254 + _x253;
    const double _x258 = -_x0*_x10 + _x24*_x6;
    const double _x259 = -_x258;
    const double _x260 = -_x0*_x39 + _x48*_x6;
    const double _x261 = -_x260;
    const double _x262 = -_x0*_x57 + _x6*_x66;
    const double _x263 = -_x262;
    const double _x264 = _x245*_x6;
    const double _x265 = _x250*_x6;
    const double _x266 = _x254*_x6;
    const double _x267 = _x6*_x9;
    const double _x268 = _x0*_x9;
    const double _x269 = _x10*_x267 - _x20*_x5 + _x24*_x268;
    const double _x270 = -_x269;
    const double _x271 = _x267*_x39 + _x268*_x48 - _x44*_x5;
    const double _x272 = -_x271;
    const double _x273 = _x267*_x57 + _x268*_x66 - _x5*_x62;
    const double _x274 = -_x273;
    const double _x275 = _x243*_x5 - _x245*_x268;
    const double _x276 = _x248*_x5 - _x250*_x268;
    const double _x277 = _x252*_x5 - _x254*_x268;
    const double _x278 = -_x275;
    const double _x279 = -_x276;
    const double _x280 = -_x277;
    out[0] = _x187*_x25 + _x206*_x49 + _x219*_x67 + _x26*_x29 + _x50*_x52 + _x68*_x69;
    out[1] = _x49;
    out[2] = _x220*_x25 + _x221*_x49 + _x222*_x67;
    out[3] = _x225*_x25 + _x226*_x49 + _x227*_x67;
    out[4] = _x238*_x25 + _x240*_x49 + _x242*_x67;
    out[5] = _x187*_x247 + _x206*_x256 + _x219*_x257 + _x246*_x26 - _x247*_x29 + _x251*_x50 + _x255*_x68 - _x256*_x52 - _x257*_x69;
    out[6] = _x187*_x258 + _x206*_x260 + _x219*_x262 + _x259*_x29 + _x261*_x52 + _x263*_x69;
    out[7] = _x260;
    out[8] = _x220*_x258 + _x221*_x260 + _x222*_x262;
    out[9] = _x225*_x258 + _x226*_x260 + _x227*_x262;
    out[10] = _x238*_x258 + _x240*_x260 + _x242*_x262;
    out[11] = _x187*_x264 + _x206*_x265 + _x219*_x266 + _x246*_x259 + _x251*_x261 + _x255*_x263 - _x264*_x29 - _x265*_x52 - _x266*_x69;
    out[12] = _x187*_x269 + _x206*_x271 + _x219*_x273 + _x270*_x29 + _x272*_x52 + _x274*_x69;
    out[13] = _x271;
    out[14] = _x220*_x269 + _x221*_x271 + _x222*_x273;
    out[15] = _x225*_x269 + _x226*_x271 + _x227*_x273;
    out[16] = _x238*_x269 + _x240*_x271 + _x242*_x273;
    out[17] = _x187*_x278 + _x206*_x279 + _x219*_x280 + _x246*_x270 + _x251*_x272 + _x255*_x274 + _x275*_x29 + _x276*_x52 + _x277*_x69;
    out[18] = _x160*_x25 + _x205*_x49 + _x218*_x67;
    out[19] = 0;
    out[20] = 0;
    out[21] = 0;
    out[22] = _x237*_x25 + _x239*_x49 + _x241*_x67;
    out[23] = _x160*_x247 + _x205*_x256 + _x218*_x257;
    out[24] = _x160*_x258 + _x205*_x260 + _x218*_x262;
    out[25] = 0;
    out[26] = 0;
    out[27] = 0;
    out[28] = _x237*_x258 + _x239*_x260 + _x241*_x262;
    out[29] = _x160*_x264 + _x205*_x265 + _x218*_x266;
    out[30] = _x160*_x269 + _x205*_x271 + _x218*_x273;
    out[31] = 0;
    out[32] = 0;
    out[33] = 0;
    out[34] = _x237*_x269 + _x239*_x271 + _x241*_x273;
    out[35] = _x160*_x278 + _x205*_x279 + _x218*_x280;
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
    const double _x0 = (1.0/180.0)*MTK_PI;
    const double _x1 = C*_x0;
    const double _x2 = cos(_x1);
    const double _x3 = sin(_x1);
    const double _x4 = Z*_x3;
    const double _x5 = Z*_x2;
    const double _x6 = Y*_x2;
    const double _x7 = B*_x0;
    const double _x8 = sin(_x7);
    const double _x9 = E_Y0B*_x8;
    const double _x10 = cos(_x7);
    const double _x11 = _x10 - 1;
    const double _x12 = -_x11;
    const double _x13 = E_X0B*_x12;
    const double _x14 = tool_length + 150;
    const double _x15 = -_x14;
    const double _x16 = _x10*_x15;
    const double _x17 = _x16*_x3;
    const double _x18 = _x15*_x8;
    const double _x19 = _x18*_x3;
    const double _x20 = _x16*_x2;
    const double _x21 = Z + _x16;
    const double _x22 = _x2*_x21;
    const double _x23 = E_A0B*_x12;
    const double _x24 = _x23*_x3;
    const double _x25 = _x14 + _x21;
    const double _x26 = _x25*_x3;
    const double _x27 = _x2*_x25;
    const double _x28 = -_x21;
    const double _x29 = _x28*_x3;
    const double _x30 = _x2 - 1;
    const double _x31 = -_x30;
    const double _x32 = -_x2*_x31 + pow(_x3, 2);
    const double _x33 = E_B0C*_x25;
    const double _x34 = X + _x18;
    const double _x35 = _x3*_x34;
    const double _x36 = _x2*_x3 + _x3*_x31;
    const double _x37 = Y*_x3;
    const double _x38 = _x18*_x2;
    const double _x39 = _x21*_x3;
    const double _x40 = _x2*_x23;
    const double _x41 = _x2*_x28;
    const double _x42 = E_A0C*_x30;
    const double _x43 = _x10*_x3;
    const double _x44 = _x3*_x8;
    const double _x45 = _x10*_x2;
    const double _x46 = _x2*_x8;
    out[0] = -E_A0C*_x26 + E_A0Z*_x4 + E_AB*_x17 - E_AC*_x26 - E_AX*_x29 - E_AY*_x29 + E_AZ*_x17 + E_B0B*_x19 + E_B0Z*_x5 + E_BB*_x19 - E_BC*_x27 + E_BX*_x22 + E_BY*_x22 + E_BZ*_x20 - E_C0Y*_x6 + E_CB*_x20 + E_CC*(_x35 + _x6) + E_CX*(-_x19 - _x6) - E_CY*_x19 - E_CZ*_x19 + E_X0C*_x32 + E_XB*_x2 - E_XC*_x2 + E_XX*_x2 + E_XY*_x2 + E_XZ*_x2 + E_Y0C*_x36 + E_YC*_x3 - E_YX*_x3 - E_YY*_x3 - E_YZ*_x3 - E_ZB*_x3 + _x13*_x2 - _x15*_x24 + _x2*_x9 + _x31*_x33;
    out[1] = -E_A0Z*_x5 - E_AB*_x20 + E_AC*_x27 + E_AX*_x41 + E_AY*_x41 - E_AZ*_x20 - E_B0B*_x38 + E_B0Z*_x4 - E_BB*_x38 - E_BC*_x26 + E_BX*_x39 + E_BY*_x39 + E_BZ*_x17 - E_C0Y*_x37 + E_CB*_x17 + E_CC*(-_x2*_x34 + _x37) + E_CX*(_x15*_x2*_x8 - _x37) + E_CY*_x38 + E_CZ*_x38 - E_X0C*_x36 + E_XB*_x3 - E_XC*_x3 + E_XX*_x3 + E_XY*_x3 + E_XZ*_x3 + E_Y0C*_x32 - E_YC*_x2 + E_YX*_x2 + E_YY*_x2 + E_YZ*_x2 + E_ZB*_x2 + _x13*_x3 + _x15*_x40 + _x25*_x42 - _x3*_x33 + _x3*_x9;
    out[2] = E_A0C*(Y*_x30 + _x35) - E_AC*Y + E_AX*Y + E_B0C*(_x31*_x34 + _x37) + E_BC*_x34 - E_BX*_x18 - E_BY*_x18 - E_BZ*_x18 - E_CB*_x18 + E_X0B*_x8 + E_Y0B*_x11 - E_YB - E_ZC + E_ZX + E_ZY + E_ZZ;
    out[3] = -E_A0C*_x43 + E_AB*_x43 - E_AC*_x43 + E_AX*_x43 + E_AY*_x43 + E_AZ*_x43 + E_B0B*_x44 + E_B0C*_x10*_x31 + E_BB*_x44 - E_BC*_x45 + E_BX*_x45 + E_BY*_x45 + E_BZ*_x45 + E_CB*_x45 + E_CC*_x44 - E_CX*_x44 - E_CY*_x44 - E_CZ*_x44 - _x24;
    out[4] = -E_AB*_x45 + E_AC*_x45 - E_AX*_x45 - E_AY*_x45 - E_AZ*_x45 - E_B0B*_x46 - E_B0C*_x43 - E_BB*_x46 - E_BC*_x43 + E_BX*_x43 + E_BY*_x43 + E_BZ*_x43 + E_CB*_x43 - E_CC*_x46 + E_CX*_x46 + E_CY*_x46 + E_CZ*_x46 + _x10*_x42 + _x40;
    out[5] = E_A0C*_x3*_x8 + E_B0C*_x31*_x8 + E_BC*_x8 - E_BX*_x8 - E_BY*_x8 - E_BZ*_x8 - E_CB*_x8;
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
