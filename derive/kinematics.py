"""Error-inclusive forward kinematics, its Jacobians and the closed-form inverse, derived from a chain spec.

Conventions (docs/design.md):
* axes: linear in mm, rotary in degrees (as in NC programs); every joint moves along / about its local z
  unless a linear joint states another direction;
* pose = [x, y, z, i, j, k]: tool tip and tool axis in the workpiece frame, T_w^t = (T_0^w)^-1 T_0^t;
* errors in mm and rad, ISO 230-1 names.  Exact model, rotation parametrisation
  Rot(a, b, c) = Rz(c) Ry(b) Rx(a) (rotations about the fixed x, then y, then z axis):
  - linear joint J:  Trans(J n_J) Trans(E_XJ, E_YJ, E_ZJ) Rot(E_AJ, E_BJ, E_CJ), with n_J the axis direction
    tilted by its squareness errors (e.g. n_Z = Ry(E_B0Z) Rx(E_A0Z) z);
  - rotary joint R, angle s*R about the stator z:  M_R  L_R Rz(s R) L_R^-1, with the error motion
    M_R = Trans(E_XR, E_YR, E_ZR) Rot(E_AR, E_BR, E_CR) applied after the rotation in the stator frame and the
    axis average line L_R = Trans(E_X0R, E_Y0R, 0) Ry(E_B0R) Rx(E_A0R) (identity at R = 0).
* first order: the exact Jacobian with respect to the errors at zero error (product rule on the chain,
  each error alone), not a hand truncation.
"""
from __future__ import annotations

import sympy as sp

from .codegen import Arg, Function, Module, symbols
from .spec import ROTATIONS, TOOL_LENGTH, TRANSLATIONS, Spec

DEG = sp.pi / 180


def _rot(axis: str, angle: sp.Expr) -> sp.Matrix:
    c, s = sp.cos(angle), sp.sin(angle)
    m = {"x": [[1, 0, 0], [0, c, -s], [0, s, c]],
         "y": [[c, 0, s], [0, 1, 0], [-s, 0, c]],
         "z": [[c, -s, 0], [s, c, 0], [0, 0, 1]]}[axis]
    return sp.Matrix(m)


def htm(rot: sp.Matrix | None = None, trans=(0, 0, 0)) -> sp.Matrix:
    t = sp.eye(4)
    if rot is not None:
        t[:3, :3] = rot
    t[:3, 3] = sp.Matrix(trans)
    return t


def rot_small(a, b, c) -> sp.Matrix:
    """Exact rotation for the three angular errors about x, y, z: Rz(c) Ry(b) Rx(a)."""
    return _rot("z", c) * _rot("y", b) * _rot("x", a)


def inverse_htm(t: sp.Matrix) -> sp.Matrix:
    r = t[:3, :3].T
    return htm(r, -r * t[:3, 3])


