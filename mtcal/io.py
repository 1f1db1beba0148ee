"""File helpers: atomic output, never overwriting an input nor a file mtcal did not write, JSON with numpy values.

The replace rule (once, here): an output never replaces an existing file that mtcal did not write -- or that was
changed since mtcal wrote it -- unless replacing is allowed (``replace_allowed``; the CLI's ``--force``).  "mtcal
wrote it" is known from a ledger outside the output folder, so that no output format's syntax changes (fixed-width
Heidenhain tables, LinuxCNC comp files, PNG): every file mtcal writes (``atomic_open``, ``record_written``) leaves
the SHA-256 of its content under ``written_state_dir()`` (``$MTCAL_STATE_DIR``, else ``$XDG_STATE_HOME/mtcal``,
else ``~/.local/state/mtcal``), one small file per output path named by the hash of the path.  A file whose content
no longer has that hash (edited, or replaced by another program) is not mtcal's any more.
"""
from __future__ import annotations

import contextlib
import contextvars
import csv
import errno
import fnmatch
import hashlib
import json
import os
import re
import secrets
import warnings
from pathlib import Path
from typing import IO, Any, Iterable, Iterator, Mapping, Sequence

import numpy as np

from mtcal.errors import InputError, InputWarning

_REPLACE_ALLOWED = contextvars.ContextVar("mtcal_replace_allowed", default=False)


@contextlib.contextmanager
def replace_allowed(allowed: bool = True) -> Iterator[None]:
    """Within this block outputs may replace files mtcal did not write (the CLI's ``--force``)."""
    token = _REPLACE_ALLOWED.set(bool(allowed))
    try:
        yield
    finally:
        _REPLACE_ALLOWED.reset(token)


def written_state_dir() -> Path:
    """The folder of the ledger of files mtcal wrote (module docstring)."""
    if os.environ.get("MTCAL_STATE_DIR"):
        return Path(os.environ["MTCAL_STATE_DIR"])
    base = os.environ.get("XDG_STATE_HOME") or str(Path.home() / ".local" / "state")
    return Path(base) / "mtcal"


def _ledger(path: str | os.PathLike) -> Path:
    key = hashlib.sha256(str(Path(path).resolve()).encode("utf-8", "surrogateescape")).hexdigest()
    return written_state_dir() / "written" / key[:2] / key


def record_written(path: str | os.PathLike) -> None:
    """Note in the ledger that mtcal wrote ``path`` as it is now (a ledger that cannot be written is skipped:
    the file is then treated as not mtcal's on the next run, which only asks for ``--force``)."""
    entry = _ledger(path)
    try:
        entry.parent.mkdir(parents=True, exist_ok=True)
        tmp = entry.with_name(f".{entry.name}.{secrets.token_hex(4)}")
        tmp.write_text(f"{file_sha256(path)} {Path(path).resolve()}\n", encoding="utf-8")
        os.replace(tmp, entry)
    except OSError:
        pass


def written_by_mtcal(path: str | os.PathLike) -> bool:
    """Whether mtcal wrote ``path`` and nothing changed it since (its content has the hash the ledger noted)."""
    try:
        return _ledger(path).read_text(encoding="utf-8").split(" ", 1)[0] == file_sha256(path)
    except OSError:
        return False


def refuse_foreign(path: str | os.PathLike) -> None:
    """Raise InputError when ``path`` is an existing file that mtcal did not write (or that changed since) and
    replacing is not allowed (``replace_allowed``; the CLI's ``--force``, ``--replace`` on export and compensate)."""
    p = Path(path)
    if _REPLACE_ALLOWED.get() or not p.is_file() or written_by_mtcal(p):
        return
    raise InputError("exists and was not written by mtcal (or was changed since): not replaced, nothing was "
                     "written; choose another output or give `replace` to replace it", p)


