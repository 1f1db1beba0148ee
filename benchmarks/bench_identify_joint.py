"""Benchmark: the joint weighted fit (mtcal.identify.joint) of the spec's full campaign (X, Y, Z, B, C; 11 positions
per linear axis, B 0-180 step 10, C 0-340 step 20, bidirectional) from one station (4 rounds) and from four
stations (1 round each, the same 1680 readings), against the three-point method on the same one-station data
timed in this run.  It must stay interactive: seconds."""
from __future__ import annotations

from timing import best_of


def run() -> dict:
    from mtcal.campaign.plans import Plan
    from mtcal.campaign.simulate import simulate_campaign
    from mtcal.campaign.stations import simulate_stations
    from mtcal.identify.run import identify

    tracker = Plan().tracker
    one = simulate_campaign(None, tracker=tracker, seed=0)
    four, _ = simulate_stations(None, [tracker, (-1500, 0, 150), (1300, -1300, 150), (-1000, -1000, 1200)],
                                rounds=1, seed=0)
    identify(one, tracker=tracker)  # warm-up
    t3 = best_of(lambda: identify(one, tracker=tracker, method="three-point"), 3)
    t1 = best_of(lambda: identify(one, tracker=tracker, method="joint"), 3)
    t4 = best_of(lambda: identify(four, method="joint"), 3)
    return {"readings": len(one), "identify_three_point_1_station_s": t3, "identify_joint_1_station_s": t1,
            "identify_joint_4_stations_s": t4, "joint_1_station_vs_three_point": t1 / t3,
            "joint_4_vs_1_station": t4 / t1}


if __name__ == "__main__":
    for k, v in run().items():
        print(f"{k}: {v:.4g}" if isinstance(v, float) else f"{k}: {v}")
