"""Options shared by the subcommands, defined once: --json, -q/--quiet and --debug on every command
(``add_common_arguments``, added by mtcal.cli), --machine on every command that takes a machine
(``machine_argument``), --tracker-model on every command that takes a tracker law (``tracker_model_argument``),
and the argparse ``type=`` helpers: every numeric option is checked (finite, in range, unit named) at parse time.

A helper raises ``argparse.ArgumentTypeError``, so argparse prints ``mtcal CMD: error: argument --OPT: PROBLEM``
and exits 2.  ``join_negative_values`` lets ``--tracker -2000,0,300`` mean what it says (argparse would take the
leading '-' for an option).
"""
from __future__ import annotations

import argparse
import math
import re
from typing import TYPE_CHECKING, Callable

from mtcal.errors import InputError

if TYPE_CHECKING:  # numpy is not imported for `mtcal --help`
    import numpy as np

# options whose value may start with '-' (a negative first number): pre-joined as --OPT=VALUE
NEGATIVE_OK = ("--tracker", "--target-points", "--tracker-model")
_NUMBERISH = re.compile(r"^-[0-9.]")


def join_negative_values(argv: list[str]) -> list[str]:
    """``[..., '--tracker', '-2000,0,300', ...]`` -> ``[..., '--tracker=-2000,0,300', ...]``."""
    out: list[str] = []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in NEGATIVE_OK and i + 1 < len(argv) and _NUMBERISH.match(argv[i + 1]):
            out.append(f"{a}={argv[i + 1]}")
            i += 2
            continue
        out.append(a)
        i += 1
    return out


def _number(text: str, what: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"expected {what} (finite), got {text!r}")
    return v


def real(lo: float | None = None, hi: float | None = None, unit: str = "", lo_open: bool = False,
         hi_open: bool = False) -> Callable[[str], float]:
    """A finite float in [lo, hi] (an end is open when ``lo_open``/``hi_open``); ``unit`` is named in messages."""
    what = "a number" + (f" in {unit}" if unit else "")

    def parse(text: str) -> float:
        v = _number(text, what)
        low_bad = lo is not None and (v <= lo if lo_open else v < lo)
        high_bad = hi is not None and (v >= hi if hi_open else v > hi)
        if low_bad or high_bad:
            raise argparse.ArgumentTypeError(f"expected {what} {_range(lo, hi, lo_open, hi_open)}, got {text!r}")
        return v
    parse.__name__ = "number"
    return parse


def integer(lo: int | None = None, hi: int | None = None) -> Callable[[str], int]:
    """A whole number in [lo, hi]."""
    def parse(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
        if (lo is not None and v < lo) or (hi is not None and v > hi):
            raise argparse.ArgumentTypeError(f"expected a whole number {_range(lo, hi)}, got {text!r}")
        return v
    parse.__name__ = "integer"
    return parse


def _range(lo, hi, lo_open: bool = False, hi_open: bool = False) -> str:
    if lo is not None and hi is not None:
        return f"in {'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
    if lo is not None:
        return f"{'>' if lo_open else '>='} {lo:g}"
    return f"{'<' if hi_open else '<='} {hi:g}"


def xyz(text: str) -> np.ndarray:
    """'x,y,z' in mm -> array (3,) of finite numbers (``--tracker``; mtcal.measurement.tracker.parse_xyz)."""
    from mtcal.measurement.tracker import parse_xyz
    try:
        return parse_xyz(text, what=None)
    except InputError as exc:
        raise argparse.ArgumentTypeError(exc.problem) from None


def tracker_law(text: str):
    """An instrument's name or 'a_r,b_r,a_t,b_t[,k]' (MPE, um and um/m) -> TrackerSpec (``--tracker-model``;
    mtcal.measurement.tracker.tracker_model)."""
    from mtcal.measurement.tracker import tracker_model
    try:
        return tracker_model(text, what=None)
    except InputError as exc:
        raise argparse.ArgumentTypeError(exc.problem) from None


def tracker_model_argument(p: argparse.ArgumentParser, what: str) -> None:
    """--tracker-model NAME|a_r,b_r,a_t,b_t[,k], the same for every command that takes one; ``what`` says what the
    law does in that command."""
    from mtcal.measurement.tracker import TRACKER_MODELS
    p.add_argument("--tracker-model", metavar="NAME|a_r,b_r,a_t,b_t[,k]", type=tracker_law, default=None,
                   help=f"the tracker's noise law: an instrument ({', '.join(TRACKER_MODELS)}; case-insensitive) or "
                   "its MPE along the beam a_r um + b_r um/m and across it a_t um + b_t um/m, sigma = MPE / k "
                   f"(default k 2) (default: AT960); {what}")


finite = real()
positive = real(0.0, lo_open=True)
nonnegative = real(0.0)
probability = real(0.0, 1.0, lo_open=True, hi_open=True)


def add_common_arguments(p: argparse.ArgumentParser, debug_help: str) -> None:
    """The options every subcommand has."""
    p.add_argument("--json", action="store_true", help="print a machine-readable JSON answer on stdout")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress on stderr (warnings and errors only)")
    p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS, help=debug_help)


OUTPUT_OPTIONS = ("output", "plots", "plot", "store", "out")  # dests of the options naming files a command writes
REPLACE_HELP = "replace an output file that mtcal did not write (or that was changed since)"


def force_argument(p: argparse.ArgumentParser) -> None:
    """The flag that lets a command replace output files mtcal did not write (mtcal.io.refuse_foreign; keyword
    ``replace``), on every command that writes a file (one of OUTPUT_OPTIONS): --force, except where --force already
    overrides the plausibility guard (export, compensate), which take --replace: replacing a file must never let an
    implausible model through, nor the other way round."""
    for sub in (a for a in p._actions if isinstance(a, argparse._SubParsersAction)):  # actions (history trend)
        for action_parser in sub.choices.values():
            force_argument(action_parser)
    dests = {a.dest for a in p._actions}
    if dests & set(OUTPUT_OPTIONS):
        p.add_argument("--replace" if "force" in dests else "--force", dest="replace", action="store_true",
                       help=REPLACE_HELP)


def machine_argument(p: argparse.ArgumentParser, default: str | None = None) -> None:
    """--machine NAME, the same for every command that takes one (default: DEFAULT_MACHINE, or the model's)."""
    p.add_argument("--machine", default=default, metavar="NAME",
                   help="machine spec, one of derive/machines/*.toml (default: the model's if one is given, else "
                        "dmu50)")
