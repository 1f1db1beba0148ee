"""Issue 56: `mtcal thermal fit` on the real spindle thermal test FL_THERMAL, the last 40 % held out in time.

Data: tests/data/fl_thermal/fl_thermal_2min.csv (every 8th row of CAIVIAC/FL_THERMAL data/data.xlsx, MIT).
Figures: per channel the model's out-of-sample RMSE and R^2, the constant and time-only baselines' RMSE (fitted on
the same first 60 %), predictable (1/0); beside them, computed here independently with numpy, the issue's
sixteen-sensor OLS on the first 60 %; the CPU seconds of the fit (selection of all five channels); and, on the same
temperatures and speed, 40 random walks without a thermal cause: how many beat the constant's RMSE on the
hold-out by chance and how many the test declares predictable (the false compensations).
Run alone: ``python benchmarks/bench_thermal.py`` (prints the JSON), or through benchmarks/run.py.
"""
from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np

from mtcal.thermal import fit_thermal, read_thermal_test

CSV = Path(__file__).resolve().parents[1] / "tests" / "data" / "fl_thermal" / "fl_thermal_2min.csv"
HOLDOUT = 0.4


def ols16(path: Path = CSV, holdout: float = HOLDOUT) -> dict[str, float]:
    """The issue's independent measurement: all sixteen temperatures, OLS on the first part, RMSE on the rest."""
    a = np.loadtxt(path, delimiter=",", skiprows=1)
    n = len(a)
    k = round((1 - holdout) * n)
    X = np.column_stack([np.ones(n), a[:, 7:]])
    out = {}
    for j in range(5):
        y = a[:, 2 + j]
        p = np.linalg.lstsq(X[:k], y[:k], rcond=None)[0]
        out[f"ch{j + 1}"] = float(np.sqrt(np.mean((y[k:] - X[k:] @ p) ** 2)))
    return out


def run() -> dict:
    t0 = time.process_time()
    model = fit_thermal(read_thermal_test(CSV), HOLDOUT)
    out = {"thermal_fl_fit_cpu_s": round(time.process_time() - t0, 2)}
    for c in model.channels:
        key = f"thermal_fl_{c.channel}"
        out.update({f"{key}_rmse_um": c.rmse_um, f"{key}_r2": c.r2, f"{key}_constant_rmse_um": c.constant_rmse_um,
                    f"{key}_time_only_rmse_um": c.time_only_rmse_um, f"{key}_predictable": int(c.predictable),
                    f"{key}_u95_um": c.u95_um})
    out.update({f"thermal_fl_{ch}_ols16_rmse_um": v for ch, v in ols16().items()})
    return {**out, **random_walks()}


def random_walks(k: int = 40, seed: int = 2026) -> dict:
    """Channels without a thermal cause (random walks, 0.5 um steps) on FL_THERMAL's temperatures and speed."""
    t = read_thermal_test(CSV)
    rng = np.random.default_rng(seed)
    t.channels = {f"w{i}": np.cumsum(rng.normal(0.0, 0.5, len(t))) for i in range(k)}
    m = fit_thermal(t, HOLDOUT)
    return {"thermal_random_walks": k,
            "thermal_random_walks_beat_constant": sum(c.rmse_um < c.constant_rmse_um for c in m.channels),
            "thermal_random_walks_predictable": sum(c.predictable for c in m.channels)}


if __name__ == "__main__":
    print(json.dumps(run(), indent=1, sort_keys=True))
