"""Foundation (issue 2): generated kinematics vs the thesis closed form, inverse, CasADi, Jacobians, first order."""
from __future__ import annotations

from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mtcal
from mtcal.errors import InputError

MACHINES = sorted(p.stem for p in (Path(__file__).resolve().parent.parent / "derive" / "machines").glob("*.toml"))
D = 154.996  # mm, DMU 50 (docs/design.md)


def random_axes(m: mtcal.Machine, n: int, rng: np.random.Generator) -> np.ndarray:
    cols = []
    for kind, lim in zip(m.axis_kinds, m.limits):
        if kind == "linear":
            cols.append(rng.uniform(-300, 300, n))
        else:
            lo, hi = lim if lim else (-400.0, 400.0)
            cols.append(rng.uniform(lo, hi, n))
    return np.column_stack(cols)


def random_errors(m: mtcal.Machine, n: int, rng: np.random.Generator, scale: float = 1.0) -> np.ndarray:
    """Errors of the thesis' magnitudes: translations ~20 um, angles ~50 urad (times ``scale``)."""
    mag = np.array([50e-6 if name[2] in "ABC" else 0.02 for name in m.error_names])
    return rng.normal(size=(n, len(m.error_names))) * mag * scale


def thesis_forward(ax: np.ndarray) -> np.ndarray:
    """Thesis eqs. 3.19-3.24 (Sørby's closed form), typed in independently of derive/."""
    X, Y, Z, B, C = ax.T
    b, c = np.radians(B), np.radians(C)
    sB, cB, sC, cC = np.sin(b), np.cos(b), np.sin(c), np.cos(c)
    r2 = np.sqrt(2)
    i = 0.5 * (r2 * cC * sB - sC * cB + sC)
    j = 0.5 * (r2 * sC * sB + cC * cB - cC)
    k = 0.5 + 0.5 * cB
    x = r2 / 2 * (X * sC + (Y + Z - D) * cC) * sB + 0.5 * (-Y + Z - D - (Y + Z - D) * cB) * sC + X * cC * cB
    y = r2 / 2 * ((Y + Z - D) * sC - X * cC) * sB + X * sC * cB + 0.5 * ((Y + Z - D) * cC * cB + (Y - Z + D) * cC)
    z = 0.5 * (-r2 * X * sB + (Y + Z - D) * cB - Y + Z + D)
    return np.column_stack([x, y, z, i, j, k])


def thesis_inverse(pose: np.ndarray) -> np.ndarray:
    """Thesis eqs. 3.25-3.29."""
    x, y, z, i, j, k = pose.T
    s = np.sqrt(2 * (k - k**2))
    B = np.arccos(2 * k - 1)
    C = np.arctan2((1 - k) * i + s * j, s * i + (k - 1) * j)
    cC, sC = np.cos(C), np.sin(C)
    X = (-y * s - x + 2 * x * k) * cC + (x * s + 2 * y * k - y) * sC + (D - z) * s
    Y = (x * s + y * k) * cC + (y * s - x * k) * sC - z + D - D * k + z * k
    Z = (x * s + y * k - y) * cC + (y * s - x * k + x) * sC + D - D * k + z * k
    return np.column_stack([X, Y, Z, np.degrees(B), np.degrees(C)])


# ---------------------------------------------------------------------------- thesis closed form
def test_nominal_forward_equals_thesis_closed_form():
    m = mtcal.load_machine("dmu50")
    ax = random_axes(m, 2000, np.random.default_rng(1))
    err = np.abs(m.forward(ax) - thesis_forward(ax))
    assert err[:, :3].max() < 1e-9  # mm
    assert err[:, 3:].max() < 1e-12


def test_inverse_equals_thesis_closed_form_and_round_trips():
    m = mtcal.load_machine("dmu50")
    rng = np.random.default_rng(2)
    ax = random_axes(m, 2000, rng)
    ax[:, 3] = rng.uniform(1.0, 179.0, len(ax))
    ax[:, 4] = rng.uniform(-179.0, 179.0, len(ax))  # the thesis' atan2 gives C in (-180, 180]
    pose = m.forward(ax)
    ours = m.inverse(pose)
    assert np.abs(ours - thesis_inverse(pose)).max() < 1e-8
    assert np.abs(ours - ax).max() < 1e-8


