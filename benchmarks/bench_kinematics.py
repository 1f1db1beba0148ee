"""Error-inclusive tool pose + 6x5 axis Jacobian: generated NumPy vs a per-pose 4x4 HTM chain (thesis approach)."""
from __future__ import annotations

import time

import numpy as np

import mtcal

D = 154.996


def _htm(rot: np.ndarray | None = None, t=(0.0, 0.0, 0.0)) -> np.ndarray:
    m = np.eye(4)
    if rot is not None:
        m[:3, :3] = rot
    m[:3, 3] = t
    return m


def _r(axis: str, a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return {"x": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]), "y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
            "z": np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])}[axis]


def _err(e6) -> np.ndarray:
    return _htm(_r("z", e6[5]) @ _r("y", e6[4]) @ _r("x", e6[3]), e6[:3])


def htm_pose(q: np.ndarray, e: np.ndarray, tool_length: float = 0.0) -> np.ndarray:
    """One pose by multiplying 4x4 matrices, the way the thesis builds its model (same exact error model)."""
    X, Y, Z, B, C = q
    ey = _r("z", e[18]) @ np.array([0, 1.0, 0])
    ez = _r("y", e[19]) @ _r("x", e[20]) @ np.array([0, 0, 1.0])
    tool = (_htm(t=(0, 0, tool_length)) @ _htm(t=(X, 0, 0)) @ _err(e[0:6]) @ _htm(t=Y * ey) @ _err(e[6:12])
            @ _htm(t=Z * ez) @ _err(e[12:18]) @ _htm(t=(0, 0, -tool_length)))

    def joint(angle, mot, loc):
        line = _htm(_r("y", loc[3]) @ _r("x", loc[2]), (loc[0], loc[1], 0))
        return _err(mot) @ line @ _htm(_r("z", angle)) @ np.linalg.inv(line)
    t45 = np.radians(45)
    table = (_htm(t=(0, 0, D)) @ _htm(_r("x", t45)) @ joint(np.radians(B), e[21:27], e[33:37]) @ _htm(_r("x", -t45))
             @ _htm(t=(0, 0, -D)) @ joint(-np.radians(C), e[27:33], e[37:41]))
    t = np.linalg.inv(table) @ tool
    return np.r_[t[:3, 3], t[:3, 2]]


def htm_pose_and_jacobian(q, e, h=1e-4):
    pose = htm_pose(q, e)
    jac = np.empty((6, 5))
    for k in range(5):
        dq = np.zeros(5)
        dq[k] = h
        jac[:, k] = (htm_pose(q + dq, e) - htm_pose(q - dq, e)) / (2 * h)
    return pose, jac


def run(n: int = 1_000_000, n_loop: int = 2000) -> dict:
    m = mtcal.load_machine("dmu50")
    rng = np.random.default_rng(0)
    q = np.column_stack([rng.uniform(-250, 250, (n, 3)), rng.uniform(1, 179, n), rng.uniform(-360, 360, n)])
    e = rng.normal(size=(n, 41)) * np.where([nm[2] in "ABC" for nm in m.error_names], 5e-5, 0.02)
    assert np.abs(htm_pose(q[0], e[0]) - m.forward(q[0], e[0])).max() < 1e-9  # same model, so a fair race
    t0 = time.perf_counter()
    for i in range(n_loop):
        htm_pose_and_jacobian(q[i], e[i])
    loop_per_pose = (time.perf_counter() - t0) / n_loop
    t0 = time.perf_counter()
    m._np.forward_errors_with_jacobian(q, e, 0.0)
    gen_s = time.perf_counter() - t0
    f = m.casadi.forward_errors_with_jacobian().map(n_cas := 100_000, "serial")
    t0 = time.perf_counter()
    f(q[:n_cas].T, e[:n_cas].T, 0.0)
    cas_s = time.perf_counter() - t0
    return {"fk_poses_per_s": n / gen_s, "fk_htm_loop_poses_per_s": 1 / loop_per_pose,
            "fk_speedup_vs_htm_loop": loop_per_pose * n / gen_s, "fk_casadi_map_poses_per_s": n_cas / cas_s}
