"""generated/threepoint_*: symbolic vs numeric, closed form = numeric solve = least squares, and the three-point
system against the machine's own error Jacobians and central finite differences of its exact kinematics."""
from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import mtcal
from mtcal.generated import threepoint_casadi as tpc
from mtcal.generated import threepoint_numpy as tp

RNG = np.random.default_rng(7)


def _points(n=1):
    """Random well-spread P, Q, K (mm), like reflectors on a spindle head or a table."""
    return RNG.uniform(-150, 150, (n, 3, 3)) + RNG.uniform(-400, 400, (n, 1, 3))


def _errors(n=1):
    return np.concatenate([RNG.normal(0, 0.01, (n, 3)), RNG.normal(0, 5e-5, (n, 3))], axis=1)


def _design(p):  # (n, 3, 3) -> (n, 9, 6), independent of the generated code: [I | -[p]x] per point
    out = np.zeros(p.shape[:-2] + (9, 6))
    for k in range(3):
        x, y, z = np.moveaxis(p[..., k, :], -1, 0)
        blk = out[..., 3 * k:3 * k + 3, :]
        blk[..., [0, 1, 2], [0, 1, 2]] = 1
        blk[..., 0, 4], blk[..., 0, 5] = z, -y
        blk[..., 1, 3], blk[..., 1, 5] = -z, x
        blk[..., 2, 3], blk[..., 2, 4] = y, -x
    return out


@pytest.fixture(scope="module")
def derived():
    from derive.threepoint import derive_threepoint
    return derive_threepoint()


@pytest.mark.slow
def test_generated_numpy_equals_sympy_expressions(derived):
    """Every generated function against SymPy's lambdify of the derivation's expressions (separate printer)."""
    for f in derived.functions:
        syms = [s for a in f.args for s in a.symbols]
        ref = sp.lambdify(syms, f.outputs, modules="numpy", cse=True)
        for _ in range(3):
            vals = []
            args = []
            for a in f.args:
                if a.name == "axes":
                    v = RNG.uniform(0, 180, len(a.symbols))
                elif a.name == "deltas":
                    v = RNG.normal(0, 0.01, len(a.symbols))
                else:
                    v = _points(1).ravel()[:len(a.symbols)]
                vals += list(v)
                args.append(v)
            expect = np.array(ref(*vals), dtype=float)
            got = getattr(tp, f.name)(*args)
            assert np.allclose(got.reshape(expect.shape), expect, rtol=1e-10, atol=1e-12), f.name


def test_casadi_equals_numpy():
    p, d = _points(1)[0].ravel(), RNG.normal(0, 0.01, 9)
    for name in ("ls_solve", "solve_selected", "ls_residuals"):
        got = np.array(getattr(tpc, name)()(p, d)).ravel()
        assert np.allclose(got, getattr(tp, name)(p, d), rtol=1e-12, atol=1e-15), name
    assert np.allclose(np.array(tpc.design_matrix()(p)), tp.design_matrix(p), atol=0)


def test_design_matrix_is_eq31():
    p = _points(5)
    assert np.array_equal(tp.design_matrix(p.reshape(5, 9)), _design(p))


def test_closed_form_equals_numeric_solve_equals_least_squares_on_exact_data():
    p, e = _points(200), _errors(200)
    a = _design(p)
    d = np.einsum("nij,nj->ni", a, e)
    pf = p.reshape(-1, 9)
    sel = tp.solve_selected(pf, d)
    rows = [0, 1, 3, 5, 7, 8]  # P_x, P_y, Q_x, Q_z, K_y, K_z
    numeric = np.linalg.solve(a[:, rows], d[:, rows][..., None])[..., 0]
    ls = tp.ls_solve(pf, d)
    for got in (sel, numeric, ls):
        assert np.allclose(got[:, :3], e[:, :3], rtol=0, atol=1e-12)  # mm
        assert np.allclose(got[:, 3:], e[:, 3:], rtol=0, atol=1e-14)  # rad
    assert np.abs(tp.ls_residuals(pf, d)).max() < 1e-12


def test_least_squares_equals_lstsq_with_noise_and_residuals_are_orthogonal():
    p = _points(50)
    a = _design(p)
    d = np.einsum("nij,nj->ni", a, _errors(50)) + RNG.normal(0, 0.005, (50, 9))
    ls = tp.ls_solve(p.reshape(-1, 9), d)
    res = tp.ls_residuals(p.reshape(-1, 9), d)
    for k in range(50):
        ref = np.linalg.lstsq(a[k], d[k], rcond=None)[0]
        assert np.allclose(ls[k], ref, rtol=1e-9, atol=1e-13)
        assert np.allclose(res[k], d[k] - a[k] @ ref, atol=1e-12)
        assert np.abs(a[k].T @ res[k]).max() < 1e-9  # normal equations hold
    # the selected six equations are solved exactly by their closed form even with noise
    sel = tp.solve_selected(p.reshape(-1, 9), d)
    rows = [0, 1, 3, 5, 7, 8]
    assert np.allclose(np.einsum("nij,nj->ni", a[:, rows], sel), d[:, rows], atol=1e-9)


