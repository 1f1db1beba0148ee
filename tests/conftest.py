"""Suite-wide pytest set-up: the header names the numerical releases the run uses (a fresh install gets the newest
the pins allow, and a result that depends on them must be traceable to them)."""
from __future__ import annotations

import importlib.metadata as md


def pytest_report_header(config) -> str:
    names = ("numpy", "scipy", "sympy", "casadi", "matplotlib")
    return "mtcal numerics: " + ", ".join(f"{n} {_version(n)}" for n in names)


def _version(name: str) -> str:
    try:
        return md.version(name)
    except md.PackageNotFoundError:
        return "absent"
