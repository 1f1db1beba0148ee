"""The history database as data (issue 54, items 1 and 2): no output replaces it whatever the flag, read commands
never write, every fault of the database is one line naming it and the fault (exit 2), the schema's owner is
mtcal's own marker, concurrent writers stay serialised; what is added is validated against its schema and its
machine, so that the report never fails on a stored result (and a result stored before the checks existed is one
line naming the database, the result and the field)."""
from __future__ import annotations

import datetime as dt
import hashlib
import json
import os
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest
import test_history
from history_data import check_doc, diagnose_doc, iso_doc, model_doc, uncertainty_doc, verify_doc, write
from pg_server import fresh_database
from test_history import KILLED

from mtcal.cli import main
from mtcal.errors import InputError
from mtcal.history import add, show


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def sha(p: Path) -> str | None:
    return hashlib.sha256(p.read_bytes()).hexdigest() if p.exists() else None


def refused(capsys, *argv, untouched: tuple = ()) -> str:
    """Exit 2, one line on stderr, nothing on stdout, the files ``untouched`` byte-identical."""
    before = [sha(p) for p in untouched]
    code, out, err = run(capsys, *argv)
    assert code == 2, (code, out, err)
    assert len(err.strip().splitlines()) == 1 and out == "" and "internal error" not in err, err
    assert [sha(p) for p in untouched] == before
    return err


@pytest.fixture
def hist(tmp_path):
    """Two models of M1 (2024-01-15, 2024-06-15) in a SQLite history."""
    db = tmp_path / "h.db"
    for i, d in enumerate(("2024-01-15", "2024-06-15")):
        add(write(tmp_path / f"m{i}.json", model_doc(noise=1, seed=i)), "M1", dt.date.fromisoformat(d), str(db))
    return db


# ----------------------------------------------------------------------------- no output is the database
@pytest.mark.parametrize("how", ["same", "symlink", "default"])
def test_no_output_replaces_the_database_whatever_the_flag(hist, tmp_path, capsys, monkeypatch, how):
    """Seen failing on main: `trend --plot H.db --force --db H.db` and `report -o H.db --force --db H.db` replaced
    the history with a PNG and an HTML file, exit 0."""
    db = hist
    out, given = str(db), ["--db", str(db)]
    if how == "symlink":
        (tmp_path / "pic.png").symlink_to(db)
        out = str(tmp_path / "pic.png")
    elif how == "default":  # no --db: the database is $MTCAL_HISTORY_DB
        monkeypatch.setenv("MTCAL_HISTORY_DB", str(db))
        given = []
    for argv in (["history", "trend", "M1", "--error", "E_C0Y", "--plot", out, "--force", *given],
                 ["report", "M1", "-o", out, "--force", *given]):
        err = refused(capsys, *argv, untouched=(db,))
        assert f"is the history database {db}" in err, err


def test_no_output_replaces_another_database(hist, tmp_path, capsys):
    """An output onto another database file (another history than --db's), is refused with --force too."""
    other = tmp_path / "other.db"
    add(write(tmp_path / "o.json", model_doc(noise=1, seed=5)), "M2", dt.date(2024, 1, 1), str(other))
    err = refused(capsys, "report", "M1", "-o", str(other), "--force", "--db", str(hist), untouched=(other, hist))
    assert "is a SQLite database: an output never replaces a database" in err and str(other) in err


# ----------------------------------------------------------------------------- read commands never write
def test_read_commands_never_write(hist, tmp_path, capsys):
    """Seen failing on main: `history show` on an empty file wrote the schema into it."""
    empty = tmp_path / "empty.db"
    empty.write_bytes(b"")
    for argv in (["history", "show", "M1"], ["history", "compare", "M1"], ["history", "list"],
                 ["history", "trend", "M1", "--error", "E_C0Y"], ["report", "M1", "-o", str(tmp_path / "r.html")]):
        err = refused(capsys, *argv, "--db", str(empty), untouched=(empty,))
        assert f"history database {empty} is empty" in err, err
    assert empty.stat().st_size == 0 and not (tmp_path / "r.html").exists()
    before = sha(hist)
    for argv in (["history", "show", "M1"], ["history", "compare", "M1"], ["history", "list"]):
        code, out, err = run(capsys, *argv, "--db", str(hist))
        assert code == 0, err
    assert sha(hist) == before


