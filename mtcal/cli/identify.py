"""mtcal identify REC.csv -o MODEL.json: identification of every axis in a laser-tracker recording (the joint
weighted fit, the tracker's station given or estimated; three-point when it cannot be estimated or by --method)."""
from __future__ import annotations

import argparse
import logging

import numpy as np

from mtcal.cli._options import integer, machine_argument, nonnegative, tracker_model_argument, xyz
from mtcal.errors import InputError
from mtcal.identify import fitting
from mtcal.identify.run import identify
from mtcal.io import dumps, refuse_overwrite
from mtcal.kinematics.machine import DEFAULT_MACHINE
from mtcal.measurement.inspire import parse_positions, read_inspire
from mtcal.measurement.recordings import read_recording
from mtcal.model.errormodel import save_model
from mtcal.model.fits import Polynomial

NAME = "identify"
log = logging.getLogger("mtcal." + NAME)
HELP = ("identify the six error motions per axis and position (joint weighted fit, or the three-point method; "
        "Type A uncertainty over rounds), squareness and fitted error functions from a laser-tracker recording")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("recording", metavar="REC.csv", nargs="+",
                   help="tidy recording CSV (axis,round,position,point,x,y,z[,time_s,direction,temperature_c]; mm and "
                        "deg, machine frame); with --layout inspire: one export per round, in round order")
    p.add_argument("-o", "--output", metavar="MODEL.json", help="write the error model (mm, rad) here")
    p.add_argument("--plots", metavar="DIR", help="write PNG plots (errors with their 95 %% bands, fits, reference "
                                                  "lines)")
    p.add_argument("--tracker", metavar="x,y,z", type=xyz,
                   help="tracker position in the machine frame (mm): weight the least squares by the tracker law's "
                        "covariance (--tracker-model) (default: estimated from the scatter of the rounds)")
    tracker_model_argument(p, "the prior of the weights: the repeated rounds still check its shape and the data's law "
                           "is used (and said) where they disagree; the JSON key noise_law reports the law used")
    p.add_argument("--reference", choices=fitting.REFERENCE_METHODS, default="least-squares",
                   help="ISO 230-1 reference straight line for straightness and squareness (default least-squares)")
    p.add_argument("--layout", choices=("tidy", "inspire"), default="tidy",
                   help="input layout: tidy CSV (docs/design.md) or the thesis' Inspire exports (blocks of K, P, Q "
                        "rows)")
    p.add_argument("--axis", help="with --layout inspire: the axis measured (X, Y, Z, B or C)")
    p.add_argument("--positions", help="with --layout inspire: positions as start:stop:count or a comma list "
                   "(default: the thesis plan of the axis)")
    p.add_argument("--method", choices=("auto", "three-point", "joint"), default="auto",
                   help="joint: one weighted fit of all readings and stations (error motions, reflector positions, "
                        "station alignments; needs the tracker position); three-point: per position (Zhang & Hu); "
                        "auto (default): joint when the tracker position is known or estimated from the rounds' "
                        "scatter, else three-point (with a warning)")
    machine_argument(p, DEFAULT_MACHINE)
    p.add_argument("--max-degree", type=integer(0, 15), default=7, help="highest polynomial degree tried (default 7)")
    p.add_argument("--outlier-k", type=nonnegative, default=5.0,
                   help="warn when a round differs from the others by more than k sigma (default 5; 0 = off)")


def _report(res) -> str:
    lines = [f"{res.source}: {'weighted (tracker covariance)' if res.weighted else 'unweighted'} least squares, "
             f"reference lines: {res.reference}"]
    for axis, ar in res.axes.items():
        unit = res.model.kinematics.unit(axis)
        lines.append(f"\naxis {axis}: {len(ar.positions)} positions, {len(ar.rounds)} rounds, points "
                     f"{','.join(ar.points)}; mean +- std of the mean; um and urad")
        lines.append(f"{'pos/' + unit:>9}" + "".join(f"{n:>17}" for n in ar.names) + f"{'rms9/um':>9}")
        mean, sm = ar.mean, ar.std_mean
        for k, x in enumerate(ar.positions):
            cells = "".join(f"{mean[k, i] * 1e3 if i < 3 else mean[k, i] * 1e6:9.2f}"
                            f"+-{(sm[k, i] * 1e3 if i < 3 else sm[k, i] * 1e6):<6.2f}" for i in range(6))
            lines.append(f"{x:9.2f}{cells}{ar.residual_rms[k] * 1e3:9.2f}")
        fits = ", ".join(f"{n}: " + (f"deg {f.degree}" if isinstance(f, Polynomial) else f"{f.harmonics} harm")
                         for n, f in ar.fits.items())
        lines.append(f"fits: {fits}")
    if res.squareness:
        lines.append("\nsquareness (urad; " + fitting.SQUARENESS_CONVENTION + "):")
        lines.append("  " + "  ".join(f"{k} = {v * 1e6:.2f}" for k, v in res.squareness.items()))
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    refuse_overwrite([args.output], *args.recording, dirs={args.plots: ["identify_*.png"]})
    if args.layout == "inspire":
        if not args.axis:
            raise InputError("--layout inspire needs --axis (the axis the exports measured)")
        positions = None if args.positions is None else parse_positions(args.positions)
        rec = read_inspire(args.recording, args.axis, positions, args.machine)
    elif len(args.recording) != 1:
        raise InputError(f"a tidy recording is one file, got {len(args.recording)} (use --layout inspire for exports)")
    else:
        rec = read_recording(args.recording[0], args.machine)
    res = identify(rec, tracker=args.tracker, machine=args.machine, reference=args.reference,
                   outlier_k=args.outlier_k, max_degree=args.max_degree, method=args.method,
                   tracker_model=args.tracker_model)
    for w in res.warnings:
        log.warning("warning: %s", w)
    if args.output:
        save_model(res.model, args.output)
    if args.plots:
        from mtcal.identify.plots import plot_all
        paths = plot_all(res, args.plots)
        log.info("wrote %d plots to %s", len(paths), args.plots)
    if args.json:
        out = res.to_json()
        if args.tracker is not None:
            out["tracker"] = np.asarray(args.tracker).tolist()
        print(dumps(out))
    else:
        print(_report(res))
        if args.output:
            print(f"\nwrote {args.output}")
    return 0
