"""ISO 230-2 on the public axis shipped in tests/data (b02/x of anderssandstrom/ecmc_target_muts_logger, 9 targets
x 5 runs each way against a reference sensor): mtcal's parameters and their largest difference from the standard's
definitions evaluated independently (tests/iso230_2_oracle.py), in µm.  The guide quotes them; the other public
sets need a fetched copy (benchmarks/iso230_2_public.py).  Run alone: ``python benchmarks/bench_iso230_2.py``."""
from __future__ import annotations

import csv
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
B02 = ROOT / "tests" / "data" / "iso230_2_b02_x.csv"
KEYS = ("A", "A_up", "A_down", "E", "E_up", "E_down", "M", "R", "R_up", "R_down", "B", "B_mean")


def run() -> dict:
    sys.path.insert(0, str(ROOT / "tests"))
    from iso230_2_oracle import evaluate as oracle

    from mtcal.iso230_2.evaluation import evaluate_runs
    from mtcal.iso230_2.readings import read_readings

    runs, kind = read_readings(B02)[:2]
    ours = evaluate_runs(runs, "X", kind).parameters
    rows = list(csv.DictReader(line for line in B02.read_text().splitlines() if not line.startswith("#")))
    targets = {float(r["target_mm"]): float(r["target_mm"]) for r in rows}
    readings = {(float(r["target_mm"]), int(r["run"]), r["direction"]): float(r["measured_mm"]) for r in rows}
    ref = {k: v * 1e3 for k, v in oracle(targets, readings).items()}  # mm -> µm
    out = {f"iso230_2_b02_x_{k}_um": ours[k] for k in KEYS}
    out["iso230_2_b02_x_vs_independent_max_um"] = max(abs(ours[k] - ref[k]) for k in ref)
    return out


if __name__ == "__main__":
    print(json.dumps(run(), indent=1, sort_keys=True))
