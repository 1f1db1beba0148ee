"""NC programs read as rows of axis positions (G-code, CL data)."""
from mtcal.nc.gcode import read_moves

__all__ = ["read_moves"]
