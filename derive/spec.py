"""Declarative machine chain specs (TOML in derive/machines/) and the ISO 230-1 error names they imply."""
from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

import sympy as sp

MACHINES_DIR = Path(__file__).with_name("machines")
ROTATIONS = ("A", "B", "C")  # about x, y, z
TRANSLATIONS = ("X", "Y", "Z")
TOOL_LENGTH = sp.Symbol("tool_length", real=True)


@dataclass(frozen=True)
class Axis:
    name: str
    kind: str  # "linear" (mm) or "rotary" (deg)
    limits: tuple[float, float] | None

    @property
    def unit(self) -> str:
        return "mm" if self.kind == "linear" else "deg"


@dataclass(frozen=True)
class Spec:
    name: str
    title: str
    path: Path
    parameters: dict[str, sp.Expr]
    axes: tuple[Axis, ...]
    table_chain: tuple[dict, ...]
    tool_chain: tuple[dict, ...]
    ik: dict

    def axis(self, name: str) -> Axis:
        return next(a for a in self.axes if a.name == name)

    def error_names(self) -> dict[str, tuple[str, ...]]:
        """ISO 230-1 error names by group, in the order of the generated error vector."""
        lin = [a.name for a in self.axes if a.kind == "linear"]
        rot = [a.name for a in self.axes if a.kind == "rotary"]
        squ = [s[0] for el in self.tool_chain + self.table_chain for s in el.get("squareness", [])]
        return {
            "linear": tuple(f"E_{c}{j}" for j in lin for c in TRANSLATIONS + ROTATIONS),
            "squareness": tuple(squ),
            "rotary": tuple(f"E_{c}{r}" for r in rot for c in TRANSLATIONS + ROTATIONS),
            "location": tuple(f"E_{c}0{r}" for r in rot for c in ("X", "Y", "A", "B")),
        }


def _expr(value: str | int | float, params: dict[str, sp.Expr]) -> sp.Expr:
    """Exact SymPy value of a spec string: decimals become rationals, names refer to parameters."""
    return sp.sympify(str(value), locals=dict(params, tool_length=TOOL_LENGTH), rational=True)


def load_spec(name_or_path: str | Path) -> Spec:
    """Load and validate a chain spec; errors name the file and the problem."""
    path = Path(name_or_path)
    if not path.suffix:
        path = MACHINES_DIR / f"{name_or_path}.toml"
    raw = tomllib.loads(path.read_text())
    where = f"{path.name}"
    params: dict[str, sp.Expr] = {}
    for k, v in raw.get("parameters", {}).items():
        params[k] = _expr(v, params)
    axes = []
    for a in raw["axes"]:
        if a["kind"] not in ("linear", "rotary"):
            raise ValueError(f"{where}: axis {a['name']}: kind must be 'linear' or 'rotary'")
        lim = a.get("limits")
        axes.append(Axis(a["name"], a["kind"], (float(lim[0]), float(lim[1])) if lim else None))
    names = [a.name for a in axes]
    if len(set(names)) != len(names):
        raise ValueError(f"{where}: duplicate axis names {names}")
    chains = {}
    for side in ("table_chain", "tool_chain"):
        els = []
        for i, el in enumerate(raw.get(side, [])):
            el = dict(el)
            if "joint" in el:
                if el["joint"] not in names:
                    raise ValueError(f"{where}: {side}[{i}] names unknown axis {el['joint']!r}")
            elif el.get("op") in ("Tx", "Ty", "Tz", "Rx", "Ry", "Rz"):
                el["value"] = _expr(el["value"], params)
            else:
                raise ValueError(f"{where}: {side}[{i}] needs 'joint' or op in Tx/Ty/Tz/Rx/Ry/Rz")
            els.append(el)
        chains[side] = tuple(els)
    used = [el["joint"] for c in chains.values() for el in c if "joint" in el]
    if sorted(used) != sorted(names):
        raise ValueError(f"{where}: every axis must appear exactly once in the chains (found {used})")
    return Spec(raw["name"], raw.get("title", raw["name"]), path, params, tuple(axes),
                chains["table_chain"], chains["tool_chain"], dict(raw.get("ik", {})))


def all_specs() -> list[Spec]:
    return [load_spec(p) for p in sorted(MACHINES_DIR.glob("*.toml"))]
