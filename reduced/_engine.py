"""Which form of the RK4 kernels runs: interpreted, or compiled by numba.

Loading numba and the cached machine code of the kernels costs, once per process, as
much as interpreting some 10^5 scalar RK4 steps (``benchmarks/run_all.py`` measures
where the two break even). So a single short run of a
one-coordinate model (the paper's case, the command line's default) is interpreted, and
everything else (several coordinates, long records, sweeps, any run in a process that
has already loaded the compiled kernels) runs compiled. Both forms execute the same
source with the same IEEE operations in the same order and give the same bits
(``tests/test_reduced_dynamics.py`` checks it), so the choice changes the speed only.
"""

from __future__ import annotations

import functools
import types

from . import _kernels

#: the kernels, each with whether its compiled twin runs its ``prange`` loop in parallel
_KERNELS = {
    "lateral_force": False,
    "_participation": False,
    "_deriv": False,
    "_rk4_step": False,
    "_rk4_step_1": False,
    "_energy": False,
    "integrate_store_1": False,
    "integrate_store": False,
    "extract_cycles": False,
    "sweep_kernel": True,
}

#: the most scalar RK4 steps (or samples split into cycles) run interpreted
INTERPRETED_MAX_STEPS = 100_000


@functools.cache
def compiled() -> types.SimpleNamespace:
    """The numba-compiled twins of :mod:`reduced._kernels` (cache=True), loaded once per
    process: each twin is the kernel's own code with its calls bound to the other twins."""
    import numba

    namespace = dict(vars(_kernels), prange=numba.prange)
    for name, parallel in _KERNELS.items():
        kernel = getattr(_kernels, name)
        twin = types.FunctionType(kernel.__code__, namespace, kernel.__name__, kernel.__defaults__)
        twin.__qualname__, twin.__module__ = kernel.__qualname__, kernel.__module__
        twin.__doc__ = kernel.__doc__
        namespace[name] = numba.njit(cache=True, parallel=parallel)(twin)
    return types.SimpleNamespace(**{name: namespace[name] for name in _KERNELS})


def load_compiled_kernels() -> None:
    """Load the compiled kernels now, so that every later run in this process (a study
    worker's many simulations, a timed measurement) runs compiled."""
    compiled()


def is_compiled_loaded() -> bool:
    """Whether this process has loaded the compiled kernels."""
    return compiled.cache_info().currsize > 0


def kernels_for(steps: int, *, scalar: bool = True):
    """The kernels to run ``steps`` steps (or samples) with: the interpreted module for a
    short scalar job in a process without the compiled twins, the compiled twins otherwise."""
    if scalar and steps <= INTERPRETED_MAX_STEPS and not is_compiled_loaded():
        return _kernels
    return compiled()
