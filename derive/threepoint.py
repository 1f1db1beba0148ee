"""Three-point identification of the six error motions of one axis (Zhang & Hu; thesis eqs. 31-37, 3.5-3.8).

Three reflectors P, Q, K are fixed to the moving part of an axis (spindle for linear axes, table for rotary
axes).  In the frame F in which the axis' error motion M = Trans(E_X, E_Y, E_Z) Rot(E_A, E_B, E_C) acts
(derive/kinematics.py: a linear axis' frame after its nominal translation, a rotary axis' stator frame, B tilted
45 degrees on the DMU 50), a point at p (nominal, in F) is displaced to first order by

    delta = E + w x p = [I3 | -[p]x] e,    e = (E_X, E_Y, E_Z, E_A, E_B, E_C),

so three points give nine equations in six unknowns (eq. 31 / 3.5).  Emitted here:

* ``rigid_point``: the exact small rigid motion M p of a point (M = Trans(E) Rot(E_A, E_B, E_C)); the joint fit
  uses it for each tracker station's alignment correction (a rigid motion of the whole station's readings, whose
  derivative at zero is ``point_rows``) and the simulator for each station's alignment error;
* ``point_rows`` / ``design_matrix``: the 3 x 6 block of one point and the 9 x 6 system of P, Q, K, taken as the
  exact derivative of M p at e = 0 (not typed in);
* ``solve_selected``: the closed-form solution of the six equations Zhang & Hu select (P_x, P_y, Q_x, Q_z, K_y, K_z;
  eqs. 32-34, 3.6-3.8), and ``selected_denominator`` N of eq. 34 (zero: the selection is singular);
* ``ls_solve`` / ``ls_residuals``: the least-squares solution of all nine equations in a numerically stable closed
  form: with the centroid c of the points and r_i = p_i - c, the columns of [I | -[r_i]x] are orthogonal in
  blocks (asserted), so E' = mean(delta_i), w = J^-1 sum r_i x (delta_i - mean delta), J = sum(|r|^2 I - r r^T)
  (the points' inertia tensor, 3 x 3), E = E' - w x c;
* ``point_shape``: 32 det(J) / tr(J)^3 in [0, 1] (1: equilateral triangle, 0: collinear points, w unobservable);
* ``frame_<machine>_<axis>``: the frame F of each axis of each machine spec as [R | o] (3 x 4) in the machine
  (base) frame at the given axis positions, so a runtime can take machine-frame readings into F.

Units: points and deltas in mm; errors in mm and rad.
"""
from __future__ import annotations

import sympy as sp

from .codegen import Arg, Function, Module, symbols
from .kinematics import Chain, htm, rot_small
from .spec import ROTATIONS, TOOL_LENGTH, TRANSLATIONS, all_specs

POINTS = ("P", "Q", "K")
SELECTED = (("P", 0), ("P", 1), ("Q", 0), ("Q", 2), ("K", 1), ("K", 2))  # Zhang & Hu (eq. 32): (point, x/y/z)
ERROR_PARTS = tuple(f"E_{c}" for c in TRANSLATIONS + ROTATIONS)  # + axis name -> ISO name


def rigid_moved(p: sp.Matrix, e) -> sp.Matrix:
    """M p exactly, M = Trans(e[:3]) Rot(e[3], e[4], e[5]) (the error-motion model of derive/kinematics.py)."""
    return (htm(rot_small(*e[3:]), e[:3]) * sp.Matrix([*p, 1]))[:3, 0]


def rigid_rows(p: sp.Matrix) -> sp.Matrix:
    """d (M p) / d e at e = 0, M = Trans(E) Rot(E_A, E_B, E_C) (exact model of derive/kinematics.py)."""
    e = symbols([f"_e{i}" for i in range(6)])
    return rigid_moved(p, e).jacobian(e).subs({s: 0 for s in e})


