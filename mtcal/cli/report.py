"""`mtcal report ID|RESULT.json -o report.html [--db URL]`: one self-contained HTML report (mtcal.report)."""
from __future__ import annotations

import argparse

from mtcal.io import dumps

NAME = "report"
HELP = ("one self-contained HTML report (pictures inline, A4 print styles, numbered pages) of a machine's history or "
        "of one result file: page one the summary (machine, dates, instrument, what changed since the previous "
        "calibration, the volumetric error, the largest errors ranked, what to do next), then the details and a "
        "glossary of the ISO 230-1 codes")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("target", metavar="ID|RESULT.json", help="a machine ID in the history, or one result file")
    p.add_argument("-o", "--output", required=True, metavar="report.html", help="the HTML file to write")
    p.add_argument("--db", metavar="URL", help="the history database (as mtcal history's --db)")


def run(args: argparse.Namespace) -> int:
    from mtcal.history.store import refuse_database_output
    from mtcal.report import write_report
    refuse_database_output([args.output], args.db)  # never the history, whatever --force
    out = write_report(args.target, args.output, args.db)
    if args.json:
        print(dumps(out))
    else:
        print(f"wrote {out['report']} ({out['sections']} sections, {out['pictures']} pictures, {out['bytes']} bytes)")
    return 0
