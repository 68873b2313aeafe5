"""Measuring one run: wall time and peak memory in a fresh child process.

The child is forked from a warmed-up parent (imports and compiled kernels ready), so the
run alone is timed; its peak memory is the growth of its peak resident set (``VmHWM``,
reset at the start of the child: ``ru_maxrss`` would report the parent's peak).
"""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

__all__ = ["REPEATS", "REPEAT_BELOW_S", "fork_available", "measure", "measure_repeated"]

#: runs faster than this are repeated (median of REPEATS) to tame timing noise
REPEAT_BELOW_S = 2.0
REPEATS = 3


def _peak_rss_mb() -> float:
    """This process's peak resident set [MB] (Linux VmHWM; ru_maxrss elsewhere)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return float(line.split()[1]) / 1024.0
    except OSError:
        pass
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # KiB on Linux


def _reset_peak_rss() -> None:
    """Start the peak resident set afresh at the current one (Linux >= 4.0)."""
    try:
        Path("/proc/self/clear_refs").write_text("5")
    except OSError:
        pass


def fork_available() -> bool:
    """True where runs can be measured in a forked child (POSIX)."""
    import multiprocessing as mp

    try:
        import resource  # noqa: F401
    except ImportError:  # pragma: no cover - not POSIX
        return False
    return "fork" in mp.get_all_start_methods()


def measure(fn: Callable[[], Any], isolate: bool = True) -> tuple[Any, float, float]:
    """Run ``fn()`` and return ``(result, seconds, peak_memory_mb)``.

    With ``isolate`` (and a POSIX 'fork'), in a fresh child process: the peak memory is
    the growth of the child's peak resident set over its value at the start, so memory
    the parent already holds (imports, earlier rungs) is not counted. ``result`` must be
    picklable. Without isolation the memory is NaN. An exception in the child is
    re-raised in the parent as RuntimeError with the child's message; a child that
    dies (e.g. killed for memory) raises RuntimeError with its exit code.
    """
    if not (isolate and fork_available()):
        t = time.perf_counter()
        out = fn()
        return out, time.perf_counter() - t, float("nan")
    import multiprocessing as mp

    ctx = mp.get_context("fork")
    recv, send = ctx.Pipe(duplex=False)

    def child() -> None:
        recv.close()
        try:
            _reset_peak_rss()
            base = _peak_rss_mb()
            t = time.perf_counter()
            out = fn()
            dt = time.perf_counter() - t
            send.send((True, (out, dt, max(_peak_rss_mb() - base, 0.0))))
        except BaseException as exc:  # noqa: BLE001 - reported to the parent
            msg = f"{type(exc).__name__}: {exc}".splitlines()[0]
            send.send((False, msg))
        finally:
            send.close()

    proc = ctx.Process(target=child, daemon=True)
    proc.start()
    send.close()
    try:
        msg = recv.recv()
    except EOFError:
        msg = None
    finally:
        recv.close()
        proc.join()
    if msg is None:
        raise RuntimeError(f"child process died (exit code {proc.exitcode}; out of memory?)")
    ok, payload = msg
    if not ok:
        raise RuntimeError(payload)
    return payload


def measure_repeated(
    fn: Callable[[], Any],
    isolate: bool = True,
    repeat_below_s: float = REPEAT_BELOW_S,
    repeats: int = REPEATS,
) -> Any:
    """:func:`measure` once, and ``repeats`` times in all if the first run was quick.

    Returns ``(result of the first run, median seconds, max peak memory MB, runs)``.
    """
    out, dt, mem = measure(fn, isolate)
    times, mems = [dt], [mem]
    if dt < repeat_below_s:
        for _ in range(repeats - 1):
            _, dt, mem = measure(fn, isolate)
            times.append(dt)
            mems.append(mem)
    finite = [m for m in mems if math.isfinite(m)]
    return out, statistics.median(times), (max(finite) if finite else float("nan")), len(times)
