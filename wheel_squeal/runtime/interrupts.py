"""What a stop signal may interrupt, and what it must not: the state the command line's
stop handlers keep (:mod:`wheel_squeal.cli.stops` installs them), the spans they hold a
stop back over, and a result's commit.

A stop (SIGTERM, SIGINT, the time budget's alarm) raises its exception in the main
thread at once, so that the usual clean-up runs; within :func:`uninterrupted` it waits
until the span ends (native libraries that do not survive an exception between their
calls). Once a result folder is being put in place (:func:`committing`) a stop no longer
interrupts the request: the new result is complete, the old one is removed, and the
command ends as it would have (exit status 0), never with a half-deleted result beside
it. Without the handlers (the Python API) nothing here changes how a signal acts.
"""

from __future__ import annotations

import contextlib
import signal
from collections.abc import Iterator
from dataclasses import dataclass, field

__all__ = ["STATE", "STOPS", "OutOfTime", "StopState", "Terminated", "committing", "uninterrupted"]


class Terminated(KeyboardInterrupt):
    """SIGTERM (sent by timeout, batch schedulers, systemd): stop as on Ctrl-C, so that
    the same clean-up runs (staging folders removed, worker processes stopped)."""


class OutOfTime(KeyboardInterrupt):
    """The request's time budget ran out while it worked (SIGALRM, armed by the command
    line for the time left): stop as on Ctrl-C, then report the budget."""


#: The signals that stop a command, the exception each raises in the main thread, and the
#: exit status.
STOPS: dict[int, tuple[type[KeyboardInterrupt], int]] = {
    signal.SIGTERM: (Terminated, 143),
    signal.SIGINT: (KeyboardInterrupt, 130),
    signal.SIGALRM: (OutOfTime, 1),
}


@dataclass
class StopState:
    """This process's stop signals: those received, in order (a library that turns the
    exception a signal raised into another one, as some do during an import, cannot hide
    it), the time budget the alarm was armed with [s], whether a stop is held back until
    the work under way ends (:func:`uninterrupted`), and whether a result is being or has
    been committed (:func:`committing`: a stop then ends nothing; ``retiring``: an
    earlier result still being removed), and the temporary folders the command made that
    a stop must remove too (``temporary_folders``: the libraries' files under
    ``--no-cache``)."""

    received: list[int] = field(default_factory=list)
    budget_s: float | None = None
    holding: bool = False
    committed: bool = False
    retiring: bool = False
    temporary_folders: list[str] = field(default_factory=list)

    def reset(self) -> None:
        """A new command in this process (the tests run several)."""
        self.received.clear()
        self.budget_s = None
        self.holding = self.committed = self.retiring = False
        self.temporary_folders.clear()


STATE = StopState()


@contextlib.contextmanager
def uninterrupted() -> Iterator[None]:
    """Hold a stop signal back until the block ends, then stop: for native libraries that
    do not survive an exception raised between their calls (VTK's off-screen rendering
    crashes as it unwinds). The watcher still ends the process after its grace period."""
    if STATE.committed:  # nothing interrupts a committed request
        yield
        return
    STATE.holding = True
    try:
        yield
    finally:
        STATE.holding = False
    if STATE.received:
        raise STOPS[STATE.received[0]][0]


@contextlib.contextmanager
def committing() -> Iterator[None]:
    """The span in which a result folder is put in place and the earlier one removed:
    from its start a stop is held back for good (the request ends as if none had come),
    and the earlier result's removal (``retiring``) is waited for by the stop watcher."""
    STATE.holding = True
    STATE.retiring = True
    try:
        yield
        STATE.committed = True
    finally:
        STATE.retiring = False
