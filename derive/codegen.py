"""Code generation: one SymPy expression set -> a NumPy module, a CasADi module (and C99 functions).

A derivation hands over a :class:`Module` (functions with named arguments and matrix-valued
outputs, plus plain metadata).  Each target has one printer and one template:

* NumPy: vectorised over any leading array shape (arguments broadcast against each other),
  common subexpressions eliminated once per function, outputs written into one array.
* CasADi: the same cse'd assignments written as ``casadi.SX`` code, wrapped in a ``casadi.Function``.
* C99: the same cse'd assignments as ``const double`` locals of a ``static void`` function writing its outputs
  row-major into ``out`` (no allocation, no includes: sin, cos, sqrt, atan2, fabs from the including file).

Everything printed is a pure function of the expressions, so the bytes are identical from run to run.
"""
from __future__ import annotations

import keyword
import pprint
from dataclasses import dataclass, field
from typing import Any, Sequence

import sympy as sp
from sympy.printing.c import C99CodePrinter
from sympy.printing.numpy import NumPyPrinter

HEADER = '''\
# -----------------------------------------------------------------------------
# GENERATED FILE - DO NOT EDIT.
# Generator: python -m derive ({target}); source: derive/{source}
# Target: {backend}.  Regenerate with `python -m derive`; CI runs `python -m derive --check`.
# Inputs (machine spec, SymPy/CasADi versions, hash of derive/) are in manifest.json.
# -----------------------------------------------------------------------------
'''


@dataclass(frozen=True)
class Arg:
    """A function argument: a scalar (shape ()) or a vector of symbols (shape (n,))."""

    name: str
    symbols: tuple[sp.Symbol, ...]
    doc: str
    vector: bool = True

    def __post_init__(self) -> None:
        if not self.vector and len(self.symbols) != 1:
            raise ValueError(f"scalar argument {self.name} needs exactly one symbol")


@dataclass(frozen=True)
class Function:
    """One generated function: ``name(*args) -> outputs`` with outputs a SymPy Matrix."""

    name: str
    args: tuple[Arg, ...]
    outputs: sp.Matrix
    doc: str
    vector_output: bool = False  # (m, 1) Matrix returned as shape (..., m) instead of (..., m, 1)

    def __post_init__(self) -> None:
        known = {s for a in self.args for s in a.symbols}
        free = set().union(*(e.free_symbols for e in self.outputs)) if self.outputs else set()
        missing = free - known
        if missing:  # invariant asserted while generating (ACTS style)
            raise ValueError(f"{self.name}: output depends on undeclared symbols {sorted(map(str, missing))}")


@dataclass
class Module:
    """What one derivation target produces."""

    name: str  # module stem, e.g. "dmu50" -> dmu50_numpy.py, dmu50_casadi.py
    source: str  # derive/ file that built it, for the header
    doc: str
    functions: list[Function]
    metadata: dict[str, Any] = field(default_factory=dict)


# ----------------------------------------------------------------------------- printers
class _NumPy(NumPyPrinter):
    def __init__(self) -> None:
        super().__init__({"fully_qualified_modules": True, "inline": True})


_CASADI_NAMES = {"arctan2": "atan2", "arccos": "acos", "arcsin": "asin", "arctan": "atan",
                 "absolute": "fabs", "pi": "pi", "sin": "sin", "cos": "cos", "tan": "tan",
                 "sqrt": "sqrt", "exp": "exp", "log": "log", "sign": "sign", "hypot": "hypot"}


class _CasADi(NumPyPrinter):
    """Prints the NumPy spelling, then maps each ``numpy.f`` to the ``casadi.f`` of the same maths."""

    def __init__(self) -> None:
        super().__init__({"fully_qualified_modules": True, "inline": True})

    def _module_format(self, fqn: str, register: bool = True) -> str:  # noqa: D401
        if fqn.startswith("numpy."):
            name = fqn[len("numpy."):]
            if name not in _CASADI_NAMES:
                raise NotImplementedError(f"no CasADi equivalent registered for numpy.{name}")
            return "ca." + _CASADI_NAMES[name]
        return super()._module_format(fqn, register)


def _ident(sym: sp.Symbol) -> str:
    """A Python identifier for a symbol (E_XX stays E_XX; keywords get a trailing _)."""
    name = str(sym)
    if not name.isidentifier() or keyword.iskeyword(name):
        name = name + "_"
    return name


def _cse(f: Function) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.Expr]]:
    flat = list(f.outputs)
    taken = {str(s) for a in f.args for s in a.symbols}
    names = (sp.Symbol(f"_x{i}") for i in range(10**9))
    names = (s for s in names if str(s) not in taken)
    reps, reduced = sp.cse(flat, symbols=names, optimizations=None, order="canonical")
    return reps, reduced


def _doc_block(f: Function, indent: str) -> str:
    lines = [f.doc.strip(), ""]
    for a in f.args:
        shape = f"(..., {len(a.symbols)})" if a.vector else "(...)"
        lines.append(f"{a.name} {shape}: {a.doc}")
        if a.vector:
            lines.append("    [" + ", ".join(map(str, a.symbols)) + "]")
    rows, cols = f.outputs.shape
    oshape = f"(..., {rows})" if f.vector_output else f"(..., {rows}, {cols})"
    lines.append(f"returns {oshape}")
    body = "\n".join((indent + ln).rstrip() for ln in lines)
    return f'{indent}"""{body.lstrip()}\n{indent}"""\n'


