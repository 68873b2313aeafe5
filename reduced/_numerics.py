"""The thread rule of the reduced model's dense linear algebra.

:func:`one_blas_thread`: the model's eigen-solves are many small dense problems
(``numpy.linalg.eig``, LAPACK's geev, which is mostly serial). Left to a multi-threaded
BLAS they gain nothing alone and lose up to ten times on a busy machine, where the BLAS
threads of several processes fight for the same cores; on one thread each solve costs
what its estimate says whatever else runs.
"""

from __future__ import annotations

import contextlib
import functools
from collections.abc import Iterator
from typing import Any

__all__ = ["one_blas_thread"]


@functools.cache
def _blas_pools() -> tuple[Any, ...]:
    """The loaded BLAS libraries' thread controls (``threadpoolctl``), found once: the
    inspection of the loaded libraries takes tens of microseconds."""
    import numpy.linalg  # noqa: F401  (its BLAS loaded before the inspection)
    from threadpoolctl import ThreadpoolController

    return tuple(c for c in ThreadpoolController().lib_controllers if c.user_api == "blas")


@contextlib.contextmanager
def one_blas_thread() -> Iterator[None]:
    """Run the block with BLAS and LAPACK on one thread, each library's own count set
    back after it (a few microseconds; none where every library runs on one already, as
    in a dask worker)."""
    pools = _blas_pools()
    before = [c.num_threads for c in pools]
    if all(n == 1 for n in before):
        yield
        return
    for c in pools:
        c.set_num_threads(1)
    try:
        yield
    finally:
        for c, n in zip(pools, before):
            c.set_num_threads(n)
