"""Benchmark: diagnosis of a default simulated campaign (5 axes, 4 rounds, 1680 readings, AT960 noise), tracker
given; and of the bundled demo campaign as a newcomer runs it (`mtcal diagnose demo_campaign.csv`: the station
estimated from the rounds' scatter, issue 34's "under 5 s"), in this process and by the command line (its start,
imports and output included), wall and CPU seconds."""
from __future__ import annotations

import os
import resource
import subprocess
import sys
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
    out.update(demo())
    return out


def demo() -> dict:
    """The bundled demo campaign, station estimated: library call and command line, wall and CPU seconds."""
    import mtcal
    from mtcal.data import path
    from mtcal.diagnose import diagnose

    rec = mtcal.read_recording(path("demo_campaign.csv"))
    t0, c0 = time.perf_counter(), time.process_time()
    diagnose(rec)
    out = {"diagnose_demo_s": time.perf_counter() - t0, "diagnose_demo_cpu_s": time.process_time() - c0}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "mtcal.cli", "diagnose", str(path("demo_campaign.csv")), "--json", "-q"],
                   check=True, capture_output=True, env={**os.environ, "MPLBACKEND": "Agg"})
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    out["diagnose_demo_cli_s"] = time.perf_counter() - t0
    out["diagnose_demo_cli_cpu_s"] = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    out["diagnose_demo_load_average"] = os.getloadavg()[0]
    return out


if __name__ == "__main__":
    import json
    print(json.dumps(run(), indent=2))
