"""Docs sized for people (issue 55): a README of at most 200 lines, no table cell of it over 600 characters and no
sentence over 60 words; every guide (docs/guide/*.md) at most 300 lines."""
from __future__ import annotations

import re

import pytest
from docs_snippets import ROOT

README = ROOT / "README.md"
GUIDES = sorted((ROOT / "docs" / "guide").glob("*.md"))


def _text(markdown: str) -> str:
    """Prose of a page: fenced blocks, HTML comments and link targets left out."""
    markdown = re.sub(r"```.*?```", "\n", markdown, flags=re.S)
    markdown = re.sub(r"<!--.*?-->", "", markdown, flags=re.S)
    return re.sub(r"\]\([^)]*\)", "]", markdown)


def sentences(markdown: str) -> list[str]:
    """Sentences of the prose: a paragraph, list item or table cell is split after `.`, `!`, `?` or `:` followed
    by a blank and a capital, a backtick or a bracket (so `e.g. X` and `3.18` stay whole)."""
    parts = []
    for block in re.split(r"\n\s*\n|\n(?=\s*[*|] )|\|", _text(markdown)):
        parts += re.split(r"(?<=[.!?])\s+(?=[A-Z`(\[*])", " ".join(block.split()))
    return [p for p in parts if p.strip()]


def table_cells(markdown: str) -> list[str]:
    return [c.strip() for line in markdown.split("\n") if line.startswith("|") for c in line.strip("|").split("|")]


def test_the_readme_is_at_most_200_lines():
    assert len(README.read_text().split("\n")) <= 200


def test_no_readme_table_cell_is_over_600_characters():
    long = [c[:80] for c in table_cells(README.read_text()) if len(c) > 600]
    assert not long, long


def test_no_readme_sentence_is_over_60_words():
    long = [s[:100] for s in sentences(README.read_text()) if len(s.split()) > 60]
    assert not long, long


@pytest.mark.parametrize("guide", GUIDES, ids=[g.name for g in GUIDES])
def test_a_guide_is_at_most_300_lines(guide):
    assert len(guide.read_text().split("\n")) <= 300


def test_the_measures_fail_on_what_they_guard():
    assert len(sentences("One two. Three four: e.g. five 3.18 six.\n\n* Seven `x`. Eight")) == 4
    assert [len(s.split()) for s in sentences("| a b | c d e |")] == [2, 3]
    assert max(len(s.split()) for s in sentences(" ".join(["word"] * 61) + ". Short.")) == 61
    assert table_cells("| " + "x" * 601 + " | y |") == ["x" * 601, "y"]
