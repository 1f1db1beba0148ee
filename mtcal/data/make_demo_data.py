"""Writes the demo's bundled data (byte-identical on every run: fixed seeds):

* demo_truth.json: a DMU 50 with errors of the magnitudes Ellingsdalen measured (positioning ~20 um,
  straightness ~5 um, angular ~20-40 urad, squareness ~10-20 urad, rotary location ~10 um); invented smooth
  curves, zero at the reference position;
* demo_campaign.csv (+ demo_campaign.truth.json): a simulated laser-tracker campaign of that machine, travel
  centred on the C axis, tracker at the thesis' Pos. 1, AT960 noise, and one concealed effect (DEMO_EFFECT)
  that the truth model does not contain.

Run `python -m mtcal.data.make_demo_data` to rewrite them.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from mtcal.model.errormodel import ErrorFunction, ErrorModel, save_model

HERE = Path(__file__).resolve().parent
TRAVEL = {"X": (-250.0, 250.0), "Y": (-225.0, 225.0), "Z": (-200.0, 200.0)}
SIZE_UM = {"pos": 20.0, "str": 5.0}
SIZE_URAD = {"lin": 25.0, "rot": 15.0}


def _curve(rng: np.random.Generator, s: np.ndarray, amp: float) -> np.ndarray:
    """Smooth cubic through 0 at s = 0 with peak magnitude ~amp on s in [-1, 1]."""
    c = rng.normal(size=3)
    v = c[0] * s + c[1] * s**2 + c[2] * s**3
    return amp * v / max(np.abs(v).max(), 1e-12)


def build() -> ErrorModel:
    rng = np.random.default_rng(20210601)
    funcs: dict[str, ErrorFunction] = {}
    for j, (lo, hi) in TRAVEL.items():
        pos = np.linspace(lo, hi, 21)
        s = pos / hi
        for c in "XYZABC":
            amp = (SIZE_UM["pos"] if c == j else SIZE_UM["str"]) * 1e-3 if c in "XYZ" else SIZE_URAD["lin"] * 1e-6
            funcs[f"E_{c}{j}"] = ErrorFunction(j, pos, np.round(_curve(rng, s, amp), 9))
    b = np.arange(0.0, 181.0, 10.0)
    for c in "XYZABC":
        amp = 8e-3 if c in "XYZ" else SIZE_URAD["rot"] * 1e-6
        funcs[f"E_{c}B"] = ErrorFunction("B", b, np.round(_curve(rng, b / 180.0, amp), 9))
    for c in "XYZABC":  # C: periodic, zero at C = 0: a (1 - cos) + b sin + second harmonic
        amp = 6e-3 if c in "XYZ" else 12e-6
        a1, b1, a2, b2 = rng.normal(size=4) * amp / 2
        fit = {"kind": "harmonic", "period": 360.0, "a0": float(a1 + a2), "cos": [float(-a1), float(-a2)],
               "sin": [float(b1), float(b2)]}
        grid = np.arange(0.0, 361.0, 20.0)
        f = ErrorFunction("C", grid, np.zeros_like(grid), fit)
        f.values = np.round(f(grid), 12)
        funcs[f"E_{c}C"] = f
    consts = {"E_C0Y": 18e-6, "E_B0Z": -11e-6, "E_A0Z": 7e-6,
              "E_X0B": 0.012, "E_Y0B": -0.007, "E_A0B": 9e-6, "E_B0B": -14e-6,
              "E_X0C": 0.010, "E_Y0C": -0.006, "E_A0C": 6e-6, "E_B0C": -8e-6}
    return ErrorModel("dmu50", consts, funcs, {"note": "demo truth: thesis-magnitude errors (invented curves)"})


def build_for(machine, seed: int = 20210601) -> ErrorModel:
    """A synthetic truth of any machine (mtcal.Machine) with the same magnitudes as ``build``: smooth curves of
    every error motion of every axis over its campaign positions (spec), zero at the reference position (the
    position closest to zero); harmonic for a rotary axis measured over (nearly) a full turn; squareness
    ~15 urad, location ~10 um / ~8 urad.  For `mtcal demo --machine NAME` on machines without bundled data."""
    from mtcal.identify import fitting
    from mtcal.kinematics.defaults import default_positions
    rng = np.random.default_rng(seed)
    funcs: dict[str, ErrorFunction] = {}
    for a, pos in default_positions(machine).items():
        q0 = pos[np.argmin(np.abs(pos))]
        s = (pos - q0) / np.abs(pos - q0).max()
        linear = machine.kind(a) == "linear"
        for n in machine.error_motions(a):
            trans = n[2] in "XYZ"
            if linear:
                amp = (SIZE_UM["pos"] if n == machine.positioning_errors[a] else SIZE_UM["str"]) * 1e-3 if trans \
                    else SIZE_URAD["lin"] * 1e-6
            else:
                amp = 6e-3 if trans else SIZE_URAD["rot"] * 1e-6
            if not linear and fitting.is_periodic(pos):
                a1, b1 = rng.normal(size=2) * amp / 2
                t = np.radians(pos - q0)
                funcs[n] = ErrorFunction(a, pos, np.round(a1 * (1 - np.cos(t)) + b1 * np.sin(t), 12))
            else:
                funcs[n] = ErrorFunction(a, pos, np.round(_curve(rng, s, amp), 9))
    g = machine.error_groups
    consts = {n: float(np.round(rng.normal() * 15e-6, 9)) for n in g["squareness"]}
    consts.update({n: float(np.round(rng.normal() * (0.010 if n[2] in "XY" else 8e-6), 9)) for n in g["location"]})
    return ErrorModel(machine.name, consts, funcs, {"note": f"demo truth of {machine.name}: thesis-magnitude errors "
                                                            f"(invented curves)"})


DEMO_PLAN = {"axes": {"X": {"start": -250, "stop": 250, "count": 11}, "Y": {"start": -225, "stop": 225, "count": 11},
                      "Z": {"start": -200, "stop": 200, "count": 11}, "B": {"start": 0, "stop": 180, "count": 19},
                      "C": {"start": 0, "stop": 340, "count": 18}},
             "tracker": [250.0, -1500.0, 150.0], "rounds": 4}
DEMO_EFFECT = ("backlash", {"axis": "X", "amount": 0.006})
DEMO_SEED = 2021


def write_all() -> None:
    from mtcal.campaign.simulate import simulate, write_campaign
    truth = build()
    save_model(truth, HERE / "demo_truth.json")
    rec, planted = simulate(truth, plan=DEMO_PLAN, rounds=None, seed=DEMO_SEED, effects=[DEMO_EFFECT])
    write_campaign(rec, planted, HERE / "demo_campaign.csv")
    print(f"wrote demo_truth.json and demo_campaign.csv ({len(rec)} readings) to {HERE}")


if __name__ == "__main__":
    write_all()