class Chain:
    """Builds both chains of a spec with the error symbols of ``err`` (missing names are zero)."""

    def __init__(self, spec: Spec):
        self.spec = spec
        self.q = symbols([a.name for a in spec.axes])
        self.qs = dict(zip([a.name for a in spec.axes], self.q))
        groups = spec.error_names()
        self.error_names = tuple(n for g in groups.values() for n in g)
        self.e = symbols(self.error_names)
        self.es = dict(zip(self.error_names, self.e))

    def _err(self, name: str, on: dict) -> sp.Expr:
        return on.get(name, 0)

    def _joint(self, el: dict, on: dict) -> sp.Matrix:
        name = el["joint"]
        q = self.qs[name]
        sign = el.get("sign", 1)
        if self.spec.axis(name).kind == "linear":
            n = sp.Matrix(el.get("direction", [0, 0, 1]))
            for sq, about in reversed(el.get("squareness", [])):
                n = _rot(about, self._err(sq, on)) * n
            e = [self._err(f"E_{c}{name}", on) for c in TRANSLATIONS + ROTATIONS]
            return htm(trans=sign * q * n) * htm(rot_small(*e[3:]), e[:3])
        e = [self._err(f"E_{c}{name}", on) for c in TRANSLATIONS + ROTATIONS]
        loc = [self._err(f"E_{c}0{name}", on) for c in ("X", "Y", "A", "B")]
        line = htm(_rot("y", loc[3]) * _rot("x", loc[2]), (loc[0], loc[1], 0))
        motion = htm(rot_small(*e[3:]), e[:3])
        return motion * line * htm(_rot("z", sign * q * DEG)) * inverse_htm(line)

    def _const(self, el: dict) -> sp.Matrix:
        op, v = el["op"], el["value"]
        if op[0] == "T":
            return htm(trans=[v if op[1] == ax else 0 for ax in "xyz"])
        return htm(_rot(op[1], v * DEG))

    def chain(self, side: str, on: dict, upto: int | None = None) -> sp.Matrix:
        els = getattr(self.spec, side)[:upto]
        t = sp.eye(4)
        for el in els:
            t = t * (self._joint(el, on) if "joint" in el else self._const(el))
        return t

    def point(self, side: str, on: dict, p: sp.Matrix) -> sp.Matrix:
        """Base-frame position of a point fixed to the tool carriage (p relative to the error reference point,
        tool_length = 0) or to the table (p in workpiece coordinates)."""
        t = self.chain(side, on).subs(TOOL_LENGTH, 0)
        return (t * sp.Matrix([*p, 1]))[:3, 0]

    def pose(self, on: dict) -> sp.Matrix:
        """[x, y, z, i, j, k] of the tool in the workpiece frame with the errors in ``on``."""
        t = inverse_htm(self.chain("table_chain", on)) * self.chain("tool_chain", on)
        return sp.Matrix([t[0, 3], t[1, 3], t[2, 3], t[0, 2], t[1, 2], t[2, 2]])


def _error_jacobian(ch: Chain) -> sp.Matrix:
    """d pose / d e at e = 0: each error alone in the chain, differentiated exactly, then set to zero."""
    cols = []
    for name, sym in zip(ch.error_names, ch.e):
        p = ch.pose({name: sym})
        cols.append(p.diff(sym).subs(sym, 0))
    return sp.Matrix.hstack(*cols)


def _point_functions(ch: Chain) -> list[Function]:
    """Where a reflector fixed to the spindle or the table is in the machine (base) frame: what a tracker sees."""
    p = sp.Matrix(symbols(["px", "py", "pz"]))
    fns = []
    for side, what in (("tool_chain", "tool"), ("table_chain", "table")):
        where = ("relative to the error reference point (spindle gauge point, tool_length = 0)" if what == "tool"
                 else "in workpiece (table) coordinates")
        p_arg = Arg("point", tuple(p), f"point fixed to the {what}, mm, {where}")
        exact = ch.point(side, ch.es, p)
        jac = sp.Matrix.hstack(*[ch.point(side, {n: s}, p).diff(s).subs(s, 0) for n, s in zip(ch.error_names, ch.e)])
        fns += [Function(f"{what}_point", (Arg("axes", ch.q, "axis positions: linear mm, rotary deg"),
                                           Arg("errors", ch.e, "error parameters, mm and rad"), p_arg), exact,
                         f"Machine-frame position (mm) of a point fixed to the {what}, exact error-inclusive.",
                         vector_output=True),
                Function(f"{what}_point_jacobian_errors", (Arg("axes", ch.q, "axis positions: linear mm, rotary deg"),
                                                           p_arg), jac,
                         f"d {what}_point / d errors at zero error (3 x n_errors), per mm and per rad.")]
    return fns


