"""The machine: chain-spec facts and the geometry API on the generated kinematics (mm, deg; machine frame)."""
from mtcal.kinematics.machine import DEFAULT_MACHINE, Machine, available_machines, load_machine

__all__ = ["DEFAULT_MACHINE", "Machine", "available_machines", "load_machine"]
