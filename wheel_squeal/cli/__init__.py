"""The command line: ``wheel-squeal COMMAND`` (or ``python pipeline.py COMMAND``).

:func:`main` parses the arguments (:mod:`.parser`), runs the command (:mod:`.commands`)
and turns the errors a user can act on into one line on stderr: a refused request
(``RequestError``, ``DesignError``) exits with status 2, a computation that failed
(``MeshError``, ``EigenError``, ``IntegrationError``, ``CurvingError``) with status 1.
Anything else is a bug: its traceback is shown, exit status 1.
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import os
import re
import signal
import sys
import warnings
from collections.abc import Callable, Sequence
from typing import Any

from geometry import DesignError

from ..plotting import plot_workers
from ..runtime.library_folders import LibraryFolders, keep_library_files
from ..runtime.pools import keep_freed_memory
from ..runtime.request_errors import BudgetExhausted, RequestError
from ..runtime.stage_cache import StageCache
from .parser import DRAWING_COMMANDS, build_parser
from .stops import STATE, STOPS, Terminated, install_stop_handlers, stop_line, uninterrupted

__all__ = ["main", "run", "uninterrupted"]

#: The anticipated failures of a computation: (module, exception name).
_COMPUTATION_FAILURES = (
    ("geometry.mesh", "MeshError"),
    ("fem.eigen", "EigenError"),
    ("reduced.model", "IntegrationError"),
    ("track.bogie_curving", "CurvingError"),
)


def _computation_failures() -> tuple[type, ...]:
    """Those failure types whose modules are loaded (one not loaded cannot have been
    raised), so that catching them imports nothing."""
    return tuple(getattr(sys.modules[m], name) for m, name in _COMPUTATION_FAILURES if m in sys.modules)


def _one_line_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    file: object = None,
    line: str | None = None,
) -> None:
    print(f"warning: {str(message).splitlines()[0]}", file=sys.stderr)


def _warnings_for(cache: StageCache | None) -> Callable[..., None]:
    """How the command shows a warning: in one line; a cache write of a library (numba's
    compiled kernels, whose folder is in the cache) that failed goes the cache's one way
    for failed writes, so that a full cache gives one warning, not one per writer."""

    def show(message: Warning | str, category: type[Warning], *rest: Any, **kw: Any) -> None:
        error = getattr(message, "error", None)
        if cache is not None and cache.enabled and category.__name__ == "CompiledCodeNotKept":
            cache.cannot_store(error if isinstance(error, OSError) else OSError(str(message)))
            return
        _one_line_warning(message, category, *rest, **kw)

    return show


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
    keep_freed_memory()  # this process's own work, as each worker's
    STATE.holding = STATE.committed = STATE.retiring = False  # a new command in this process
    if not os.environ.get("DISPLAY"):
        # Without an X server VTK tries X first and warns before falling back to EGL;
        # go straight to EGL (off-screen) so the terminal stays clean.
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    draws = args.command in DRAWING_COMMANDS
    libraries: LibraryFolders | None = None
    try:  # around the plot process too: a stop may land while it shuts down
        with contextlib.ExitStack() as stack:
            stack.enter_context(warnings.catch_warnings())
            warnings.showwarning = _one_line_warning
            # the libraries' own files go into the cache before any library is loaded (the
            # plot process loads matplotlib and VTK as it starts)
            cache = _stage_cache(args)
            warnings.showwarning = _warnings_for(cache)
            libraries = keep_library_files(cache)
            if libraries.temporary is not None:
                STATE.temporary_folders.append(str(libraries.temporary))
            plots = stack.enter_context(plot_workers()) if draws else None
            from .commands import COMMANDS  # after the plot process started: it imports meanwhile
            from .common import settings_of

            budget = settings_of(args)  # the flags and environment, checked before any work
            if alarm and budget is not None and budget.seconds_left() > 0:
                # (a budget spent before any work is refused by the first estimate instead)
                STATE.budget_s = budget.max_seconds
                signal.setitimer(signal.ITIMER_REAL, budget.seconds_left())
            command = COMMANDS[args.command]
            status = command(args, plots) if draws else command(args)
    except BaseException as exc:
        status = _status_of(exc)
    finally:
        if alarm:
            signal.setitimer(signal.ITIMER_REAL, 0.0)
        if libraries is not None:
            libraries.remove()
    return status


def _stage_cache(args: argparse.Namespace) -> StageCache | None:
    """The command's stage cache, made once here so that the libraries' folders can be in
    it (``cli.common.cache_of`` returns the same one); None for a command without one."""
    if not hasattr(args, "cache_dir"):
        return None
    cache = args._cache = StageCache(args.cache_dir, enabled=not getattr(args, "no_cache", False))
    return cache


#: The settings the application's messages name in the API's words, and the flag a
#: command-line user gives instead (the API names no flag; the command line names its own).
FLAG_OF_SETTING = {
    "max_seconds": "--max-seconds S",
    "max_dofs": "--max-dofs N",
    "fmax_hz": "--fmax",
    "remedy=False": "--no-remedy",
}
_SETTING = re.compile("|".join(rf"(?<![\w-]){re.escape(k)}(?![\w-])" for k in FLAG_OF_SETTING))


def in_flags(message: str) -> str:
    """An application message with the settings it names as the command line's flags."""
    return _SETTING.sub(lambda m: FLAG_OF_SETTING[m.group(0)], message)


def _status_of(exc: BaseException) -> int:
    """The exit status of a command that raised ``exc``, with its one line on stderr
    (a bug's traceback is re-raised)."""
    if STATE.received and not STATE.committed:  # a signal stopped it, whatever the exception became
        print(stop_line(STATE.received[0], STATE.budget_s), file=sys.stderr)
        return STOPS[STATE.received[0]][1]
    if isinstance(exc, RequestError | DesignError):
        print(f"error: {in_flags(str(exc))}", file=sys.stderr)
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
        print(f"error: {in_flags(str(exc))}", file=sys.stderr)
        return 1
    raise exc


def run(prog: str | None = None, started_s: float | None = None) -> None:
    """The console-script entry point: :func:`main`, then leave at once.

    Once the result is written and the report printed there is nothing left to do, but
    the interpreter's own shutdown (tearing down numba's compiler and a few thousand
    modules) takes a noticeable share of a short command; the streams are flushed and
    the process ends without it.
    """
    try:  # a stop may land as soon as its handler is in place, before the handlers are all set
        install_stop_handlers()
        status = main(prog=prog, alarm=True, started_s=started_s)
        sys.stdout.flush()
        sys.stderr.flush()
    except KeyboardInterrupt:  # a stop outside the command (its result, if any, is written)
        status = _status_of(KeyboardInterrupt())
    os._exit(status)
