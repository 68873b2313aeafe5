"""The resource budget: what a request may cost before it is refused.

Every kind of work is estimated before it starts (``fem.cost`` for the FE, the RK4 step
count for sweeps, the eigen-solve count for the stability analyses, the air mesh for
sound, the case count for studies); a request beyond the budget is refused with a
:class:`~wheel_squeal.runtime.request_errors.BudgetError` that states the estimate and how to proceed.

Limits, each from the API argument / CLI flag, else the environment, else the default:

- size of the modal solve: ``max_dofs`` / ``--max-dofs`` / ``WHEEL_SQUEAL_MAX_DOFS``,
  default :data:`DEFAULT_MAX_DOFS` (the accurate 3-D preset of the Table 1 wheel is
  1.4 million);
- run time: ``max_seconds`` / ``--max-seconds`` / ``WHEEL_SQUEAL_MAX_SECONDS``, default
  :data:`DEFAULT_MAX_SECONDS`;
- memory: :data:`MEMORY_FRACTION` of the memory available when the budget is made
  (:func:`available_memory`: the system's, the cgroup's and ``ulimit -v``); not a
  setting: beyond it the machine swaps or kills the run;
- the size of each file written: :data:`MAX_FILE_BYTES` (a mode-shape VTU of every mode
  becomes one of the verdict's mode alone beyond it; a sound file is cut to its last
  seconds).
"""

from __future__ import annotations

import contextlib
import math
import os
import resource
import time
from dataclasses import dataclass, field
from pathlib import Path

from .request_errors import BudgetError, BudgetExhausted, RequestError

__all__ = [
    "Budget",
    "CostPlan",
    "DEFAULT_MAX_DOFS",
    "DEFAULT_MAX_SECONDS",
    "MAX_FILE_BYTES",
    "MEMORY_FRACTION",
    "machine_slowdown",
    "usable_cores",
]

DEFAULT_MAX_DOFS = 2_000_000
DEFAULT_MAX_SECONDS = 1800.0
#: The largest file a command writes [bytes].
MAX_FILE_BYTES = 200e6
MEMORY_FRACTION = 0.75
ENV_MAX_DOFS = "WHEEL_SQUEAL_MAX_DOFS"
ENV_MAX_SECONDS = "WHEEL_SQUEAL_MAX_SECONDS"


