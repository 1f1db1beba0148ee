"""The README's links into docs/ land (issue 55: its validation table links each row to its section): every
``docs/...md`` it links exists, and every ``#anchor`` is a heading of that page (GitHub's and MkDocs' slug:
lower case, punctuation dropped, blanks to ``-``).  mkdocs build --strict checks the links between the pages."""
from __future__ import annotations

import re

from docs_snippets import ROOT


def slug(heading: str) -> str:
    return re.sub(r"\s", "-", re.sub(r"[^\w\s-]", "", heading.strip().lower()))


def anchors(page) -> set[str]:
    text = re.sub(r"```.*?```", "", page.read_text(), flags=re.S)
    return {slug(m.group(1)) for m in re.finditer(r"^#+ (.+)$", text, flags=re.M)}


def broken_links(markdown: str) -> list[str]:
    bad = []
    for target in re.findall(r"\]\((docs/[^)#\s]+)(#[^)\s]+)?\)", markdown):
        path, anchor = ROOT / target[0], target[1][1:]
        if not path.exists():
            bad.append(f"{target[0]}: no such page")
        elif anchor and anchor not in anchors(path):
            bad.append(f"{target[0]}#{anchor}: no such heading")
    return bad


def test_every_readme_link_into_the_docs_lands():
    assert broken_links((ROOT / "README.md").read_text()) == []


def test_the_link_check_fails_on_what_it_guards():
    assert slug("ISO 230-2") == "iso-230-2" and slug("When `identify` warns") == "when-identify-warns"
    assert broken_links("[a](docs/reference/validation.md#no-such) [b](docs/nowhere.md)") == [
        "docs/reference/validation.md#no-such: no such heading", "docs/nowhere.md: no such page"]
