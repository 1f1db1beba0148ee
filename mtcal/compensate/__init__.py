"""First-order compensation of NC programs against an error model: the solver (core) and
``compensate_program`` (run)."""
from mtcal.compensate.core import Compensator, ProgramCompensator
from mtcal.compensate.run import compensate_program

__all__ = ["compensate_program", "Compensator", "ProgramCompensator"]
