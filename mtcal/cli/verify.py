"""`mtcal verify REC.csv --model M.json`: a compensation verified by a measurement made after it (a tracker
recording, a circular test or an R-test sweep; mtcal.check.verify): what is left against what the model promised,
within its uncertainty or not, where, how much, and what the compensation did not cover."""
from __future__ import annotations

import argparse

from mtcal.cli._options import machine_argument, xyz
from mtcal.errors import InputError
from mtcal.io import dumps

NAME = "verify"
HELP = ("verify a compensation: a recording, circular test or R-test made on the compensated machine against the "
        "model that compensated it (what is left, within its uncertainty or not, what was not covered); exit 0 "
        "either way, the verdict in the output")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("data", metavar="REC.csv", help="a tracker recording (docs/design.md), or a measured circular "
                                                   "test or R-test sweep (docs/guide/checks.md)")
    p.add_argument("--model", required=True, metavar="M.json", help="the model the machine was compensated with")
    p.add_argument("--covered", metavar="NAME,...",
                   help="the errors the compensation acted on (default: all of the model's; e.g. a table format "
                        "that holds only the positioning errors)")
    p.add_argument("--tracker", metavar="x,y,z", type=xyz,
                   help="a recording: the tracker position in the machine frame (mm), as for mtcal identify")
    machine_argument(p, None)


def run(args: argparse.Namespace) -> int:
    from mtcal.check import read_check, verify
    from mtcal.check.files import is_check_file
    from mtcal.measurement.recordings import read_recording
    from mtcal.model.errormodel import load_model

    model = load_model(args.model)
    covered = {n.strip() for n in args.covered.split(",") if n.strip()} if args.covered is not None else None
    if args.machine and args.machine != model.machine:
        raise InputError(f"{args.model}: the model is of machine {model.machine}, not {args.machine} (--machine): "
                         f"verify a compensation with the model of the machine measured")
    if is_check_file(args.data):
        v = verify(read_check(args.data), model, covered=covered)
    else:
        v = verify(read_recording(args.data, model.machine), model, covered=covered, tracker=args.tracker)
    if args.json:
        print(dumps(v.to_dict()))
        return 0
    print(f"{args.data}: {'PASSED' if v.passed else 'NOT PASSED'}: the compensation with {args.model} "
          f"{'left nothing beyond the model uncertainty' if v.passed else 'left errors beyond the model uncertainty'}")
    for e in v.errors:
        if not e.within:
            print(f"  {e.text}")
    if v.not_covered:
        print("  not covered by the compensation: " + ", ".join(v.not_covered))
    if v.check is not None:
        c = v.check
        print(f"  {c['kind']} test: worst reading {c['worst_z']:.1f} combined sigma (limit {c['k_agree']:g})")
        for f in c["findings"]:
            print(f"  {'found' if f['quasi_static'] else 'dynamic'}: {f['text']}")
    return 0
