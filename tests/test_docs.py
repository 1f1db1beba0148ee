"""Every example in README.md and docs/ runs as written and prints what the page shows (tests/docs_snippets.py);
the ten-line Python example of docs/api.md is one of them."""
from __future__ import annotations

import pytest
from docs_snippets import ROOT, blocks, matches, pages, run_block

PAGES = pages()


@pytest.mark.parametrize("page", PAGES, ids=[str(p.relative_to(ROOT)) for p in PAGES])
@pytest.mark.slow
def test_page_examples_run_as_written(page, tmp_path):
    problems = []
    for b in blocks(page):
        if b.lang in ("bash", "console", "python") and not b.skip:
            problems += run_block(b, tmp_path)
    assert not problems, "\n\n".join(problems)


def test_api_example_is_on_its_page():
    """docs/api.md opens with the recording -> model -> compensated program -> controller table example."""
    py = [b for b in blocks(ROOT / "docs" / "api.md") if b.lang == "python"]
    assert py and len(py[0].text.strip().splitlines()) <= 12
    for verb in ("read_recording", "identify", "compensate_program", "export_model"):
        assert verb in py[0].text


def test_the_checker_fails_on_what_it_guards():
    """The output comparison refuses a typed figure that the command does not print, allows `...`."""
    assert matches("tool tip: 0.842 um\n", "tool tip: 0.842 um\n")
    assert not matches("tool tip: 43.325 um\n", "tool tip: 0.842 um\n")
    assert matches("wrote ... readings\n...\ndone\n", "wrote 12 readings\nx\ny\ndone\n")
