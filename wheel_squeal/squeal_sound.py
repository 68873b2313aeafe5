"""The squeal as acousticians report it: the limit cycle's harmonics, each radiated at its
own frequency, the microphone signal of the whole run, its levels in dB and dB(A), its
one-third-octave bands, the levels at 1 m and 7.5 m from the wheel centre and the
far-field directivity (the numerics are ``acoustics.levels``, ``acoustics.farfield`` and
``acoustics.signal``; the radiation of each harmonic is :func:`wheel_squeal.sound.mode_sound`'s).

The contact velocity's harmonics radiated are ``acoustics.harmonics``'s; each harmonic k of
the tone f0 is the mode's shape vibrating at k f0; the microphone hears their sum. Levels of
several harmonics add in energy.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from acoustics.signal import MicrophoneSignal
    from fem.modes import Mode, ModeSet

    from .design import Design
    from .simulation import Simulation
    from .sound import Sound

__all__ = [
    "DISTANCES_M",
    "SquealSound",
    "squeal_sound",
    "tone_sound",
]

#: The distances from the wheel centre the far levels are given at [m] (a listener at
#: 1 m; 7.5 m, the pass-by distance of railway noise measurements)
DISTANCES_M = (1.0, 7.5)
#: The one-third-octave bands reported [Hz] (their centres)
BANDS_HZ = (20.0, 10_000.0)
#: A band this far below the overall level holds only round-off: it is reported empty
EMPTY_BAND_DB = 100.0


def tone_sound(sound: Sound, tone_hz: float | None = None) -> SquealSound:
    """A pure tone (one ``Sound``, no record) as a :class:`SquealSound`, heard at
    ``tone_hz`` [Hz] (default: the frequency it was radiated at)."""
    return SquealSound((sound,), (1,), 1.0, float(sound.field.frequency_hz if tone_hz is None else tone_hz))


@dataclass(frozen=True, eq=False)
class SquealSound:
    """The sound of a squeal (module docstring): ``harmonics`` (a ``Sound`` each, the
    fundamental first, at its own frequency and velocity amplitude), their ``orders``,
    the ``velocity_share`` of the contact velocity's energy they hold, the tone
    ``tone_hz`` [Hz] the microphone hears, and the microphone ``signal`` of the run
    (None for a tone without a record)."""

    harmonics: tuple[Sound, ...]
    orders: tuple[int, ...]
    velocity_share: float
    tone_hz: float
    signal: MicrophoneSignal | None = None

    @property
    def fundamental(self) -> Sound:
        return self.harmonics[0]

    @property
    def frequencies_hz(self) -> np.ndarray:
        """The harmonics' frequencies as the microphone hears them, k f0 [Hz]."""
        return np.array(self.orders, float) * self.tone_hz

    # -- levels ---------------------------------------------------------------------------
    def mean_squares_pa2(self) -> np.ndarray:
        """Each harmonic's mean-square pressure at the microphone [Pa^2]."""
        return np.array([0.5 * s.microphone_pressure_pa**2 for s in self.harmonics])

    def powers_w(self) -> np.ndarray:
        """Each harmonic's radiated power [W]."""
        return np.array([s.sound_power_w for s in self.harmonics])

    def far_mean_squares_pa2(self, distance_m: float, angle_rad: float) -> np.ndarray:
        """Each harmonic's mean-square pressure at ``distance_m`` from the wheel centre at
        meridian angle ``angle_rad`` from the +z axis, at an antinode around the axis
        (a travelling wave passes every angle with it) [Pa^2]."""
        from acoustics.farfield import distant_mean_squares_pa2

        fields = [s.field for s in self.harmonics]
        return distant_mean_squares_pa2(
            fields, [s.velocity_amplitude_m_s for s in self.harmonics], distance_m, angle_rad
        )

    def loudest_angle_rad(self) -> float:
        """The meridian angle of the far field's largest intensity (all harmonics)."""
        from acoustics.farfield import loudest_angle_rad

        directivities = [s.radiation.directivity_pa_m for s in self.harmonics]
        return loudest_angle_rad(directivities, [s.velocity_amplitude_m_s for s in self.harmonics])

    def bands(self) -> tuple[list[Any], np.ndarray, float | None]:
        """(bands, band levels [dB re 20 uPa], overall [dB re 20 uPa]) of the microphone
        pressure: of its record over the limit cycle (Parseval), or of the harmonics'
        line spectrum without a record."""
        from acoustics.levels import band_levels_db, energy_sum_db, third_octave_bands
        from acoustics.medium import mean_square_spl_db

        bands = third_octave_bands(*BANDS_HZ)
        if self.signal is not None:
            levels, overall = band_levels_db(self.signal.cycle_pa, self.signal.cycle_rate_hz, bands)
            return bands, levels, overall
        ms = self.mean_squares_pa2()
        levels = np.full(len(bands), -math.inf)
        for f, m in zip(self.frequencies_hz, ms):
            for i, b in enumerate(bands):
                if b.lower_hz <= f < b.upper_hz and m > 0:
                    levels[i] = energy_sum_db([levels[i], float(mean_square_spl_db(m))])
        return bands, levels, _spl(ms.sum())

    def summary(self) -> dict:
        """summary.json's ``sound``: the fundamental's fields (its radiation per unit
        velocity, the checks), the overall levels of all harmonics in dB and dB(A), the
        far levels, the bands and the harmonics (None where a level has no pressure);
        computed once (a copy each call)."""
        return dict(self._summary)

    @functools.cached_property
    def _summary(self) -> dict:
        from acoustics.levels import a_weighting_db

        out = self.fundamental.summary()
        ms, w = self.mean_squares_pa2(), self.powers_w()
        a = np.power(10.0, a_weighting_db(self.frequencies_hz) / 10.0)
        angle = self.loudest_angle_rad()
        far = {}
        silent_axis = self.fundamental.field.harmonic >= 1  # cos(n phi) with n >= 1 vanishes on the axis
        for d in DISTANCES_M:
            tag = f"{d:g}".replace(".", "_")
            far[f"spl_{tag}m_db"] = _spl(self.far_mean_squares_pa2(d, angle).sum())
            axis = None if silent_axis else _spl(self.far_mean_squares_pa2(d, 0.0).sum())
            far[f"spl_{tag}m_axis_db"] = axis
        bands, levels, overall = self.bands()
        if overall is not None and math.isfinite(overall):
            levels = np.where(levels >= overall - EMPTY_BAND_DB, levels, -math.inf)
        out |= {
            "spl_db": _spl(ms.sum()),
            "sound_power_level_db": _lw(w.sum()),
            "spl_dba": _spl((ms * a).sum()),
            "sound_power_level_dba": _lw((w * a).sum()),
            "tone_hz": self.tone_hz,
            **far,
            "loudest_angle_deg": math.degrees(angle),
            "third_octave_bands": [
                {"centre_hz": b.centre_hz, "label_hz": b.label_hz, "spl_db": _finite(x)}
                for b, x in zip(bands, levels)
            ],
            "harmonics": [
                {
                    "order_k": k,
                    "frequency_hz": k * self.tone_hz,
                    "velocity_amplitude_m_s": s.velocity_amplitude_m_s,
                    "spl_db": _spl(m),
                    "sound_power_level_db": _lw(p),
                }
                for k, s, m, p in zip(self.orders, self.harmonics, ms, w)
            ],
            "velocity_energy_share": self.velocity_share,
        }
        out["wav_full_scale_pa"] = None
        if self.signal is not None and self.audible:
            out["wav_full_scale_pa"] = self.signal.wav_full_scale_pa()
        return out

    @property
    def audible(self) -> bool:
        """Whether the microphone hears it (False: silence, no sound file)."""
        return _spl(float(self.mean_squares_pa2().sum())) is not None


