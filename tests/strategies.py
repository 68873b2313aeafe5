"""Hypothesis strategies shared by the property tests."""

from __future__ import annotations

import math

from hypothesis import strategies as st

from geometry import WheelDesign


def unit(lo: float = 0.0, hi: float = 1.0):
    """Finite floats in [lo, hi]."""
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


@st.composite
def wheel_designs(
    draw, *, web=(0.3, 1.0), min_rim=0.001, bore=(0.05, 0.85), nu=(-0.9, 0.49), symmetric_often: bool = False
) -> WheelDesign:
    """Realistic wheels, built so that every constraint holds: rolling radius 0.1-0.4 m,
    rim 10-50 mm wide, web a fraction ``web`` of the rim, any web offset that keeps the
    web inside the rim (a symmetric wheel one time in three if ``symmetric_often``),
    crown 2-100 x rim_width/2, rim depth from ``min_rim`` [m] above the crown's sagitta
    to a quarter of the radius, bore a fraction ``bore`` of the rim inner radius,
    Poisson's ratio in ``nu``."""
    R1 = draw(unit(0.10, 0.40))
    w = draw(unit(0.010, 0.050))
    t = w * draw(unit(*web))
    offset = draw(st.sampled_from([0.0, None, None])) if symmetric_often else None
    if offset is None:
        offset = draw(unit(-1.0, 1.0)) * (w - t) / 2
    crown = w / 2 * draw(unit(2.0, 100.0))
    sag = crown - math.sqrt(crown**2 - (w / 2) ** 2)
    depth = sag + draw(unit(min_rim, 0.25 * R1))
    rb = (R1 - depth) * draw(unit(*bore))
    poisson = draw(unit(*nu))
    return WheelDesign(
        name="h",
        rolling_radius=R1,
        rim_width=w,
        web_thickness=t,
        web_offset=offset,
        crown_radius=crown,
        rim_depth=depth,
        bore_radius=rb,
        poissons_ratio=poisson,
    )