def refuse_overwrite(outputs: Iterable[str | os.PathLike | None] | str | os.PathLike,
                     *inputs: str | os.PathLike | None,
                     dirs: Mapping[str | os.PathLike | None, Sequence[str]] | None = None) -> None:
    """Raise InputError when a planned output would overwrite an input of the same run.

    ``outputs``: output file paths (one path or several; None entries are skipped); ``inputs``: the run's input
    files; ``dirs``: output directories -> glob patterns of the files the command writes there (e.g.
    ``{"plots": ["*.png"]}``): an input inside such a directory matching a pattern is refused too.
    Same file = same resolved path or the same inode (symlinks, hard links).  An output (or a file matching a
    directory's patterns) that exists and was not written by mtcal is refused too (``refuse_foreign``), before
    anything is written.
    """
    outs = [outputs] if isinstance(outputs, (str, os.PathLike)) else list(outputs)
    ins = [Path(i) for i in inputs if i is not None and Path(i).exists()]
    for out in outs:
        if out is None:
            continue
        if Path(out).is_dir():
            raise InputError("is a directory; give an output file name", out)
        _check_parents(Path(out))
        for i in ins:
            if _same(Path(out), i):
                raise InputError(f"output {out} is also an input of this run; choose another output path")
        refuse_foreign(out)
    for d, patterns in (dirs or {}).items():
        if d is None:
            continue
        if Path(d).exists() and not Path(d).is_dir():
            raise InputError("exists and is not a directory; give an output directory", d)
        _check_parents(Path(d))
        dd = Path(d).resolve()
        for i in ins:
            if i.resolve().parent == dd and any(fnmatch.fnmatch(i.name, pat) for pat in patterns):
                raise InputError(f"output directory {d} would overwrite the input {i} (it writes "
                                 f"{', '.join(patterns)} there); choose another directory")
        if Path(d).is_dir():
            for f in sorted(Path(d).iterdir()):
                if any(fnmatch.fnmatch(f.name, pat) for pat in patterns):
                    refuse_foreign(f)


def _check_parents(p: Path) -> None:
    """The nearest existing parent of an output path must be a directory."""
    for q in p.absolute().parents:
        if q.exists():
            if not q.is_dir():
                raise InputError(f"cannot write here: {q} is a file, not a directory", p)
            return


def _same(a: Path, b: Path) -> bool:
    if a.resolve() == b.resolve():
        return True
    try:
        return a.exists() and os.path.samefile(a, b)
    except OSError:
        return False


_UMASK = os.umask(0)
os.umask(_UMASK)


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike, mode: str = "w", **kwargs) -> Iterator[IO]:
    """Open a temporary file beside ``path`` for writing (streaming is fine); on success it is renamed onto
    ``path`` with the permissions open() would give and noted as mtcal's (``record_written``), on failure removed:
    readers never see half a file.  An existing ``path`` mtcal did not write is refused (``refuse_foreign``)."""
    p = Path(path)
    if p.is_dir():
        raise IsADirectoryError(errno.EISDIR, "is a directory", str(p))
    refuse_foreign(p)
    p.parent.mkdir(parents=True, exist_ok=True)
    tmp = None
    try:
        tmp, fd = _create_temporary(p)
        with os.fdopen(fd, mode, **kwargs) as fh:
            yield fh
        os.chmod(tmp, 0o666 & ~_UMASK)  # created 0600
        refuse_foreign(p)  # nothing else put a file there meanwhile
        os.replace(tmp, p)
        record_written(p)
    except BaseException:
        if tmp is not None:
            Path(tmp).unlink(missing_ok=True)
        raise
    finally:
        _ACTIVE.discard(tmp)


_ACTIVE: set[str] = set()  # temporaries of atomic_open calls under way


def _create_temporary(p: Path) -> tuple[str, int]:
    """A new ``.NAME.XXXXXXXX`` beside ``p`` (0600, exclusive), registered in _ACTIVE *before* it exists: a Ctrl-C or
    SIGTERM raised at any point (Python runs signal handlers between any two calls) cannot leave an unknown file."""
    for _ in range(100):
        tmp = str(p.parent / f".{p.name}.{secrets.token_hex(4)}")
        _ACTIVE.add(tmp)
        try:
            return tmp, os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o600)
        except FileExistsError:
            _ACTIVE.discard(tmp)
    raise FileExistsError(errno.EEXIST, "no free temporary name", str(p))


