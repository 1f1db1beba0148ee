"""`mtcal export`: controller compensation tables from an error model (formatting only; see mtcal/export/)."""
from __future__ import annotations

import argparse
import logging
from pathlib import Path

from mtcal.cli._options import integer, real
from mtcal.cli._words import warn
from mtcal.errors import InputError
from mtcal.export import FORMATS, export_model
from mtcal.export.linuxcnc_kins import DEFAULT_NAME, export_kins
from mtcal.io import dumps, read_json, refuse_overwrite
from mtcal.kinematics.machine import load_machine
from mtcal.model.errormodel import load_model

NAME = "export"
KINS = "linuxcnc-kins"
log = logging.getLogger("mtcal." + NAME)
HELP = "write an error model as controller compensation tables (LinuxCNC, Siemens 840D sl, Heidenhain, TF5280)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("model", help="error model JSON (mtcal identify)")
    p.add_argument("--format", required=True, choices=sorted(FORMATS) + [KINS],
                   help="linuxcnc: folder of COMP_FILEs + INI snippet; siemens: one MPF (LEC + CEC); heidenhain: "
                        "folder of *.COM + CONFIG.CMA; tf5280: ISG CSV file; etalon: Etalon exchange file; "
                        "linuxcnc-kins: a LinuxCNC kinematics component NAME.comp (volumetric, every move)")
    p.add_argument("-o", "--output", required=True, help="output folder (linuxcnc, heidenhain) or file")
    p.add_argument("--step", type=real(0.0, unit="mm or deg", lo_open=True), default=None, metavar="MM_OR_DEG",
                   help="table spacing (mm for linear, deg for rotary axes; default: the finest 1/2/2.5/5 x 10^k "
                        "that covers each axis' range within the format's point limit)")
    p.add_argument("--max-points", type=integer(2), default=None, metavar="N",
                   help="points per table (default: the format's limit: 256; tf5280/etalon 1000)")
    p.add_argument("--diagnosis", metavar="DIAG.json",
                   help="`mtcal diagnose --json` answer: significant backlash findings give direction-dependent tables")
    p.add_argument("--comp-file-type", type=int, choices=(0, 1), default=0,
                   help="linuxcnc COMP_FILE_TYPE: 0 = nominal, forward, reverse positions; 1 = nominal and trims "
                        "(default 0)")
    p.add_argument("--require", default="", metavar="NAMES",
                   help="comma-separated error names (e.g. E_XX,E_YX) that must be held; refused if the format cannot")
    p.add_argument("--kinematics-comp", action="store_true",
                   help="heidenhain: also write KinematicsComp tables KC_<axis>.COM (C1..C6 = ISO 230-1 errors)")
    p.add_argument("--control", choices=("840d", "828d", "808d"), default="840d",
                   help="siemens: the SINUMERIK control (808D / 828D: 200 points per table, 828D: 8 CEC tables; "
                        "840D sl: sized by MD38000 / MD18342; default 840d)")
    p.add_argument("--measuring-system", type=int, choices=(0, 1), default=0,
                   help="siemens: index e of $AA_ENC_COMP[e,N,AXi], the axis' encoder the LEC table belongs to "
                        "(default 0, the first; 1 = the second, as machines whose MD38000[1] is sized)")
    p.add_argument("--linear-units", choices=("mm", "inch"), default="mm",
                   help="linuxcnc: the machine INI's [TRAJ]LINEAR_UNITS; linear joints' tables are written in it "
                        "(default mm)")
    p.add_argument("--name", default=DEFAULT_NAME, metavar="C_NAME",
                   help=f"linuxcnc-kins: the component's name, [KINS]KINEMATICS (default {DEFAULT_NAME})")
    p.add_argument("--scope", choices=("position", "full"), default="position",
                   help="linuxcnc-kins: position = the linear axes compensate the tool tip; full = the rotary axes "
                        "also correct the tool axis, as `mtcal compensate --scope full` (default position)")
    p.add_argument("--machine", metavar="NAME",
                   help="the machine the tables are for: refused when the model is of another (default: the model's)")
    p.add_argument("--force", action="store_true",
                   help="write a model that fails the plausibility guard (values beyond a machine's errors, tables "
                        "outside the travel, a diagnosis of another recording), with a loud warning (it never replaces "
                        "a file mtcal did not write: --replace)")