def _spl(mean_square_pa2: float) -> float | None:
    """The SPL [dB re 20 uPa] of a mean square [Pa^2]; None where it is silence
    (``acoustics.medium.SILENT_SPL_DB``)."""
    from acoustics.medium import audible_spl_db, mean_square_spl_db

    return audible_spl_db(float(mean_square_spl_db(mean_square_pa2))) if mean_square_pa2 > 0 else None


def _lw(power_w: float) -> float | None:
    """The sound power level [dB re 1 pW]; None where nothing is radiated."""
    from acoustics import sound_power_level_db

    return float(sound_power_level_db(power_w)) if power_w > 0 else None


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def squeal_sound(
    design: Design,
    modeset: ModeSet,
    mode: Mode,
    mode_frequency_hz: float,
    simulation: Simulation,
    tone_hz: float,
    **radiation: Any,
) -> SquealSound:
    """The :class:`SquealSound` of ``mode`` squealing as ``simulation`` says, heard at
    ``tone_hz`` [Hz]: its harmonics radiated at k times ``mode_frequency_hz``
    (``acoustics.harmonics.radiation_frequency_hz``: within half a per cent of the tone) through
    :func:`wheel_squeal.sound.mode_sound` (``radiation``: its keywords: listener,
    travelling, fidelity, fmax_hz, cache, budget, memo), and the microphone signal of the
    whole run (each band of the contact velocity's spectrum through its harmonic's
    transfer)."""
    from acoustics.harmonics import SAMPLES_PER_PERIOD, limit_cycle_harmonics
    from acoustics.signal import MicrophoneSignal, pressure_signal

    from .sound import contact_velocity_phase, mode_sound

    h = simulation.history
    orders, amplitudes, share, window, cycle = limit_cycle_harmonics(h.t, h.v, tone_hz, mode_frequency_hz)
    tone_hz = window[2] / (window[1] - window[0])  # measured over whole periods
    sounds = tuple(
        mode_sound(design, modeset, mode, k * mode_frequency_hz, float(abs(a)), **radiation)
        for k, a in zip(orders, amplitudes)
    )
    phase = contact_velocity_phase(mode)
    transfer = {
        k: s.microphone_transfer() / phase for k, s in zip(orders, sounds)
    }  # pressure per unit contact velocity
    rate = tone_hz * SAMPLES_PER_PERIOD
    cycle_t = np.arange(len(cycle)) / rate
    signal = MicrophoneSignal(
        h.t,
        pressure_signal(h.t, h.v, tone_hz, transfer),
        pressure_signal(cycle_t, cycle, tone_hz, transfer, periodic=True),
        rate,
        window,
    )
    return SquealSound(sounds, orders, share, tone_hz, signal)
