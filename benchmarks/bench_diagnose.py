"""Benchmark: diagnosis of a default simulated campaign (5 axes, 4 rounds, 1680 readings, AT960 noise)."""
from __future__ import annotations

import time


def run() -> dict:
    from mtcal.campaign.plans import Plan
    from mtcal.campaign.simulate import simulate_campaign
    from mtcal.diagnose import diagnose
    DEFAULT_TRACKER = Plan().tracker

    out = {}
    for label, effects in (("clean", ()), ("backlash_x", [("backlash", {"axis": "X", "amount": 0.004})])):
        rec = simulate_campaign(seed=0, effects=effects)
        t0 = time.perf_counter()
        d = diagnose(rec, tracker=DEFAULT_TRACKER)
        out[f"diagnose_default_campaign_{label}_s"] = time.perf_counter() - t0
        out[f"diagnose_{label}_significant_effects"] = sum(e["significant"] for e in d.effects)
        out[f"diagnose_{label}_sigma_ratio_after"] = d.sigma_ratio_after
    out["readings"] = len(rec)
    return out


if __name__ == "__main__":
    import json
    print(json.dumps(run(), indent=2))
