"""`mtcal import-sa EXPORT.txt`: SpatialAnalyzer ASCII point export -> tidy recording CSV
(mtcal.measurement.import_sa)."""
from __future__ import annotations

import argparse
import logging
from pathlib import Path

from mtcal.cli._options import machine_argument
from mtcal.io import dumps, read_text, refuse_overwrite
from mtcal.kinematics.machine import DEFAULT_MACHINE

NAME = "import-sa"
log = logging.getLogger("mtcal." + NAME)
HELP = ("convert a SpatialAnalyzer ASCII point export (Collection Group Target x y z ...) to a tidy recording, "
        "mapping target names to axis, round, position, point by a mapping file or a naming pattern")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("export", metavar="EXPORT.txt", help="SpatialAnalyzer ASCII export (space, comma or tab separated)")
    how = p.add_mutually_exclusive_group(required=True)
    how.add_argument("--mapping", metavar="MAP.csv", help="CSV target,axis,round,position,point[,direction]")
    how.add_argument("--pattern", metavar="REGEX", help="regular expression with named groups axis, round, "
                     r"position, point [, direction], e.g. "
                     r"'(?P<axis>[A-Z])_r(?P<round>\d+)_(?P<position>-?[\d.]+)_(?P<point>\w+)'")
    p.add_argument("--units", choices=("mm", "in", "m"), help="length unit of the export (default: its "
                   "'// Units:' line (Millimeters, Inches, Meters), else mm; one contradicting that line is refused)")
    p.add_argument("--skip-unmatched", action="store_true",
                   help="leave out targets that match no mapping (default: an error listing them)")
    p.add_argument("--name-fields", type=int, choices=(1, 2, 3),
                   help="name fields before x y z (default: the non-numeric leading fields of the first line)")
    p.add_argument("-o", "--output", required=True, metavar="REC.csv", help="tidy recording to write")
    machine_argument(p, DEFAULT_MACHINE)


def run(args: argparse.Namespace) -> int:
    from mtcal.measurement.import_sa import import_sa, read_mapping
    from mtcal.measurement.recordings import write_recording

    refuse_overwrite(args.output, args.export, args.mapping)
    path = Path(args.export)
    text = read_text(path, "SpatialAnalyzer export")
    mapping = read_mapping(args.mapping) if args.mapping else None
    res = import_sa(text, str(path), mapping=mapping, pattern=args.pattern, units=args.units,
                    skip_unmatched=args.skip_unmatched, name_fields=args.name_fields, machine=args.machine)
    write_recording(res.recording, args.output)
    out = {"output": args.output} | res.to_dict()
    if args.json:
        print(dumps(out))
        return 0
    print(f"wrote {args.output}: {out['rows']} readings, axes {' '.join(out['axes'])} from {path} "
          f"({out['matched']} targets matched, {out['skipped']} left out; lengths {res.units} -> mm)")
    for n in res.notes:
        log.warning("note: %s", n)
    return 0