def test_least_squares_jacobian_is_the_pseudo_inverse_by_central_differences():
    """d ls_solve / d deltas by central differences (ls_solve is linear in deltas, so the step only meets
    rounding: h = 1e-3 mm on deltas of 1e-2 mm gives ~1e-13 relative error; atol 1e-9 per mm)."""
    p = _points(1)[0]
    pf, d0 = p.ravel(), RNG.normal(0, 0.01, 9)
    h = 1e-3
    jac = np.stack([(tp.ls_solve(pf, d0 + h * np.eye(9)[k]) - tp.ls_solve(pf, d0 - h * np.eye(9)[k])) / (2 * h)
                    for k in range(9)], axis=1)
    assert np.allclose(jac, np.linalg.pinv(_design(p[None])[0]), rtol=1e-7, atol=1e-9)


def test_selected_denominator_is_n_of_eq34_and_least_squares_survives_where_it_vanishes():
    p = _points(20)
    (xp, yp, zp), (xq, yq, zq), (xk, yk, zk) = (np.moveaxis(p[:, k], -1, 0) for k in range(3))
    n_eq34 = (xk - xq) * (yp - yq) * (zp - zk) - (xk - xp) * (yk - yq) * (zq - zp)
    det = tp.selected_denominator(p.reshape(-1, 9))[:, 0]
    assert np.allclose(np.abs(det), np.abs(n_eq34), rtol=1e-12)
    # all three points at one height: N = 0 (eq. 33 divides by z_Q - z_P), yet not collinear
    flat = np.array([[100.0, 0, 50], [-50, 90, 50], [-50, -90, 50]])
    assert tp.selected_denominator(flat.ravel())[0] == 0
    e = _errors(1)[0]
    d = _design(flat[None])[0] @ e
    assert np.allclose(tp.ls_solve(flat.ravel(), d), e, atol=1e-12)
    with np.errstate(divide="ignore", invalid="ignore"):  # the selected closed form divides by N = 0 here
        assert not np.all(np.isfinite(tp.solve_selected(flat.ravel(), d)))


def test_point_shape():
    tri = np.array([[1, 0, 0], [-0.5, np.sqrt(3) / 2, 0], [-0.5, -np.sqrt(3) / 2, 0]]) * 80 + [300, -20, 100]
    assert tp.point_shape(tri.ravel())[0] == pytest.approx(1.0, abs=1e-12)
    line = np.array([[0, 0, 0], [10, 20, 30], [25, 50, 75.0]])
    assert abs(tp.point_shape(line.ravel())[0]) < 1e-12
    from mtcal.identify.threepoint import _shape
    p = _points(10)
    assert np.allclose(tp.point_shape(p.reshape(-1, 9))[:, 0], _shape(p), rtol=1e-10)


def test_frames_of_the_dmu50():
    """B's frame is tilted +45 deg about x at height d; C's is the table frame at B = 0; linear axes translate."""
    d = 154.996
    fb = tp.frame_dmu50_B(np.array([0, 0, 0, 0, 0.0]))
    c, s = np.cos(np.pi / 4), np.sin(np.pi / 4)
    assert np.allclose(fb[:, :3], [[1, 0, 0], [0, c, -s], [0, s, c]], atol=1e-15)
    assert np.allclose(fb[:, 3], [0, 0, d])
    assert np.allclose(tp.frame_dmu50_C(np.zeros(5)), np.hstack([np.eye(3), np.zeros((3, 1))]), atol=1e-12)
    fy = tp.frame_dmu50_Y(np.array([10, 20, 30, 40, 50.0]))
    assert np.allclose(fy, np.hstack([np.eye(3), [[10], [20], [0]]]))
    for name in tp.FRAMES.values():
        f = getattr(tp, name)(RNG.uniform(0, 180, (4, 5)))
        r = f[..., :3]
        assert np.allclose(r @ np.swapaxes(r, -1, -2), np.eye(3), atol=1e-12), name
        assert np.allclose(np.linalg.det(r), 1), name


@pytest.mark.parametrize("axis", ["X", "Y", "Z", "B", "C"])
def test_three_point_system_is_the_machine_error_jacobian_in_the_axis_frame(axis):
    """R_F design(p_F) equals the generated machine Jacobian columns of the axis' six errors, and central
    differences of the exact tool_point / table_point.  Step h = 1e-6 (mm, rad): truncation O(h^2 |p|) <= 1e-9,
    rounding eps |x| / h ~ 2e-16 * 1e3 / 1e-6 = 2e-7 mm per unit -> atol 2e-6."""
    m = mtcal.load_machine("dmu50")
    side = tp.FRAME_SIDES[f"dmu50_{axis}"]
    point = getattr(m._np, f"{side}_point")
    jac = getattr(m._np, f"{side}_point_jacobian_errors")
    cols = [m.error_names.index(f"E_{c}{axis}") for c in "XYZABC"]
    k = m.axes.index(axis)
    for _ in range(3):
        axes = np.zeros(5)
        axes[k] = RNG.uniform(0, 180) if axis in "BC" else RNG.uniform(0, 400)
        w = RNG.uniform(-150, 150, 3)
        nominal = point(axes, np.zeros(len(m.error_names)), w)
        f = getattr(tp, f"frame_dmu50_{axis}")(axes)
        p_f = f[:, :3].T @ (nominal - f[:, 3])
        ours = f[:, :3] @ tp.point_rows(p_f)
        assert np.allclose(ours, jac(axes, w)[:, cols], rtol=1e-12, atol=1e-12)
        h = 1e-6
        fd = np.empty((3, 6))
        for j, c in enumerate(cols):
            e = np.zeros(len(m.error_names))
            e[c] = h
            fd[:, j] = (point(axes, e, w) - point(axes, -e, w)) / (2 * h)
        assert np.allclose(fd, ours, rtol=0, atol=2e-6)
