"""Benchmark: three-point identification of a full simulated campaign (X, Y, Z, B, C; 4 bidirectional rounds;
thesis plan: 11 positions per linear axis, B 0-180 step 10, C 0-340 step 20; 1680 readings).  Target < 1 s."""
from __future__ import annotations

import numpy as np
from timing import best_of


def run() -> dict:
    from mtcal.campaign.plans import Plan
    from mtcal.campaign.simulate import simulate_campaign
    from mtcal.generated import threepoint_numpy as tp
    from mtcal.identify.run import identify
    DEFAULT_TRACKER = Plan().tracker

    rec = simulate_campaign(None, tracker=DEFAULT_TRACKER, seed=0)
    identify(rec)  # warm-up (imports, first calls)
    rng = np.random.default_rng(0)
    pts, dls = rng.uniform(-200, 200, (100_000, 9)), rng.normal(0, 0.01, (100_000, 9))
    return {
        "identify_campaign_three_point_s": best_of(lambda: identify(rec, method="three-point", worth=False), 5),
        "identify_campaign_joint_s": best_of(lambda: identify(rec, tracker=DEFAULT_TRACKER, worth=False), 5),
        # identify's default: the station estimated from the scatter, the joint fit, and the split-half prediction
        # of the model's error (two more fits)
        "identify_campaign_default_s": best_of(lambda: identify(rec), 3),
        "readings": len(rec),
        "ls_solve_per_position_us": best_of(lambda: tp.ls_solve(pts, dls), 5) / 1e5 * 1e6,
    }


if __name__ == "__main__":
    for k, v in run().items():
        print(f"{k}: {v:.4g}" if isinstance(v, float) else f"{k}: {v}")
