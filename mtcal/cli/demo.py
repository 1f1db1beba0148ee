"""mtcal demo: identify -> plan -> compensate -> diagnose -> plate on bundled data, with plots and a report."""
from __future__ import annotations

import argparse
from pathlib import Path

from mtcal.cli._options import machine_argument

NAME = "demo"
HELP = ("the main job on bundled data: identify, plan, compensate, check, diagnose, plate reversal, a calibration "
        "history; PNG plots, report.md and report.html in DIR")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, default=Path("mtcal-demo"), metavar="DIR",
                   help="output folder (default ./mtcal-demo)")
    machine_argument(p)  # dmu50: the bundled campaign and program; any other spec: a campaign simulated now


def run(args: argparse.Namespace) -> int:
    from mtcal.demo.run import print_summary, run_demo
    from mtcal.io import dumps, refuse_overwrite
    # an existing file is no output folder; the demo writes many files into it: every file already there must be
    # one mtcal wrote (mtcal.io.refuse_foreign), so a folder of the user's is refused before anything is written
    refuse_overwrite([], dirs={args.out: ("*",)})
    summary = run_demo(args.out, machine=args.machine)
    if args.json:
        print(dumps(summary))
    else:
        print_summary(summary)
    return 0
