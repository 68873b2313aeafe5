"""A request's context: how it computes (the FE preset and band) and what it may spend
and keep (the budget, the stage cache, a process's memo of radiated modes), with its
progress; one object instead of the same five parameters through every stage."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from .budget import Budget
from .cache import StageCache
from .presets import DEFAULT_FIDELITY, DEFAULT_FMAX_HZ, Fidelity, fidelity_for
from .progress import Progress

__all__ = ["RunContext"]


@dataclass
class RunContext:
    """How a request computes and what it may spend.

    Attributes
    ----------
    fidelity : Fidelity
        The FE preset (solver, elements, mesh).
    fmax_hz : float
        The band: modes up to this frequency [Hz].
    cache : StageCache or None
        The stage cache (None: compute everything, keep nothing).
    budget : Budget
        The request's limits; its time counts from its ``started_s``.
    progress : Progress
        Progress of long work (quiet by default).
    memo : dict
        What one process keeps between requests (a study's operating points): each mode's
        radiation at its frequencies, computed once.

    Examples
    --------
    >>> from wheel_squeal import RunContext
    >>> RunContext.of("fast", fmax_hz=3000.0).fidelity.name
    'fast'
    """

    fidelity: Fidelity = field(default_factory=lambda: fidelity_for(DEFAULT_FIDELITY))
    fmax_hz: float = DEFAULT_FMAX_HZ
    cache: StageCache | None = None
    budget: Budget = field(default_factory=Budget.from_environment)
    progress: Progress = field(default_factory=lambda: Progress(quiet=True))
    memo: dict[Any, Any] = field(default_factory=dict)

    @classmethod
    def of(
        cls,
        fidelity: str | Fidelity = DEFAULT_FIDELITY,
        *,
        solver: str | None = None,
        fmax_hz: float = DEFAULT_FMAX_HZ,
        cache: StageCache | None = None,
        budget: Budget | None = None,
        progress: Progress | None = None,
    ) -> RunContext:
        """A context from a preset's name (and another solver for it)."""
        fid = fidelity if isinstance(fidelity, Fidelity) else fidelity_for(fidelity, solver)
        return cls(fid, fmax_hz, cache, budget or Budget.from_environment(), progress or Progress(quiet=True))