def test_an_empty_url_is_refused(tmp_path, capsys, monkeypatch):
    """Seen failing on main: `--db ''` silently wrote ./mtcal-history.db."""
    monkeypatch.chdir(tmp_path)
    m = write(tmp_path / "m.json", model_doc())
    err = refused(capsys, "history", "add", str(m), "--machine", "M1", "--db", "")
    assert "--db is empty" in err
    monkeypatch.setenv("MTCAL_HISTORY_DB", "")
    err = refused(capsys, "history", "add", str(m), "--machine", "M1")
    assert "MTCAL_HISTORY_DB is empty" in err
    assert list(tmp_path.iterdir()) == [m]


# ----------------------------------------------------------------------------- faults: one line, exit 2
def test_a_malformed_database(hist, tmp_path, capsys):
    """Seen failing on main: a damaged page gave `report` exit 1 "internal error"."""
    data = bytearray(hist.read_bytes())
    page = int.from_bytes(data[16:18], "big")
    for i in range(page * 2, len(data)):  # every page after the first two (the schema stays readable)
        data[i] = 0xA5
    hist.write_bytes(bytes(data))
    for argv in (["report", "M1", "-o", str(tmp_path / "r.html")], ["history", "show", "M1"],
                 ["history", "compare", "M1"]):
        err = refused(capsys, *argv, "--db", str(hist), untouched=(hist,))
        assert str(hist) in err and "malformed" in err, err
    assert not (tmp_path / "r.html").exists()


@pytest.mark.parametrize("revision", ["0001", "ae1027a6acf"])
def test_another_programs_alembic_database(tmp_path, capsys, revision):
    """Seen failing on main: another program's Alembic database at revision 0001 was taken as mtcal's (then "no
    such table", exit 1), one at an unknown revision as "written by a newer mtcal"."""
    other = tmp_path / "app.db"
    with sqlite3.connect(other) as c:
        c.execute("CREATE TABLE alembic_version (version_num VARCHAR(32) NOT NULL PRIMARY KEY)")
        c.execute("INSERT INTO alembic_version VALUES (?)", (revision,))
        c.execute("CREATE TABLE users (id INTEGER PRIMARY KEY, name TEXT)")
    m = write(tmp_path / "m.json", model_doc())
    for argv in (["history", "add", str(m), "--machine", "M1"], ["history", "show", "M1"]):
        err = refused(capsys, *argv, "--db", str(other), untouched=(other,))
        assert f"the database {other} is not an mtcal history" in err and "users" in err, err
        assert "newer" not in err


@pytest.mark.parametrize("table", ["quantities", "results", "machines"])
def test_a_dropped_table(hist, tmp_path, capsys, table):
    """Seen failing on main: a dropped table gave `compare` exit 1 "internal error"."""
    with sqlite3.connect(hist) as c:
        c.execute("PRAGMA foreign_keys = OFF")
        c.execute(f"DROP TABLE {table}")
    m = write(tmp_path / "new.json", model_doc(noise=1, seed=9))
    for argv in (["history", "compare", "M1"], ["history", "show", "M1"], ["history", "add", str(m), "--machine",
                                                                          "M1"]):
        err = refused(capsys, *argv, "--db", str(hist), untouched=(hist,))
        assert str(hist) in err and f"table '{table}' is missing" in err, err


def test_a_read_only_database_on_add(hist, tmp_path, capsys):
    """Seen failing on main (as a user without write permission: exit 1 "internal error"; as root the file was
    written through its read-only mode)."""
    m = write(tmp_path / "new.json", model_doc(noise=1, seed=9))
    os.chmod(hist, 0o444)
    try:
        err = refused(capsys, "history", "add", str(m), "--machine", "M1", "--db", str(hist), untouched=(hist,))
        assert str(hist) in err and "read-only" in err, err
        code, out, err = run(capsys, "history", "show", "M1", "--db", str(hist))  # reading it is fine
        assert code == 0 and len(out.splitlines()) == 2, err
    finally:
        os.chmod(hist, 0o644)


def test_a_database_that_is_a_folder(tmp_path, capsys):
    m = write(tmp_path / "m.json", model_doc())
    (tmp_path / "d.db").mkdir()
    err = refused(capsys, "history", "add", str(m), "--machine", "M1", "--db", str(tmp_path / "d.db"))
    assert str(tmp_path / "d.db") in err and "is a folder" in err