@pytest.mark.parametrize("b", [0.0, 1e-9, 1e-6, 1e-3, 0.1, 179.9, 180.0])
def test_inverse_near_singularity(b):
    """B = 0: tool axis parallel to C, C is free and taken from the hint; FK(IK(pose)) = pose anyway."""
    m = mtcal.load_machine("dmu50")
    ax = np.array([[120.0, -80.0, 35.0, b, 37.0]])
    pose = m.forward(ax)
    back = m.inverse(pose, hint=[0, 0, 0, 0, 30.0])
    assert np.abs(m.forward(back) - pose).max() < 1e-9
    if b == 0.0:
        assert back[0, 4] == 30.0  # C kept from the hint at the singularity


def test_inverse_keeps_c_continuous_with_hint():
    m = mtcal.load_machine("dmu50")
    ax = np.array([[10.0, 20.0, 30.0, 45.0, 710.0]])
    back = m.inverse(m.forward(ax), hint=[0, 0, 0, 40, 700])
    assert back[0, 4] == pytest.approx(710.0, abs=1e-9)


def test_inverse_rejects_unreachable_and_bad_input():
    m = mtcal.load_machine("dmu50")
    with pytest.raises(InputError, match="unreachable"):
        m.inverse([0, 0, 0, 0, -0.6, -0.8])  # k < 0: below the horizon of the DMU 50
    with pytest.raises(InputError, match="unit vector"):
        m.inverse([0, 0, 0, 0, 0, 2.0])
    with pytest.raises(InputError, match="shape"):
        m.inverse([0, 0, 0, 1])
    with pytest.raises(InputError, match="NaN"):
        m.inverse([np.nan, 0, 0, 0, 0, 1])


# ---------------------------------------------------------------------------- head-table machine (headbc)
PIVOT = 150.0  # mm, headbc: B pivot above the spindle gauge point (derive/machines/headbc.toml)


def head_table_forward(ax: np.ndarray, tool_length: float = 0.0) -> np.ndarray:
    """Swivel head B about machine Y on X, Y, Z, C table turning the workpiece by -C, written here by hand:
    tool axis t = (sin B, 0, cos B); the pivot sits at (X, Y, Z + P + L) and the tip P + L below it along t;
    the workpiece frame sees base vectors turned by Rz(C)."""
    X, Y, Z, B, C = ax.T
    b, c = np.radians(B), np.radians(C)
    arm = PIVOT + tool_length
    tip = np.column_stack([X - arm * np.sin(b), Y, Z + arm * (1 - np.cos(b))])
    t = np.column_stack([np.sin(b), np.zeros_like(b), np.cos(b)])

    def rz(v):
        return np.column_stack([v[:, 0] * np.cos(c) - v[:, 1] * np.sin(c), v[:, 0] * np.sin(c) + v[:, 1] * np.cos(c),
                                v[:, 2]])
    return np.hstack([rz(tip), rz(t)])


def test_head_table_forward_equals_closed_form():
    m = mtcal.load_machine("headbc")
    ax = random_axes(m, 2000, np.random.default_rng(21))
    for tl in (0.0, 95.0):
        err = np.abs(m.forward(ax, tool_length=tl) - head_table_forward(ax, tl))
        assert err[:, :3].max() < 1e-9 and err[:, 3:].max() < 1e-12


@pytest.mark.parametrize("b", [0.0, 1e-9, 1e-6, 1e-3, -1e-3, -1e-6, 0.1, -45.0, 110.0, -110.0])
def test_head_table_inverse_through_singularity_and_both_branches(b):
    """B = 0: tool axis parallel to C (C free, taken from the hint).  B < 0 and B > 0 are the two branches:
    (B, C) and (-B, C + 180) give the same pose; the hint picks the branch, FK(IK(pose)) = pose either way."""
    m = mtcal.load_machine("headbc")
    assert m.ik_info["singular_k"] == 1.0 and m.ik_info["tilt_side"] == "tool"
    ax = np.array([[120.0, -80.0, 35.0, b, 37.0]])
    for tl in (0.0, 60.0):
        pose = m.forward(ax, tool_length=tl)
        assert np.abs(pose - head_table_forward(ax, tl)).max() < 1e-9
        default = m.inverse(pose, hint=[0, 0, 0, 0, 30.0], tool_length=tl)
        assert np.abs(m.forward(default, tool_length=tl) - pose).max() < 1e-9
        assert default[0, 3] >= 0.0  # preferred branch +1: B = +acos(k)
        if b == 0.0:
            assert default[0, 4] == 30.0
        elif b < 0:  # the other branch: C turned by 180 deg
            assert default[0, 3] == pytest.approx(-b, abs=1e-7)
            assert (default[0, 4] - 37.0) % 360 == pytest.approx(180.0, abs=1e-6)
        hinted = m.inverse(pose, hint=ax[0], tool_length=tl)  # the hint's branch comes back exactly
        if abs(b) > 1e-6:
            assert np.abs(hinted - ax).max() < 1e-7
        assert np.abs(m.forward(hinted, tool_length=tl) - pose).max() < 1e-9


