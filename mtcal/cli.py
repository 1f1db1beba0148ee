"""`mtcal` command line.  Each subcommand is a module in mtcal/commands/ with NAME, HELP,
add_arguments(parser) and run(args) -> exit code; every subcommand offers --json (machine-readable stdout)."""
from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys

from mtcal import commands


def _modules():
    for info in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
        if not info.name.startswith("_"):
            yield importlib.import_module(f"mtcal.commands.{info.name}")


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="mtcal", description="Machine-tool calibration with a laser tracker or a 2-D plate.")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for mod in _modules():
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=mod.HELP)
        p.add_argument("--json", action="store_true", help="print a machine-readable JSON answer on stdout")
        mod.add_arguments(p)
        p.set_defaults(_run=mod.run)
    return ap


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return int(args._run(args) or 0)
    except (ValueError, FileNotFoundError) as exc:  # InputError is a ValueError
        print(f"mtcal {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