def _ik(ch: Chain, nominal_t0w: sp.Matrix) -> tuple[list[Function], dict]:
    """Closed-form inverse for a tilt axis (on the table or on the head) plus a rotary table (last table joint).

    With R_pre the table rotation before the rotary joint and R_tool(tilt) the head rotation, the tool axis seen
    from the rotary table is u(tilt) = R_pre^T R_tool z, and in the workpiece frame n = Rz(s C)^T u(tilt).  So
    k = u_z(tilt) = a + b cos(tilt) + c sin(tilt) (asserted) gives tilt = phi +/- acos((k - a)/rho) (the two IK
    branches); C is the angle that turns u onto n about z (free at the singularity u || z, k = a + rho); the
    linear axes follow from the tool tip = T_0^w(tilt, C) p_w.
    """
    spec = ch.spec
    ik = spec.ik
    if ik.get("kind") not in ("tilt_rotary", "table_tilt_rotary"):
        raise ValueError(f"{spec.path.name}: unsupported ik kind {ik.get('kind')!r}")
    tilt, rot = ch.qs[ik["tilt"]], ch.qs[ik["rotary"]]
    last = spec.table_chain[-1]
    if last.get("joint") != ik["rotary"]:
        raise ValueError(f"{spec.path.name}: ik needs the rotary table joint last in table_chain")
    zero: dict = {}
    tool_nom = ch.chain("tool_chain", zero)
    s = last.get("sign", 1)
    u = ch.chain("table_chain", zero, upto=-1)[:3, :3].T * tool_nom[:3, :3] * sp.Matrix([0, 0, 1])
    if u.free_symbols - {tilt}:
        raise ValueError(f"{spec.path.name}: the tool axis seen from the rotary table depends on "
                         f"{u.free_symbols - {tilt}}; ik needs it to depend on {ik['tilt']} only")
    uz = sp.simplify(u[2])
    at = {v: uz.subs(tilt, v) for v in (0, 90, 180)}
    a = sp.nsimplify((at[0] + at[180]) / 2)
    b = sp.nsimplify((at[0] - at[180]) / 2)
    c = sp.nsimplify(at[90] - a)
    assert sp.simplify(uz - (a + b * sp.cos(tilt * DEG) + c * sp.sin(tilt * DEG))) == 0, "k(tilt) not harmonic"
    rho, phi = sp.sqrt(b**2 + c**2), sp.atan2(c, b)
    k, i, j = symbols(["k", "i", "j"])
    # cos(B - phi) = (k - a)/rho.  Near k = 1 the acos loses B (k rounds to 1 for B < 1e-8 rad), so the sine
    # comes from the x, y components: 1 - ((k - a)/rho)^2 = (a + rho - k)(k - a + rho)/rho^2 and, when the
    # tilt reaches the C axis (a + rho = 1), 1 - k = (i^2 + j^2)/(1 + k) exactly for a unit vector.
    if sp.simplify(a + rho - 1) != 0:
        raise ValueError(f"{spec.path.name}: ik needs a tilt range that reaches k = 1 (a + rho = {a + rho})")
    sin_t = sp.sqrt((i**2 + j**2) / (1 + k) * (k - a + rho)) / rho
    branch = [(phi + sg * sp.atan2(sin_t, (k - a) / rho)) / DEG for sg in (1, -1)]
    ux, uy = sp.simplify(u[0]), sp.simplify(u[1])
    c_deg = -s * sp.atan2(ux * j - uy * i, ux * i + uy * j) / DEG
    x, y, z = symbols(["x", "y", "z"])
    tip = (nominal_t0w * sp.Matrix([x, y, z, 1]))[:3, 0]
    tool_pos = tool_nom[:3, 3]
    lin = [ch.qs[a_.name] for a_ in spec.axes if a_.kind == "linear"]
    sol = sp.solve(list(tool_pos - tip), lin, dict=True)
    if len(sol) != 1:
        raise ValueError(f"{spec.path.name}: linear axes not uniquely determined by the tool tip")
    linear = sp.Matrix([sp.simplify(sol[0][q]) for q in lin])
    k_range = (sp.simplify(a - rho), sp.simplify(a + rho))
    return [
        Function("ik_tilt", (Arg("n", (i, j, k), "unit tool axis in the workpiece frame"),),
                 sp.Matrix(branch),
                 f"Both candidate {ik['tilt']} angles (deg) for the tool axis: phi +/- t with cos t = (k - a)/rho "
                 f"(a = {a}, rho = {rho}, phi = {phi}); reachable k in [{k_range[0]}, {k_range[1]}].",
                 vector_output=True),
        Function("ik_rotary", (Arg("tilt", (tilt,), f"{ik['tilt']} angle, deg", vector=False),
                               Arg("ij", (i, j), "tool-axis x, y components in the workpiece frame")),
                 sp.Matrix([c_deg, sp.sqrt(ux**2 + uy**2)]),
                 f"[{ik['rotary']} in (-180, 180] deg, |u_xy|]: the {ik['rotary']} angle that turns the tilted tool "
                 f"axis onto (i, j), and sin of the angle between tool axis and {ik['rotary']} axis "
                 f"(0 at the singularity, where {ik['rotary']} is free).", vector_output=True),
        Function("ik_linear", (Arg("rot", (tilt, rot), f"[{ik['tilt']}, {ik['rotary']}] in deg"),
                               Arg("tip", (x, y, z), "tool tip in the workpiece frame, mm"),
                               Arg("tool_length", (TOOL_LENGTH,), "tool length below the error reference point, mm",
                                   vector=False)),
                 linear, "Linear axes (mm) that put the tool tip at `tip` for the given rotary angles and tool.",
                 vector_output=True),
    ], {"tilt_axis": ik["tilt"], "rotary_axis": ik["rotary"], "rotary_sign": int(s),
        "k_range": [float(k_range[0]), float(k_range[1])], "preferred_branch": int(ik.get("preferred_branch", 1)),
        "singular_k": float(a + rho), "phi_deg": float(phi / DEG),
        "branches": f"{ik['tilt']} = phi + t (branch +1) or phi - t (branch -1), cos t = (k - a)/rho; "
                    f"singular at k = {float(a + rho):g} (tool axis parallel to {ik['rotary']}, which is then free)",
        "tilt_side": spec.side(ik["tilt"])}


