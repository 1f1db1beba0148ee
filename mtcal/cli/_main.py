"""`mtcal` command line and its error boundary.  Each subcommand is a module of mtcal/cli/ with NAME, HELP,
add_arguments(parser) and run(args) -> exit code; every subcommand offers --json (machine-readable stdout).

Exit codes: 0 done; 2 bad input (a file, a field or an option: one line ``mtcal CMD: error: FILE:LINE: problem``,
also an operating-system refusal such as a missing file, a directory, no permission, a full disk); 1 a bug in
mtcal (a short request for a report; the traceback with ``--debug``); 130 interrupted (Ctrl-C); 143 terminated
(SIGTERM).  Interrupted and terminated runs leave no temporary file (mtcal.io.atomic_open removes its own).
"""
from __future__ import annotations

import argparse
import ast
import contextlib
import errno
import importlib
import logging
import pkgutil
import re
import sys
import traceback
import warnings
from pathlib import Path

from mtcal.cli._options import add_common_arguments, force_argument, join_negative_values
from mtcal.cli._signals import Terminated, caught
from mtcal.errors import InputError

EXIT_OK, EXIT_BUG, EXIT_INPUT, EXIT_INTERRUPT, EXIT_TERMINATED = 0, 1, 2, 130, 143
REPORT_URL = "the mtcal issue tracker"


