"""Bessel functions of integer order at many real arguments, as the far field of a ring
source needs them: J_n at every pair of a body's quadrature points and the directions
looked at (hundreds of thousands of arguments in a bounded range).

``scipy.special.jv`` costs about half a microsecond an argument at any order; the far field
spent most of its time there. :func:`bessel_j` tabulates J_n once on a uniform grid over
the arguments' range (with ``jv``) and interpolates between its nodes by cubic Hermite
polynomials on the exact values and slopes (J_n' = (J_{n-1} - J_{n+1}) / 2). The error of
cubic Hermite interpolation is at most h^4 / 384 max |f''''| and every derivative of J_n
is bounded by 1, so the grid step :data:`TABLE_STEP` bounds the error by 1e-11 whatever the
order and the argument.
"""

from __future__ import annotations

import functools

import numpy as np

__all__ = ["TABLE_STEP", "BesselTable", "bessel_j"]

#: The table's argument step: h^4 / 384 = 1.2e-11 (module docstring)
TABLE_STEP = 2.0**-7


def bessel_j(order: int, x: np.ndarray) -> np.ndarray:
    """J_order(x) for an integer ``order`` (of either sign) at real ``x`` >= 0 (any shape),
    to 1e-11 absolute (module docstring)."""
    x = np.asarray(x, dtype=float)
    if x.size == 0:
        return np.zeros_like(x)
    return BesselTable((order,), float(np.max(x)))(x)[0]


#: Tables are made in whole blocks of this many nodes (:class:`BesselTable`)
TABLE_BLOCK = 1024


@functools.lru_cache(maxsize=32)
def _tabulated(orders: tuple[int, ...], count: int) -> tuple[np.ndarray, list[np.ndarray], list[np.ndarray]]:
    """The nodes and each order's values and slopes there (read-only: shared)."""
    from scipy.special import jv

    nodes = np.arange(count) * TABLE_STEP
    values = [jv(n, nodes) for n in orders]
    slopes = [0.5 * (jv(n - 1, nodes) - jv(n + 1, nodes)) for n in orders]
    for a in (nodes, *values, *slopes):
        a.setflags(write=False)
    return nodes, values, slopes


class BesselTable:
    """J_n for each integer n of ``orders`` tabulated up to the argument ``largest``
    (module docstring); called with arguments in [0, largest], the values of each order,
    to 1e-11 absolute. The tables are made once for many calls (a far field's blocks)."""

    def __init__(self, orders: tuple[int, ...], largest: float) -> None:
        # the node count rounded up to a whole block: the fields of a process share tables
        count = -(-(int(largest / TABLE_STEP) + 2) // TABLE_BLOCK) * TABLE_BLOCK
        self.nodes, self.values, self.slopes = _tabulated(tuple(orders), count)

    def __call__(self, x: np.ndarray) -> tuple[np.ndarray, ...]:
        x = np.asarray(x, dtype=float)
        if x.size and (np.min(x) < 0.0 or np.max(x) > self.nodes[-1]):
            raise ValueError(f"the table holds arguments in [0, {self.nodes[-1]:g}]")
        h = TABLE_STEP
        u = x / h
        i = np.minimum(u.astype(np.intp), len(self.nodes) - 2)
        t = u - i
        t2 = t * t
        t3 = t2 * t
        # the cubic Hermite basis on [0, 1]
        h00 = 2.0 * t3 - 3.0 * t2 + 1.0
        h10 = h * (t3 - 2.0 * t2 + t)
        h01 = 1.0 - h00
        h11 = h * (t3 - t2)
        j = i + 1
        return tuple(
            h00 * v[i] + h10 * s[i] + h01 * v[j] + h11 * s[j] for v, s in zip(self.values, self.slopes)
        )
