"""mtcal demo: identify -> plan -> compensate -> diagnose -> plate on bundled data, with plots and a report."""
from __future__ import annotations

import argparse
from pathlib import Path

NAME = "demo"
HELP = ("the main job on bundled data: identify, plan, compensate, diagnose, plate reversal; "
        "PNG plots and report.md in DIR")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, default=Path("mtcal-demo"), metavar="DIR",
                   help="output folder (default ./mtcal-demo)")
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    p.add_argument("--machine", default=None, help="machine spec (default dmu50, with the bundled campaign and "
                   "program; any other spec in derive/machines/ gets a campaign simulated from a synthetic truth)")


def run(args: argparse.Namespace) -> int:
    from mtcal.demo import print_summary, run_demo
    from mtcal.io import dumps
    summary = run_demo(args.out, quiet=args.quiet, machine=args.machine)
    if args.json:
        print(dumps(summary))
    else:
        print_summary(summary)
    return 0
