"""The history store: SQLAlchemy Core on SQLite (the default, a file) or PostgreSQL (by URL), its schema versioned
by Alembic migrations shipped in mtcal/history/migrations and run on open, in the store's own transaction.

Where: ``--db URL`` (``db``), else the environment variable ``MTCAL_HISTORY_DB``, else ``./mtcal-history.db``.  A
value without ``://`` is a SQLite file; ``postgresql://user@host/db`` (or ``?host=/socket/dir``) is PostgreSQL
through psycopg (``pip install mtcal[postgres]``).

Every write is one transaction (a killed write leaves nothing); writers are serialised (SQLite: ``BEGIN
IMMEDIATE`` with a busy timeout; PostgreSQL: a transaction-scoped advisory lock), so two processes adding at once
both land, and the date rule (never before the machine's previous calibration) and the duplicate rule are checked
inside the writer's transaction.  Reads never write: SQLite is opened read-only (``mode=ro``; a killed writer's
hot journal is first rolled back by SQLite itself, which restores the file as it was), PostgreSQL in read-only
transactions, and only ``add`` creates or upgrades the schema.

A database is mtcal's by mtcal's own marker (the table ``mtcal_owner``, revision 0002), or, written before the
marker, by the first revision's tables with their columns; anything else (another program's database, even an
Alembic one at a revision called 0001) is refused untouched.  A revision this mtcal does not know (a newer
mtcal's) is refused, never read with a guess.  Every fault of the database (unreachable, malformed, a missing
table, read-only, locked, empty) is one InputError naming the database and the fault; an error of mtcal's own SQL
stays a bug.
"""
from __future__ import annotations

import contextlib
import datetime as dt
import json
import os
import re
import sqlite3
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import sqlalchemy as sa

from mtcal.errors import InputError
from mtcal.history.results import Quantity, Result, check_spec, document_text
from mtcal.history.schema import checked_document

DEFAULT_DB = "mtcal-history.db"
ENV_VAR = "MTCAL_HISTORY_DB"
MACHINE_ID = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$")
LOCK_KEY = 230_038  # PostgreSQL advisory lock of the store's writers
MIGRATIONS = Path(__file__).parent / "migrations"
REVISIONS = ("0001", "0002")  # every revision in MIGRATIONS, oldest first (tests/test_history.py: as Alembic's)
HEAD = REVISIONS[-1]
OWNER = "mtcal calibration history"  # the marker's row (migration 0002)
EARLIEST = dt.date(1970, 1, 1)  # the earliest calibration date a history accepts

meta = sa.MetaData()
machines = sa.Table("machines", meta, sa.Column("id", sa.String(64), primary_key=True),
                    sa.Column("spec", sa.String(64)), sa.Column("created_at", sa.String(32)))
results = sa.Table("results", meta, sa.Column("id", sa.Integer, primary_key=True),
                   sa.Column("machine_id", sa.String(64)), sa.Column("kind", sa.String(16)),
                   sa.Column("date", sa.Date), sa.Column("added_at", sa.String(32)), sa.Column("spec", sa.String(64)),
                   sa.Column("source", sa.Text), sa.Column("file_sha256", sa.String(64)),
                   sa.Column("recording_sha256", sa.String(64)), sa.Column("model_sha256", sa.String(64)),
                   sa.Column("tool_version", sa.String(32)), sa.Column("instrument", sa.Text),
                   sa.Column("environment", sa.Text), sa.Column("document", sa.Text))
quantities = sa.Table("quantities", meta, sa.Column("id", sa.Integer, primary_key=True),
                      sa.Column("result_id", sa.Integer), sa.Column("name", sa.String(32)),
                      sa.Column("axis", sa.String(16)), sa.Column("position", sa.Float),
                      sa.Column("value", sa.Float), sa.Column("u95", sa.Float), sa.Column("dof", sa.Float),
                      sa.Column("unit", sa.String(16)))
