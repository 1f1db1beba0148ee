"""`mtcal compensate`: corrected NC data (G-code or CL data) from an error model."""
from __future__ import annotations

import argparse
import logging
import time
from pathlib import Path

from mtcal.cli._options import integer, real
from mtcal.cli._words import listed, warn, warn_outside
from mtcal.compensate.run import compensate_program
from mtcal.compensate.solver import MAX_CORRECTION_MM, MAX_ROTARY_CORRECTION_DEG, RESIDUAL_EVERY
from mtcal.io import dumps, refuse_overwrite

TABLE_FILES = ("comp_*.csv", "constants.csv")  # what mtcal.compensate.tables.write_tables writes
NAME = "compensate"
log = logging.getLogger("mtcal." + NAME)
HELP = "compensate an NC program (G-code or CL data) for the errors in a model, exactly to first order"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("program", help="NC program: G-code (G0/G1, X Y Z B C) or CL data (x y z i j k; .cl or --input cl)")
    p.add_argument("--model", required=True, help="error model JSON (mtcal identify)")
    p.add_argument("--force", action="store_true",
                   help="compensate with a model that fails the plausibility guard (mtcal.model.plausibility), "
                        "with a loud warning (it never replaces a file mtcal did not write: --replace)")
    p.add_argument("--allow-subprograms", action="store_true",
                   help="pass subprogram calls (M98, M99, CALL PGM / LBL) unchanged with a warning: the moves of the "
                        "called program are NOT compensated (default: refused)")
    p.add_argument("-o", "--output", required=True, help="compensated G-code to write")
    p.add_argument("--scope", choices=("position", "full"), default="position",
                   help="position: X Y Z put the tool tip on target (L-VOL, R-VOL); full: B C also correct the tool "
                        "axis (FOR) outside the cone around B = 0 (default: position)")
    p.add_argument("--tolerance", type=real(0.0, unit="mm", lo_open=True), default=0.001, metavar="MM",
                   help="largest predicted mid-segment tool-tip error before a feed move is subdivided (default 0.001)")
    p.add_argument("--tool-length", type=real(0.0, unit="mm"), default=0.0, metavar="MM",
                   help="tool length below the error reference point (default 0)")
    p.add_argument("--iterations", type=integer(1, 50), default=None, metavar="N",
                   help="1: first-order correction; more: fixed-point iterations on the exact model (default 1 for "
                        "scope position, 2 for full: first order leaves up to ~0.5 urad of second-order tool-axis "
                        "error where the uncompensated error is ~180 urad)")
    p.add_argument("--precision", type=integer(0, 9), default=None, metavar="N",
                   help="least decimals written (mm and deg; inch one more); more if the input has more (default 4)")
    p.add_argument("--cone", type=real(0.0, 45.0, "deg"), default=2.0, metavar="DEG",
                   help="full scope: no B/C correction while the tool axis is within DEG of the C axis, blended in "
                        "up to 2*DEG (default 2)")
    p.add_argument("--input", choices=("auto", "gcode", "cl"), default="auto",
                   help="input kind (default: by extension, .cl/.cls/.apt = CL data)")
    p.add_argument("--outside", choices=("hold", "error"), default="hold",
                   help="axis positions outside an error table: hold the end values and count them, or stop")
    p.add_argument("--max-correction", type=real(0.0, unit="mm", lo_open=True), default=MAX_CORRECTION_MM,
                   metavar="MM",
                   help="refuse to write a program with a linear-axis correction larger than MM: a model in the wrong "
                        f"units (default {MAX_CORRECTION_MM:g})")
    p.add_argument("--max-rotary-correction", type=real(0.0, unit="deg", lo_open=True),
                   default=MAX_ROTARY_CORRECTION_DEG, metavar="DEG",
                   help=f"the same for rotary axes (default {MAX_ROTARY_CORRECTION_DEG:g})")
    p.add_argument("--tables", metavar="DIR", help="also write per-axis compensation tables (CSV) to DIR")
    p.add_argument("--uncertainty", metavar="MC.json",
                   help="report the tool tip's uncertainty after compensation from `mtcal uncertainty REC.csv "
                        "--program PROGRAM -o MC.json` (GUM-S1 Monte Carlo of the model at this program's moves)")
    p.add_argument("--residual-every", type=integer(1), default=RESIDUAL_EVERY, metavar="K",
                   help="evaluate the exact error-inclusive residual of what is written on every K-th move (and on "
                        f"every inserted point); 1: on all moves (default {RESIDUAL_EVERY}; the JSON says which)")


