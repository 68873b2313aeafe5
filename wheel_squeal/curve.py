"""A wheel design in curves: for each curve radius, train speed and wheel of a two-axle
bogie, the kinematics (``track.curving``), the chain's verdict at that operating point,
the squealing wheels' amplitude and sound, and the level of the bogie's pass-by at the
ISO 3095 position (``acoustics.passby``).

The two wheels of an axle share its angle of attack and, here, its tread contact and its
load (no flange contact, no cant deficiency: ``track.curving``): one analysis per axle
answers for both; the inner and outer wheels differ in the pass-by, on the rails nearer
and farther from the microphone (on the curve's outer side).

The amplitude and sound of a squealing wheel are the chain's, by one of its two methods
(:data:`wheel_squeal.types.AmplitudeMethod`, ``ChainOptions.amplitude``): the harmonic
balance of the squeal mode (the default here: fast, the fundamental radiated) or the
time domain (every harmonic radiated, seconds per squealing axle).
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .analysis import Analysis, ChainOptions
from .api import contact_law
from .chain import AMPLITUDE_METHODS
from .design import Design
from .errors import RequestError
from .outputs import finite_or_none
from .plan import CurveSize, check_curve_files, curve_plan, time_domain_axle_seconds
from .stability import excitable, mode_dofs
from .types import AmplitudeMethod

if TYPE_CHECKING:
    from acoustics.passby import PassbyResult, PassbySource
    from track.curving import Bogie, WheelKinematics

    from .context import RunContext

__all__ = ["AMPLITUDE_METHODS", "AxleSound", "BogiePassby", "CurveCase", "curve"]


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
    (None: not asked), with which source is whose wheel."""

    free: PassbyResult
    ground: PassbyResult | None
    owners: tuple[int, ...]

    def wheel_levels(self, wheel: int) -> tuple[float, float, float, float] | None:
        """(L_pmax, L_pAmax, SEL, SEL_A) [dB] of one wheel (its index in
        ``track.curving.WHEELS``) alone in free field; None where it is silent."""
        idx = [i for i, w in enumerate(self.owners) if w == wheel]
        return self.free.levels_of(idx) if idx else None


@dataclass(frozen=True)
class CurveCase:
    """One wheel at one radius and train speed: its kinematics, the chain's analysis, its
    squeal's amplitude and sound (None: silent) and the bogie's pass-by it takes part in
    (None: no wheel of the bogie squeals audibly)."""

    radius_m: float
    train_speed_km_h: float
    wheel: WheelKinematics
    analysis: Analysis
    sound: AxleSound | None = None
    passby: BogiePassby | None = None

    @property
    def index(self) -> int:
        from track.curving import WHEELS

        return WHEELS.index((self.wheel.axle, self.wheel.rail))

    def to_record(self) -> dict[str, Any]:
        """curve.csv's row and summary.json's case."""
        v, w, s, p = self.analysis.verdict, self.wheel, self.sound, self.passby
        mine = p.wheel_levels(self.index) if p is not None else None
        bogie = (p.free.lpmax_db, p.free.lpamax_dba, p.free.sel_db, p.free.sel_dba) if p is not None else None
        ground = p.ground.lpamax_dba if p is not None and p.ground is not None else None
        return {
            "radius_m": self.radius_m,
            "train_speed_km_h": self.train_speed_km_h,
            "axle": w.axle,
            "rail": w.rail,
            "angle_of_attack_rad": w.angle_of_attack_rad,
            "lateral_creepage": w.lateral_creepage,
            "crabbing_velocity_m_s": w.crabbing_velocity_m_s,
            "rolling_speed_m_s": w.rolling_speed_m_s,
            "squeals": v.squeals,
            "verdict_mode": v.get("mode") or "",
            "mechanism": v.get("mechanism") or "",
            "tone_hz": v.get("tone_hz"),
            "growth_rate_1_s": v.get("growth_rate_1_s"),
            "amplitude_m_s": s.amplitude_m_s if s is not None else None,
            "amplitude_method": s.method if s is not None and s.amplitude_m_s is not None else "",
            "harmonic_distortion": s.distortion if s is not None else None,
            "amplitude_note": s.note if s is not None else "",
            "passby_lpamax_dba": finite_or_none(mine[1]) if mine else None,
            "passby_sel_dba": finite_or_none(mine[3]) if mine else None,
            "bogie_lpmax_db": finite_or_none(bogie[0]) if bogie else None,
            "bogie_lpamax_dba": finite_or_none(bogie[1]) if bogie else None,
            "bogie_sel_dba": finite_or_none(bogie[3]) if bogie else None,
            "bogie_lpamax_ground_dba": finite_or_none(ground) if ground is not None else None,
        }