# ---------------------------------------------------------------------------- generic, every machine
@pytest.mark.parametrize("name", MACHINES)
def test_forward_inverse_round_trip_generic(name):
    m = mtcal.load_machine(name)
    ax = random_axes(m, 500, np.random.default_rng(3))
    back = m.inverse(m.forward(ax), hint=ax)
    assert np.abs(m.forward(back) - m.forward(ax)).max() < 1e-9
    assert np.abs(back - ax).max() < 1e-8


@given(st.floats(-500, 500), st.floats(-500, 500), st.floats(-500, 500), st.floats(0, 180), st.floats(-720, 720))
@settings(max_examples=200, deadline=None)
def test_forward_inverse_property(x, y, z, b, c):
    m = mtcal.load_machine("dmu50")
    ax = np.array([x, y, z, b, c])
    pose = m.forward(ax)
    assert np.abs(m.forward(m.inverse(pose, hint=ax)) - pose).max() < 1e-9


@pytest.mark.parametrize("name", MACHINES)
def test_numpy_and_casadi_agree(name):
    """Every generated function: NumPy and CasADi evaluate the same expressions to 1e-12 relative."""
    m = mtcal.load_machine(name)
    rng = np.random.default_rng(4)
    ax = random_axes(m, 8, rng)
    e = random_errors(m, 8, rng)
    L, p = np.full(8, 120.0), np.tile([30.0, -40.0, 85.0], (8, 1))  # one row per evaluation
    args = {"forward": (ax, L), "jacobian_axes": (ax, L), "forward_errors": (ax, e, L),
            "forward_errors_with_jacobian": (ax, e, L), "jacobian_errors": (ax, L),
            "deviation_first_order": (ax, e, L), "correction_first_order": (ax, e, L),
            "tool_point": (ax, e, p), "table_point": (ax, e, p),
            "tool_point_jacobian_errors": (ax, p), "table_point_jacobian_errors": (ax, p),
            "ik_tilt": (m.forward(ax)[:, 3:],),
            "ik_rotary": (ax[:, 3], rng.normal(size=(8, 2))),
            "ik_linear": (ax[:, 3:], rng.normal(size=(8, 3)) * 100, L)}
    assert set(args) == set(m._np.FUNCTIONS) == set(m.casadi.FUNCTIONS)
    for fname, a in args.items():
        out_np = getattr(m._np, fname)(*a)
        f = getattr(m.casadi, fname)()
        for r in range(8):
            row = [x[r] for x in a]
            out_ca = np.array(f(*row)).reshape(np.shape(out_np[r]) or (1,))
            scale = max(1.0, np.abs(out_np[r]).max())
            assert np.abs(out_ca.reshape(np.shape(out_np[r])) - out_np[r]).max() <= 1e-12 * scale, fname


@pytest.mark.parametrize("name", MACHINES)
def test_axis_jacobians_against_central_differences(name):
    """Central differences: truncation ~ h^2 |f'''| / 6 and rounding ~ eps |f| / h.  With |f| <~ 1e3 mm,
    h = 1e-3 mm (or 1e-3 deg) gives rounding ~ 2e-10 and truncation ~ 1e-6 * |f'''| (|f'''| <~ 1e3 * (pi/180)^3
    per deg^3 ~ 5e-3), so 1e-7 absolute (mm/mm, mm/deg) is safe and still far below any real derivative."""
    m = mtcal.load_machine(name)
    rng = np.random.default_rng(5)
    ax = random_axes(m, 20, rng)
    for k, lim in enumerate(m.limits):  # central differences must stay inside the limits
        if lim:
            ax[:, k] = rng.uniform(lim[0] + 1, lim[1] - 1, 20)
    e = random_errors(m, 20, rng)
    h = 1e-3
    fd_nom, fd_err = np.zeros((20, 6, 5)), np.zeros((20, 6, 5))
    for k in range(5):
        dq = np.zeros(5)
        dq[k] = h
        fd_nom[:, :, k] = (m.forward(ax + dq, tool_length=80) - m.forward(ax - dq, tool_length=80)) / (2 * h)
        fd_err[:, :, k] = (m.forward(ax + dq, e, 80) - m.forward(ax - dq, e, 80)) / (2 * h)
    assert np.abs(m.jacobian_axes(ax, tool_length=80) - fd_nom).max() < 1e-7
    pose, jac = m.forward_with_jacobian(ax, e, 80)
    assert np.abs(jac - fd_err).max() < 1e-7
    assert np.abs(pose - m.forward(ax, e, 80)).max() < 1e-12


