"""`mtcal plan`: predicted standard uncertainty of every identified error for a tracker placement."""
from __future__ import annotations

import argparse
import logging

from mtcal.io import dumps
from mtcal.tracker import parse_xyz
from mtcal.commands._options import machine_argument
from mtcal.machine import DEFAULT_MACHINE

NAME = "plan"
HELP = "predict the uncertainty of the identified errors for a tracker placement (linear propagation + Monte Carlo)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--tracker", metavar="x,y,z", help="tracker position in mm, machine frame "
                   "(default: the plan's, else the machine spec's first tracker station)")
    machine_argument(p, DEFAULT_MACHINE)
    p.add_argument("--plan", metavar="PLAN.json", help="measurement plan (schema in mtcal.simulate)")
    p.add_argument("--monte-carlo", type=int, default=0, metavar="N",
                   help="also run N simulated rounds per axis through the estimator (GUM Supplement 1)")
    p.add_argument("--seed", type=int, default=0, help="Monte Carlo seed (default 0)")
    p.add_argument("--weighting", choices=("tracker", "none"), default="tracker",
                   help="estimator weighting: AT960 covariance (identify --tracker, default) or none")
    p.add_argument("--axes", metavar="X,Y,...", help="axes to report (default: all axes of the plan)")
    p.add_argument("--plot", metavar="PNG", help="write a map of the predicted uncertainty over tracker floor positions")


def run(args: argparse.Namespace) -> int:
    from mtcal.plan import plan_uncertainty, plot_placement_map
    from mtcal.machine import load_machine
    from mtcal.simulate import Plan, load_plan

    if args.monte_carlo < 0:
        raise ValueError(f"--monte-carlo must be >= 0, got {args.monte_carlo}")
    if args.monte_carlo == 1:
        raise ValueError("--monte-carlo needs at least 2 rounds for a standard deviation")
    m = load_machine(args.machine)
    plan = load_plan(args.plan, m) if args.plan else Plan(m)
    tracker = parse_xyz(args.tracker) if args.tracker is not None else None
    axes = None if not args.axes else [a.strip().upper() for a in args.axes.split(",") if a.strip()]
    res = plan_uncertainty(tracker, plan, monte_carlo_n=args.monte_carlo, seed=args.seed,
                           weighting=args.weighting, axes=axes).to_dict()
    if args.plot:
        logging.getLogger("mtcal.plan").info("computing the placement map ...")
        mp = plot_placement_map(args.plot, plan, tracker=res["tracker"], z=res["tracker"][2])
        res["plot"] = {"path": args.plot, "best_floor_position": mp["best"], "z": res["tracker"][2]}
    if args.json:
        print(dumps(res))
        return 0
    t = res["tracker"]
    passes = "out and back passes averaged" if res["approaches_per_round"] == 2 else "one pass"
    print(f"tracker at ({t[0]:g}, {t[1]:g}, {t[2]:g}) mm; one round = {passes}, each 3 reflectors vs the round's "
          f"reference reading; {res['weighting']} weighting; sigma in um / urad")
    mc = res.get("monte_carlo", {}).get("axes", {})
    mean_label = f"mean of {res['rounds']}"
    head = f"{'error':8s} {'unit':5s} {'1 round':>9s}" + (f" {'MC':>9s}" if mc else "") + f" {mean_label:>11s}"
    for a, vals in res["axes"].items():
        print(f"\naxis {a} at {res['mid_travel'][a]:g} {m.unit(a)} (mid-travel)")
        print(head)
        for n, v in vals.items():
            f, unit = (1e3, "um") if n[2] in "XYZ" else (1e6, "urad")  # E_X.., E_Y.., E_Z..: translations
            line = f"{n:8s} {unit:5s} {v * f:9.2f}"
            if mc:
                line += f" {mc[a][n] * f:9.2f}"
            line += f" {res['mean_of_rounds'][a][n] * f:11.2f}"
            print(line)
    if args.plot:
        b = res["plot"]["best_floor_position"]
        print(f"\nplot: {args.plot}; best floor position on the grid (x, y, mm): translational {b['translational']}, "
              f"angular {b['angular']}")
    return 0