def axle_sound(a: Analysis) -> AxleSound | None:
    """What one axle's analysis sends to the pass-by (None: it does not squeal audibly):
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
    sound: AxleSound, wheel: WheelKinematics, wheelbase_m: float, rolling_radius_m: float
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
        )  # fmt: skip
        for f, d in sound.tones
    ]


def bogie_sources(cases: Sequence[CurveCase], bogie: Bogie, rolling_radius_m: float) -> tuple[list, list]:
    """The pass-by sources of one radius and speed's four wheels, and whose each is."""
    sources: list[PassbySource] = []
    owners: list[int] = []
    for c in cases:
        if c.sound is not None:
            mine = _sources(c.sound, c.wheel, bogie.wheelbase_m, rolling_radius_m)
            sources += mine
            owners += [c.index] * len(mine)
    return sources, owners


def curve(
    design: Design,
    radii_m: Sequence[float],
    train_speeds_km_h: Sequence[float],
    bogie: Bogie,
    *,
    method: AmplitudeMethod = "harmonic balance",
    context: RunContext | None = None,
    ground_reflection: float | None = None,
) -> list[CurveCase]:
    """Every wheel of ``bogie`` at every radius and train speed (module docstring).

    Parameters
    ----------
    design : Design
        The wheel and what it rolls on (a track).
    radii_m, train_speeds_km_h : sequence of float
        Curve radii [m] and train speeds [km/h].
    bogie : track.curving.Bogie
    method : {"harmonic balance", "time domain"}
        How a squealing wheel's amplitude is found (module docstring).
    ground_reflection : float, optional
        The ground's reflection factor (0 to 1) for a second pass-by level over the
        ground (``acoustics.passby.GROUND_DEPTH_M`` below the rail head); None: free
        field only.

    Returns
    -------
    list of CurveCase
        Radius by radius, speed by speed, the four wheels in ``track.curving.WHEELS`` order.

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> from track.curving import Bogie
    >>> cases = ws.curve(ws.load_design("railway_920_track"), [150.0], [40.0], Bogie(2.5),
    ...                  context=ws.RunContext.of("fast"))
    >>> [(c.wheel.axle, c.wheel.rail, c.analysis.verdict.squeals) for c in cases][:2]
    [('leading', 'inner', True), ('leading', 'outer', True)]
    """
    from dataclasses import replace

    from acoustics.passby import passby
    from reduced import OperatingPoint
    from track.curving import check_curve, wheel_kinematics

    from .api import compute_modes
    from .chain import analyse
    from .context import RunContext

    if design.counter_body.KIND != "track":
        raise RequestError(
            f"{design.name} rolls on a {design.counter_body.KIND}: a curve needs a design on a track"
        )
    if ground_reflection is not None and not 0.0 <= ground_reflection <= 1.0:
        raise RequestError(
            f"ground reflection {ground_reflection:g}: a reflection factor from 0 (absorbing) to 1 (rigid)"
        )
    if method not in AMPLITUDE_METHODS:
        raise RequestError(f"amplitude method {method!r}: one of {', '.join(AMPLITUDE_METHODS)}")
    ctx = context or RunContext.of("balanced")
    size = _size(radii_m, train_speeds_km_h, bogie)
    plan_of = functools.partial(
        curve_plan, design, size, method == "time domain", ctx.fidelity, ctx.fmax_hz,
        passbys=1 if ground_reflection is None else 2,
    )  # fmt: skip
    plan_of().check(ctx.budget, "the curve map", "")  # before the modes: counts alone
    check_curve_files(size, ctx.budget.max_file_bytes)
    tightest, slowest, fastest = (
        min(radii_m, default=1.0),
        min(train_speeds_km_h, default=1.0),
        max(train_speeds_km_h, default=1.0),
    )
    try:  # the tightest curve at the slowest and fastest speed bound every other
        check_curve(float(tightest), float(slowest), bogie)
        check_curve(float(tightest), float(fastest), bogie)
    except ValueError as exc:
        raise RequestError(str(exc)) from None
    modes = compute_modes(design, ctx.fidelity, fmax_hz=ctx.fmax_hz, cache=ctx.cache, progress=ctx.progress,
                          budget=ctx.budget)  # fmt: skip
    contact = contact_law(design)
    wheel = excitable(modes, contact)
    td = None
    if method == "time domain":
        ops = [  # the slowest: the squeal model's step is shortest there
            OperatingPoint(w.rolling_speed_m_s, w.crabbing_velocity_m_s)
            for w in wheel_kinematics(float(tightest), float(slowest), bogie)
            if w.crabbing_velocity_m_s != 0.0
        ]
        td = time_domain_axle_seconds(design, wheel, contact, ops)
    plan_of(wheel_dofs=mode_dofs(wheel, design), time_domain_seconds=td).check(
        ctx.budget, "the curve map", ""
    )
    options = ChainOptions(mode="model", stop_after="sound", remedy=False, amplitude=method)
    cases: list[CurveCase] = []
    for radius in radii_m:
        for speed in train_speeds_km_h:
            ctx.budget.checkpoint(f"the curve of {float(radius):g} m at {float(speed):g} km/h")
            by_axle: dict[str, tuple[Analysis, AxleSound | None]] = {}
            group = []
            for w in wheel_kinematics(float(radius), float(speed), bogie):
                if w.axle not in by_axle:
                    op = OperatingPoint(w.rolling_speed_m_s, w.crabbing_velocity_m_s)
                    a = analyse(design, op=op, options=options, context=ctx, modes=modes)
                    by_axle[w.axle] = (a, axle_sound(a))
                a, s = by_axle[w.axle]
                group.append(CurveCase(float(radius), float(speed), w, a, s))
            sources, owners = bogie_sources(group, bogie, design.rolling_radius)
            if sources:
                free = passby(sources, speed / 3.6)
                ground = None
                if ground_reflection is not None:
                    ground = passby(sources, speed / 3.6, reflection=ground_reflection)
                bp = BogiePassby(free, ground, tuple(owners))
                group = [replace(c, passby=bp) for c in group]
            cases += group
    return cases


