"""Exceptions with messages meant for people: name the file, row and problem."""
from __future__ import annotations

import os


class InputError(ValueError):
    """Bad input (a user's file, row, value or option); the CLI prints one line without a traceback and exits 2.

    ``file`` and ``line`` (1-based) are optional; when given, ``str()`` is ``"FILE:LINE: problem"`` (or
    ``"FILE: problem"``), the one-line format of every refusal.  Still a ValueError for library callers that
    catch ValueError, but the CLI never treats a bare ValueError as the user's fault.
    """

    def __init__(self, message: str, file: str | os.PathLike | None = None, line: int | None = None):
        self.problem = message
        self.file = None if file is None else str(file)
        self.line = None if line is None else int(line)
        super().__init__(message)

    def __str__(self) -> str:
        where = self.file or ""
        if self.file and self.line is not None:
            where += f":{self.line}"
        return f"{where}: {self.problem}" if where else self.problem


class InputWarning(UserWarning):
    """Something about an input a person should know (a guessed encoding or separator); the CLI prints it as
    one line ``mtcal CMD: warning: ...``."""
