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
    campaign: dict

    def axis(self, name: str) -> Axis:
        return next(a for a in self.axes if a.name == name)

    def side(self, name: str) -> str:
        """"tool" when the axis moves the spindle (tool_chain), "table" when it moves the workpiece."""
        return "tool" if any(el.get("joint") == name for el in self.tool_chain) else "table"

    def positioning_error(self, name: str) -> str:
        """ISO name of the error along / about the axis' own motion: E_XX for X along x, E_C<R> for a rotary axis
        (rotation about the stator z, docs/design.md)."""
        if self.axis(name).kind == "rotary":
            return f"E_C{name}"
        el = next(e for e in self.tool_chain + self.table_chain if e.get("joint") == name)
        d = [abs(float(c)) for c in el.get("direction", [0, 0, 1])]
        return f"E_{TRANSLATIONS[d.index(max(d))]}{name}"

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
                chains["table_chain"], chains["tool_chain"], dict(raw.get("ik", {})),
                _campaign(raw.get("campaign", {}), axes, where))


def _xyz(v, where: str) -> list[float]:
    if not isinstance(v, list) or len(v) != 3:
        raise ValueError(f"{where}: expected [x, y, z] in mm, got {v!r}")
    return [float(c) for c in v]


def _campaign(raw: dict, axes: list[Axis], where: str) -> dict:
    """Default measurement campaign of the machine (mtcal simulate / plan): axis order and positions
    ([start, stop, count], mm or deg), reflector nests per side (mm; tool: relative to the spindle gauge point,
    table: workpiece coordinates), named tracker stations (mm, machine frame; the first is the default), rounds.
    Named entries are [name, value] lists so that their order survives (the generated metadata sorts dicts)."""
    names = [a.name for a in axes]
    pos = raw.get("positions", {})
    if sorted(pos) != sorted(names):
        raise ValueError(f"{where}: [campaign.positions] needs [start, stop, count] for every axis {names}")
    positions = {}
    for a in names:  # spec order of the axes = the order they are measured in
        v = pos[a]
        if not (isinstance(v, list) and len(v) == 3 and int(v[2]) == v[2] and v[2] >= 2 and v[0] != v[1]):
            raise ValueError(f"{where}: campaign.positions.{a} must be [start, stop, count >= 2], got {v!r}")
        positions[a] = [a, float(v[0]), float(v[1]), int(v[2])]
    refl = raw.get("reflectors", {})
    reflectors = {}
    for side in ("tool", "table"):
        pts = refl.get(side, {})
        if len(pts) < 3:
            raise ValueError(f"{where}: [campaign.reflectors.{side}] needs >= 3 labelled points")
        reflectors[side] = [[k, _xyz(v, f"{where}: campaign.reflectors.{side}.{k}")] for k, v in pts.items()]
    trackers = [[k, _xyz(v, f"{where}: campaign.trackers.{k}")] for k, v in raw.get("trackers", {}).items()]
    if not trackers:
        raise ValueError(f"{where}: [campaign.trackers] needs at least one named tracker station")
    return {"positions": list(positions.values()), "reflectors": reflectors, "trackers": trackers,
            "rounds": int(raw.get("rounds", 4))}


def all_specs() -> list[Spec]:
    return [load_spec(p) for p in sorted(MACHINES_DIR.glob("*.toml"))]
