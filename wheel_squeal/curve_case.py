"""The records of a curve map: one wheel at one radius and train speed (:class:`CurveCase`),
what its squeal sends to the pass-by (:class:`AxleSound`) and the bogie's pass-by
(:class:`BogiePassby`); :func:`wheel_squeal.curve.curve` makes them."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .analysis import Analysis
from .outputs import finite_or_none
from .types import AmplitudeMethod

if TYPE_CHECKING:
    from acoustics.passby import PassbyResult, PassbySource
    from track.bogie_curving import ContactState, Vehicle, WheelContact

    from .design import Design

__all__ = [
    "FLANGING_NOTE",
    "AxleSound",
    "BogiePassby",
    "CurveCase",
    "CurveRequest",
    "PassbySound",
    "axle_sound",
    "bogie_sources",
    "loudest",
    "loudest_passby_sound",
]

#: What the rows of a flanging wheel say of the noise the model leaves out
FLANGING_NOTE = "flange contact: flanging noise (broad-band rubbing) is not modelled"


@dataclass(frozen=True)
class AxleSound:
    """What an axle's squeal sends to the pass-by: its contact velocity amplitude [m/s]
    and how it was found, each radiated tone [Hz] with its far-field directivity |D|
    [Pa m] at that amplitude, the harmonic balance's distortion (the contact force's
    rms beyond its fundamental over the modal force; under 0.1 the amplitude is within
    a few per cent of the time domain's) and a note where something was left out."""

    method: AmplitudeMethod
    amplitude_m_s: float | None = None
    tones: tuple[tuple[float, Any], ...] = ()
    nodal_diameters: int = 0
    distortion: float | None = None
    note: str = ""


@dataclass(frozen=True)
class BogiePassby:
    """The bogie's pass-by at one radius and train speed: free field, and over the ground
    (None: not asked), with which source is whose wheel, and the sources."""

    free: PassbyResult
    ground: PassbyResult | None
    owners: tuple[int, ...]
    sources: tuple[PassbySource, ...] = ()

    def wheel_levels(self, wheel: int) -> tuple[float, float, float, float] | None:
        """(L_pmax, L_pAmax, SEL, SEL_A) [dB] of one wheel (its index in
        ``track.curving.WHEELS``) alone in free field; None where it is silent."""
        idx = [i for i, w in enumerate(self.owners) if w == wheel]
        return self.free.levels_of(idx) if idx else None

    def wheel_band_maxima_dba(self, wheel: int, centres_hz: Sequence[float]) -> np.ndarray:
        """One wheel's largest A-weighted level over the pass-by in each one-third-octave
        band [dB(A) re 20 uPa] in free field (-inf where it has no tone)."""
        idx = [i for i, w in enumerate(self.owners) if w == wheel]
        if not idx:
            return np.full(len(centres_hz), -math.inf)
        return self.free.band_maxima_db(centres_hz, a_weighted=True, sources=idx)


