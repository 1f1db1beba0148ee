"""mtcal history (issue 38): the store (SQLite always, PostgreSQL where it starts: tests/pg_server.py), the
kinds of result files, the comparison against the uncertainty (Holm), the refusals of bad input (exit 2, one line,
nothing written) and two processes adding at once."""
from __future__ import annotations

import datetime as dt
import json
import math
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest
from history_data import check_doc, diagnose_doc, iso_doc, model_doc, uncertainty_doc, verify_doc, write
from pg_server import fresh_database, private_server
from scipy import stats

from mtcal.cli import main
from mtcal.errors import InputError
from mtcal.history import add, compare_history, read_result, show, trend_of
from mtcal.history.compare import _holm, _welch


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def _db_state(db: Path) -> tuple:
    """(rows of results, rows of quantities) of a SQLite history, or None when the file does not exist."""
    if not db.exists():
        return None
    with sqlite3.connect(db) as c:
        return tuple(c.execute(f"SELECT COUNT(*) FROM {t}").fetchone()[0] for t in ("results", "quantities"))


@pytest.fixture
def hist(tmp_path):
    """Three calibrations of M1: an unchanged repeat, then E_C0Y +60 urad (12 x its sigma 5 urad) and E_XX
    +10 um at X = 200 (x20 the sigma 0.5 um)."""
    db = tmp_path / "h.db"
    files = [write(tmp_path / "m1.json", model_doc(noise=1, seed=1)),
             write(tmp_path / "m2.json", model_doc(noise=1, seed=2)),
             write(tmp_path / "m3.json", model_doc({"E_C0Y": 6e-5, "E_XX": (4, 0.010)}, noise=1, seed=3))]
    for f, d in zip(files, ("2024-01-15", "2024-06-15", "2024-11-20")):
        add(f, "M1", dt.date.fromisoformat(d), str(db))
    return db, files


def test_add_show_keeps_kind_hashes_and_quantities(tmp_path, capsys):
    (tmp_path / "rec.csv").write_text("axis,round,position,point,x,y,z,temperature_c\nX,1,0,P,0,0,0,20.5\n"
                                      "X,1,0,Q,0,0,0,21.5\n")
    m = write(tmp_path / "m.json", model_doc())
    db = tmp_path / "h.db"
    code, out, err = run(capsys, "history", "add", str(m), "--machine", "DMU50-7", "--date", "2024-03-01",
                         "--db", str(db), "--json")
    assert code == 0, err
    r = json.loads(out)
    assert r["kind"] == "model" and r["spec"] == "dmu50" and r["date"] == "2024-03-01"
    assert r["quantities"] == 2 * 5 + 2  # two functions on five positions, two constants
    import hashlib
    assert r["file_sha256"] == hashlib.sha256(m.read_bytes()).hexdigest() == r["model_sha256"]
    assert r["recording_sha256"] == hashlib.sha256((tmp_path / "rec.csv").read_bytes()).hexdigest()
    assert r["environment"]["temperature_c"] == {"mean": 21.0, "min": 20.5, "max": 21.5}
    assert r["instrument"] == "laser tracker (AT960)"
    recs = show("DMU50-7", str(db))
    qx = {(q.name, q.position): q for q in recs[0].quantities}
    assert qx[("E_XX", 200.0)].value == pytest.approx(0.004) and qx[("E_XX", 200.0)].dof == 3
    assert qx[("E_C0Y", None)].u95 == pytest.approx(1.959964 * 5e-6, rel=1e-6) and qx[("E_C0Y", None)].dof is None


@pytest.mark.parametrize("doc,kind", [(uncertainty_doc(), "uncertainty"), (iso_doc(), "iso230-2"),
                                      (check_doc(), "check"), (verify_doc(), "verify"), (diagnose_doc(), "diagnose")])
def test_the_kind_is_read_from_the_file(tmp_path, doc, kind):
    r = read_result(write(tmp_path / "r.json", doc))
    assert r.kind == kind
    if kind == "uncertainty":  # the 95 % half-width of the Monte Carlo interval
        q = {(q.name, q.position): q for q in r.quantities}
        assert q[("E_XX", 100.0)].u95 == pytest.approx(0.0002) and q[("tool_tip_u95_max", None)].value == 0.0031
    if kind == "iso230-2":
        assert {(q.axis, q.name): q.value for q in r.quantities}[("X", "A")] == 3.5


