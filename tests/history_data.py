"""Small result files for the history tests, in the layouts mtcal writes (docs/design.md; the to_dict of each
result): an error model of the DMU 50 with per-position u95 (three-point rounds: k = t_0.975(3)) and squareness
with its joint-fit sigma, and the --json answers of uncertainty, iso230-2, check evaluate, verify and diagnose."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from scipy import stats

K3 = float(stats.t.ppf(0.975, 3))  # four rounds: Student's t of 3 degrees of freedom
POSITIONS = [-200.0, -100.0, 0.0, 100.0, 200.0]


def model_doc(shift: dict | None = None, noise: float = 0.0, seed: int = 0, machine: str = "dmu50") -> dict:
    """An identified model: E_XX (mm) and E_CX (rad) over X, E_C0Y and E_B0Z (rad); ``shift`` adds to a name's
    values ({"E_C0Y": 6e-5} or {"E_XX": (index, 0.01)}); ``noise`` scales a random draw of each value by its own
    standard uncertainty (so ``noise=1`` is a repeat calibration of an unchanged machine)."""
    rng = np.random.default_rng(seed)
    shift = shift or {}
    funcs = {}
    for name, base, sm in (("E_XX", 0.004, 0.0005), ("E_CX", 8e-6, 1e-6)):
        v = base * np.asarray(POSITIONS) / 200.0
        s = np.full(len(POSITIONS), sm)
        s[2] = 0.0  # the reference position
        v = v + noise * s * rng.standard_normal(len(v))
        if name in shift:
            i, dv = shift[name]
            v[i] += dv
        funcs[name] = {"axis": "X", "positions": POSITIONS, "values": v.tolist(), "std": (2 * s).tolist(),
                       "std_mean": s.tolist(), "u95": (K3 * s).tolist(), "n": [4] * len(POSITIONS)}
    sigma = {"E_C0Y": 5e-6, "E_B0Z": 5e-6}
    consts = {n: 1e-5 + noise * sg * rng.standard_normal() + shift.get(n, 0.0) for n, sg in sigma.items()}
    return {"machine": machine, "units": {"length": "mm", "angle": "rad"}, "constants": consts, "functions": funcs,
            "identified_from": "rec.csv", "method": "three-point", "squareness_sigma": sigma,
            "noise_law": {"radial_um": 0.4, "radial_um_per_m": 0.3, "transverse_um": 15.0,
                          "transverse_um_per_m": 6.0, "k": 2.0, "instrument": "AT960", "source": "prior"}}


def uncertainty_doc() -> dict:
    return {"trials": 100, "seed": 0, "p": 0.95, "units": {"length": "mm", "angle": "rad"}, "inputs": {},
            "errors": {"E_XX": {"axis": "X", "positions": [0.0, 100.0], "mean": [0.0, 0.002], "u": [0.0, 1e-4],
                                "lo95": [0.0, 0.0018], "hi95": [0.0, 0.0022]}},
            "constants": {"E_C0Y": {"mean": 1e-5, "lo95": 0.5e-5, "hi95": 1.5e-5}},
            "volumetric": {"poses": [[0, 0, 0, 0, 0]], "deviation_xyz_mm": [[0, 0, 0]], "u95_max_mm": 0.0031}}


def iso_doc() -> dict:
    t = {k: [1.0, 2.0] for k in ("n_up", "n_down", "mean_up", "mean_down", "mean", "reversal", "s_up", "s_down",
                                 "R_up", "R_down", "R")}
    return {"file": "rec.csv", "standard": "ISO 230-2:2014", "temperature_normalisation": None,
            "axes": {"X": {"axis": "X", "kind": "linear", "unit": "um", "position_unit": "mm",
                           "positions": [0.0, 100.0], "targets": t, "parameters": {"A": 3.5, "E": 2.0, "R": 1.2},
                           "parameter_meaning": {}, "runs": [], "notes": []}}}


def check_doc() -> dict:
    trace = [[float(a), 1e-3 * np.sin(np.radians(2 * a)), 0.9e-3 * np.sin(np.radians(2 * a)), 2e-4, d]
             for d in (1, -1) for a in range(0, 360, 10)]
    return {"kind": "circular", "source": "ballbar.csv", "plane": "XY", "radius_mm": 150.0, "centre_mm": [0, 0, 0],
            "measured": {"G_mm": 0.004, "H_mm": 0.001, "F_mm": 0.003},
            "predicted": {"G_mm": 0.0038, "H_mm": 0.0, "F_mm": 0.003}, "residual": {}, "prediction_u95_mm": 0.0008,
            "noise_sd_mm": 1e-4, "agrees": True, "worst_z": 1.2, "k_agree": 3.0, "findings": [], "trace": trace}


def verify_doc() -> dict:
    return {"source": "after.csv", "passed": False, "k": 2.0,
            "errors": [{"name": "E_XX", "text": "E_XX left 3 um at X = 200", "within": False}], "not_covered": []}


def diagnose_doc() -> dict:
    return {"machine": "dmu50", "recording": "rec.csv", "base_sigma": 1e-3, "base_sigma_ratio": 1.4,
            "sigma_after": 1e-3, "sigma_ratio_after": 1.0, "located": [], "unexplained": [],
            "effects": [{"name": "backlash", "axis": "X", "direction": None, "significant": True, "estimate": 0.006,
                         "sigma_after": 1e-3, "evidence": {}, "interval_95": [0.0055, 0.0065]}],
            "noise_model": {"law": {"instrument": "AT960"}}}


def write(path: Path, doc: dict) -> Path:
    path.write_text(json.dumps(doc))
    return path
