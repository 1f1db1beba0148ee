"""The docs's "Proof of concealment" table: one planted effect on the full default campaign (seed 11, tracker at
the spec's first station, AT960 noise); the base lacks the effect (fitted for the effects that are not
quasi-static, an empty given model for the quasi-static ones).  Prints what is found first, its estimate and the
sigma ratio before -> after.  Run: python benchmarks/diagnose_concealment.py [--per-axis-positions]."""
from __future__ import annotations

import sys

from mtcal.campaign.plans import Plan
from mtcal.campaign.simulate import simulate_campaign
from mtcal.diagnose import diagnose
from mtcal.model.errormodel import ErrorModel

ROWS = [  # (effect, parameters, base: "fit" = fitted, "model" = an empty given model)
    ("backlash", {"axis": "X", "amount": 0.004}, "fit"),
    ("backlash", {"axis": "C", "amount": 20e-6}, "fit"),
    ("periodic", {"axis": "Y", "amplitude": 0.002, "pitch": 120.0}, "fit"),
    ("periodic", {"axis": "C", "amplitude": 10e-6, "pitch": 45.0}, "fit"),  # 8 per turn: above the harmonics
    ("thermal_drift", {"amplitude": 0.004, "direction": "+Y", "tau_s": 1800.0}, "fit"),
    ("outlier", {"axis": "X", "size": 0.05, "direction": "+Z"}, "fit"),
    ("outlier", {"axis": "B", "size": 0.03, "mode": "bump"}, "fit"),
    ("scale", {"axis": "X", "ppm": 20.0}, "model"),
    ("second_order", {"error": "E_YY", "coefficient": 2e-8}, "model"),
    ("squareness", {"error": "E_C0Y", "value": 20e-6}, "model"),
    ("rotary_location", {"error": "E_X0C", "value": 0.005}, "model"),
    ("tracker_scale", {"ppm": 2.0}, "model"),
    ("offset", {"size": 0.03, "direction": "+X", "t_from_s": 3000.0}, "fit"),
    # below the tracker's noise (the text under the table)
    ("thermal_drift", {}, "fit"),
    ("periodic", {"axis": "X", "amplitude": 0.002}, "fit"),
    ("second_order", {"error": "E_XX", "coefficient": 2e-8}, "model"),
]


def main(tie: bool = True) -> None:
    for name, params, base in ROWS:
        rec = simulate_campaign(seed=11, effects=[(name, params)])
        d = diagnose(rec, ErrorModel() if base == "model" else None, tracker=Plan().tracker, tie_positions=tie)
        found = [e for e in d.effects if e["significant"]]
        top = (f"{found[0]['name']} {found[0].get('axis') or ''} {found[0].get('where', '')}: "
               f"{found[0]['estimate']:.4g} +- {found[0].get('uncertainty') or 0:.2g} {found[0].get('unit', '')}"
               if found else "nothing")
        print(f"{name} {params} ({base}): {top} | significant {len(found)} | sigma ratio "
              f"{d.base_sigma_ratio:.3f} -> {d.sigma_ratio_after:.3f}", flush=True)


if __name__ == "__main__":
    main(tie="--per-axis-positions" not in sys.argv[1:])
