"""Shared timing helper for the benchmark modules (benchmarks/ is on sys.path when run.py imports them)."""
from __future__ import annotations

import time


def best_of(fn, repeat: int = 3) -> float:
    """Shortest wall time (s) of ``repeat`` calls of ``fn()``: the least disturbed run on a shared machine."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best