owner = sa.Table("mtcal_owner", meta, sa.Column("owner", sa.String(64), primary_key=True))
TABLES = (machines, results, quantities)
DATE_TEXT = sa.type_coerce(results.c.date, sa.String).label("date")  # parsed by _as_date, which names a bad one


@dataclass
class Record:
    """One stored result: its machine ID, kind, calibration date, provenance and quantities (mm, rad)."""

    id: int
    machine: str
    kind: str
    date: dt.date
    added_at: str
    spec: str | None
    source: str
    file_sha256: str
    recording_sha256: str | None
    model_sha256: str | None
    tool_version: str
    instrument: str | None
    environment: dict
    document: dict | None = None
    quantities: list[Quantity] = field(default_factory=list)

    def to_dict(self) -> dict:
        return {"id": self.id, "machine": self.machine, "kind": self.kind, "date": self.date.isoformat(),
                "added_at": self.added_at, "spec": self.spec, "source": self.source,
                "file_sha256": self.file_sha256, "recording_sha256": self.recording_sha256,
                "model_sha256": self.model_sha256, "tool_version": self.tool_version, "instrument": self.instrument,
                "environment": self.environment, "quantities": len(self.quantities)}


def database_url(db: str | None = None) -> str:
    """The store's URL: ``db``, else $MTCAL_HISTORY_DB, else ./mtcal-history.db (a path is a SQLite file); an
    empty ``db`` or an empty variable is an InputError (never the default in its place)."""
    if db is None:
        db = os.environ.get(ENV_VAR)
        if db is not None and not db.strip():
            raise InputError(f"the environment variable {ENV_VAR} is empty: set it to a SQLite file or "
                             f"postgresql://..., or unset it for ./{DEFAULT_DB}")
        db = db or DEFAULT_DB
    elif not db.strip():
        raise InputError("`db` is empty: give a SQLite file or postgresql://...")
    if "://" not in db:
        return "sqlite:///" + str(Path(db).absolute())
    if db.startswith("postgresql://") or db.startswith("postgres://"):
        return "postgresql+psycopg://" + db.split("://", 1)[1]
    return db


def check_machine_id(mid: str) -> str:
    """A machine ID as a filesystem and a URL keep it: letters, digits, '.', '_', '-' (first a letter or digit),
    at most 64; anything else is an InputError naming the character."""
    if not MACHINE_ID.match(mid or "") or ".." in mid:
        bad = next((c for c in mid if not (c.isascii() and (c.isalnum() or c in "._-"))), None)
        why = (f"the character {bad!r}" if bad else "an empty ID" if not mid else "'..'" if ".." in mid
               else "more than 64 characters" if len(mid) > 64 else "a first character that is not a letter or digit")
        raise InputError(f"machine ID {mid!r} has {why}; use letters, digits, '.', '_' and '-' (a filesystem and a "
                         "URL keep those)")
    return mid


def check_date(date: dt.date) -> dt.date:
    """A calibration's date: from 1970-01-01 (EARLIEST) to today; anything else is an InputError."""
    today = dt.date.today()
    if date < EARLIEST:
        raise InputError(f"date {date.isoformat()} is before {EARLIEST.isoformat()}: not a calibration's date (a "
                         "typing error?)")
    if date > today:
        raise InputError(f"date {date.isoformat()} is in the future (today is {today.isoformat()})")
    return date


def refuse_database_output(outputs: list, db: str | None = None) -> None:
    """No output is the history database ``db`` (as database_url finds it; nor its journal) nor any other
    database file (SQLite's header): an InputError, whatever ``replace`` allows.  Called before anything is
    written (mtcal history trend --plot, mtcal report -o)."""
    u = sa.engine.make_url(database_url(db))
    main = Path(u.database) if u.get_backend_name() == "sqlite" and u.database else None
    kept = [main] + [Path(f"{main}{tail}") for tail in ("-journal", "-wal", "-shm")] if main else []
    for out in (Path(o) for o in outputs if o is not None):
        for p in kept:
            if _same_file(out, p):
                raise InputError(f"{out} is the history database {main}{' (its journal)' if p != main else ''}: "
                                 "an output never replaces it, whatever `replace` says; choose another output")
        if _is_database_file(out):
            raise InputError(f"{out} is a SQLite database: an output never replaces a database, whatever `replace` "
                             "says; choose another output")