def usable_cores() -> int:
    """The cores this process may run on (its affinity where the system says it)."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def available_memory() -> float:
    """Memory a new computation may use [bytes]: the smallest of the memory the system
    has available (Linux MemAvailable, else the physical memory), the cgroup's limit
    (containers, batch schedulers) and the process's address-space limit (ulimit -v)."""
    limits = []
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    limits.append(float(line.split()[1]) * 1024)
    except OSError:
        with contextlib.suppress(ValueError, OSError, AttributeError):
            limits.append(float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")))
    with contextlib.suppress(OSError, ValueError):
        cap = Path("/sys/fs/cgroup/memory.max").read_text().strip()
        if cap != "max":
            used = float(Path("/sys/fs/cgroup/memory.current").read_text())
            limits.append(float(cap) - used)
    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft != resource.RLIM_INFINITY:
        with contextlib.suppress(OSError, ValueError):
            pages = int(Path("/proc/self/statm").read_text().split()[0])
            limits.append(soft - pages * os.sysconf("SC_PAGE_SIZE"))
    return max(min(limits), 0.0) if limits else 8e9


def _limit(value: float | None, env: str, default: float, what: str) -> float:
    if value is None:
        text = os.environ.get(env, "").strip()
        if not text:
            return default
        try:
            value = float(text)
        except ValueError:
            raise RequestError(f"{env}={text!r} is not a number") from None
        what = env
    if not (math.isfinite(value) and value > 0):
        raise RequestError(f"{what} must be a positive number, got {value:g}")
    return float(value)


def machine_slowdown() -> float:
    """How much slower than on a quiet machine work runs now: the processes wanting a
    core per core this process may use, at least 1. Wanting a core: the 1-minute load
    average plus this process (the average lags a process just started), or the processes
    runnable at this instant where that is more (requests started together, before the
    average has seen them). An estimate measured alone holds on a busy machine times
    this (three requests at once on two cores take about twice as long each)."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    try:
        load = os.getloadavg()[0] + 1.0
    except (AttributeError, OSError):
        return 1.0
    with contextlib.suppress(OSError, ValueError, IndexError):
        with open("/proc/loadavg") as f:  # "0.50 0.40 0.30 3/120 4567": runnable/threads
            load = max(load, float(f.read().split()[3].split("/")[0]))
    return max(1.0, load / cores)


def _human_time(seconds: float) -> str:
    if seconds < 90:
        return f"{seconds:.2g} s"
    if seconds < 5400:
        return f"{seconds / 60:.2g} min"
    if seconds < 86400 * 3:
        return f"{seconds / 3600:.2g} h"
    return f"{seconds / 86400:.2g} days"


def _human_bytes(n: float) -> str:
    return f"{n / 1e9:.3g} GB" if n >= 1e9 else f"{n / 1e6:.3g} MB"


def or_raise(remedy: str, setting: str, variable: str) -> str:
    """A refusal's way out: the ``remedy`` (if any), or raising ``setting``."""
    raise_it = f"raise {setting} ({variable})"
    return f"{remedy}, or {raise_it}" if remedy.strip() else raise_it


@dataclass(frozen=True)
class Budget:
    """Limits on one request (see the module docstring); ``started_s``: when the request
    began (``time.monotonic``), from which its time is counted."""

    max_dofs: float = DEFAULT_MAX_DOFS
    max_seconds: float = DEFAULT_MAX_SECONDS
    max_memory_bytes: float = math.inf
    started_s: float = field(default_factory=time.monotonic, compare=False)
    max_file_bytes: float = MAX_FILE_BYTES
    slowdown: float = 1.0

    def elapsed_s(self) -> float:
        """Seconds since the request began."""
        return time.monotonic() - self.started_s

    def seconds_left(self) -> float:
        """Seconds the request may still run."""
        return self.max_seconds - self.elapsed_s()

    def checkpoint(self, what: str) -> None:
        """Stop the request (:class:`BudgetExhausted`) if it has run past its time
        budget; ``what``: the work under way, in words."""
        if self.seconds_left() < 0.0:
            raise BudgetExhausted(
                f"the request ran past its time budget of {_human_time(self.max_seconds)} "
                f"({_human_time(self.elapsed_s())}, during {what}); raise max_seconds "
                f"({ENV_MAX_SECONDS}) or ask for less"
            )

    @classmethod
    def from_environment(cls, max_dofs: float | None = None, max_seconds: float | None = None) -> Budget:
        """The budget of this machine: explicit limits, else the environment, else the
        defaults; memory from what is available now, and its load now
        (:func:`machine_slowdown`)."""
        return cls(
            _limit(max_dofs, ENV_MAX_DOFS, DEFAULT_MAX_DOFS, "max_dofs"),
            _limit(max_seconds, ENV_MAX_SECONDS, DEFAULT_MAX_SECONDS, "max_seconds"),
            MEMORY_FRACTION * available_memory(),
            slowdown=machine_slowdown(),
        )

    def check_solve(self, what: str, dofs: float, memory_bytes: float, seconds: float, remedy: str) -> None:
        """Refuse a modal solve of ``dofs`` DOFs estimated at ``memory_bytes`` and
        ``seconds``; ``what`` names the request, ``remedy`` the cheaper alternative."""
        seconds *= self.slowdown
        cost = (
            f"{what} would need about {dofs:,.0f} DOFs, {_human_bytes(memory_bytes)} "
            f"and {_human_time(seconds)}"
        )
        self._check_memory(cost, memory_bytes, remedy)
        if dofs > self.max_dofs:
            raise BudgetError(
                f"{cost} (limit {self.max_dofs:,.0f} DOFs); {or_raise(remedy, 'max_dofs', ENV_MAX_DOFS)}"
            )
        self._check_time(cost, seconds, remedy)

    def check_work(self, what: str, seconds: float, remedy: str, memory_bytes: float = 0.0) -> float:
        """Refuse ``what`` (a phrase naming the work) estimated at ``seconds`` on a quiet
        machine (times :attr:`slowdown` on this one now) and ``memory_bytes``; returns the
        estimated run time [s]."""
        seconds *= self.slowdown
        busy = f" on this machine's load (x{self.slowdown:.2g})" if self.slowdown > 1.1 else ""
        cost = f"{what} would take about {_human_time(seconds)}{busy}" + (
            f" and {_human_bytes(memory_bytes)}" if memory_bytes else ""
        )
        self._check_memory(cost, memory_bytes, remedy)
        self._check_time(cost, seconds, remedy)
        return seconds

    def _check_memory(self, cost: str, memory_bytes: float, remedy: str) -> None:
        if memory_bytes > self.max_memory_bytes:
            raise BudgetError(
                f"{cost}: more memory than this machine has free "
                f"({_human_bytes(self.max_memory_bytes)} usable); {remedy}"
            )

    def _check_time(self, cost: str, seconds: float, remedy: str) -> None:
        left = self.seconds_left()
        if seconds > left:
            spent = self.max_seconds - left
            limit = _human_time(self.max_seconds) + (
                f", {_human_time(max(left, 0.0))} of it left" if spent > 1.0 else ""
            )
            raise BudgetError(f"{cost} (limit {limit}); {or_raise(remedy, 'max_seconds', ENV_MAX_SECONDS)}")


@dataclass
class CostPlan:
    """The estimated parts of one request (``add(what, seconds, memory_bytes, remedy)``),
    checked against a :class:`Budget` as a whole: the one line names the total, its
    largest parts and what would make the largest one cheaper."""

    parts: list[tuple[str, float, float, str]] = field(default_factory=list)

    def add(self, what: str, seconds: float, memory_bytes: float = 0.0, remedy: str = "") -> None:
        self.parts.append((what, float(seconds), float(memory_bytes), remedy))

    @property
    def seconds(self) -> float:
        return sum(p[1] for p in self.parts)

    @property
    def memory_bytes(self) -> float:
        return max((p[2] for p in self.parts), default=0.0)

    def check(self, budget: Budget, what: str, remedy: str) -> float:
        """Refuse the plan beyond ``budget`` (``what``: the request, in words; ``remedy``:
        how to ask for less, after the largest part's own); returns its estimated time [s]."""
        if not self.parts:
            return 0.0
        ranked = sorted(self.parts, key=lambda p: -p[1])
        named = "; ".join(f"{w} {_human_time(t)}" for w, t, _, _ in ranked[:3] if t >= 0.01 * self.seconds)
        own = ranked[0][3]
        hint = "; or ".join(h for h in (own, remedy) if h)
        return budget.check_work(f"{what} ({named})", self.seconds, hint, self.memory_bytes)
