"""`mtcal thermal fit FILE` and `mtcal thermal export MODEL.json`: a thermal error model of each drift channel from
the temperatures and the spindle speed's history, selected and judged out of sample in time, and the controller
compensation of the channels it predicts (mtcal.thermal.model, mtcal.export.thermal; this module parses arguments
and formats)."""
from __future__ import annotations

import argparse
import logging
import math
from pathlib import Path

from mtcal.cli._options import positive, probability, real
from mtcal.cli.history import _parser_class
from mtcal.cli.iso230_3 import reader_arguments
from mtcal.errors import InputError
from mtcal.io import atomic_write_text, dumps, read_json, refuse_overwrite

NAME = "thermal"
log = logging.getLogger("mtcal." + NAME)
HELP = ("thermal error model: fit each drift channel from temperatures and spindle speed, judged on the last part "
        "of the test against constant and time-only baselines (fit); controller compensation of the predictable "
        "channels: SINUMERIK SD43900, LinuxCNC HAL component (export)")


def _lags(text: str) -> tuple[float, ...]:
    try:
        v = tuple(float(t) for t in text.split(",") if t.strip())
    except ValueError:
        v = ()
    if not v or not all(math.isfinite(t) and t > 0 for t in v):
        raise argparse.ArgumentTypeError(f"expected positive time constants in s separated by commas, got {text!r}")
    return v


def add_arguments(p: argparse.ArgumentParser) -> None:
    sub = p.add_subparsers(dest="action", required=True, metavar="ACTION", parser_class=_parser_class(p))
    f = sub.add_parser("fit", help="fit and judge a model of each channel (the last --holdout of the test in time)")
    reader_arguments(f)
    f.add_argument("--holdout", type=real(0.0, 1.0, lo_open=True, hi_open=True), default=0.4, metavar="SHARE",
                   help="share of the readings, the last in time, held out to judge the models (default 0.4)")
    f.add_argument("--lags", type=_lags, metavar="S,S,...", help="time constants of the lag terms, s (default "
                                                                 "900,1800,3600,7200,14400)")
    f.add_argument("--alpha", type=probability, default=0.05, help="level of each channel's test against each "
                                                                   "baseline (default 0.05)")
    f.add_argument("-o", "--output", metavar="MODEL.json", help="write the model (for `mtcal thermal export`)")
    f.add_argument("--plot", metavar="FILE.png", help="measured, model and baselines against time, split marked")
    e = sub.add_parser("export", help="compensation of the predictable channels for a controller")
    e.add_argument("model", metavar="MODEL.json", help="a model of `mtcal thermal fit -o`")
    e.add_argument("--format", required=True, choices=("siemens", "linuxcnc"),
                   help="siemens: a subprogram writing SD43900 from R parameters; linuxcnc: a folder with a HAL "
                        "component driving the external axis offsets")
    e.add_argument("-o", "--output", required=True, metavar="FILE|DIR", help="file (siemens) or folder (linuxcnc)")
    e.add_argument("--axes", metavar="CH=[-]AXIS,...", help="each compensated channel's machine axis, '-' where it "
                                                           "reads against it (default: the channels' directions)")
    e.add_argument("--machine", default="dmu50", metavar="NAME", help="the machine (axes, travel; default dmu50)")
    e.add_argument("--period", type=positive, default=60.0, metavar="S",
                   help="siemens: the period the PLC calls the program at, s (default 60)")
    e.add_argument("--force", action="store_true", help="write past the plausibility guard, with a loud warning "
                                                        "(never a channel that is not predictable)")
    for q in (f, e):
        q.add_argument("--json", action="store_true", default=argparse.SUPPRESS, help="print a JSON answer")
        q.add_argument("-q", "--quiet", action="store_true", default=argparse.SUPPRESS, help="warnings and errors")


def run(args: argparse.Namespace) -> int:
    return _fit(args) if args.action == "fit" else _export(args)


def _fit(args: argparse.Namespace) -> int:
    from mtcal.thermal.model import fit_thermal
    from mtcal.thermal.readings import read_thermal_test
    refuse_overwrite([args.output, args.plot], args.test)
    test = read_thermal_test(args.test, args.columns, args.directions)
    log.info("%s: %d readings over %.1f h, %d channels, %d temperatures%s", args.test, len(test),
             (test.time_s[-1] - test.time_s[0]) / 3600, len(test.channels), len(test.temperatures),
             "" if test.spindle_rpm is not None else ", no spindle speed")
    model = fit_thermal(test, args.holdout, args.lags, args.alpha)
    out = model.to_dict()
    files = []
    if args.output:
        atomic_write_text(args.output, dumps(out) + "\n")
        files.append(args.output)
    if args.plot:
        from mtcal.thermal.plots import plot_model
        files.append(str(plot_model(model, test, args.plot)))
    if args.json:
        print(dumps({**out, "files": files}))
        return 0
    print(table(model))
    for f in files:
        print(f"wrote {f}")
    return 0


def table(model) -> str:
    """The out-of-sample table: channel, model, RMSE, R^2, the baselines' RMSE, predictable."""
    lines = [f"{model.source}: judged on the last {model.holdout:.0%} in time (from t = {model.split_s:g} s); "
             "RMSE out of sample, um", "",
             "| channel | model | RMSE | R² | constant | time only | U95 | predictable |",
             "|---|---|---:|---:|---:|---:|---:|---|"]
    for c in model.channels:
        lines.append(f"| {c.channel} | {c.model} | {c.rmse_um:.2f} | {c.r2:.2f} | {c.constant_rmse_um:.2f} | "
                     f"{c.time_only_rmse_um:.2f} | {c.u95_um:.2f} | {'yes' if c.predictable else 'no'} |")
    lines += [""] + [f"- {c.channel}: {c.reason}" for c in model.channels]
    lines += [f"- note: {n}" for n in model.notes] + [""]
    return "\n".join(lines)


def _export(args: argparse.Namespace) -> int:
    from mtcal.export.thermal import export_thermal
    from mtcal.kinematics.machine import load_machine
    from mtcal.thermal.model import model_from_dict
    if args.format == "linuxcnc":
        if Path(args.output).exists() and not Path(args.output).is_dir():
            raise InputError(f"{args.output}: format linuxcnc writes a folder, and this is a file")
    else:
        refuse_overwrite(args.output, args.model)
    model = model_from_dict(read_json(args.model, "thermal model"), args.model)
    res = export_thermal(model, args.format, args.output, load_machine(args.machine), args.axes, args.period,
                         args.force, args.model, protect=(args.model,))
    if args.json:
        print(dumps({"format": res.format, "files": res.files, "channels": res.channels, "sign": res.sign,
                     "warnings": res.warnings}))
        return 0
    print(f"{args.model} -> {args.format}: sign: {res.sign}")
    for c in res.channels:
        print(f"  {c['channel']} -> {'-' if c['sign'] < 0 else ''}{c['axis']}: {c['model']} (RMSE {c['rmse_um']:.2f} "
              f"um out of sample; largest offset {c['largest_offset_um']:.1f} um)")
    for w in res.warnings:
        log.warning("warning: %s", w)
    for f in res.files:
        print(f"wrote {f}")
    return 0