def remove_temporaries() -> None:
    """Remove the temporaries of every atomic_open still under way (the CLI calls this when a run is interrupted:
    an exception raised between a generator's ``yield`` and the ``with`` taking it over never reaches it)."""
    for tmp in list(_ACTIVE):
        Path(tmp).unlink(missing_ok=True)
        _ACTIVE.discard(tmp)


def save_figure(fig, path: str | os.PathLike, dpi: int = 110) -> None:
    """A matplotlib figure as PNG, written atomically (see ``atomic_open``)."""
    with atomic_open(path, "wb") as fh:
        fig.savefig(fh, format="png", dpi=dpi)


def atomic_write_text(path: str | os.PathLike, text: str) -> None:
    """Write ``text`` atomically (see ``atomic_open``)."""
    with atomic_open(path, "w", newline="") as fh:
        fh.write(text)


def read_text(path: str | os.PathLike, what: str = "input") -> str:
    """Text of an input file for people's exports: UTF-8 (a byte-order mark is dropped), else Windows-1252 /
    Latin-1 (said in a warning); missing, directory, empty and binary (NUL bytes) files are errors naming the
    file.  Line ends are kept as they are."""
    p = Path(path)
    if not p.exists():
        raise InputError(f"{what} file not found", p)
    if p.is_dir():
        raise InputError(f"is a directory, expected a {what} file", p)
    data = p.read_bytes()
    if not data.strip():
        raise InputError(f"empty {what} file", p)
    utf16 = _utf16(data)
    if utf16 is not None:
        warnings.warn(InputWarning(f"{p}: UTF-16 text (\"Unicode Text\" export); read as {utf16}"), stacklevel=2)
        try:
            return data.decode(utf16).removeprefix("\ufeff")
        except UnicodeDecodeError as exc:
            raise InputError(f"UTF-16 text with an undecodable byte at offset {exc.start}", p) from None
    if b"\0" in data:
        line = data[:data.index(b"\0")].count(b"\n") + 1
        raise InputError(f"NUL byte: a binary file, not a {what} file", p, line)
    data = data.removeprefix(b"\xef\xbb\xbf")  # UTF-8 byte-order mark (Excel "CSV UTF-8")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[:exc.start].count(b"\n") + 1
    for enc in ("cp1252", "latin-1"):
        try:
            text = data.decode(enc)
        except UnicodeDecodeError:
            continue
        warnings.warn(InputWarning(f"{p}:{line}: not UTF-8; read as {enc} (Windows-1252/Latin-1)"), stacklevel=2)
        return text
    raise AssertionError("latin-1 decodes every byte")  # pragma: no cover


def _utf16(data: bytes) -> str | None:
    """The codec of UTF-16 text (a byte-order mark; or, without one, a NUL in every other byte of the first line,
    as Excel's "Unicode Text" writes ASCII), else None."""
    if data[:2] in (b"\xff\xfe", b"\xfe\xff"):
        return "utf-16"
    head = data[:200]
    if len(head) >= 4 and len(data) % 2 == 0:
        if head[1::2].count(0) == len(head[1::2]) and 0 not in head[0::2]:
            return "utf-16-le"
        if head[0::2].count(0) == len(head[0::2]) and 0 not in head[1::2]:
            return "utf-16-be"
    return None


_DECIMAL_COMMA = re.compile(r"^\s*[+-]?\d*,\d+(?:[eE][+-]?\d+)?\s*$")


