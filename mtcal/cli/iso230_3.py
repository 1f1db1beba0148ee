"""`mtcal iso230-3 FILE`: ISO 230-3 evaluations of a thermal test -- the thermal drift of each direction and the
tilts under a rotating spindle (clause 6), the ETVE of a machine at rest (clause 5) (mtcal.thermal.iso230_3; this
module parses arguments and formats)."""
from __future__ import annotations

import argparse
from pathlib import Path

from mtcal.cli._options import positive
from mtcal.errors import InputError
from mtcal.io import atomic_write_text, dumps, refuse_overwrite

NAME = "iso230-3"
HELP = ("ISO 230-3 thermal test: drift of each direction over the test and per spindle-speed stage, tilts from "
        "sensor pairs, ETVE of a machine at rest; drift against time and against temperature (um, urad, degC)")
FILES = ("iso230-3.md", "iso230-3_drift.png", "iso230-3_drift_temperature.png")


def reader_arguments(p: argparse.ArgumentParser) -> None:
    """The thermal test reader's options (shared with `mtcal thermal fit`)."""
    p.add_argument("test", metavar="FILE", help="a thermal test: CSV or .xlsx, a header naming each column's unit: "
                                               "time (s), spindle (rpm), ch1 (um) ..., t1 (degC) ... or time_s, "
                                               "spindle_rpm, ch1_um, ..., t1_c")
    p.add_argument("--columns", metavar="HEADER=NAME (UNIT),...|MAP.json",
                   help="rename headers that do not say their unit, e.g. 'Zeit=time (s),Fühler 1=t1 (degC)'")
    p.add_argument("--directions", metavar="CH=DIR,...|MAP.json",
                   help="each displacement channel's direction in the five-sensor set-up: X1, X2, Y1, Y2 (pairs along "
                        "the mandrel, 1 nearer the spindle nose), Z, or X, Y (e.g. ch1=X1,ch2=X2,ch3=Y1,ch4=Y2,ch5=Z); "
                        "default: channels named by their direction, else none (no tilt; export needs --axes)")


def add_arguments(p: argparse.ArgumentParser) -> None:
    reader_arguments(p)
    p.add_argument("--spacing", type=positive, metavar="MM", help="distance between the two sensors of a pair "
                                                                  "along the mandrel (mm): gives the tilts")
    p.add_argument("--sensor", metavar="NAME", help="the temperature of the drift-against-temperature plot "
                                                    "(default: the one with the largest range)")
    p.add_argument("-o", "--output", metavar="DIR", help=f"write {', '.join(FILES)} there")


def run(args: argparse.Namespace) -> int:
    from mtcal.thermal.iso230_3 import evaluate_iso230_3
    from mtcal.thermal.readings import read_thermal_test
    test = read_thermal_test(args.test, args.columns, args.directions, args.spacing)
    if args.sensor and args.sensor not in test.temperatures:
        raise InputError(f"--sensor {args.sensor}: not a temperature of the file ({', '.join(test.temperatures)})",
                         args.test)
    res = evaluate_iso230_3(test)
    out = res.to_dict()
    if args.output:
        paths = [Path(args.output) / f for f in FILES]
        refuse_overwrite(paths, args.test)
        out["files"] = _write(res, test, paths, args.sensor)
    if args.json:
        print(dumps(out))
        return 0
    print(markdown(res))
    for f in out.get("files", []):
        print(f"wrote {f}")
    return 0


def _write(res, test, paths: list[Path], sensor: str | None) -> list[str]:
    from mtcal.thermal.plots import plot_drift, plot_drift_temperature
    atomic_write_text(paths[0], markdown(res))
    plot_drift(res, test, paths[1])
    files = [str(paths[0]), str(paths[1])]
    if test.temperatures:
        s = sensor or max(res.temperature_range_c, key=res.temperature_range_c.get)
        files.append(str(plot_drift_temperature(res, test, s, paths[2])))
    return files


def markdown(res) -> str:
    """The figures as a report table: per direction and tilt, then per stage."""
    unit = {k: "urad" if k in res.tilt_urad else "um" for k in res.figures}
    lines = [f"### {res.clause} -- {res.source}", "",
             f"Test of {(res.time_s[-1] - res.time_s[0]) / 3600:.2f} h; drift = displacement from the first "
             "reading; tilts (urad) from the pairs' difference over their spacing.", ""]
    etve = res.kind == "etve"
    lines += [f"| direction | range | at the end | largest abs. drift |{' ETVE |' if etve else ''}",
              f"|---|---:|---:|---:|{'---:|' if etve else ''}"]
    for k, f in res.figures.items():
        lines.append(f"| {k} ({unit[k]}) | {f['range']:.2f} | {f['at_end']:.2f} | {f['max_abs']:.2f} |"
                     + (f" {f['etve']:.2f} |" if etve else ""))
    if not etve:
        lines += ["", "Per spindle-speed stage: the drift's range within the stage / its value at the stage's end.",
                  "", "| stage | rpm | from (h) | to (h) | " + " | ".join(res.figures) + " |",
                  "|---:|---:|---:|---:|" + "---|" * len(res.figures)]
        t0 = res.time_s[0]
        for i, s in enumerate(res.stages):
            cells = [f"{f['stages'][i]['range']:.2f} / {f['stages'][i]['at_end']:.2f}" for f in res.figures.values()]
            lines.append(f"| {i + 1} | {s.rpm:g} | {(s.start_s - t0) / 3600:.2f} | {(s.end_s - t0) / 3600:.2f} | "
                         + " | ".join(cells) + " |")
    lines += ["", "| temperature | range (K) |", "|---|---:|"]
    lines += [f"| {k} | {v:.2f} |" for k, v in res.temperature_range_c.items()]
    lines += [""] + [f"- note: {n}" for n in res.notes] + [""]
    return "\n".join(lines)