# ----------------------------------------------------------------------------- what is added is validated
def test_an_unknown_spec_or_markup_as_the_machine_is_refused(hist, tmp_path, capsys):
    """Seen failing on main: a diagnosis naming the spec 'dmu60' (or markup) was stored and became the machine's
    spec; the machine's real dmu50 models were refused afterwards."""
    for spec in ("dmu60", "<b>dmu50</b>"):
        f = write(tmp_path / "d.json", dict(diagnose_doc(), machine=spec))
        err = refused(capsys, "history", "add", str(f), "--machine", "M9", "--db", str(hist), untouched=(hist,))
        assert f"unknown machine spec {spec!r}" in err and "dmu50" in err, err
    with sqlite3.connect(hist) as c:
        assert c.execute("SELECT COUNT(*) FROM machines WHERE id = 'M9'").fetchone() == (0,)


def test_a_spec_change_is_refused(hist, tmp_path, capsys):
    """A diagnosis of another known spec than the machine's models: refused naming both (a machine ID names one
    machine; a retrofitted machine gets a new ID)."""
    f = write(tmp_path / "d.json", dict(diagnose_doc(), machine="headbc"))
    err = refused(capsys, "history", "add", str(f), "--machine", "M1", "--db", str(hist), untouched=(hist,))
    assert "spec 'headbc'" in err and "spec 'dmu50'" in err


@pytest.mark.parametrize("day", ["0001-01-01", "1969-12-31"])
def test_dates_before_1970_are_refused(hist, tmp_path, capsys, day):
    """Seen failing on main: --date 0001-01-01 was accepted, then `trend --plot` failed inside matplotlib."""
    f = write(tmp_path / "m.json", model_doc(noise=1, seed=9))
    err = refused(capsys, "history", "add", str(f), "--machine", "M7", "--date", day, "--db", str(hist),
                  untouched=(hist,))
    assert f"date {day} is before 1970-01-01" in err


def test_a_temperature_that_is_not_a_number(tmp_path, capsys):
    """Seen failing on main: temperature_c "n/a" in the recording gave ValueError (exit 1).  The readings that are
    numbers are kept with the count of those that are not, and a warning names the file, line and value."""
    (tmp_path / "rec.csv").write_text("axis,round,position,point,x,y,z,temperature_c\nX,1,0,P,0,0,0,20.5\n"
                                      "X,1,0,Q,0,0,0,n/a\nX,1,0,R,0,0,0,21.5\n")
    m = write(tmp_path / "m.json", model_doc())
    code, out, err = run(capsys, "history", "add", str(m), "--machine", "M1", "--db", str(tmp_path / "h.db"),
                         "--json")
    assert code == 0, err
    assert "rec.csv:3: temperature_c 'n/a' is not a number" in err
    assert json.loads(out)["environment"]["temperature_c"] == {"mean": 21.0, "min": 20.5, "max": 21.5,
                                                               "readings": 2, "not_numbers": 1}


def _iso_without_targets():
    d = iso_doc()
    del d["axes"]["X"]["targets"]
    return d


def _iso_short_targets():
    d = iso_doc()
    d["axes"]["X"]["targets"]["mean_up"] = [1.0]
    return d


def _law_as_text():
    d = model_doc()
    d["noise_law"]["radial_um"] = "0.4"
    return d


BAD = [(_iso_without_targets, "axes.X.targets", "missing"),
       (_iso_short_targets, "axes.X.targets.mean_up", "1 values for 2 positions"),
       (lambda: dict(check_doc(), worst_z="large"), "worst_z", "not a number"),
       (lambda: dict(check_doc(), kind="laser"), "kind", "'laser'"),
       (_law_as_text, "noise_law.radial_um", "not a number"),
       (lambda: dict(verify_doc(), errors=[{"name": "E_XX"}]), "errors[0].text", "missing"),
       (lambda: dict(diagnose_doc(), base_sigma_ratio="1.4"), "base_sigma_ratio", "not a number"),
       (lambda: dict(uncertainty_doc(), volumetric={"u95_max_mm": [1]}), "volumetric.u95_max_mm", "not a number"),
       (lambda: dict(diagnose_doc(), effects=[dict(diagnose_doc()["effects"][0], interval_95=[0.005])]),
        "effects[0].interval_95", "1 values, not two")]


@pytest.mark.parametrize("make,field,words", BAD, ids=[b[1] for b in BAD])
def test_every_field_the_report_reads_is_checked_when_added(hist, tmp_path, capsys, make, field, words):
    """Seen failing on main: these were stored, then `report` failed with KeyError/TypeError (exit 1)."""
    f = write(tmp_path / "r.json", make())
    err = refused(capsys, "history", "add", str(f), "--machine", "M1", "--db", str(hist), untouched=(hist,))
    assert "r.json" in err and f"field '{field}'" in err and words in err, err
    err = refused(capsys, "report", str(f), "-o", str(tmp_path / "r.html"))
    assert "r.json" in err and f"field '{field}'" in err, err


