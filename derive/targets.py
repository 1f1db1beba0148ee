"""The manifest of generation targets: single source of truth for what generated/ contains.

Each target is a name and a zero-argument builder returning a codegen.Module.  Add new derivations here.
"""
from __future__ import annotations

from collections.abc import Callable

from .codegen import Module
from .spec import MACHINES_DIR


def _machine(name: str) -> Callable[..., Module]:
    def build(progress=lambda m: None) -> Module:
        from .kinematics import derive_machine
        from .spec import load_spec
        return derive_machine(load_spec(name), progress)
    return build


TARGETS: dict[str, Callable[..., Module]] = {
    **{p.stem: _machine(p.stem) for p in sorted(MACHINES_DIR.glob("*.toml"))},
    "plate": lambda progress=lambda m: None: __import__("derive.plate", fromlist=["build"]).build(progress),
    "signatures": lambda progress=lambda m: None: __import__("derive.signatures", fromlist=["build"]).build(progress),
    "threepoint": lambda progress=lambda m: None: __import__("derive.threepoint", fromlist=["x"]).derive_threepoint(progress),
}
