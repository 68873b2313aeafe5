"""A wheel design in curves: for each curve radius and train speed, the bogie's steady
curving (``track.bogie_curving``: each wheel's contacts, load, creepages and forces), the
chain's verdict at each wheel's own contacts, the squealing wheels' amplitude and sound,
and the level of the bogie's pass-by at the ISO 3095 position (``acoustics.passby``).

Each contact of a wheel (the tread's; on a flanging wheel the flange's too) is analysed as
the design at that contact (:class:`~wheel_squeal.design.ContactSite`: the modes read
there, the Hertz ellipse of that contact's curvatures under its normal force, Kalker's C22
of that ellipse, the friction the longitudinal creep force leaves to the lateral one) at
the wheel's rolling speed and the contact's lateral sliding speed. A wheel's verdict is the
one of its contacts whose squeal grows fastest (``reduced.stability.leading_mode`` inside
each); the contacts are not coupled through the wheel's modes. Flanging noise, the
broad-band noise of the flange's rubbing, is not modelled: the rows where a flange touches
say so.

The amplitude and sound of a squealing wheel are the chain's, by one of its two methods
(:data:`wheel_squeal.types.AmplitudeMethod`, ``ChainOptions.amplitude``): the harmonic
balance of the squeal mode (the default here: fast, the fundamental radiated) or the
time domain (every harmonic radiated, seconds per squealing contact).
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from .analysis import ChainOptions
from .api import contact_law
from .budget import CostPlan
from .chain import AMPLITUDE_METHODS
from .curve_case import AxleSound, BogiePassby, CurveCase, axle_sound, bogie_sources
from .design import Design
from .errors import RequestError
from .plan import CurveSize, check_curve_files, curve_plan, squealing_axles
from .stability import excitable, mode_dofs
from .types import AmplitudeMethod

if TYPE_CHECKING:
    from fem.modes import ModeSet
    from reduced import ContactLaw, OperatingPoint
    from track.bogie_curving import ContactState, Vehicle, WheelContact
    from track.contact_geometry import ContactGeometry

    from .context import RunContext

__all__ = [
    "AMPLITUDE_METHODS",
    "AxleSound",
    "BogiePassby",
    "ContactSiteAnalysis",
    "CurveCase",
    "contact_geometry",
    "curve",
    "curve_estimate",
    "wheel_sites",
]


#: What a map keeps of each time-domain record once its metrics and sound are taken: the
#: contact's last this many seconds and the final state (a whole record, a few seconds
#: of the rail's and the modes' states at the integrator's step, is tens of MB: a map of
#: hundreds would not fit)
KEPT_RECORD_S = 0.05


#: A contact carrying less than this share of its wheel's load is not analysed (it is
#: the first touch of a two-point contact, about to lift)
LEAST_LOAD_SHARE = 0.01


@dataclass(frozen=True)
class ContactSiteAnalysis:
    """One contact of a wheel in a curve: the design at that contact
    (:class:`~wheel_squeal.design.ContactSite`), its operating point and contact law."""

    state: ContactState
    design: Design
    op: OperatingPoint
    law: ContactLaw


def contact_geometry(design: Design) -> ContactGeometry:
    """The design's wheel (its outline's running surface) on its rail (UIC60 at 1:40):
    where each wheel of a wheelset touches for each lateral shift (``track.contact_geometry``)."""
    from track.contact_geometry import ContactGeometry
    from track.profiles import running_surface

    outline = design.wheel.profile
    if outline is None:
        raise RequestError(
            f"{design.name} is a parametric wheel: a curve needs its running surface and flange, "
            "a design with a [profile] outline"
        )
    r0 = design.rolling_radius
    return ContactGeometry(wheel=running_surface(outline, r0), rolling_radius_m=r0)


def wheel_sites(design: Design, wheel: WheelContact, train_speed_km_h: float) -> list[ContactSiteAnalysis]:
    """Each contact of ``wheel`` as the design there (module docstring); contacts with
    less than :data:`LEAST_LOAD_SHARE` of the wheel's load left out."""
    from dataclasses import replace

    from geometry.contact import frame_on_running_surface
    from reduced import OperatingPoint

    from .design import ContactSite

    assert design.wheel.profile is not None  # contact_geometry refused a parametric wheel
    speed = train_speed_km_h / 3.6
    mu = design.contact.friction_coefficient
    sites = []
    for c in wheel.contacts:
        if c.load_share < LEAST_LOAD_SHARE:
            continue
        frame = frame_on_running_surface(design.wheel.profile, c.point.wheel_lateral_m)
        at = design.replace(
            normal_load=c.normal_force_n, c22=c.c22, friction_coefficient=c.lateral_friction_coefficient(mu)
        )
        at = replace(at, contact_site=ContactSite(frame, c.point.relative_transverse_radius_m))
        op = OperatingPoint(speed, speed * c.crabbing_velocity_fraction)
        sites.append(ContactSiteAnalysis(c, at, op, contact_law(at)))
    return sites


