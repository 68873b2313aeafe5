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

__all__ = [
    "GROUND_DEPTH_M",
    "MICROPHONE_HEIGHT_M",
    "MICROPHONE_DISTANCE_M",
    "PassbySource",
    "PassbyResult",
    "passby",
    "passby_pressure",
]

#: The ISO 3095 microphone: its distance from the track centre line and height above the
#: rail head [m]
MICROPHONE_DISTANCE_M, MICROPHONE_HEIGHT_M = 7.5, 1.2
#: Half the distance between the rails' contact points [m] (standard gauge 1435 mm plus
#: the rail head)
HALF_TRACK_M = 0.75
#: The reference pressure [Pa]
P_REF_PA = 20e-6
#: The ground's depth below the rail head [m]: the rail (0.17 m) on its sleeper and
#: ballast shoulder (about 0.3 m), the plane the image source is mirrored in
GROUND_DEPTH_M = 0.5


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


def _level(x: float) -> float:
    return 10 * math.log10(x / P_REF_PA**2) if x > 0 else -math.inf


@dataclass(frozen=True)
class PassbyResult:
    """The pass-by: time [s] (0: the bogie's centre passes), the mean-square pressure
    [Pa^2] of all sources and of each, L_pmax and L_pAmax [dB re 20 uPa], SEL and SEL_A
    [dB re 20 uPa^2 s]; each source's tone [Hz] and A-weighting [dB]."""

    t: np.ndarray
    mean_square_pa2: np.ndarray
    each_pa2: np.ndarray
    lpmax_db: float
    lpamax_dba: float
    sel_db: float
    sel_dba: float
    frequencies_hz: np.ndarray
    a_weighting_db: np.ndarray

    def levels_of(self, sources: Sequence[int]) -> tuple[float, float, float, float]:
        """(L_pmax, L_pAmax, SEL, SEL_A) [dB] of the sources ``sources`` (indices) alone."""
        idx = list(sources)
        each = self.each_pa2[idx]
        total = each.sum(axis=0)
        total_a = (each * 10 ** (self.a_weighting_db[idx, None] / 10)).sum(axis=0)
        dt = float(self.t[1] - self.t[0]) if len(self.t) > 1 else 0.0
        return (
            _level(float(total.max(initial=0.0))),
            _level(float(total_a.max(initial=0.0))),
            _level(float(total.sum() * dt)),
            _level(float(total_a.sum() * dt)),
        )

    def fast_level_dba(self, time_constant_s: float = 0.125) -> np.ndarray:
        """The A-weighted level over the pass-by [dB(A) re 20 uPa], its mean square averaged
        over ``time_constant_s`` (0.125 s: IEC 61672's "fast"), at ``t``."""
        weighted = (self.each_pa2 * 10 ** (self.a_weighting_db[:, None] / 10)).sum(axis=0)
        dt = float(self.t[1] - self.t[0]) if len(self.t) > 1 else time_constant_s
        window = max(1, int(round(time_constant_s / dt)))
        fast = np.convolve(weighted, np.ones(window) / window, mode="same")
        return 10 * np.log10(np.maximum(fast, 1e-30) / P_REF_PA**2)

    def band_maxima_db(
        self, centres_hz: Sequence[float], a_weighted: bool = False, sources: Sequence[int] | None = None
    ) -> np.ndarray:
        """The largest level over the pass-by [dB re 20 uPa] in each one-third-octave band
        of centre ``centres_hz`` (its sources' tones within the band's edges, centre
        times 10^(+-1/20)), A-weighted at each tone if ``a_weighted``; -inf where no
        tone falls in a band. ``sources``: those sources (indices) alone (None: all)."""
        weight = 10 ** (self.a_weighting_db / 10) if a_weighted else np.ones(len(self.frequencies_hz))
        mine = np.zeros(len(self.frequencies_hz), bool)
        mine[list(range(len(mine))) if sources is None else list(sources)] = True
        out = np.full(len(centres_hz), -math.inf)
        for i, centre in enumerate(centres_hz):
            inside = (self.frequencies_hz >= centre * 10**-0.05) & (self.frequencies_hz < centre * 10**0.05)
            inside &= mine
            if inside.any():
                out[i] = _level(float((self.each_pa2[inside] * weight[inside, None]).sum(axis=0).max()))
        return out


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
    ground_depth_m: float = GROUND_DEPTH_M,
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
    >>> float(round(r.lpmax_db - 20 * np.log10(1 / np.hypot(6.75, 1.2 - 0.46) / np.sqrt(2) / 20e-6), 6))
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
    return PassbyResult(
        t,
        total,
        each,
        _level(float(total.max())),
        _level(float(total_a.max())),
        _level(float(total.sum() * dt)),
        _level(float(total_a.sum() * dt)),
        np.array([s.frequency_hz for s in sources], float),
        np.array([s.a_weighting_db for s in sources], float),
    )