@dataclass(frozen=True)
class CurveCase:
    """One wheel at one radius and train speed: its steady curving, the chain's analysis at
    each of its contacts it analysed (``analyses``, of the contacts ``states``: those
    carrying load, in ``wheel.contacts`` order; ``analysis`` the one
    that decides; at a contact where nothing grows, the eigenvalues without per-mode rows,
    ``ChainOptions.stable_rows``), its squeal's amplitude and sound (None: silent) and the
    bogie's pass-by it takes part in (None: no wheel of the bogie squeals audibly)."""

    radius_m: float
    train_speed_km_h: float
    wheel: WheelContact
    analyses: tuple[Analysis, ...]
    sound: AxleSound | None = None
    passby: BogiePassby | None = None
    states: tuple[ContactState, ...] = ()

    def __post_init__(self) -> None:
        if len(self.analyses) != len(self.contacts):
            raise ValueError(
                f"{len(self.analyses)} analyses for {len(self.contacts)} contacts: give the "
                "states of the contacts analysed (those carrying load) when they are not all the wheel's"
            )

    @property
    def contacts(self) -> tuple[ContactState, ...]:
        """The contacts analysed, in ``analyses``' order."""
        return self.states or self.wheel.contacts

    def __repr__(self) -> str:  # one line: the meshes and records stay out of a notebook's view
        v = self.analysis.verdict
        said = (
            f"squeals in {v.get('mode')} at {v.get('tone_hz'):.1f} Hz by {v.get('mechanism')}"
            if v.squeals
            else "no squeal"
        )
        level = self.to_record()["passby_lpamax_dba"]
        heard = f", L_pAmax {level:.1f} dB(A)" if level is not None else ""
        return (
            f"CurveCase(R={self.radius_m:g} m, V={self.train_speed_km_h:g} km/h, "
            f"{self.wheel.axle} {self.wheel.rail}: {said}{heard})"
        )

    @property
    def deciding(self) -> int:
        """The index of the contact whose verdict is the wheel's: the squealing one whose
        squeal grows fastest, else the wheel's main contact (the flange's where it touches)."""
        growing = [
            (a.verdict.get("growth_rate_1_s") or 0.0, i)
            for i, a in enumerate(self.analyses)
            if a.verdict.squeals
        ]
        if growing:
            return max(growing)[1]
        return max(range(len(self.contacts)), key=lambda i: abs(self.contacts[i].contact_angle_rad))

    @property
    def analysis(self) -> Analysis:
        return self.analyses[self.deciding]

    @property
    def index(self) -> int:
        from track.curving import WHEELS

        return WHEELS.index((self.wheel.axle, self.wheel.rail))

    def band_lpamax_dba(self, centres_hz: Sequence[float]) -> np.ndarray:
        """The wheel's own L_pAmax per one-third-octave band of centre ``centres_hz`` at the
        pass-by position, free field [dB(A) re 20 uPa] (-inf: no tone in the band)."""
        if self.passby is None:
            return np.full(len(centres_hz), -math.inf)
        return self.passby.wheel_band_maxima_dba(self.index, centres_hz)

    def to_record(self) -> dict[str, Any]:
        """curve.csv's row and summary.json's case."""
        v, w, s, p = self.analysis.verdict, self.wheel, self.sound, self.passby
        c = self.contacts[self.deciding]
        mine = p.wheel_levels(self.index) if p is not None else None
        bogie = (p.free.lpmax_db, p.free.lpamax_dba, p.free.sel_db, p.free.sel_dba) if p is not None else None
        ground = p.ground.lpamax_dba if p is not None and p.ground is not None else None
        speed = self.train_speed_km_h / 3.6
        notes = [s.note if s is not None else "", FLANGING_NOTE if w.flange_contact else ""]
        return {
            "radius_m": self.radius_m,
            "train_speed_km_h": self.train_speed_km_h,
            "axle": w.axle,
            "rail": w.rail,
            "lateral_shift_mm": 1e3 * w.lateral_shift_m,
            "angle_of_attack_rad": w.angle_of_attack_rad,
            "flange_contact": w.flange_contact,
            "contacts": len(w.contacts),
            "deciding_contact": "flange" if c.on_flange else "tread",
            "contact_angle_deg": math.degrees(c.contact_angle_rad),
            "flange_angle_deg": math.degrees(w.main.contact_angle_rad) if w.flange_contact else None,
            "wheel_load_n": w.wheel_load_n,
            "normal_force_n": c.normal_force_n,
            "lateral_force_n": w.lateral_force_n,
            "longitudinal_creepage": c.longitudinal_creepage,
            "lateral_creepage": c.lateral_creepage,
            "spin_creepage_1_m": c.spin_creepage_1_m,
            "crabbing_velocity_m_s": speed * c.crabbing_velocity_fraction,
            "rolling_speed_m_s": speed,
            "squeals": v.squeals,
            "verdict_mode": v.get("mode") or "",
            "mechanism": v.get("mechanism") or "",
            "tone_hz": v.get("tone_hz"),
            "growth_rate_1_s": v.get("growth_rate_1_s"),
            "amplitude_m_s": s.amplitude_m_s if s is not None else None,
            "amplitude_method": s.method if s is not None and s.amplitude_m_s is not None else "",
            "harmonic_distortion": s.distortion if s is not None else None,
            "amplitude_note": "; ".join(n for n in notes if n),
            "passby_lpamax_dba": finite_or_none(mine[1]) if mine else None,
            "passby_sel_dba": finite_or_none(mine[3]) if mine else None,
            "bogie_lpmax_db": finite_or_none(bogie[0]) if bogie else None,
            "bogie_lpamax_dba": finite_or_none(bogie[1]) if bogie else None,
            "bogie_sel_dba": finite_or_none(bogie[3]) if bogie else None,
            "bogie_lpamax_ground_dba": finite_or_none(ground) if ground is not None else None,
        }


def axle_sound(a: Analysis) -> AxleSound | None:
    """What one wheel's analysis sends to the pass-by (None: it does not squeal audibly):
    its outcome's amplitude, method and each radiated tone's directivity at it."""
    from .verdict import LOWEST_SQUEAL_HZ

    o = a.verdict.outcome
    if not a.verdict.squeals or o is None or not o.tone_hz >= LOWEST_SQUEAL_HZ:
        return None
    method: AmplitudeMethod = "time domain" if o.simulation is not None else "harmonic balance"
    balance = o.balance
    note = balance.note if balance is not None else ""
    distortion = balance.distortion if balance is not None else None
    if o.sound is None:
        why = "a modal model's modes do not radiate" if o.amplitude_m_s is not None else ""
        return AxleSound(method, o.amplitude_m_s, (), o.mode.nodal_diameters, distortion, note or why)
    tones = tuple(
        (float(f), h.velocity_amplitude_m_s * h.radiation.directivity_pa_m)
        for h, f in zip(o.sound.harmonics, o.sound.frequencies_hz)
    )
    return AxleSound(method, o.amplitude_m_s, tones, o.mode.nodal_diameters, distortion, note)


