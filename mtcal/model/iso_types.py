"""ISO/TR 16907 compensation types of a machine: which ISO 230-1 errors each type acts on, from the machine's
axes (mtcal.Machine), never from a list of letters.

L-POS positioning, L-STR straightness, L-SQU squareness, L-ANG angular errors of the linear axes; R-POS
positioning, R-RAX radial and axial motions, R-POR position and orientation (location) errors, R-ANG tilt
motions of the rotary axes; the composites L-VOL / R-VOL (all four parts) and FOR (tool orientation)."""
from __future__ import annotations

import numpy as np

from mtcal.model.errormodel import ErrorModel

PARTS = {"L-VOL": ("L-POS", "L-STR", "L-SQU", "L-ANG"), "R-VOL": ("R-POS", "R-RAX", "R-POR", "R-ANG")}
ORDER = ("L-POS", "L-STR", "L-SQU", "L-ANG", "L-VOL", "R-POS", "R-RAX", "R-POR", "R-ANG", "R-VOL", "FOR")


def iso_16907_types(machine) -> dict[str, tuple[str, ...]]:
    """{type: ISO names} of ``machine``'s errors for the eight elementary types (module docstring)."""
    own = machine.positioning_errors
    known = set(machine.error_names)

    def motions(axes, components: str, positioning: bool) -> tuple[str, ...]:
        names = (f"E_{c}{a}" for a in axes for c in components)
        return tuple(n for n in names if n in known and (n == own[n[3:]]) == positioning)

    lin, rot = machine.linear_axes, machine.rotary_axes
    return {"L-POS": motions(lin, "XYZ", True), "L-STR": motions(lin, "XYZ", False),
            "L-SQU": tuple(machine.error_groups.get("squareness", ())), "L-ANG": motions(lin, "ABC", False),
            "R-POS": motions(rot, "ABC", True), "R-RAX": motions(rot, "XYZ", False),
            "R-POR": tuple(machine.error_groups.get("location", ())), "R-ANG": motions(rot, "ABC", False)}


def orientation_errors(machine) -> tuple[str, ...]:
    """Errors that turn the tool axis: the angular motions of every axis (positioning of the rotary axes
    included) and the tilts of the rotary axes' average lines (E_A0R, E_B0R); squareness only tilts a motion."""
    t = iso_16907_types(machine)
    tilts = tuple(n for n in t["R-POR"] if n[2] in "ABC")
    return t["L-ANG"] + t["R-ANG"] + t["R-POS"] + tilts


def present_errors(model: ErrorModel) -> set[str]:
    """ISO names the model gives a non-zero value anywhere."""
    out = {n for n, v in model.constants.items() if v != 0}
    for n, f in model.functions.items():
        if np.any(f.values != 0) or (f.fit is not None and not f.fit.is_zero()):
            out.add(n)
    return out


def iso_types(model: ErrorModel, machine, scope: str = "position") -> dict[str, list[str]]:
    """ISO/TR 16907 types covered by compensating ``model`` on ``machine`` with ``scope`` ("position": the tool
    tip; "full": also the tool axis, FOR): {"covered": [...], "partial": composites of which only some parts are
    covered}."""
    names = present_errors(model)
    covered = {t for t, members in iso_16907_types(machine).items() if names & set(members)}
    covered |= {c for c, parts in PARTS.items() if set(parts) <= covered}
    if scope == "full" and names & set(orientation_errors(machine)):
        covered.add("FOR")
    partial = [c for c, parts in PARTS.items() if c not in covered and covered & set(parts)]
    return {"covered": [t for t in ORDER if t in covered], "partial": partial}
