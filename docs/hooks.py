"""MkDocs hooks: the CLI reference (docs/cli.md) generated from the parsers at build time, and every benchmark figure
the docs quote checked against benchmarks/results.json, so neither can drift from what the code does.

A quoted figure is written as plain text followed by a marker that names its key and format, so the markdown reads
as it is on GitHub and in the built site alike (an HTML comment shows in neither)::

    the demo campaign is diagnosed in 2.80 s<!-- bench diagnose_demo_s .2f -->

The number right before the marker (its last number on the line; ``*`` and a unit between them allowed) must equal
``format(results[KEY], FORMAT)`` (a ``%`` format compares the percentage: ``84 %`` for ``.0%`` of 0.844); a text
figure (``machine``, ``date``) must end the text before the marker.  The build fails on a figure that differs or a
key that is missing (tests/test_docs_figures.py checks the same in the suite).  After
``python benchmarks/run.py --save``, ``python docs/hooks.py README.md docs/**/*.md`` rewrites every quoted figure
from the file.
"""
from __future__ import annotations

import json
import os
import re
import sys
from pathlib import Path

MARK = "<!-- cli-reference -->"
RESULTS = Path(__file__).resolve().parents[1] / "benchmarks" / "results.json"
RATES = RESULTS.parent / "gen3"  # benchmarks/diagnose_gen3_rates.py --json rates_<code>_seed<S>_<mix>.json
RATES_BLOCK = re.compile(r"(<!-- rates -->\n)(.*?)(<!-- /rates -->)", re.S)
QUOTE = re.compile(r"<!-- bench (\w+)(?: ([^ ]+))? -->")
NUMBER = re.compile(r"-?\d[\d,]*(?:\.\d+)?")


def cli_reference() -> str:
    """Markdown of `mtcal --help` and every subcommand's help, as argparse prints them (120 columns)."""
    os.environ["COLUMNS"] = "120"
    from mtcal.cli import build_parser

    ap = build_parser()
    sub = next(a for a in ap._actions if a.__class__.__name__ == "_SubParsersAction")
    parts = ["```text", ap.format_help().rstrip(), "```"]
    for name, p in sub.choices.items():
        parts += ["", f"## mtcal {name}", "", "```text", p.format_help().rstrip(), "```"]
        nested = next((a for a in p._actions if a.__class__.__name__ == "_SubParsersAction"), None)
        for action, q in (nested.choices.items() if nested else ()):  # e.g. mtcal history add|show|compare|trend
            parts += ["", f"### mtcal {name} {action}", "", "```text", q.format_help().rstrip(), "```"]
    return "\n".join(parts)


def results() -> dict:
    return json.loads(RESULTS.read_text())


def expected(key: str, spec: str | None, figures: dict) -> str:
    """The text of figure ``key`` in ``spec`` (a ``%`` spec without its sign); KeyError names a missing key."""
    if key not in figures:
        raise KeyError(f"benchmarks/results.json has no figure {key!r}: run python benchmarks/run.py --save")
    value = figures[key]
    return (format(value, spec) if spec else str(value)).rstrip("%")


def quoted(before: str) -> re.Match | None:
    """The number a marker quotes: the last one in the text before it on its line (None when there is none)."""
    found = list(NUMBER.finditer(before.split("\n")[-1]))
    return found[-1] if found else None


def _rates_row(path: Path) -> str:
    """One table row of a kept rates run: its code, seed, mix and campaigns, then per way (defaults / tracker)."""
    d = json.loads(path.read_text())
    code = path.stem.removeprefix("rates_").split("_seed")[0]
    ways = [d["summary"][m] for m in ("defaults", "tracker") if m in d["summary"]]
    cells = [
        [f"{w['totals']['wrong']} of {w['planted_runs']} (≤ {100 * w['wrong_upper95']:.0f} %)" for w in ways],
        [f"{w['false_alarms']} of {w['clean_runs']}" for w in ways],
        [f"{w['gen3_in_reach_right']} of {w['gen3_in_reach_runs']}" for w in ways],
        [f"{w['sizes_beyond_1_5x']} of {w['sizes_checked']}" for w in ways]]
    ratio = max(w["largest_size_ratio"] or 0.0 for w in ways)
    return " | ".join(["", code, f"{d['seed']}, {d['mix']}, {d['n']}", *(" / ".join(c) for c in cells),
                       f"{ratio:.1f}", ""]).strip()


def rates_table(folder: Path = RATES) -> str:
    """The markdown table of every kept gen3 rates run (benchmarks/gen3/rates_*.json), in file-name order: what a
    page's ``<!-- rates -->`` block must read (``python docs/hooks.py PAGE`` rewrites it)."""
    head = ("| code | seed, mix, campaigns | wrong, defaults / tracker (95 % bound) | clean false alarms "
            "| gen3 physics within reach located right | located sizes beyond 1.5x the planted displacement "
            "| largest size ratio |\n|---|---|---|---|---|---|---|\n")
    return head + "".join(_rates_row(p) + "\n" for p in sorted(folder.glob("rates_*.json")))


def check(markdown: str, figures: dict | None = None, rates: Path = RATES) -> list[str]:
    """Every quoted figure of a page that differs from benchmarks/results.json: ``line: quoted ... , file ...``."""
    figures = results() if figures is None else figures
    problems = []
    block = RATES_BLOCK.search(markdown)
    if block and block.group(2) != rates_table(rates):
        problems.append(f"line {markdown.count(chr(10), 0, block.start()) + 1}: the rates table differs from "
                        f"benchmarks/gen3/rates_*.json: run python docs/hooks.py on the page")
    for m in QUOTE.finditer(markdown):
        line = markdown.count("\n", 0, m.start()) + 1
        want = expected(m.group(1), m.group(2), figures)
        before = markdown[:m.start()]
        if not isinstance(figures[m.group(1)], (int, float)):
            if not before.rstrip("* ").endswith(want):
                problems.append(f"line {line}: {m.group(1)} should read {want!r}")
            continue
        got = quoted(before)
        if got is None or got.group(0) != want:
            problems.append(f"line {line}: {m.group(1)} quoted as {got and got.group(0)!r}, results.json gives {want}")
    return problems


def update(markdown: str, figures: dict | None = None) -> str:
    """The page with every quoted number rewritten from benchmarks/results.json (text figures are not)."""
    figures = results() if figures is None else figures
    out, last = [], 0
    for m in QUOTE.finditer(markdown):
        got = quoted(markdown[:m.start()])
        if got is None or not isinstance(figures.get(m.group(1)), (int, float)):
            continue
        start = m.start() - len(markdown[:m.start()].split("\n")[-1]) + got.start()
        end = start + len(got.group(0))
        out += [markdown[last:start], expected(m.group(1), m.group(2), figures)]
        last = end
    markdown = "".join(out) + markdown[last:]
    return RATES_BLOCK.sub(lambda m: m.group(1) + rates_table() + m.group(3), markdown)


def on_page_markdown(markdown: str, page, config, files) -> str:
    problems = check(markdown)
    if problems:
        raise ValueError(f"{page.file.src_path}: figures that differ from benchmarks/results.json:\n" +
                         "\n".join(problems))
    if MARK in markdown:
        markdown = markdown.replace(MARK, cli_reference())
    return markdown


if __name__ == "__main__":
    for arg in sys.argv[1:]:
        p = Path(arg)
        text = p.read_text()
        new = update(text)
        if new != text:
            p.write_text(new)
            print(f"{arg}: figures rewritten from {RESULTS.name} and {RATES.name}'s rates")