def _size(radii_m: Sequence[float], train_speeds_km_h: Sequence[float], bogie: Bogie) -> CurveSize:
    """The map's size: its curves, and the bogie's axles that slide (a rigid bogie's
    trailing axle runs radially)."""
    return CurveSize(len(radii_m), len(train_speeds_km_h), 2, 1 if bogie.kind == "rigid" else 2)


#: Rudd's rule of thumb: squeal in curves tighter than about this many wheelbases
RUDD_WHEELBASES = 100.0
#: The lateral creepage above which field measurements find squeal (about 0.0045)
FIELD_CREEPAGE_THRESHOLD = 0.0045
#: CNOSSOS-EU's squeal correction to rolling noise: (upper radius [m], +dB) by class
CNOSSOS_CLASSES = ((300.0, 8.0), (500.0, 5.0))


def _squeals_by(c: CurveCase, coupling: bool) -> bool:
    v = c.analysis.verdict
    return v.squeals and (v.get("mechanism") == "mode coupling") == coupling


def findings(cases: Sequence[CurveCase], bogie: Bogie) -> list[str]:
    """Where squeal stops, per train speed, beside the field's anchors: the largest radius
    at which a wheel squeals by falling friction and its lateral creepage, against
    Rudd's 100 wheelbases, the field's creepage threshold and CNOSSOS-EU's classes; and
    any squeal by mode coupling, which a falling branch does not explain."""
    out = []
    rudd = RUDD_WHEELBASES * bogie.wheelbase_m
    # a rigid bogie's leading axle reaches the threshold at R = 2a / threshold
    at_threshold = bogie.wheelbase_m / FIELD_CREEPAGE_THRESHOLD
    anchors = (
        f"the field's creepage threshold {FIELD_CREEPAGE_THRESHOLD} is reached at R = {at_threshold:.0f} m "
        f"for this wheelbase; Rudd's rule: below about {rudd:.0f} m; CNOSSOS-EU: +8 dB below 300 m, "
        "+5 dB to 500 m"
    )
    for speed in dict.fromkeys(c.train_speed_km_h for c in cases):
        mine = [c for c in cases if c.train_speed_km_h == speed]
        friction = [c for c in mine if _squeals_by(c, coupling=False)]
        coupling = sorted({c.radius_m for c in mine if _squeals_by(c, coupling=True)})
        if friction:
            top = max(friction, key=lambda c: c.radius_m)
            wider = [c.radius_m for c in mine if c.radius_m > top.radius_m and not c.analysis.verdict.squeals]
            stops = f"and not from {min(wider):g} m" if wider else "up to the widest curve asked"
            out.append(
                f"{speed:g} km/h: falling-friction squeal up to R = {top.radius_m:g} m {stops} "
                f"(lateral creepage there {top.wheel.lateral_creepage:.4f}; {anchors})"
            )
        else:
            out.append(f"{speed:g} km/h: no falling-friction squeal at any radius asked ({anchors})")
        if coupling:
            radii = ", ".join(f"{r:g}" for r in coupling)
            out.append(
                f"{speed:g} km/h: mode coupling makes a wheel squeal at R = {radii} m, whatever the creepage"
            )
    return out
