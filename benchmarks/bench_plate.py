"""Timing of `mtcal.plate.reversal.fit_plate` on a large synthetic plate (no asserts; `python
benchmarks/bench_plate.py`)."""
from __future__ import annotations

import math
import time

import numpy as np


def _plate(n: int, seed: int = 0):
    from mtcal.plate.reversal import plate_from_arrays
    rng = np.random.default_rng(seed)
    X = rng.uniform(0, 400.0, (n, 2))  # mm
    a, b, g, eps = 5e-6, -1.4e-4, 1.2e-5, np.array([-0.004, 0.003])
    A = np.array([[1 + g / 2, -a], [0, 1 - g / 2]])
    th = math.pi / 2 + b
    B = np.array([[math.cos(th), math.sin(th)], [-math.sin(th), math.cos(th)]])
    p1 = X @ A.T + rng.normal(0, 5e-4, (n, 2))
    p2 = (X @ A.T - eps) @ np.linalg.inv(A @ B.T @ np.linalg.inv(A)).T + rng.normal(0, 5e-4, (n, 2))
    return plate_from_arrays(range(n), p1, p2, source=f"synthetic {n} points")


def run(n: int = 10_000) -> dict:
    """Seconds for a full first-order fit (closed form + statistics + flags + gage frame) and an exact fit
    of an n-point plate; the key names say 1e4 (the default n)."""
    from mtcal.plate.reversal import fit_plate
    data = _plate(n)
    fit_plate(data)  # warm-up (imports, scipy.stats)
    t0 = time.perf_counter()
    fit_plate(data)
    t1 = time.perf_counter()
    fit_plate(data, exact=True)
    t2 = time.perf_counter()
    return {"plate_1e4_points_s": t1 - t0, "plate_1e4_points_exact_s": t2 - t1, "n_points": n}


if __name__ == "__main__":
    print(run())
