"""`mtcal uncertainty REC.csv --trials N --seed S [--workers K | --scheduler ADDRESS] [--json]`: a GUM Supplement 1
Monte Carlo through the whole estimator (mtcal.uncertainty; this module parses arguments and formats)."""
from __future__ import annotations

import argparse
from pathlib import Path

from mtcal.cli._options import integer, machine_argument, real, tracker_model_argument, xyz
from mtcal.cli._words import Bar
from mtcal.io import atomic_write_text, dumps, file_sha256, refuse_overwrite, replace_allowed

NAME = "uncertainty"
HELP = ("GUM Supplement 1 Monte Carlo of the identification: readings drawn from the tracker's law and its "
        "systematic terms, each trial's fit batched on the campaign's factorisation (identify re-run per trial with "
        "--exact), on Dask workers; 95 %% intervals of every error, constant and of the tool tip over the work "
        "volume (mm, rad)")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("recording", metavar="REC.csv", help="the recording identify ran on (docs/design.md)")
    p.add_argument("--trials", type=integer(2), default=1000,
                   help="trials (default 1000; the most with --tolerance-um)")
    p.add_argument("--seed", type=integer(0), default=0, help="trial k draws from (seed, k) (default 0)")
    p.add_argument("--workers", type=integer(0), metavar="K",
                   help="local worker processes (default: the machine's cores; 0: in this process)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask cluster (tcp://host:8786)")
    p.add_argument("--store", metavar="TRIALS.npz", help="keep the trials here; a later run extends them")
    p.add_argument("--tracker", metavar="x,y,z", type=xyz, help="tracker position (mm), as given to identify")
    p.add_argument("--method", choices=("auto", "three-point", "joint"), default="auto", help="as identify's")
    tracker_model_argument(p, "as given to identify; the trials draw from the law identify then weights by")
    p.add_argument("--p", type=real(0.5, 0.999), default=0.95, help="coverage probability (default 0.95)")
    p.add_argument("--tolerance-um", type=real(0, unit="um", lo_open=True), metavar="UM",
                   help="adaptive stopping (GUM-S1 7.9): stop when the interval limits are stable to this (um; "
                        "angles in urad)")
    p.add_argument("--air-temperature-u", type=real(0, 10, "K"), default=0.3, metavar="K",
                   help="u of the tracker's air temperature (K, default 0.3): its length scale, Edlen")
    p.add_argument("--air-pressure-u", type=real(0, 50, "hPa"), default=0.5, metavar="HPA",
                   help="u of the tracker's air pressure (hPa, default 0.5)")
    p.add_argument("--centring-um", type=real(0, 100, "um"), default=2.5 / 3 ** 0.5, metavar="UM",
                   help="u of each reflector's centring (um per axis, default 1.44: +-2.5 um rectangular)")
    p.add_argument("--material-temperature-u", type=real(0, 20, "K"), default=0.0, metavar="K",
                   help="u of the structure's temperature (K, default 0: off) with --alpha")
    p.add_argument("--alpha", type=real(0, 1e-3, "1/K"), default=11.5e-6, metavar="PER_K",
                   help="expansion coefficient (1/K, default 11.5e-6: steel)")
    p.add_argument("--program", metavar="P.nc",
                   help="the tool tip's interval at this program's moves (up to 500; the task-specific uncertainty "
                        "that `mtcal compensate --uncertainty` reports) instead of 100 poses of the work volume")
    p.add_argument("--exact", action="store_true",
                   help="every trial runs identify (default: batched trials, the joint fit linearised at the "
                        "campaign's estimate, checked against identify on a few trials; docs/guide/uncertainty.md)")
    p.add_argument("--budget", action="store_true", help="also the uncertainty budget (one-at-a-time Monte Carlo)")
    p.add_argument("--plots", metavar="DIR", help="write uncertainty_AXIS.png (bands) and, adaptive, convergence.png "
                                                  "into DIR")
    p.add_argument("-o", "--output", metavar="RESULT.json", help="write the JSON answer here")
    machine_argument(p, None)


