"""`mtcal iso230-2 REC.csv`: ISO 230-2:2014 positioning accuracy and repeatability of linear and rotary axes
(evaluation in mtcal.iso230_2.evaluation; this module parses arguments and formats tables)."""
from __future__ import annotations

import argparse
import csv
import io
import math
from pathlib import Path

from mtcal.cli._options import machine_argument, real
from mtcal.errors import InputError
from mtcal.io import atomic_write_text, dumps, refuse_overwrite
from mtcal.kinematics.machine import DEFAULT_MACHINE

NAME = "iso230-2"
HELP = ("ISO 230-2:2014 evaluation of an axis from a recording: per target mean deviations up/down, reversal, "
        "repeatability; axis A, E, M, R, B (linear: um; rotary: arcsec)")
COLUMNS = (("n_up", "n↑"), ("n_down", "n↓"), ("mean_up", "x̄↑"), ("mean_down", "x̄↓"), ("mean", "x̄"),
           ("reversal", "B_i"), ("s_up", "s↑"), ("s_down", "s↓"), ("R_up", "R↑"), ("R_down", "R↓"), ("R", "R_i"))
ORDER = ("A", "A_up", "A_down", "E", "E_up", "E_down", "M", "R", "R_up", "R_down", "B", "B_mean")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("recording", metavar="FILE.csv",
                   help="a tidy tracker recording (docs/design.md), or an interferometer's readings: target_UNIT, run, "
                        "direction, measured_UNIT or deviation_UNIT[, air_temperature_c, material_temperature_c]")
    p.add_argument("--unit", choices=("mm", "um", "in", "deg", "arcsec"),
                   help="interferometer export: the unit of target / reading / error columns whose header and "
                        "metadata give none")
    p.add_argument("--columns", metavar="ROLE=HEADER,...",
                   help="interferometer export: the headers it does not recognise, e.g. target_mm=Pos,run=Lauf,"
                        "direction=Richtung,deviation_um=Abw; values=measured|deviation: what a wide table's run "
                        "columns hold when their headers do not say")
    p.add_argument("--directions", metavar="WORD=up,WORD=down",
                   help="interferometer export: direction words beyond up/down, +/-, Fwd/Rev, forward/reverse, "
                        "vorwärts/rückwärts, hin/rück, ...")
    p.add_argument("--target-tolerance", type=real(0.0, 10.0, "mm or deg", lo_open=True), metavar="MM_OR_DEG",
                   help="targets closer than this are one target (written a few um off in one run); default "
                        "0.01 mm (linear) / 0.01 deg (rotary)")
    p.add_argument("--result-unit", choices=("um", "mm", "inch", "arcsec", "urad", "deg"),
                   help="unit of the deviations reported (default um for a linear axis, arcsec or --angle-unit for "
                        "a rotary one)")
    p.add_argument("--axis", metavar="NAME", help="axis to evaluate (default: every axis in the recording; "
                                                  "readings layout: the axis' name in the report, default 'axis')")
    p.add_argument("--target-points", metavar="P,P,...",
                   help="evaluate only these target positions (mm or deg; default: every position recorded)")
    p.add_argument("--alpha", type=real(-1e-3, 1e-3, "1/K"), metavar="PER_K",
                   help="expansion coefficient for --temperature-normalise (1/K, e.g. 11.5e-6 for steel)")
    p.add_argument("--temperature-normalise", action="store_true",
                   help="normalise linear axes to 20 C: x - alpha (T - 20) (P - P_0), T from temperature_c")
    p.add_argument("--angle-unit", choices=("arcsec", "urad", "deg"), default="arcsec",
                   help="unit of rotary deviations (default arcsec)")
    p.add_argument("--point", metavar="LABEL", help="use one reflector (default: the centroid of all of them)")
    machine_argument(p, DEFAULT_MACHINE)
    p.add_argument("-o", "--output", metavar="REPORT_DIR",
                   help="write iso230-2_AXIS.csv (targets), iso230-2_AXIS_parameters.csv, iso230-2_AXIS.md, "
                        "iso230-2_AXIS.png per axis")


def _targets(text: str | None) -> list[float] | None:
    if text is None:
        return None
    try:
        v = [float(t) for t in text.replace(";", ",").split(",") if t.strip()]
    except ValueError:
        v = []
    if not v or not all(math.isfinite(t) for t in v):
        raise InputError(f"--target-points must be finite numbers separated by commas, got {text!r}")
    return v


def run(args: argparse.Namespace) -> int:
    if args.temperature_normalise != (args.alpha is not None):
        raise InputError("temperature normalisation needs both --temperature-normalise and --alpha PER_K")
    res = _evaluate(args)
    planned = _planned(res, Path(args.output), args.recording) if args.output else {}
    out = res.to_dict()
    if args.output:
        out["files"] = _write(res, planned)
    if args.json:
        print(dumps(out))
        return 0
    for ev in res.axes.values():
        print(markdown(ev, res.source, res.temperature))
    if args.output:
        print("wrote " + ", ".join(out["files"]))
    return 0


