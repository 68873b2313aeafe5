"""The command line: ``wheel-squeal COMMAND`` (or ``python pipeline.py COMMAND``).

:func:`main` parses the arguments (:mod:`.parser`), runs the command (:mod:`.commands`)
and turns the errors a user can act on into one line on stderr: a refused request
(``RequestError``, ``DesignError``) exits with status 2, a computation that failed
(``MeshError``, ``EigenError``, ``IntegrationError``) with status 1. Anything else is a
bug: its traceback is shown, exit status 1.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import warnings
from collections.abc import Sequence

from geometry import DesignError

from ..errors import RequestError
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


def _terminate(signum, frame) -> None:
    raise Terminated


def main(argv: Sequence[str] | None = None, prog: str | None = None) -> int:
    """Run the command line; returns the exit status (0 done, 1 computation failed or a
    bug, 2 request refused, 130 interrupted, 143 terminated)."""
    args = build_parser(prog or os.path.basename(sys.argv[0]) or "wheel-squeal").parse_args(argv)
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _terminate)
    if not os.environ.get("DISPLAY"):
        # Without an X server VTK tries X first and warns before falling back to EGL;
        # go straight to EGL (off-screen) so the terminal stays clean.
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    draws = args.command in DRAWING_COMMANDS
    with warnings.catch_warnings(), plot_workers() if draws else contextlib.nullcontext() as plots:
        warnings.showwarning = _one_line_warning
        try:
            from .commands import COMMANDS  # after the plot process started: it imports meanwhile

            command = COMMANDS[args.command]
            return command(args, plots) if draws else command(args)
        except (RequestError, DesignError) as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
        except Terminated:
            print("terminated", file=sys.stderr)
            return 143
        except KeyboardInterrupt:
            print("interrupted", file=sys.stderr)
            return 130
        except BrokenPipeError:
            # The reader of stdout left (``| head``): the results are written, the
            # rest of the report has nowhere to go.
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            return 141
        except Exception as exc:
            if isinstance(exc, _computation_failures()):
                print(f"error: {exc}", file=sys.stderr)
                return 1
            raise


def run(prog: str | None = None) -> None:
    """The console-script entry point: :func:`main`, then leave at once.

    Once the result is written and the report printed there is nothing left to do, but
    the interpreter's own shutdown (tearing down numba's compiler and a few thousand
    modules) takes about 0.3 s, a fifth of a typical command; the streams are flushed
    and the process ends without it.
    """
    status = main(prog=prog)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)
