"""From the squeal mode to sound: the mode's surface velocity scaled to the contact's
velocity amplitude, its radiation (``acoustics``), and the levels a user is judged on.

The radiation of one mode per unit contact velocity (peak, 1 m/s) is its shape's radiation
scaled by the shape's displacement at the contact it is read at: one solve per mode and
frequency serves every contact of a curve. A limit cycle of amplitude v scales the
pressure by v and the power by v^2.
The wheel is alone in free field (no roller, shaft or floor). Levels: SPL in dB re
20 uPa of the rms pressure (a pure tone, rms = peak / sqrt 2), sound power level in dB
re 1 pW.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np

from acoustics.tone import Radiation, Sound
from geometry.files import stored_array

from .context import memo_get, memo_put
from .design import Design
from .listener import Listener, default_microphone
from .presets import DEFAULT_FIDELITY, DEFAULT_FMAX_HZ, fidelity_for
from .runtime.provenance import code_version
from .runtime.request_errors import RequestError
from .runtime.stage_cache import CacheMiss, StageCache
from .types import FidelityName

if TYPE_CHECKING:
    from acoustics import Air, RadiationCost, Surface
    from fem.modes import Mode, ModeSet

    from .runtime.budget import Budget

__all__ = [
    "mode_sound",
    "Radiation",
    "Sound",
    "mode_radiation",
    "radiation_key",
    "mode_surface",
    "check_velocity_amplitude",
    "contact_velocity_phase",
    "sound_cost",
    "sound_of",
]


def mode_surface(
    modeset: ModeSet, mode: Mode, frequency_hz: float, contact_velocity_m_s: float = 1.0
) -> Surface:
    """The mode's outline and surface velocity (``acoustics.Surface``), scaled so that
    the axial velocity amplitude at the contact is ``contact_velocity_m_s`` [m/s] (the
    velocity j w u of the shape u so scaled does not depend on ``frequency_hz``)."""
    return _shape_surface(modeset, mode, contact_velocity_m_s / _contact_amplitude(mode))


def _contact_amplitude(mode: Mode) -> float:
    """|phi| of the mode's lateral displacement at the contact it is read at; a mode that
    does not move the contact is refused."""
    v_c = abs(float(mode.contact_lateral[0]))
    if not v_c > 0:
        raise RequestError(f"mode {mode.index} ({mode.label()}) does not move the contact: it cannot squeal")
    return v_c


def _shape_peak(modeset: ModeSet, mode: Mode) -> float:
    """The largest displacement component of the mode's shape (its cos member) anywhere:
    the reference its radiation is solved for, the same whichever contact it is read at."""
    return float(np.max(np.abs(modeset.shapes[mode.index][0])))


def _shape_surface(modeset: ModeSet, mode: Mode, velocity_per_displacement: float) -> Surface:
    """The mode's outline with the surface velocity j s u: the shape u times
    ``velocity_per_displacement`` s, a quarter period ahead of the displacement."""
    from acoustics import Surface
    from fem.shapes import meridian_outline

    points, displacement = meridian_outline(modeset, mode.index)
    return Surface(points, 1j * displacement * velocity_per_displacement, int(mode.nodal_diameters))


def sound_cost(
    design: Design,
    modeset: ModeSet,
    mode: Mode,
    listener: Listener | None = None,
    frequency_hz: float | None = None,
) -> RadiationCost | None:
    """The estimated cost of radiating ``mode`` at ``frequency_hz`` (default its natural
    frequency; a harmonic at a multiple) (``acoustics.RadiationCost``), None where nothing
    would be radiated (a modal model's modes have no shapes, a mode that does not move the
    contact laterally does not squeal through it)."""
    from acoustics import AIR, radiation_cost
    from fem.modal_model import MODAL_MODEL_SOLVER

    if modeset.solver == MODAL_MODEL_SOLVER or not abs(float(mode.contact_lateral[0])) > 0:
        return None
    air = listener.air if listener is not None else AIR
    f = mode.frequency_hz if frequency_hz is None else frequency_hz
    cost = radiation_cost(mode_surface(modeset, mode, f), f, air)
    return replace(cost, seconds=cost.seconds + VIEW_SECONDS)


#: What :meth:`Radiation.of` adds to a solve: the pressure at the microphone and on the
#: plot's circle, and the far field's directivity (Kirchhoff-Helmholtz integrals over the
#: wheel) [s], on railway_920's (2,0) mode at 300 Hz
VIEW_SECONDS = 0.2


def radiation_cached(
    cache: StageCache | None,
    modes_key: dict[str, Any],
    mode: Mode,
    frequency_hz: float,
    air: Air | None = None,
) -> bool:
    """Whether ``cache`` holds ``mode``'s radiation at ``frequency_hz`` (no solve to price)."""
    from acoustics import AIR

    if cache is None:
        return False
    return cache.path("sound", radiation_key(modes_key, mode, frequency_hz, air or AIR)).is_file()


