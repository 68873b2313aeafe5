"""The errors the application reports to its user as a request it cannot meet.

They are few on purpose: :class:`RequestError` (bad input, in the words of the API:
a notebook user reads ``mass_kg``, a command-line user the flag, because the CLI checks
its flags first) and its subclass :class:`BudgetError` (a request beyond the resource
budget, with its cost and how to proceed). With ``geometry.DesignError`` they are the
only exceptions the CLI turns into one line and exit status 2; the anticipated failures
of a computation (``geometry.MeshError``, ``fem.EigenError``, ``reduced.IntegrationError``,
``track.bogie_curving.CurvingError``)
and :class:`BudgetExhausted` (a request that ran past its time budget although its
estimate fitted) are one line and exit status 1; anything else is a bug and shows its
traceback.
"""

from __future__ import annotations

__all__ = ["BudgetError", "BudgetExhausted", "RequestError"]


class RequestError(ValueError):
    """A request that cannot be met as asked (bad input, unusable folder, nothing to
    select). The message is one line that names the problem; the command line prints it and
    exits with status 2.

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> try:
    ...     ws.operating_point(ws.load_design(), rpm=-1)
    ... except ws.RequestError as exc:
    ...     print(exc)
    rpm must be positive, got -1
    """


class BudgetError(RequestError):
    """A request whose estimated memory, size or run time exceeds the budget; the
    message states the estimate and how to proceed (a coarser preset, or a limit to lift).

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> try:
    ...     ws.Budget(max_seconds=1.0).check_work("ten minutes of work", 600.0, "ask for less")
    ... except ws.BudgetError as exc:
    ...     print(str(exc).split(";")[0])
    ten minutes of work would take about 10 min (limit 1 s)
    """


class BudgetExhausted(RuntimeError):
    """A request that ran past its time budget while working (its estimate fitted, the
    machine was slower): it stops where it is, nothing half-written. The message says how
    long it ran, at which stage, and how to proceed; the command line exits with status 1.

    Examples
    --------
    >>> import time
    >>> import wheel_squeal as ws
    >>> try:
    ...     ws.Budget(max_seconds=1.0, started_s=time.monotonic() - 2.0).checkpoint("the squeal model")
    ... except ws.BudgetExhausted as exc:
    ...     print(str(exc).split(" (")[0])
    the request ran past its time budget of 1 s
    """