def run(args: argparse.Namespace) -> int:
    from mtcal.measurement.recordings import read_recording
    from mtcal.uncertainty import Inputs, monte_carlo
    from mtcal.uncertainty.plots import plot_bands, plot_convergence

    refuse_overwrite([args.output], args.recording, args.program)
    with replace_allowed():  # the store is read and checked before it is extended (mtcal.uncertainty.run.Store)
        refuse_overwrite([args.store], args.recording, args.program)
    rec = read_recording(args.recording, args.machine)
    poses = None
    if args.program:
        from mtcal.kinematics.machine import DEFAULT_MACHINE, load_machine
        from mtcal.uncertainty.run import program_poses
        poses = program_poses(args.program, load_machine(args.machine or DEFAULT_MACHINE))
    inputs = Inputs(air_temperature_u_k=args.air_temperature_u, air_pressure_u_hpa=args.air_pressure_u,
                    centring_u_um=args.centring_um, alpha_per_k=args.alpha,
                    material_temperature_u_k=args.material_temperature_u)
    bar = _progress(args)
    try:
        res = monte_carlo(rec, trials=args.trials, seed=args.seed, p=args.p, inputs=inputs, workers=args.workers,
                          scheduler=args.scheduler, store=args.store, budget=args.budget, poses=poses,
                          tolerance_mm=None if args.tolerance_um is None else args.tolerance_um * 1e-3,
                          progress=bar.update if bar else None, tracker=args.tracker, method=args.method,
                          tracker_model=args.tracker_model, exact=args.exact,
                          **({"machine": args.machine} if args.machine else {}))
    finally:
        if bar:
            bar.close()
    out = res.to_dict()
    out["provenance"].update(recording={"file": Path(args.recording).name, "sha256": file_sha256(args.recording)},
                             program=None if not args.program else {"file": Path(args.program).name,
                                                                    "sha256": file_sha256(args.program)})
    if args.program:
        out["volumetric"]["program"] = Path(args.program).name
    if args.plots:
        out["plots"] = [str(p) for p in plot_bands(res, args.plots)]
        conv = plot_convergence(res, Path(args.plots) / "convergence.png")
        out["plots"] += [str(conv)] if conv else []
    if args.output:
        atomic_write_text(args.output, dumps(out) + "\n")
    if args.json:
        print(dumps(out))
        return 0
    print(_text(out))
    return 0


def _progress(args):
    if args.quiet or args.json:
        return None
    try:
        import tqdm  # noqa: F401
    except ImportError:
        return None
    return Bar(args.trials, "mtcal uncertainty")


def _text(d: dict) -> str:
    lines = [f"{d['trials']} trials (seed {d['seed']}, estimator {d['inputs']['estimator']}), {d['seconds']:.1f} s; "
             f"{d['p']:.0%} intervals, probabilistically symmetric; translations um, angles urad"]
    for n, e in d["errors"].items():
        s = 1e6 if n[2] in "ABC" else 1e3
        half = max((h - lo) / 2 for lo, h in zip(e["lo95"], e["hi95"])) * s
        lines.append(f"  {n:6s} axis {e['axis']}: largest half-width {half:8.2f}")
    for n, c in d["constants"].items():
        lines.append(f"  {n:6s} {c['mean'] * 1e6:8.2f} urad, [{c['lo95'] * 1e6:.2f}, {c['hi95'] * 1e6:.2f}]")
    pth = d.get("path", {})
    if pth.get("batched"):
        tr = pth.get("trials", {})
        full = {k: v for k, v in tr.items() if k != "batched" and v}
        lines.append(f"  batched trials: {tr.get('batched', 0)}; by identify: " + (", ".join(
            f"{v} ({k})" for k, v in full.items()) or "none") + f"; check on {pth['check']['trials']} trials: "
            f"largest difference {pth['check']['largest_difference_of_half_width']:.2%} of a half-width")
    elif pth:
        lines.append(f"  every trial ran identify ({pth.get('why')})")
    v = d["volumetric"]
    where = f"moves of {v['program']}" if v.get("program") else "poses of the work volume"
    lines.append(f"  tool tip over {len(v['poses'])} {where}: largest half-width {v['u95_max_mm'] * 1e3:.2f} um")
    for term, b in d.get("budget", {}).items():
        lines.append(f"  budget {term:9s}: tool tip u up to {b['volumetric_u_max_mm'] * 1e3:.2f} um")
    return "\n".join(lines)
