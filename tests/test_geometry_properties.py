"""Property-based tests (hypothesis): every valid design meshes in 2-D and 3-D with the
right volume; every invalid one raises DesignError naming a parameter, before gmsh."""

from __future__ import annotations

import math
from dataclasses import fields

import numpy as np
import pytest
from hypothesis import HealthCheck, event, example, given, settings, strategies as st
from strategies import unit, wheel_designs

from geometry import (
    SECTIONS,
    DesignError,
    WheelDesign,
    mesh_profile,
    mesh_wheel,
    profile_area,
    revolved_volume,
)

SETTINGS = dict(
    max_examples=15,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)

NUMERIC = [f.name for f in fields(WheelDesign) if f.type in (float, "float")]


def valid_designs():
    """The realistic box of tests/strategies.py (the extreme corners, a semicircular crown
    or a rim a few micrometres thick, are in test_geometry.DEGENERATE)."""
    return wheel_designs()


@settings(**SETTINGS)
@given(d=valid_designs(), order=st.sampled_from([1, 2]))
def test_valid_designs_mesh_in_2d(d, order):
    m = mesh_profile(d, size=d.rolling_radius / 12, order=order)
    rel = 1e-3 if order == 2 else 2e-2
    assert m.area() == pytest.approx(profile_area(d), rel=rel)
    assert m.points[m.contact_node].tolist() == [d.rolling_radius, 0.0]
    assert np.allclose(m.points[m.bore_nodes, 0], d.bore_radius, rtol=0, atol=1e-12)
    assert len(m.tread_nodes) >= 3


@pytest.mark.slow
@settings(**SETTINGS)
@given(d=valid_designs())
def test_valid_designs_mesh_in_3d(d):
    m = mesh_wheel(d, size=d.rolling_radius / 7, order=2)
    assert m.volume() == pytest.approx(revolved_volume(d), rel=5e-3)
    assert m.points[m.contact_node].tolist() == [d.rolling_radius, 0.0, 0.0]
    r = np.hypot(m.points[m.bore_nodes, 0], m.points[m.bore_nodes, 1])
    assert np.allclose(r, d.bore_radius, rtol=0, atol=1e-12)


# A wider box: lengths on a 1 mm grid from -0.1 to 0.5 m, other values from -2 to 2 x
# their default, plus zero, infinities and NaN. Most draws are invalid; the valid ones
# must mesh.
SPECIAL = st.sampled_from([0.0, -0.0, math.inf, -math.inf, math.nan])
LENGTHS = set(SECTIONS["wheel"])


def wide_value(name: str):
    default = getattr(WheelDesign(), name)
    if name in LENGTHS:
        grid = st.integers(-100, 500).map(lambda i: i * 1e-3)
    elif name == "poissons_ratio":
        grid = unit(-2.0, 2.0)
    else:
        grid = unit(-2.0, 2.0).map(lambda x: x * default)
    return st.one_of(grid, SPECIAL, st.just(default))


#: valid designs at the edge of the box: a web flush with a rim face, a flat plate
VALID_EXAMPLES = ({"web_offset": 0.0055}, {"rim_width": 0.015, "web_thickness": 0.015})


@st.composite
def wide_parameters(draw) -> dict:
    changed = draw(st.sets(st.sampled_from(NUMERIC), min_size=1, max_size=5))
    return {k: draw(wide_value(k)) for k in sorted(changed)}


@settings(**{**SETTINGS, "max_examples": 60})
@given(params=wide_parameters())
@example(params=VALID_EXAMPLES[0])
@example(params=VALID_EXAMPLES[1])
@example(params={"rim_depth": 0.213})  # invalid
def test_wide_box_raises_design_error_or_meshes(params):
    try:
        d = WheelDesign(**params)
    except DesignError as exc:
        event("invalid")
        assert params not in VALID_EXAMPLES, exc  # the valid branch runs at least for these
        assert any(name in str(exc) for name in NUMERIC), exc
        return
    event("valid")
    m = mesh_profile(d, size=max(d.rolling_radius / 12, d.web_thickness / 4), order=2)
    assert m.area() == pytest.approx(profile_area(d), rel=1e-3)


@settings(**SETTINGS)
@given(
    d=valid_designs(),
    broken=st.sampled_from(
        [
            ("rolling_radius", lambda d: -d.rolling_radius),
            ("rim_width", lambda d: 0.0),
            ("web_thickness", lambda d: d.rim_width * 1.01),
            ("bore_radius", lambda d: d.rim_inner_radius),
            ("web_offset", lambda d: (d.rim_width - d.web_thickness) / 2 + 1e-4),
            ("crown_radius", lambda d: d.rim_width / 2 * 0.99),
            ("poissons_ratio", lambda d: 0.5),
            ("density", lambda d: math.nan),
            ("rim_depth", lambda d: math.inf),
        ]
    ),
)
def test_breaking_one_rule_names_it(d, broken):
    name, value = broken
    with pytest.raises(DesignError, match=name):
        d.replace(**{name: value(d)})
