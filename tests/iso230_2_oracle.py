"""An evaluation of ISO 230-2:2014 written from the standard's terms and definitions (clause 3), independent of
mtcal/iso230_2/evaluation.py (plain loops, no shared code), for the tests and benchmarks/iso230_2_public.py.

Input: readings[(i, j, direction)] = P_ij, the measured position of run j at target i approached in direction
"up" or "down", and targets[i] = P_i, in one unit.  Every x_ij = P_ij - P_i is taken from the same datum (3.x:
"positional deviation: actual position reached minus target position").  A missing reading is skipped.
  x_mean_up_i = mean_j x_ij(up)            mean unidirectional positional deviation at a position
  x_mean_i    = (x_mean_up_i + x_mean_down_i) / 2       mean bidirectional positional deviation at a position
  B_i         = x_mean_up_i - x_mean_down_i             reversal value at a position
  B = max |B_i|;  B_mean = mean B_i                     reversal value of an axis; mean reversal value
  s_up_i      = sqrt(sum_j (x_ij - x_mean_up_i)^2 / (n - 1))   estimator of the unidirectional standard uncertainty
  R_up_i = 4 s_up_i;  R_i = max(2 s_up_i + 2 s_down_i + |B_i|, R_up_i, R_down_i)   repeatability at a position
  R_up = max R_up_i;  R = max R_i                       repeatability of an axis
  E_up = max x_mean_up_i - min x_mean_up_i;  E = max over both directions' means - min over both
  M = max x_mean_i - min x_mean_i                       range of the mean bidirectional positional deviation
  A_up = max(x_mean_up_i + 2 s_up_i) - min(x_mean_up_i - 2 s_up_i);  A = max over both directions of
        (x_mean + 2 s) - min over both of (x_mean - 2 s)   accuracy
(the standard's clause 3, terms and definitions, in its words' order; no clause numbers cited here)
"""
from __future__ import annotations

import math


def _mean(v):
    return sum(v) / len(v)


def _s(v):
    m = _mean(v)
    return math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1))


def evaluate(targets: dict, readings: dict) -> dict:
    """targets {i: P_i}; readings {(i, j, "up"|"down"): P_ij} -> {"A", "A_up", "A_down", "E", "E_up", "E_down",
    "M", "R", "R_up", "R_down", "B", "B_mean"} in the input's unit."""
    per = {}
    for i, p_i in targets.items():
        row = {}
        for d in ("up", "down"):
            x = [readings[k] - p_i for k in sorted(readings) if k[0] == i and k[2] == d]
            row[d] = (_mean(x), _s(x))
        row["mean"] = (row["up"][0] + row["down"][0]) / 2
        row["B"] = row["up"][0] - row["down"][0]
        row["R"] = max(2 * row["up"][1] + 2 * row["down"][1] + abs(row["B"]), 4 * row["up"][1], 4 * row["down"][1])
        per[i] = row
    out = {}
    for d in ("up", "down"):
        means = [r[d][0] for r in per.values()]
        out[f"E_{d}"] = max(means) - min(means)
        out[f"R_{d}"] = max(4 * r[d][1] for r in per.values())
        hi = max(r[d][0] + 2 * r[d][1] for r in per.values())
        out[f"A_{d}"] = hi - min(r[d][0] - 2 * r[d][1] for r in per.values())
    both = [r[d][0] for r in per.values() for d in ("up", "down")]
    out["E"] = max(both) - min(both)
    out["M"] = max(r["mean"] for r in per.values()) - min(r["mean"] for r in per.values())
    out["R"] = max(r["R"] for r in per.values())
    out["B"] = max(abs(r["B"]) for r in per.values())
    out["B_mean"] = _mean([r["B"] for r in per.values()])
    hi = max(r[d][0] + 2 * r[d][1] for r in per.values() for d in ("up", "down"))
    lo = min(r[d][0] - 2 * r[d][1] for r in per.values() for d in ("up", "down"))
    out["A"] = hi - lo
    return out


def read_dat(text: str) -> tuple[dict, dict, str]:
    """The `TGT_DATA[i]=`, `REF_DATA_FWD[i,j]=`, `REF_DATA_BWD[i,j]=` lines of an ecmc_target_muts_logger
    `*_ISO230.dat` file (its forward block is the upward approach) -> (targets, readings, unit)."""
    targets, readings, unit = {}, {}, "mm"
    for line in text.splitlines():
        if line.startswith("UNIT="):
            unit = line.split("=", 1)[1].strip()
        for key, d in (("REF_DATA_FWD[", "up"), ("REF_DATA_BWD[", "down")):
            if line.startswith(key):
                idx, val = line[len(key):].split("]=")
                i, j = (int(v) for v in idx.split(","))
                readings[(i, j, d)] = float(val)
        if line.startswith("TGT_DATA["):
            idx, val = line[len("TGT_DATA["):].split("]=")
            targets[int(idx)] = float(val)
    return targets, readings, unit