def emit_numpy(mod: Module, target: str) -> str:
    p = _NumPy()
    out = [HEADER.format(target=target, source=mod.source, backend="NumPy (vectorised, broadcasting)"),
           f'"""{mod.doc.strip()}\n\nNumPy implementation."""\n', "import numpy\n\n",
           "from mtcal._gensupport import as_arg, out_array\n\n"]
    for k, v in mod.metadata.items():
        out.append(f"{k} = {pprint.pformat(v, width=110, compact=True, sort_dicts=True)}\n")
    out.append(f"FUNCTIONS = {tuple(f.name for f in mod.functions)!r}\n")
    for f in mod.functions:
        reps, reduced = _cse(f)
        out.append(f"\n\ndef {f.name}({', '.join(a.name for a in f.args)}):\n")
        out.append(_doc_block(f, "    "))
        for a in f.args:
            n = len(a.symbols) if a.vector else 0
            out.append(f"    {a.name} = as_arg({a.name}, {n}, {a.name!r}, {f.name!r})\n")
        shapes = ", ".join(f"{a.name}.shape[:-1]" if a.vector else f"{a.name}.shape" for a in f.args)
        used = set().union(*(e.free_symbols for e in list(reduced) + [r for _, r in reps])) if reduced else set()
        for a in f.args:
            for i, s in enumerate(a.symbols):
                if s in used:
                    out.append(f"    {_ident(s)} = {a.name}[..., {i}]\n" if a.vector else f"    {_ident(s)} = {a.name}\n")
        for s, e in reps:
            out.append(f"    {s} = {p.doprint(e)}\n")
        rows, cols = f.outputs.shape
        oshape = (rows,) if f.vector_output else (rows, cols)
        out.append(f"    _out = out_array(({shapes},), {oshape!r})\n")
        for idx, e in enumerate(reduced):
            r, c = divmod(idx, cols)
            key = f"{r}" if f.vector_output else f"{r}, {c}"
            out.append(f"    _out[..., {key}] = {p.doprint(e)}\n")
        out.append("    return _out\n")
    return "".join(out)


def emit_casadi(mod: Module, target: str) -> str:
    p = _CasADi()
    out = [HEADER.format(target=target, source=mod.source, backend="CasADi SX"),
           f'"""{mod.doc.strip()}\n\nCasADi implementation: each function returns a cached casadi.Function."""\n',
           "import functools\n\nimport casadi as ca\n\n"]
    out.append(f"FUNCTIONS = {tuple(f.name for f in mod.functions)!r}\n")
    for f in mod.functions:
        reps, reduced = _cse(f)
        out.append(f"\n\n@functools.cache\ndef {f.name}():\n")
        out.append(_doc_block(f, "    "))
        for a in f.args:
            n = len(a.symbols)
            out.append(f"    {a.name} = ca.SX.sym({a.name!r}, {n})\n")
            for i, s in enumerate(a.symbols):
                out.append(f"    {_ident(s)} = {a.name}[{i}]\n")
        for s, e in reps:
            out.append(f"    {s} = {p.doprint(e)}\n")
        rows, cols = f.outputs.shape
        out.append(f"    _out = ca.SX.zeros({rows}, {cols})\n")
        for idx, e in enumerate(reduced):
            r, c = divmod(idx, cols)
            out.append(f"    _out[{r}, {c}] = {p.doprint(e)}\n")
        names = ", ".join(repr(a.name) for a in f.args)
        out.append(f"    return ca.Function({(mod.name + '_' + f.name)!r}, [{', '.join(a.name for a in f.args)}], "
                   f"[_out], [{names}], ['out'])\n")
    return "".join(out)


class _C(C99CodePrinter):
    """SymPy's C99 printer with pi as a literal (no M_PI macro: the including file decides the headers)."""

    def __init__(self) -> None:
        super().__init__({"math_macros": {sp.Symbol("_no_macro_"): "_no_macro_"}})

    def _print_Pi(self, expr) -> str:  # noqa: D401
        return "MTK_PI"


def emit_c_functions(functions: Sequence[Function], prefix: str) -> str:
    """``static void <prefix><name>(const double *vector_arg, double scalar_arg, ..., double *out)`` for each
    function: its cse'd assignments as locals, the outputs row-major into out (rows x cols)."""
    p = _C()
    out = []
    for f in functions:
        reps, reduced = _cse(f)
        rows, cols = f.outputs.shape
        params = ", ".join(f"const double *{a.name}" if a.vector else f"double {a.name}" for a in f.args)
        out.append(f"\n/* {f.doc.strip()}\n * out: {rows} x {cols}, row-major */\n")
        out.append(f"static void {prefix}{f.name}({params}, double *out)\n{{\n")
        used = set().union(*(e.free_symbols for e in list(reduced) + [r for _, r in reps])) if reduced else set()
        for a in f.args:
            if not any(s in used for s in a.symbols):
                out.append(f"    (void){a.name};\n")
            for i, s in enumerate(a.symbols):
                if s in used and a.vector:
                    out.append(f"    const double {_ident(s)} = {a.name}[{i}];\n")
                elif s in used and _ident(s) != a.name:
                    out.append(f"    const double {_ident(s)} = {a.name};\n")
        for s, e in reps:
            out.append(f"    const double {s} = {p.doprint(e)};\n")
        for idx, e in enumerate(reduced):
            out.append(f"    out[{idx}] = {p.doprint(e)};\n")
        out.append("}\n")
    return "".join(out)


def symbols(names: Sequence[str]) -> tuple[sp.Symbol, ...]:
    """Real symbols with the given names (ISO names become Python identifiers unchanged)."""
    return tuple(sp.Symbol(n, real=True) for n in names)
