"""False-positive rate of ``mtcal diagnose`` at its defaults (no --tracker, the level mtcal.diagnose.run.LEVEL) on
clean campaigns.

Campaigns from the physical simulator (mtcal.campaign.simulate, AT960 noise, no planted effect) of varied design: the
tracker in front (the spec's station), at the side, or far; 3 to 6 rounds; five axes or three; every second
position of the default plan (kept small).  A campaign is a false positive when any effect is reported
significant or any mismatch "unexplained".  Run: python benchmarks/fp_rate_diagnose.py [N] (default 50).
"""
from __future__ import annotations

import sys

import numpy as np

from mtcal.campaign.plans import Plan
from mtcal.campaign.simulate import simulate_campaign
from mtcal.diagnose import diagnose
from mtcal.diagnose.run import LEVEL

STATIONS = {"front": None, "side": (1900.0, 250.0, 350.0), "far": (400.0, -4500.0, 900.0)}
AXES = ("XYZBC", "XYC", "YZB")


def clean_campaign(i: int):
    """The i-th campaign of the varied design (deterministic: seed 1000 + i)."""
    rng = np.random.default_rng(1000 + i)
    station = list(STATIONS)[i % 3]
    axes = AXES[(i // 3) % 3]
    rounds = int(rng.integers(3, 7))
    pos = Plan().positions
    plan = {"axes": {a: {"positions": pos[a][::2].tolist()} for a in axes}, "rounds": rounds}
    rec = simulate_campaign(seed=1000 + i, plan=plan, rounds=None, tracker=STATIONS[station])
    return rec, f"{station} {axes} {rounds} rounds"


def false_alarms(d) -> list[str]:
    return ([f"{e.name} {e.axis or ''} {e.get('where', '')}" for e in d.effects if e.significant] +
            [f"unexplained {u.axis} {u.by} {u.where}" for u in d.unexplained])


def main(n: int = 50) -> int:
    hits = 0
    for i in range(n):
        rec, label = clean_campaign(i)
        d = diagnose(rec)
        fa = false_alarms(d)
        hits += bool(fa)
        print(f"{i:3d} {label:<28} noise {d.noise.kind:<26} ratio {d.base_sigma_ratio:.3f}  {'; '.join(fa) or 'clean'}",
              flush=True)
    print(f"false positives: {hits} of {n} campaigns ({hits / n:.3f}); level {LEVEL:g}")
    return hits


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 50)
