"""Count the effect-specific branches of the diagnosis' selection (issue 52: "the count of effect-specific branches
in the selection before and after").  Run: python benchmarks/diagnose_branches.py [FILE ...] (default
mtcal/diagnose/selection.py); ``--json`` prints the counts as JSON.

Definition (reproducible, read from the source's syntax tree, nothing executed):

* an *effect word* is a string that names a candidate effect, a family or a member of one: every name of the
  diagnosis' vocabulary (mtcal.diagnose.effects.VOCABULARY, the free forms' name ``unexplained``, ``step``) and
  every ``variant`` / ``kind`` / ``target`` value the candidates carry ("tracker knock", "re-seated nest",
  "growing", "reversal", "place", "tracker", ...), read from the string constants of mtcal/diagnose/*.py that stand
  as a ``Candidate(...)``'s first argument or as the value of a ``"variant"``/``"kind"``/``"target"`` key;
* a *name table* is a module-level constant of the diagnosis (any mtcal/diagnose/*.py) whose value is a
  collection (tuple, list, set, frozenset, dict keys) holding an effect word -- ROUND_SPECIFIC, ALTERNATE_FOLDS,
  REVERSALS, NESTED, ORDERED, SEPARATE_BY, ...;
* a *branch* is one comparison (``==``, ``!=``, ``in``, ``not in``; one per operator of a chained comparison) or one
  look-up (``TABLE.get(...)``, ``TABLE[...]``) of which one side is an effect word, a tuple/set of them, or a name
  table.  Each counts once where it is written, whatever it is inside (if, filter, comprehension, return);
* ``functions``: the functions holding at least one branch (their names listed).

The count measures dispatch on names, not the statistics: a general test over the grammar's attributes (a place's
columns, their inclusion) has none.
"""
from __future__ import annotations

import ast
import json
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
DIAGNOSE = ROOT / "mtcal" / "diagnose"
KEYS = ("variant", "kind", "target")


def _strings(node: ast.AST) -> list[str]:
    """The string constants directly in a literal collection (or the constant itself)."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return [s for e in node.elts for s in _strings(e)]
    if isinstance(node, ast.Dict):
        return [s for k in node.keys if k is not None for s in _strings(k)]
    if isinstance(node, ast.Call) and getattr(node.func, "id", None) in ("frozenset", "set", "tuple") and node.args:
        return _strings(node.args[0])
    if isinstance(node, ast.SetComp | ast.ListComp | ast.GeneratorExp):
        return [s for g in node.generators for s in _strings(g.iter)]
    return []


def effect_words() -> set[str]:
    """Every effect word of the diagnosis (module docstring)."""
    sys.path.insert(0, str(ROOT))
    from mtcal.diagnose import effects as fx
    words = {*fx.VOCABULARY, fx.UNEXPLAINED, "step"}
    for path in DIAGNOSE.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Call) and getattr(node.func, "attr", getattr(node.func, "id", "")) == "Candidate":
                if node.args and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str):
                    words.add(node.args[0].value)
            if isinstance(node, ast.Dict):
                for k, v in zip(node.keys, node.values):
                    if isinstance(k, ast.Constant) and k.value in KEYS:
                        words.update(_strings(v))
            if isinstance(node, ast.Call):
                for kw in node.keywords:
                    if kw.arg in KEYS:
                        words.update(_strings(kw.value))
    return words


def name_tables(words: set[str]) -> set[str]:
    """The module-level constants of mtcal/diagnose/*.py holding an effect word (module docstring)."""
    out = set()
    for path in DIAGNOSE.glob("*.py"):
        for node in ast.parse(path.read_text()).body:
            targets = node.targets if isinstance(node, ast.Assign) else [node.target] if isinstance(
                node, ast.AnnAssign) and node.value is not None else []
            value = node.value if targets else None
            if value is None:
                continue
            expr = value
            if isinstance(expr, ast.BinOp):  # ROUND_SPECIFIC + (...) + fx.ALTERNATE_FOLDS
                expr = ast.Tuple(elts=[expr.left, expr.right])
            if set(_strings(expr)) & words or (isinstance(value, ast.BinOp)):
                for t in targets:
                    if isinstance(t, ast.Name) and t.id.isupper() and (set(_strings(expr)) & words
                                                                       or _mentions_table(value, out)):
                        out.add(t.id)
    return out


def _mentions_table(node: ast.AST, tables: set[str]) -> bool:
    return any(isinstance(n, ast.Name) and n.id in tables or isinstance(n, ast.Attribute) and n.attr in tables
               for n in ast.walk(node))


def _is_effect(node: ast.AST, words: set[str], tables: set[str]) -> bool:
    """Whether ``node`` is an effect word, a literal collection of them, or a name table."""
    if isinstance(node, ast.Name) and node.id in tables or isinstance(node, ast.Attribute) and node.attr in tables:
        return True
    if isinstance(node, ast.Attribute) and node.attr == "UNEXPLAINED":
        return True
    found = _strings(node)
    return bool(found) and bool(set(found) & words)


def branches(path: pathlib.Path, words: set[str], tables: set[str]) -> list[tuple[int, str, str]]:
    """(line, function, source) of every branch of ``path`` (module docstring)."""
    src = path.read_text()
    tree = ast.parse(src)
    out = []

    def visit(node: ast.AST, fn: str) -> None:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            fn = node.name
        if isinstance(node, ast.Compare):
            sides = [node.left, *node.comparators]
            for op, a, b in zip(node.ops, sides, sides[1:]):
                if isinstance(op, ast.Eq | ast.NotEq | ast.In | ast.NotIn) and (
                        _is_effect(a, words, tables) or _is_effect(b, words, tables)):
                    out.append((node.lineno, fn, ast.get_source_segment(src, node) or ""))
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "get" \
                and _is_effect(node.func.value, words, tables):
            out.append((node.lineno, fn, ast.get_source_segment(src, node) or ""))
        elif isinstance(node, ast.Subscript) and isinstance(node.ctx, ast.Load) and _is_effect(node.value, words,
                                                                                            tables):
            out.append((node.lineno, fn, ast.get_source_segment(src, node) or ""))
        for child in ast.iter_child_nodes(node):
            visit(child, fn)

    visit(tree, "<module>")
    return out


def count(paths: list[pathlib.Path]) -> dict:
    """Branch counts per file (module docstring): total, functions holding one, the name tables defined."""
    words = effect_words()
    tables = name_tables(words)
    out = {}
    for p in paths:
        b = branches(p, words, tables)
        defined = sorted(t for t in tables if any(
            isinstance(n, ast.Assign) and any(getattr(x, "id", None) == t for x in n.targets)
            for n in ast.parse(p.read_text()).body))
        out[str(p.relative_to(ROOT))] = {"branches": len(b), "functions": sorted({f for _, f, _ in b}),
                                         "name_tables": defined, "lines": [f"{ln}: {s}" for ln, _, s in b]}
    return out


def main(argv: list[str]) -> None:
    as_json = "--json" in argv
    paths = [pathlib.Path(a).resolve() for a in argv if a != "--json"] or [DIAGNOSE / "selection.py"]
    res = count(paths)
    if as_json:
        print(json.dumps({k: {x: v[x] for x in ("branches", "functions", "name_tables")} for k, v in res.items()},
                         indent=1))
        return
    for k, v in res.items():
        print(f"{k}: {v['branches']} effect-specific branches in {len(v['functions'])} functions; "
              f"name tables defined: {', '.join(v['name_tables']) or 'none'}")
        for line in v["lines"]:
            print("   ", line.replace("\n", " ")[:150])


if __name__ == "__main__":
    main(sys.argv[1:])
