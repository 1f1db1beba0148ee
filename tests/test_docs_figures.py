"""Every benchmark figure the docs quote is benchmarks/results.json's (issue 55): a quoted figure is plain text with
a marker naming its key (docs/hooks.py, ``12.4<!-- bench KEY .1f --> µm``), checked here and by the docs build;
the validation and benchmark pages, and the README's table of what is validated, quote no measured figure
without one."""
from __future__ import annotations

import importlib.util
import re

import pytest
from docs_snippets import ROOT, pages

spec = importlib.util.spec_from_file_location("docs_hooks", ROOT / "docs" / "hooks.py")
hooks = importlib.util.module_from_spec(spec)
spec.loader.exec_module(hooks)

PAGES = pages()
# A figure is a number with a unit.  Not a measured figure: a limit (after >=, <=, <, >, / or "within"), a planted or
# nominal size ("a 2 µm backlash", "changed by 15 µrad"), a confidence level ("95 % intervals").
UNIT = r"(?:µm|um|µrad|urad|nm|nrad|%|×|ms|s|min|h|ppm|MB|mm)"
FIGURE = re.compile(r"(?<![\w.\-])(\d[\d,]*(?:\.\d+)?)\s?(" + UNIT + r")(?!\w)")
NOT_MEASURED = re.compile(r"(?:[≥≤<>/]|\bwithin|\ba|\bby|\bup to)\s*\**$")


def _prose(markdown: str) -> str:
    """The page without fenced blocks, code spans and link targets (line numbers kept)."""
    markdown = re.sub(r"```.*?```", lambda m: "\n" * m.group(0).count("\n"), markdown, flags=re.S)
    markdown = re.sub(r"`[^`\n]*`", "``", markdown)
    return re.sub(r"\]\([^)]*\)", "]()", markdown)


def unquoted_figures(markdown: str) -> list[str]:
    """Measured figures without a results.json marker: ``line N: TEXT``."""
    found = []
    for n, line in enumerate(_prose(markdown).split("\n"), 1):
        for m in FIGURE.finditer(line):
            after = line[m.end(1):m.end() + 12]
            if "<!-- bench" in after or NOT_MEASURED.search(line[:m.start()]):
                continue
            if m.group(2) == "%" and re.match(r"\s*(interval|band|bound|confidence)", line[m.end():]):
                continue
            found.append(f"line {n}: {m.group(0)}")
    return found


def _readme_validation() -> str:
    text = (ROOT / "README.md").read_text()
    start = text.index("## What is validated against what")
    return text[start:text.index("\n## ", start + 1)]


@pytest.mark.parametrize("page", PAGES, ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_every_quoted_figure_is_the_results_files(page):
    assert hooks.check(page.read_text()) == []


@pytest.mark.parametrize("name", ["docs/reference/validation.md", "docs/reference/benchmarks.md", "README table"])
def test_the_validation_pages_quote_every_measured_figure(name):
    text = _readme_validation() if name == "README table" else (ROOT / name).read_text()
    assert unquoted_figures(text) == []


def test_the_checker_fails_on_what_it_guards():
    figures = {"speed": 208.7, "share": 0.844, "machine": "x86_64 2 cores"}
    page = ("fast: **209<!-- bench speed .0f -->×**, agree 84 %<!-- bench share .0% --> on "
            "x86_64 2 cores<!-- bench machine -->")
    assert hooks.check(page, figures) == []
    stale = page.replace("209<", "208<").replace("84 %", "85 %").replace("x86_64 2", "arm64 2")
    assert len(hooks.check(stale, figures)) == 3
    assert hooks.update(stale, figures) == page.replace("x86_64 2", "arm64 2")  # numbers rewritten, text is not
    with pytest.raises(KeyError, match="no figure 'gone'"):
        hooks.check("0.5<!-- bench gone .1f -->", figures)
    assert unquoted_figures("took 2.80 s and 3.1 µm; limit < 5 s; a 2 µm backlash; 95 % intervals") == [
        "line 1: 2.80 s", "line 1: 3.1 µm"]
    assert unquoted_figures("took 2.80<!-- bench x .2f --> s, `9.9 um` in code") == []