def _trig_reduce(ch: Chain, expr: sp.Expr) -> sp.Expr:
    """Canonical form of an expression polynomial in cos and sin of the rotary axes: with c, s symbols for
    cos(q DEG), sin(q DEG), the remainder modulo s^2 + c^2 - 1 (a Groebner basis: one pair per axis), back in
    cos and sin.  Cancels what a frame change leaves (cos^2 + sin^2) in seconds, where simplify takes minutes."""
    sub, back, rels, gens = {}, {}, [], []
    for a in ch.spec.axes:
        if a.kind == "rotary":
            q = ch.qs[a.name]
            c, s = sp.Symbol(f"_c_{a.name}"), sp.Symbol(f"_s_{a.name}")
            sub.update({sp.cos(q * DEG): c, sp.sin(q * DEG): s})
            back.update({c: sp.cos(q * DEG), s: sp.sin(q * DEG)})
            rels.append(s**2 + c**2 - 1)
            gens += [s, c]
    p = sp.expand(sp.expand_trig(expr).subs(sub))
    left = [f for f in p.atoms(sp.sin, sp.cos) if f.free_symbols & set(ch.q)]
    assert not left, f"trigonometric terms not in cos/sin(axis DEG): {left}"
    if p == 0 or not (p.free_symbols & set(gens)):
        return p
    _, r = sp.reduced(p, rels, *gens)
    return sp.factor_terms(sp.collect(sp.expand(r), gens)).subs(back)


def _correction_first_order(ch: Chain, jq_nom: sp.Matrix, je: sp.Matrix) -> sp.Matrix:
    """[linear-axis step (3), tool-axis deviation (3)], first order: the step -J_lin^-1 dev[:3] (J_lin = d tip /
    d linear axes, nominal) that cancels the tool-tip deviation dev = jacobian_errors @ errors, and dev[3:] turned
    into the machine (base) frame by the nominal table rotation (norm kept).  In the machine frame the coefficients
    reduce to lever arms and a few sines and cosines: about half the operations of deviation_first_order."""
    lin = [i for i, a in enumerate(ch.spec.axes) if a.kind == "linear"]
    red = lambda x: _trig_reduce(ch, x)  # noqa: E731
    jl = jq_nom[:3, lin].applyfunc(red)
    if (jl.T * jl).applyfunc(red) == sp.eye(3):
        jl_inv = jl.T  # orthonormal linear axes (a rotation): the inverse is the transpose
    else:
        jl_inv = jl.inv().applyfunc(sp.simplify)
    rot = ch.chain("table_chain", {})[:3, :3].applyfunc(red)  # workpiece -> base
    step = (-jl_inv * je[:3, :].applyfunc(red)).applyfunc(red)
    dev_o = (rot * je[3:, :].applyfunc(red)).applyfunc(red)
    e = sp.Matrix(ch.e)
    return sp.Matrix.vstack(step * e, dev_o * e)


