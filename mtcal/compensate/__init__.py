"""First-order compensation of NC programs against an error model: the solver (``solver``: Compensator), NC
programs streamed through it (``program``: ProgramCompensator), per-axis tables (``tables``), example models
(``examples``) and ``compensate_program`` (``run``), the entry point."""
from mtcal.compensate.program import ProgramCompensator
from mtcal.compensate.run import compensate_program
from mtcal.compensate.solver import Compensator

__all__ = ["compensate_program", "Compensator", "ProgramCompensator"]
