"""Which modes a verdict integrates, decided from the linear stability alone: the one
rule every command follows (through :func:`wheel_squeal.chain.analyse`).

- The **named mode** (the request's ``mode``, else the design's ``[squeal] mode``) is an
  override: it is integrated with the modes that share its fastest eigenvalue (alone when
  it is isolated, its partner when the two are coupled) and the counter-body's degrees of
  freedom, and reported as asked.
- The **model's own outcome** integrates together the modes of every growing eigenvalue
  (the fastest-growing eigenvalue's first, at most ``max_modes`` of them) with the
  counter-body's degrees of freedom: the mode that carries the limit cycle (the largest
  share of its vibration energy) is the squeal mode. Without a time domain the model's
  pick is the mode that holds most of the fastest-growing eigenvalue.
- Nothing grows: no squeal (nothing is integrated for the model).

An eigenvalue held by the counter-body (a light roller mode growing on its own) takes
part as its wheel modes do: the counter-body's degrees of freedom are always integrated.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .presets import MAX_MULTIMODE

if TYPE_CHECKING:
    from fem.modes import Mode

    from .mode_stability import NamedMode, StabilityTable

__all__ = ["Decision", "decide", "eigenvalue_of", "fastest_mode", "group_label", "modes_of_eigenvalue"]


@dataclass(frozen=True)
class Decision:
    """What the verdict integrates (see the module docstring).

    Attributes
    ----------
    named : fem.Mode or None
        The override (None: nothing named).
    named_by : str
        Who names it, in words ("the design table1 names").
    named_group : tuple of fem.Mode
        The override and the modes that share its fastest eigenvalue, it first.
    growing : tuple of fem.Mode
        The modes of every growing eigenvalue, fastest first, at most ``max_modes``: the
        model's own outcome integrates them together (empty: nothing grows).
    fastest : fem.Mode or None
        The model's linear pick: the mode holding most of the fastest-growing eigenvalue
        a mode of the wheel takes part in (None: nothing grows).
    left_out : int
        Modes of growing eigenvalues beyond ``max_modes``, not integrated.

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> a = ws.analyse(ws.load_design(), modes=ws.explicit_modes(3.1, 1.6e8, 42), stop_after="stability")
    >>> a.decision.fastest.label(), a.decision.named is None
    ('the given mode (1143.4 Hz)', True)
    """

    named: Mode | None
    named_by: str
    named_group: tuple[Mode, ...]
    growing: tuple[Mode, ...]
    fastest: Mode | None
    left_out: int = 0


def modes_of_eigenvalue(table: StabilityTable, j: int) -> list[int]:
    """The rows whose mode takes part in eigenvalue ``j`` (a share of its vibration
    energy of at least ``reduced.stability.PARTNER_SHARE``), largest share first."""
    from reduced.stability import PARTNER_SHARE

    shares = table.result.shares
    assert shares is not None
    n = len(table.rows)
    return [int(k) for k in np.argsort(-shares[:n, j], kind="stable") if shares[k, j] >= PARTNER_SHARE]


def eigenvalue_of(table: StabilityTable, row: int) -> int:
    """The eigenvalue that speaks for the row's mode (``reduced.StabilityResult.speaking``:
    the fastest-growing one it takes part in, :func:`modes_of_eigenvalue`, else the one
    assigned to it); a coupled pair's growing eigenvalue speaks for both its modes."""
    return table.result.speaking[row]


def fastest_mode(table: StabilityTable) -> int | None:
    """The row that holds most of the fastest-growing eigenvalue a mode of the wheel takes
    part in (``StabilityTable.fastest``; None: nothing grows)."""
    return table.fastest if table.grows else None


def _together(table: StabilityTable, row: int) -> tuple[Mode, ...]:
    """The row's mode and those that share its fastest eigenvalue, it first."""
    partners = table.rows[row].stability.partners
    n = len(table.rows)
    group = [row] + [k for k in partners if k < n and k != row]
    return tuple(table.rows[k].mode for k in group)


def decide(table: StabilityTable, named: NamedMode, max_modes: int = MAX_MULTIMODE) -> Decision:
    """The rule of the module docstring on ``table``.

    Parameters
    ----------
    table : StabilityTable
        The linear stability at the operating point.
    named : stability.NamedMode
        Who names which mode (``stability.named_mode``).
    max_modes : int
        The most modes the model's outcome integrates together.

    Returns
    -------
    Decision

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> from wheel_squeal.mode_stability import named_mode
    >>> d = ws.load_design()
    >>> modes = ws.explicit_modes(3.1, 1.6e8, 42)
    >>> t = ws.stability_table(d, modes, ws.contact_law(d), ws.operating_point(d))
    >>> len(ws.decide(t, named_mode(d.replace(squeal_mode=""), modes)).growing)
    1
    """
    row_of = {r.mode.index: k for k, r in enumerate(table.rows)}
    named_group: tuple[Mode, ...] = ()
    if named.mode is not None:
        named_group = _together(table, row_of[named.mode.index])
    lam = table.result.eigenvalues
    rows: list[int] = []
    for j in table.result.ranked():
        if lam[j].real <= 0.0:
            break
        rows += [k for k in modes_of_eigenvalue(table, j) if k not in rows]
    first = fastest_mode(table)
    fastest = table.rows[first].mode if first is not None else None
    kept = rows[:max_modes]
    return Decision(
        named.mode,
        named.source,
        named_group,
        tuple(table.rows[k].mode for k in kept),
        fastest,
        len(rows) - len(kept),
    )


def group_label(modes: Sequence[Mode]) -> str:
    """``A`` or ``A with B, C``: a mode and those integrated with it."""
    head, *rest = modes
    return head.label() + (f" with {', '.join(m.label() for m in rest)}" if rest else "")
