"""The outline of a parametric wheel: web (straight, tapered, conical), optional hub,
rim with a crowned tread, optional fillets where the web meets rim and hub.

Kept apart from :mod:`geometry.wheel_design` (which calls it to validate a design) and
:mod:`geometry.profile` (which serves it) so that neither imports the other's caller.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any

from .outline import Outline, OutlineError, fillet

__all__ = ["parametric_outline"]


@lru_cache(maxsize=256)
def parametric_outline(d: Any) -> Outline:
    """The outline the [wheel] parameters of ``d`` (a :class:`geometry.wheel_design.WheelDesign`,
    which imports this module) make:
    clockwise in (r, z) from the bore, the bore segment first. Raises OutlineError when
    the parameters make an impossible shape (a fillet that does not fit)."""
    rb, ri = d.bore_radius, d.rim_inner_radius
    hw = d.rim_width / 2
    re = (
        d.rolling_radius - d.crown_radius + math.sqrt(d.crown_radius * d.crown_radius - hw * hw)
    )  # tread at the faces
    r0 = d.hub_radius if d.hub_radius > 0 else rb  # where the web starts
    t0, o0 = d.web_thickness, d.web_offset
    t1 = t0 if d.web_thickness_rim is None else d.web_thickness_rim
    o1 = o0 if d.web_offset_rim is None else d.web_offset_rim

    def web(r: float, side: int) -> float:  # z of the web's face (side +1 / -1) at r
        s = (r - r0) / (ri - r0)
        return o0 + s * (o1 - o0) + side * (t0 + s * (t1 - t0)) / 2

    # Clockwise in the (r, z) plane: up the bore (+z), out along the upper faces, over
    # the tread (from +z to -z) and back along the lower faces.
    upper = [(ri, web(ri, 1)), (ri, hw), (re, hw)]
    lower = [(re, -hw), (ri, -hw), (ri, web(ri, -1))]
    if d.hub_radius > 0:
        hz = d.hub_width / 2
        upper = [(rb, o0 + hz), (d.hub_radius, o0 + hz), (d.hub_radius, web(r0, 1))] + upper
        lower = lower + [(d.hub_radius, web(r0, -1)), (d.hub_radius, o0 - hz), (rb, o0 - hz)]
        fillets = {(ri, web(ri, 1)): "fillet_rim", (ri, web(ri, -1)): "fillet_rim"}
        fillets |= {(d.hub_radius, web(r0, 1)): "fillet_hub", (d.hub_radius, web(r0, -1)): "fillet_hub"}
    else:
        upper = [(rb, web(rb, 1))] + upper
        lower = lower + [(rb, web(rb, -1))]
        fillets = {(ri, web(ri, 1)): "fillet_rim", (ri, web(ri, -1)): "fillet_rim"}
    pts = [lower[-1]] + upper + lower[:-1]
    bulges = [0.0] * len(pts)
    bulges[pts.index((re, hw))] = math.tan(-2 * math.asin(hw / d.crown_radius) / 4)
    # A web flush with a rim or hub face makes a zero-length segment: drop the vertex.
    keep = [
        i for i in range(len(pts)) if math.dist(pts[i], pts[(i + 1) % len(pts)]) >= 1e-12 * d.rolling_radius
    ]
    pts, bulges = [pts[i] for i in keep], [bulges[i] for i in keep]
    # Round the web's corners, last first so that the earlier indices stay valid.
    rounded = (i for i, p in enumerate(pts) if p in fillets and getattr(d, fillets[p]) > 0)
    for v in sorted(rounded, reverse=True):
        if _is_corner(pts, v):
            name = fillets[pts[v]]
            try:
                pts, bulges = fillet(pts, bulges, v, getattr(d, name))
            except OutlineError as exc:
                raise OutlineError(f"{name}: {exc}") from None
    return Outline(tuple(pts), tuple(bulges), (0,), (d.rolling_radius, 0.0), min_segment_rel=0.0)


def _is_corner(pts: list[tuple[float, float]], v: int) -> bool:
    """True when the loop turns at vertex v (a web flush with a face does not)."""
    (ax, az), (bx, bz), (cx, cz) = pts[v - 1], pts[v], pts[(v + 1) % len(pts)]
    return abs((bx - ax) * (cz - bz) - (bz - az) * (cx - bx)) > 1e-15 * max(abs(bx), 1.0) ** 2
