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
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from .analysis import ChainOptions
from .api import contact_law
from .chain import AMPLITUDE_METHODS
from .context import memo_get, memo_put
from .curve_case import (
    AxleSound,
    BogiePassby,
    CurveCase,
    CurveRequest,
    PassbySound,
    axle_sound,
    bogie_sources,
    loudest_passby_sound,
)
from .curve_contacts import ContactSiteAnalysis, contact_geometry, modes_at_contacts, wheel_sites
from .design import Design
from .mode_stability import excitable, mode_dofs
from .plan import CurveSize, check_curve_files, curve_plan, squealing_axles
from .runtime.budget import CostPlan
from .runtime.request_errors import RequestError
from .types import AmplitudeMethod

if TYPE_CHECKING:
    from fem.modes import ModeSet
    from track.bogie_curving import Vehicle, WheelContact

    from .context import RunContext
    from .curve_remedy import CurveRemedy
    from .mode_stability import StabilityTable

__all__ = [
    "AMPLITUDE_METHODS",
    "CurveMap",
    "AxleSound",
    "BogiePassby",
    "ContactSiteAnalysis",
    "CurveCase",
    "contact_geometry",
    "curve",
    "curve_estimate",
    "curve_map",
    "wheel_sites",
]


#: What a map keeps of each time-domain record once its metrics and sound are taken: the
#: contact's last this many seconds and the final state (a whole record, a few seconds
#: of the rail's and the modes' states at the integrator's step, is tens of MB: a map of
#: hundreds would not fit)
KEPT_RECORD_S = 0.05


@dataclass(frozen=True)
class CurveMap:
    """A curve map: its cases (:class:`CurveCase`, radius by radius, speed by speed, the
    four wheels in ``track.curving.WHEELS`` order) and what stops its squeal (None: not
    asked), and the sound of its loudest pass-by (None: nothing squeals audibly)."""

    cases: list[CurveCase]
    remedy: CurveRemedy | None = None
    loudest: PassbySound | None = None


def curve_map(
    design: Design, request: CurveRequest, *, context: RunContext | None = None, remedy: bool = True
) -> CurveMap:
    """:func:`curve`'s cases of ``request`` and, with ``remedy``, every treatment of
    :data:`wheel_squeal.curve_remedy.TREATMENTS` checked by running the map again with it
    (priced with the map before anything runs)."""
    from .curve_remedy import TREATMENTS, map_remedy

    maps = 1 + len(TREATMENTS) if remedy else 1
    ctx = context or _default_context()
    cases = _cases(design, request, ctx, maps=maps)
    heard = loudest_passby_sound(cases)
    if not remedy:
        return CurveMap(cases, loudest=heard)

    def again(treated: Design, speeds: list[float]) -> list[CurveCase]:
        # a treatment's map: free field only, priced with the map above
        asked = replace(request, train_speeds_km_h=tuple(speeds), ground_reflection=None)
        return _cases(treated, asked, ctx, check=False)

    asked = (list(request.radii_m), list(request.train_speeds_km_h))
    return CurveMap(cases, map_remedy(design, cases, again, asked), heard)


def curve(
    design: Design,
    radii_m: Sequence[float],
    train_speeds_km_h: Sequence[float],
    *,
    cant_mm: float = 0.0,
    vehicle: Vehicle | None = None,
    c22: float | None = None,
    method: AmplitudeMethod = "harmonic balance",
    context: RunContext | None = None,
    ground_reflection: float | None = None,
    priced: bool = False,
    counter_body_effect: bool = True,
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
    c22 : float, optional
        Kalker's C22 for every contact (None: each contact's own ellipse's).
    method : {"harmonic balance", "time domain"}
        How a squealing wheel's amplitude is found (module docstring).
    ground_reflection : float, optional
        The ground's reflection factor (0 to 1) for a second pass-by level over the
        ground (``acoustics.passby.GROUND_DEPTH_M`` below the rail head); None: free
        field only.
    priced : bool
        The caller has priced and allowed the work as part of a larger whole (a line):
        neither priced nor refused here.
    counter_body_effect : bool
        Each verdict's ``ChainOptions.counter_body_effect`` (False: what the rail adds to the
        fastest growth rate left out, as a line leaves it).

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
    request = CurveRequest(radii_m, train_speeds_km_h, vehicle, cant_mm, c22, method, ground_reflection)
    return _cases(
        design,
        request,
        context or _default_context(),
        check=not priced,
        counter_body_effect=counter_body_effect,
    )


