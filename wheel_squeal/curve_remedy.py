"""What stops squeal over a whole curve map: each treatment a railway can apply, within the
range it has in service, applied to the design and checked by running the same map again.

Treatments (:data:`TREATMENTS`):

- a top-of-rail **friction modifier**: a flat creep curve beyond saturation (the
  ``constant`` friction law: no falling branch), the friction coefficient kept;
- a **lower friction** coefficient, 0.2, what a top-of-rail product holds the rail at;
- **flange lubrication**: the gauge face's friction coefficient at 0.1 (a lubricated
  flange: 0.1 and below, Lewis & Olofsson (eds.), Wheel-rail interface handbook, 2009,
  the chapters on friction management), the rail head's kept;
- a **friction modifier and flange lubrication** together (the practice on curves where the
  outer wheel's flange squeals beside the inner wheel's tread);
- **wheel dampers** on the families of the squealing modes, at the damping ratio tuned
  absorbers and constrained layers give a railway wheel (0.005; Thompson 2009, ch. 14);
  where that is not enough, the ratio the squeal would need, to first order
  (zeta + sigma / omega of the still-squealing cases);
- a **steering bogie**: a primary yaw stiffness ten times lower (1e6 N m/rad per wheelset),
  so that the axles run nearer radial (its running stability on straight track, the speed
  at which it hunts, is the vehicle's to check: it is not modelled here);
- a **lower speed**: every train speed of the map at three quarters (no design change).

The recommended one leaves the fewest cases squealing (a case is one wheel at one radius
and speed), then the quietest loudest pass-by; a treatment that leaves cases squealing
never says that nothing grows.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from .design import Design

if TYPE_CHECKING:
    from .curve_case import CurveCase

__all__ = ["DAMPER_DAMPING_RATIO", "TREATMENTS", "CurveRemedy", "Treatment", "TreatmentResult", "map_remedy"]

#: The modal damping ratio wheel dampers give a railway wheel's modes (tuned absorbers and
#: constrained layers: loss factors of 0.005 to 0.02, Thompson 2009 ch. 14)
DAMPER_DAMPING_RATIO = 0.005
#: What a top-of-rail friction product holds the friction coefficient at
MODIFIED_FRICTION = 0.2
#: A lubricated gauge face's friction coefficient
LUBRICATED_FLANGE_FRICTION = 0.1
#: A steering bogie's primary yaw stiffness [N m/rad per wheelset]
STEERING_YAW_STIFFNESS = 1.0e6
#: The lower speed's share of each train speed
LOWER_SPEED_SHARE = 0.75


@dataclass(frozen=True)
class Treatment:
    """One treatment: its name, what it is in words, the design it makes of a design and
    the map's cases (the treatment's changes as [section] key = value lines for
    remedy.toml; empty where the design is unchanged), and the speeds it runs the map at."""

    name: str
    what: str
    apply: Callable[[Design, Sequence[CurveCase]], tuple[Design, dict[str, dict[str, Any]]]]
    speeds: Callable[[Sequence[float]], list[float]] = field(default=lambda v: [float(x) for x in v])


def _modifier(design: Design, cases: Sequence[CurveCase]) -> tuple[Design, dict[str, dict[str, Any]]]:
    return design.replace(friction_law="constant"), {"contact": {"friction_law": "constant"}}


def _lower_friction(design: Design, cases: Sequence[CurveCase]) -> tuple[Design, dict[str, dict[str, Any]]]:
    mu = min(MODIFIED_FRICTION, design.contact.friction_coefficient)
    return design.replace(friction_coefficient=mu), {"contact": {"friction_coefficient": mu}}


def _flange_lubrication(
    design: Design, cases: Sequence[CurveCase]
) -> tuple[Design, dict[str, dict[str, Any]]]:
    mu = min(LUBRICATED_FLANGE_FRICTION, design.contact.friction_coefficient)
    return design.replace(flange_friction_coefficient=mu), {"contact": {"flange_friction_coefficient": mu}}


def _modifier_and_lubrication(
    design: Design, cases: Sequence[CurveCase]
) -> tuple[Design, dict[str, dict[str, Any]]]:
    modified, top = _modifier(design, cases)
    lubricated, flange = _flange_lubrication(modified, cases)
    return lubricated, {"contact": top["contact"] | flange["contact"]}


def _dampers(design: Design, cases: Sequence[CurveCase]) -> tuple[Design, dict[str, dict[str, Any]]]:
    from .model_sections import family_keys

    keys = sorted({family_keys(*_mode_of(c))[0] for c in cases if c.analysis.verdict.squeals})
    table = dict(design.damping.by_mode) | {k: DAMPER_DAMPING_RATIO for k in keys}
    damped = design.replace(mode_damping=tuple(sorted(table.items())))
    return damped, {"squeal.damping": {k: DAMPER_DAMPING_RATIO for k in keys}}


def _mode_of(case: CurveCase) -> tuple[int, str]:
    o = case.analysis.verdict.outcome
    assert o is not None  # a squealing verdict has its outcome
    return o.mode.nodal_diameters, o.mode.family


def _steering(design: Design, cases: Sequence[CurveCase]) -> tuple[Design, dict[str, dict[str, Any]]]:
    k = min(STEERING_YAW_STIFFNESS, design.vehicle.primary_yaw_stiffness)
    return design.replace(primary_yaw_stiffness=k), {"vehicle": {"primary_yaw_stiffness": k}}


def _unchanged(design: Design, cases: Sequence[CurveCase]) -> tuple[Design, dict[str, dict[str, Any]]]:
    return design, {}


#: The treatments the curve's remedy considers (module docstring), cheapest to apply first
TREATMENTS: tuple[Treatment, ...] = (
    Treatment(
        "friction modifier",
        "a top-of-rail friction modifier: the creep curve flat beyond saturation (no falling branch), "
        "the friction coefficient kept",
        _modifier,
    ),
    Treatment(
        "lower friction",
        f"the rail head's friction held at {MODIFIED_FRICTION:g} by a top-of-rail product (the creep curve's "
        "shape kept)",
        _lower_friction,
    ),
    Treatment(
        "flange lubrication",
        f"the gauge face lubricated: the flange's friction coefficient {LUBRICATED_FLANGE_FRICTION:g}, "
        "the rail head's kept",
        _flange_lubrication,
    ),
    Treatment(
        "friction modifier and flange lubrication",
        "a top-of-rail friction modifier (the creep curve flat beyond saturation) and the gauge face "
        f"lubricated (the flange's friction coefficient {LUBRICATED_FLANGE_FRICTION:g})",
        _modifier_and_lubrication,
    ),
    Treatment(
        "wheel dampers",
        f"dampers on the wheel: damping ratio {DAMPER_DAMPING_RATIO:g} on the families of the squealing "
        "modes (what tuned absorbers and constrained layers give)",
        _dampers,
    ),
    Treatment(
        "steering bogie",
        f"a primary yaw stiffness of {STEERING_YAW_STIFFNESS:.0e} N m/rad per wheelset (the axles run nearer "
        "radial; a softer yaw stiffness lowers the speed at which the bogie hunts, which is not checked "
        "here)",
        _steering,
    ),
    Treatment(
        "lower speed",
        f"every train speed at {LOWER_SPEED_SHARE:.0%} of the map's (no change to the wheel or the track)",
        _unchanged,
        lambda v: [round(LOWER_SPEED_SHARE * float(x), 1) for x in v],
    ),
)


@dataclass(frozen=True)
class TreatmentResult:
    """A treatment checked over the map: the design with it, the changes to paste, and the
    map run again with it."""

    treatment: Treatment
    design: Design
    changes: dict[str, dict[str, Any]]
    cases: tuple[CurveCase, ...]
    cases_squealing_before: int
    loudest_before_dba: float | None

    @property
    def cases_still_squealing(self) -> int:
        return sum(c.analysis.verdict.squeals for c in self.cases)

    @property
    def loudest_after_dba(self) -> float | None:
        levels = [c.passby.free.lpamax_dba for c in self.cases if c.passby is not None]
        return max(levels) if levels else None

    @property
    def lpamax_reduction_db(self) -> float | None:
        """How much quieter the loudest pass-by is [dB]; where nothing squeals any more, all
        of the loudest level; None where it is not known (nothing was heard before, or what
        still squeals has no level: a squeal by mode coupling, whose amplitude the harmonic
        balance leaves to the time domain)."""
        after = self.loudest_after_dba
        if self.loudest_before_dba is None or (after is None and self.cases_still_squealing):
            return None
        return self.loudest_before_dba - (after if after is not None else 0.0)

    def still(self) -> str:
        """What still squeals, in words (empty: nothing)."""
        left = [c for c in self.cases if c.analysis.verdict.squeals]
        if not left:
            return ""
        kinds = sorted(
            {
                f"{c.analysis.verdict.get('mechanism')} at the {c.to_record()['deciding_contact']}"
                for c in left
            }
        )
        unheard = sum(c.passby is None for c in left)
        level = f"; {unheard} without a level, which the time domain gives" if unheard else ""
        return f"{len(left)} ({', '.join(kinds)}{level})"

    def damping_needed(self) -> float | None:
        """With dampers that leave cases squealing: the damping ratio they would need, to
        first order (the applied ratio plus the largest growth rate over the squeal's
        circular frequency); None otherwise."""
        if self.treatment.name != "wheel dampers" or not self.cases_still_squealing:
            return None
        rates = [
            c.analysis.verdict.get("growth_rate_1_s") / (2 * math.pi * c.analysis.verdict.get("tone_hz"))
            for c in self.cases
            if c.analysis.verdict.squeals and c.analysis.verdict.get("tone_hz")
        ]
        return DAMPER_DAMPING_RATIO + max(rates, default=0.0)

    def to_dict(self, design_file: str | None) -> dict[str, Any]:
        needed = self.damping_needed()
        what = self.treatment.what
        if needed is not None:
            what += f"; not enough here: the squeal would need a damping ratio of about {needed:.2g}"
        return {
            "name": self.treatment.name,
            "what": what,
            "design_file": design_file,
            "cases_squealing_before": self.cases_squealing_before,
            "cases_still_squealing": self.cases_still_squealing,
            "still_squealing": self.still(),
            "loudest_lpamax_before_dba": self.loudest_before_dba,
            "loudest_lpamax_after_dba": self.loudest_after_dba,
            "lpamax_reduction_db": self.lpamax_reduction_db,
        }


@dataclass(frozen=True)
class CurveRemedy:
    """Every treatment checked over the map, and the recommended one (None: nothing
    squeals, nothing to stop)."""

    treatments: tuple[TreatmentResult, ...]

    @property
    def recommended(self) -> TreatmentResult | None:
        if not self.treatments or not self.treatments[0].cases_squealing_before:
            return None
        return min(
            self.treatments,
            key=lambda t: (t.cases_still_squealing, t.loudest_after_dba or -math.inf),
        )

    def words(self) -> str:
        """One line that leads the printed text and the report."""
        best = self.recommended
        if best is None:
            return "remedy: nothing squeals on this map"
        stops = (
            "stops the squeal in every case"
            if not best.cases_still_squealing
            else f"leaves {best.still()} of the {best.cases_squealing_before} squealing cases squealing: the "
            f"best of {len(self.treatments)} treatments"
        )
        return f"remedy: {best.treatment.name} ({best.treatment.what}) {stops}"


def map_remedy(
    design: Design,
    cases: Sequence[CurveCase],
    run: Callable[[Design, list[float]], list[CurveCase]],
    radii_speeds: tuple[Sequence[float], Sequence[float]],
) -> CurveRemedy:
    """Each treatment applied to ``design`` and checked by ``run(design, speeds)`` (the same
    map again), beside the map's own ``cases``."""
    before = sum(c.analysis.verdict.squeals for c in cases)
    heard = [c.passby.free.lpamax_dba for c in cases if c.passby is not None]
    loudest = max(heard) if heard else None
    if not before:
        return CurveRemedy(())
    results = []
    for t in TREATMENTS:
        treated, changes = t.apply(design, cases)
        again = run(treated, t.speeds(radii_speeds[1]))
        results.append(TreatmentResult(t, treated, changes, tuple(again), before, loudest))
    return CurveRemedy(tuple(results))
