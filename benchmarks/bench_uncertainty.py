"""Speed of the Monte Carlo of `mtcal uncertainty` against workers (benchmarks/uncertainty_mc.py speed)."""
from __future__ import annotations

import uncertainty_mc


def run(trials: int = 24) -> dict:
    r = uncertainty_mc.speed(trials)
    return {"mc_trials_per_s_1_worker": r["workers_1"]["trials_per_s"],
            "mc_speedup_2_workers": r["speedup_2_over_1"],
            "mc_projected_hours_1e6_on_64_workers": r["projected_hours_1e6_trials"]["64"],
            "mc_projected_hours_1e6_on_2_workers": r["projected_hours_1e6_trials"]["2"]}
