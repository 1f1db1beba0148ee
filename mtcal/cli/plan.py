"""`mtcal plan`: predicted standard uncertainty of every identified error for a tracker placement."""
from __future__ import annotations

import argparse
import logging
import math

from mtcal.cli._options import integer, machine_argument, real, tracker_model_argument, xyz
from mtcal.errors import InputError
from mtcal.io import dumps, refuse_overwrite
from mtcal.kinematics.machine import DEFAULT_MACHINE

NAME = "plan"
HELP = "predict the uncertainty of the identified errors for a tracker placement (linear propagation + Monte Carlo)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--tracker", metavar="x,y,z", type=xyz, help="tracker position in mm, machine frame "
                   "(default: the plan's, else the machine spec's first tracker station)")
    machine_argument(p, DEFAULT_MACHINE)
    p.add_argument("--plan", metavar="PLAN.json", help="measurement plan (schema in mtcal.campaign.simulate)")
    p.add_argument("--monte-carlo", type=integer(0), default=0, metavar="N",
                   help="also run the estimator on N simulated draws (GUM Supplement 1): rounds per axis for the "
                        "three-point method, whole campaigns of the plan for the joint fit; with --target-um: N "
                        "trials of mtcal identify per step of the design's path on Dask, which then decide the "
                        "recommendation")
    p.add_argument("--workers", type=integer(0), metavar="K",
                   help="with --target-um --monte-carlo: local Dask worker processes (default: the cores)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="with --target-um --monte-carlo: an existing Dask cluster (tcp://host:8786)")
    p.add_argument("--exact", action="store_true",
                   help="with --target-um --monte-carlo: every trial runs identify (default: batched trials, as "
                        "mtcal uncertainty)")
    p.add_argument("--estimator", choices=("auto", "joint", "three-point"), default="auto",
                   help="the estimator to predict: auto (default) = the one mtcal identify uses with the same "
                        "inputs: the joint fit (a tracker position given or estimated from the rounds), three-point "
                        "with --weighting none")
    p.add_argument("--seed", type=integer(0), default=0, help="Monte Carlo seed (default 0)")
    tracker_model_argument(p, "the law the prediction weights and draws by")
    p.add_argument("--weighting", choices=("tracker", "none"), default="tracker",
                   help="estimator weighting: the tracker law's covariance (identify --tracker, default) or none")
    p.add_argument("--axes", metavar="X,Y,...", help="axes to report (default: all axes of the plan)")
    p.add_argument("--target-um", type=real(0, unit="um", lo_open=True), metavar="UM",
                   help="design the measurement: recommend stations, reflector spread and rounds for this volumetric "
                        "standard uncertainty of the identified model (um, RMS over the work volume)")
    p.add_argument("--floor", action="append", metavar="x,y",
                   help="with --target-um: an allowed tracker floor position (mm, machine frame; repeatable; "
                        "default: 8 positions 1 m outside the machine's enclosure)")
    p.add_argument("--heights", default="150,1200", metavar="z,...",
                   help="with --target-um: allowed tracker heights (mm, machine frame; default 150,1200)")
    p.add_argument("--max-spread", type=real(1), default=1.0, metavar="K",
                   help="with --target-um: reflector layouts may be spread up to K times the plan's (fixture limit)")
    p.add_argument("--hours", type=real(0, unit="h", lo_open=True), metavar="H",
                   help="with --target-um: measuring time available (h)")
    p.add_argument("--max-stations", type=integer(1), default=4, metavar="N",
                   help="with --target-um: at most N stations")
    p.add_argument("--plot", metavar="PNG",
                   help="write a map of the predicted uncertainty over tracker floor positions")


def _floats(text: str, n: int | None, what: str) -> tuple[float, ...]:
    try:
        v = tuple(float(c) for c in text.split(","))
    except ValueError:
        v = ()
    if not v or (n is not None and len(v) != n) or not all(math.isfinite(c) for c in v):
        raise InputError(f"{what} must be {'x,y' if n == 2 else 'comma-separated numbers'} in mm, got {text!r}")
    return v


def _design(args: argparse.Namespace, plan) -> int:
    from mtcal.planning.stations import default_floor, design
    floor = [_floats(f, 2, "--floor") for f in args.floor] if args.floor else default_floor(plan)
    heights = _floats(args.heights, None, "--heights")
    log = logging.getLogger("mtcal.planning.plan")
    d = design(plan, floor, heights, args.target_um, args.hours, args.max_spread, args.max_stations, progress=log.info)
    if args.monte_carlo:
        d = _design_monte_carlo(d, plan, args)
    if args.json:
        print(dumps(d.to_dict()))
        return 0
    r = d.recommended
    print(f"target {d.target_um:g} um (RMS over the work volume of the identified model's 3-D standard uncertainty): "
          f"{'met' if d.met else 'NOT met'}")
    mc = "" if r.monte_carlo_um is None else f", Monte Carlo {r.monte_carlo_um:.2f} um"
    print(f"recommended: {len(r.stations)} station(s), {r.rounds_per_station} round(s) each, reflectors spread "
          f"{r.reflector_scale:g}x, {r.hours:.1f} h -> predicted {r.model_um:.2f} um{mc} (model and compensated "
          f"machine); decided by {d.decided_by}")
    for label, pos in r.stations:
        print(f"  station {label}: {', '.join(f'{c:g}' for c in pos)} mm")
    print("path: " + " -> ".join(f"{len(p.stations)} st. {p.model_um:.2f} um" + (
        "" if p.monte_carlo_um is None else f" (MC {p.monte_carlo_um:.2f})") for p in d.steps))
    for a in d.alternatives:
        print(f"alternative at the same stations' time: {len(a.stations)} station(s) x {a.rounds_per_station} rounds, "
              f"spread {a.reflector_scale:g}x: {a.model_um:.2f} um")
    return 0


def _design_monte_carlo(d, plan, args: argparse.Namespace):
    """The design's path re-evaluated by the Monte Carlo of identify (mtcal.uncertainty.design), with a progress
    bar over all the trials it may run."""
    from mtcal.cli._words import Bar
    from mtcal.uncertainty.design import design_monte_carlo
    bar = None if (args.quiet or args.json) else Bar(args.monte_carlo * len(d.steps), "mtcal plan")
    try:
        return design_monte_carlo(d, plan, args.monte_carlo, args.seed, args.workers, args.scheduler,
                                  progress=bar.update if bar else None, exact=args.exact)
    finally:
        if bar:
            bar.close()


def run(args: argparse.Namespace) -> int:
    from mtcal.campaign.plans import Plan, load_plan
    from mtcal.kinematics.machine import load_machine
    from mtcal.planning.plan import plan_uncertainty, plot_placement_map

    if args.monte_carlo == 1:
        raise InputError("--monte-carlo needs at least 2 rounds for a standard deviation")
    if args.tracker_model is not None and (args.target_um is not None or args.plot):
        raise InputError("--tracker-model sets the law of the prediction for one placement; the design (--target-um) "
                         "and the map (--plot) still weight by the AT960's: run them without it")
    refuse_overwrite([args.plot], args.plan)
    m = load_machine(args.machine)
    plan = load_plan(args.plan, m) if args.plan else Plan(m)
    if args.target_um is not None:
        return _design(args, plan)
    axes = None if not args.axes else [a.strip().upper() for a in args.axes.split(",") if a.strip()]
    res = plan_uncertainty(args.tracker, plan, monte_carlo_n=args.monte_carlo, seed=args.seed,
                           weighting=args.weighting, axes=axes, estimator=args.estimator,
                           tracker_model=args.tracker_model).to_dict()
    if args.plot:
        logging.getLogger("mtcal.planning.plan").info("computing the placement map ...")
        mp = plot_placement_map(args.plot, plan, tracker=res["tracker"], z=res["tracker"][2])
        res["plot"] = {"path": args.plot, "best_floor_position": mp["best"], "z": res["tracker"][2]}
    if args.json:
        print(dumps(res))
        return 0
    t = res["tracker"]
    passes = "out and back passes averaged" if res["approaches_per_round"] == 2 else "one pass"
    if "joint" in res["estimator"]:
        where = (f"{len(res['stations'])} stations" if res.get("stations") else
                 f"tracker at ({t[0]:g}, {t[1]:g}, {t[2]:g}) mm")
        print(f"{where}; estimator: the joint fit (as mtcal identify with a tracker position); {passes} per round; "
              f"'1 round' = the estimate's sigma x sqrt(rounds); sigma in um / urad")
    else:
        print(f"tracker at ({t[0]:g}, {t[1]:g}, {t[2]:g}) mm; estimator: three-point, one round = {passes}, each 3 "
              f"reflectors vs the round's reference reading; {res['weighting']} weighting; sigma in um / urad")
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