def _commands() -> dict[str, tuple[str, str]]:
    """{command: (module, help)} of every subcommand module, read from the modules' NAME and HELP literals without
    importing them: ``mtcal --help`` and the parser of one command load only what that command needs."""
    out = {}
    here = Path(__file__).parent
    for info in sorted(pkgutil.iter_modules([str(here)]), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        tree = ast.parse((here / f"{info.name}.py").read_text(encoding="utf-8"))
        lit = {t.id: ast.literal_eval(node.value) for node in tree.body if isinstance(node, ast.Assign)
               for t in node.targets if isinstance(t, ast.Name) and t.id in ("NAME", "HELP")}
        out[lit["NAME"]] = (info.name, lit["HELP"])
    return out


def _command_in(argv: list[str]) -> str | None:
    """The subcommand an argument list names (the first word that is not a top-level option), or None."""
    return next((a for a in argv if not a.startswith("-")), None)


def flag_names(parser: argparse.ArgumentParser) -> dict[str, str]:
    """{keyword: --flag} of a command's options (argparse's dest and its long option string), its actions'
    (``history trend --plot``) included."""
    names = {}
    for a in parser._actions:
        if isinstance(a, argparse._SubParsersAction):
            for sub in a.choices.values():
                names.update(flag_names(sub))
        elif a.option_strings:
            names[a.dest] = max(a.option_strings, key=len)
    return names


def to_flags(text: str, flags: dict[str, str]) -> str:
    """A library message as the command line says it: an option the library names by its keyword in backquotes
    (`max_points`) becomes the command's flag (--max-points); other backquoted words stay."""
    return _KEYWORD.sub(lambda m: flags.get(m.group(1), m.group(0)), text)


_KEYWORD = re.compile(r"`([a-z][a-z0-9_]*)`")


class _FlagFormatter(logging.Formatter):
    def __init__(self, fmt: str, flags: dict[str, str]):
        super().__init__(fmt)
        self.flags = flags

    def format(self, record: logging.LogRecord) -> str:
        return to_flags(super().format(record), self.flags)


class _FlagWriter:
    """stdout as the command prints it: library messages' option keywords as the command's flags (``to_flags``)."""

    def __init__(self, stream, flags: dict[str, str]):
        self.stream, self.flags = stream, flags

    def write(self, text: str) -> int:
        return self.stream.write(to_flags(text, self.flags) if "`" in text else text)

    def __getattr__(self, name: str):
        return getattr(self.stream, name)


class _Folding(logging.StreamHandler):
    """stderr's handler: a line that repeats the one before it is not printed again; how many times it came is
    said once, when another line comes or the command ends ("the line above 8 more times")."""

    def __init__(self, stream, prefix: str):
        super().__init__(stream)
        self.prefix, self.last, self.repeats = prefix, None, 0

    def emit(self, record: logging.LogRecord) -> None:
        text = record.getMessage()
        if text == self.last:
            self.repeats += 1
            return
        self.flush_repeats()
        self.last = text
        super().emit(record)

    def flush_repeats(self) -> None:
        if self.repeats:
            self.stream.write(f"{self.prefix}the line above {self.repeats} more time{'s' * (self.repeats > 1)}\n")
            self.flush()
        self.repeats = 0


def _stopped(prog: str, how: type[BaseException], why: str, remove_temporaries) -> int:
    """Interrupted (Ctrl-C) or terminated (SIGTERM): no temporary left, one line, the exit code."""
    remove_temporaries()
    word, code = ("terminated", EXIT_TERMINATED) if how is Terminated else ("interrupted", EXIT_INTERRUPT)
    print(f"{prog}: {word}" + (f": {why}" if why else ""), file=sys.stderr)
    return code


class _logging:
    """Progress of every module goes through `logging` (logger "mtcal.<module>") to stderr as
    "mtcal COMMAND: message", a line repeating the one before it folded (``_Folding``); -q keeps warnings only.
    The previous configuration is restored on exit (the demo runs commands in-process)."""

    def __init__(self, command: str, quiet: bool, flags: dict[str, str] | None = None):
        self.log = logging.getLogger("mtcal")
        self.command, self.quiet, self.flags = command, quiet, flags or {}

    def __enter__(self):
        self.saved = (self.log.handlers[:], self.log.level, self.log.propagate)
        h = self.handler = _Folding(sys.stderr, f"mtcal {self.command}: ")
        h.setFormatter(_FlagFormatter(f"mtcal {self.command}: %(message)s", self.flags))
        self.log.handlers[:] = [h]
        self.log.setLevel(logging.WARNING if self.quiet else logging.INFO)
        self.log.propagate = False

    def __exit__(self, *exc):
        self.handler.flush_repeats()
        self.log.handlers[:], self.log.level, self.log.propagate = self.saved


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error (no usage block): ``mtcal CMD: error: argument --OPT: problem``."""

    def error(self, message: str):
        self.exit(EXIT_INPUT, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The whole command line; with ``only``, every command is listed but only that one's module is imported and
    its options added (what ``parse_args`` uses: ``mtcal --help`` imports no command at all)."""
    ap = _Parser(prog="mtcal", description="Machine-tool calibration with a laser tracker or a 2-D plate.")
    debug_help = "on an internal error (exit 1) print the full traceback"
    ap.add_argument("--debug", action="store_true", help=debug_help)
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, (module, text) in _commands().items():
        p = sub.add_parser(name, help=text, description=text.replace("%%", "%"))  # help is %-formatted, this not
        if only is None or name == only:
            mod = importlib.import_module(f"mtcal.cli.{module}")
            add_common_arguments(p, debug_help)
            mod.add_arguments(p)
            force_argument(p)
            p.set_defaults(_run=mod.run, _flags=flag_names(p))
    return ap


def describe_os_error(exc: OSError) -> str:
    """One line for an operating-system refusal: the path(s) and the problem in words."""
    words = {errno.EISDIR: "is a directory", errno.ENOTDIR: "a parent of this path is not a directory",
             errno.EACCES: "permission denied", errno.EPERM: "operation not permitted",
             errno.EROFS: "read-only file system", errno.ENOSPC: "no space left on device",
             errno.ENOENT: "no such file or directory", errno.EEXIST: "exists and is not a directory"}
    problem = words.get(exc.errno) or (exc.strerror or str(exc)).rstrip(".").lower()
    if exc.filename is None:
        return problem if exc.strerror else str(exc)
    paths = str(exc.filename) + (f" -> {exc.filename2}" if exc.filename2 is not None else "")
    return f"{paths}: {problem}"


def _show_warning(message, category, filename, lineno, file=None, line=None, prog: str = "mtcal",
                  flags: dict[str, str] | None = None) -> None:
    print(f"{prog}: warning: {to_flags(str(message), flags or {})}", file=sys.stderr)


def parse_args(argv: list[str]) -> argparse.Namespace:
    """Parsed command line (``args._run(args)`` runs it without the error boundary, e.g. inside ``mtcal demo``);
    a bad option raises SystemExit(2) after printing one line."""
    argv = join_negative_values(list(argv))
    return build_parser(_command_in(argv) or "").parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    """Run ``mtcal ARGV`` behind the error boundary (module docstring); returns the exit code."""
    try:
        args = parse_args(sys.argv[1:] if argv is None else argv)
    except SystemExit as exc:  # --help (0) or a bad option (2, message printed)
        return int(exc.code or 0)
    except KeyboardInterrupt:  # Ctrl-C while the command's modules load: nothing was started
        print("mtcal: interrupted", file=sys.stderr)
        return EXIT_INTERRUPT
    from mtcal.io import remove_temporaries, replace_allowed  # after parsing: `mtcal --help` stays light
    prog = f"mtcal {args.command}"
    old_show = warnings.showwarning
    flags = args._flags
    warnings.showwarning = lambda *a, **k: _show_warning(*a, prog=prog, flags=flags)
    signals = caught()
    try:
        with signals, _logging(args.command, getattr(args, "quiet", False), flags), \
                contextlib.redirect_stdout(_FlagWriter(sys.stdout, flags)), \
                replace_allowed(getattr(args, "replace", False)):
            return int(args._run(args) or 0)
    except InputError as exc:
        print(f"{prog}: error: {to_flags(str(exc), flags)}", file=sys.stderr)
        return EXIT_INPUT
    except OSError as exc:
        print(f"{prog}: error: {describe_os_error(exc)}", file=sys.stderr)
        return EXIT_INPUT
    except (KeyboardInterrupt, Terminated) as exc:  # its message, where it has one, says what was kept (uncertainty)
        return _stopped(prog, type(exc), to_flags(str(exc), flags), remove_temporaries)
    except Exception as exc:
        if signals.received is not None:  # the signal's exception turned into another on its way (an extension
            return _stopped(prog, signals.received, "", remove_temporaries)  # module's init: ImportError)
        print(f"{prog}: internal error ({type(exc).__name__}: {exc}); this is a bug in mtcal, please report it "
              f"to {REPORT_URL} with the command line{'' if args.debug else ' and the output of --debug'}",
              file=sys.stderr)
        if args.debug:
            traceback.print_exc()
        return EXIT_BUG
    finally:
        warnings.showwarning = old_show