def contact_velocity_phase(mode: Mode) -> complex:
    """The complex contact velocity of :func:`mode_surface`'s surface per unit amplitude:
    j sign(phi_c) (the pressure's phase against the contact velocity divides by it)."""
    return 1j * math.copysign(1.0, float(mode.contact_lateral[0]))


def radiation_key(modes_key: dict[str, Any], mode: Mode, frequency_hz: float, air: Air) -> dict[str, Any]:
    """The cache key of a mode's radiation (its field at a unit peak velocity of its
    shape, :func:`mode_radiation`): the modes', the mode, the frequency, the air, the
    settings and the acoustics code."""
    from acoustics import RadiationSettings
    from acoustics.helmholtz import FIELD_ARRAYS

    return {
        **modes_key,
        "stage": "sound",
        "mode": mode.index,
        "velocity": "unit peak of the shape",
        "frequency_hz": round(float(frequency_hz), 6),
        "settings": repr(RadiationSettings()),
        "air": repr(air),
        "code": code_version("acoustics"),
        "stored": list(FIELD_ARRAYS),
    }


def mode_radiation(
    design: Design,
    modeset: ModeSet,
    mode: Mode,
    frequency_hz: float,
    microphone: tuple[float, float, float],
    cache: StageCache | None = None,
    modes_key: dict[str, Any] | None = None,
    air: Air | None = None,
    budget: Budget | None = None,
    memo: dict[Any, Any] | None = None,
) -> Radiation:
    """The :class:`Radiation` of ``mode`` at 1 m/s contact velocity (at the contact its
    components are read at) seen from the microphone.

    The field is solved for the mode's shape at a unit peak velocity (:func:`_shape_peak`),
    which does not depend on the contact, and scaled to the contact's velocity: the
    contacts of a curve share one solve of a mode at a frequency. It is cached beside the
    modes when ``modes_key`` (:func:`wheel_squeal.api.modes_cache_key`) is given, and so
    are the pressures at the microphone and on the plot's circle (a warm run needs no
    finite elements), and kept in ``memo`` (a dict) for later calls of the same process,
    with each contact's scaled copy (the contacts of a map repeat: their records share it);
    ``air``: ``acoustics.Air`` (default: 1.21 kg/m^3, 343 m/s); ``budget``: a
    :class:`~wheel_squeal.runtime.budget.Budget` the solve is estimated against first."""
    from acoustics import AIR

    air = air or AIR
    peak = _shape_peak(modeset, mode)
    factor = peak / _contact_amplitude(mode)
    # the moved mode sets of a curve's contacts share their shapes (the same list)
    f = round(float(frequency_hz), 6)
    memo_key = ("radiation", id(modeset.shapes), mode.index, f, repr(air), tuple(microphone[:2]))
    if memo is None:
        unit = _unit_radiation(modeset, mode, peak, frequency_hz, microphone, cache, modes_key, air, budget)
        return unit.scaled(factor)
    scaled = memo_get(memo, (*memo_key, factor), modeset.shapes)
    if scaled is not None:
        return scaled
    unit = memo_get(memo, memo_key, modeset.shapes)
    if unit is None:
        unit = _unit_radiation(modeset, mode, peak, frequency_hz, microphone, cache, modes_key, air, budget)
        memo_put(memo, memo_key, modeset.shapes, unit)
    return memo_put(memo, (*memo_key, factor), modeset.shapes, unit.scaled(factor))


def _unit_radiation(
    modeset: ModeSet,
    mode: Mode,
    peak: float,
    frequency_hz: float,
    microphone: tuple[float, float, float],
    cache: StageCache | None,
    modes_key: dict[str, Any] | None,
    air: Air,
    budget: Budget | None,
) -> Radiation:
    """The radiation of the mode's shape at a unit peak velocity (its shape's ``peak``,
    :func:`mode_radiation`), from the cache or solved."""
    from acoustics import SoundField, radiate

    key = at_key = None
    if cache is not None and modes_key is not None:
        key = radiation_key(modes_key, mode, frequency_hz, air)
        at_key = {
            **key,
            "stage": "sound-at",
            "microphone_rz": [round(microphone[0], 9), round(microphone[1], 9)],
            "stored": ["microphone_pressure", "ring_pressure", "directivity"],
        }
        try:
            field = SoundField.from_arrays(cache.load("sound", key))
        except CacheMiss:
            field = None
        if field is not None:
            try:
                at = cache.load("sound-at", at_key, _checked_at)
                return Radiation(
                    field, complex(at["microphone_pressure"][0]), at["ring_pressure"], at["directivity"]
                )
            except CacheMiss:
                rad = Radiation.of(field, microphone)
                cache.store("sound-at", at_key, _at_arrays(rad))
                return rad
    surface = _shape_surface(modeset, mode, 1.0 / peak)
    if budget is not None:
        from acoustics import radiation_cost

        cost = radiation_cost(surface, frequency_hz, air)
        budget.check_work(
            f"the sound of mode {mode.index} ({mode.label()}) at {frequency_hz:.6g} Hz "
            f"({cost.dofs:,.0f} unknowns of air)",
            cost.seconds,
            "a lower frequency is cheaper (the air mesh grows as its square)",
            cost.memory_bytes,
        )
    field = radiate(surface, frequency_hz, air)
    rad = Radiation.of(field, microphone)
    if cache is not None and key is not None and at_key is not None:
        cache.store("sound", key, field.to_arrays())
        cache.store("sound-at", at_key, _at_arrays(rad))
    return rad


