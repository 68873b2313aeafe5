"""Progress of long work on stderr: ``[  3.2 s] modes: done (1.9 s)``."""

from __future__ import annotations

import contextlib
import sys
import time
from collections.abc import Callable, Iterator
from typing import TextIO

__all__ = ["Progress"]


class Progress:
    """Stage progress on stderr: ``[  3.2 s] modes: done (1.9 s)``. Silent if quiet."""

    def __init__(self, quiet: bool = False, stream: TextIO | None = None) -> None:
        self.quiet = quiet
        self.stream = stream or sys.stderr
        self.t0 = time.perf_counter()
        self.timings: dict[str, float] = {}

    def say(self, text: str) -> None:
        if not self.quiet:
            print(f"[{time.perf_counter() - self.t0:6.1f} s] {text}", file=self.stream, flush=True)

    @contextlib.contextmanager
    def stage(self, name: str) -> Iterator[None]:
        self.say(f"{name} ...")
        t = time.perf_counter()
        yield
        dt = time.perf_counter() - t
        self.timings[name] = self.timings.get(name, 0.0) + dt
        self.say(f"{name}: done ({dt:.2f} s)")

    def counter(self, name: str, unit: str, every_s: float = 1.0) -> Callable[[int, int], None]:
        """A ``report(done, total)`` callback for long loops: ``name: 120/3000 cases (4 %),
        ~35 s left``, at most once every ``every_s`` seconds and at the end."""
        start = time.perf_counter()
        last = [start]

        def report(done: int, total: int) -> None:
            now = time.perf_counter()
            if done < total and now - last[0] < every_s:
                return
            last[0] = now
            rate = done / max(now - start, 1e-9)
            left = (total - done) / rate if rate > 0 else float("inf")
            self.say(
                f"{name}: {done:,}/{total:,} {unit} ({100 * done / total:.0f} %), "
                f"{rate:.3g} {unit}/s, ~{left:.0f} s left"
            )

        return report