@pytest.mark.parametrize("name", MACHINES)
def test_error_jacobians_against_central_differences(name):
    """d pose / d e at e = 0 by central differences of the exact model.  h = 1e-6 (mm or rad): truncation
    ~ h^2 * |lever|^... <~ 1e-12 * 1e3 and rounding ~ 2e-16 * 1e3 / 1e-6 = 2e-7, so 1e-6 absolute per unit."""
    m = mtcal.load_machine(name)
    rng = np.random.default_rng(6)
    ax = random_axes(m, 10, rng)
    p = np.array([60.0, -25.0, 140.0])
    h, n = 1e-6, len(m.error_names)
    fd_pose, fd_tool, fd_table = np.zeros((10, 6, n)), np.zeros((10, 3, n)), np.zeros((10, 3, n))
    for k in range(n):
        de = np.zeros(n)
        de[k] = h
        fd_pose[:, :, k] = (m.forward(ax, de, 150) - m.forward(ax, -de, 150)) / (2 * h)
        fd_tool[:, :, k] = (m.points('tool', ax, p, de) - m.points('tool', ax, p, -de)) / (2 * h)
        fd_table[:, :, k] = (m.points('table', ax, p, de) - m.points('table', ax, p, -de)) / (2 * h)
    assert np.abs(m.jacobian_errors(ax, 150) - fd_pose).max() < 1e-6
    assert np.abs(m.point_jacobian_errors('tool', ax, p) - fd_tool).max() < 1e-6
    assert np.abs(m.point_jacobian_errors('table', ax, p) - fd_table).max() < 1e-6


@pytest.mark.parametrize("name", MACHINES)
def test_casadi_ad_jacobian_equals_symbolic(name):
    m = mtcal.load_machine(name)
    f = m.casadi.forward_errors()
    q, e, L = ca.SX.sym("q", 5), ca.SX.sym("e", len(m.error_names)), ca.SX.sym("L")
    out = f(q, e, L)
    jac = ca.Function("j", [q, e, L], [ca.jacobian(out, e), ca.jacobian(out, q)])
    rng = np.random.default_rng(7)
    for ax, err in zip(random_axes(m, 5, rng), random_errors(m, 5, rng)):
        je, jq = (np.array(v) for v in jac(ax, np.zeros(len(m.error_names)), 90.0))
        assert np.abs(je - m.jacobian_errors(ax, 90.0)).max() < 1e-11
        _, jq_err = (np.array(v) for v in jac(ax, err, 90.0))
        assert np.abs(jq_err - m.forward_with_jacobian(ax, err, 90.0)[1]).max() < 1e-10


@pytest.mark.parametrize("name", MACHINES)
def test_first_order_gap_is_second_order(name):
    """Halving all errors shrinks |exact - first order| about 4x: the linearisation is exact to first order."""
    m = mtcal.load_machine(name)
    rng = np.random.default_rng(8)
    ax, e = random_axes(m, 200, rng), random_errors(m, 200, rng, scale=20.0)
    gap = [np.abs(m.deviation(ax, s * e, order=None, tool_length=100) - m.deviation(ax, s * e, tool_length=100)).max()
           for s in (1.0, 0.5, 0.25)]
    assert 3.8 < gap[0] / gap[1] < 4.2 and 3.8 < gap[1] / gap[2] < 4.2
    first = np.abs(m.deviation(ax, e, tool_length=100)).max()
    assert gap[0] < 1e-2 * first  # the second-order remainder is small against the first-order deviation


