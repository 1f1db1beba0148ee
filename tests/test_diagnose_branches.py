"""The count of effect-specific branches in the diagnosis' selection (issue 52; benchmarks/diagnose_branches.py
states the definition).  The count may only fall: SELECTION_BRANCHES is the count on this branch's head, and a new
rule keyed to an effect's name makes this test fail."""
from __future__ import annotations

import importlib.util
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[1]
# mtcal/diagnose/selection.py at 83feade: 43 in 17 functions (issue 52's "before"); with the grammar's attributes
# deciding nesting, ties, rivals, folds, separate_by, the adequacy checks and the free forms, and change points one
# search per place: 2 in 2 functions
SELECTION_BRANCHES = 2


def _counter():
    spec = importlib.util.spec_from_file_location("diagnose_branches", ROOT / "benchmarks" / "diagnose_branches.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_counter_finds_a_rule_keyed_to_a_name_and_not_a_test_over_columns(tmp_path):
    b = _counter()
    words = b.effect_words()
    assert {"backlash", "thermal_drift", "tracker knock", "re-seated nest", "growing", "unexplained"} <= words
    tables = b.name_tables(words)
    assert "REVERSALS" in tables  # the diagnosis' tables of names (the selection's own are gone: w52attr)
    tables |= {"NESTED", "ROUND_SPECIFIC"}
    src = tmp_path / "snippet.py"
    src.write_text("def keyed(c, o):\n"
                   "    if c.name == 'backlash' or c.extra.get('variant') == 'tracker knock':\n"
                   "        return NESTED.get(c.name)\n"
                   "    return c.name in ROUND_SPECIFIC\n"
                   "def general(eng, G, level):\n"
                   "    return eng.score(G).logp < level and G.shape[1] == 3\n")
    found = b.branches(src, words, tables)
    assert [(ln, fn) for ln, fn, _ in found] == [(2, "keyed"), (2, "keyed"), (3, "keyed"), (4, "keyed")]


def test_the_selection_has_no_more_effect_specific_branches_than_recorded():
    b = _counter()
    res = b.count([ROOT / "mtcal" / "diagnose" / "selection.py"])["mtcal/diagnose/selection.py"]
    assert res["branches"] <= SELECTION_BRANCHES, res["lines"]
