"""A request's context: how it computes (the FE preset and band) and what it may spend
and keep (the budget, the stage cache, a process's memo of radiated modes), with its
progress; one object instead of the same five parameters through every stage."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from .presets import DEFAULT_FIDELITY, DEFAULT_FMAX_HZ, Fidelity, fidelity_for
from .runtime.budget import Budget
from .runtime.progress import Progress
from .runtime.stage_cache import StageCache
from .types import FidelityName, SolverName

__all__ = ["MEMO_MODE_SETS_KEPT", "RunContext", "memo_get", "memo_put"]


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
        radiation at its frequencies, computed once, for the last
        :data:`MEMO_MODE_SETS_KEPT` mode sets (:func:`memo_put`).

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
        fidelity: FidelityName | Fidelity = DEFAULT_FIDELITY,
        *,
        solver: SolverName | None = None,
        fmax_hz: float = DEFAULT_FMAX_HZ,
        cache: StageCache | None = None,
        budget: Budget | None = None,
        progress: Progress | None = None,
    ) -> RunContext:
        """A context from a preset's name (and another solver for it)."""
        fid = fidelity if isinstance(fidelity, Fidelity) else fidelity_for(fidelity, solver)
        return cls(fid, fmax_hz, cache, budget or Budget.from_environment(), progress or Progress(quiet=True))


#: The mode sets whose derived results a memo keeps (the radiation of their modes, their
#: meridian slice, a curve map's tables): a curve map's or a line's contacts share one;
#: each other design brings its own, with its shapes (some 50 MB for the railway wheel),
#: and beyond this many the oldest one's entries go
MEMO_MODE_SETS_KEPT = 4
_OWNERS = ("the mode sets held, oldest first",)


def memo_get(memo: dict[Any, Any], key: Any, owner: object = None) -> Any:
    """What :func:`memo_put` kept in ``memo`` under ``key`` (None: nothing, or it was kept
    for another ``owner`` than the one given: a key holding an object's ``id`` outlives it)."""
    held = memo.get(key)
    if held is None or (owner is not None and held[0] is not owner):
        return None
    return held[1]


def memo_put(memo: dict[Any, Any], key: Any, owner: object, value: Any) -> Any:
    """Keep ``value`` in ``memo`` (a :class:`RunContext`'s) under ``key``, derived from
    ``owner`` (a mode set's shapes): the memo holds what :data:`MEMO_MODE_SETS_KEPT`
    owners gave, and a new one's arrival drops the oldest one's entries. Returns ``value``.

    Examples
    --------
    >>> memo = {}
    >>> owners = [object() for _ in range(MEMO_MODE_SETS_KEPT + 1)]
    >>> for i, o in enumerate(owners):
    ...     _ = memo_put(memo, ("x", i), o, i)
    >>> memo_get(memo, ("x", 0)) is None, memo_get(memo, ("x", 1), owners[1])
    (True, 1)
    """
    owners: list[object] = memo.setdefault(_OWNERS, [])
    if not any(o is owner for o in owners):
        owners.append(owner)
        if len(owners) > MEMO_MODE_SETS_KEPT:
            gone = owners.pop(0)
            for k in [k for k, v in memo.items() if _owned_by(v, gone)]:
                del memo[k]
    memo[key] = (owner, value)
    return value


def _owned_by(held: Any, owner: object) -> bool:
    """Whether a memo entry is one :func:`memo_put` kept for ``owner`` (a list of owners or
    anything else put there is not)."""
    return isinstance(held, tuple) and len(held) == 2 and held[0] is owner
