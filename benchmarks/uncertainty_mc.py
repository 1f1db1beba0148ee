"""The Monte Carlo of `mtcal uncertainty` (mtcal.uncertainty): speed against workers and coverage of its intervals.

`python benchmarks/uncertainty_mc.py speed [--trials 40]`: trials per second with 1 and 2 local Dask workers on
the bundled campaign (all five axes, the joint fit), and the projected wall time of 10^6 trials on N workers.

`python benchmarks/uncertainty_mc.py coverage [--n 40] [--trials 100] [--axis X]`: over n simulated campaigns of
the demo's true machine (independent seeds, AT960 noise, tracker given), the share of 95 % intervals (symmetric)
that hold the truth, for the table values and for the fitted functions the model evaluates, of the positioning
and angular errors of one axis (truth taken relative to the reference position, as identify defines the errors;
straightness is left out: its reference line is a convention of the frame, not of the truth).  The Monte Carlo
draws noise only: the campaigns carry no scale or centring error.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import mtcal  # noqa: E402
from mtcal.data import path  # noqa: E402
from mtcal.data.make_demo_data import DEMO_PLAN  # noqa: E402
from mtcal.uncertainty import Inputs, monte_carlo  # noqa: E402


def speed(trials: int) -> dict:
    rec = mtcal.read_recording(path("demo_campaign.csv"))
    out = {"trials": trials, "cores": os.cpu_count(), "readings": len(rec)}
    for w in (1, 2):
        t = time.perf_counter()
        monte_carlo(rec, trials=trials, seed=0, workers=w, tracker=DEMO_PLAN["tracker"])
        dt = time.perf_counter() - t
        out[f"workers_{w}"] = {"seconds": dt, "trials_per_s": trials / dt}
    per_worker = out["workers_1"]["trials_per_s"]
    out["speedup_2_over_1"] = out["workers_2"]["trials_per_s"] / per_worker
    out["projected_hours_1e6_trials"] = {str(n): 1e6 / (per_worker * n * min(1.0, out["speedup_2_over_1"] / 2)) / 3600
                                         for n in (2, 16, 64, 256)}
    return out


def coverage(n: int, trials: int, axis: str) -> dict:
    truth = mtcal.load_model(path("demo_truth.json"))
    m = truth.kinematics
    names = [e for e in m.error_motions(axis) if e == m.positioning_errors[axis] or e[2] in "ABC"]
    hit = {"tables": [], "fits": []}
    for k in range(n):
        rec, _ = mtcal.simulate(truth, plan=DEMO_PLAN, rounds=None, seed=5000 + k)
        rec = rec.select(rec.axis == axis)
        for mode in hit:
            r = monte_carlo(rec, trials=trials, seed=k, workers=2, inputs=Inputs().only("noise"),
                            tracker=DEMO_PLAN["tracker"], tables=(mode == "tables"))
            for nme in names:
                _, pos, sl = r.outputs.functions[nme]
                ref = DEMO_PLAN["axes"][axis]["start"] * 0.0  # the reference position: closest to zero
                ref = pos[np.argmin(np.abs(pos - ref))]
                true = truth.functions[nme](pos, "hold") - truth.functions[nme](np.array([ref]), "hold")[0]
                keep = pos != ref
                hit[mode] += ((r.stats["lo"][sl] <= true) & (true <= r.stats["hi"][sl]))[keep].tolist()
    return {"campaigns": n, "trials": trials, "axis": axis, "errors": names,
            **{f"coverage_95_{k}": float(np.mean(v)) for k, v in hit.items()},
            "intervals": {k: len(v) for k, v in hit.items()}}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("what", choices=("speed", "coverage"))
    ap.add_argument("--trials", type=int, default=None)
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--axis", default="X")
    a = ap.parse_args()
    res = speed(a.trials or 40) if a.what == "speed" else coverage(a.n, a.trials or 100, a.axis)
    print(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
