"""`mtcal diagnose`: locate where recordings and the quasi-static model disagree, name and model the left-out effect."""
from __future__ import annotations

import argparse
import logging
import time

from mtcal.cli._options import integer, machine_argument, probability, tracker_model_argument, xyz

NAME = "diagnose"
log = logging.getLogger("mtcal." + NAME)
HELP = "fit a quasi-static base model to tracker recordings, locate the misfit, name and model left-out effects"
BARE = object()  # --calibrate without N: mtcal.diagnose.calibrate.CAMPAIGNS (kept out of the parser: no numpy there)


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("recording", metavar="REC.csv", help="laser-tracker recording (tidy CSV of docs/design.md)")
    p.add_argument("--model", metavar="MODEL.json", help="base model = this error model (residuals = recordings "
                   "minus its simulation); default: fit smooth error functions to the recording")
    p.add_argument("--tracker", metavar="x,y,z", type=xyz,
                   help="tracker position, mm, machine frame: weights readings by the tracker law's covariance "
                   "(--tracker-model; default: the position estimated from the scatter of the repeated rounds; the "
                   "JSON key noise_model says which was used)")
    tracker_model_argument(p, "the prior of the noise model: the repeated rounds still check its shape and the "
                           "data's law is used (and said) where they disagree; noise_model.law reports the law used")
    p.add_argument("--station", metavar="LABEL", help="diagnose the readings of this tracker station only (default: "
                   "every station in one fit, each weighted about its own tracker_x,y,z, with its own alignment)")
    p.add_argument("--level", type=probability, default=None,
                   help="family-wise significance level (default 0.005: mtcal.diagnose.run.LEVEL)")
    p.add_argument("--per-axis-positions", action="store_true",
                   help="one position per (axis, reflector) instead of sharing a reflector's position between the "
                   "axes measured from the same reference pose (then a reflector creeping between the axes is "
                   "absorbed; docs, diagnosis base model)")
    p.add_argument("--plots", metavar="DIR",
                   help="write residuals_before.png, residuals_after.png and a picture per finding "
                        "(finding_N_NAME_AXIS.png: a reversal by approach direction, a drift or knock against time, "
                        "a periodic error against position) to DIR")
    p.add_argument("--calibrate", metavar="N", nargs="?", const=BARE, type=integer(1),
                   help="calibrate the level: simulate N campaigns (default 20 when N is not given) from the fitted "
                        "null -- the base and the noise law, at the recording's plan -- diagnose each with the same "
                        "options and report the share with any claim and its 95 %% upper bound (N times the "
                        "diagnosis' CPU time; docs/guide/diagnose.md)")
    p.add_argument("--seed", type=integer(0), default=None,
                   help="seed of --calibrate's campaigns: campaign k draws from (seed, k) (default 0)")
    machine_argument(p)


def campaigns(args: argparse.Namespace) -> int | None:
    """The null campaigns ``--calibrate`` asks for (None: the level stays nominal)."""
    from mtcal.diagnose.calibrate import CAMPAIGNS

    return CAMPAIGNS if args.calibrate is BARE else args.calibrate


def _fmt(e: dict) -> str:
    u = e.get("unit", "")
    est = e["estimate"]
    scale, unit = (1e3, "um") if u == "mm" else (1e6, "urad") if u == "rad" else (1.0, u)
    return f"{est * scale:.4g} +- {e['uncertainty'] * scale:.2g} {unit}"


def run(args: argparse.Namespace) -> int:
    from mtcal.diagnose import diagnose, plot_findings, plot_residuals
    from mtcal.diagnose.run import LEVEL
    from mtcal.errors import InputError
    from mtcal.io import dumps, refuse_overwrite
    from mtcal.kinematics.machine import DEFAULT_MACHINE
    from mtcal.model.errormodel import load_model

    if args.seed is not None and args.calibrate is None:
        raise InputError("--seed sets the campaigns of --calibrate N: give --calibrate too")
    refuse_overwrite([], args.recording, args.model, dirs={args.plots: ["residuals_*.png", "finding_*.png"]})
    model = load_model(args.model) if args.model else None
    machine = args.machine or (model.machine if model is not None else DEFAULT_MACHINE)
    rec = _recording(args, machine)
    level = LEVEL if args.level is None else args.level
    options = dict(machine=machine, tracker=args.tracker, tie_positions=not args.per_axis_positions,
                   tracker_model=args.tracker_model)
    cpu = time.process_time()
    d = diagnose(rec, model, level=level, **options)
    out = d.to_dict()
    out["level"] = _level(args, d, level, time.process_time() - cpu, dict(options, model=model))
    if args.plots:
        out["plots"] = plot_residuals(d, args.plots) + plot_findings(d, args.plots)
    if args.json:
        print(dumps(out))
        return 0
    _print_model(d, rec, args.recording)
    _print_effects(d, out, level)
    _print_rest(d)
    print(f"level {level:g} (family-wise): {out['level']['says']}")
    for p in out.get("plots", []):
        log.info("plot: %s", p)
    return 0


def _level(args: argparse.Namespace, d, level: float, cpu_s: float, options: dict) -> dict:
    """The JSON answer's ``level``: nominal, or calibrated by ``--calibrate N`` null campaigns (with a progress
    bar on a terminal; mtcal.diagnose.calibrate)."""
    from mtcal.cli._words import Bar
    from mtcal.diagnose.calibrate import calibrate, nominal

    n = campaigns(args)
    if n is None:
        return nominal(level)
    log.info("calibrating the level: %d campaigns simulated from the fitted null, each diagnosed (about %.0f "
             "CPU-s: %.1f each)", n, n * cpu_s, cpu_s)
    bar = None if args.quiet or args.json else Bar(n, "mtcal diagnose --calibrate")
    try:
        cal = calibrate(d, n, seed=args.seed or 0, level=level, progress=bar.update if bar else None, **options)
    finally:
        if bar:
            bar.close()
    return cal.to_dict()


