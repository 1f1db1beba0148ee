"""MkDocs hooks: the CLI reference (docs/cli.md) generated from the parsers at build time, and benchmark figures
(``[[bench KEY FORMAT]]``) read from benchmarks/results.json, so neither can drift from what the code does."""
from __future__ import annotations

import json
import os
import re
from pathlib import Path

MARK = "<!-- cli-reference -->"


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


BENCH = re.compile(r"\[\[bench (\w+)(?: ([^\]]+))?\]\]")
RESULTS = Path(__file__).resolve().parents[1] / "benchmarks" / "results.json"


def bench_figures(markdown: str) -> str:
    """``[[bench KEY FORMAT]]`` -> the figure KEY of benchmarks/results.json in FORMAT (a missing key fails)."""
    results = json.loads(RESULTS.read_text())

    def one(m: re.Match) -> str:
        if m.group(1) not in results:
            raise KeyError(f"benchmarks/results.json has no figure {m.group(1)!r}: run python benchmarks/run.py --save")
        value = results[m.group(1)]
        return format(value, m.group(2)) if m.group(2) else str(value)

    return BENCH.sub(one, markdown)


def on_page_markdown(markdown: str, page, config, files) -> str:
    if MARK in markdown:
        markdown = markdown.replace(MARK, cli_reference())
    return bench_figures(markdown)