def read_csv_rows(path: str | os.PathLike, what: str) -> list[tuple[int, list[str]]]:
    """Non-empty, non-comment (``#``) rows of a CSV input as (file line, fields); see ``read_text`` for encodings.

    The separator is ``,``; a header with tabs and no ``,`` is tab-separated (said in a warning); a header with ``;``
    and no ``,`` is a spreadsheet export with ``;`` separators, whose decimal commas (``1,25``) are read as decimal
    points: said in a warning naming the file."""
    return read_csv_table(path, what)[1]


def csv_separator(line: str) -> str:
    """The separator of a CSV header line: tab (tabs, no ``,``), ``;`` (``;``, no ``,``), else ``,``."""
    return "\t" if "\t" in line and "," not in line else ";" if ";" in line and "," not in line else ","


def read_csv_table(path: str | os.PathLike, what: str, is_header=None) -> tuple[list[tuple[int, str]],
                                                                               list[tuple[int, list[str]]]]:
    """(preamble, rows) of a CSV input whose table may follow a block of other lines (an instrument's metadata):
    ``is_header(fields)`` picks the header line (default: the first line); the lines before it are the preamble
    as (file line, text), the header and the lines after it the rows, read as ``read_csv_rows`` says.  No line
    taken as the header: (every line as the preamble, [])."""
    text = read_text(path, what)
    lines = [(i + 1, ln) for i, ln in enumerate(text.splitlines()) if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise InputError(f"empty {what} file (only comments or blank lines)", path)
    start = 0
    if is_header is not None:
        start = next((k for k, (i, ln) in enumerate(lines)
                      if is_header(_csv_fields(ln, csv_separator(ln), path, i))), None)
        if start is None:
            return lines, []
    preamble, lines = lines[:start], lines[start:]
    head = lines[0][1]
    sep = csv_separator(head)
    if sep == "\t":
        warnings.warn(InputWarning(f"{path}: tab-separated"), stacklevel=2)
    rows = [(i, _csv_fields(ln, sep, path, i)) for i, ln in lines]
    if sep == ";":
        commas = 0
        for _, r in rows[1:]:
            for k, f in enumerate(r):
                if _DECIMAL_COMMA.match(f):
                    r[k] = f.replace(",", ".")
                    commas += 1
        warnings.warn(InputWarning(f"{path}: ';'-separated (spreadsheet export)"
                                   + (f"; {commas} decimal comma(s) read as decimal points" if commas else "")),
                      stacklevel=2)
    return preamble, rows


def _csv_fields(line: str, sep: str, path: str | os.PathLike, lno: int) -> list[str]:
    """Fields of one CSV line; what the csv module cannot read (a field over its 128 KiB limit, a stray quote
    under strict rules) is an error naming the file and line."""
    try:
        return next(csv.reader([line], delimiter=sep))
    except csv.Error as exc:
        raise InputError(f"unreadable CSV line: {exc}", path, lno) from None


def file_sha256(path: str | os.PathLike) -> str:
    """sha256 of a file's bytes (what a result derived from the file records of it, and the ledger of what mtcal
    wrote)."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def read_json(path: str | os.PathLike, what: str) -> Any:
    """Parsed JSON of an input file; a missing file or bad JSON is an error naming the file (``what``: e.g. "model")."""
    p = Path(path)
    text = read_text(p, what)
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"not valid JSON ({exc.msg}, column {exc.colno})", p, exc.lineno) from None


def _default(o: Any):
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, (np.floating, np.integer, np.bool_)):
        return o.item()
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")


def dumps(obj: Any) -> str:
    """JSON text; NaN is written as null (JSON has no NaN)."""
    def clean(x):
        if isinstance(x, float) and not np.isfinite(x):
            return None
        if isinstance(x, dict):
            return {k: clean(v) for k, v in x.items()}
        if isinstance(x, (list, tuple)):
            return [clean(v) for v in x]
        if isinstance(x, np.ndarray):
            return clean(x.tolist())
        if isinstance(x, (np.floating, np.integer, np.bool_)):
            return clean(x.item())
        return x
    return json.dumps(clean(obj), indent=2, default=_default)