def test_a_check_whose_worst_z_is_null_is_reported(hist, tmp_path, capsys):
    """Seen failing on main: mtcal writes a NaN worst_z as null; the report failed on it (TypeError, exit 1)."""
    f = write(tmp_path / "c.json", dict(check_doc(), worst_z=None, prediction_u95_mm=None))
    code, out, err = run(capsys, "history", "add", str(f), "--machine", "M1", "--db", str(hist))
    assert code == 0, err
    code, out, err = run(capsys, "report", "M1", "-o", str(tmp_path / "r.html"), "--db", str(hist))
    assert code == 0, err
    assert "circular test" in (tmp_path / "r.html").read_text()


@pytest.mark.parametrize("make,field,words", BAD[:5], ids=[b[1] for b in BAD[:5]])
def test_a_result_stored_before_the_checks_is_one_line(hist, tmp_path, capsys, make, field, words):
    """A database written before validation existed: the stored result the report cannot read is named (the
    database, the result, the field), exit 2, never a traceback."""
    good = {"iso230-2": iso_doc, "check": check_doc, "model": model_doc}
    doc = make()
    kind = "iso230-2" if "axes" in doc else "check" if "worst_z" in doc else "model"
    add(write(tmp_path / "g.json", good[kind]() if kind != "model" else model_doc(noise=1, seed=7)), "M1",
        dt.date(2024, 7, 1), str(hist))
    with sqlite3.connect(hist) as c:
        rid = c.execute("SELECT MAX(id) FROM results").fetchone()[0]
        c.execute("UPDATE results SET document = ? WHERE id = ?", (json.dumps(doc), rid))
    err = refused(capsys, "report", "M1", "-o", str(tmp_path / "r.html"), "--db", str(hist), untouched=(hist,))
    assert str(hist) in err and f"the {kind} #{rid} of 2024-07-01 (g.json)" in err and f"field '{field}'" in err
    assert not (tmp_path / "r.html").exists()


# ----------------------------------------------------------------------------- history list
def test_history_list(hist, tmp_path, capsys):
    add(write(tmp_path / "c.json", check_doc()), "ZZ-2", dt.date(2024, 3, 1), str(hist))
    code, out, err = run(capsys, "history", "list", "--db", str(hist))
    assert code == 0, err
    assert out.splitlines() == ["M1    dmu50  2 results  2024-01-15 .. 2024-06-15  (model 2)",
                                "ZZ-2  -      1 result   2024-03-01 .. 2024-03-01  (check 1)"]
    code, out, err = run(capsys, "history", "list", "--db", str(hist), "--json")
    js = json.loads(out)
    assert js["machines"][0] == {"machine": "M1", "spec": "dmu50", "results": 2, "first": "2024-01-15",
                                 "last": "2024-06-15", "kinds": {"model": 2}}


# ----------------------------------------------------------------------------- concurrent writers
SAME = """
import pathlib, sys, time, datetime as dt
from mtcal.errors import InputError
from mtcal.history import add
db, sync, who, f = sys.argv[1:]
pathlib.Path(sync, who).touch()
t0 = time.time()
while len(list(pathlib.Path(sync).iterdir())) < 2 and time.time() - t0 < 300:
    time.sleep(0.001)
try:
    add(f, "M1", dt.date(2024, 1, 1), db)
    print("added")
except InputError as exc:
    print("refused:", exc)
"""


