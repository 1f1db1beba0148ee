"""`mtcal simulate`: a virtual laser-tracker campaign -> tidy recording CSV + REC.truth.json (planted truth)."""
from __future__ import annotations

import argparse
import logging

from mtcal.campaign import effects as fx
from mtcal.cli._options import integer, machine_argument, real, tracker_model_argument, xyz
from mtcal.errors import InputError
from mtcal.io import dumps, refuse_overwrite

NAME = "simulate"
log = logging.getLogger("mtcal." + NAME)
HELP = "simulate laser-tracker recordings from an error model, a tracker placement and planted effects"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--model", metavar="MODEL.json", help="error model of the simulated machine (default: no errors)")
    p.add_argument("--plan", metavar="PLAN.json", help="measurement plan: positions, points, rounds, times "
                   "(schema in mtcal.campaign.simulate; default: the thesis campaign)")
    p.add_argument("--alignment-um", type=real(0, unit="um"), default=None, metavar="UM",
                   help="several stations: 1-sigma alignment error of each station, translation (default 20 um)")
    p.add_argument("--alignment-urad", type=real(0, unit="urad"), default=None, metavar="URAD",
                   help="several stations: 1-sigma alignment error of each station, rotation (default 30 urad)")
    p.add_argument("--tracker", metavar="x,y,z", type=xyz, action="append",
                   help="tracker position in mm, machine frame; "
                   "repeat for several stations (each measures the whole campaign, --rounds rounds each) "
                   "(default: the plan's, else thesis Pos. 1 = 250,-1500,150)")
    p.add_argument("--rounds", type=integer(1), metavar="N", help="rounds (default: the plan's, else 4)")
    p.add_argument("--seed", type=integer(0), default=0, metavar="S", help="random seed (default 0)")
    p.add_argument("--no-noise", action="store_true", help="exact readings (no tracker noise)")
    tracker_model_argument(p, "the law the readings' noise is drawn from (every station's)")
    p.add_argument("--effect", action="append", default=[], metavar="NAME[:key=value,...]",
                   help=f"plant an effect (repeatable): {', '.join(fx.NAMES)}; e.g. backlash:axis=X,amount=0.004")
    p.add_argument("--temperature", metavar="rise_c=K,tau_s=S,t0_s=S", nargs="?", const="",
                   help="write a warm-up curve to temperature_c: plan temperature + rise_c (1 - exp(-(t - t0_s) / "
                        "tau_s)) (defaults 2 K, 1800 s, 0 s; the default curve is also used by thermal_temperature)")
    p.add_argument("--extrapolate", choices=("error", "hold"), default="error",
                   help="a pose beyond the range of one of the model's error tables: refused (error, default) or "
                        "the table's end value held (hold; counted in the summary and REC.truth.json's model_held)")
    machine_argument(p)
    p.add_argument("-o", "--output", required=True, metavar="REC.csv", help="recording to write (+ REC.truth.json)")


def _where(truth: dict) -> str:
    fmt = lambda t: ",".join(f"{c:g}" for c in t)  # noqa: E731
    if truth.get("stations"):
        return f"{len(truth['stations'])} stations at " + "; ".join(
            f"{s['label']} {fmt(s['tracker'])}" for s in truth["stations"]) + " mm (each with its alignment error)"
    return f"tracker at {fmt(truth['tracker'])} mm"


def run(args: argparse.Namespace) -> int:
    from mtcal.campaign.plans import load_plan
    from mtcal.campaign.simulate import simulate, truth_path, write_campaign
    from mtcal.kinematics.machine import DEFAULT_MACHINE
    from mtcal.model.errormodel import load_model

    refuse_overwrite([args.output, truth_path(args.output)], args.model, args.plan)
    effects = [fx.parse_effect(e) for e in args.effect]
    model = load_model(args.model) if args.model else None
    machine = args.machine or (model.machine if model is not None else DEFAULT_MACHINE)
    plan = load_plan(args.plan, machine) if args.plan else None
    from mtcal.measurement.tracker import AT960

    spec = args.tracker_model or AT960
    trackers = args.tracker or []
    stations = ([(f"S{i + 1}", tuple(t)) for i, t in enumerate(trackers)] if len(trackers) > 1
                else list(plan.stations.items()) if plan is not None and plan.stations and not trackers else None)
    try:
        if stations:
            from mtcal.campaign.stations import ALIGNMENT_UM, ALIGNMENT_URAD, simulate_stations
            rec, truth = simulate_stations(
                model, stations, machine=machine, rounds=args.rounds or 1, seed=args.seed, effects=effects,
                noise=not args.no_noise, plan=plan, temperature=args.temperature, spec=spec,
                alignment_um=ALIGNMENT_UM if args.alignment_um is None else args.alignment_um,
                alignment_urad=ALIGNMENT_URAD if args.alignment_urad is None else args.alignment_urad,
                extrapolate=args.extrapolate)
        else:
            rec, truth = simulate(model, machine=machine, tracker=trackers[0] if trackers else None, rounds=args.rounds,
                                  seed=args.seed, effects=effects, noise=not args.no_noise, plan=plan,
                                  temperature=args.temperature, spec=spec, extrapolate=args.extrapolate)
    except InputError as exc:  # the library's hint (extrapolate='hold') said as this command's option
        if "extrapolate='hold'" not in exc.problem or args.extrapolate == "hold":
            raise
        raise InputError(exc.problem.replace("use extrapolate='hold'", "give --extrapolate hold"),
                         exc.file or args.model, exc.line) from None
    truth["model_file"] = args.model
    truth["plan_file"] = args.plan
    tp = write_campaign(rec, truth, args.output)
    summary = {"output": args.output, "truth": str(tp), "rows": len(rec), "axes": rec.axes(),
               "rounds": truth["rounds"], "tracker": truth["tracker"], "noise": truth["noise"],
               "tracker_model": {"instrument": spec.label, **spec.mpe()}, "seed": args.seed,
               "duration_s": float(rec.time_s.max()), "effects": truth["effects"],
               **({"stations": truth["stations"]} if "stations" in truth else {}),
               **({"model_held": truth["model_held"]} if "model_held" in truth else {})}
    if args.json:
        print(dumps(summary))
    else:
        print(f"wrote {args.output}: {len(rec)} readings, axes {' '.join(rec.axes())}, {truth['rounds']} rounds, "
              f"{summary['duration_s'] / 3600:.2f} h simulated; " + _where(truth)
              + f"; noise {spec.label if truth['noise'] else 'off'}")
        if "model_held" in truth:
            held = truth["model_held"]
            print(f"  model's end values held (--extrapolate hold) beyond its tables: {sum(held.values())} error "
                  f"evaluations ({len(held)} errors, at most {max(held.values())} readings each)")
        for e in truth["effects"]:
            print(f"  planted {e['name']}: " + ", ".join(f"{k}={v}" for k, v in e["params"].items()))
        log.info("truth: %s", tp)
    return 0