def _checked_at(arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """A kept radiation's values at its microphone, checked before use (the cache is
    untrusted input): finite pressures of the shapes :func:`_at_arrays` stores."""
    if stored_array(arrays, "microphone_pressure", "fc", ndim=1).shape != (1,):
        raise ValueError("the kept microphone pressure is not one value")
    stored_array(arrays, "ring_pressure", "fc", ndim=1)
    stored_array(arrays, "directivity", "fc", ndim=(1, 2))
    return arrays


def _at_arrays(rad: Radiation) -> dict[str, np.ndarray]:
    return {
        "microphone_pressure": np.array([rad.microphone_pressure_pa]),
        "ring_pressure": rad.ring_pressure_pa,
        "directivity": rad.directivity_pa_m,
    }


#: The largest contact velocity amplitude a level is computed for [m/s]: squeal
#: reaches a fraction of the crabbing velocity (under 1 m/s); beyond this it is a slip.
MAX_VELOCITY_AMPLITUDE_M_S = 100.0


def check_velocity_amplitude(velocity_amplitude_m_s: float) -> None:
    """Refuse (:class:`RequestError`) a contact velocity amplitude [m/s] that is negative,
    not finite or above :data:`MAX_VELOCITY_AMPLITUDE_M_S`."""
    v = velocity_amplitude_m_s
    if not (math.isfinite(v) and 0 <= v <= MAX_VELOCITY_AMPLITUDE_M_S):
        raise RequestError(
            f"velocity amplitude must be from 0 to {MAX_VELOCITY_AMPLITUDE_M_S:g} m/s, got {v!r}"
        )


def sound_of(
    radiation: Radiation,
    velocity_amplitude_m_s: float,
    microphone: tuple[float, float, float],
    travelling: bool = False,
) -> Sound:
    """The levels of ``radiation`` (at 1 m/s) for a contact velocity amplitude [m/s] at a
    microphone (r, z, theta)."""
    check_velocity_amplitude(velocity_amplitude_m_s)
    r, z, theta = microphone
    return Sound(radiation, float(velocity_amplitude_m_s), (float(r), float(z), float(theta)), travelling)


def mode_sound(
    design: Design,
    modeset: ModeSet,
    mode: Mode,
    frequency_hz: float,
    velocity_amplitude_m_s: float = 1.0,
    *,
    listener: Listener | None = None,
    travelling: bool = False,
    fidelity: FidelityName = DEFAULT_FIDELITY,
    fmax_hz: float = DEFAULT_FMAX_HZ,
    cache: StageCache | None = None,
    budget: Budget | None = None,
    memo: dict[Any, Any] | None = None,
) -> Sound:
    """The sound of ``mode`` (of ``modeset``, solved with ``fidelity`` up to ``fmax_hz``)
    vibrating at ``frequency_hz`` [Hz] with a contact velocity amplitude [m/s]:
    what ``listener`` (default: :func:`default_microphone`, air at 20 degC) hears and the
    power radiated (a travelling wave on a turning wheel: ``travelling``).

    The surface velocity comes from the axisymmetric solver's shape: a mode set of
    another solver is solved again axisymmetrically (the same preset) and the mode of
    the same label taken. The radiation is cached beside the modes (``cache``),
    estimated against ``budget`` first, and kept in ``memo`` (a dict) for later calls of
    the same process (a study's operating points).
    """
    from acoustics import AIR

    from .fe_stages import compute_modes, modes_cache_key, pick_mode

    listener = listener or Listener(default_microphone(design), AIR)
    fid = fidelity_for(fidelity)
    if modeset.solver != "axisym":
        modeset = compute_modes(design, fid, fmax_hz=fmax_hz, cache=cache, budget=budget)
        mode, _ = pick_mode(modeset, f"n={mode.nodal_diameters},c={mode.nodal_circles}")
    mic = listener.microphone
    key = modes_cache_key(design, fid, fmax_hz) if cache is not None else None
    rad = mode_radiation(design, modeset, mode, frequency_hz, mic, cache, key, listener.air, budget, memo)
    return sound_of(rad, velocity_amplitude_m_s, mic, travelling)