def _same_file(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist (yet)
        return a.resolve() == b.resolve()


def _is_database_file(p: Path) -> bool:
    try:
        with p.open("rb") as fh:
            return fh.read(16) == b"SQLite format 3\x00"
    except OSError:
        return False


def _shown(url: str) -> str:
    """The database as messages name it: a SQLite file by its path, a server's URL without its password."""
    try:
        u = sa.engine.make_url(url)
    except Exception:  # noqa: BLE001 - an unparsable URL is shown as given
        return url
    if u.get_backend_name() == "sqlite" and u.database:
        return u.database
    return u.render_as_string(hide_password=True)


class Store:
    """An open history store (module docstring).  ``write``: open for ``add`` (a new SQLite file is created when
    there is none, the schema created or upgraded, in the writer's transaction); otherwise read-only (SQLite opened
    with ``mode=ro``, PostgreSQL in read-only transactions), and a missing or empty database is refused."""

    def __init__(self, db: str | None = None, write: bool = False):
        self.url = database_url(db)
        self.shown = _shown(self.url)
        self.write = write
        self.engine = _engine(self.url, self.shown, write)
        try:
            with self.engine.connect() as conn:
                self.dialect = conn.dialect.name
        except sa.exc.DBAPIError as exc:
            self.engine.dispose()
            raise InputError(f"cannot reach the history database {self.shown}: {_first_line(exc)}") from None
        try:
            with self._faults():
                self.revision = self._open_schema()
        except BaseException:
            self.engine.dispose()
            raise

    def close(self) -> None:
        self.engine.dispose()

    def __enter__(self) -> Store:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    @contextlib.contextmanager
    def _faults(self):
        """A fault of the database (unreachable, malformed, a missing table, read-only, locked) as one InputError
        naming the database; an error of mtcal's own SQL stays a bug."""
        try:
            yield
        except sa.exc.DBAPIError as exc:
            if not _is_fault(exc):
                raise
            raise InputError(_fault(exc, self.shown)) from None

    # ------------------------------------------------------------------ schema
    def _open_schema(self) -> str:
        """Check the database is mtcal's (its marker, or the first schema's tables) at a revision this mtcal knows,
        with its tables; for ``write``, create or upgrade it inside one writer's transaction."""
        with self.engine.connect() as conn:
            state = _schema_state(conn)
        revision = self._owned(*state)
        if revision == HEAD or not self.write:
            return revision
        with self._writer() as conn:  # again inside the writer: another process may have created it meanwhile
            revision = self._owned(*_schema_state(conn))
            if revision != HEAD:
                from alembic import command
                from alembic.config import Config
                cfg = Config()
                cfg.set_main_option("script_location", str(MIGRATIONS))
                cfg.attributes["connection"] = conn
                command.upgrade(cfg, "head")
        return HEAD

    def _owned(self, revision: str | None, marked: bool, tables: dict[str, set[str]]) -> str | None:
        """The revision of an mtcal history (None: an empty database, which only ``write`` accepts); anything else
        is an InputError naming the database and what is wrong."""
        if not tables:
            if not self.write:
                raise InputError(f"the history database {self.shown} is empty (nothing added yet: `mtcal history "
                                 "add` creates the history)")
            return None
        ours = [t for t in TABLES if t.name in tables]  # the first revision's tables, each with its columns
        first = revision == REVISIONS[0] and bool(ours) and all(set(t.c.keys()) <= tables[t.name] for t in ours)
        if not (marked or first):  # another program's database: never add mtcal's tables to it
            names = sorted(tables)
            alembic = f", at another program's Alembic revision {revision!r}" if revision else ""
            raise InputError(f"the database {self.shown} is not an mtcal history (it holds the tables "
                             f"{', '.join(names[:5])}{' ...' if len(names) > 5 else ''} and no mtcal marker{alembic}): "
                             "nothing was written; give another `db`")
        if revision not in REVISIONS:
            raise InputError(f"the history database {self.shown} has schema revision {revision!r}, newer than this "
                             f"mtcal knows (its newest is {HEAD!r}): written by a newer mtcal; upgrade mtcal to read "
                             "it")
        for t in TABLES:
            if t.name not in tables:
                raise InputError(_missing(self.shown, t.name))
        return revision

    def _writer(self):
        """A serialised write transaction (module docstring)."""
        return _Writer(self.engine)

    # ------------------------------------------------------------------ writes
    def add(self, result: Result, machine: str, date: dt.date, tool_version: str) -> Record:
        """Add one result to ``machine``'s history at ``date`` (one transaction; every refusal before anything is
        written): the spec must be the machine's, the date not before its latest calibration, the file not
        already in its history."""
        check_machine_id(machine)
        check_date(date)
        _fits(result)
        now = dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds")
        with self._faults(), self._writer() as conn:
            row = conn.execute(sa.select(machines).where(machines.c.id == machine)).first()
            if row is not None and row.spec and result.spec and row.spec != result.spec:
                raise InputError(f"{result.source}: a result of machine spec {result.spec!r}, but the history of "
                                 f"{machine} holds results of spec {row.spec!r}; a machine ID names one machine")
            latest = _as_date(conn.execute(sa.select(sa.func.max(DATE_TEXT)).where(
                results.c.machine_id == machine)).scalar(), self.shown)
            if latest is not None and date < latest:
                raise InputError(f"{result.source}: date {date.isoformat()} is before the previous calibration of "
                                 f"{machine} ({latest.isoformat()}); results are added in the order they were made")
            dup = conn.execute(sa.select(DATE_TEXT, results.c.kind).where(
                (results.c.machine_id == machine) & (results.c.file_sha256 == result.file_sha256))).first()
            if dup is not None:
                raise InputError(f"{result.source}: already in the history of {machine} (the {dup.kind} of "
                                 f"{_as_date(dup.date, self.shown).isoformat()}); nothing added")
            if row is None:
                conn.execute(machines.insert().values(id=machine, spec=result.spec, created_at=now))
            elif not row.spec and result.spec:
                conn.execute(machines.update().where(machines.c.id == machine).values(spec=result.spec))
            values = dict(machine_id=machine, kind=result.kind, date=date, added_at=now, spec=result.spec,
                          source=Path(result.source).name, file_sha256=result.file_sha256,
                          recording_sha256=result.recording_sha256, model_sha256=result.model_sha256,
                          tool_version=tool_version, instrument=result.instrument,
                          environment=json.dumps(result.environment), document=document_text(result.document))
            rid = conn.execute(results.insert().values(**values).returning(results.c.id)).scalar_one()
            if result.quantities:
                conn.execute(quantities.insert(), [
                    {"result_id": rid, "name": q.name, "axis": q.axis, "position": q.position, "value": q.value,
                     "u95": q.u95, "dof": q.dof, "unit": q.unit} for q in result.quantities])
        return Record(rid, machine, result.kind, date, now, result.spec, values["source"], result.file_sha256,
                      result.recording_sha256, result.model_sha256, tool_version, result.instrument,
                      result.environment, result.document, list(result.quantities))

    # ------------------------------------------------------------------ reads
    def machine_ids(self) -> list[str]:
        with self._faults(), self.engine.connect() as conn:
            return [r.id for r in conn.execute(sa.select(machines.c.id).order_by(machines.c.id))]

    def machines(self) -> list[dict]:
        """Every machine of the history: its ID, spec, number of results, first and last date, results per kind."""
        q = (sa.select(machines.c.id, machines.c.spec, results.c.kind, sa.func.count(results.c.id),
                       sa.func.min(DATE_TEXT), sa.func.max(DATE_TEXT))
             .select_from(machines.outerjoin(results, results.c.machine_id == machines.c.id))
             .group_by(machines.c.id, machines.c.spec, results.c.kind).order_by(machines.c.id, results.c.kind))
        out: dict[str, dict] = {}
        with self._faults(), self.engine.connect() as conn:
            for mid, spec, kind, n, first, last in conn.execute(q):
                m = out.setdefault(mid, {"machine": mid, "spec": spec, "results": 0, "first": None, "last": None,
                                         "kinds": {}})
                if kind is None:
                    continue
                first, last = _as_date(first, self.shown).isoformat(), _as_date(last, self.shown).isoformat()
                m["results"] += n
                m["kinds"][kind] = n
                m["first"] = min(m["first"] or first, first)
                m["last"] = max(m["last"] or last, last)
        return list(out.values())

    def records(self, machine: str, kind: str | None = None, with_documents: bool = False) -> list[Record]:
        """``machine``'s results (of ``kind``), oldest first (date, then the order they were added), with their
        quantities; an unknown machine is an InputError naming the known ones.  ``with_documents``: each stored
        result checked as ``history add`` checks it (mtcal.history.schema), so that what reads them (the report)
        never meets a field it cannot read: a result stored before those checks that fails them is an InputError
        naming the database, the result and the field."""
        check_machine_id(machine)
        with self._faults(), self.engine.connect() as conn:
            if conn.execute(sa.select(machines.c.id).where(machines.c.id == machine)).first() is None:
                known = [r.id for r in conn.execute(sa.select(machines.c.id).order_by(machines.c.id))]
                raise InputError(f"no machine {machine!r} in the history {self.shown} (machines: "
                                 f"{', '.join(known) or 'none yet'})")
            cols = [DATE_TEXT if c.name == "date" else c for c in results.c if with_documents or c.name != "document"]
            q = sa.select(*cols).where(results.c.machine_id == machine)
            if kind:
                q = q.where(results.c.kind == kind)
            rows = conn.execute(q.order_by(results.c.date, results.c.id)).all()
            ids = [r.id for r in rows]
            qs: dict[int, list[Quantity]] = {i: [] for i in ids}
            if ids:
                for r in conn.execute(sa.select(quantities).where(quantities.c.result_id.in_(ids))
                                      .order_by(quantities.c.id)):
                    qs[r.result_id].append(Quantity(r.name, r.value, r.unit, r.axis, r.position, r.u95, r.dof))
        return [_record(r, machine, qs[r.id], with_documents, self.shown) for r in rows]

    def spec_of(self, machine: str) -> str | None:
        with self._faults(), self.engine.connect() as conn:
            return conn.execute(sa.select(machines.c.spec).where(machines.c.id == machine)).scalar()


class _Writer:
    """``with _Writer(engine) as conn``: one serialised transaction, committed on success, rolled back on any
    exception (module docstring)."""

    def __init__(self, engine: sa.Engine):
        self.engine = engine

    def __enter__(self) -> sa.Connection:
        self.cm = self.engine.begin()
        conn = self.cm.__enter__()
        if conn.dialect.name == "postgresql":
            conn.execute(sa.text("SELECT pg_advisory_xact_lock(:k)"), {"k": LOCK_KEY})
        return conn

    def __exit__(self, *exc) -> bool | None:
        return self.cm.__exit__(*exc)


def _record(r, machine: str, qs: list[Quantity], with_document: bool, shown: str) -> Record:
    """A stored row of the database ``shown`` as a Record; with its document, checked (Store.records)."""
    what = f"the {r.kind} #{r.id} of {str(r.date)[:10]} ({r.source})"
    try:
        date = dt.date.fromisoformat(str(r.date)[:10])
        env = json.loads(r.environment or "{}")
        doc = checked_document(r.kind, json.loads(r.document), what) if with_document else None
        if r.spec:
            check_spec(r.spec, what)
    except InputError as exc:  # it names the result
        problem = str(exc)
    except ValueError as exc:  # a date or JSON that is none
        problem = f"{what}: {exc}"
    else:
        return Record(r.id, machine, r.kind, date, r.added_at, r.spec, r.source, r.file_sha256, r.recording_sha256,
                      r.model_sha256, r.tool_version, r.instrument, env, doc, qs)
    raise InputError(f"the history database {shown}: {problem}; this stored result cannot be read (written before "
                     "mtcal checked what it adds, or changed since)")


def _fits(result: Result) -> None:
    """Every quantity's name, axis and unit within its column's length (PostgreSQL refuses a longer one, SQLite
    would keep it): an InputError naming the value."""
    for q in result.quantities:
        for col in ("name", "axis", "unit"):
            v, n = getattr(q, col), quantities.c[col].type.length
            if v is not None and len(v) > n:
                raise InputError(f"the {col} {v[:40]!r}{'...' if len(v) > 40 else ''} has {len(v)} characters; the "
                                 f"history keeps at most {n}", result.source)


def _schema_state(conn: sa.Connection) -> tuple[str | None, bool, dict[str, set[str]]]:
    """(Alembic's revision or None, whether mtcal's marker is there, every table with its columns)."""
    insp = sa.inspect(conn)
    tables = {t: {c["name"] for c in insp.get_columns(t)} for t in insp.get_table_names()}
    revision = (conn.execute(sa.text("SELECT version_num FROM alembic_version")).scalar()
                if "alembic_version" in tables else None)
    marked = owner.name in tables and conn.execute(sa.select(owner.c.owner)).scalar() == OWNER
    return revision, marked, tables


# PostgreSQL's codes of a database's state rather than of mtcal's SQL: an undefined table or column (dropped by
# someone), insufficient privilege (a user who may only read)
_PG_FAULTS = ("42P01", "42703", "42501")


def _is_fault(exc: sa.exc.DBAPIError) -> bool:
    """Whether a driver's error is the database's state (a fault to report) rather than a bug of mtcal's SQL."""
    if isinstance(exc, (sa.exc.OperationalError, sa.exc.InterfaceError)) or type(exc) is sa.exc.DatabaseError:
        return True  # SQLite: no such table, read-only, locked, malformed ("DatabaseError"); lost connections
    return getattr(exc.orig, "sqlstate", None) in _PG_FAULTS


def _missing(shown: str, table: str) -> str:
    return (f"the history database {shown}: the table '{table}' is missing (dropped, or damaged by another "
            "program); nothing was written")


def _fault(exc: sa.exc.DBAPIError, shown: str) -> str:
    """One line for a fault of the database ``shown``."""
    text = _first_line(exc)
    table = re.search(r'no such table: "?(\w+)|relation "(\w+)" does not exist', text)
    if table:
        return _missing(shown, table.group(1) or table.group(2))
    if "readonly" in text or "read-only" in text or "permission denied" in text:
        return f"the history database {shown} is read-only ({text}); nothing was written"
    if "locked" in text:
        return f"the history database {shown} is locked by another writer ({text}); nothing was written, try again"
    if "malformed" in text or "not a database" in text:
        return f"the history database {shown} cannot be read as a database: {text}; give another `db`"
    return f"the history database {shown}: {text}"


def _as_date(v: Any, shown: str) -> dt.date | None:
    """A stored date (a date, or its ISO text as SQLite keeps it); one that is neither is an InputError naming the
    database ``shown``."""
    if v is None or isinstance(v, dt.date):
        return v
    try:
        return dt.date.fromisoformat(str(v)[:10])
    except ValueError:
        raise InputError(f"the history database {shown}: a stored date {str(v)[:40]!r} is not a date "
                         "(YYYY-MM-DD); changed by another program?") from None


def _first_line(exc: BaseException) -> str:
    text = str(getattr(exc, "orig", None) or exc).strip().splitlines()
    return text[0] if text else type(exc).__name__


def _engine(url: str, shown: str, write: bool) -> sa.Engine:
    """An engine for ``url`` (Store's ``write``): SQLite with writers serialised (BEGIN IMMEDIATE, 60 s busy
    timeout), or read-only (``mode=ro``); PostgreSQL through psycopg with a 5 s connect timeout, read-only
    transactions unless ``write``.  Other databases, a missing driver, a folder, a missing SQLite file (unless
    ``write``) and a read-only file to write are InputErrors."""
    from sqlalchemy.pool import NullPool
    try:
        u = sa.engine.make_url(url)
    except sa.exc.ArgumentError:
        raise InputError(f"not a database URL: {shown} (give a SQLite file path or postgresql://...)") from None
    if u.get_backend_name() == "sqlite":
        return _sqlite_engine(u, shown, write)
    if u.get_backend_name() != "postgresql":
        raise InputError(f"history database {shown}: only SQLite (a file) and PostgreSQL (postgresql://...) are "
                         "supported")
    args = {"connect_timeout": 5} if write else {"connect_timeout": 5, "options": "-c default_transaction_read_only=on"}
    try:
        return sa.create_engine(url, poolclass=NullPool, connect_args=args)
    except ModuleNotFoundError:
        raise InputError(f"history database {shown}: PostgreSQL needs the psycopg driver "
                         "(pip install 'mtcal[postgres]')") from None


def _sqlite_engine(u: sa.engine.URL, shown: str, write: bool) -> sa.Engine:
    from sqlalchemy.pool import NullPool
    if not u.database or u.database == ":memory:":
        raise InputError("the history needs a SQLite file, not an in-memory database")
    path = Path(u.database)
    if path.is_dir():
        raise InputError(f"the history database {shown} is a folder, not a database file; give a file")
    if not path.exists() and not write:
        raise InputError(f"no history database at {path} (nothing added yet: `mtcal history add` creates it)")
    if not path.parent.is_dir():
        raise InputError(f"cannot reach the history database {shown}: {path.parent} is not a directory")
    if write:
        for p in (path, path.parent):  # SQLite writes its journal beside the file
            if p.exists() and not (os.access(p, os.W_OK) and p.stat().st_mode & 0o222):
                what = "the history database" if p == path else "the folder of the history database"
                raise InputError(f"{what} {p} is read-only (mode {p.stat().st_mode & 0o777:o}): nothing was "
                                 "added; make it writable to add to it")
        eng = sa.create_engine(u, poolclass=NullPool, connect_args={"timeout": 60})
        sa.event.listen(eng, "begin", lambda conn: conn.exec_driver_sql("BEGIN IMMEDIATE"))
    else:
        _roll_back_interrupted(path)
        uri = path.absolute().as_uri() + "?mode=ro"
        eng = sa.create_engine("sqlite://", poolclass=NullPool,
                               creator=lambda: sqlite3.connect(uri, uri=True, timeout=60, check_same_thread=False))
        sa.event.listen(eng, "begin", lambda conn: conn.exec_driver_sql("BEGIN"))
    sa.event.listen(eng, "connect", _sqlite_connect)
    return eng


def _roll_back_interrupted(path: Path) -> None:
    """A writer killed inside its transaction may leave a hot journal beside the file (its pages already in the
    file), which only a writable connection can roll back; let SQLite do so before a read-only open, so that the
    file is again what it was before that transaction (nothing of the reader's is written).  Where the file cannot
    be opened for writing, the read-only open then says so."""
    journal = Path(f"{path}-journal")
    if not (journal.is_file() and journal.stat().st_size > 0 and os.access(path, os.W_OK)):
        return
    conn = sqlite3.connect(path, timeout=60)
    try:
        conn.execute("SELECT COUNT(*) FROM sqlite_master").fetchone()  # SQLite rolls a hot journal back here
    except sqlite3.DatabaseError:
        pass  # not a database, or damaged: the read-only open names it
    finally:
        conn.close()


def _sqlite_connect(dbapi_conn, record) -> None:
    dbapi_conn.isolation_level = None  # SQLAlchemy's "begin" event issues BEGIN IMMEDIATE itself
    dbapi_conn.execute("PRAGMA foreign_keys = ON")