def derive_machine(spec: Spec, progress=lambda msg: None) -> Module:
    ch = Chain(spec)
    ax_arg = Arg("axes", ch.q, "axis positions: linear mm, rotary deg")
    err_arg = Arg("errors", ch.e, "error parameters, mm and rad (ISO 230-1 names)")
    tl_arg = Arg("tool_length", (TOOL_LENGTH,), "tool length below the error reference point, mm", vector=False)

    progress("nominal forward kinematics")
    nominal = ch.pose({}).applyfunc(sp.simplify)
    jq_nom = nominal.jacobian(ch.q)
    progress("exact error-inclusive forward kinematics")
    exact = ch.pose(ch.es)
    progress("axis Jacobian of the error-inclusive pose")
    with_jac = sp.Matrix.hstack(exact, exact.jacobian(ch.q))
    progress(f"first-order error Jacobian (6 x {len(ch.e)})")
    je = _error_jacobian(ch)
    assert je.free_symbols <= set(ch.q) | {TOOL_LENGTH}
    dev1 = je * sp.Matrix(ch.e)
    progress("first-order correction of the linear axes (machine frame)")
    corr1 = _correction_first_order(ch, jq_nom, je)
    progress("inverse kinematics")
    ik_funcs, ik_meta = _ik(ch, ch.chain("table_chain", {}))

    groups = spec.error_names()
    names = [a.name for a in spec.axes]
    meta = {
        "MACHINE": spec.name,
        "TITLE": spec.title,
        "AXES": tuple(a.name for a in spec.axes),
        "AXIS_KINDS": tuple(a.kind for a in spec.axes),
        "AXIS_LIMITS": tuple(a.limits for a in spec.axes),
        "ERRORS": ch.error_names,
        "ERROR_GROUPS": {k: list(v) for k, v in groups.items()},
        "PARAMETERS": {k: str(v) for k, v in spec.parameters.items()},
        "AXIS_SIDES": {n: spec.side(n) for n in names},
        "POSITIONING_ERRORS": {n: spec.positioning_error(n) for n in names},
        "CAMPAIGN": spec.campaign,
        "IK": ik_meta,
        "POSE": ("x", "y", "z", "i", "j", "k"),
    }
    fns = [
        Function("forward", (ax_arg, tl_arg), nominal,
                 "Nominal pose [x, y, z (mm), i, j, k] of the tool in the workpiece frame.", vector_output=True),
        Function("jacobian_axes", (ax_arg, tl_arg), jq_nom,
                 "d pose / d axes of the nominal pose; columns per mm (linear) and per degree (rotary)."),
        Function("forward_errors", (ax_arg, err_arg, tl_arg), exact,
                 "Exact error-inclusive pose [x, y, z, i, j, k] (errors in mm, rad; see derive/kinematics.py).",
                 vector_output=True),
        Function("forward_errors_with_jacobian", (ax_arg, err_arg, tl_arg), with_jac,
                 "Column 0: exact error-inclusive pose; columns 1..: its partial derivatives with respect to the "
                 "axes at fixed error values (per mm, per degree)."),
        Function("jacobian_errors", (ax_arg, tl_arg), je,
                 "d pose / d errors at zero error (exact first-order sensitivity; per mm and per rad)."),
        Function("deviation_first_order", (ax_arg, err_arg, tl_arg), dev1,
                 "First-order pose deviation jacobian_errors(axes) @ errors.", vector_output=True),
        Function("correction_first_order", (ax_arg, err_arg, tl_arg), corr1,
                 "First order, for compensation: rows 0-2 the linear-axis step (mm) -J_lin^-1 dev[:3] that cancels "
                 "the tool-tip deviation dev = deviation_first_order (J_lin = d tip / d linear axes, nominal, so "
                 "|dev[:3]| = |J_lin step|); rows 3-5 the tool-axis deviation dev[3:] turned into the machine "
                 "(base) frame by the nominal table rotation (same norm).", vector_output=True),
    ] + _point_functions(ch) + ik_funcs
    return Module(spec.name, "kinematics.py", f"{spec.title}: kinematics generated from derive/machines/"
                  f"{spec.path.name}.", fns, meta)
