"""Wheel and rail profiles, the contact geometry of a wheelset on its rails, and the steady
curving of a bogie: against the standards' definitions, closed forms for cones, published
properties and the equilibrium's own limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from contact.hertz import kalker_c22, kalker_coefficients
from contact.profiles import _S1002_BOUNDS_MM, _s1002_rise_mm, cone_wheel, profile_from_points, s1002, uic60
from contact.wheel_rail import ContactGeometry
from track.bogie_curving import Vehicle, steady_curving

WHEEL_LOAD_N = 50e3


def test_s1002_is_the_standards_profile():
    """EN 13715: a 28 mm flange whose flank is a 70 deg straight line, the sections joined
    without a step (0.2 um: the standard's coefficients are given to 10 digits)."""
    p = s1002()
    assert 1e3 * p.height_m.max() == pytest.approx(28.0, abs=1e-3)
    on_flank = (p.lateral_m > -0.0395) & (p.lateral_m < -0.0386)
    assert np.degrees(np.arctan(-p.slope()[on_flank])) == pytest.approx(70.0, abs=0.01)
    for b in _S1002_BOUNDS_MM[1:-1]:
        left, right = _s1002_rise_mm(np.array([b - 1e-7, b + 1e-7]))
        assert abs(left - right) < 2e-4, b


def test_uic60_head_is_72_mm_wide_at_its_gauge_point():
    """EN 13674-1: the 300, 80 and 13 mm arcs tangent to one another and to the 1:20 flank
    put the gauge point (14 mm below the crown) 36 mm from the centre line: a 72 mm head."""
    p = uic60()
    right = p.lateral_m >= 0
    v = np.interp(-0.014, p.height_m[right][::-1], p.lateral_m[right][::-1])
    assert 1e3 * v == pytest.approx(36.0, abs=0.05)
    assert np.all(np.diff(p.height_m[right]) <= 0)  # falls monotonically from the crown


def _knife_rail():
    """A rail head of 5 mm crown radius: its contact hardly moves as the wheelset rolls, the
    closed forms' idealisation of a cone on a rail."""
    v = np.linspace(-0.0049, 0.0049, 401)
    return profile_from_points("knife", v, np.sqrt(0.005**2 - v * v) - 0.005)


@pytest.mark.parametrize("half_angle", [0.025, 0.05, 0.1])
def test_a_cone_meets_the_closed_forms(half_angle):
    """A cone on a knife-edge rail: gamma = lambda (+- the wheelset's roll phi), and
    r = r0 -+ tan(lambda) (y + r0 phi): rolling about its axle, the wheelset moves its
    lowest points r0 phi sideways, phi = dr / 2e for contacts e from the centre, hence
    dr = 2 tan(lambda) y / (1 - tan(lambda) r0 / e) and the equivalent conicity the same
    factor over tan(lambda) (0.2 %: the knife's 5 mm crown rolls the contact too)."""
    g = ContactGeometry(wheel=cone_wheel(half_angle), rail=_knife_rail(), inclination=0.0)
    y = 0.003
    p = g.position(y)
    e = p.outer[0].lateral_position_m
    lam = math.tan(half_angle)
    rolling = lam / (1.0 - lam * g.rolling_radius_m / e)
    assert p.roll_rad == pytest.approx(p.rolling_radius_difference_m / (2 * e), rel=0.002)
    assert p.rolling_radius_difference_m / (2 * y) == pytest.approx(rolling, rel=0.002)
    assert p.outer[0].contact_angle_rad - p.roll_rad == pytest.approx(half_angle, abs=1e-4)
    assert g.equivalent_conicity(y) == pytest.approx(rolling, rel=0.002)


@pytest.mark.slow
def test_s1002_on_uic60_has_the_published_conicity_and_flange_angle():
    """S1002 on UIC60 1:40 at 1435 mm gauge and 1360 mm between the flange backs: an
    equivalent conicity of 0.1-0.3 at 2-4 mm amplitude (EN 15302 reference combinations;
    about 0.15-0.2 at 3 mm in the literature), falling with amplitude; the flange touches
    at 5-8 mm of shift, on its 70 deg flank."""
    g = ContactGeometry()
    conicity = [g.equivalent_conicity(a) for a in (0.002, 0.003, 0.004)]
    assert all(0.1 < c < 0.3 for c in conicity) and conicity == sorted(conicity, reverse=True)
    clearance = g.flange_clearance_m()
    assert 0.005 < clearance < 0.008
    flank = max(
        c.contact_angle_rad for y in np.linspace(clearance, clearance + 5e-4, 6) for c in g.position(y).outer
    )
    assert math.degrees(flank) == pytest.approx(70.0, abs=0.5)


def test_kalker_coefficients_meet_kalkers_identities():
    """At nu = 0 the longitudinal and lateral coefficients are equal (Kalker); the table's
    circle at nu = 0.25 is 4.12, 3.67, 1.47; C22 is the one the squeal model uses."""
    for g in (0.2, 0.5, 1.0, 2.0, 5.0):
        k = kalker_coefficients(g, 0.0)
        assert k.c11 == pytest.approx(k.c22, rel=1e-12)
        assert kalker_coefficients(g, 0.3).c22 == pytest.approx(kalker_c22(g, 0.3), rel=1e-12)
    assert kalker_coefficients(1.0, 0.25) == kalker_coefficients(1.0, 0.25).__class__(4.12, 3.67, 1.47)


@pytest.fixture(scope="module")
def geometry():
    return ContactGeometry()


def _curving(geometry, radius_m, speed_km_h, vehicle, cant_mm=0.0):
    return steady_curving(
        geometry,
        vehicle,
        radius_m,
        speed_km_h,
        wheel_load_n=WHEEL_LOAD_N,
        friction_coefficient=0.3,
        cant_mm=cant_mm,
    )


def _unbalanced_force_n(radius_m, speed_km_h, cant_mm=0.0):
    v = speed_km_h / 3.6
    return 4 * WHEEL_LOAD_N / 9.81 * (v * v / radius_m - 9.81 * cant_mm * 1e-3 / 1.5)


def test_a_free_wheelset_on_a_wide_curve_runs_radially_and_rolls_purely(geometry):
    """Zero yaw stiffness on 3000 m: every wheelset finds the shift whose rolling radius
    difference matches the curvature; angle of attack and longitudinal creepage under 2e-4
    (a wheel on two points of its tread, where S1002's contact jumps near the centre, rolls
    purely on their load-weighted mean: each point's own radius creeps a little)."""
    wheels = _curving(geometry, 3000.0, 40.0, Vehicle(primary_yaw_stiffness_n_m_rad=0.0))
    for w in wheels:
        creepage = sum(c.load_share * c.longitudinal_creepage for c in w.contacts)
        assert abs(w.angle_of_attack_rad) < 2e-4 and abs(creepage) < 2e-4, w
        assert not w.flange_contact
    lead = wheels[0]
    assert lead.lateral_shift_m > 0  # outward, toward the larger radius on the outer wheel


def test_a_stiff_bogie_flanges_at_the_geometric_angle_of_attack(geometry):
    """A yaw stiffness of 1e10 N m/rad at 150 m: the leading outer wheel on its flange (over
    45 deg) at an angle of attack within 30 % of 2a/R; the outer wheels loaded more (cant
    deficiency); the four lateral forces sum to the unbalanced force (5 %; the equilibrium
    holds it to the solver's tolerance)."""
    vehicle = Vehicle(primary_yaw_stiffness_n_m_rad=1e10)
    wheels = _curving(geometry, 150.0, 40.0, vehicle)
    lead_inner, lead_outer, trail_inner, trail_outer = wheels
    assert lead_outer.flange_contact and math.degrees(lead_outer.contact_angle_rad) > 45
    assert not lead_inner.flange_contact
    assert lead_outer.angle_of_attack_rad == pytest.approx(vehicle.wheelbase_m / 150.0, rel=0.3)
    assert (
        lead_outer.wheel_load_n > lead_inner.wheel_load_n
        and trail_outer.wheel_load_n > trail_inner.wheel_load_n
    )
    total = sum(w.lateral_force_n for w in wheels)
    assert total == pytest.approx(_unbalanced_force_n(150.0, 40.0), rel=0.05)


def test_cant_moves_the_load_and_the_lateral_force(geometry):
    """At the balancing speed of a cant the wheels carry their static load and the lateral
    forces sum to nothing; above it the outer wheels carry more."""
    cant_mm = 1.5 * (40 / 3.6) ** 2 / 600.0 / 9.81 * 1e3
    balanced = _curving(geometry, 600.0, 40.0, Vehicle(), cant_mm)
    assert all(w.wheel_load_n == pytest.approx(WHEEL_LOAD_N, rel=1e-9) for w in balanced)
    assert sum(w.lateral_force_n for w in balanced) == pytest.approx(0.0, abs=1.0)
    fast = _curving(geometry, 600.0, 80.0, Vehicle(), cant_mm)
    assert fast[1].wheel_load_n > WHEEL_LOAD_N > fast[0].wheel_load_n
    assert sum(w.lateral_force_n for w in fast) == pytest.approx(
        _unbalanced_force_n(600.0, 80.0, cant_mm), rel=0.05
    )