def _recording(args: argparse.Namespace, machine: str):
    """The recording, of one station where ``--station`` says so."""
    from mtcal.errors import InputError
    from mtcal.measurement.recordings import read_recording

    rec = read_recording(args.recording, machine)
    if args.station is not None:
        keep = rec.stations() == args.station
        if not keep.any():
            raise InputError(f"{args.recording}: no readings of station {args.station!r} "
                             f"(stations: {', '.join(sorted(set(rec.stations())))})")
        rec = rec.select(keep)
    return rec


def _print_model(d, rec, source: str) -> None:
    """The noise model and law, the base model and the sigma before and after."""
    law = d.noise.law
    spec = ("the data's law" if law["source"] == "data" else "the law given" if law["instrument"] == "given numbers"
            else f"{law['instrument']} spec") if law else "the trackers' law"
    unit = f"sigma ratio (1 = {spec})" if d.prep.weighted else "unweighted"
    print(f"noise model: {d.noise.kind}: {d.noise.how}")
    if law:
        print(f"noise law (MPE, k = {law['k']:g}): along the beam {law['radial_um']:.3g} um + "
              f"{law['radial_um_per_m']:.3g} um/m, across {law['transverse_um']:.3g} um + "
              f"{law['transverse_um_per_m']:.3g} um/m: {law['obtained']}")
    print(f"{source}: {len(rec)} readings; base model: {d.base['kind']}, degrees "
          f"{', '.join(f'{a}={k}' for a, k in d.base['degrees'].items())}")
    print(f"sigma {d.base_sigma * 1e3:.3f} um before -> {d.sigma_after * 1e3:.3f} um after "
          f"({unit}: {d.base_sigma_ratio:.3f} -> {d.sigma_ratio_after:.3f})")


def _print_effects(d, out: dict, level: float) -> None:
    """The named effects with their evidence, what they say and what they are confounded with."""
    sig = [e for e in d.effects if e["significant"]]
    if not sig:
        print("no effect left out: nothing significant at level", level)
    for e in sig:
        ev = e["evidence"]
        print(f"  {e['name']:<14} {e['axis'] or '-':<2} {e.get('where', ''):<28} {_fmt(e):<24} "
              f"F = {ev['F']:.1f}, p_adj = {ev['p_adjusted']:.2g}, cv gain = "
              f"{'-' if ev['cv_gain'] is None else format(ev['cv_gain'], '.3g')}, "
              f"sigma after {e['sigma_after'] * 1e3:.3f} um")
    scatter = (out["noise_model"].get("axis_scatter") or {}).get("found")
    if scatter:
        print(f"  {scatter['says']}")
    for e in sig:
        if e.get("says"):
            print(f"  {e['name']}: {e['says']}")
    for e in sig:
        for c in e.get("confounded_with", []):
            # a rival names the measurement that separates it; a failed predictive check says what it left
            print(f"    confounded with {c['name']} {c['axis'] or ''} {c['where']}: {c.get('separate_by') or c['why']}")
        if e.get("possible_alias"):
            print(f"    {e['note']}")


SHOWN = 8  # located and unexplained entries printed of each; --json holds them all


def _more(count: int, what: str) -> None:
    if count > SHOWN:
        print(f"  ... and {count - SHOWN} more {what} entries (the first {SHOWN} shown; --json lists all)")


def _size(u) -> str:
    """A located mean's size beyond the base in words (um, with its standard uncertainty): where nothing is seen
    beyond the base (size 0, scans.Beyond.largest), that it is too small to size; a spread has none."""
    if u.kind != "mean" or u.shift_mm is None:
        return ""
    sd = "" if u.shift_sd_mm is None else f"{u.shift_sd_mm * 1e3:.2f}"
    if u.shift_mm == 0:
        return ", too small beyond the base to size" + (f": standard uncertainty {sd} um" if sd else "")
    return f", {u.shift_mm * 1e3:.2f}" + (f" +- {sd}" if sd else "") + " um"


def _print_rest(d) -> None:
    """The located and unexplained mismatches, what was not named and what cannot be separated."""
    for loc in d.located[:SHOWN]:
        print(f"  located: axis {loc.axis} by {loc.by} = {loc.where} (score {loc.score:.1f}, {loc.kind})")
    _more(len(d.located), "located")
    for u in d.unexplained[:SHOWN]:
        print(f"  UNEXPLAINED: axis {u.axis} by {u.by} = {u.where} ({u.kind}{_size(u)}, p_adj = {u.p_adjusted:.2g})")
    _more(len(d.unexplained), "unexplained")
    for e in d.effects:
        if e.get("inadequate"):
            print(f"  not named: {e['name']} {e['axis'] or ''} {e['where']}: {e['inadequate']}")
    ns: dict[tuple[str, str], list[str]] = {}
    for e in d.effects:
        if e.get("not_separable"):
            ns.setdefault((e["name"], e["not_separable"]), []).append(e["axis"] or "")
    for (name, why), axes in ns.items():
        where = f" ({' '.join(a for a in axes if a)})" if any(axes) else ""
        print(f"  not separable: {name}{where}: {why}")
