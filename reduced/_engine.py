"""Which form of the RK4 kernels runs: interpreted, or compiled by numba.

Loading numba and the cached machine code of the kernels costs, once per process, as
much as interpreting some 10^5 scalar RK4 steps (``benchmarks/run_all.py`` measures
where the two break even). A process does not know how many runs will follow, so it
rents before it buys: scalar (one-coordinate) integrations run interpreted until they
have taken :data:`INTERPRETED_MAX_STEPS` steps in this process, about the price of the
load, and compiled from then on. One run of the paper's model (the command line's
default) is interpreted; a loop of runs in a notebook pays at most twice the best
choice made in hindsight. Several coordinates, sweeps and any run in a process that has
loaded the compiled kernels run compiled. Both forms execute the same source with the
same IEEE operations in the same order and give the same bits
(``tests/test_reduced_dynamics.py`` checks it), so the choice changes the speed only.
"""

from __future__ import annotations

import dataclasses
import functools
import types
import warnings
from collections.abc import Callable
from typing import Any

from . import _exponential, _kernels

#: the modules of kernels (plain Python, numba-compilable), in the order their names bind
_MODULES = (_kernels, _exponential)
#: the kernels, each with whether its compiled twin runs its ``prange`` loop in parallel
_KERNELS = {
    "adhesion": False,
    "lateral_force": False,
    "normal_force": False,
    "hertz_energy": False,
    "_contact": False,
    "steady_force": False,
    "_participation": False,
    "_deriv": False,
    "_rk4_step": False,
    "_rk4_step_1": False,
    "_energy": False,
    "_total_energy": False,
    "integrate_store_1": False,
    "integrate_store": False,
    "extract_cycles": False,
    "sweep_kernel": True,
    "adhesion_slope": False,
    "_hertz": False,
    "_safeguarded": False,
    "_normal_force": False,
    "_lateral_residual": False,
    "contact_forces": False,
    "exp_integrate": False,
}

#: scalar RK4 steps a process interprets before it loads the compiled kernels
INTERPRETED_MAX_STEPS = 100_000


@dataclasses.dataclass
class _Interpreted:
    """Scalar RK4 steps this process has interpreted so far."""

    steps: int = 0


_INTERPRETED = _Interpreted()


class CompiledCodeNotKept(UserWarning):
    """numba could not write a kernel's machine code into its cache folder (a full disk,
    no permission): the kernel runs all the same, and the next process compiles it again.
    ``error`` is the failed write's ``OSError``."""

    def __init__(self, error: OSError) -> None:
        why = error.strerror or error
        super().__init__(f"the compiled kernels cannot be kept ({why}); they run all the same")
        self.error = error


def _kept_or_not(dispatcher: Any) -> Callable[..., Any]:
    """``dispatcher`` whose failure to save its machine code is a warning, not an error.

    numba adds a compiled overload to its dispatcher before it saves it, and lets the
    save's ``OSError`` out of the call; called again, the dispatcher finds the overload.
    A kernel that calls others compiles them first, each of which may fail once: at most
    one retry per kernel, then the error is real."""

    @functools.wraps(dispatcher.py_func)
    def call(*args: Any) -> Any:
        for attempt in range(len(_KERNELS) + 1):
            try:
                return dispatcher(*args)
            except OSError as exc:
                if attempt == len(_KERNELS):
                    raise
                if attempt == 0:
                    warnings.warn(CompiledCodeNotKept(exc), stacklevel=2)
        raise AssertionError("unreachable")

    return call


@functools.cache
def compiled() -> types.SimpleNamespace:
    """The numba-compiled twins of :mod:`reduced._kernels` (cache=True), made once per
    process: each twin is the kernel's own code with its calls bound to the other twins,
    and a failure to keep its machine code is a warning (:class:`CompiledCodeNotKept`)."""
    import numba

    namespace = {k: v for m in _MODULES for k, v in vars(m).items()} | {"prange": numba.prange}
    for name, parallel in _KERNELS.items():
        kernel = next(getattr(m, name) for m in _MODULES if hasattr(m, name))
        twin = types.FunctionType(kernel.__code__, namespace, kernel.__name__, kernel.__defaults__)
        twin.__qualname__, twin.__module__ = kernel.__qualname__, kernel.__module__
        twin.__doc__ = kernel.__doc__
        # nogil: a stop signal's watcher thread can run while a long kernel does
        namespace[name] = numba.njit(cache=True, parallel=parallel, nogil=True)(twin)
    return types.SimpleNamespace(**{name: _kept_or_not(namespace[name]) for name in _KERNELS})


def load_compiled_kernels() -> None:
    """Make the compiled kernels now (numba's import), so that every later run in this
    process (a study worker's many simulations, a timed measurement) runs compiled; each
    kernel's machine code is read from numba's cache at its first call."""
    compiled()


def is_compiled_loaded() -> bool:
    """Whether this process has loaded the compiled kernels."""
    return compiled.cache_info().currsize > 0


def interprets(steps: int, scalar: bool, loaded: bool, interpreted_so_far: int) -> bool:
    """The rule: interpret an integration of ``steps`` RK4 steps when it is scalar, the
    compiled kernels are not ``loaded`` and the steps interpreted so far in this process
    plus these stay within :data:`INTERPRETED_MAX_STEPS`."""
    return scalar and not loaded and interpreted_so_far + steps <= INTERPRETED_MAX_STEPS


@functools.cache
def interpreted() -> types.SimpleNamespace:
    """The kernels as they are (no compiler)."""
    return types.SimpleNamespace(
        **{name: getattr(next(m for m in _MODULES if hasattr(m, name)), name) for name in _KERNELS}
    )


def integration_kernels(steps: int, *, scalar: bool = True) -> Any:
    """The kernels for an integration of ``steps`` RK4 steps (:func:`interprets`)."""
    if interprets(steps, scalar, is_compiled_loaded(), _INTERPRETED.steps):
        _INTERPRETED.steps += steps
        return interpreted()
    return compiled()


def cycle_kernels(samples: int) -> Any:
    """The kernels to split a record of ``samples`` samples into cycles: interpreted while
    the compiled kernels are not loaded, up to 4 x :data:`INTERPRETED_MAX_STEPS` samples
    (a sample costs under a quarter of a scalar RK4 step interpreted)."""
    return interpreted() if not is_compiled_loaded() and samples <= 4 * INTERPRETED_MAX_STEPS else compiled()
