"""Integrating the squeal model: the one rule for which scheme integrates a request
(:func:`choose_method`) and the one entry point (:func:`simulate`): the paper's explicit
RK4 (:func:`reduced.model.simulate_rk4`) or the exponential integrator
(:mod:`reduced.stepping`), the same model either way."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from contact.creep import ContactLaw

from .counter_body import BodyModel
from .model import Integration, Modes, OperatingPoint, TimeHistory, as_modes, simulate_rk4
from .stepping import ExponentialRun

__all__ = ["METHODS", "choose_method", "simulate"]

#: The integration methods of :func:`simulate`
METHODS = ("rk4", "exponential")


def choose_method(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    wheel_speed_rad_s: float = 0.0,
    body: BodyModel | None = None,
) -> str:
    """The one rule for how the squeal model is integrated: the exponential integrator
    (:mod:`reduced.stepping`: each linear part exact, the contact's forces solved per
    step) with a counter-body in series, whose fitted terms are fast and stiff linear
    parts that would set RK4's step; else the paper's explicit RK4 (a stiff contact, a low
    rolling speed or a light mode, shortens either's step alike)."""
    return "exponential" if body is not None and body.terms else "rk4"


def simulate(
    modes: Modes,
    contact: ContactLaw,
    operating_point: OperatingPoint,
    duration: float,
    initial_state: tuple[ArrayLike, ArrayLike] | None = None,
    *,
    wheel_speed_rad_s: float = 0.0,
    integration: Integration | None = None,
    body: BodyModel | None = None,
    preload_body: bool = False,
    **changes: Any,
) -> TimeHistory:
    """Integrate the modal squeal model for ``duration`` [s] by the method
    :func:`choose_method` names (or ``integration.method``).

    Parameters
    ----------
    modes : a ModalDOF or a sequence of them, all driven by the same contact force.
    contact : creep-law parameters.
    operating_point : rolling speed and crabbing velocity.
    duration : simulated time, s.
    initial_state : None (rest) or (y0, v0) per modal coordinate in m and m/s.
    wheel_speed_rad_s : Omega, rad/s (0: no rotation).
    integration : the step and the record (``reduced.model.Integration``, RK4's); ``changes``
        replace its fields, as in ``simulate(..., store_every=4)`` or ``method="rk4"``.
    body : the counter-body in series with the contact (``BodyModel``; None: rigid).
    preload_body : the counter-body starts in its static deflection under the steady
        creep force (a track), else at rest.

    Returns
    -------
    TimeHistory
    """
    opts = replace(integration or Integration(), **changes)
    method = opts.method or choose_method(modes, contact, operating_point, wheel_speed_rad_s, body)
    if method not in METHODS:
        raise ValueError(f"method {method!r}: one of {', '.join(METHODS)}")
    if method == "rk4":
        return simulate_rk4(
            modes,
            contact,
            operating_point,
            duration,
            initial_state,
            wheel_speed_rad_s=wheel_speed_rad_s,
            integration=opts,
            body=body,
        )
    start = None
    if initial_state is not None:
        start = (np.asarray(initial_state[0], float), np.asarray(initial_state[1], float))
    run = ExponentialRun(
        as_modes(modes),
        contact,
        operating_point,
        wheel_speed_rad_s,
        body,
        start,
        preload_body,
        float(duration),
    )
    run.advance(float(duration))
    return run.history()
