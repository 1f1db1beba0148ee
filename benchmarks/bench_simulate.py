"""Virtual laser tracker and planning performance: targets < 1 s per default campaign, < 10 s for a Monte Carlo
of 10^4 rounds of one axis (all 11 positions of X)."""
from __future__ import annotations

import time

import numpy as np
from timing import best_of


def run() -> dict:
    from mtcal import load_machine
    from mtcal.campaign.plans import Plan
    from mtcal.campaign.simulate import simulate_campaign
    from mtcal.planning.plan import linear_covariance, monte_carlo, placement_map

    m = load_machine("dmu50")
    pl = Plan()
    t0 = time.perf_counter()
    rec = simulate_campaign()  # first call: includes loading the generated module
    first = time.perf_counter() - t0
    effects = [("backlash", {}), ("thermal_drift", {}), ("outlier", {}), ("tracker_scale", {}), ("periodic", {})]
    out = {
        "simulate_default_campaign_s": best_of(lambda: simulate_campaign(seed=1)),
        "simulate_default_campaign_first_call_s": first,
        "simulate_campaign_rows": len(rec),
        "simulate_campaign_5_effects_s": best_of(lambda: simulate_campaign(seed=1, effects=effects)),
        "simulate_100_rounds_s": best_of(lambda: simulate_campaign(rounds=100), repeat=1),
        "linear_propagation_all_axes_s": best_of(
            lambda: [linear_covariance(m, pl, a, pl.positions[a], pl.tracker) for a in pl.positions]),
        "monte_carlo_1e4_rounds_X_11_positions_s": best_of(
            lambda: monte_carlo(m, pl, "X", pl.positions["X"], pl.tracker, 10_000), repeat=1),
        "monte_carlo_1e4_rounds_X_mid_travel_identify_2_passes_s": best_of(
            lambda: monte_carlo(m, pl, "X", [250.0], pl.tracker, 10_000, approaches=2), repeat=1),
        "monte_carlo_1e4_rounds_C_18_positions_s": best_of(
            lambda: monte_carlo(m, pl, "C", pl.positions["C"], pl.tracker, 10_000), repeat=1),
    }
    xs = ys = np.arange(-2500.0, 3001.0, 250.0)
    t = time.perf_counter()
    placement_map(xs, ys, 150.0, pl, machine=m)
    out["placement_map_23x23_s"] = time.perf_counter() - t
    return out


if __name__ == "__main__":
    for k, v in run().items():
        print(f"{k:45s} {v:.4g}")
