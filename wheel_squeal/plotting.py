"""Plots drawn in a child process that imports matplotlib while the command computes.

A command that writes figures runs inside :func:`plot_workers`, started as soon as its
arguments are parsed, so that matplotlib's import overlaps the command's work. The
command ``submit``s each file's writer and ``draw``s them all at the end: the plot
process forks up to one child per core, which share its imports, and they write the
files side by side. Importing matplotlib once instead of in every drawing process
leaves the cores to the computation. Without ``fork`` (not POSIX) the files are written
in this process, in order. Every process here ends when its parent does, also when the
parent is killed.
"""

from __future__ import annotations

import contextlib
import importlib
import multiprocessing
import os
import signal
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from typing import Any

from .runtime.budget import usable_cores

__all__ = ["PLOT_MODULES", "PlotWorkers", "plot_workers"]

#: What the plot process imports while it waits: matplotlib's object API on the Agg
#: canvas, and the modules whose writers draw the commands' figures.
PLOT_MODULES = (
    "matplotlib.figure",
    "matplotlib.backends.backend_agg",
    "matplotlib.tri",
    "reduced.summaries",
    "wheel_squeal.present.figures",
    "wheel_squeal.present.sound_figures",
)

_Job = tuple[Callable, tuple, dict]


def _follow_parent() -> None:
    """End this process when its parent is gone (killed before it could stop it): an
    orphan would wait for work forever, holding the parent's output streams open."""
    parent = os.getppid()

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.25)
        os._exit(1)

    threading.Thread(target=watch, daemon=True).start()


def _start_plot_process(modules: Sequence[str]) -> None:
    # a process group of its own, which its drawing children share: the parent stops
    # them all at once (:func:`_stop_plot_processes`), and a stop signal sent to the
    # parent's group (Ctrl-C, ``timeout``) is the parent's alone to handle
    with contextlib.suppress(OSError):
        os.setpgid(0, 0)
    _follow_parent()
    for name in modules:
        importlib.import_module(name)


def _write(job: _Job) -> None:
    fn, args, kwargs = job
    fn(*args, **kwargs)


def _write_all(jobs: list[_Job], processes: int) -> None:
    """Run in the plot process: every job, on up to ``processes`` children forked from it."""
    if processes < 2 or len(jobs) < 2:
        for job in jobs:
            _write(job)
        return
    fork = multiprocessing.get_context("fork")
    with ProcessPoolExecutor(min(processes, len(jobs)), mp_context=fork, initializer=_follow_parent) as pool:
        for future in [pool.submit(_write, job) for job in jobs]:
            future.result()


class PlotWorkers:
    """Files to write: ``submit(fn, *args, **kwargs)`` queues ``fn(*args, **kwargs)``,
    :meth:`draw` writes everything queued (in the plot process when there is one) and
    re-raises the first error."""

    def __init__(self, executor: ProcessPoolExecutor | None, processes: int):
        self.executor = executor
        self.processes = processes
        self.jobs: list[_Job] = []
        self.drawn = False

    def submit(self, fn: Callable[..., Any], *args: Any, **kwargs: Any) -> None:
        self.jobs.append((fn, args, kwargs))

    def draw(self) -> None:
        jobs, self.jobs = self.jobs, []
        if self.executor is None:
            _write_all(jobs, 1)
        elif jobs:
            # one message: objects that several writers share are pickled once
            future: Future = self.executor.submit(_write_all, jobs, self.processes)
            self.drawn = True
            try:
                future.result()
            except BaseException:
                # stopped (or failed) while drawing: no process may go on writing into a
                # result folder that is being removed
                _stop_plot_processes()
                raise


def _stop_plot_processes() -> None:
    """Kill the plot process and its drawing children (their own process group) and wait
    for them."""
    for child in multiprocessing.active_children():
        with contextlib.suppress(OSError):
            if child.pid is not None and os.getpgid(child.pid) == child.pid:
                os.killpg(child.pid, signal.SIGKILL)
                child.join(5.0)


@contextlib.contextmanager
def plot_workers(processes: int | None = None) -> Iterator[PlotWorkers]:
    """:class:`PlotWorkers` for the ``with`` block, their process started (and importing
    :data:`PLOT_MODULES`) at once; ``processes``: children drawing side by side (default:
    the cores this process may use). Leaving the block discards what was not drawn."""
    processes = processes or usable_cores()
    if "fork" not in multiprocessing.get_all_start_methods():
        yield PlotWorkers(None, 1)
        return
    fork = multiprocessing.get_context("fork")
    ex = ProcessPoolExecutor(1, mp_context=fork, initializer=_start_plot_process, initargs=(PLOT_MODULES,))
    ex.submit(int)  # the first task starts the process (and its imports) now
    workers = PlotWorkers(ex, processes)
    try:
        yield workers
    finally:
        # A plot process that drew is idle: stop it. One that did not (a refused request)
        # may still be importing: it stops when that is done, or when this process ends.
        ex.shutdown(wait=workers.drawn, cancel_futures=True)
