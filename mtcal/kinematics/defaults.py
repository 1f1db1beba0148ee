"""The machine spec's campaign defaults ([campaign] of derive/machines/<name>.toml, Machine.campaign): the
positions of every axis (mm or deg), the reflector nests of each side (mm) and the named tracker stations (mm,
machine frame)."""
from __future__ import annotations

import numpy as np

from mtcal.kinematics.machine import Machine


def tracker_positions(machine: Machine) -> dict[str, tuple[float, float, float]]:
    """The spec's named tracker stations (mm, machine frame); the first is the default."""
    return {k: tuple(v) for k, v in machine.campaign["trackers"]}


def default_positions(machine: Machine) -> dict[str, np.ndarray]:
    """The spec's campaign positions of every axis (mm or deg), in the order the axes are measured."""
    return {a: np.linspace(start, stop, count) for a, start, stop, count in machine.campaign["positions"]}


def default_points(machine: Machine, side: str) -> dict[str, tuple]:
    """The spec's reflector nests of one side ("tool": mm from the spindle gauge point; "table": workpiece)."""
    return {k: tuple(v) for k, v in machine.campaign["reflectors"][side]}
