"""The demo's multi-station step (issue 14): the thesis' single station next to four stations at equal measuring
time, on the demo's true machine.

Both campaigns are simulated now from the demo's truth with its campaign plan (positions and reflectors of the
demo campaign, no concealed effect): one station at the campaign's tracker position with its rounds (the thesis:
Pos. 1, 4 rounds), identified by the three-point method (the thesis') and by the joint fit; and four stations
(front, left, front-right at the single station's height, front-left raised by 1.05 m; placed 1 m outside the
machine's enclosure, mtcal.planning.stations.default_floor) with one round each, misaligned by N(0, 20 um) /
N(0, 30 urad), identified jointly.  For each: model - truth (volumetric RMS over the demo's poses, um), the
predicted uncertainty (mtcal.planning.stations.predict, four stations), and the tool-tip error on the true machine of
the sample program compensated with that model (``compensate`` callback of mtcal.demo.run).
"""
from __future__ import annotations

import numpy as np

from mtcal.campaign.plans import as_plan
from mtcal.campaign.simulate import simulate
from mtcal.campaign.stations import simulate_stations
from mtcal.identify.run import identify
from mtcal.planning.stations import default_floor, predict

RAISE_MM = 1050.0  # the elevated station: ~1.2 m above the floor when the others stand at 0.15 m


def campaign_plan(m, planted: dict):
    """The demo campaign's plan (positions, reflectors, rounds, tracker) from its truth sidecar."""
    return as_plan({"axes": {a: {"positions": v["positions"]} for a, v in planted["axes"].items()},
                    "points": planted["points"], "rounds": planted["rounds"], "tracker": planted["tracker"]}, m)


def four_stations(plan) -> list[tuple[str, tuple[float, float, float]]]:
    """Front, left, front-right and a raised front-left station around the plan's machine (mm)."""
    floor = default_floor(plan)  # x outer loop: (x0,y0) (x0,yc) (x0,y1) (xc,y0) (xc,y1) (x1,y0) (x1,yc) (x1,y1)
    z = float(plan.tracker[2])
    (fl, left, _, front, _, fr, _, _) = floor
    return [("front", (*front, z)), ("left", (*left, z)), ("front-right", (*fr, z)),
            ("elevated", (*fl, z + RAISE_MM))]


def run_stations(m, truth, planted: dict, volumetric, compensate, seed: int = 1) -> dict:
    """Summary dict of the step; ``volumetric(model)`` -> model - truth RMS um, ``compensate(model, name)`` ->
    (before, after) tool-tip errors (mm) of the sample program on the true machine."""
    plan = campaign_plan(m, planted)
    one, _ = simulate(truth, machine=m, plan=plan, rounds=None, seed=seed)
    stations = four_stations(plan)
    four, _ = simulate_stations(truth, stations, machine=m, plan=plan, rounds=max(1, plan.rounds // len(stations)),
                                seed=seed)
    t = plan.tracker
    cases = {"one_station_three_point": identify(one, tracker=t, machine=m, method="three-point").model,
             "one_station_joint": identify(one, tracker=t, machine=m, method="joint").model,
             "four_stations_joint": identify(four, machine=m).model}
    out = {"stations": [{"label": s, "tracker": list(x)} for s, x in stations], "rounds_one_station": plan.rounds,
           "rounds_per_station": max(1, plan.rounds // len(stations)),
           "predicted_four_stations_um": predict(plan, stations, max(1, plan.rounds // len(stations))).model_um,
           "predicted_one_station_um": predict(plan, [("one", t)], plan.rounds).model_um}
    for name, model in cases.items():
        before, after = compensate(model, name)
        out[name] = {"model_minus_true_rms_um": volumetric(model),
                     "compensated_rms_um": float(np.sqrt(np.mean(after**2)) * 1e3),
                     "compensated_max_um": float(after.max() * 1e3),
                     "uncompensated_rms_um": float(np.sqrt(np.mean(before**2)) * 1e3)}
    return out


ROWS = [("one station, three-point (thesis)", "one_station_three_point"),
        ("one station, joint fit", "one_station_joint"), ("four stations, joint fit", "four_stations_joint")]


def plot_stations(s: dict, path) -> None:
    """Bar chart (PNG) of the step: model - truth RMS and the compensated program's RMS on the true machine, um."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mtcal.io import save_figure
    x = np.arange(len(ROWS))
    fig, ax = plt.subplots(figsize=(8, 3.5))
    for dx, key, label in ((-0.2, "model_minus_true_rms_um", "model - truth, volumetric RMS"),
                           (0.2, "compensated_rms_um", "compensated program on the true machine, RMS")):
        ax.bar(x + dx, [s[k][key] for _, k in ROWS], width=0.4, label=label)
    ax.set_xticks(x, [label for label, _ in ROWS])
    ax.set_ylabel("um")
    ax.set_title("one tracker station vs four at equal measuring time")
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, path)
    plt.close(fig)


def report_lines(s: dict) -> list[str]:
    """Markdown of the step."""
    lines = ["", "## Several tracker stations at equal measuring time", "",
             f"One station ({s['rounds_one_station']} rounds) vs four stations ({s['rounds_per_station']} round(s) "
             "each, every station misaligned by ~20 um / 30 urad): " + "; ".join(
                 f"{d['label']} at ({', '.join(f'{c:.0f}' for c in d['tracker'])}) mm" for d in s["stations"]), "",
             "| campaign | model - truth RMS (um) | compensated program RMS / max (um) |", "|---|---|---|"]
    for label, k in ROWS:
        v = s[k]
        lines.append(f"| {label} | {v['model_minus_true_rms_um']:.2f} | {v['compensated_rms_um']:.2f} / "
                     f"{v['compensated_max_um']:.2f} |")
    lines += ["", f"Predicted (linear propagation through the joint estimator, per-position estimates): one station "
              f"{s['predicted_one_station_um']:.2f} um, four stations {s['predicted_four_stations_um']:.2f} um; the "
              "fitted functions smooth below that.", "", "![stations](plots/stations.png)"]
    return lines