@pytest.mark.slow
@pytest.mark.parametrize("n", range(3))
def test_two_processes_adding_the_same_file_at_once_land_once(tmp_path, n):
    """Serialised writers: the duplicate check and the insert are one transaction, so of two processes adding the
    same file at the same moment exactly one lands and the other is refused."""
    db, sync = tmp_path / "h.db", tmp_path / "sync"
    sync.mkdir()
    f = write(tmp_path / "m.json", model_doc())
    add(write(tmp_path / "c.json", check_doc()), "M1", dt.date(2023, 1, 1), str(db))  # the schema exists
    procs = [subprocess.Popen([sys.executable, "-c", SAME, str(db), str(sync), w, str(f)], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for w in "AB"]
    outs = [p.communicate(timeout=300) for p in procs]
    assert all(p.returncode == 0 for p in procs), outs
    said = sorted(o.split(":")[0].strip() for o, _ in outs)
    assert said == ["added", "refused"], outs
    assert len(show("M1", str(db))) == 2


# ----------------------------------------------------------------------------- PostgreSQL
pg = test_history.pg  # the private server's fixture (tests/pg_server.py)


def _pg_tables(url: str) -> list[str]:
    import sqlalchemy as sa

    from mtcal.history.store import database_url
    eng = sa.create_engine(database_url(url))
    with eng.connect() as c:
        names = sorted(sa.inspect(c).get_table_names())
    eng.dispose()
    return names


def _pg_exec(url: str, sql: str) -> None:
    import sqlalchemy as sa

    from mtcal.history.store import database_url
    eng = sa.create_engine(database_url(url))
    with eng.begin() as c:
        c.exec_driver_sql(sql)
    eng.dispose()


def test_postgresql_faults(pg, tmp_path, capsys):
    """On a real server: a read command on an empty database writes nothing; another program's Alembic database
    and a dropped table are one line; a database that does not exist and a server that is not there too."""
    url = fresh_database(pg, "mtcal_faults")
    err = refused(capsys, "history", "show", "M1", "--db", url)
    assert "is empty" in err and _pg_tables(url) == []
    _pg_exec(url, "CREATE TABLE alembic_version (version_num VARCHAR(32) PRIMARY KEY); "
                  "INSERT INTO alembic_version VALUES ('0001'); CREATE TABLE users (id INTEGER)")
    m = write(tmp_path / "m.json", model_doc())
    err = refused(capsys, "history", "add", str(m), "--machine", "M1", "--db", url)
    assert "is not an mtcal history" in err and "users" in err
    assert _pg_tables(url) == ["alembic_version", "users"]
    url = fresh_database(pg, "mtcal_dropped")
    add(m, "M1", dt.date(2024, 1, 1), url)
    _pg_exec(url, "DROP TABLE quantities")
    err = refused(capsys, "history", "compare", "M1", "--db", url)
    assert "table 'quantities' is missing" in err
    base, _, query = pg.partition("?")
    err = refused(capsys, "history", "show", "M1", "--db", base.rsplit("/", 1)[0] + "/no_such_db?" + query)
    assert "cannot reach the history database" in err and "no_such_db" in err
    err = refused(capsys, "history", "show", "M1", "--db", "postgresql://postgres@/x?host=/nonexistent/socket")
    assert "cannot reach the history database" in err


def test_postgresql_read_commands_are_read_only(pg, tmp_path):
    url = fresh_database(pg, "mtcal_ro")
    add(write(tmp_path / "m.json", model_doc()), "M1", dt.date(2024, 1, 1), url)
    from mtcal.history.store import Store
    with Store(url) as s:
        import sqlalchemy as sa
        with s.engine.connect() as c:
            with pytest.raises(sa.exc.DBAPIError, match="read-only transaction"):
                c.exec_driver_sql("DELETE FROM quantities")
    assert len(show("M1", url)[0].quantities) == 12


def test_library_store_refuses_an_empty_url():
    from mtcal.history.store import Store
    with pytest.raises(InputError, match="empty"):
        Store("")


@pytest.mark.parametrize("which", ["circular", "rtest"])
def test_what_mtcal_check_writes_passes_the_checks_and_reports(tmp_path, capsys, which):
    """The schema refuses nothing mtcal writes: a real evaluation of each check kind (its to_dict through mtcal's
    JSON, NaN as null) is added and reported."""
    import numpy as np

    import mtcal
    from mtcal.check import CircleSetup, RTestSetup, evaluate_check, simulate_circular, simulate_rtest
    from mtcal.data import path
    from mtcal.io import dumps
    truth = mtcal.load_model(path("demo_truth.json"))
    if which == "circular":
        meas = simulate_circular(truth, CircleSetup("XY", 150.0, (0.0, 0.0, 0.0)), seed=1)
    else:
        meas = simulate_rtest(truth, RTestSetup("C", tuple(np.arange(0.0, 360.0, 30.0)), (120.0, 40.0, 30.0)))
    f = tmp_path / "c.json"
    f.write_text(dumps(evaluate_check(meas, truth).to_dict()))
    db = str(tmp_path / "h.db")
    code, out, err = run(capsys, "history", "add", str(f), "--machine", "M1", "--date", "2024-01-01", "--db", db)
    assert code == 0, err
    code, out, err = run(capsys, "report", "M1", "-o", str(tmp_path / "r.html"), "--db", db)
    assert code == 0, err


def test_postgresql_a_role_that_may_only_read(pg, tmp_path, capsys):
    """docs/guide/history.md: a role granted SELECT only runs the read commands; its add is one line."""
    url = fresh_database(pg, "mtcal_reader")
    add(write(tmp_path / "m.json", model_doc()), "M1", dt.date(2024, 1, 1), url)
    _pg_exec(url, "DROP ROLE IF EXISTS reader; CREATE ROLE reader LOGIN; "
                  "GRANT SELECT ON ALL TABLES IN SCHEMA public TO reader")
    base, _, query = url.partition("?")
    reader = base.replace("postgres@", "reader@", 1) + "?" + query
    code, out, err = run(capsys, "history", "list", "--db", reader)
    assert code == 0 and out.startswith("M1"), err
    err = refused(capsys, "history", "add", str(write(tmp_path / "n.json", model_doc(noise=1, seed=3))),
                  "--machine", "M1", "--db", reader)
    assert "is read-only (permission denied for table" in err, err
    assert len(show("M1", url)) == 1


@pytest.mark.parametrize("column,value,words", [("kind", "spreadsheet", "not a kind of result"),
                                                ("date", "yesterday", "yesterday"),
                                                ("document", "{not json", "Expecting property name")])
def test_a_stored_row_changed_by_hand_is_one_line(hist, tmp_path, capsys, column, value, words):
    with sqlite3.connect(hist) as c:
        c.execute(f"UPDATE results SET {column} = ? WHERE id = 2", (value,))
    err = refused(capsys, "report", "M1", "-o", str(tmp_path / "r.html"), "--db", str(hist), untouched=(hist,))
    assert str(hist) in err and "#2 of" in err and words in err, err



@pytest.mark.skipif(sys.platform == "win32", reason="SIGKILL")
def test_a_read_after_a_killed_write_sees_the_history_as_before(hist, tmp_path, capsys):
    """A writer killed inside its transaction leaves its journal beside the file: the next read command, read-only,
    reads the history as it was (a hot journal, of pages already spilled into the file: the next test)."""
    import signal
    new = write(tmp_path / "new.json", model_doc(noise=1, seed=9))
    p = subprocess.Popen([sys.executable, "-c", KILLED, str(hist), str(new)], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "inside"
    p.send_signal(signal.SIGKILL)
    p.wait(timeout=60)
    assert Path(f"{hist}-journal").exists()
    code, out, err = run(capsys, "history", "show", "M1", "--db", str(hist))
    assert code == 0 and len(out.splitlines()) == 2, err


SPILLED = """
import sqlite3, sys, time
c = sqlite3.connect(sys.argv[1], isolation_level=None)
c.execute("PRAGMA cache_size = 2")  # a small page cache: the transaction's pages spill into the file
c.execute("BEGIN IMMEDIATE")
for i in range(50):
    c.execute("INSERT INTO quantities (result_id, name, value, unit) VALUES (1, ?, 0, 'mm')", ("E" * 20000,))
print("inside", flush=True)
time.sleep(600)
"""


@pytest.mark.skipif(sys.platform == "win32", reason="SIGKILL")
def test_a_read_after_a_killed_write_that_spilled_into_the_file(hist, capsys):
    """A writer killed after its pages spilled into the file leaves a hot journal, which a read-only connection
    cannot roll back (SQLITE_READONLY_ROLLBACK): the read command lets SQLite roll it back first, and the file is
    byte for byte what it was before the transaction."""
    import signal
    before = sha(hist)
    p = subprocess.Popen([sys.executable, "-c", SPILLED, str(hist)], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "inside"
    p.send_signal(signal.SIGKILL)
    p.wait(timeout=60)
    assert sha(hist) != before and Path(f"{hist}-journal").stat().st_size > 0  # a hot journal
    code, out, err = run(capsys, "history", "show", "M1", "--db", str(hist))
    assert code == 0 and len(out.splitlines()) == 2, err
    assert sha(hist) == before


def test_a_name_longer_than_the_history_keeps(hist, tmp_path, capsys):
    """A check figure named with 40 characters: PostgreSQL refuses it (a DataError, exit 1 on main), SQLite kept it;
    both refuse it in one line before anything is written."""
    name = "G_" + "x" * 38
    f = write(tmp_path / "c.json", dict(check_doc(), measured={name: 0.004}, predicted={name: 0.004}))
    err = refused(capsys, "history", "add", str(f), "--machine", "M1", "--db", str(hist), untouched=(hist,))
    assert "c.json" in err and "has 40 characters; the history keeps at most 32" in err, err
