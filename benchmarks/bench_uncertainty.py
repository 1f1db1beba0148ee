"""Speed of the Monte Carlo of `mtcal uncertainty`: the full path (identify per trial, `--exact`) and the batched
path (mtcal.uncertainty.fast) in one run, in this process and on 1 and 2 workers (benchmarks/uncertainty_mc.py
speed)."""
from __future__ import annotations

import uncertainty_mc


def run(trials: int = 8, fast_trials: int = 20000) -> dict:
    r = uncertainty_mc.speed(trials, fast_trials)
    one = r["one_core"]
    return {"mc_trials_per_s_1_worker": r["full_workers_1"]["trials_per_s"],
            "mc_speedup_2_workers": r["full_speedup_2_over_1"],
            "mc_full_trials_per_s_one_core": one["full_trials_per_s"],
            "mc_batched_trials_per_s_one_core": one["batched_trials_per_s"],
            "mc_batched_trials_per_cpu_s_one_core": one["batched_trials_per_cpu_s"],
            "mc_full_trials_per_cpu_s_one_core": one["full_trials_per_cpu_s"],
            "mc_batched_over_full_one_core": one["ratio_cpu"],
            "mc_batched_trials_per_s_1_worker": r["batched_workers_1"]["trials_per_s"],
            "mc_batched_trials_per_s_2_workers": r["batched_workers_2"]["trials_per_s"],
            "mc_batched_speedup_2_workers": r["batched_speedup_2_over_1"],
            "mc_batched_speedup_2_workers_trials_phase": r["batched_speedup_2_over_1_trials_phase"],
            "mc_projected_hours_1e5_batched_2_workers": r["projected_hours"]["batched_2_workers_1e5"],
            "mc_projected_hours_1e6_batched_2_workers": r["projected_hours"]["batched_2_workers_1e6"],
            "mc_projected_hours_1e5_full_2_workers": r["projected_hours"]["full_2_workers_1e5"],
            "mc_projected_hours_1e6_full_2_workers": r["projected_hours"]["full_2_workers_1e6"],
            "mc_load_average": r["load_average_1min_before"]}
