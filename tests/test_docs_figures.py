"""Every benchmark figure the docs quote is benchmarks/results.json's (issue 55): a quoted figure is plain text with
a marker naming its key (docs/hooks.py, ``12.4<!-- bench KEY .1f --> µm``), checked here and by the docs build;
the validation and benchmark pages, the README's table of what is validated and every guide quote no measured
figure without one.

A *measured figure* is a number with a unit of a result (µm, µrad, nm, nrad, %, ×, ms, s, min, h, ppm, MB; not mm,
which in these pages is a size a user sets: a travel, a radius, a tool length) in prose — not in a fenced block or
a code span, whose outputs tests/test_docs.py runs.  Not measured: a limit (after >=, <=, <, >, /, "within",
"than", "below", "above", "at least", "at most"), a planted or nominal size ("a 2 µm backlash", "changed by
15 µrad", "up to"), a confidence level ("95 % intervals", "its 95 % half-width"), and every figure on a line
before an ``<!-- input -->`` marker (a size a user types, a value planted in an example, a default, a standard's
or a datasheet's constant).  A figure read from the page's own example is marked ``<!-- output -->``: its number
must be printed in the last fenced block before it (the block tests/test_docs.py runs).  A guide's rates over many
campaigns are lab figures: the validation page quotes them (marked) or the lab notes hold them
(docs/reference/lab-notes.md, unchecked)."""
from __future__ import annotations

import importlib.util
import re

import pytest
from docs_snippets import ROOT, pages

spec = importlib.util.spec_from_file_location("docs_hooks", ROOT / "docs" / "hooks.py")
hooks = importlib.util.module_from_spec(spec)
spec.loader.exec_module(hooks)

PAGES = pages()
# A measured figure and what is not one: the module's docstring.
UNIT = r"(?:µm|um|µrad|urad|nm|nrad|%|×(?!\s*\d)|ppm|MB|(?<=\s)(?:ms|s|min|h))"  # "2s↑", "9 × 90" are not figures
FIGURE = re.compile(r"(?<![\w.\-])(\d[\d,]*(?:\.\d+)?)\s?(" + UNIT + r")(?!\w)")
INPUT, OUTPUT = "<!-- input -->", "<!-- output -->"
NOT_MEASURED = re.compile(r"(?:[≥≤<>/]|\bwithin|\bthan|\bbelow|\babove|\bat least|\bat most|\ba|\bby|\bup to)\s*\**$")


def _prose(markdown: str) -> str:
    """The page without fenced blocks, code spans and link targets (line numbers kept)."""
    markdown = re.sub(r"```.*?```", lambda m: "\n" * m.group(0).count("\n"), markdown, flags=re.S)
    markdown = re.sub(r"`[^`\n]*`", "``", markdown)
    return re.sub(r"\]\([^)]*\)", "]()", markdown)


def unquoted_figures(markdown: str) -> list[str]:
    """Measured figures without a results.json marker: ``line N: TEXT``."""
    found = []
    for n, line in enumerate(_prose(markdown).split("\n"), 1):
        line = line.split(INPUT)[-1]  # the figures before an input marker are inputs
        for m in FIGURE.finditer(line):
            after = line[m.end(1):m.end() + 12]
            if "<!-- bench" in after or NOT_MEASURED.search(line[:m.start()]):
                continue
            if m.group(2) == "%" and re.match(r"\s*(interval|band|bound|confidence|half-width)", line[m.end():]):
                continue
            found.append(f"line {n}: {m.group(0)}")
    return found


def unshown_outputs(markdown: str) -> list[str]:
    """Figures marked ``<!-- output -->`` that the page's last fenced block before them does not print."""
    found = []
    for m in re.finditer(re.escape(OUTPUT), markdown):
        block = re.findall(r"```[^\n]*\n(.*?)```", markdown[:m.start()], flags=re.S)
        got = hooks.quoted(markdown[:m.start()])
        if not block or got is None or not re.search(rf"(?<![\d.]){re.escape(got.group(0))}(?![\d])", block[-1]):
            found.append(f"line {markdown.count(chr(10), 0, m.start()) + 1}: {got and got.group(0)}")
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


GUIDES = sorted((ROOT / "docs" / "guide").glob("*.md"))
# Pages another helper rewrites in this session (their figures are theirs to mark): strict, so the mark goes with it.
NOT_YET: dict[str, str] = {}


@pytest.mark.parametrize("guide", [pytest.param(g, marks=pytest.mark.xfail(strict=True, reason=NOT_YET[g.name]))
                                   if g.name in NOT_YET else g for g in GUIDES], ids=[g.name for g in GUIDES])
def test_a_guide_quotes_no_measured_figure_without_a_marker(guide):
    assert unquoted_figures(guide.read_text()) == []
    assert unshown_outputs(guide.read_text()) == []


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
    assert unquoted_figures("planted 4 µm and 2 s<!-- input -->, found 4.3 µm; a 300 mm radius") == ["line 1: 4.3 µm"]
    assert unquoted_figures("R = 4s↑, 9 × 90 readings, took 2s") == []
    shown = "```text\nB 4.19 um\n```\nB is 4.19<!-- output --> µm, E 9.9<!-- output --> µm"
    assert unquoted_figures(shown) == [] and unshown_outputs(shown) == ["line 4: 9.9"]
    assert unquoted_figures("found 4.3 µm and 4.19<!-- output --> µm") == ["line 1: 4.3 µm"]


def test_the_rates_table_is_generated_from_the_kept_runs_and_a_stale_one_fails(tmp_path):
    """issue 52 item 5: the diagnosis' rates on the validation page are gen3's kept runs
    (benchmarks/gen3/rates_*.json), never typed: the page's block is what the files give, and a changed file makes
    the page stale (the docs build and this test fail)."""
    page = (ROOT / "docs" / "reference" / "validation.md").read_text()
    block = hooks.RATES_BLOCK.search(page)
    assert block, "validation.md has no <!-- rates --> block"
    runs = sorted(hooks.RATES.glob("rates_*.json"))
    rows = block.group(2).strip().split("\n")[2:]
    assert len(rows) == len(runs) >= 3
    assert hooks.check(page) == []
    import json
    first = json.loads(runs[0].read_text())
    first["summary"]["defaults"]["totals"]["wrong"] += 1
    (tmp_path / runs[0].name).write_text(json.dumps(first))
    for p in runs[1:]:
        (tmp_path / p.name).write_text(p.read_text())
    stale = hooks.check(page, rates=tmp_path)
    assert len(stale) == 1 and "rates table differs" in stale[0], stale
    wrong = first["summary"]["defaults"]["totals"]["wrong"]
    assert f"| {wrong} of {first['summary']['defaults']['planted_runs']} (" in hooks.rates_table(tmp_path)
