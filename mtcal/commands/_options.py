"""Options shared by the subcommands, defined once: --json and -q/--quiet on every command (added by
mtcal.cli), --machine on every command that takes a machine."""
from __future__ import annotations

import argparse


def add_common_arguments(p: argparse.ArgumentParser) -> None:
    """The options every subcommand has (defined once here)."""
    p.add_argument("--json", action="store_true", help="print a machine-readable JSON answer on stdout")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress on stderr (warnings and errors only)")


def machine_argument(p: argparse.ArgumentParser, default: str | None = None) -> None:
    """--machine NAME, the same for every command that takes one (default: DEFAULT_MACHINE, or the model's)."""
    p.add_argument("--machine", default=default, metavar="NAME",
                   help="machine spec, one of derive/machines/*.toml (default: the model's if one is given, else "
                        "dmu50)")
