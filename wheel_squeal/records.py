"""A squeal model's record kept in the stage cache: an unchanged request (the same modes
at the contact, contact, operating point, duration, rotation and counter-body, and the
same model code) reads its record back instead of integrating it again, and its limit
cycle is analysed from it as a fresh one is (``reduced.limit_cycle``, milliseconds).

Only a record that ended as the model ends it is kept: one cut short because the time
left did not allow a longer run is the budget's answer, not the model's."""

from __future__ import annotations

import hashlib
from typing import TYPE_CHECKING, Any

import numpy as np

from geometry.files import printable, stored_array

from .runtime.provenance import code_version
from .runtime.stage_cache import CacheMiss, StageCache

if TYPE_CHECKING:
    from reduced import BodyModel, ContactLaw, ModalDOF, OperatingPoint, TimeHistory

__all__ = ["RECORD_STAGE", "load_record", "record_key", "store_record"]

#: The cache's stage of the records
RECORD_STAGE = "record"
#: The record's series an entry keeps (the rest is the request's own)
SERIES = (
    "t",
    "y",
    "v",
    "y_modes",
    "v_modes",
    "creepage",
    "Q",
    "P",
    "u_n",
    "N",
    "t_modes",
    "v_body",
    "body_states",
)


def _body_digest(body: BodyModel | None) -> str:
    if body is None:
        return "rigid"
    h = hashlib.sha256()
    for x in (body.order, body.direction, body.a0, body.a1, body.b0, body.b1):
        h.update(np.ascontiguousarray(x).tobytes())
    return h.hexdigest()[:32]


def record_key(
    dofs: list[ModalDOF],
    contact: ContactLaw,
    op: OperatingPoint,
    duration: float | None,
    wheel_speed_rad_s: float,
    body: BodyModel | None,
    preload_body: bool,
) -> dict[str, Any]:
    """What a record depends on, and nothing else."""
    return {
        "stage": RECORD_STAGE,
        "modes": [repr(d) for d in dofs],
        "contact": repr(contact),
        "operating_point": repr(op),
        "duration_s": duration,
        "wheel_speed_rad_s": float(wheel_speed_rad_s),
        "counter_body": _body_digest(body),
        "preloaded": bool(preload_body),
        "code": code_version("reduced"),
    }


def store_record(cache: StageCache, key: dict[str, Any], history: TimeHistory) -> None:
    """Keep ``history``'s series and scalars under ``key``."""
    arrays = {
        name: np.asarray(getattr(history, name)) for name in SERIES if getattr(history, name) is not None
    }
    arrays |= {
        "step_s": np.asarray(history.step_s),
        "energy_mismatch_j": np.asarray(history.energy_mismatch_j),
        "method": np.asarray(history.method),
    }
    cache.store(RECORD_STAGE, key, arrays)


#: The series over the record's times ``t`` and over its modes' times ``t_modes``
_OVER_T = ("y", "v", "creepage", "Q", "P", "u_n", "N", "v_body")


def _checked_series(arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """A kept record's arrays, checked before use (a cache entry is untrusted input):
    finite float series of the lengths of their times, and the scalars."""
    t = stored_array(arrays, "t", "f", ndim=1)
    t_modes = stored_array(arrays, "t_modes", "f", ndim=1) if "t_modes" in arrays else t
    for name in ("y", "v", "creepage", "Q", "P", "y_modes", "v_modes"):
        arrays[name]  # noqa: B018 (a KeyError: the entry lacks a series every record has)
    for name in SERIES:
        if name in arrays and name not in ("t", "t_modes"):
            a = stored_array(arrays, name, "f", ndim=1 if name in _OVER_T else 2)
            if len(a) != (len(t) if name in _OVER_T else len(t_modes)):  # time along the first axis
                raise ValueError(f"kept series {name!r} is not over its record's times")
    if not float(stored_array(arrays, "step_s", "f", ndim=0)) > 0:
        raise ValueError("a kept record's step is not positive")
    if not printable(str(stored_array(arrays, "method", "U", ndim=0))):
        raise ValueError("a kept record's method is not a name")
    mismatch = arrays["energy_mismatch_j"]  # NaN where the method does not measure it
    if not (isinstance(mismatch, np.ndarray) and mismatch.dtype.kind == "f" and mismatch.ndim == 0):
        raise ValueError("a kept record's energy mismatch is not a number")
    return arrays


def load_record(
    cache: StageCache,
    key: dict[str, Any],
    dofs: list[ModalDOF],
    contact: ContactLaw,
    op: OperatingPoint,
    wheel_speed_rad_s: float,
    body: BodyModel | None,
) -> TimeHistory | None:
    """The record kept under ``key`` with the request's own objects around it (None: not
    kept)."""
    from reduced import TimeHistory
    from reduced.model import coordinates

    try:
        arrays = cache.load(RECORD_STAGE, key, _checked_series)
    except CacheMiss:
        return None
    series: dict[str, Any] = {name: arrays.get(name) for name in SERIES}
    return TimeHistory(
        **series,
        modes=tuple(dofs),
        contact=contact,
        operating_point=op,
        step_s=float(arrays["step_s"]),
        method=str(arrays["method"]),
        energy_mismatch_j=float(arrays["energy_mismatch_j"]),
        wheel_speed_rad_s=wheel_speed_rad_s,
        coordinates=coordinates(dofs, wheel_speed_rad_s),
        body=body,
    )
