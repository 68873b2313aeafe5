"""A pool of local worker processes that knows which case each one runs.

Each worker process runs one case at a time, sent to it over its own pipe, so that
when a worker dies (killed, out of memory, a crash in a native library) exactly the
case it was running is charged with the death; the other workers go on and a new one
takes the dead one's place. Workers die with the process that started them (Linux
``PR_SET_PDEATHSIG``, and a check of the parent's pid), whether it ends, is killed with
SIGKILL or stops on SIGTERM; they ignore SIGINT (the parent handles Ctrl-C and stops
them). Each worker runs its native libraries' thread pools (BLAS, OpenMP) on its share
of the cores (:func:`blas_threads_per_worker`) and keeps freed memory for reuse
(:func:`keep_freed_memory`).
"""

from __future__ import annotations

import contextlib
import ctypes
import multiprocessing as mp
import os
import signal
import sys
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from typing import Any

from .budget import usable_cores

__all__ = ["Death", "blas_threads_per_worker", "keep_freed_memory", "run_on_pool"]

#: prctl's option: the signal a process gets when its parent thread ends (Linux).
_PR_SET_PDEATHSIG = 1


def die_with_parent(parent_pid: int) -> None:
    """Make this process receive SIGKILL when its parent ends (Linux; elsewhere a no-op),
    and end now if the parent already has."""
    if sys.platform.startswith("linux"):
        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGKILL)
    if os.getppid() != parent_pid:  # the parent ended before prctl took effect
        os._exit(1)


def blas_threads_per_worker(workers: int) -> int:
    """The BLAS and OpenMP threads each of ``workers`` processes may run: the cores this
    process may use (``wheel_squeal.runtime.budget.usable_cores``) shared out, at least one. The
    native libraries' own default (every core in each process) oversubscribes the machine:
    two workers each factorising a radiation's air on two threads of a 2-core machine took
    3.6-4.0 s a solve against 0.9 s on one thread each."""
    return max(1, usable_cores() // max(1, workers))


#: glibc's malloc gives an array beyond its mmap threshold fresh pages from the system and
#: hands freed memory at the heap's top back beyond its trim threshold: numpy's temporaries
#: of a megabyte or so (a harmonic balance's grid, a radiation's assembly) then pay a page
#: fault per page on every use, as much as their arithmetic or more (a limit-cycle
#: prediction several times slower than with them kept). A process keeps arrays below
#: MMAP_THRESHOLD_BYTES on its heap and up to KEPT_FREE_BYTES of freed memory for reuse.
MMAP_THRESHOLD_BYTES = 32 * 2**20
KEPT_FREE_BYTES = 128 * 2**20
#: mallopt's parameters (glibc's malloc.h)
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3


def keep_freed_memory() -> bool:
    """Have this process's allocator keep freed memory for reuse (:data:`KEPT_FREE_BYTES`;
    glibc, elsewhere a no-op); whether it took the setting."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None)
        return bool(
            libc.mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES)
            and libc.mallopt(_M_TRIM_THRESHOLD, KEPT_FREE_BYTES)
        )
    except (OSError, AttributeError):
        return False


def _worker(conn: Connection, parent_pid: int, task: Callable, threads: int) -> None:
    from threadpoolctl import threadpool_limits

    die_with_parent(parent_pid)
    threadpool_limits(limits=threads)  # set now, for the worker's life
    keep_freed_memory()
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    while True:
        try:
            message = conn.recv()
        except EOFError:
            return
        if message is None:
            return
        i, job = message
        try:
            conn.send((i, task(job), None))
        except Exception as exc:  # a bug in the task: the parent re-raises it
            conn.send((i, None, exc))


@dataclass
class _Slot:
    process: mp.process.BaseProcess
    conn: Connection
    case: int | None = None


@dataclass(frozen=True)
class Death:
    """A case whose worker died ``count`` times (the caller decides when to give up)."""

    case: int
    count: int


def run_on_pool(
    n: int,
    jobs: Mapping[int, Any],
    task: Callable,
    done: Callable[[int, Any], None],
    died: Callable[[Death], bool],
) -> None:
    """Run ``task(job)`` for every job on ``n`` worker processes; ``done(i, result)`` as
    each finishes. When the worker running case i dies, ``died(Death(i, count))`` is
    asked whether to submit it again (True) or not (False). A task that raises re-raises
    in this process. Every worker is stopped on return, on an exception and on
    KeyboardInterrupt."""
    ctx = mp.get_context("fork")
    threads = blas_threads_per_worker(n)
    queue = list(jobs)
    deaths = dict.fromkeys(jobs, 0)
    slots: list[_Slot] = []

    def start() -> _Slot:
        parent, child = ctx.Pipe()
        p = ctx.Process(target=_worker, args=(child, os.getpid(), task, threads), daemon=True)
        p.start()
        child.close()
        return _Slot(p, parent)

    try:
        slots = [start() for _ in range(min(n, len(queue)))]
        while queue or any(s.case is not None for s in slots):
            for s in slots:
                if s.case is None and queue:
                    s.case = queue.pop(0)
                    s.conn.send((s.case, jobs[s.case]))
            busy = [s for s in slots if s.case is not None]
            ready = wait([s.conn for s in busy] + [s.process.sentinel for s in busy])
            for s in busy:
                if s.conn in ready or s.process.sentinel in ready:
                    try:  # a result sent just before the worker ended is still read
                        i, result, error = s.conn.recv() if s.conn.poll() else (None, None, None)
                    except (EOFError, OSError):
                        i = None
                    if i is not None:
                        s.case = None
                        if error is not None:
                            raise error
                        done(i, result)
                        continue
                if not s.process.is_alive() and s.case is not None:
                    i = s.case
                    deaths[i] += 1
                    s.process.join()
                    s.conn.close()
                    new = start()
                    s.process, s.conn, s.case = new.process, new.conn, None
                    if died(Death(i, deaths[i])):
                        queue.insert(0, i)
    finally:
        for s in slots:
            with contextlib.suppress(OSError, ValueError):
                s.conn.close()
            if s.process.is_alive():
                s.process.kill()
        for s in slots:
            s.process.join(5)
