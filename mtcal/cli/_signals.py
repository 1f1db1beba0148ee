"""Ctrl-C (SIGINT) and SIGTERM while a command runs: each raised as its exception in the main thread
(KeyboardInterrupt, Terminated), so that every cleanup on the way out runs, and raised again every ``REPEAT_S``
seconds until the main thread is handling it.

Why again: NumPy drops the exception a signal handler raises while it compares a string scalar -- an ``np.str_``
compared with a ``str`` or looked up in a dict inside a list comprehension (a Ctrl-C lost in every one of 60 tries,
numpy 2.4.6; a plain ``str`` loses none) -- and the readings' labels are such scalars throughout: one Ctrl-C there
was lost and the command ran on (`mtcal plan --monte-carlo 2000000` hung after a Ctrl-C in CI, and in 1 of 50
tries here under load).  The signal sent again lands in the same place, so the repeat is an asynchronous exception
of the main thread (``PyThreadState_SetAsyncExc``), which the interpreter raises between two bytecodes, where no C
code can drop it.  It is sent only while the main thread is not handling that exception (a command saving its
trials after Ctrl-C is left to finish, mtcal.uncertainty.run), and never after the command's context ended (one
still pending then is withdrawn).
"""
from __future__ import annotations

import ctypes
import signal
import sys
import threading

REPEAT_S = 1.0


class Terminated(BaseException):
    """SIGTERM as an exception, so that every ``finally``/cleanup (temporary files) runs on the way out."""


_RAISES = {signal.SIGINT: KeyboardInterrupt, signal.SIGTERM: Terminated}


def _async_raise(thread_id: int, exc: type[BaseException] | None) -> None:
    """Raise ``exc`` in the thread at its next bytecode (None: withdraw one pending)."""
    ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(thread_id), ctypes.py_object(exc) if exc else None)


class caught:
    """Context of a command's run: SIGTERM always, SIGINT where it is at Python's default (a shell's background job
    starts with SIGINT ignored, and it stays so), raised as their exceptions and repeated until taken (module
    docstring); the previous handlers come back on exit.  Outside the main thread (a test thread) signals are left
    alone.  ``received``: the exception of the first signal, for a caller whose exception came out otherwise (C
    code turns one raised inside it into its own: an extension module's init into ImportError)."""

    def __init__(self):
        self.old: dict[int, object] = {}
        self.received: type[BaseException] | None = None  # the exception of the first signal received
        self.ended = False
        self.timer: threading.Timer | None = None
        self.lock = threading.Lock()
        self.main = threading.main_thread().ident

    def __enter__(self) -> caught:
        if threading.get_ident() != self.main:
            return self
        for sig in _RAISES:
            if sig == signal.SIGINT and signal.getsignal(sig) is not signal.default_int_handler:
                continue
            self.old[sig] = signal.signal(sig, self._raise)
        return self

    def __exit__(self, *exc) -> None:
        with self.lock:
            self.ended = True
            if self.timer is not None:
                self.timer.cancel()
                _async_raise(self.main, None)
        for sig, old in self.old.items():
            signal.signal(sig, old)

    def _raise(self, signum, frame):
        self.received = self.received or _RAISES[signum]
        self._watch(_RAISES[signum])
        raise _RAISES[signum]()

    def _watch(self, exc: type[BaseException]) -> None:
        if self.timer is None and not self.ended:
            self.timer = threading.Timer(REPEAT_S, self._again, (exc,))
            self.timer.daemon = True
            self.timer.start()

    def _again(self, exc: type[BaseException]) -> None:
        """``exc`` again in the main thread unless it is handling one (taken) or the command ended."""
        with self.lock:
            self.timer = None
            if self.ended:
                return
            now = sys._current_exceptions().get(self.main)
            now = now[1] if isinstance(now, tuple) else now  # (type, value, traceback) before Python 3.12
            if not isinstance(now, exc):
                _async_raise(self.main, exc)
            self._watch(exc)  # look again later: taken, or dropped again