def test_holm_and_welch_by_hand():
    # Holm at 0.05 over p = 0.001, 0.02, 0.04: thresholds 0.05/3, 0.05/2, 0.05 -> all three (Bonferroni: one)
    assert _holm([0.04, 0.001, 0.02], 0.05) == [True, True, True]
    assert _holm([0.04, 0.001, 0.03], 0.05) == [False, True, False]  # 0.03 > 0.025 stops the procedure
    # Welch-Satterthwaite: two sigmas 1 with 3 dof each -> (1+1)^2 / (1/3 + 1/3) = 6
    assert _welch(1.0, 3.0, 1.0, 3.0) == pytest.approx(6.0)
    assert math.isinf(_welch(1.0, None, 2.0, None))


def test_compare_names_what_changed_with_its_interval(hist, capsys):
    db, _ = hist
    code, out, err = run(capsys, "history", "compare", "M1", "--db", str(db), "--json")
    assert code == 0, err
    c = json.loads(out)
    assert c["machine"] == "M1" and c["level"] == 0.01
    first, second = c["steps"]
    assert (first["from"], first["to"], first["changed"]) == ("2024-01-15", "2024-06-15", [])
    assert first["unchanged"] == 4
    named = {ch["name"]: ch for ch in second["changed"]}
    assert set(named) == {"E_C0Y", "E_XX"} and second["unchanged"] == 2
    sq = named["E_C0Y"]
    # U95 of the difference of two joint-fit values of sigma 5 urad: 1.96 * sqrt(2) * 5 = 13.86 urad
    assert sq["u95"] == pytest.approx(1.959964 * math.sqrt(2) * 5, rel=1e-6) and sq["unit"] == "µrad"
    assert 40 < sq["change"] < 80
    assert "squareness of Y to X" in sq["text"] and "between 2024-06-15 and 2024-11-20" in sq["text"]
    xx = named["E_XX"]  # three-point rounds: Welch dof 6, t_0.975(6) * sqrt(2) * 0.5 um
    assert xx["u95"] == pytest.approx(stats.t.ppf(0.975, 6) * math.sqrt(2) * 0.5, rel=1e-6) and xx["unit"] == "µm"
    assert xx["position"] == 200.0 and "positioning error of X" in xx["text"]
    code, out, _ = run(capsys, "history", "compare", "M1", "--from", "2024-01-15", "--to", "2024-11-20",
                       "--db", str(db), "--json")
    assert [s["from"] for s in json.loads(out)["steps"]] == ["2024-01-15"]


