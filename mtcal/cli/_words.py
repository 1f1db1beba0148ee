"""Messages the commands print, said once: a warning goes through the command's logger (so it carries the
``mtcal CMD: warning:`` prefix of every other line on stderr, and -q keeps it), and counts or lists are words
("E_AX 79, E_BX 79 and 3 more errors"), never a Python dict or list."""
from __future__ import annotations

import logging

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
