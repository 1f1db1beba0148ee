"""Rates of the check-test evaluation (mtcal.check) over many simulated campaigns of the demo's true machine:
`python benchmarks/check_rates.py [--n 40] [--json]`.

Per campaign (seed k): a tracker campaign of the true machine (AT960 noise, the demo's layout) is identified with
identify's default; then ballbar tests of the true machine (exact kinematics, 0.2 um noise) in XY, YZ and ZX are
evaluated against that model:
* clean tests: the share that agrees with the model within its uncertainty (the evaluation's rule), and the
  share with each signature reported (on a clean test a finding is the identified model's own error beyond its
  stated uncertainty: e.g. cyclic content of the true error functions that the fitted polynomials leave out);
* the same tests with a backlash of 2 um on the plane's first axis and a servo mismatch of 0.1 ms at 2000 mm/min
  (3.3 um): the share in which each is named (backlash as quasi-static with its axis, servo mismatch as dynamic),
  and the backlash's size error;
* a machine changed since its calibration (the squareness E_C0Y 15 or 40 urad larger than the truth the campaign
  saw: a 2.25 or 6 um oval at R = 150 mm in XY): the share of XY tests with the squareness named (beyond the
  model's own squareness uncertainty, about 3.5 urad from an AT960 campaign).
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import mtcal  # noqa: E402
from mtcal.check import CircleSetup, evaluate_check, simulate_circular  # noqa: E402
from mtcal.data import path  # noqa: E402
from mtcal.data.make_demo_data import DEMO_PLAN  # noqa: E402
from mtcal.model.errormodel import ErrorModel  # noqa: E402

PLAN = DEMO_PLAN  # the demo's campaign layout (mtcal/data/make_demo_data.py): inside the true tables
PLANES = ("XY", "YZ", "ZX")


def run(n: int) -> dict:
    truth = mtcal.load_model(path("demo_truth.json"))
    clean_agree = planted_b = planted_s = total = 0
    changed = {15: 0, 40: 0}
    size_err, u95, clean_found = [], [], {}
    moved = {d: ErrorModel(truth.machine, {**truth.constants, "E_C0Y": truth.constants["E_C0Y"] + d * 1e-6},
                           truth.functions) for d in changed}
    for k in range(n):
        rec, _ = mtcal.simulate(truth, plan=PLAN, rounds=None, seed=1000 + k)
        model = mtcal.identify(rec, tracker=PLAN["tracker"], worth=False).model
        for j, plane in enumerate(PLANES):
            s = CircleSetup(plane, 150.0, (0.0, 0.0, 0.0))
            ev = evaluate_check(simulate_circular(truth, s, seed=10 * k + j), model)
            total += 1
            u95.append(ev.prediction_u95_mm)
            clean_agree += ev.agrees
            for f in ev.findings:
                clean_found[f.name] = clean_found.get(f.name, 0) + 1
            ev = evaluate_check(simulate_circular(truth, s, backlash={plane[0]: 0.002},
                                                  servo_lag_s={plane[0]: 0.0100, plane[1]: 0.0101},
                                                  feed_mm_min=2000.0, seed=10 * k + j + 5), model)
            names = {f.name: f for f in ev.findings}
            b = names.get(f"backlash_{plane[0]}")
            planted_b += b is not None
            if b is not None:
                size_err.append(b.size - 0.002)
            sm = names.get("servo_mismatch")
            planted_s += sm is not None and not sm.quasi_static
        for d, truth_d in moved.items():
            ev = evaluate_check(simulate_circular(truth_d, CircleSetup("XY", 150.0, (0.0, 0.0, 0.0)), seed=k), model)
            changed[d] += any(f.name == "squareness" for f in ev.findings)
    return {"campaigns": n, "tests": total, "clean_agree": clean_agree / total,
            "clean_findings": {k: v / total for k, v in clean_found.items()},
            "backlash_named": planted_b / total, "servo_mismatch_named_dynamic": planted_s / total,
            "backlash_size_error_um": {"mean": float(np.mean(size_err) * 1e3), "sd": float(np.std(size_err) * 1e3)},
            "prediction_u95_um_median": float(np.median(u95) * 1e3),
            "changed_squareness_found": {f"{d}_urad": c / n for d, c in changed.items()}}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    out = run(args.n)
    print(json.dumps(out, indent=1) if args.json else "\n".join(f"{k}: {v}" for k, v in out.items()))


if __name__ == "__main__":
    main()
