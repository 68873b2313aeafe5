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
from .budget import CostPlan
from .chain import AMPLITUDE_METHODS
from .design import Design
from .errors import RequestError
from .outputs import finite_or_none
from .plan import CurveSize, check_curve_files, curve_plan, squealing_axles
from .stability import excitable, mode_dofs
from .types import AmplitudeMethod

if TYPE_CHECKING:
    from acoustics.passby import PassbyResult, PassbySource
    from fem.modes import ModeSet
    from track.curving import Bogie, WheelKinematics

    from .context import RunContext

__all__ = ["AMPLITUDE_METHODS", "AxleSound", "BogiePassby", "CurveCase", "curve", "curve_estimate"]


#: What a map keeps of each time-domain record once its metrics and sound are taken: the
#: contact's last this many seconds and the final state (a whole record, a few seconds
#: of the rail's and the modes' states at the integrator's step, is tens of MB: a map of
#: hundreds would not fit)
KEPT_RECORD_S = 0.05


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
        )
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
    from track.curving import wheel_kinematics

    from .chain import analyse
    from .context import RunContext

    ctx = context or RunContext.of("balanced")
    modes, _ = _planned(design, radii_m, train_speeds_km_h, bogie, method, ctx, ground_reflection, True)
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
                    by_axle[w.axle] = (a.tail(KEPT_RECORD_S), axle_sound(a))
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


def curve_estimate(
    design: Design,
    radii_m: Sequence[float],
    train_speeds_km_h: Sequence[float],
    bogie: Bogie,
    *,
    method: AmplitudeMethod = "harmonic balance",
    context: RunContext | None = None,
    ground_reflection: float | None = None,
) -> CostPlan:
    """What :func:`curve` would take (``budget.CostPlan``: its parts' seconds and
    bytes), from the wheel's modes and every sliding axle's linear stability, without
    refusing anything (``benchmarks/bench_estimates.py`` sets it beside the time taken)."""
    from .context import RunContext

    ctx = context or RunContext.of("balanced")
    return _planned(design, radii_m, train_speeds_km_h, bogie, method, ctx, ground_reflection, False)[1]


def _planned(
    design: Design,
    radii_m: Sequence[float],
    train_speeds_km_h: Sequence[float],
    bogie: Bogie,
    method: AmplitudeMethod,
    ctx: RunContext,
    ground_reflection: float | None,
    check: bool,
) -> tuple[ModeSet, CostPlan]:
    """The request checked and priced in its three steps (``plan.curve_plan``), each
    refused beyond the budget before the next where ``check``: (the modes, the plan)."""
    from reduced import OperatingPoint
    from track.curving import check_curve, wheel_kinematics

    from .api import compute_modes
    from .modes import modes_cache_key
    from .sound import radiation_cached

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
    size = _size(radii_m, train_speeds_km_h, bogie)
    plan_of = functools.partial(
        curve_plan,
        design,
        size,
        method == "time domain",
        ctx.fidelity,
        ctx.fmax_hz,
        passbys=1 if ground_reflection is None else 2,
    )

    def checked(plan: CostPlan) -> CostPlan:
        if check:
            plan.check(ctx.budget, "the curve map", "")
        return plan

    checked(plan_of())  # before the modes: counts alone
    check_curve_files(size, ctx.budget.max_file_bytes)
    tightest = float(min(radii_m, default=1.0))
    try:  # the tightest curve at the slowest and fastest speed bound every other
        for speed in (min(train_speeds_km_h, default=1.0), max(train_speeds_km_h, default=1.0)):
            check_curve(tightest, float(speed), bogie)
    except ValueError as exc:
        raise RequestError(str(exc)) from None
    modes = compute_modes(
        design, ctx.fidelity, fmax_hz=ctx.fmax_hz, cache=ctx.cache, progress=ctx.progress, budget=ctx.budget
    )
    contact = contact_law(design)
    wheel_dofs = mode_dofs(excitable(modes, contact), design)
    checked(plan_of(wheel_dofs=wheel_dofs))
    sliding = [  # each axle's operating point (the wheels of an axle share it)
        OperatingPoint(w.rolling_speed_m_s, w.crabbing_velocity_m_s)
        for r in radii_m
        for v in train_speeds_km_h
        for w in wheel_kinematics(float(r), float(v), bogie)
        if w.crabbing_velocity_m_s != 0.0 and w.rail == "inner"
    ]
    key = modes_cache_key(design, ctx.fidelity, ctx.fmax_hz)
    with ctx.progress.stage(f"linear stability of {len(sliding):,} sliding axles"):
        squealing = squealing_axles(
            design,
            modes,
            contact,
            sliding,
            method == "time domain",
            lambda m, f: radiation_cached(ctx.cache, key, m, f),
        )
    return modes, checked(plan_of(wheel_dofs=wheel_dofs, squealing=squealing))


def _size(radii_m: Sequence[float], train_speeds_km_h: Sequence[float], bogie: Bogie) -> CurveSize:
    """The map's size: its curves, and the bogie's axles that slide (a rigid bogie's
    trailing axle runs radially)."""
    return CurveSize(len(radii_m), len(train_speeds_km_h), 2, 1 if bogie.kind == "rigid" else 2)
