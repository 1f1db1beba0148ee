"""Coverage of the law and the station from what is rigid (mtcal.measurement.tracker_position.rigid_law,
rigid_station, station_interval) on simulated campaigns of known truth: the demo plan on the DMU 50, the tracker at
T, four rounds, the AT960's law (or ``--spec`` 1:4), seeds 0 .. N - 1.  For each seed: whether the law's stated
95 % intervals (about the true tracker) hold the true factors (1, 1), whether the mutual distances' station interval
(rigid_station, from the rounds' estimate) holds the true distance, and whether the interval the diagnosis and
identify state (station_interval with the recording) does.

    python benchmarks/rigid_coverage.py [--seeds 20]

Prints JSON: per seed and the counts; CPU seconds.
"""
from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace

import numpy as np

from mtcal.campaign.plans import as_plan
from mtcal.campaign.simulate import simulate
from mtcal.data import path
from mtcal.data.make_demo_data import DEMO_PLAN
from mtcal.identify.run import estimate_station
from mtcal.kinematics.machine import load_machine
from mtcal.measurement.tracker_position import rigid_law
from mtcal.model.errormodel import load_model

T = np.array([250.0, -1500.0, 150.0])


def one(seed: int) -> dict:
    m = load_machine("dmu50")
    plan = replace(as_plan(DEMO_PLAN, m), tracker=tuple(T), rounds=4)
    rec, _ = simulate(load_model(path("demo_truth.json")), machine=m, plan=plan, seed=seed)
    law = rigid_law(rec, T)
    out = {"seed": seed}
    for k in ("radial", "transverse"):
        lo, hi = law[k]["interval_95"]
        out[k] = {"holds_1": (lo is None or lo <= 1) and (hi is None or hi >= 1), "determined": law[k]["determined"],
                  "interval_95": law[k]["interval_95"]}
    est, why = estimate_station(rec)
    true = float(np.linalg.norm(T - rec.xyz.mean(axis=0)))
    out["true_distance_mm"] = round(true, 1)
    if est is None:
        out["station"] = why
        return out
    st = est.interval
    iv = st["interval_95_mm"]
    rig = st.get("mutual_distances", {}).get("interval_95_mm")
    out["station"] = {"stated": iv, "determined": st["determined"], "holds": iv is not None and iv[0] <= true <= iv[1],
                      "mutual_distances": rig, "rigid_holds": rig is not None and rig[0] <= true <= rig[1],
                      "error_mm": round(float(np.linalg.norm(est.position - T)), 1),
                      "sigma_mm": est.sigma_mm.round(1).tolist()}
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, default=20)
    a = ap.parse_args(argv)
    t0 = time.process_time()
    rows = [one(s) for s in range(a.seeds)]
    st = [r["station"] for r in rows if isinstance(r["station"], dict)]
    print(json.dumps({"runs": rows, "summary": {
        "seeds": a.seeds, "radial_holds": sum(r["radial"]["holds_1"] for r in rows),
        "transverse_holds": sum(r["transverse"]["holds_1"] for r in rows),
        "radial_determined": sum(r["radial"]["determined"] for r in rows),
        "transverse_determined": sum(r["transverse"]["determined"] for r in rows),
        "station_estimated": len(st), "stated_holds": sum(s["holds"] for s in st),
        "rigid_holds": sum(s["rigid_holds"] for s in st), "stated_determined": sum(s["determined"] for s in st),
        "cpu_s": round(time.process_time() - t0, 1)}}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