def _skew(v: sp.Matrix) -> sp.Matrix:
    return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def _frames(progress, sides: dict) -> list[Function]:
    """F of every axis of every machine: the frame in which that axis' error motion acts (3 x 4 [R | o]);
    ``sides`` is filled with machine_axis -> "tool" / "table" (which generated *_point function moves)."""
    fns = []
    for spec in all_specs():
        ch = Chain(spec)
        for side in ("tool_chain", "table_chain"):
            els = getattr(spec, side)
            for k, el in enumerate(els):
                if "joint" not in el:
                    continue
                name = el["joint"]
                f = ch.chain(side, {}, upto=k)
                if spec.axis(name).kind == "linear":
                    n = sp.Matrix(el.get("direction", [0, 0, 1]))
                    f = f * htm(trans=el.get("sign", 1) * ch.qs[name] * n)
                f = f.subs(TOOL_LENGTH, 0)
                what = "after its nominal translation" if spec.axis(name).kind == "linear" else "(stator frame)"
                sides[f"{spec.name}_{name}"] = "tool" if side == "tool_chain" else "table"
                fns.append(Function(
                    f"frame_{spec.name}_{name}", (Arg("axes", ch.q, "axis positions: linear mm, rotary deg"),),
                    f[:3, :4],
                    f"{spec.name}: frame of axis {name} {what} in which its error motion acts, as [R | o] "
                    f"(rotation, origin in mm) in the machine frame; {'tool' if side == 'tool_chain' else 'table'} "
                    f"side, tool_length = 0."))
        progress(f"frames of {spec.name}")
    return fns