# ---------------------------------------------------------------------------- conventions of docs/design.md
def test_error_conventions_of_design_notes():
    m = mtcal.load_machine("dmu50")
    dev = lambda ax, **e: m.deviation(np.array(ax, float), e, order=1)[:3]  # noqa: E731
    # squareness, right-hand: actual Y = (-E_C0Y, 1, 0), actual Z = (E_B0Z, -E_A0Z, 1)
    assert dev([0, 100, 0, 0, 0], E_C0Y=1e-4) == pytest.approx([-0.01, 0, 0], abs=1e-9)
    assert dev([0, 0, 100, 0, 0], E_B0Z=1e-4) == pytest.approx([0.01, 0, 0], abs=1e-9)
    assert dev([0, 0, 100, 0, 0], E_A0Z=1e-4) == pytest.approx([0, -0.01, 0], abs=1e-9)
    # linear axis: delta = E + omega x p; the tool tip sits tool_length below the reference point
    d = m.deviation([0, 0, 0, 0, 0], {"E_BZ": 1e-4, "E_AZ": 2e-4, "E_XZ": 0.003}, order=1, tool_length=100)[:3]
    assert d == pytest.approx([0.003 - 100 * 1e-4, 100 * 2e-4, 0], abs=1e-12)
    # rotary location errors move nothing at C = 0, and (I - Rz) (E_X0C, E_Y0C, 0) to first order elsewhere
    exact = m.deviation([0, 0, 0, 0, 0], {"E_X0C": 0.01, "E_Y0C": 0.02, "E_A0C": 1e-4}, order=None)
    assert np.abs(exact).max() < 1e-12
    assert np.linalg.norm(dev([0, 0, 0, 0, 90], E_X0C=0.01)) == pytest.approx(0.01 * np.sqrt(2), rel=1e-6)


def test_bad_input_names_the_problem():
    m = mtcal.load_machine("dmu50")
    with pytest.raises(InputError, match="outside its range"):
        m.forward([0, 0, 0, 190, 0])
    with pytest.raises(InputError, match="B = -1"):
        m.forward([[0, 0, 0, 10, 0], [0, 0, 0, -1, 0]])
    with pytest.raises(InputError, match="shape"):
        m.forward([0, 0, 0, 0])
    with pytest.raises(InputError, match="NaN"):
        m.forward([0, np.nan, 0, 0, 0])
    with pytest.raises(InputError, match="unknown error names"):
        m.forward([0, 0, 0, 0, 0], {"E_QQ": 1.0})
    with pytest.raises(InputError, match="order"):
        m.deviation([0, 0, 0, 0, 0], {}, order=2)
    with pytest.raises(InputError, match="unknown machine"):
        mtcal.load_machine("nope")


def test_broadcasting_of_leading_shapes():
    m = mtcal.load_machine("dmu50")
    ax = random_axes(m, 12, np.random.default_rng(9)).reshape(3, 4, 5)
    assert m.forward(ax).shape == (3, 4, 6)
    assert m.jacobian_errors(ax).shape == (3, 4, 6, 41)
    flat = m.forward(ax.reshape(12, 5), {"E_XX": 0.01})
    assert np.array_equal(m.forward(ax, {"E_XX": 0.01}).reshape(12, 6), flat)


@pytest.mark.parametrize("name", MACHINES)
def test_machine_geometry_api(name):
    """The public geometry API: rigid motions are rotations + translations that reproduce the reflector points;
    turning a rotary axis moves the points of its side about the z axis of its stator frame (axis_frame): the
    displacement is orthogonal to that axis and the distance from it is kept; facts of the spec."""
    m = mtcal.load_machine(name)
    rng = np.random.default_rng(31)
    ax = random_axes(m, 50, rng)
    for k, lim in enumerate(m.limits):
        if lim:
            ax[:, k] = rng.uniform(lim[0] + 2, lim[1] - 2, 50)
    local = rng.normal(size=(50, 3)) * 100
    for side in ("tool", "table"):
        b, rot = m.rigid_motion(side, ax)
        assert np.abs(rot @ np.swapaxes(rot, 1, 2) - np.eye(3)).max() < 1e-12
        assert np.abs(np.linalg.det(rot) - 1).max() < 1e-12
        assert np.abs(m.points(side, ax, local) - (b + np.einsum("nij,nj->ni", rot, local))).max() < 1e-9
    for a in m.rotary_axes:
        r_f, o = m.axis_frame(a, ax)
        z = r_f[..., 2]
        k = m.index(a)
        moved = ax.copy()
        moved[:, k] += 1.5
        p0, p1 = m.points(a, ax, local), m.points(a, moved, local)
        assert np.abs(np.einsum("ni,ni->n", p1 - p0, z)).max() < 1e-9  # in the plane normal to the axis
        dist = lambda p, o=o, z=z: np.linalg.norm(np.cross(p - o, z), axis=1)  # noqa: E731
        assert np.abs(dist(p1) - dist(p0)).max() < 1e-9
        assert np.abs(p1 - p0).max() > 0.1  # and it did move
    assert set(m.sides.values()) <= {"tool", "table"}
    assert m.sides[m.ik_info["rotary_axis"]] == "table"
    if name in ("headbc", "dmu50"):  # the head's B moves the spindle, the DMU 50's B the table
        assert m.sides["B"] == ("tool" if name == "headbc" else "table")
    assert all(m.positioning_errors[a] == f"E_C{a}" for a in m.rotary_axes)
