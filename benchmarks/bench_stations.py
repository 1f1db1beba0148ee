"""Accuracy of several tracker stations (issue 14; the numbers of the docs section "Several stations"):
volumetric RMS of identified model - truth over 2000 poses of the demo's work volume, mean over seeds 1-5.

Truth: the bundled demo truth (mtcal/data/demo_truth.json) and the same truth in the ISO frame of the linear
axes (linear part of E_YX, E_ZX, E_ZY removed; the estimate is in that frame and no tracker can see the frame's
rotation relative to the table).  Campaigns: the demo plan (mtcal.data.make_demo_data.DEMO_PLAN) simulated
through the exact kinematics; one station = thesis Pos. 1, 4 rounds (mtcal.campaign.simulate, no alignment error);
four stations = front, left, front-right, elevated 1.2 m, 1 round each, each station misaligned by
N(0, 20 um) / N(0, 30 urad) (mtcal.campaign.stations, translations centred: the gauge)."""
from __future__ import annotations

import copy

import numpy as np

FRONT, LEFT, FRONT_RIGHT, HIGH = (250, -1500, 150), (-1500, 0, 150), (1300, -1300, 150), (-1000, -1000, 1200)
STATIONS4 = [("front", FRONT), ("left", LEFT), ("front-right", FRONT_RIGHT), ("elevated", HIGH)]
WIDE = {"tool": {"P": [210, 0, 30], "Q": [-105, 180, 120], "K": [-105, -180, 210]},
        "table": {"P": [450, 0, 40], "Q": [-225, 390, 80], "K": [-225, -390, 120]}}


def iso_framed(truth):
    from mtcal.model.errormodel import ErrorFunction
    t = copy.deepcopy(truth)
    for nm in ("E_YX", "E_ZX", "E_ZY"):
        f = t.functions[nm]
        xs = np.linspace(f.positions.min(), f.positions.max(), 201)
        v = f(xs)
        t.functions[nm] = ErrorFunction(f.axis, xs, v - np.polyfit(xs, v, 1)[0] * xs)
    return t


def _identify(m, truth, case: str, seed: int):
    """The identified model of one campaign of ``case`` (see module docstring)."""
    from mtcal.campaign.simulate import simulate
    from mtcal.campaign.stations import simulate_stations
    from mtcal.data.make_demo_data import DEMO_PLAN
    from mtcal.identify.run import identify
    if case.startswith("1_station"):
        rec = simulate(truth, machine=m, seed=seed, plan=DEMO_PLAN, rounds=None)[0]
        method = "three-point" if case.endswith("three_point") else "joint"
        return identify(rec, tracker=FRONT, machine=m, method=method).model
    plan = {**DEMO_PLAN, "points": WIDE} if case.endswith("wide_reflectors") else DEMO_PLAN
    rounds = 2 if case.endswith("2_rounds") else 1
    rec = simulate_stations(truth, STATIONS4, machine=m, rounds=rounds, seed=seed, plan=plan)[0]
    return identify(rec, machine=m).model


CASES = ("1_station_three_point", "1_station_joint", "4_stations", "4_stations_2_rounds",
         "4_stations_wide_reflectors")


def run(seeds=range(1, 6)) -> dict:
    import mtcal
    from mtcal.demo.run import data_path
    from mtcal.model.errormodel import load_model
    m = mtcal.load_machine("dmu50")
    rng = np.random.default_rng(0)
    grid = np.column_stack([rng.uniform(-200, 200, 2000), rng.uniform(-180, 180, 2000),
                            rng.uniform(-150, 150, 2000), rng.uniform(0, 120, 2000), rng.uniform(0, 360, 2000)])
    out = {}
    for tname, truth in (("demo", load_model(data_path("demo_truth.json"))),
                         ("iso", iso_framed(load_model(data_path("demo_truth.json"))))):
        dt = m.deviation(grid, truth.errors_at(m, grid, "hold"), order=None)[:, :3]
        for case in CASES:
            v = []
            for s in seeds:
                d = m.deviation(grid, _identify(m, truth, case, s).errors_at(m, grid, "hold"), order=None)[:, :3] - dt
                v.append(float(np.sqrt(np.mean(np.sum(d**2, axis=1))) * 1e3))
            out[f"{tname}_truth_{case}_um"] = float(np.mean(v))
            out[f"{tname}_truth_{case}_max_um"] = float(np.max(v))
    return out


if __name__ == "__main__":
    for k, v in run().items():
        print(f"{k}: {v:.4g}" if isinstance(v, float) else f"{k}: {v}")