def curve(
    design: Design,
    radii_m: Sequence[float],
    train_speeds_km_h: Sequence[float],
    *,
    cant_mm: float = 0.0,
    vehicle: Vehicle | None = None,
    method: AmplitudeMethod = "harmonic balance",
    context: RunContext | None = None,
    ground_reflection: float | None = None,
) -> list[CurveCase]:
    """Every wheel of the design's bogie at every radius and train speed (module docstring).

    Parameters
    ----------
    design : Design
        The wheel (an outline with its flange) and what it rolls on (a track); its
        ``[vehicle]`` the bogie.
    radii_m, train_speeds_km_h : sequence of float
        Curve radii [m] and train speeds [km/h].
    cant_mm : float
        The curves' installed cant [mm] (with the speed, the cant deficiency).
    vehicle : track.bogie_curving.Vehicle, optional
        The bogie instead of the design's ``[vehicle]``.
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
    >>> d = ws.load_design("railway_920_track")
    >>> cases = ws.curve(d, [150.0], [40.0], context=ws.RunContext.of("fast"))
    >>> [(c.wheel.axle, c.wheel.rail, c.wheel.flange_contact) for c in cases][:2]
    [('leading', 'inner', False), ('leading', 'outer', True)]
    """
    from dataclasses import replace

    from acoustics.passby import passby

    from .chain import analyse
    from .context import RunContext

    ctx = context or RunContext.of("balanced")
    vehicle = vehicle or design.vehicle.vehicle()
    modes, _, curvings = _planned(
        design, radii_m, train_speeds_km_h, vehicle, cant_mm, method, ctx, ground_reflection, True
    )
    options = ChainOptions(mode="model", stop_after="sound", remedy=False, amplitude=method)
    cases: list[CurveCase] = []
    for (radius, speed), wheels in curvings.items():
        ctx.budget.checkpoint(f"the curve of {radius:g} m at {speed:g} km/h")
        group = []
        for wheel, sites in wheels:
            analyses = tuple(
                analyse(s.design, op=s.op, options=options, context=ctx, modes=_moved(modes, s.design))
                for s in sites
            )
            case = CurveCase(radius, speed, wheel, tuple(a.tail(KEPT_RECORD_S) for a in analyses))
            group.append(replace(case, sound=axle_sound(analyses[case.deciding])))
        sources, owners = bogie_sources(group, vehicle.wheelbase_m, design.rolling_radius)
        if sources:
            free = passby(sources, speed / 3.6)
            ground = None
            if ground_reflection is not None:
                ground = passby(sources, speed / 3.6, reflection=ground_reflection)
            bp = BogiePassby(free, ground, tuple(owners))
            group = [replace(c, passby=bp) for c in group]
        cases += group
    return cases


def _moved(modes: ModeSet, at: Design) -> ModeSet:
    """The design's modes read at a contact site."""
    from fem.moved_contact import modes_at_contact

    return modes_at_contact(modes, at.contact_frame)


def curve_estimate(
    design: Design,
    radii_m: Sequence[float],
    train_speeds_km_h: Sequence[float],
    *,
    cant_mm: float = 0.0,
    vehicle: Vehicle | None = None,
    method: AmplitudeMethod = "harmonic balance",
    context: RunContext | None = None,
    ground_reflection: float | None = None,
) -> CostPlan:
    """What :func:`curve` would take (``budget.CostPlan``: its parts' seconds and
    bytes), from the wheel's modes, the curving and every contact's linear stability,
    without refusing anything (``benchmarks/bench_estimates.py`` sets it beside the time
    taken)."""
    from .context import RunContext

    ctx = context or RunContext.of("balanced")
    vehicle = vehicle or design.vehicle.vehicle()
    return _planned(
        design, radii_m, train_speeds_km_h, vehicle, cant_mm, method, ctx, ground_reflection, False
    )[1]


Curvings = dict[tuple[float, float], list[tuple["WheelContact", list[ContactSiteAnalysis]]]]


def _planned(
    design: Design,
    radii_m: Sequence[float],
    train_speeds_km_h: Sequence[float],
    vehicle: Vehicle,
    cant_mm: float,
    method: AmplitudeMethod,
    ctx: RunContext,
    ground_reflection: float | None,
    check: bool,
) -> tuple[ModeSet, CostPlan, Curvings]:
    """The request checked and priced in its three steps (``plan.curve_plan``), each
    refused beyond the budget before the next where ``check``: (the modes, the plan, each
    curve's wheels and their contact sites)."""
    from track.bogie_curving import steady_curving
    from track.curving import check_curve

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
    size = CurveSize(len(radii_m), len(train_speeds_km_h))
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
    try:
        for r in radii_m:
            for v in train_speeds_km_h:
                check_curve(float(r), float(v), vehicle.wheelbase_m, cant_mm)
    except ValueError as exc:
        raise RequestError(str(exc)) from None
    geometry = contact_geometry(design)
    modes = compute_modes(
        design, ctx.fidelity, fmax_hz=ctx.fmax_hz, cache=ctx.cache, progress=ctx.progress, budget=ctx.budget
    )
    contact = contact_law(design)
    wheel_dofs = mode_dofs(excitable(modes, contact), design)
    checked(plan_of(wheel_dofs=wheel_dofs))
    curvings: Curvings = {}
    with ctx.progress.stage(f"steady curving of {size.curves:,} curves"):
        for r in radii_m:
            for v in train_speeds_km_h:
                wheels = steady_curving(
                    geometry,
                    vehicle,
                    float(r),
                    float(v),
                    wheel_load_n=design.contact.normal_load,
                    friction_coefficient=design.contact.friction_coefficient,
                    cant_mm=cant_mm,
                    youngs_modulus_pa=design.wheel.youngs_modulus,
                    poissons_ratio=design.wheel.poissons_ratio,
                )
                curvings[(float(r), float(v))] = [(w, wheel_sites(design, w, float(v))) for w in wheels]
    sites = [
        (s.design, _moved(modes, s.design), s.law, s.op)
        for wheels in curvings.values()
        for _, mine in wheels
        for s in mine
        if s.op.crabbing_velocity_m_s != 0.0
    ]
    key = modes_cache_key(design, ctx.fidelity, ctx.fmax_hz)
    with ctx.progress.stage(f"linear stability at {len(sites):,} sliding contacts"):
        squealing = squealing_axles(
            sites, method == "time domain", lambda m, f: radiation_cached(ctx.cache, key, m, f)
        )
    return modes, checked(plan_of(wheel_dofs=wheel_dofs, squealing=squealing)), curvings
