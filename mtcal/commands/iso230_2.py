"""`mtcal iso230-2 REC.csv`: ISO 230-2:2014 positioning accuracy and repeatability of linear and rotary axes
(evaluation in mtcal.iso230_2; this module parses arguments and formats tables)."""
from __future__ import annotations

import argparse
import csv
import io
import math
from pathlib import Path

from mtcal.commands._options import real
from mtcal.errors import InputError
from mtcal.io import atomic_write_text, dumps, refuse_overwrite
from mtcal.commands._options import machine_argument
from mtcal.machine import DEFAULT_MACHINE

NAME = "iso230-2"
HELP = ("ISO 230-2:2014 evaluation of an axis from a recording: per target mean deviations up/down, reversal, "
        "repeatability; axis A, E, M, R, B (linear: um; rotary: arcsec)")
COLUMNS = (("n_up", "n↑"), ("n_down", "n↓"), ("mean_up", "x̄↑"), ("mean_down", "x̄↓"), ("mean", "x̄"),
           ("reversal", "B_i"), ("s_up", "s↑"), ("s_down", "s↓"), ("R_up", "R↑"), ("R_down", "R↓"), ("R", "R_i"))
ORDER = ("A", "A_up", "A_down", "E", "E_up", "E_down", "M", "R", "R_up", "R_down", "B", "B_mean")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("recording", metavar="REC.csv", help="tidy recording (design.md)")
    p.add_argument("--axis", metavar="NAME", help="axis to evaluate (default: every axis in the recording)")
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
    from mtcal.iso230_2 import evaluate
    from mtcal.recordings import read_recording

    if args.temperature_normalise != (args.alpha is not None):
        raise InputError("temperature normalisation needs both --temperature-normalise and --alpha PER_K")
    if args.output:
        refuse_overwrite([], args.recording, dirs={args.output: ["iso230-2_*"]})
    rec = read_recording(args.recording, args.machine)
    res = evaluate(rec, axis=args.axis.upper() if args.axis else None, machine=args.machine,
                   targets=_targets(args.target_points), alpha=args.alpha, angle_unit=args.angle_unit,
                   point=args.point)
    out = res.to_dict()
    if args.output:
        out["files"] = _write(res, Path(args.output), args.recording)
    if args.json:
        print(dumps(out))
        return 0
    for ev in res.axes.values():
        print(markdown(ev, res.source, res.temperature))
    if args.output:
        print("wrote " + ", ".join(out["files"]))
    return 0


def _write(res, folder: Path, source: str) -> list[str]:
    from mtcal.plots_iso230_2 import plot_evaluation
    files = []
    for a, ev in res.axes.items():
        texts = {f"iso230-2_{a}.csv": targets_csv(ev), f"iso230-2_{a}_parameters.csv": parameters_csv(ev),
                 f"iso230-2_{a}.md": markdown(ev, res.source, res.temperature)}
        for name in list(texts) + [f"iso230-2_{a}.png"]:
            refuse_overwrite(folder / name, source)
        for name, text in texts.items():
            atomic_write_text(folder / name, text)
            files.append(str(folder / name))
        files.append(str(plot_evaluation(ev, folder / f"iso230-2_{a}.png")))
    return files


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
        w.writerow([f"{p:g}"] + [int(ev.targets[k][i]) if k.startswith("n_") else _num(ev.targets[k][i], 4)
                                 for k, _ in COLUMNS])
    return buf.getvalue()


def parameters_csv(ev) -> str:
    from mtcal.iso230_2 import PARAMETERS
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["parameter", f"value_{ev.unit}", "meaning"])
    for k in ORDER:
        w.writerow([k, _num(ev.parameters[k], 4), PARAMETERS[k]])
    return buf.getvalue()


def markdown(ev, source: str, temperature: dict | None) -> str:
    """The table labs report: per target, then the axis parameters (ISO 230-2:2014 names)."""
    from mtcal.iso230_2 import PARAMETERS
    lines = [f"### ISO 230-2:2014 axis {ev.axis} ({ev.kind}) — {source}", "",
             f"Positional deviations in {ev.unit}, target positions in {ev.position_unit}; "
             f"↑ = approached in the + direction, ↓ = in the − direction."]
    if temperature and ev.kind == "linear":
        lines.append(f"Normalised to 20 °C with α = {temperature['alpha_per_K']:g} /K: {temperature['formula']}.")
    lines += ["", "| target | " + " | ".join(h for _, h in COLUMNS) + " |", "|" + "---:|" * (len(COLUMNS) + 1)]
    for i, p in enumerate(ev.positions):
        cells = [str(int(ev.targets[k][i])) if k.startswith("n_") else _num(ev.targets[k][i]) for k, _ in COLUMNS]
        lines.append(f"| {p:g} | " + " | ".join(cells) + " |")
    lines += ["", f"| parameter | {ev.unit} | meaning |", "|---|---:|---|"]
    lines += [f"| {k} | {_num(ev.parameters[k])} | {PARAMETERS[k]} |" for k in ORDER]
    lines += [""] + [f"- note: {n}" for n in ev.notes] + [""]
    return "\n".join(lines)
