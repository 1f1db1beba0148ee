"""`mtcal --help` loads no command: the parser reads each command's NAME and HELP from its source (mtcal.cli._main
._commands), and only the command named on the line is imported (issue 36: `mtcal --help` took 6.8 s because the
parser imported every command and with them scipy)."""
from __future__ import annotations

import subprocess
import sys

CODE = """
import contextlib, io, sys
from mtcal.cli import main
with contextlib.redirect_stdout(io.StringIO()) as out:
    code = main(ARGV)
heavy = sorted(m for m in sys.modules if m in ("numpy", "scipy", "matplotlib") or m.startswith("mtcal.cli.")
               and not m.startswith("mtcal.cli._"))
print(code, heavy, "COMMAND" in out.getvalue() or "usage" in out.getvalue())
"""


def _run(argv: list[str]) -> str:
    r = subprocess.run([sys.executable, "-c", CODE.replace("ARGV", repr(argv))], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    return r.stdout.strip()


def test_top_level_help_imports_no_command_and_no_numpy():
    assert _run(["--help"]) == "0 [] True"


def test_one_commands_help_imports_that_command_only():
    code, rest = _run(["plate", "--help"]).split(" ", 1)
    assert code == "0"
    assert "'mtcal.cli.plate'" in rest
    others = [m for m in ("identify", "diagnose", "uncertainty", "compensate", "export") if f"mtcal.cli.{m}'" in rest]
    assert others == []


def test_every_command_is_listed_with_its_help():
    from mtcal.cli._main import _commands
    names = _commands()
    assert {"identify", "diagnose", "iso230-2", "import-sa", "uncertainty", "plate"} <= set(names)
    r = subprocess.run([sys.executable, "-m", "mtcal.cli", "--help"], capture_output=True, text=True, timeout=120)
    for name in names:
        assert name in r.stdout
    assert "ISO 230-2:2014 evaluation" in r.stdout