def test_trend_in_order_with_intervals(hist, tmp_path, capsys):
    db, _ = hist
    t = trend_of("M1", "E_C0Y", db=str(db))
    assert [p["date"] for p in t.points] == ["2024-01-15", "2024-06-15", "2024-11-20"]
    assert t.points[2]["value"] - t.points[1]["value"] > 40 and t.unit == "µrad"
    code, out, err = run(capsys, "history", "trend", "M1", "--error", "E_XX", "--plot", str(tmp_path / "t.png"),
                         "--db", str(db), "--json")
    assert code == 0, err
    assert json.loads(out)["position"] == 200.0  # where the latest value is largest
    assert (tmp_path / "t.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# ----------------------------------------------------------------------------- bad input: one line, exit 2
def _refused(capsys, db: Path, *argv) -> str:
    before = _db_state(db)
    code, out, err = run(capsys, *argv)
    assert code == 2, (out, err)
    assert len(err.strip().splitlines()) == 1 and out == ""
    assert _db_state(db) == before  # nothing written
    return err


def test_not_an_mtcal_result(hist, tmp_path, capsys):
    db, _ = hist
    f = write(tmp_path / "other.json", {"name": "a spreadsheet export", "rows": [1, 2]})
    err = _refused(capsys, db, "history", "add", str(f), "--machine", "M1", "--db", str(db))
    assert "other.json: not an mtcal result" in err


@pytest.mark.parametrize("mid,why", [("M1/2", "'/'"), ("../etc", "'/'"), ("a..b", "'..'"), ("M 1", "' '"),
                                     ("Mé", "'é'"), ("_M", "first character"), ("M?x=1", "'?'"), ("", "empty"),
                                     ("M" * 65, "more than 64")])
def test_machine_ids_a_filesystem_or_url_would_mangle(hist, mid, why, capsys):
    db, files = hist
    err = _refused(capsys, db, "history", "add", str(files[0]), "--machine", mid, "--db", str(db))
    assert "machine ID" in err and why in err


def test_unreachable_database(tmp_path, capsys):
    m = write(tmp_path / "m.json", model_doc())
    err = _refused(capsys, tmp_path / "none.db", "history", "add", str(m), "--machine", "M1", "--db",
                   "postgresql://nobody@127.0.0.1:9/nothing")
    assert "cannot reach the history database postgresql+psycopg://nobody@127.0.0.1:9/nothing" in err
    err = _refused(capsys, tmp_path / "none.db", "history", "show", "M1", "--db", str(tmp_path / "none.db"))
    assert "no history database at" in err
    err = _refused(capsys, tmp_path / "x.db", "history", "add", str(m), "--machine", "M1", "--db",
                   str(tmp_path / "missing" / "h.db"))
    assert "is not a directory" in err


def test_another_programs_database_or_a_file_that_is_none_is_refused_untouched(tmp_path, capsys):
    """--db naming another program's SQLite file (tables, no mtcal revision) or a file that is no database: one
    line, exit 2, the file's bytes unchanged (mtcal never adds its tables to a database it did not make)."""
    m = write(tmp_path / "m.json", model_doc())
    other = tmp_path / "inventory.db"
    with sqlite3.connect(other) as c:
        c.execute("CREATE TABLE parts (id INTEGER, name TEXT)")
        c.execute("INSERT INTO parts VALUES (1, 'spindle')")
    text = tmp_path / "notes.db"
    text.write_text("the machine builder's notes\n")
    for db, words in ((other, "is not an mtcal history (it holds the tables parts"),
                      (text, "cannot be read as a database")):
        before = db.read_bytes()
        code, out, err = run(capsys, "history", "add", str(m), "--machine", "M1", "--db", str(db))
        assert code == 2 and words in err and len(err.strip().splitlines()) == 1, err
        assert db.read_bytes() == before


def test_the_store_knows_its_revisions_and_migrates_an_empty_database(tmp_path):
    from alembic.config import Config
    from alembic.script import ScriptDirectory

    from mtcal.history import store
    cfg = Config()
    cfg.set_main_option("script_location", str(store.MIGRATIONS))
    script = ScriptDirectory.from_config(cfg)
    assert store.HEAD == script.get_current_head()
    assert list(store.REVISIONS) == [r.revision for r in reversed(list(script.walk_revisions()))]
    assert store.OWNER == script.get_revision("0002").module.OWNER
    sqlite3.connect(tmp_path / "empty.db").close()  # an existing, empty file: migrated to HEAD when opened to write
    with store.Store(str(tmp_path / "empty.db"), write=True) as s:
        assert s.revision == store.HEAD
    with sqlite3.connect(tmp_path / "empty.db") as c:
        assert c.execute("SELECT version_num FROM alembic_version").fetchone() == (store.HEAD,)
        assert c.execute("SELECT owner FROM mtcal_owner").fetchall() == [(store.OWNER,)]
        assert {r[0] for r in c.execute("SELECT name FROM sqlite_master WHERE type = 'table'")} >= {
            "machines", "results", "quantities"}


def test_a_history_of_the_first_revision_is_read_and_upgraded(hist, capsys):
    """A history written before the owner's marker (revision 0001, its tables): read as it is, upgraded by add."""
    db, files = hist
    with sqlite3.connect(db) as c:
        c.execute("DROP TABLE mtcal_owner")
        c.execute("UPDATE alembic_version SET version_num = '0001'")
    before = db.read_bytes()
    assert len(show("M1", str(db))) == 3 and db.read_bytes() == before
    add(write(files[0].parent / "new.json", model_doc(noise=1, seed=9)), "M1", None, str(db))
    with sqlite3.connect(db) as c:
        assert c.execute("SELECT version_num FROM alembic_version").fetchone() == ("0002",)
        assert c.execute("SELECT COUNT(*) FROM mtcal_owner").fetchone() == (1,)


def test_a_newer_schema_is_refused(hist, capsys):
    db, files = hist
    with sqlite3.connect(db) as c:
        c.execute("UPDATE alembic_version SET version_num = '0099_from_the_future'")
    err = _refused(capsys, db, "history", "show", "M1", "--db", str(db))
    from mtcal.history.store import HEAD
    assert f"schema revision '0099_from_the_future', newer than this mtcal knows (its newest is '{HEAD}')" in err
    m = write(files[0].parent / "new.json", model_doc(noise=1, seed=9))
    _refused(capsys, db, "history", "add", str(m), "--machine", "M1", "--db", str(db))


def test_dates_in_the_future_or_before_the_previous_calibration(hist, capsys):
    db, files = hist
    m = write(files[0].parent / "new.json", model_doc(noise=1, seed=9))
    tomorrow = (dt.date.today() + dt.timedelta(days=1)).isoformat()
    err = _refused(capsys, db, "history", "add", str(m), "--machine", "M1", "--date", tomorrow, "--db", str(db))
    assert f"date {tomorrow} is in the future" in err
    err = _refused(capsys, db, "history", "add", str(m), "--machine", "M1", "--date", "2024-07-01", "--db", str(db))
    assert "before the previous calibration of M1 (2024-11-20)" in err
    err = _refused(capsys, db, "history", "add", str(m), "--machine", "M1", "--date", "2024-13-01", "--db", str(db))
    assert "expected a date YYYY-MM-DD" in err


def test_another_spec_and_a_repeated_file_are_refused(hist, capsys):
    db, files = hist
    from mtcal.kinematics.machine import available_machines
    other = next(m for m in available_machines() if m != "dmu50")
    doc = model_doc(machine=other)
    doc["functions"] = {}  # names of the DMU 50's X axis may not exist on the other spec
    doc["constants"] = {}
    m = write(files[0].parent / "other.json", doc)
    err = _refused(capsys, db, "history", "add", str(m), "--machine", "M1", "--db", str(db))
    assert f"spec '{other}'" in err and "spec 'dmu50'" in err
    err = _refused(capsys, db, "history", "add", str(files[2]), "--machine", "M1", "--db", str(db))
    assert "already in the history of M1" in err


def test_a_failed_write_leaves_nothing(hist, monkeypatch):
    db, files = hist
    from mtcal.history import store
    before = _db_state(db)
    real = store.quantities.insert

    def broken():
        raise RuntimeError("killed between the result row and its quantities")
    monkeypatch.setattr(store.quantities, "insert", broken)
    with pytest.raises(RuntimeError):
        add(write(files[0].parent / "new.json", model_doc(noise=1, seed=9)), "M1", None, str(db))
    monkeypatch.setattr(store.quantities, "insert", real)
    assert _db_state(db) == before


KILLED = """
import datetime as dt, sys, time
from mtcal.history import add, store
def stall():  # the result row is written, its quantities not yet: say so and wait for the kill
    print("inside", flush=True)
    time.sleep(600)
store.quantities.insert = stall
add(sys.argv[2], "M1", dt.date(2024, 11, 25), sys.argv[1])
"""


@pytest.mark.skipif(sys.platform == "win32", reason="SIGKILL")
def test_a_killed_write_leaves_nothing(hist):
    """A process killed (SIGKILL) inside its transaction, after the result row and before its quantities: the
    history is as before, and the next add lands."""
    import signal
    db, files = hist
    before = _db_state(db)
    new = write(files[0].parent / "new.json", model_doc(noise=1, seed=9))
    p = subprocess.Popen([sys.executable, "-c", KILLED, str(db), str(new)], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "inside"
    p.send_signal(signal.SIGKILL)
    p.wait(timeout=60)
    assert _db_state(db) == before
    add(new, "M1", dt.date(2024, 11, 25), str(db))
    assert _db_state(db)[0] == before[0] + 1


ADDER = """
import datetime as dt, pathlib, sys, time
from mtcal.history import add
from mtcal.history.store import Store
db, sync, who, *files = sys.argv[1:]
pathlib.Path(sync, who).touch()  # imported and ready
t0 = time.time()
while len(list(pathlib.Path(sync).iterdir())) < 2 and time.time() - t0 < 300:
    time.sleep(0.001)
for i, f in enumerate(files):
    add(f, "M" + who, dt.date(2024, 1, 1 + i), db)
"""


def _two_processes_add(tmp_path: Path, db: str, n: int = 5) -> None:
    """Two processes each add n results (machines MA and MB), starting together once both have imported mtcal."""
    procs = []
    sync = tmp_path / "sync"
    sync.mkdir()
    for who in ("A", "B"):
        fs = [str(write(tmp_path / f"r_{who}_{i}.json", model_doc(noise=1, seed=100 * ord(who) + i)))
              for i in range(n)]
        procs.append(subprocess.Popen([sys.executable, "-c", ADDER, db, str(sync), who, *fs], stderr=subprocess.PIPE,
                                      text=True))
    for p in procs:
        _, err = p.communicate(timeout=300)
        assert p.returncode == 0, err


@pytest.mark.slow
def test_two_processes_adding_at_once_both_land_sqlite(tmp_path):
    db = tmp_path / "h.db"
    _two_processes_add(tmp_path, str(db))
    assert [len(show(m, str(db))) for m in ("MA", "MB")] == [5, 5]
    assert _db_state(db) == (10, 10 * 12)


# ----------------------------------------------------------------------------- PostgreSQL (Debian's package)
@pytest.fixture(scope="module")
def pg():
    with private_server() as (url, why):
        if url is None:
            pytest.skip(f"PostgreSQL cannot start here: {why}")
        yield url


def test_postgresql_gives_the_same_answers_as_sqlite(pg, hist):
    db, files = hist
    url = fresh_database(pg, "mtcal_same")
    for f, d in zip(files, ("2024-01-15", "2024-06-15", "2024-11-20")):
        add(f, "M1", dt.date.fromisoformat(d), url)
    assert compare_history("M1", db=url).to_dict() == compare_history("M1", db=str(db)).to_dict()
    assert trend_of("M1", "E_XX", db=url).to_dict() == trend_of("M1", "E_XX", db=str(db)).to_dict()
    with pytest.raises(InputError, match="before the previous calibration"):
        add(write(files[0].parent / "late.json", model_doc(noise=1, seed=7)), "M1", dt.date(2024, 2, 1), url)


@pytest.mark.slow
def test_two_processes_adding_at_once_both_land_postgresql(pg, tmp_path):
    url = fresh_database(pg, "mtcal_concurrent")
    _two_processes_add(tmp_path, url)
    assert [len(show(m, url)) for m in ("MA", "MB")] == [5, 5]


def test_postgresql_newer_schema_refused(pg, tmp_path):
    import sqlalchemy as sa

    from mtcal.history.store import database_url
    url = fresh_database(pg, "mtcal_newer")
    add(write(tmp_path / "m.json", model_doc()), "M1", dt.date(2024, 1, 1), url)
    eng = sa.create_engine(database_url(url))
    with eng.begin() as c:
        c.exec_driver_sql("UPDATE alembic_version SET version_num = '0042'")
    eng.dispose()
    with pytest.raises(InputError, match="newer than this mtcal knows"):
        show("M1", url)


@pytest.mark.parametrize("argv", [["history"], ["history", "add"], ["history", "list"], ["history", "show"],
                                  ["history", "compare"], ["history", "trend"], ["report"]])
def test_help_of_every_action(argv, capsys):
    """`--help` of the command and of each action prints and exits 0 (a bare % in a help text breaks argparse)."""
    code, out, err = run(capsys, *argv, "--help")
    assert code == 0 and out.startswith("usage: mtcal " + " ".join(argv)) and err == ""


def test_the_report_pairs_a_tool_tip_uncertainty_only_with_its_own_model(tmp_path):
    """Review: the report showed the latest uncertainty beside the latest model without asking whether it was
    drawn about that model; it is shown only when its provenance names the model's digest."""
    from mtcal.model.errormodel import model_from_dict
    from mtcal.report.run import write_report
    doc = model_doc(noise=1, seed=1)
    digest = model_from_dict(doc).digest()
    for name, their_digest, shown in (("own", digest, True), ("other", "0" * 64, False)):
        db = str(tmp_path / f"{name}.db")
        unc = dict(uncertainty_doc(), provenance={"model_sha256": their_digest})
        add(write(tmp_path / f"m_{name}.json", doc), "M1", dt.date(2024, 1, 15), db)
        add(write(tmp_path / f"u_{name}.json", unc), "M1", dt.date(2024, 1, 16), db)
        write_report("M1", tmp_path / f"{name}.html", db)
        text = (tmp_path / f"{name}.html").read_text()
        assert ("up to ±3.10 µm (95 %)" in text) is shown
        assert ("is of another model than the latest identified one" in text) is not shown


def test_trend_plot_onto_a_foreign_file_is_refused_and_force_replaces_it(hist, tmp_path, capsys):
    """Review: the refusal advised a flag the `trend` action did not have (--force was added to commands only)."""
    db, _ = hist
    plot = tmp_path / "trend.png"
    plot.write_text("a picture of the user's\n")
    code, out, err = run(capsys, "history", "trend", "M1", "--error", "E_C0Y", "--db", str(db), "--plot", str(plot))
    assert code == 2 and "exists and was not written by mtcal" in err and "give --force to replace it" in err, err
    assert plot.read_text() == "a picture of the user's\n"
    code, out, err = run(capsys, "history", "trend", "M1", "--error", "E_C0Y", "--db", str(db), "--plot", str(plot),
                         "--force")
    assert code == 0 and plot.read_bytes()[:4] == b"\x89PNG", err
