"""C99 for a controller's kinematics module (a LinuxCNC KINEMATICS_BOTH component, mtcal export --format
linuxcnc-kins): the machine's generated functions, an evaluator of the error model's functions and the
compensating inverse with its exact forward, in one file generated/<machine>_kins.c.

* The functions are ``C_FUNCTIONS`` of derive.kinematics, printed by SymPy's C99 printer over the same cse as the
  NumPy and CasADi modules (codegen.emit_c_functions): one source of the maths.
* The evaluator takes the model as data (``struct mtk_model``, written by mtcal.export.linuxcnc_kins from
  mtcal.model.errormodel.ErrorEvaluator's plan): tables piecewise linear with the end values held (a + s x per
  segment, constants folded in), harmonic series by the multiple-angle recurrence, polynomials by Horner in the
  position mapped to [-1, 1] after holding it within the table's range; the same definitions, step by step, as
  ErrorEvaluator (mtcal/model/errormodel.py) and mtcal.model.fits.
* ``mtk_inverse`` (world -> joints): mtcal.compensate.Compensator iterated to convergence.  Scope "position": the
  linear axes solve p(q, e(q)) = p_nominal(world) for the tool tip by Newton steps on the error-inclusive position
  and its axis Jacobian at fixed error values (the rotary axes as commanded).  Scope "full": Compensator's steps
  (the tilt and rotary axes first, by least squares on the tool-axis residual, blended near the singular pose by
  Compensator.weight and held within the tilt limits; then the linear axes).  -1 (the move refused) when a step is
  still above ``MTK_TOLERANCE_MM`` after ``max_iterations`` steps.  ``mtk_forward_kins`` (joints -> world) is its
  exact inverse: scope "position", the nominal axes whose nominal pose is the error-inclusive one (the nominal
  tool tip is affine in the linear axes, so one solve is exact); scope "full", fixed-point steps on the inverse.
  Under a tool length L the world is the tool tip plus L along the tool-length axis (LinuxCNC's G43:
  motion.tooloffset.z), joints likewise.
No allocation, no state between calls, no includes (the including file provides sin, cos, sqrt, fabs).
"""
from __future__ import annotations

from .codegen import Module, emit_c_functions

C_FUNCTIONS = ("forward", "jacobian_axes", "forward_errors", "forward_errors_with_jacobian", "deviation_first_order")
TOLERANCE_MM = 1e-10  # a Newton step below this ends the solve: what is left is ~1e-4 of it (the errors' slopes)

HEADER = """\
/* -----------------------------------------------------------------------------
 * GENERATED FILE - DO NOT EDIT.
 * Generator: python -m derive ({target}); source: derive/kins_c.py, derive/{source}
 * Target: C99 (a LinuxCNC kinematics component; mtcal export --format linuxcnc-kins).
 * Inputs (machine spec, SymPy version, hash of derive/) are in manifest.json.
 * ---------------------------------------------------------------------------*/
"""

RUNTIME = r"""
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
"""


def tool_axis(spec) -> int:
    """Index of the linear axis that moves along the machine's z (the tool-length direction of G43)."""
    for el in spec.tool_chain + spec.table_chain:
        if "joint" in el and spec.axis(el["joint"]).kind == "linear" and list(el.get("direction", [0, 0, 1])) == [0, 0, 1]:
            return [a.name for a in spec.axes].index(el["joint"])
    raise ValueError(f"{spec.path.name}: no linear axis along z (the tool-length direction)")


def emit(mod: Module, target: str, spec) -> str:
    """generated/<machine>_kins.c: constants, the generated functions, the evaluator and the solver."""
    names = [a.name for a in spec.axes]
    lin = [i for i, a in enumerate(spec.axes) if a.kind == "linear"]
    tilt_lim = spec.axis(spec.ik["tilt"]).limits or (-1e300, 1e300)
    if len(lin) != 3:
        raise ValueError(f"{spec.path.name}: the C kinematics need three linear axes, got {len(lin)}")
    out = [HEADER.format(target=target, source=mod.source),
           f"/* {mod.doc.strip()} */\n",
           f"#define MTK_N_AXES {len(names)}\n",
           f"#define MTK_N_ERRORS {len(mod.metadata['ERRORS'])}\n",
           f"#define MTK_TOOL_AXIS {tool_axis(spec)} /* {names[tool_axis(spec)]} */\n",
           f"#define MTK_TOLERANCE_MM {TOLERANCE_MM!r}\n",
           f"#define MTK_TILT {names.index(spec.ik['tilt'])} /* {spec.ik['tilt']} */\n",
           f"#define MTK_ROTARY {names.index(spec.ik['rotary'])} /* {spec.ik['rotary']} */\n",
           f"#define MTK_TILT_LO {tilt_lim[0]!r}\n",
           f"#define MTK_TILT_HI {tilt_lim[1]!r}\n",
           "#define MTK_PI 3.141592653589793\n",
           f"static const char mtk_axes[] = \"{''.join(names)}\";\n",
           f"static const int mtk_linear[3] = {{{', '.join(map(str, lin))}}};\n"]
    fns = {f.name: f for f in mod.functions}
    out.append(emit_c_functions([fns[n] for n in C_FUNCTIONS], "mtk_"))
    out.append(RUNTIME)
    return "".join(out)
