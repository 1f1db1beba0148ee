"""File helpers: atomic output, never overwriting an input, JSON with numpy values."""
from __future__ import annotations

import contextlib
import json
import os
import tempfile
from pathlib import Path
from typing import IO, Any, Iterator

import numpy as np


def refuse_overwrite(out: str | os.PathLike, *inputs: str | os.PathLike | None) -> None:
    """Raise if the output path is one of the inputs (inputs are never overwritten)."""
    o = Path(out).resolve()
    for i in inputs:
        if i is not None and Path(i).exists() and Path(i).resolve() == o:
            raise ValueError(f"output {out} is also an input; choose another output path")


_UMASK = os.umask(0)
os.umask(_UMASK)


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike, mode: str = "w", **kwargs) -> Iterator[IO]:
    """Open a temporary file beside ``path`` for writing (streaming is fine); on success it is renamed onto
    ``path`` with the permissions open() would give, on failure removed: readers never see half a file."""
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", dir=p.parent)
    try:
        with os.fdopen(fd, mode, **kwargs) as fh:
            yield fh
        os.chmod(tmp, 0o666 & ~_UMASK)  # mkstemp makes 0600
        os.replace(tmp, p)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def atomic_write_text(path: str | os.PathLike, text: str) -> None:
    """Write ``text`` atomically (see ``atomic_open``)."""
    with atomic_open(path, "w", newline="") as fh:
        fh.write(text)


def read_json(path: str | os.PathLike, what: str) -> Any:
    """Parsed JSON of an input file; a missing file or bad JSON is an error naming the file (``what``: e.g. "model")."""
    from mtcal.errors import InputError
    p = Path(path)
    try:
        return json.loads(p.read_text())
    except FileNotFoundError:
        raise FileNotFoundError(f"{what} file not found: {p}") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"{p}: not valid JSON ({exc})") from None


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
