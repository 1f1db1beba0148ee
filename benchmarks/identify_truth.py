"""Identification against a known truth over many simulated campaigns (issue 22): `python benchmarks/identify_truth.py
[--n 54] [--json OUT.json]`.

Campaigns: the three machine specs (dmu50 with the bundled demo truth; headbc and xyzac with a synthetic truth of
the same magnitudes, mtcal.data.make_demo_data.build_for), three tracker positions each, 3 to 8 rounds, AT960
noise, seeds fixed: campaign k uses seed 1000 + k.  Every campaign is identified by each path:
  three-point         no tracker position given (the thesis method, unweighted)
  three-point+tracker the tracker position given (weighted)
  joint+tracker       one weighted fit of all readings with the tracker position (identify's default with --tracker)
  auto                identify's default without the tracker position
Reported per path over all campaigns: the model's error (truth - model, RMS over 2000 poses inside the measured
ranges, after the re-setup gauge; mtcal.identify.compare), the share of campaigns where compensating with the model
leaves the
true machine worse than no compensation, and the share of (function, campaign) pairs whose fitted function is at
least as close to the truth as its table (RMS over the table's positions; 0.05 um tolerance).
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time

import numpy as np

import mtcal
from mtcal.campaign.plans import as_plan
from mtcal.campaign.simulate import simulate
from mtcal.data.make_demo_data import DEMO_PLAN, build, build_for
from mtcal.identify.compare import compare_models
from mtcal.identify.run import identify
from mtcal.kinematics.defaults import default_positions

SPECS = ("dmu50", "headbc", "xyzac")
TRACKERS = {"dmu50": [(250, -1500, 150), (-1500, 225, 150), (1200, -1200, 600)],
            "headbc": [(250, -1500, 150), (-1500, 225, 150), (1200, -1200, 600)],
            "xyzac": [(250, -1500, 150), (-1500, 225, 150), (1200, -1200, 600)]}
PATHS = {"three-point": lambda t: dict(method="three-point"),
         "three-point+tracker": lambda t: dict(method="three-point", tracker=t),
         "joint+tracker": lambda t: dict(method="joint", tracker=t),
         "auto": lambda t: dict()}
TOL_MM = 5e-5  # a fit "at least as close as the table" within this (0.05 um / 0.05 urad when angular, x1e-3)


def campaigns(n: int):
    """(k, machine, truth, tracker, rounds, seed) of the n campaigns, cycling specs, trackers and rounds."""
    truths = {}
    for k in range(n):
        name = SPECS[k % 3]
        m = mtcal.load_machine(name)
        if name not in truths:
            truths[name] = build() if name == "dmu50" else build_for(m)
        yield k, m, truths[name], TRACKERS[name][(k // 3) % 3], 3 + (k // 9) % 6, 1000 + k


def _positions(m) -> dict:
    """The campaign positions: the bundled demo's plan on the DMU 50 (its truth's tables), else the spec's."""
    return as_plan(DEMO_PLAN, m).positions if m.name == "dmu50" else default_positions(m)


def _plan_axes(m) -> dict:
    return {a: {"start": float(p[0]), "stop": float(p[-1]), "count": len(p)} for a, p in _positions(m).items()}