def _default_context() -> RunContext:
    from .context import RunContext

    return RunContext.of("balanced")


def _cases(
    design: Design,
    request: CurveRequest,
    ctx: RunContext,
    *,
    maps: int = 1,
    check: bool = True,
    counter_body_effect: bool = True,
) -> list[CurveCase]:
    """:func:`curve`, its plan counting ``maps`` runs of the map (refused where ``check``)."""
    from acoustics.passby import passby

    from .chain import analyse

    modes, _, curvings, tables = _planned(design, request, ctx, check, maps, check)
    options = ChainOptions(
        mode="model",
        stop_after="sound",
        remedy=False,
        amplitude=request.method,
        counter_body_effect=counter_body_effect,
        stable_rows=False,  # as the pricing's tables are solved (_planned)
    )
    moved = modes_at_contacts(modes, ctx.memo)
    cases: list[CurveCase] = []
    for (radius, speed), wheels in curvings.items():
        ctx.budget.checkpoint(f"the curve of {radius:g} m at {speed:g} km/h")
        group = []
        for w, (wheel, sites) in enumerate(wheels):
            analyses = tuple(
                analyse(
                    s.design,
                    op=s.op,
                    options=options,
                    context=ctx,
                    modes=moved(s.design.contact_frame),
                    table=tables.get(((radius, speed), w, k)),
                )
                for k, s in enumerate(sites)
            )
            states = tuple(s.state for s in sites)
            case = CurveCase(
                radius, speed, wheel, tuple(a.tail(KEPT_RECORD_S) for a in analyses), states=states
            )
            group.append(replace(case, sound=axle_sound(analyses[case.deciding])))
        sources, owners = bogie_sources(group, request.bogie(design).wheelbase_m, design.rolling_radius)
        if sources:
            free = passby(sources, speed / 3.6)
            ground = None
            if request.ground_reflection is not None:
                ground = passby(sources, speed / 3.6, reflection=request.ground_reflection)
            bp = BogiePassby(free, ground, tuple(owners), tuple(sources))
            group = [replace(c, passby=bp) for c in group]
        cases += group
    return cases


def curve_estimate(design: Design, request: CurveRequest, *, context: RunContext | None = None) -> CostPlan:
    """What :func:`curve` would take for ``request`` (``budget.CostPlan``: its parts'
    seconds and bytes), from the wheel's modes, the curving and every contact's linear
    stability, without refusing anything (``benchmarks/bench_estimates.py`` sets it beside
    the time taken)."""
    return _planned(design, request, context or _default_context(), False)[1]


Curvings = dict[tuple[float, float], list[tuple["WheelContact", list[ContactSiteAnalysis]]]]
#: Each sliding contact's linear stability by (curve, wheel, contact) indices
SolvedTables = dict[tuple[tuple[float, float], int, int], "StabilityTable"]


