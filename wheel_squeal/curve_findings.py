"""What a curve map says beside the field's anchors: where squeal stops at each train
speed, against Rudd's rule of thumb, the lateral creepage above which field measurements
find squeal, and CNOSSOS-EU's squeal classes."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .curve_case import CurveCase

__all__ = ["FIELD_CREEPAGE_THRESHOLD", "RUDD_WHEELBASES", "findings"]

#: Rudd's rule of thumb: squeal in curves tighter than about this many wheelbases
RUDD_WHEELBASES = 100.0
#: The lateral creepage above which field measurements find squeal (about 0.0045)
FIELD_CREEPAGE_THRESHOLD = 0.0045


def _squeals_by(c: CurveCase, coupling: bool) -> bool:
    v = c.analysis.verdict
    return v.squeals and (v.get("mechanism") == "mode coupling") == coupling


def _at_flange(c: CurveCase) -> bool:
    """Whether the case's verdict is its flange contact's."""
    return c.contacts[c.deciding].on_flange


def findings(cases: Sequence[CurveCase], wheelbase_m: float) -> list[str]:
    """Where squeal stops, per train speed, beside the field's anchors: the largest radius
    at which a wheel squeals by falling friction at its tread and its lateral creepage,
    against Rudd's 100 wheelbases, the field's creepage threshold and CNOSSOS-EU's
    classes; where a flange contact squeals (the field's anchors are for the tread); and
    any squeal by mode coupling, which a falling branch does not explain."""
    out = []
    rudd = RUDD_WHEELBASES * wheelbase_m
    from acoustics.emission import CNOSSOS_CURVE_CLASSES

    lower = [0.0, *(r for r, _ in CNOSSOS_CURVE_CLASSES[:-1])]
    cnossos = ", ".join(
        f"+{db:g} dB {'below' if lo == 0.0 else 'to'} {r:g} m"
        for lo, (r, db) in zip(lower, CNOSSOS_CURVE_CLASSES)
    )
    # a bogie's leading axle held against the outer rail reaches it at R = 2a / threshold
    at_threshold = wheelbase_m / FIELD_CREEPAGE_THRESHOLD
    anchors = (
        f"the field's creepage threshold {FIELD_CREEPAGE_THRESHOLD} is reached at R = {at_threshold:.0f} m "
        f"for this wheelbase; Rudd's rule: below about {rudd:.0f} m; CNOSSOS-EU: {cnossos}"
    )
    for speed in dict.fromkeys(c.train_speed_km_h for c in cases):
        mine = [c for c in cases if c.train_speed_km_h == speed]
        friction = [c for c in mine if _squeals_by(c, coupling=False) and not _at_flange(c)]
        flange = sorted({c.radius_m for c in mine if _squeals_by(c, coupling=False) and _at_flange(c)})
        coupling = sorted({c.radius_m for c in mine if _squeals_by(c, coupling=True)})
        if friction:
            top = max(friction, key=lambda c: c.radius_m)
            wider = [c.radius_m for c in mine if c.radius_m > top.radius_m]
            stops = f"and not from {min(wider):g} m" if wider else "up to the widest curve asked"
            out.append(
                f"{speed:g} km/h: falling-friction squeal at a tread up to R = {top.radius_m:g} m {stops} "
                f"(lateral creepage there {abs(top.to_record()['lateral_creepage']):.4f}; {anchors})"
            )
        else:
            out.append(
                f"{speed:g} km/h: no falling-friction squeal at a tread at any radius asked ({anchors})"
            )
        if flange:
            radii = ", ".join(f"{r:g}" for r in flange)
            out.append(
                f"{speed:g} km/h: the flanging wheel squeals at its flange contact at R = {radii} m (its "
                "lateral creepage psi / cos(gamma) is 2-3 times the tread's; a lubricated flange has less "
                "friction than the design's)"
            )
        if coupling:
            radii = ", ".join(f"{r:g}" for r in coupling)
            out.append(
                f"{speed:g} km/h: mode coupling makes a wheel squeal at R = {radii} m, whatever the creepage"
            )
    return out
