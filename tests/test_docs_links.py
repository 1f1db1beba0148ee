"""Links into pages land (issue 55: the README's validation table links each row to its section): every ``.md``
page that README.md or a page under docs/ links exists, and every ``#anchor`` is a heading of that page (GitHub's
and MkDocs' slug: lower case, punctuation dropped, blanks to ``-``).  mkdocs build --strict does not check an
anchor on another page."""
from __future__ import annotations

import re
from pathlib import Path

import pytest
from docs_snippets import ROOT, pages


def slug(heading: str) -> str:
    return re.sub(r"\s", "-", re.sub(r"[^\w\s-]", "", heading.strip().lower()))


def anchors(page: Path) -> set[str]:
    text = re.sub(r"```.*?```", "", page.read_text(), flags=re.S)
    return {slug(m.group(1)) for m in re.finditer(r"^#+ (.+)$", text, flags=re.M)}


def broken_links(markdown: str, here: Path) -> list[str]:
    """Links of a page in folder ``here`` to a page that is not there or to a heading it does not have."""
    bad = []
    for target, anchor in re.findall(r"\]\(([^)#\s:]*\.md)?(#[^)\s]+)?\)", markdown):
        path = (here / target).resolve() if target else None
        if path is None:
            continue  # an anchor on the page itself: mkdocs checks those
        if not path.exists():
            bad.append(f"{target}: no such page")
        elif anchor and anchor[1:] not in anchors(path):
            bad.append(f"{target}{anchor}: no such heading")
    return bad


PAGES = pages()


@pytest.mark.parametrize("page", PAGES, ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_every_link_to_a_page_lands(page):
    assert broken_links(page.read_text(), page.parent) == []


def test_the_link_check_fails_on_what_it_guards():
    assert slug("ISO 230-2") == "iso-230-2" and slug("When `identify` warns") == "when-identify-warns"
    assert broken_links("[a](docs/reference/validation.md#no-such) [b](docs/nowhere.md) [c](#here)", ROOT) == [
        "docs/reference/validation.md#no-such: no such heading", "docs/nowhere.md: no such page"]
    assert broken_links("[a](docs/reference/validation.md#diagnosis)", ROOT) == []
