"""The runnable examples of README.md and docs/ (issue 23: docs that cannot drift), read and run as written.

Blocks (fenced, the info string decides):
* ``bash``: the block runs as one ``bash -e`` script;
* ``console``: each ``$ COMMAND`` line runs; the lines after it, up to the next ``$``, are its expected output
  (stdout and stderr, trailing blanks ignored; ``...`` in a line matches any text, a line ``...`` any lines);
  ``# exit N`` at the end of a command expects exit code N (else 0);
* ``python``: runs with the page's interpreter;
* anything else (``text``, ``json``, ``toml``, ``csv``): shown, not run.  A fenced block without a language,
  or an indented code block, is refused (each example says what it is).
A block right after ``<!-- not run: REASON -->`` is skipped (the README's two set-up commands, which CI runs).
Every page runs in its own empty folder, its blocks in order: an example builds what it needs on its page.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RUN = {"bash", "console", "python"}
SHOWN = {"text", "json", "toml", "csv", "output", "ini", "mermaid"}


@dataclass
class Block:
    page: Path
    line: int
    lang: str
    text: str
    skip: str | None


def pages() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def blocks(page: Path) -> list[Block]:
    """The fenced blocks of a page; raises ValueError on a fence without a language or an indented code block."""
    lines = page.read_text().split("\n")
    out, i, skip = [], 0, None
    while i < len(lines):
        line = lines[i]
        m = re.match(r"<!-- not run: (.+) -->", line.strip())
        if m:
            skip = m.group(1)
        elif line.startswith("```"):
            lang = line[3:].strip().split()[0] if line[3:].strip() else ""
            if not lang:
                raise ValueError(f"{page.name}:{i + 1}: a fenced block needs a language ({sorted(RUN | SHOWN)})")
            j = i + 1
            while not lines[j].startswith("```"):
                j += 1
            out.append(Block(page, i + 1, lang, "\n".join(lines[i + 1:j]), skip))
            skip, i = None, j
        elif line.startswith("    ") and i > 0 and not lines[i - 1].strip() and not _in_list(lines, i):
            raise ValueError(f"{page.name}:{i + 1}: an indented code block; fence it with a language")
        i += 1
    return out


def _in_list(lines: list[str], i: int) -> bool:
    """Whether line i continues a list item (indented text under `* ` / `1. `), not a code block."""
    k = i - 1
    while k >= 0 and (not lines[k].strip() or lines[k].startswith("  ")):
        k -= 1
    return k >= 0 and bool(re.match(r"\s*([*+-]|\d+\.) ", lines[k])) and not lines[i].lstrip().startswith("$ ")


def _env() -> dict:
    env = dict(os.environ, MPLBACKEND="Agg", COLUMNS="120")
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    return env


def matches(want: str, got: str) -> bool:
    """Expected output with ``...`` wildcards (within a line; a line of its own: any lines) against the real one."""
    pat = []
    for line in want.rstrip().split("\n"):
        if line.strip() == "...":
            pat.append(r"(?:.*\n)*?")
        else:
            pat.append(".*".join(re.escape(part) for part in line.rstrip().split("...")) + r"[ \t]*\n")
    got = "\n".join(x.rstrip() for x in got.rstrip().split("\n")) + "\n"
    return re.fullmatch("".join(pat), got) is not None


def console_steps(text: str) -> list[tuple[str, int, str]]:
    """(command, expected exit code, expected output) of each ``$`` line of a console block."""
    steps: list[tuple[str, int, str]] = []
    for line in text.split("\n"):
        if line.startswith("$ "):
            cmd = line[2:]
            m = re.search(r"\s+# exit (\d+)$", cmd)
            steps.append((cmd[:m.start()] if m else cmd, int(m.group(1)) if m else 0, ""))
        elif steps:
            c, code, out = steps[-1]
            steps[-1] = (c, code, out + line + "\n")
    return steps


def run_block(b: Block, cwd: Path, timeout: float = 900) -> list[str]:
    """Problems found running one block (empty when it ran as written)."""
    where = f"{b.page.relative_to(ROOT)}:{b.line}"
    if b.lang == "python":
        p = subprocess.run([sys.executable, "-c", b.text], cwd=cwd, env=_env(), capture_output=True, text=True,
                           timeout=timeout)
        return [] if p.returncode == 0 else [f"{where}: python block failed:\n{p.stderr[-2000:]}"]
    if b.lang == "bash":
        p = subprocess.run(["bash", "-e", "-c", b.text], cwd=cwd, env=_env(), capture_output=True, text=True,
                           timeout=timeout)
        return [] if p.returncode == 0 else [f"{where}: bash block failed ({p.returncode}):\n{p.stderr[-2000:]}"]
    problems = []
    for cmd, code, want in console_steps(b.text):
        p = subprocess.run(["bash", "-c", cmd], cwd=cwd, env=_env(), capture_output=True, text=True,
                           timeout=timeout)
        got = p.stdout + p.stderr
        if p.returncode != code:
            problems.append(f"{where}: `{cmd}` exited {p.returncode}, the page says {code}:\n{got[-2000:]}")
        elif want.strip() and not matches(want, got):
            problems.append(f"{where}: `{cmd}` printed\n{got}\nthe page shows\n{want}")
    return problems


_DURATION = re.compile(r"\(\d+(\.\d+)? s\)|\d+\.\d+ s\b")


def update(page: Path) -> int:
    """Rewrite the expected output of every console step that shows one with what the command prints now (run
    in a fresh folder, the page's blocks in order; durations become ``...``).  Returns the number of steps
    rewritten.  `python tests/docs_snippets.py PAGE.md ...`: outputs are produced by running, never typed."""
    import tempfile

    text = page.read_text()
    n = 0
    with tempfile.TemporaryDirectory() as d:
        for b in blocks(page):
            if b.skip or b.lang not in RUN:
                continue
            if b.lang != "console":
                run_block(b, Path(d))
                continue
            new = []
            for cmd, code, want in console_steps(b.text):
                p = subprocess.run(["bash", "-c", cmd], cwd=d, env=_env(), capture_output=True, text=True)
                got = "\n".join(x.rstrip() for x in (p.stdout + p.stderr).rstrip().split("\n"))
                suffix = f"  # exit {code}" if code else ""
                new.append(f"$ {cmd}{suffix}")
                if want.strip():
                    new.append(_DURATION.sub(lambda m: "(...)" if m.group(0).startswith("(") else "...", got))
                    n += want.strip() != new[-1].strip()
            text = text.replace("```console\n" + b.text + "\n```", "```console\n" + "\n".join(new) + "\n```", 1)
    page.write_text(text)
    return n


if __name__ == "__main__":
    for arg in sys.argv[1:]:
        print(f"{arg}: {update(Path(arg).resolve())} output(s) rewritten")