def passby_pressure(
    sources: Sequence[PassbySource],
    speed_m_s: float,
    duration_s: float,
    rate_hz: float,
    *,
    distance_m: float = MICROPHONE_DISTANCE_M,
    height_m: float = MICROPHONE_HEIGHT_M,
    ground_depth_m: float = GROUND_DEPTH_M,
    reflection: float = 0.0,
    air: Air = AIR,
) -> tuple[np.ndarray, np.ndarray]:
    """The pressure [Pa] at the microphone over ``duration_s`` centred on the bogie's
    passing (time [s], pressure), sampled at ``rate_hz``: each source's tone as it
    arrives, emitted at the retarded time t_e (t = t_e + r(t_e) / c, solved by
    fixed-point iteration: the error shrinks by V/c each step), so that its frequency
    falls as it passes (Doppler, f c / (c - V cos)) and its level follows its distance
    and directivity; the image source over the ground as in :func:`passby`. The
    orientation of a mode's nodal diameters is not known: its amplitude is the rms
    over it (sqrt(1/2) for n >= 1).

    The wheels squeal independently (:func:`passby` adds them in energy): sources of one
    tone are combined with the energy sum of their amplitudes, sqrt(sum |p_k|^2), and the
    phase of their amplitude-weighted sum, so that the signal's level at every moment is
    the one :func:`passby` gives (two wheels summed in phase would read up to 3 dB
    louder); different tones add as they are."""
    c = air.sound_speed_m_s
    if not (0 < speed_m_s < 0.5 * c):
        raise ValueError(f"speed {speed_m_s!r} m/s: positive and well below the speed of sound")
    t = (np.arange(int(round(duration_s * rate_hz))) - 0.5 * duration_s * rate_hz) / rate_hz
    microphone = np.array([0.0, distance_m, height_m])
    tones: dict[float, list[np.ndarray]] = {}
    for s in sources:
        facing = 1.0 if s.across_m >= 0 else -1.0
        around = math.sqrt(0.5) if s.nodal_diameters >= 1 else 1.0
        analytic = np.zeros(len(t), dtype=complex)
        for depth_sign, factor in ((1.0, 1.0), (-1.0, reflection)):
            if factor == 0.0:
                continue
            height = s.centre_height_m if depth_sign > 0 else -2 * ground_depth_m - s.centre_height_m
            fixed = np.array([0.0, s.across_m, height]) - microphone
            cross2 = fixed[1] ** 2 + fixed[2] ** 2
            t_e = t.copy()
            for _ in range(6):
                t_e = t - np.sqrt((s.along_m + speed_m_s * t_e) ** 2 + cross2) / c
            along = s.along_m + speed_m_s * t_e
            r = np.sqrt(along**2 + cross2)
            d = np.stack([-along, -np.full_like(along, fixed[1]), -np.full_like(along, fixed[2])], axis=1)
            mag = np.interp(_angle_weight(d, facing), s.angles_rad, s.directivity_pa_m)
            analytic += factor * around * mag / r * np.exp(2j * math.pi * s.frequency_hz * t_e)
        tones.setdefault(float(s.frequency_hz), []).append(analytic)
    p = np.zeros_like(t)
    for parts in tones.values():
        each = np.array(parts)
        weighted = (np.abs(each) * each).sum(axis=0)
        phase = np.exp(1j * np.angle(weighted))
        p += np.sqrt((np.abs(each) ** 2).sum(axis=0)) * phase.real
    return t, p
