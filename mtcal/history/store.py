"""The history store: SQLAlchemy Core on SQLite (the default, a file) or PostgreSQL (by URL), its schema versioned
by Alembic migrations shipped in mtcal/history/migrations and run on open, in the store's own transaction.

Where: ``--db URL`` (``db``), else the environment variable ``MTCAL_HISTORY_DB``, else ``./mtcal-history.db``.  A
value without ``://`` is a SQLite file; ``postgresql://user@host/db`` (or ``?host=/socket/dir``) is PostgreSQL
through psycopg (``pip install mtcal[postgres]``).

Every write is one transaction (a killed write leaves nothing); writers are serialised (SQLite: ``BEGIN
IMMEDIATE`` with a busy timeout; PostgreSQL: a transaction-scoped advisory lock), so two processes adding at once
both land, and the date rule (never before the machine's previous calibration) is checked inside the writer's
transaction.  A database whose schema revision this mtcal does not know (written by a newer mtcal) is refused,
never read with a guess.
"""
from __future__ import annotations

import datetime as dt
import json
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import sqlalchemy as sa

from mtcal.errors import InputError
from mtcal.history.results import Quantity, Result, document_text

DEFAULT_DB = "mtcal-history.db"
ENV_VAR = "MTCAL_HISTORY_DB"
MACHINE_ID = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$")
LOCK_KEY = 230_038  # PostgreSQL advisory lock of the store's writers
MIGRATIONS = Path(__file__).parent / "migrations"
HEAD = "0001"  # the newest revision in MIGRATIONS (tests/test_history.py checks it against Alembic's head)

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
    """The store's URL: ``db``, else $MTCAL_HISTORY_DB, else ./mtcal-history.db (a path is a SQLite file)."""
    db = db or os.environ.get(ENV_VAR) or DEFAULT_DB
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


def _shown(url: str) -> str:
    try:
        return sa.engine.make_url(url).render_as_string(hide_password=True)
    except Exception:  # noqa: BLE001 - an unparsable URL is shown as given
        return url


class Store:
    """An open history store (module docstring); ``create``: make a new SQLite file when there is none (``add``
    only; reading a history that does not exist is refused)."""

    def __init__(self, db: str | None = None, create: bool = False):
        self.url = database_url(db)
        self.shown = _shown(self.url)
        self.engine = _engine(self.url, self.shown, create)
        try:
            with self.engine.connect() as conn:
                self.dialect = conn.dialect.name
        except sa.exc.DBAPIError as exc:
            self.engine.dispose()
            raise InputError(f"cannot reach the history database {self.shown}: {_first_line(exc)}") from None
        self.revision = self._migrate()

    def close(self) -> None:
        self.engine.dispose()

    def __enter__(self) -> Store:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # ------------------------------------------------------------------ schema
    def _migrate(self) -> str:
        """Bring the schema to this mtcal's head inside one writer's transaction; a revision this mtcal does not
        know (a newer mtcal's) is an InputError.  Alembic is loaded only when the revision is not HEAD."""
        try:
            with self.engine.connect() as conn:
                revision = _revision(conn)
                foreign = sorted(sa.inspect(conn).get_table_names()) if revision is None else []
        except sa.exc.DatabaseError as exc:
            raise InputError(f"the history database {self.shown} cannot be read as a database: "
                             f"{_first_line(exc)}; give another `db`") from None
        if revision == HEAD:
            return HEAD
        if foreign:  # another program's database: never add mtcal's tables to it
            raise InputError(f"the database {self.shown} is not an mtcal history (it holds the tables "
                             f"{', '.join(foreign[:5])}{' ...' if len(foreign) > 5 else ''} and no mtcal schema "
                             "revision): nothing was written; give another `db`")
        from alembic import command
        from alembic.config import Config
        from alembic.runtime.migration import MigrationContext
        from alembic.script import ScriptDirectory

        cfg = Config()
        cfg.set_main_option("script_location", str(MIGRATIONS))
        script = ScriptDirectory.from_config(cfg)
        head = script.get_current_head()
        with self._writer() as conn:
            current = MigrationContext.configure(conn).get_current_revision()
            if current != head:
                try:
                    script.get_revision(current)
                except Exception:  # noqa: BLE001 - alembic raises several kinds for an unknown revision
                    raise InputError(f"the history database {self.shown} has schema revision {current!r}, newer "
                                     f"than this mtcal knows (its newest is {head!r}): written by a newer mtcal; "
                                     "upgrade mtcal to read it") from None
                cfg.attributes["connection"] = conn
                command.upgrade(cfg, "head")
        return head

    def _writer(self):
        """A serialised write transaction (module docstring)."""
        return _Writer(self.engine)

    # ------------------------------------------------------------------ writes
    def add(self, result: Result, machine: str, date: dt.date, tool_version: str) -> Record:
        """Add one result to ``machine``'s history at ``date`` (one transaction; every refusal before anything is
        written): the spec must be the machine's, the date not before its latest calibration, the file not
        already in its history."""
        check_machine_id(machine)
        now = dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds")
        with self._writer() as conn:
            row = conn.execute(sa.select(machines).where(machines.c.id == machine)).first()
            if row is not None and row.spec and result.spec and row.spec != result.spec:
                raise InputError(f"{result.source}: a result of machine spec {result.spec!r}, but the history of "
                                 f"{machine} holds results of spec {row.spec!r}; a machine ID names one machine")
            latest = conn.execute(sa.select(sa.func.max(results.c.date)).where(
                results.c.machine_id == machine)).scalar()
            latest = _as_date(latest)
            if latest is not None and date < latest:
                raise InputError(f"{result.source}: date {date.isoformat()} is before the previous calibration of "
                                 f"{machine} ({latest.isoformat()}); results are added in the order they were made")
            dup = conn.execute(sa.select(results.c.date, results.c.kind).where(
                (results.c.machine_id == machine) & (results.c.file_sha256 == result.file_sha256))).first()
            if dup is not None:
                raise InputError(f"{result.source}: already in the history of {machine} (the {dup.kind} of "
                                 f"{_as_date(dup.date).isoformat()}); nothing added")
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
        with self.engine.connect() as conn:
            return [r.id for r in conn.execute(sa.select(machines.c.id).order_by(machines.c.id))]

    def records(self, machine: str, kind: str | None = None, with_documents: bool = False) -> list[Record]:
        """``machine``'s results (of ``kind``), oldest first (date, then the order they were added), with their
        quantities; an unknown machine is an InputError naming the known ones."""
        check_machine_id(machine)
        with self.engine.connect() as conn:
            if conn.execute(sa.select(machines.c.id).where(machines.c.id == machine)).first() is None:
                known = [r.id for r in conn.execute(sa.select(machines.c.id).order_by(machines.c.id))]
                raise InputError(f"no machine {machine!r} in the history {self.shown} (machines: "
                                 f"{', '.join(known) or 'none yet'})")
            cols = [c for c in results.c if with_documents or c.name != "document"]
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
        return [Record(r.id, machine, r.kind, _as_date(r.date), r.added_at, r.spec, r.source, r.file_sha256,
                       r.recording_sha256, r.model_sha256, r.tool_version, r.instrument,
                       json.loads(r.environment or "{}"),
                       json.loads(r.document) if with_documents else None, qs[r.id]) for r in rows]

    def spec_of(self, machine: str) -> str | None:
        with self.engine.connect() as conn:
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


