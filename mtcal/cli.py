"""`mtcal` command line.  Each subcommand is a module in mtcal/commands/ with NAME, HELP,
add_arguments(parser) and run(args) -> exit code; every subcommand offers --json (machine-readable stdout)."""
from __future__ import annotations

import argparse
import importlib
import logging
import pkgutil
import sys

from mtcal import commands
from mtcal.commands._options import add_common_arguments


def _modules():
    for info in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
        if not info.name.startswith("_"):
            yield importlib.import_module(f"mtcal.commands.{info.name}")


class _logging:
    """Progress of every module goes through `logging` (logger "mtcal.<module>") to stderr as
    "mtcal COMMAND: message"; -q keeps warnings only.  The previous configuration is restored on exit (the demo
    runs commands in-process)."""

    def __init__(self, command: str, quiet: bool):
        self.log = logging.getLogger("mtcal")
        self.command, self.quiet = command, quiet

    def __enter__(self):
        self.saved = (self.log.handlers[:], self.log.level, self.log.propagate)
        h = logging.StreamHandler(sys.stderr)
        h.setFormatter(logging.Formatter(f"mtcal {self.command}: %(message)s"))
        self.log.handlers[:] = [h]
        self.log.setLevel(logging.WARNING if self.quiet else logging.INFO)
        self.log.propagate = False

    def __exit__(self, *exc):
        self.log.handlers[:], self.log.level, self.log.propagate = self.saved


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="mtcal", description="Machine-tool calibration with a laser tracker or a 2-D plate.")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for mod in _modules():
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=mod.HELP)
        add_common_arguments(p)
        mod.add_arguments(p)
        p.set_defaults(_run=mod.run)
    return ap


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        with _logging(args.command, args.quiet):
            return int(args._run(args) or 0)
    except (ValueError, FileNotFoundError) as exc:  # InputError is a ValueError
        print(f"mtcal {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
