"""Messages the commands print, said once: a warning goes through the command's logger (so it carries the
``mtcal CMD: warning:`` prefix of every other line on stderr, and -q keeps it), counts or lists are words
("E_AX 79, E_BX 79 and 3 more errors"), never a Python dict or list, and one progress bar of trials (``Bar``)."""
from __future__ import annotations

import contextlib
import logging
import sys

log = logging.getLogger("mtcal.cli")


def warn(text: str) -> None:
    """``text`` as a warning of the running command."""
    log.warning("warning: %s", text)


def counted(counts: dict[str, int], what: str = "errors", most: int = 6) -> str:
    """'E_AX 79, E_BX 79, E_CX 60 and 3 more errors': the largest counts first."""
    top = sorted(counts.items(), key=lambda kv: (-kv[1], kv[0]))
    text = ", ".join(f"{k} {v}" for k, v in top[:most])
    return text + (f" and {len(top) - most} more {what}" if len(top) > most else "")


def listed(items, most: int = 5) -> str:
    """'3, 5, 9, 12, 20 and 7 more'."""
    items = [str(i) for i in items]
    return ", ".join(items[:most]) + (f" and {len(items) - most} more" if len(items) > most else "")


def warn_outside(outside: dict[str, int]) -> None:
    """Evaluations outside an error function's measured range hold its end values (compensate, check): the
    total and the errors it happened to, in words."""
    if outside:
        warn(f"{sum(outside.values())} error evaluations outside the measured range (end values held): "
             f"{counted(outside)}")


class Bar:
    """The one progress bar of a command's trials on stderr (uncertainty, plan --monte-carlo), drawn only on a
    terminal (a log file gets the lines, not a bar's every refresh) and started at the first trials done, so
    that its rate and remaining time are the trials' (the set-up before them says its own lines).  The lines
    said while it runs are printed above it (else each one leaves a copy of the bar behind)."""

    def __init__(self, total: int, desc: str):
        self.total, self.desc, self.bar, self.lines = total, desc, None, contextlib.ExitStack()

    def update(self, n: int) -> None:
        if self.bar is None:
            from tqdm import tqdm
            from tqdm.contrib.logging import logging_redirect_tqdm

            self.bar = tqdm(total=self.total, unit="trial", file=sys.stderr, desc=self.desc, disable=None)
            self.lines.enter_context(logging_redirect_tqdm([logging.getLogger("mtcal")]))
        self.bar.update(n)

    def close(self) -> None:
        self.lines.close()
        if self.bar is not None:
            self.bar.close()