def _planned(
    design: Design,
    request: CurveRequest,
    ctx: RunContext,
    check: bool,
    maps: int = 1,
    price: bool = True,
) -> tuple[ModeSet, CostPlan, Curvings, SolvedTables]:
    """The request checked and priced in its three steps (``plan.curve_plan``), each
    refused beyond the budget before the next where ``check``: (the modes, the plan, each
    curve's wheels and their contact sites, and the linear stability of each sliding
    contact where the pricing solved it, by (curve, wheel, contact): the analysis's)."""
    from track.bogie_curving import BogieCurving, contact_table, solve_curving
    from track.curving import check_curve

    from .fe_stages import context_modes, modes_cache_key
    from .mode_stability import stability_table
    from .sound import radiation_cached

    if design.counter_body.KIND != "track":
        raise RequestError(
            f"{design.name} rolls on a {design.counter_body.KIND}: a curve needs a design on a track"
        )
    q, method, vehicle, cant_mm = (
        request.ground_reflection,
        request.method,
        request.bogie(design),
        request.cant_mm,
    )
    if q is not None and not 0.0 <= q <= 1.0:
        raise RequestError(f"ground reflection {q:g}: a reflection factor from 0 (absorbing) to 1 (rigid)")
    if method not in AMPLITUDE_METHODS:
        raise RequestError(f"amplitude method {method!r}: one of {', '.join(AMPLITUDE_METHODS)}")
    radii_m, train_speeds_km_h = request.radii_m, request.train_speeds_km_h
    size = CurveSize(len(radii_m), len(train_speeds_km_h), maps=maps)
    plan_of = functools.partial(
        curve_plan,
        design,
        size,
        method == "time domain",
        ctx.fidelity,
        ctx.fmax_hz,
        passbys=1 if q is None else 2,
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
    # kept for the process: a line runs the map of many (speed, cant, friction) groups
    key = modes_cache_key(design, ctx.fidelity, ctx.fmax_hz)
    memo_key = ("curve", repr(key), design.wheel.profile, design.rolling_radius)
    held = memo_get(ctx.memo, memo_key)
    if held is None:
        wheel_on_rail = contact_geometry(design)
        wheel_modes = context_modes(design, ctx)
        table = contact_table(wheel_on_rail, design.wheel.youngs_modulus, design.wheel.poissons_ratio)
        held = memo_put(ctx.memo, memo_key, wheel_modes.shapes, (wheel_on_rail, table, wheel_modes))
    geometry, table, modes = held
    contact = contact_law(design)
    wheel_dofs = mode_dofs(excitable(modes, contact), design)
    checked(plan_of(wheel_dofs=wheel_dofs))
    curvings: Curvings = {}
    with ctx.progress.stage(f"steady curving of {size.curves:,} curves"):
        # each speed's curves from the widest to the tightest, each solve starting from the
        # last one's equilibrium: the same equilibrium in a few steps
        last: dict[float, BogieCurving] = {}
        for r in sorted(radii_m, reverse=True):
            for v in train_speeds_km_h:
                solved = solve_curving(
                    geometry,
                    vehicle,
                    float(r),
                    float(v),
                    wheel_load_n=design.contact.normal_load,
                    friction_coefficient=design.contact.friction_coefficient,
                    flange_friction_coefficient=design.contact.flange_friction_coefficient,
                    cant_mm=cant_mm,
                    table=table,
                    start=last.get(float(v)),
                )
                last[float(v)] = solved
                curvings[(float(r), float(v))] = [
                    (w, wheel_sites(design, w, float(v), request.c22)) for w in solved.wheels
                ]
    if not (check or price):  # priced by the caller as a whole (a line): no pre-pass
        return modes, plan_of(wheel_dofs=wheel_dofs), curvings, {}
    moved = modes_at_contacts(modes, ctx.memo)
    sliding = [
        ((curve, w, k), s)
        for curve, wheels in curvings.items()
        for w, (_, mine) in enumerate(wheels)
        for k, s in enumerate(mine)
        if s.op.crabbing_velocity_m_s != 0.0
    ]
    with ctx.progress.stage(f"linear stability at {len(sliding):,} sliding contacts"):
        # the analysis's own tables (what the chain would solve for CURVE_OPTIONS), solved
        # once here to price the rest and handed to the analysis
        tables = {
            at: stability_table(s.design, moved(s.design.contact_frame), s.law, s.op, stable_rows=False)
            for at, s in sliding
        }
        sites = [(s.design, moved(s.design.contact_frame), s.law, s.op, tables[at]) for at, s in sliding]
        squealing = squealing_axles(
            sites, method == "time domain", lambda m, f: radiation_cached(ctx.cache, key, m, f)
        )
    return modes, checked(plan_of(wheel_dofs=wheel_dofs, squealing=squealing)), curvings, tables
