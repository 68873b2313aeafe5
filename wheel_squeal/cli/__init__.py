"""The command line: ``wheel-squeal COMMAND`` (or ``python pipeline.py COMMAND``).

:func:`main` parses the arguments (:mod:`.parser`), runs the command (:mod:`.commands`)
and turns the errors a user can act on into one line on stderr: a refused request
(``RequestError``, ``DesignError``) exits with status 2, a computation that failed
(``MeshError``, ``EigenError``, ``IntegrationError``) with status 1. Anything else is a
bug: its traceback is shown, exit status 1.
"""

from __future__ import annotations

import contextlib
import errno
import os
import signal
import sys
import threading
import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field

from geometry import DesignError

from ..errors import BudgetExhausted, RequestError
from ..plotting import plot_workers
from .parser import DRAWING_COMMANDS, build_parser

__all__ = ["main", "run"]

#: The anticipated failures of a computation: (module, exception name).
_COMPUTATION_FAILURES = (
    ("geometry.mesh", "MeshError"),
    ("fem.eigen", "EigenError"),
    ("reduced.model", "IntegrationError"),
)


def _computation_failures() -> tuple[type, ...]:
    """Those failure types whose modules are loaded (one not loaded cannot have been
    raised), so that catching them imports nothing."""
    return tuple(getattr(sys.modules[m], name) for m, name in _COMPUTATION_FAILURES if m in sys.modules)


def _one_line_warning(message, category, filename, lineno, file=None, line=None) -> None:
    print(f"warning: {str(message).splitlines()[0]}", file=sys.stderr)


class Terminated(KeyboardInterrupt):
    """SIGTERM (sent by timeout, batch schedulers, systemd): stop as on Ctrl-C, so that
    the same clean-up runs (staging folders removed, worker processes stopped)."""


class OutOfTime(KeyboardInterrupt):
    """The request's time budget ran out while it worked (SIGALRM, armed by :func:`run`
    for the time left): stop as on Ctrl-C, then report the budget."""


#: The signals that stop a command, the exception each raises in the main thread, the
#: exit status and the line printed.
_STOPS: dict[int, tuple[type[KeyboardInterrupt], int]] = {
    signal.SIGTERM: (Terminated, 143),
    signal.SIGINT: (KeyboardInterrupt, 130),
    signal.SIGALRM: (OutOfTime, 1),
}


@dataclass
class _StopState:
    """This process's stop signals: those received, in order (a library that turns the
    exception a signal raised into another one, as some do during an import, cannot hide
    it), and the time budget the alarm was armed with [s]."""

    received: list[int] = field(default_factory=list)
    budget_s: float | None = None


_STATE = _StopState()


def _on_signal(signum, frame) -> None:
    _STATE.received.append(signum)
    raise _STOPS[signum][0]


#: Seconds a stopped command has to clean up before it ends regardless (it may be inside
#: a long native computation, where no Python code runs until it returns).
TERMINATE_GRACE_S = 5.0


def _stop_line(signum: int, budget_s: float | None) -> str:
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


def _grace_s() -> float:
    """Seconds a stopped command has to end by itself: :data:`TERMINATE_GRACE_S`, and for
    the time budget at most 5 % of it (a budget is kept within 10 %)."""
    if _STATE.received and _STATE.received[0] == signal.SIGALRM and _STATE.budget_s is not None:
        return min(TERMINATE_GRACE_S, max(0.2, 0.05 * _STATE.budget_s))
    return TERMINATE_GRACE_S


def _install_stop_handlers() -> None:
    """SIGTERM, SIGINT and SIGALRM raise their exception in the main thread; if that has
    not ended the process within :func:`_grace_s` (a LAPACK or numba call does not return
    to Python until done), a watcher thread ends it with the same line and exit status,
    after removing the staging folders: the earlier result stays as it was."""
    r, w = os.pipe()
    os.set_blocking(w, False)
    signal.set_wakeup_fd(w)  # written by the C-level handler at once, even mid-computation
    for signum in _STOPS:
        signal.signal(signum, _on_signal)
    os.register_at_fork(after_in_child=_leave_stops_to_the_parent)

    def watch() -> None:
        while True:
            got = [b for b in os.read(r, 64) if b in _STOPS]
            if got:
                break
        time.sleep(_grace_s())
        from ..outputs import ResultFolder

        ResultFolder.discard_all()
        with contextlib.suppress(OSError, ValueError):
            print(_stop_line(got[0], _STATE.budget_s), file=sys.stderr, flush=True)
        os._exit(_STOPS[got[0]][1])

    threading.Thread(target=watch, name="stop-watch", daemon=True).start()