def _options(args: argparse.Namespace) -> dict:
    """The format's own options (the rest are refused for formats they do not apply to)."""
    if args.measuring_system or args.control != "840d":
        if args.format != "siemens":
            raise InputError(f"--measuring-system and --control are siemens options, not {args.format}'s")
    if args.linear_units != "mm" and args.format != "linuxcnc":
        raise InputError(f"--linear-units is a linuxcnc option, not {args.format}'s")
    return ({"measuring_system": args.measuring_system, "control": args.control} if args.format == "siemens" else
            {"linear_units": args.linear_units} if args.format == "linuxcnc" else {})


def _run_kins(args: argparse.Namespace) -> int:
    """--format linuxcnc-kins: the kinematics component and the lines that use it (mtcal.export.linuxcnc_kins)."""
    tables = [o for o, given in (("--step", args.step is not None), ("--max-points", args.max_points is not None),
                                 ("--diagnosis", args.diagnosis), ("--require", args.require),
                                 ("--comp-file-type", args.comp_file_type), ("--kinematics-comp", args.kinematics_comp),
                                 ("--linear-units", args.linear_units != "mm")) if given]
    if tables:
        raise InputError(f"{', '.join(tables)}: table options, not {KINS}'s (the module compiles the model's error "
                         f"functions in, in mm)")
    model = load_model(args.model)
    res = export_kins(model, load_machine(args.machine or model.machine), args.output, args.name, args.model,
                      args.force, protect=(args.model,), scope=args.scope)
    if args.json:
        print(dumps({"format": KINS, "files": res.files, "name": res.name, "hal_name": res.hal_name,
                     "lines": res.lines, "held": res.held, "warnings": res.warnings}))
        return 0
    print(f"{args.model} -> {KINS}: component {res.name} (HAL {res.hal_name}), scope {args.scope}, "
          f"{len(res.held)} errors held")
    print("\n".join(res.lines))
    for w in res.warnings:
        log.warning("warning: %s", w)
    for f in res.files:
        print(f"wrote {f}")
    return 0


def run(args: argparse.Namespace) -> int:
    if args.format == KINS:
        return _run_kins(args)
    if args.name != DEFAULT_NAME or args.scope != "position":
        raise InputError(f"--name and --scope are {KINS} options, not {args.format}'s")
    if FORMATS[args.format][1] == "dir":
        if Path(args.output).exists() and not Path(args.output).is_dir():
            raise InputError(f"{args.output}: format {args.format} writes a folder, and this is a file")
        # an existing folder is fine (a re-export); export_model checks every file it writes there against the inputs
        refuse_overwrite([], args.model, args.diagnosis, dirs={args.output: []})
    else:
        refuse_overwrite(args.output, args.model, args.diagnosis)
    model = load_model(args.model)
    machine = load_machine(args.machine or model.machine)
    diag = read_json(args.diagnosis, "diagnosis") if args.diagnosis else None
    require = [n.strip() for n in args.require.split(",") if n.strip()]
    res = export_model(model, machine, args.format, args.output, args.model, args.step, args.max_points, diag,
                       args.comp_file_type, require, args.kinematics_comp,
                       protect=tuple(p for p in (args.model, args.diagnosis) if p),
                       diagnosis_source=args.diagnosis or "diagnosis", force=args.force,
                       options=_options(args))
    out = {"format": res.format, "files": res.files, "sign": res.sign, "held": res.held, "not_held": res.not_held,
           "tables": res.tables, "warnings": res.warnings,
           "units": {"positions": "mm (linear axes), deg (rotary axes)",
                     "corrections": "unit of the output axis (mm or deg)"}}
    if args.json:
        print(dumps(out))
        return 0
    print(f"{args.model} -> {args.format}: {len(res.files)} file(s)")
    print(f"sign: {res.sign}")
    for t in res.tables:
        outs = ", ".join(f"{o} from {'+'.join(v['errors'])} (max {v['max_abs_correction']:.4g} {v['unit']})"
                         for o, v in t["outputs"].items())
        print(f"  axis {t['axis']}: {t['points']} points, step {t['step']:g} {t['unit']}, "
              f"[{t['from']:g}, {t['to']:g}]: {outs}" + (f"; reversal {t['reversal']:.4g}" if t["reversal"] else ""))
        if t.get("note"):
            print(f"    {t['note']}")
    if res.not_held:
        warn(f"not held by {args.format} (compensate these with `mtcal compensate` or another format): "
             f"{', '.join(res.not_held)}")
    for w in res.warnings:
        log.warning("warning: %s", w)
    for f in res.files:
        print(f"wrote {f}")
    return 0
