"""A curve's squeal as the noise-mapping tools take a railway source: a directional sound
power per metre of track per frequency band (CNOSSOS-EU, Directive (EU) 2015/996, Annex
II), the traffic's equivalent level, and the flat correction CNOSSOS-EU adds for curves.

The source term is the one a pass-by at the ISO 3095 position gives, as CNOSSOS-EU's own
railway source terms are derived from pass-by measurements: a bogie passing at V [m/s] at
distance d from the microphone leaves in each band the exposure E_b [Pa^2 s] (the pass-by
computed with the wheels' own directivity, ``acoustics.passby``); the directional sound
power toward the track's perpendicular that gives the same exposure under CNOSSOS-EU's
propagation (free field, spherical spreading) and its horizontal directivity of the rolling
source, 10 lg(0.01 + 0.99 sin^2 phi) (phi from the track's direction), along an infinite
line, is

    W_0,b = E_b 4 pi V d / (rho c (0.01 pi + 0.99 pi / 2))

Q bogies an hour that squeal a share p of the time make the line source

    W'_b = p Q W_0,b / (3600 V)     [W/m],  L_W' = 10 lg(W'_b / 1e-12 W)

at the source height CNOSSOS-EU gives the wheel/rail sources (0.05 m above the rail head).
At the ISO 3095 position the emission gives the pass-by's exposure back by construction;
elsewhere the squeal's own directivity is not the dipole (a mode of n >= 1 nodal diameters
radiates nothing along its axle and most some tens of degrees off it), and how far the two
part at another receiver is measured (docs/validation.md). The exposure at d is

    E = rho c W_0 / (4 pi) * (0.01 pi + 0.99 pi / 2) / (V d)

and the equivalent level over a period of N bogies, L_Aeq = SEL_A + 10 lg(p N / T).

Squeal is intermittent: over the friction states a curve sees (each with its share of the
time), :func:`intermittent_emission` gives the share of time the bogie squeals, its levels
while it does (their energy mean over the squealing states) and the expected emission
(each squealing state's power times its share).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .levels import third_octave_bands
from .medium import AIR, P_REF_PA, W_REF_W, Air
from .passby import PassbyResult

__all__ = [
    "CNOSSOS_CURVE_CLASSES",
    "CNOSSOS_OCTAVES_HZ",
    "CNOSSOS_SOURCE_HEIGHT_M",
    "CNOSSOS_THIRDS",
    "PERIODS",
    "BandPower",
    "CurveEmission",
    "HeardPassby",
    "SquealState",
    "band_emission_power",
    "cnossos_curve_correction_db",
    "exposure_from_emission",
    "intermittent_emission",
    "line_emission_db",
]

#: CNOSSOS-EU's squeal correction to rolling noise: (upper radius [m], +dB) by class
CNOSSOS_CURVE_CLASSES = ((300.0, 8.0), (500.0, 5.0))
#: The octave bands of CNOSSOS-EU's railway source [Hz]
CNOSSOS_OCTAVES_HZ = (63.0, 125.0, 250.0, 500.0, 1000.0, 2000.0, 4000.0, 8000.0)
#: ... and its one-third-octave bands, 50 Hz to 10 kHz
CNOSSOS_THIRDS = tuple(third_octave_bands(50.0, 10000.0))
#: The height of CNOSSOS-EU's wheel/rail source above the rail head [m]
CNOSSOS_SOURCE_HEIGHT_M = 0.05
#: The periods of the equivalent level, as the Environmental Noise Directive (2002/49/EC)
#: defines L_den's: (name, hours)
PERIODS = (("day", 12.0), ("evening", 4.0), ("night", 8.0))
#: CNOSSOS-EU's horizontal directivity of the rolling source, 10 lg(a + b sin^2 phi)
DIPOLE_FLOOR, DIPOLE_SHARE = 0.01, 0.99


@dataclass(frozen=True)
class BandPower:
    """A bogie's directional sound power per band toward the track's perpendicular [W]:
    ``octaves`` at :data:`CNOSSOS_OCTAVES_HZ`, ``thirds`` at :data:`CNOSSOS_THIRDS`; and its
    A-weighted total [W]."""

    octaves: np.ndarray
    thirds: np.ndarray
    a_weighted_w: float


def _spread(speed_m_s: float, distance_m: float) -> float:
    """int (0.01 + 0.99 sin^2 phi) / r^2 dt over an infinite pass-by [s/m^2]."""
    return (DIPOLE_FLOOR * math.pi + DIPOLE_SHARE * math.pi / 2.0) / (speed_m_s * distance_m)


def band_emission_power(
    passby: PassbyResult, speed_m_s: float, distance_m: float, air: Air = AIR
) -> BandPower:
    """The bogie's directional sound power per band (module docstring) from its pass-by at
    ``distance_m`` [m] from the track (its exposure per band)."""
    dt = float(passby.t[1] - passby.t[0]) if len(passby.t) > 1 else 0.0
    exposure = passby.each_pa2.sum(axis=1) * dt  # per source [Pa^2 s]
    to_power = 4.0 * math.pi / (air.density_kg_m3 * air.sound_speed_m_s * _spread(speed_m_s, distance_m))
    octaves = np.zeros(len(CNOSSOS_OCTAVES_HZ))
    thirds = np.zeros(len(CNOSSOS_THIRDS))
    for e, f in zip(exposure, passby.frequencies_hz):
        w = float(e) * to_power
        for i, centre in enumerate(CNOSSOS_OCTAVES_HZ):
            if centre / math.sqrt(2.0) <= f < centre * math.sqrt(2.0):
                octaves[i] += w
        for i, band in enumerate(CNOSSOS_THIRDS):
            if band.lower_hz <= f < band.upper_hz:
                thirds[i] += w
    weighted = float(np.sum(exposure * 10 ** (passby.a_weighting_db / 10))) * to_power
    return BandPower(octaves, thirds, weighted)


def line_emission_db(
    power_w: np.ndarray, probability: float, bogies_per_hour: float, speed_m_s: float
) -> np.ndarray:
    """L_W' [dB re 1 pW per metre] per band of ``power_w`` (a bogie's directional power per
    band) squealing a share ``probability`` of the time, for ``bogies_per_hour`` passing at
    ``speed_m_s``; -inf where nothing is emitted.

    Examples
    --------
    One watt-bogie an hour at 10 m/s, always squealing: 10 lg(1 / 36000 / 1e-12) = 74.4 dB:

    >>> float(line_emission_db(np.array([1.0]), 1.0, 1.0, 10.0)[0]).__round__(1)
    74.4
    """
    per_metre = probability * bogies_per_hour * np.asarray(power_w, float) / (3600.0 * speed_m_s)
    with np.errstate(divide="ignore"):
        return 10 * np.log10(per_metre / W_REF_W)


def exposure_from_emission(power_w: float, speed_m_s: float, distance_m: float, air: Air = AIR) -> float:
    """The sound exposure level [dB re (20 uPa)^2 s] one pass-by of directional power
    ``power_w`` [W] leaves at ``distance_m`` from the track with CNOSSOS-EU's horizontal
    dipole (module docstring)."""
    e = air.density_kg_m3 * air.sound_speed_m_s * power_w / (4.0 * math.pi) * _spread(speed_m_s, distance_m)
    return 10 * math.log10(e / P_REF_PA**2) if e > 0 else -math.inf


def cnossos_curve_correction_db(radius_m: float) -> float:
    """The flat correction CNOSSOS-EU adds to rolling noise in a curve [dB]: +8 below
    300 m, +5 from 300 to 500 m, 0 beyond."""
    for upper, db in CNOSSOS_CURVE_CLASSES:
        if radius_m < upper:
            return db
    return 0.0


@dataclass(frozen=True)
class HeardPassby:
    """What a state's pass-by leaves for the line source: its L_pAmax and SEL_A [dB(A)] at
    the pass-by position and the bogie's directional power per band
    (:func:`band_emission_power`); plain numbers, to cross between processes as a dict."""

    lpamax_dba: float
    sel_dba: float
    power: BandPower

    @classmethod
    def of(cls, passby: PassbyResult, speed_m_s: float, distance_m: float) -> HeardPassby:
        """The pass-by ``passby`` of bogies at ``speed_m_s`` [m/s], heard ``distance_m`` [m]
        from the source."""
        power = band_emission_power(passby, speed_m_s, distance_m)
        return cls(float(passby.lpamax_dba), float(passby.sel_dba), power)

    def to_dict(self) -> dict[str, Any]:
        p = self.power
        return {
            "lpamax_dba": self.lpamax_dba,
            "sel_dba": self.sel_dba,
            "octaves_w": p.octaves.tolist(),
            "thirds_w": p.thirds.tolist(),
            "a_weighted_w": p.a_weighted_w,
        }

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> HeardPassby:
        """The pass-by :meth:`to_dict` gave, checked (it may come back from a cache):
        ``ValueError`` unless it has a finite level and a non-negative power per band."""
        octaves, thirds = np.asarray(d["octaves_w"], float), np.asarray(d["thirds_w"], float)
        power = BandPower(octaves, thirds, float(d["a_weighted_w"]))
        heard = cls(float(d["lpamax_dba"]), float(d["sel_dba"]), power)
        if octaves.shape != (len(CNOSSOS_OCTAVES_HZ),) or thirds.shape != (len(CNOSSOS_THIRDS),):
            raise ValueError("a pass-by's bands are not the emission's bands")
        numbers = np.array([heard.lpamax_dba, heard.sel_dba, power.a_weighted_w, *octaves, *thirds])
        if not np.isfinite(numbers).all() or (numbers[2:] < 0).any():
            raise ValueError("a pass-by's level or power is not a finite number")
        return heard


@dataclass(frozen=True)
class SquealState:
    """One state of the rail head a curve sees (a friction, say): its share of the time,
    whether the bogie squeals in it, and what its pass-by leaves (None: silent, or
    squealing without a level)."""

    share: float
    squeals: bool
    heard: HeardPassby | None


@dataclass(frozen=True)
class CurveEmission:
    """A curve's squeal over the states it sees (:func:`intermittent_emission`): the share
    of time the bogie squeals; its L_pAmax and SEL_A [dB(A)] while it does (None: never
    heard); L_Aeq per period of :data:`PERIODS` at the pass-by position [dB(A)]; the
    emission L_W' per period and band [dB re 1 pW/m] (octaves, thirds); and the SEL_A the
    expected emission gives back at the pass-by position [dB(A)]."""

    probability: float
    lpamax_dba: float | None
    sel_dba: float | None
    laeq_dba: dict[str, float | None]
    octaves_db: dict[str, np.ndarray]
    thirds_db: dict[str, np.ndarray]
    sel_from_emission_dba: float | None


def _energy_mean(levels: Sequence[tuple[float, float]]) -> float | None:
    """The energy mean of (level [dB], weight) pairs (None: none)."""
    total = sum(w for _, w in levels)
    if not levels or total <= 0:
        return None
    return 10 * math.log10(sum(w * 10 ** (x / 10) for x, w in levels) / total)


def intermittent_emission(
    states: Sequence[SquealState],
    speed_m_s: float,
    distance_m: float,
    bogies_per_hour: Mapping[str, float],
) -> CurveEmission:
    """A curve's occurrence, levels and emission over ``states`` (module docstring) for
    bogies passing at ``speed_m_s`` [m/s], their pass-bys heard at ``distance_m`` [m]
    from the source, ``bogies_per_hour`` in each period of :data:`PERIODS`."""
    probability, a_power = 0.0, 0.0
    lpamax: list[tuple[float, float]] = []
    sel: list[tuple[float, float]] = []
    octaves, thirds = np.zeros(len(CNOSSOS_OCTAVES_HZ)), np.zeros(len(CNOSSOS_THIRDS))
    for state in states:
        if not state.squeals:
            continue
        probability += state.share
        if state.heard is None:
            continue  # it squeals without a level (mode coupling alone): counted, not heard
        lpamax.append((state.heard.lpamax_dba, state.share))
        sel.append((state.heard.sel_dba, state.share))
        power = state.heard.power
        octaves = octaves + state.share * power.octaves
        thirds = thirds + state.share * power.thirds
        a_power += state.share * power.a_weighted_w
    heard = probability > 0 and bool(lpamax)
    conditional_sel = _energy_mean(sel) if heard else None
    laeq: dict[str, float | None] = dict.fromkeys((p for p, _ in PERIODS), None)
    for period, _ in PERIODS:
        n = bogies_per_hour[period]
        if conditional_sel is not None and n > 0:
            laeq[period] = conditional_sel + 10 * math.log10(probability * n / 3600.0)
    per_period = [(p, bogies_per_hour[p]) for p, _ in PERIODS]
    return CurveEmission(
        probability,
        _energy_mean(lpamax) if heard else None,
        conditional_sel,
        laeq,
        {p: line_emission_db(octaves, 1.0, n, speed_m_s) for p, n in per_period},
        {p: line_emission_db(thirds, 1.0, n, speed_m_s) for p, n in per_period},
        exposure_from_emission(a_power / probability, speed_m_s, distance_m) if heard else None,
    )
