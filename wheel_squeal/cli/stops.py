"""How a command stops: SIGTERM (``timeout``, batch schedulers, systemd), SIGINT
(Ctrl-C) and SIGALRM (the request's time budget, armed by ``cli.main``) raise their
exception in the main thread, so that the usual clean-up runs (staging folders removed,
worker processes stopped), and a watcher thread ends a command that cannot return to
Python within a grace period (a long LAPACK call) with the same line and exit status.
Processes forked from the command leave stops to it. :func:`uninterrupted` holds a stop
back over native work that does not survive an exception between its calls.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import sys
import threading
import time
from types import FrameType

from ..runtime.interrupts import STATE, STOPS, OutOfTime, StopState, Terminated, uninterrupted

__all__ = [
    "NATIVE_CALLBACKS",
    "STATE",
    "STOPS",
    "TERMINATE_GRACE_S",
    "OutOfTime",
    "StopState",
    "Terminated",
    "grace_s",
    "in_native_callback",
    "install_stop_handlers",
    "stop_line",
    "uninterrupted",
]


#: Where Python code runs as a callback of native code, as (a file's path ending, the
#: function's name or "" for any): numba's LLVM object cache (through ctypes), PROJ's log
#: (pyproj) and logging's lock around a fork (``os.register_at_fork``, when a library runs a subprocess). An
#: exception raised there is printed as "Exception ignored" with a traceback and swallowed,
#: so a stop that lands there is sent again a moment later.
NATIVE_CALLBACKS = (
    ("llvmlite/binding", ""),
    ("logging/__init__.py", "_acquireLock"),
    ("logging/__init__.py", "_releaseLock"),
    ("logging/__init__.py", "_after_at_fork_child_reinit_locks"),
    ("logging/__init__.py", "_prepareFork"),  # the same hooks' names from Python 3.13
    ("logging/__init__.py", "_afterFork"),
    # pyproj's PROJ logs through a Cython callback into logging (``--crs``)
    ("logging/__init__.py", "debug"),
    ("logging/__init__.py", "isEnabledFor"),
    ("pyproj/", ""),
)
RESEND_AFTER_S = 0.05


def in_native_callback(frame: FrameType | None) -> bool:
    """Whether ``frame`` (a signal handler's) runs inside one of :data:`NATIVE_CALLBACKS`."""
    while frame is not None:
        path = frame.f_code.co_filename.replace("\\", "/")
        if any(where in path and name in ("", frame.f_code.co_name) for where, name in NATIVE_CALLBACKS):
            return True
        frame = frame.f_back
    return False


def _on_signal(signum: int, frame: FrameType | None) -> None:
    STATE.received.append(signum)
    if STATE.holding:
        return
    if in_native_callback(frame):
        main = threading.main_thread().ident
        assert main is not None
        threading.Timer(RESEND_AFTER_S, signal.pthread_kill, (main, signum)).start()
        return
    raise STOPS[signum][0]


#: Seconds the stop watcher waits, beyond the grace period, for an earlier result that is
#: being removed after its replacement was committed
COMMIT_WAIT_S = 60.0
#: Seconds a stopped command has to clean up before it ends regardless (it may be inside
#: a long native computation, where no Python code runs until it returns).
TERMINATE_GRACE_S = 5.0


def stop_line(signum: int, budget_s: float | None) -> str:
    if signum == signal.SIGALRM:
        return (
            f"error: the request ran past its time budget of {budget_s:g} s and was stopped; "
            "raise it with --max-seconds S (WHEEL_SQUEAL_MAX_SECONDS) or ask for less"
        )
    return "terminated" if signum == signal.SIGTERM else "interrupted"


def _leave_stops_to_the_parent() -> None:
    """In a process forked from the command's (the plot process, a study's workers), at
    once: Ctrl-C and the time budget are the parent's to handle, SIGTERM ends it silently,
    and its signals do not wake the parent's watcher."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGALRM, signal.SIG_DFL)
    with contextlib.suppress(ValueError):
        signal.set_wakeup_fd(-1)


def grace_s(signum: int) -> float:
    """Seconds a command stopped by ``signum`` has to end by itself:
    :data:`TERMINATE_GRACE_S`, and for the time budget at most 5 % of it (a budget is kept
    within 10 %)."""
    if signum == signal.SIGALRM and STATE.budget_s is not None:
        return min(TERMINATE_GRACE_S, max(0.2, 0.05 * STATE.budget_s))
    return TERMINATE_GRACE_S


def install_stop_handlers() -> None:
    """SIGTERM, SIGINT and SIGALRM raise their exception in the main thread; if that has
    not ended the process within :func:`grace_s` (a LAPACK or numba call does not return
    to Python until done), a watcher thread ends it with the same line and exit status,
    after removing the staging folders: the earlier result stays as it was."""
    r, w = os.pipe()
    os.set_blocking(w, False)
    signal.set_wakeup_fd(w)  # written by the C-level handler at once, even mid-computation
    for signum in STOPS:
        signal.signal(signum, _on_signal)
    os.register_at_fork(after_in_child=_leave_stops_to_the_parent)

    def watch() -> None:
        while True:
            got = [b for b in os.read(r, 64) if b in STOPS]
            if got:
                break
        time.sleep(grace_s(got[0]))
        waited = 0.0
        while STATE.retiring and waited < COMMIT_WAIT_S:  # let the earlier result go whole
            time.sleep(0.05)
            waited += 0.05
        from ..runtime.result_folders import ResultFolder

        ResultFolder.discard_all()
        for folder in STATE.temporary_folders:
            shutil.rmtree(folder, ignore_errors=True)
        if STATE.committed:  # the result is complete: the request ended as asked
            with contextlib.suppress(OSError, ValueError):
                sys.stdout.flush()
            os._exit(0)
        with contextlib.suppress(OSError, ValueError):
            print(stop_line(got[0], STATE.budget_s), file=sys.stderr, flush=True)
        os._exit(STOPS[got[0]][1])

    threading.Thread(target=watch, name="stop-watch", daemon=True).start()