def _sources(
    sound: AxleSound, wheel: WheelContact, wheelbase_m: float, rolling_radius_m: float
) -> list[PassbySource]:
    """The wheel as pass-by sources, one per radiated tone."""
    from acoustics.farfield import DIRECTIVITY_ANGLES
    from acoustics.levels import a_weighting_db
    from acoustics.passby import HALF_TRACK_M, PassbySource

    along = 0.5 * wheelbase_m if wheel.axle == "leading" else -0.5 * wheelbase_m
    across = HALF_TRACK_M if wheel.rail == "outer" else -HALF_TRACK_M  # the microphone outside the curve
    return [
        PassbySource(
            along,
            across,
            rolling_radius_m,
            f,
            d,
            DIRECTIVITY_ANGLES,
            sound.nodal_diameters,
            float(a_weighting_db(f)),
        )
        for f, d in sound.tones
    ]


def bogie_sources(
    cases: Sequence[CurveCase], wheelbase_m: float, rolling_radius_m: float
) -> tuple[list, list]:
    """The pass-by sources of one radius and speed's four wheels, and whose each is."""
    sources: list[PassbySource] = []
    owners: list[int] = []
    for c in cases:
        if c.sound is not None:
            mine = _sources(c.sound, c.wheel, wheelbase_m, rolling_radius_m)
            sources += mine
            owners += [c.index] * len(mine)
    return sources, owners


@dataclass(frozen=True, eq=False)
class PassbySound:
    """The sound of a curve map's loudest bogie pass-by at the ISO 3095 position (free
    field): the radius and speed it was heard at, the wheels of that curve, its length [s]
    and the pressure at the microphone [Pa], sampled at ``sample_rate_hz``."""

    radius_m: float
    train_speed_km_h: float
    cases: tuple[CurveCase, ...] = field(repr=False)
    duration_s: float
    sample_rate_hz: int
    pressure_pa: np.ndarray = field(repr=False)


def loudest(cases: Sequence[CurveCase]) -> list[CurveCase]:
    """The four wheels of the radius and speed whose bogie pass-by is loudest in dB(A)
    (empty: nothing squeals audibly)."""
    heard = [c for c in cases if c.passby is not None]
    if not heard:
        return []
    top = max(heard, key=lambda c: c.passby.free.lpamax_dba)  # type: ignore[union-attr]
    return [c for c in cases if (c.radius_m, c.train_speed_km_h) == (top.radius_m, top.train_speed_km_h)]


def loudest_passby_sound(cases: Sequence[CurveCase]) -> PassbySound | None:
    """The loudest pass-by of a map as heard (:class:`PassbySound`): its sources' pressure
    at the microphone with the Doppler shift, over ten times the microphone's distance each
    side (at most 12 s); None where nothing squeals audibly."""
    from acoustics.passby import MICROPHONE_DISTANCE_M, passby_pressure
    from acoustics.signal import WAV_RATE_HZ

    group = loudest(cases)
    if not group:
        return None
    assert group[0].passby is not None  # the loudest group has a pass-by
    speed = group[0].train_speed_km_h / 3.6
    duration = min(12.0, 2 * 10.0 * MICROPHONE_DISTANCE_M / speed)
    _, p = passby_pressure(list(group[0].passby.sources), speed, duration, WAV_RATE_HZ)
    return PassbySound(group[0].radius_m, group[0].train_speed_km_h, tuple(group), duration, WAV_RATE_HZ, p)


@dataclass(frozen=True)
class CurveRequest:
    """What a curve map asks, the one record its stages take.

    Attributes
    ----------
    radii_m, train_speeds_km_h : sequence of float
        Curve radii [m] and train speeds [km/h] (kept as tuples).
    cant_mm : float
        The curves' installed cant [mm].
    vehicle : track.bogie_curving.Vehicle or None
        The bogie (None: the design's own, so that a treatment of the bogie is read from
        the treated design).
    c22 : float or None
        Kalker's C22 for every contact (None: each contact's own ellipse's).
    method : {"harmonic balance", "time domain"}
        How a squealing wheel's amplitude is found.
    ground_reflection : float or None
        The ground's reflection factor (0 to 1) of a second pass-by level; None: free
        field only.

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> from wheel_squeal.curve import CurveRequest
    >>> d = ws.load_design("railway_920_track")
    >>> r = CurveRequest([150, 300], [40])
    >>> r.radii_m, r.bogie(d).wheelbase_m
    ((150.0, 300.0), 2.5)
    """

    radii_m: Sequence[float]
    train_speeds_km_h: Sequence[float]
    vehicle: Vehicle | None = None
    cant_mm: float = 0.0
    c22: float | None = None
    method: AmplitudeMethod = "harmonic balance"
    ground_reflection: float | None = None

    def __post_init__(self) -> None:  # any sequences of numbers, kept as tuples of floats
        object.__setattr__(self, "radii_m", tuple(float(r) for r in self.radii_m))
        object.__setattr__(self, "train_speeds_km_h", tuple(float(v) for v in self.train_speeds_km_h))
        object.__setattr__(self, "cant_mm", float(self.cant_mm))

    def bogie(self, design: Design) -> Vehicle:
        """The bogie this request runs ``design``'s wheels in."""
        return self.vehicle or design.vehicle.vehicle()