def _evaluate(args: argparse.Namespace):
    """The evaluation of a tracker recording or of an interferometer's readings (by the file's header)."""
    from mtcal.iso230_2.evaluation import Iso230Result, evaluate, evaluate_runs, in_unit, temperature_normalisation
    from mtcal.iso230_2.readings import looks_like_readings, read_readings
    from mtcal.measurement.recordings import read_recording

    targets = _targets(args.target_points)
    if looks_like_readings(args.recording):
        runs, kind, notes, meta = read_readings(args.recording, args.unit, args.alpha, args.columns, args.directions)
        unit = args.result_unit or ("um" if kind == "linear" else args.angle_unit)
        if args.axis and meta.get("axis") and args.axis.strip().lower() != meta["axis"].strip().lower():
            raise InputError(f"{args.recording}: --axis {args.axis} but the export's metadata says axis "
                             f"{meta['axis']}")
        axis = args.axis or meta.get("axis") or "axis"
        ev = evaluate_runs(in_unit(runs, unit), axis, kind, targets, notes, args.target_tolerance, args.recording)
        return Iso230Result(args.recording, {axis: ev}, temperature_normalisation(args.alpha))
    for flag in ("unit", "columns", "directions"):
        if getattr(args, flag):
            raise InputError(f"{args.recording}: --{flag} is for an interferometer export; a tracker recording "
                             f"(axis, round, position, point, x, y, z) is in mm and deg (docs/design.md)")
    rec = read_recording(args.recording, args.machine)
    return evaluate(rec, axis=args.axis.upper() if args.axis else None, machine=args.machine, targets=targets,
                    alpha=args.alpha, angle_unit=args.angle_unit, point=args.point, result_unit=args.result_unit,
                    target_tolerance=args.target_tolerance)


def _planned(res, folder: Path, source: str) -> dict[str, dict]:
    """Every output of every axis checked before the first is written: {axis: {file name: path}}."""
    planned = {}
    for a in res.axes:
        names = [f"iso230-2_{a}.csv", f"iso230-2_{a}_parameters.csv", f"iso230-2_{a}.md", f"iso230-2_{a}.png"]
        planned[a] = {n: folder / n for n in names}
        for path in planned[a].values():
            if path.is_dir():
                raise InputError(f"output {path} is a directory; nothing was written")
            refuse_overwrite(path, source)
    return planned


def _write(res, planned: dict[str, dict]) -> list[str]:
    from mtcal.iso230_2.plots import plot_evaluation
    files = []
    for a, ev in res.axes.items():
        p = planned[a]
        texts = {f"iso230-2_{a}.csv": targets_csv(ev), f"iso230-2_{a}_parameters.csv": parameters_csv(ev),
                 f"iso230-2_{a}.md": markdown(ev, res.source, res.temperature)}
        for name, text in texts.items():
            atomic_write_text(p[name], text)
            files.append(str(p[name]))
        files.append(str(plot_evaluation(ev, p[f"iso230-2_{a}.png"])))
    return files


DIGITS = {"mm": 5, "inch": 6, "deg": 7}  # decimals shown per result unit (um, arcsec, urad: 2)


def _num(v: float, digits: int = 2) -> str:
    if v is None or math.isnan(v):
        return ""
    text = f"{v:.{digits}f}"
    return text.lstrip("-") if float(text) == 0 else text  # no "-0.00"


def targets_csv(ev) -> str:
    """Per-target table: position and the ISO 230-2 values (``ev.unit``)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([f"position_{ev.position_unit}"] + [k if k.startswith("n_") else f"{k}_{ev.unit}" for k, _ in COLUMNS])
    for i, p in enumerate(ev.positions):
        w.writerow([f"{p:g}"] + [int(ev.targets[k][i]) if k.startswith("n_") else
                                 _num(ev.targets[k][i], DIGITS.get(ev.unit, 2) + 2) for k, _ in COLUMNS])
    return buf.getvalue()


def parameters_csv(ev) -> str:
    from mtcal.iso230_2.evaluation import PARAMETERS
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["parameter", f"value_{ev.unit}", "meaning"])
    for k in ORDER:
        w.writerow([k, _num(ev.parameters[k], DIGITS.get(ev.unit, 2) + 2), PARAMETERS[k]])
    return buf.getvalue()


def markdown(ev, source: str, temperature: dict | None) -> str:
    """The table labs report: per target, then the axis parameters (ISO 230-2:2014 names)."""
    from mtcal.iso230_2.evaluation import PARAMETERS
    lines = [f"### ISO 230-2:2014 axis {ev.axis} ({ev.kind}) — {source}", "",
             f"Positional deviations in {ev.unit}, target positions in {ev.position_unit}; "
             f"↑ = approached in the + direction, ↓ = in the − direction."]
    if temperature and ev.kind == "linear":
        lines.append(f"Normalised to 20 °C with α = {temperature['alpha_per_K']:g} /K: {temperature['formula']}.")
    lines += ["", "| target | " + " | ".join(h for _, h in COLUMNS) + " |", "|" + "---:|" * (len(COLUMNS) + 1)]
    for i, p in enumerate(ev.positions):
        cells = [str(int(ev.targets[k][i])) if k.startswith("n_") else _num(ev.targets[k][i], DIGITS.get(ev.unit, 2))
                 for k, _ in COLUMNS]
        lines.append(f"| {p:g} | " + " | ".join(cells) + " |")
    lines += ["", f"| parameter | {ev.unit} | meaning |", "|---|---:|---|"]
    lines += [f"| {k} | {_num(ev.parameters[k], DIGITS.get(ev.unit, 2))} | {PARAMETERS[k]} |" for k in ORDER]
    lines += [""] + [f"- note: {n}" for n in ev.notes] + [""]
    return "\n".join(lines)