def _after_line(res: dict, args: argparse.Namespace) -> str:
    """What the compensated tool tip is uncertain by: the Monte Carlo's interval at this program's moves when
    ``--uncertainty`` gives it, else identify's split-half prediction of the model's error, else what to run."""
    if "task_uncertainty" in res:
        tu = res["task_uncertainty"]
        return (f"tool tip uncertain by U95 up to {tu['u95_max_um']:.2f} um, RMS {tu['u95_rms_um']:.2f} um over "
                f"{tu['moves']} moves ({tu['trials']}-trial Monte Carlo of the identification, {args.uncertainty}"
                + (f", computed for {tu['computed_for']}: the same contents" if tu["computed_for"] !=
                   Path(args.program).name else "") + ")")
    hint = (f"for the tool tip's interval at these moves run `mtcal uncertainty REC.csv --program "
            f"{Path(args.program).name} -o MC.json` and give --uncertainty MC.json")
    worth = res["model_worth"]
    if worth:
        return (f"the model's own error, predicted from the rounds: {worth['predicted_error_rms_um']:.1f} um RMS over "
                f"its measured volume (it corrects {worth['corrects_rms_um']:.1f} um RMS); {hint}")
    return f"not stated (the model carries no prediction of its own error); {hint}"


def run(args: argparse.Namespace) -> int:
    refuse_overwrite([args.output], args.program, args.model, args.uncertainty, dirs={args.tables: TABLE_FILES})
    last = [time.perf_counter()]

    def progress(done: int, total: int) -> None:
        now = time.perf_counter()
        if total > 2_000_000 and (now - last[0] > 1.0 or done >= total):
            last[0] = now
            log.info("%5.1f%% of %s", 100 * done / total, args.program)

    res = compensate_program(args.program, args.output, args.model, scope=args.scope, iterations=args.iterations,
                             tool_length=args.tool_length, cone=args.cone, outside=args.outside,
                             tolerance=args.tolerance, precision=args.precision, residual_every=args.residual_every,
                             max_correction=args.max_correction, max_rotary_correction=args.max_rotary_correction,
                             allow_subprograms=args.allow_subprograms, kind=args.input, tables=args.tables,
                             force=args.force, progress=progress, uncertainty=args.uncertainty)
    worth = res["model_worth"]
    if worth and worth.get("may_worsen"):
        log.warning("warning: %s: compensating with this model may make the machine worse: it corrects %.1f um RMS "
                    "and is itself uncertain by %.1f um RMS over its measured volume (identify's split-half "
                    "prediction); measure more rounds or from more tracker stations", args.model,
                    worth["corrects_rms_um"], worth["predicted_error_rms_um"])
    if args.json:
        print(dumps(res))
        return 0
    r = res["residual"]
    print(f"{args.program} -> {args.output}: {res['moves']} moves, {res['lines_changed']} lines changed, "
          f"{res['lines_inserted']} inserted ({res['subdivided_moves']} moves subdivided), scope {args.scope}")
    print(f"ISO/TR 16907: {', '.join(res['iso_16907']['covered']) or 'none (zero model)'}")
    print(f"tool tip  : uncompensated max {res['uncompensated']['position_um']['max']:.3f} um (the model's prediction "
          f"of the machine's error at the moves)")
    print(f"after     : {_after_line(res, args)}")
    print(f"solver    : the written program on the model itself: max {r['position_um']['max']:.4f} um, RMS "
          f"{r['position_um']['rms']:.4f} um (the compensation's numerical residual, not the machine's remaining "
          f"error; exact model on {r['evaluated_on']})")
    full = args.scope == "full"
    lab = "controllable" if full else "not corrected (scope position)"
    print(f"tool axis : uncompensated max {res['uncompensated']['orientation_urad']['max']:.2f} urad -> residual "
          f"max {r['orientation_urad']['max']:.3f} urad, RMS {r['orientation_urad']['rms']:.3f} urad ({lab})")
    if full:
        s = res["singularity"]
        print(f"near B = 0: {s['moves_in_cone']} moves inside the {args.cone:g} deg cone (position only), "
              f"{s['moves_blended']} blended; largest C correction {s['max_c_correction_deg']:.5f} deg")
    warn_outside(res["warnings"]["outside_range"])
    rapids = res["warnings"]["uncompensated_rapids"]
    if rapids:
        warn(f"{len(rapids)} rapid moves before all linear axes were known passed uncompensated (lines "
             f"{listed(rapids)})")
    for t in res["tables"]:
        print(f"table: {t}")
    return 0
