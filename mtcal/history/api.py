"""The history's verbs on a database URL (``db``: see mtcal.history.store): what `mtcal history` runs."""
from __future__ import annotations

import datetime as dt
from pathlib import Path

from mtcal.history.compare import LEVEL, Comparison, Trend, compare, trend
from mtcal.history.results import read_result
from mtcal.history.store import Record, Store, check_date, check_machine_id


def tool_version() -> str:
    """The running mtcal's version (its installed distribution's)."""
    from importlib.metadata import PackageNotFoundError, version
    try:
        return version("mtcal")
    except PackageNotFoundError:  # a source tree that is not installed
        return "unknown"


def add(path: str | Path, machine: str, date: dt.date | None = None, db: str | None = None) -> Record:
    """Add a result file to a machine's history (one transaction; everything is checked before anything is written).

    Parameters
    ----------
    path : str or Path
        An error model (`mtcal identify -o`) or the JSON answer of uncertainty, iso230-2, check evaluate, verify or
        diagnose (mtcal.history.results.KINDS).
    machine : str
        The machine's ID: letters, digits, '.', '_', '-' (at most 64).
    date : datetime.date, optional
        The calibration's date (default today); from 1970-01-01 to today, never before the machine's previous one.
    db : str, optional
        The database (mtcal.history.store.database_url: a SQLite path or postgresql://...).

    Returns
    -------
    Record
        What was stored: kind, date, spec, hashes, tool version, instrument, environment, quantities (mm, rad).

    Raises
    ------
    InputError
        A file that is not an mtcal result or a field of it that is not what mtcal writes (mtcal.history.schema),
        an unknown machine spec or another one than the machine's, a bad machine ID, a date before 1970, in the
        future or before the previous calibration, a file already in the history; a fault of the database
        (unreachable, empty URL, another program's, newer, malformed, a missing table, read-only).

    Examples
    --------
    >>> import datetime, os, tempfile
    >>> from mtcal.data import path
    >>> from mtcal.history import add
    >>> db = os.path.join(tempfile.mkdtemp(), "history.db")
    >>> record = add(path("demo_truth.json"), "DMU-1", date=datetime.date(2026, 1, 15), db=db)
    >>> record.kind, str(record.date)
    ('model', '2026-01-15')
    """
    check_machine_id(machine)
    date = check_date(date or dt.date.today())
    result = read_result(path)
    with Store(db, write=True) as store:
        return store.add(result, machine, date, tool_version())


def show(machine: str, db: str | None = None) -> list[Record]:
    """``machine``'s results, oldest first (read-only)."""
    with Store(db) as store:
        return store.records(machine)


def machines(db: str | None = None) -> list[dict]:
    """Every machine of the history ``db`` (read-only): {"machine", "spec", "results", "first", "last", "kinds"}
    (dates ISO; ``kinds``: results per kind)."""
    with Store(db) as store:
        return store.machines()


def compare_history(machine: str, date_from: dt.date | None = None, date_to: dt.date | None = None,
                    db: str | None = None, level: float = LEVEL) -> Comparison:
    """Changes between a machine's calibrations against their uncertainty (mtcal.history.compare).

    Parameters
    ----------
    machine : str
        The machine's ID.
    date_from : datetime.date, optional
        Compare the identified model of this date with the one of ``date_to`` (default: every consecutive pair).
    date_to : datetime.date, optional
        The later of the two dates compared.
    db : str, optional
        The database, as for ``add``.
    level : float
        The family-wise level of each step (Holm over every error and position), default 0.01.

    Returns
    -------
    Comparison
        ``steps`` with the named changes (µm, µrad, the 95 % interval of each difference) and the unchanged count.

    Examples
    --------
    Two models without uncertainty (the bundled truth, then the same with E_C0Y 40 µrad larger) cannot be
    compared: nothing is named, every error is listed as not compared.

    >>> import datetime, json, os, tempfile
    >>> from mtcal.data import path
    >>> from mtcal.history import add, compare_history
    >>> folder = tempfile.mkdtemp()
    >>> db = os.path.join(folder, "history.db")
    >>> model = json.loads(open(path("demo_truth.json")).read())
    >>> _ = add(path("demo_truth.json"), "DMU-1", date=datetime.date(2026, 1, 15), db=db)
    >>> model["constants"]["E_C0Y"] += 4e-5
    >>> _ = open(os.path.join(folder, "later.json"), "w").write(json.dumps(model))
    >>> _ = add(os.path.join(folder, "later.json"), "DMU-1", date=datetime.date(2026, 6, 15), db=db)
    >>> step = compare_history("DMU-1", db=db).to_dict()["steps"][0]
    >>> step["changed"], "E_C0Y" in step["not_compared"]
    ([], True)
    """
    with Store(db) as store:
        return compare(store.records(machine, "model"), machine, store.spec_of(machine), date_from, date_to, level)


def trend_of(machine: str, name: str, position: float | None = None, db: str | None = None) -> Trend:
    """An error's values over a machine's calibrations.

    Parameters
    ----------
    machine : str
        The machine's ID.
    name : str
        An ISO 230-1 error name (E_C0Y, E_XX, ...).
    position : float, optional
        An error function's position (mm or deg of its axis); default where its latest value is largest in size.
    db : str, optional
        The database, as for ``add``.

    Returns
    -------
    Trend
        ``points``: date, value and 95 % half-width (µm or µrad) per identified model, oldest first.

    Examples
    --------
    >>> import datetime, os, tempfile
    >>> from mtcal.data import path
    >>> from mtcal.history import add, trend_of
    >>> db = os.path.join(tempfile.mkdtemp(), "history.db")
    >>> _ = add(path("demo_truth.json"), "DMU-1", date=datetime.date(2026, 1, 15), db=db)
    >>> t = trend_of("DMU-1", "E_C0Y", db=db)
    >>> t.unit, t.points
    ('µrad', [{'date': '2026-01-15', 'value': 18.0, 'u95': None}])
    """
    with Store(db) as store:
        return trend(store.records(machine, "model"), machine, name, position)
