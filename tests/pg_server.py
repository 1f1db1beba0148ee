"""A private PostgreSQL for the tests, on a Unix socket only (no TCP port): Debian's postgresql package (initdb and
pg_ctl under /usr/lib/postgresql/*/bin), a throw-away cluster in a temporary folder, trust authentication.

``.ci/run`` starts one and exports ``MTCAL_TEST_POSTGRES`` (its URL); without that variable the tests start their
own (``private_server``), or skip with the reason (no PostgreSQL installed, not root and not the postgres user...).
"""
from __future__ import annotations

import contextlib
import glob
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

ENV = "MTCAL_TEST_POSTGRES"
PORT = 54338  # names the socket file only (listen_addresses is empty: no TCP)


def binaries() -> Path | None:
    found = sorted(glob.glob("/usr/lib/postgresql/*/bin/initdb"))
    return Path(found[-1]).parent if found else None


def _as_postgres(cmd: list[str]) -> list[str]:
    """Run as the postgres user when we are root (initdb refuses root)."""
    if os.geteuid() != 0:
        return cmd
    return ["runuser", "-u", "postgres", "--"] + cmd


@contextlib.contextmanager
def private_server():
    """Yield (url, None) of a fresh cluster, or (None, reason) when none can start; stopped and removed after."""
    if os.environ.get(ENV):
        yield os.environ[ENV], None
        return
    bin_dir = binaries()
    if bin_dir is None:
        yield None, "PostgreSQL is not installed (Debian: apt-get install postgresql)"
        return
    if os.geteuid() == 0 and shutil.which("runuser") is None:
        yield None, "running as root without runuser: cannot start PostgreSQL as the postgres user"
        return
    root = Path(tempfile.mkdtemp(prefix="mtcal-pg-"))
    data, sock = root / "data", root / "sock"
    sock.mkdir()
    if os.geteuid() == 0:
        shutil.chown(root, "postgres")
        shutil.chown(sock, "postgres")
    started = False
    try:
        r = subprocess.run(_as_postgres([str(bin_dir / "initdb"), "-D", str(data), "-A", "trust", "-U", "postgres",
                                         "--no-sync"]), capture_output=True, text=True, timeout=120)
        if r.returncode:
            yield None, f"initdb failed: {r.stderr.strip().splitlines()[-1] if r.stderr.strip() else r.returncode}"
            return
        opts = f"-k {sock} -c listen_addresses= -p {PORT} -c fsync=off"
        r = subprocess.run(_as_postgres([str(bin_dir / "pg_ctl"), "-D", str(data), "-o", opts, "-l",
                                         str(root / "log"), "-w", "start"]), capture_output=True, text=True,
                           timeout=120)
        if r.returncode:
            log = (root / "log").read_text()[-300:] if (root / "log").exists() else r.stderr
            yield None, f"PostgreSQL did not start: {log}"
            return
        started = True
        yield f"postgresql://postgres@/postgres?host={sock}&port={PORT}", None
    finally:
        if started:
            subprocess.run(_as_postgres([str(bin_dir / "pg_ctl"), "-D", str(data), "-m", "immediate", "stop"]),
                           capture_output=True, timeout=60)
        shutil.rmtree(root, ignore_errors=True)


def fresh_database(url: str, name: str) -> str:
    """A new empty database ``name`` on the server of ``url`` (dropped first if it exists); its URL."""
    import sqlalchemy as sa

    from mtcal.history.store import database_url
    eng = sa.create_engine(database_url(url), isolation_level="AUTOCOMMIT")
    with eng.connect() as c:
        c.exec_driver_sql(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)')
        c.exec_driver_sql(f'CREATE DATABASE "{name}"')
    eng.dispose()
    base, _, query = url.partition("?")
    return base.rsplit("/", 1)[0] + f"/{name}" + (f"?{query}" if query else "")