def _poses(m, n=2000, seed=0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    pos = _positions(m)
    return np.column_stack([rng.uniform(pos[a].min(), pos[a].max(), n) for a in m.axes])


def fits_vs_tables(model, truth, m) -> list[bool]:
    """Per function of the model: whether its fit is at least as close to the truth as its table."""
    out = []
    for name, f in model.functions.items():
        if f.fit is None:
            continue
        t = truth.functions.get(name)
        tv = t(f.positions) if t is not None else np.zeros_like(f.positions)
        fit_err = np.sqrt(np.mean((f(f.positions) - tv) ** 2))
        tab_err = np.sqrt(np.mean((f.values - tv) ** 2))
        tol = TOL_MM if m.error_names.index(name) % 6 < 3 else TOL_MM * 1e-3
        out.append(bool(fit_err <= tab_err + tol))
    return out


def run(n: int = 54) -> dict:
    logging.getLogger("mtcal").setLevel(logging.WARNING)
    rows = []
    t0 = time.perf_counter()
    for k, m, truth, tracker, rounds, seed in campaigns(n):
        rec, _ = simulate(truth, machine=m, plan={"axes": _plan_axes(m)}, tracker=tracker, rounds=rounds, seed=seed)
        poses = _poses(m)
        for path, kw in PATHS.items():
            model = identify(rec, machine=m, **kw(tracker)).model
            c = compare_models(m, model, truth, poses)
            w = model.meta.get("worth") or {}
            rows.append({"campaign": k, "machine": m.name, "tracker": list(tracker), "rounds": rounds, "seed": seed,
                         "path": path, "gauged_rms_um": c.gauged_rms_um, "truth_rms_um": c.truth_rms_um,
                         "compensated_rms_um": c.compensated_rms_um, "worse": c.worse,
                         "predicted_error_rms_um": w.get("predicted_error_rms_um"), "warned": w.get("may_worsen"),
                         "corrects_rms_um": w.get("corrects_rms_um"),
                         "fit_as_close": fits_vs_tables(model, truth, m)})
        print(f"[{k + 1}/{n}] {m.name} rounds {rounds} tracker {tracker}: "
              + ", ".join(f"{r['path']} {r['gauged_rms_um']:.1f}" for r in rows[-len(PATHS):]) + " um",
              file=sys.stderr, flush=True)
    return {"n_campaigns": n, "seconds": time.perf_counter() - t0, "paths": summarise(rows), "rows": rows}


def summarise(rows: list[dict]) -> dict:
    out = {}
    for path in PATHS:
        r = [x for x in rows if x["path"] == path]
        g = np.array([x["gauged_rms_um"] for x in r])
        fits = [b for x in r for b in x["fit_as_close"]]
        out[path] = {"model_error_median_um": float(np.median(g)), "model_error_p10_um": float(np.percentile(g, 10)),
                     "model_error_p90_um": float(np.percentile(g, 90)),
                     "compensated_median_um": float(np.median([x["compensated_rms_um"] for x in r])),
                     "uncompensated_median_um": float(np.median([x["truth_rms_um"] for x in r])),
                     "worse_share": float(np.mean([x["worse"] for x in r])),
                     "warned_share": float(np.mean([bool(x["warned"]) for x in r])),
                     "worse_not_warned_share": float(np.mean([x["worse"] and not x["warned"] for x in r])),
                     "predicted_over_actual_median": float(np.median([x["predicted_error_rms_um"] / x["gauged_rms_um"]
                                                                      for x in r])),
                     "fit_as_close_share": float(np.mean(fits)) if fits else float("nan")}
    if "auto" in out and "joint+tracker" in out:
        a = np.array([x["gauged_rms_um"] for x in rows if x["path"] == "auto"])
        j = np.array([x["gauged_rms_um"] for x in rows if x["path"] == "joint+tracker"])
        out["auto"]["median_ratio_to_joint_with_tracker"] = float(np.median(a / j))
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=54, help="number of campaigns (default 54)")
    ap.add_argument("--json", help="write every row and the summary to this file")
    args = ap.parse_args()
    res = run(args.n)
    print(f"{'path':20s} {'model-truth um, median (p10-p90)':33s} {'uncompensated um':17s} worse warned "
          f"worse&not-warned predicted/actual fit>=table")
    for path, s in res["paths"].items():
        lo, hi = s["model_error_p10_um"], s["model_error_p90_um"]
        print(f"{path:20s} {s['model_error_median_um']:6.2f} ({lo:.2f}-{hi:.2f}){'':14s} "
              f"{s['uncompensated_median_um']:6.2f}{'':11s} {s['worse_share']:4.0%} {s['warned_share']:5.0%} "
              f"{s['worse_not_warned_share']:9.0%}{'':8s} {s['predicted_over_actual_median']:6.2f}{'':10s} "
              f"{s['fit_as_close_share']:5.1%}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(res, fh, indent=1)
    print(json.dumps({"n_campaigns": res["n_campaigns"], "seconds": round(res["seconds"], 1),
                      "paths": res["paths"]}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
