"""The level of squealing wheels passing a microphone at the standard pass-by position
(ISO 3095: 7.5 m from the track centre line, 1.2 m above the rail head).

Each wheel is a point source at its centre moving along the track at the train speed V,
radiating its far field p = |D(theta)| v / r (``acoustics.farfield``: theta from the
wheel's axis, which points across the track, the wheel's field side outwards) at its
tone. Around the axis the pressure of a mode with n >= 1 nodal diameters varies as
cos(n phi), whose orientation on the wheel is not known in the field (and turns with a
travelling wave): its mean square over phi is taken (a half; 1 for n = 0). Over the
ground (a plane ``ground_depth_m`` below the rail head, reflection factor Q) the image
source adds coherently at the tone: p = D1/r1 e^{-ik r1} + Q D2/r2 e^{-ik r2}, up to
6 dB where the paths coincide over a rigid ground. Wheels add in energy (different
tones, incoherent). L_pAmax is the largest A-weighted level over the pass-by (Fast time
weighting is not applied: the tone is steady), SEL the sound exposure level
10 lg(int p^2 dt / (p0^2 1 s)).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .medium import AIR, Air

__all__ = ["MICROPHONE_HEIGHT_M", "MICROPHONE_DISTANCE_M", "PassbySource", "PassbyResult", "passby"]

#: The ISO 3095 microphone: its distance from the track centre line and height above the
#: rail head [m]
MICROPHONE_DISTANCE_M, MICROPHONE_HEIGHT_M = 7.5, 1.2
#: Half the distance between the rails' contact points [m] (standard gauge 1435 mm plus
#: the rail head)
HALF_TRACK_M = 0.75
#: The reference pressure [Pa]
P_REF_PA = 20e-6


@dataclass(frozen=True)
class PassbySource:
    """One squealing wheel as the pass-by sees it.

    Attributes
    ----------
    along_m : float
        Its position along the bogie [m] (the leading axle ahead: positive).
    across_m : float
        Its position across the track [m] (positive: on the microphone's side).
    centre_height_m : float
        Its centre above the rail head (its rolling radius) [m].
    frequency_hz : float
        Its tone [Hz].
    directivity_pa_m : numpy.ndarray
        |D| [Pa m] at ``angles_rad`` from its axis (its field side) at its amplitude.
    angles_rad : numpy.ndarray
    nodal_diameters : int
    a_weighting_db : float
        A-weighting at its tone [dB].
    """

    along_m: float
    across_m: float
    centre_height_m: float
    frequency_hz: float
    directivity_pa_m: np.ndarray
    angles_rad: np.ndarray
    nodal_diameters: int = 0
    a_weighting_db: float = 0.0


@dataclass(frozen=True)
class PassbyResult:
    """The pass-by: time [s] (0: the bogie's centre passes), the mean-square pressure
    [Pa^2] of all sources and of each, L_pmax and L_pAmax [dB re 20 uPa], SEL and SEL_A
    [dB re 20 uPa^2 s]."""

    t: np.ndarray
    mean_square_pa2: np.ndarray
    each_pa2: np.ndarray
    lpmax_db: float
    lpamax_dba: float
    sel_db: float
    sel_dba: float


def _angle_weight(d: np.ndarray, facing: float) -> np.ndarray:
    """theta [rad]: the angle between the wheel's field-side axis (across the track,
    ``facing`` = +1 towards the microphone, -1 away) and the direction ``d``."""
    r = np.linalg.norm(d, axis=-1)
    return np.arccos(np.clip(facing * d[..., 1] / r, -1.0, 1.0))


def _pressure(
    s: PassbySource, position: np.ndarray, microphone: np.ndarray, air: Air, ground_depth_m: float, q: float
) -> np.ndarray:
    """The complex pressure amplitude at the microphone over time (direct + image)."""
    facing = 1.0 if s.across_m >= 0 else -1.0
    k = 2 * math.pi * s.frequency_hz / air.sound_speed_m_s
    total = np.zeros(len(position), dtype=complex)
    image = position.copy()
    image[:, 2] = -2 * ground_depth_m - image[:, 2]
    for src, factor in ((position, 1.0), (image, q)):
        if factor == 0.0:
            continue
        d = microphone[None, :] - src
        r = np.linalg.norm(d, axis=1)
        theta = _angle_weight(d, facing)
        mag = np.interp(theta, s.angles_rad, s.directivity_pa_m)
        total += factor * mag / r * np.exp(-1j * k * r)
    return total


def passby(
    sources: Sequence[PassbySource],
    speed_m_s: float,
    *,
    distance_m: float = MICROPHONE_DISTANCE_M,
    height_m: float = MICROPHONE_HEIGHT_M,
    ground_depth_m: float = 0.5,
    reflection: float = 0.0,
    air: Air = AIR,
    samples: int = 4001,
) -> PassbyResult:
    """The pass-by of ``sources`` at ``speed_m_s`` (module docstring): the microphone
    ``distance_m`` from the track centre line and ``height_m`` above the rail head, a
    ground ``ground_depth_m`` below the rail head with reflection factor ``reflection``
    (0: free field; 1: rigid), over the time the bogie takes from 20 distances before
    the microphone to 20 after.

    Examples
    --------
    >>> import numpy as np
    >>> angles = np.linspace(0, np.pi, 181)
    >>> s = PassbySource(0.0, 0.75, 0.46, 500.0, np.ones(181), angles)
    >>> r = passby([s], 10.0)
    >>> round(r.lpmax_db - 20 * np.log10(1 / np.hypot(6.75, 1.2 - 0.46) / np.sqrt(2) / 20e-6), 6)
    0.0
    """
    if not (speed_m_s > 0 and math.isfinite(speed_m_s)):
        raise ValueError(f"speed {speed_m_s!r} m/s: positive")
    span = 20.0 * distance_m
    t = np.linspace(-span / speed_m_s, span / speed_m_s, samples)
    microphone = np.array([0.0, distance_m, height_m])
    each = np.zeros((len(sources), len(t)))
    a_each = np.zeros_like(each)
    for i, s in enumerate(sources):
        position = np.stack(
            [s.along_m + speed_m_s * t, np.full_like(t, s.across_m), np.full_like(t, s.centre_height_m)],
            axis=1,
        )
        p = _pressure(s, position, microphone, air, ground_depth_m, reflection)
        around = 0.5 if s.nodal_diameters >= 1 else 1.0  # cos(n phi) averaged over phi
        each[i] = 0.5 * np.abs(p) ** 2 * around  # the mean square of the amplitude
        a_each[i] = each[i] * 10 ** (s.a_weighting_db / 10)
    total, total_a = each.sum(axis=0), a_each.sum(axis=0)
    dt = float(t[1] - t[0])

    def level(x: float) -> float:
        return 10 * math.log10(x / P_REF_PA**2) if x > 0 else -math.inf

    return PassbyResult(
        t,
        total,
        each,
        level(float(total.max())),
        level(float(total_a.max())),
        level(float(total.sum() * dt)),
        level(float(total_a.sum() * dt)),
    )
