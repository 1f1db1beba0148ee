"""The house rules of mtcal/ (issue 23), read from the source with `ast`: no import cycle between modules (imports
inside functions and under TYPE_CHECKING count: a cycle hidden in a function is still a cycle) and no upward
import between packages: results flow down the pipeline, so a package imports only the packages below it in
LAYERS (docs/design.md, "Layout")."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1] / "mtcal"

# Bottom to top.  A package may import its own modules and any package listed before it.
LAYERS = ["errors", "_tails", "io", "_gensupport", "_verb", "generated", "kinematics", "nc", "model", "measurement",
          "thermal", "campaign", "identify", "planning", "compensate", "export", "plate", "iso230_2", "diagnose",
          "check", "uncertainty", "history", "report", "data", "demo", "api", "cli"]


def _module(path: Path) -> str:
    parts = path.relative_to(ROOT.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path) -> set[str]:
    """Every mtcal module this file imports (``from mtcal.x import y`` counts y when y is a module)."""
    mod = _module(path)
    pkg = mod if path.name == "__init__.py" else mod.rpartition(".")[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names if a.name.startswith("mtcal")}
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = pkg.split(".")[: len(pkg.split(".")) - (node.level - 1)]
                base = ".".join(up + ([node.module] if node.module else []))
            if not base.startswith("mtcal"):
                continue
            for a in node.names:
                sub = f"{base}.{a.name}"
                out.add(sub if _exists(sub) else base)
    return {m for m in out if m != mod}


def _exists(mod: str) -> bool:
    p = ROOT.parent / Path(*mod.split("."))
    return p.with_suffix(".py").exists() or (p / "__init__.py").exists()


def _graph() -> dict[str, set[str]]:
    return {_module(p): _imports(p) for p in ROOT.rglob("*.py")}


def _package(mod: str) -> str:
    parts = mod.split(".")
    return parts[1] if len(parts) > 1 else "api"


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of two or more modules (Tarjan)."""
    index, low, stack, on, out, n = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = n[0]
        n[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_every_package_has_a_layer():
    packages = {_package(m) for m in _graph()}
    assert packages <= set(LAYERS), f"packages without a layer in LAYERS: {sorted(packages - set(LAYERS))}"


def test_no_import_cycle():
    cycles = _cycles(_graph())
    assert not cycles, "import cycles: " + "; ".join(" <-> ".join(c) for c in cycles)


def test_no_upward_import():
    bad = sorted(f"{a} imports {b}" for a, deps in _graph().items() for b in deps
                 if LAYERS.index(_package(b)) > LAYERS.index(_package(a)))
    assert not bad, "upward imports (a package may import only those below it in LAYERS):\n" + "\n".join(bad)


def test_the_checks_find_what_they_guard(tmp_path):
    """The cycle finder sees a two-module cycle and a three-module one, and nothing in a chain."""
    assert _cycles({"a": {"b"}, "b": {"a"}, "c": {"a"}}) == [["a", "b"]]
    assert _cycles({"p": {"n"}, "n": {"d"}, "d": {"p"}}) == [["d", "n", "p"]]
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": set()}) == []


def test_the_api_names_agree():
    """mtcal/__init__ names its verbs three times (the lazy map, __all__ for linters, the TYPE_CHECKING imports for
    IDEs): the three lists hold the same names, and each resolves to the object its module defines."""
    import importlib

    import mtcal
    tree = ast.parse((ROOT / "__init__.py").read_text())
    checking = {a.asname or a.name for node in ast.walk(tree) if isinstance(node, ast.If)
                for sub in node.body if isinstance(sub, ast.ImportFrom) for a in sub.names}
    assert set(mtcal._API) == set(mtcal.__all__) - {"__version__"} == checking
    for name, (module, attr) in mtcal._API.items():
        importlib.import_module(module)  # the verb's own package imported first (binds e.g. mtcal.identify)
        got, want = getattr(mtcal, name), getattr(importlib.import_module(module), attr)
        assert got is want or (callable(got) and type(got).__call__.__doc__ == want.__doc__), name


@pytest.mark.slow
def test_a_verb_is_callable_after_its_package_is_imported():
    """mtcal.identify / mtcal.diagnose share their names with packages: once ``mtcal.identify.run`` is imported
    the attribute is the package, which must still be the verb (it was a module and not callable)."""
    import subprocess
    import sys
    code = ("import mtcal, mtcal.identify.run, mtcal.diagnose.run\n"
            "rec, _ = mtcal.simulate(seed=1, rounds=2)\n"
            "res = mtcal.identify(rec.select(rec.axis == 'X'), worth=False)\n"
            "print(type(res).__name__, callable(mtcal.diagnose))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["IdentifyResult", "True"]