def _revision(conn: sa.Connection) -> str | None:
    """The schema revision Alembic stamped (None: an empty database)."""
    if not sa.inspect(conn).has_table("alembic_version"):
        return None
    return conn.execute(sa.text("SELECT version_num FROM alembic_version")).scalar()


def _as_date(v: Any) -> dt.date | None:
    if v is None or isinstance(v, dt.date):
        return v
    return dt.date.fromisoformat(str(v)[:10])


def _first_line(exc: BaseException) -> str:
    text = str(getattr(exc, "orig", None) or exc).strip().splitlines()
    return text[0] if text else type(exc).__name__


def _engine(url: str, shown: str, create: bool) -> sa.Engine:
    """An engine for ``url``: SQLite with writers serialised (BEGIN IMMEDIATE, 60 s busy timeout) and foreign keys
    on; PostgreSQL through psycopg with a 5 s connect timeout.  Other databases, a missing driver and a missing
    SQLite file (unless ``create``) are InputErrors."""
    from sqlalchemy.pool import NullPool
    try:
        u = sa.engine.make_url(url)
    except sa.exc.ArgumentError:
        raise InputError(f"not a database URL: {shown} (give a SQLite file path or postgresql://...)") from None
    if u.get_backend_name() == "sqlite":
        path = Path(u.database or "")
        if not u.database or u.database == ":memory:":
            raise InputError("the history needs a SQLite file, not an in-memory database")
        if not path.exists() and not create:
            raise InputError(f"no history database at {path} (nothing added yet: `mtcal history add` creates it)")
        if not path.parent.is_dir():
            raise InputError(f"cannot reach the history database {shown}: {path.parent} is not a directory")
        eng = sa.create_engine(url, poolclass=NullPool, connect_args={"timeout": 60})
        sa.event.listen(eng, "connect", _sqlite_connect)
        sa.event.listen(eng, "begin", lambda conn: conn.exec_driver_sql("BEGIN IMMEDIATE"))
        return eng
    if u.get_backend_name() != "postgresql":
        raise InputError(f"history database {shown}: only SQLite (a file) and PostgreSQL (postgresql://...) are "
                         "supported")
    try:
        return sa.create_engine(url, poolclass=NullPool, connect_args={"connect_timeout": 5})
    except ModuleNotFoundError:
        raise InputError(f"history database {shown}: PostgreSQL needs the psycopg driver "
                         "(pip install 'mtcal[postgres]')") from None


def _sqlite_connect(dbapi_conn, record) -> None:
    dbapi_conn.isolation_level = None  # SQLAlchemy's "begin" event issues BEGIN IMMEDIATE itself
    dbapi_conn.execute("PRAGMA foreign_keys = ON")