#: Errors of the file system that end a command in one line (exit status 1): the disk or
#: the quota is full, or a file would exceed the largest size allowed.
_FULL = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG)


def main(
    argv: Sequence[str] | None = None,
    prog: str | None = None,
    *,
    alarm: bool = False,
    started_s: float | None = None,
) -> int:
    """Run the command line; returns the exit status (0 done; 1 a computation failed, the
    time budget ran out, the disk is full, or a bug; 2 request refused; 130 interrupted;
    143 terminated). ``alarm``: stop the command when its time budget runs out (SIGALRM;
    :func:`run` arms it, with the handlers that make every stop one line); ``started_s``:
    when the process started (``time.monotonic``), from which the budget counts."""
    parser = build_parser(prog or os.path.basename(sys.argv[0]) or "wheel-squeal")
    args, unknown = parser.parse_known_args(argv)
    if unknown:  # the subcommand's own error: it points to its --help
        parser.subcommands[args.command].error(f"unrecognized arguments: {' '.join(unknown)}")
    args._started_s = started_s
    if not os.environ.get("DISPLAY"):
        # Without an X server VTK tries X first and warns before falling back to EGL;
        # go straight to EGL (off-screen) so the terminal stays clean.
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    draws = args.command in DRAWING_COMMANDS
    with warnings.catch_warnings(), plot_workers() if draws else contextlib.nullcontext() as plots:
        warnings.showwarning = _one_line_warning
        try:
            from .commands import COMMANDS  # after the plot process started: it imports meanwhile
            from .common import settings_of

            budget = settings_of(args)  # the flags and environment, checked before any work
            if alarm and budget is not None:
                _STATE.budget_s = budget.max_seconds
                signal.setitimer(signal.ITIMER_REAL, max(budget.seconds_left(), 1e-3))
            command = COMMANDS[args.command]
            return command(args, plots) if draws else command(args)
        except BaseException as exc:
            return _status_of(exc)
        finally:
            if alarm:
                signal.setitimer(signal.ITIMER_REAL, 0.0)


def _status_of(exc: BaseException) -> int:
    """The exit status of a command that raised ``exc``, with its one line on stderr
    (a bug's traceback is re-raised)."""
    if _STATE.received:  # a signal stopped it, whatever the exception became on the way
        print(_stop_line(_STATE.received[0], _STATE.budget_s), file=sys.stderr)
        return _STOPS[_STATE.received[0]][1]
    if isinstance(exc, RequestError | DesignError):
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if isinstance(exc, Terminated):
        print("terminated", file=sys.stderr)
        return 143
    if isinstance(exc, KeyboardInterrupt):
        print("interrupted", file=sys.stderr)
        return 130
    if isinstance(exc, BrokenPipeError):
        # The reader of stdout left (``| head``): the results are written, the rest of
        # the report has nowhere to go.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
    if isinstance(exc, OSError) and exc.errno in _FULL:
        where = f" ({exc.filename})" if exc.filename else ""
        print(
            f"error: {os.strerror(exc.errno)}{where}: nothing was written, an earlier result is as it was",
            file=sys.stderr,
        )
        return 1
    if isinstance(exc, MemoryError):
        print(
            "error: out of memory: the machine has less free memory than the estimate assumed "
            "(other work started meanwhile?); try again, or ask for less",
            file=sys.stderr,
        )
        return 1
    if isinstance(exc, (BudgetExhausted, *_computation_failures())):
        print(f"error: {exc}", file=sys.stderr)
        return 1
    raise exc


def run(prog: str | None = None, started_s: float | None = None) -> None:
    """The console-script entry point: :func:`main`, then leave at once.

    Once the result is written and the report printed there is nothing left to do, but
    the interpreter's own shutdown (tearing down numba's compiler and a few thousand
    modules) takes about 0.3 s, a fifth of a typical command; the streams are flushed
    and the process ends without it.
    """
    _install_stop_handlers()
    status = main(prog=prog, alarm=True, started_s=started_s)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)
