"""The `mtcal` command line: ``_main`` is the error boundary (exit codes, signals, logging), ``_options`` the
shared options, and every other module one subcommand (NAME, HELP, add_arguments(parser), run(args)).  Commands
parse and format only; the work is done by the library packages."""
from mtcal.cli._main import build_parser, main, parse_args

__all__ = ["build_parser", "main", "parse_args"]
