"""A machine's calibration history: every result of a fleet in one database (SQLite by default, PostgreSQL by URL;
mtcal.history.store), changes between calibrations tested against their uncertainty (mtcal.history.compare).

Entry points: ``add`` (a result file into a machine's history), ``machines``, ``show``, ``compare_history``,
``trend_of``; the store itself is ``Store``."""
from mtcal.history.api import add, compare_history, machines, show, trend_of
from mtcal.history.compare import LEVEL, Comparison, Trend
from mtcal.history.results import KINDS, read_result
from mtcal.history.store import DEFAULT_DB, ENV_VAR, Record, Store

__all__ = ["add", "show", "machines", "compare_history", "trend_of", "Comparison", "Trend", "Record", "Store",
           "read_result", "KINDS", "LEVEL", "DEFAULT_DB", "ENV_VAR"]