def derive_threepoint(progress=lambda msg: None) -> Module:
    pts = {n: sp.Matrix(symbols([f"{c}{n}" for c in "xyz"])) for n in POINTS}
    dls = {n: sp.Matrix(symbols([f"d{c}{n}" for c in "xyz"])) for n in POINTS}
    p_one = sp.Matrix(symbols(["px", "py", "pz"]))
    points_arg = Arg("points", tuple(s for n in POINTS for s in pts[n]),
                     "nominal points P, Q, K in the axis frame F, mm")
    deltas_arg = Arg("deltas", tuple(s for n in POINTS for s in dls[n]),
                     "measured minus nominal position of P, Q, K, expressed in F, mm")

    progress("point rows and 9 x 6 system")
    rows1 = rigid_rows(p_one)
    assert rows1 == sp.Matrix.hstack(sp.eye(3), -_skew(p_one)), "rigid rows are not [I | -[p]x]"
    a9 = sp.Matrix.vstack(*[rows1.subs(dict(zip(p_one, pts[n])), simultaneous=True) for n in POINTS])
    d9 = sp.Matrix.vstack(*[dls[n] for n in POINTS])

    progress("closed form of the six selected equations (Zhang & Hu)")
    idx = [3 * POINTS.index(n) + c for n, c in SELECTED]
    a6 = a9.extract(idx, list(range(6)))
    b6 = d9.extract(idx, [0])
    det6 = sp.factor(a6.det())
    sel = (a6.adjugate() * b6).applyfunc(lambda e: sp.factor(sp.expand(e) / det6))
    assert (a6 * sel - b6).applyfunc(sp.cancel) == sp.zeros(6, 1), "closed form does not solve the selection"

    progress("centred least-squares closed form of the nine equations")
    c = sum((pts[n] for n in POINTS), sp.zeros(3, 1)) / 3
    r = {n: pts[n] - c for n in POINTS}
    ac = sp.Matrix.vstack(*[sp.Matrix.hstack(sp.eye(3), -_skew(r[n])) for n in POINTS])
    gram = (ac.T * ac).applyfunc(sp.expand)
    assert gram[:3, 3:] == sp.zeros(3, 3), "centred system is not block diagonal"
    # Built on placeholders (centred points u_i, centred deltas g_i, a generic 3 x 3 matrix for J) and only then
    # substituted, so nothing is expanded: the printed code keeps the centring that makes it stable.
    u = {n: sp.Matrix(symbols([f"_u{c_}{n}" for c_ in "xyz"])) for n in POINTS}
    g = {n: sp.Matrix(symbols([f"_g{c_}{n}" for c_ in "xyz"])) for n in POINTS}
    mj = sp.Matrix(3, 3, symbols([f"_j{i}{k}" for i in range(3) for k in range(3)]))
    inertia_u = sum((u[n].dot(u[n]) * sp.eye(3) - u[n] * u[n].T for n in POINTS), sp.zeros(3, 3))
    assert (gram[3:, 3:] - inertia_u.xreplace({s_: e_ for n in POINTS for s_, e_ in zip(u[n], r[n])})
            ).applyfunc(sp.expand) == sp.zeros(3, 3)
    rhs_u = sum((_skew(u[n]) * g[n] for n in POINTS), sp.zeros(3, 1))  # = sum u x g
    jdet_m = mj.det(method="berkowitz")
    w_m = mj.adjugate(method="berkowitz") * rhs_u / jdet_m
    dbar = sum((dls[n] for n in POINTS), sp.zeros(3, 1)) / 3
    to_j = dict(zip(mj, inertia_u))
    to_pts = {s_: e_ for n in POINTS for s_, e_ in list(zip(u[n], r[n])) + list(zip(g[n], dls[n] - dbar))}
    w = w_m.xreplace(to_j).xreplace(to_pts)
    jdet = jdet_m.xreplace(to_j).xreplace(to_pts)
    inertia = inertia_u.xreplace(to_pts)
    e_shift = dbar - _skew(w) * c  # E = E' - w x c
    ls = sp.Matrix.vstack(e_shift, w)
    resid = d9 - a9 * ls
    shape = 32 * jdet / inertia.trace() ** 3

    e6 = symbols([f"m{c}" for c in ("x", "y", "z", "a", "b", "c")])
    fns = [
        Function("rigid_point", (Arg("point", tuple(p_one), "point, mm"),
                                 Arg("motion", e6, "small rigid motion (tx, ty, tz mm; rotations about x, y, z rad)")),
                 rigid_moved(p_one, e6),
                 "The point moved exactly by Trans(t) Rz(c) Ry(b) Rx(a) (mm): a station's alignment correction or "
                 "error; its derivative at zero motion is point_rows.", vector_output=True),
        Function("point_rows", (Arg("point", tuple(p_one), "nominal point in the axis frame F, mm"),), rows1,
                 "d(displacement of the point) / d(E_X, E_Y, E_Z, E_A, E_B, E_C) in F: [I | -[p]x] (per mm, per rad)."),
        Function("design_matrix", (points_arg,), a9,
                 "The nine three-point equations (rows P_x, P_y, P_z, Q_x, ..., K_z; thesis eq. 31 / 3.5): "
                 "deltas = design_matrix @ (E_X, E_Y, E_Z, E_A, E_B, E_C)."),
        Function("solve_selected", (points_arg, deltas_arg), sel,
                 "Closed-form solution (E_X, E_Y, E_Z mm; E_A, E_B, E_C rad) of the six equations P_x, P_y, Q_x, Q_z, "
                 "K_y, K_z (Zhang & Hu; thesis eqs. 32-34); infinite/NaN where selected_denominator is zero.",
                 vector_output=True),
        Function("selected_denominator", (points_arg,), sp.Matrix([det6]),
                 "Determinant of the six selected equations (N of eq. 34 up to sign), mm^3.", vector_output=True),
        Function("ls_solve", (points_arg, deltas_arg), ls,
                 "Least-squares solution of all nine equations (E_X, E_Y, E_Z mm; E_A, E_B, E_C rad), centred closed "
                 "form (see module doc).", vector_output=True),
        Function("ls_residuals", (points_arg, deltas_arg), resid,
                 "Residuals (mm) deltas - design_matrix @ ls_solve of the nine equations (P_x ... K_z).",
                 vector_output=True),
        Function("point_shape", (points_arg,), sp.Matrix([shape]),
                 "32 det(J) / tr(J)^3 of the centred points' inertia tensor J: 1 for an equilateral triangle, "
                 "0 for collinear points (dimensionless).", vector_output=True),
    ]
    sides: dict[str, str] = {}
    fns += _frames(progress, sides)
    meta = {
        "POINTS": POINTS,
        "SELECTED_ROWS": tuple(f"{n}_{'xyz'[k]}" for n, k in SELECTED),
        "ERROR_PARTS": ERROR_PARTS,
        "FRAMES": {f.name[len("frame_"):]: f.name for f in fns if f.name.startswith("frame_")},
        "FRAME_SIDES": sides,
    }
    return Module("threepoint", "threepoint.py",
                  "Three-point identification of the six error motions of one axis (Zhang & Hu), from "
                  "derive/threepoint.py.", fns, meta)
