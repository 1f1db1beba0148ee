"""The history's verbs on a database URL (``db``: see mtcal.history.store): what `mtcal history` runs."""
from __future__ import annotations

import datetime as dt
from pathlib import Path

from mtcal.errors import InputError
from mtcal.history.compare import LEVEL, Comparison, Trend, compare, trend
from mtcal.history.results import read_result
from mtcal.history.store import Record, Store, check_machine_id


def tool_version() -> str:
    """The running mtcal's version (its installed distribution's)."""
    from importlib.metadata import PackageNotFoundError, version
    try:
        return version("mtcal")
    except PackageNotFoundError:  # a source tree that is not installed
        return "unknown"


def add(path: str | Path, machine: str, date: dt.date | None = None, db: str | None = None) -> Record:
    """Add the result file ``path`` to ``machine``'s history at ``date`` (default today; never in the future, never
    before the machine's previous calibration).  Everything is checked before anything is written."""
    check_machine_id(machine)
    today = dt.date.today()
    date = date or today
    if date > today:
        raise InputError(f"date {date.isoformat()} is in the future (today is {today.isoformat()})")
    result = read_result(path)
    with Store(db, create=True) as store:
        return store.add(result, machine, date, tool_version())


def show(machine: str, db: str | None = None) -> list[Record]:
    """``machine``'s results, oldest first."""
    with Store(db) as store:
        return store.records(machine)


def compare_history(machine: str, date_from: dt.date | None = None, date_to: dt.date | None = None,
                    db: str | None = None, level: float = LEVEL) -> Comparison:
    """Changes between ``machine``'s calibrations (mtcal.history.compare)."""
    with Store(db) as store:
        return compare(store.records(machine, "model"), machine, store.spec_of(machine), date_from, date_to, level)


def trend_of(machine: str, name: str, position: float | None = None, db: str | None = None) -> Trend:
    """``name``'s values over ``machine``'s calibrations (mtcal.history.compare.trend)."""
    with Store(db) as store:
        return trend(store.records(machine, "model"), machine, name, position)
