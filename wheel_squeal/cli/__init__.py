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
import time
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


#: Seconds a terminated command has to clean up before it ends regardless (it may be
#: inside a long native computation, where no Python code runs until it returns).
TERMINATE_GRACE_S = 5.0


def _stop_on_sigterm() -> None:
    """SIGTERM raises :class:`Terminated` in the main thread; if that has not ended the
    process within :data:`TERMINATE_GRACE_S` (a LAPACK or numba call does not return to
    Python until done), a watcher thread ends it: a half-written result stays hidden
    beside ``--out`` and is removed by the next run, and worker processes die with it."""
    r, w = os.pipe()
    os.set_blocking(w, False)
    signal.set_wakeup_fd(w)  # written by the C-level handler at once, even mid-computation
    signal.signal(signal.SIGTERM, _terminate)

    def watch() -> None:
        while signal.SIGTERM not in os.read(r, 64):
            pass
        time.sleep(TERMINATE_GRACE_S)
        os._exit(143)

    threading.Thread(target=watch, name="sigterm-watch", daemon=True).start()


def main(argv: Sequence[str] | None = None, prog: str | None = None) -> int:
    """Run the command line; returns the exit status (0 done, 1 computation failed or a
    bug, 2 request refused, 130 interrupted, 143 terminated)."""
    parser = build_parser(prog or os.path.basename(sys.argv[0]) or "wheel-squeal")
    args, unknown = parser.parse_known_args(argv)
    if unknown:  # the subcommand's own error: it points to its --help
        parser.subcommands[args.command].error(f"unrecognized arguments: {' '.join(unknown)}")
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
    _stop_on_sigterm()
    status = main(prog=prog)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)
