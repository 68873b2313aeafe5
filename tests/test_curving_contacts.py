"""Each wheel at its own contact: the design's running surface as the curving's wheel
profile, the contact frame anywhere on it, the modes read there without a new solve, and
the chain given exactly the contact the curving found."""

from __future__ import annotations

import math

import numpy as np
import pytest

import wheel_squeal as ws
from contact.frames import frame_on_running_surface
from track.bogie_curving import Vehicle, steady_curving

RAILWAY = ws.load_design("railway_920_track")  # S1002 in a curve ([contact] wheel_profile)
CONE = RAILWAY.replace(wheel_profile="outline")  # its outline's own running surface, a 1:20 cone
OUTLINE = RAILWAY.wheel.profile


def test_the_running_surface_is_the_outline_s_largest_radius():
    """On the 1:20 cone (points 8-9 of the outline) r(z) = 0.46 - z / 20 to round-off; the
    flange's tip arc rises 28 mm above the taping line; off the rim there is no surface."""
    z = np.array([-0.02, 0.0, 0.03, 0.06])
    assert OUTLINE is not None
    assert np.allclose(OUTLINE.outer_radius(z), 0.46 - z / 20.0, rtol=0, atol=1e-12)
    from contact.profiles import running_surface

    p = running_surface(OUTLINE, 0.46)
    assert 1e3 * p.height_m.max() == pytest.approx(28.0, abs=0.05)  # its description: 28 mm high
    assert math.isnan(float(OUTLINE.outer_radius(np.array([0.2]))[0]))


def test_the_contact_frame_on_the_running_surface_has_the_outline_s_normal_and_curvature():
    """The tread: the cone's angle atan(1/20), straight across; the flange root: the
    outline's 6 mm fillet, concave (negative radius) to 0.1 %; the flank beyond 60 deg."""
    assert OUTLINE is not None
    tread = frame_on_running_surface(OUTLINE, 0.01)
    assert tread.angle_rad == pytest.approx(math.atan(0.05), rel=1e-9) and math.isinf(tread.crown_radius_m)
    root = frame_on_running_surface(OUTLINE, -0.033)
    assert root.crown_radius_m == pytest.approx(-0.006, rel=1e-3)
    flank = frame_on_running_surface(OUTLINE, -0.04)
    assert math.degrees(flank.angle_rad) > 60.0


@pytest.fixture(scope="module")
def geometry():
    from wheel_squeal.curve import contact_geometry

    return contact_geometry(CONE)


def test_the_cone_wheel_flanges_where_its_conicity_cannot_steer(geometry):
    """A wheelset free to yaw rolls purely at y0 = r0 (s/2) / (lambda R) (linear theory): for
    the 1:20 cone (lambda = 0.05) and r0 = 0.46 m that is 2.3 mm at 3000 m, within the
    7.1 mm flange clearance (within 10 %: the contact moves across the curved rail head);
    at 600 m it would need 11.5 mm: the leading outer wheel flanges, in a two-point contact
    (tread and flank)."""
    wide = steady_curving(
        geometry,
        Vehicle(primary_yaw_stiffness_n_m_rad=0.0),
        3000.0,
        40.0,
        wheel_load_n=50e3,
        friction_coefficient=0.3,
    )
    assert wide[0].lateral_shift_m == pytest.approx(0.46 * 0.75 / (0.05 * 3000.0), rel=0.1)
    tight = steady_curving(geometry, Vehicle(), 600.0, 40.0, wheel_load_n=50e3, friction_coefficient=0.3)
    outer = tight[1]
    assert outer.flange_contact and len(outer.contacts) == 2
    assert math.degrees(outer.main.contact_angle_rad) > 60.0
    assert sum(c.load_share for c in outer.contacts) == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("design", [CONE, RAILWAY], ids=["cone", "S1002"])
def test_each_contact_reaches_the_chain_as_the_curving_found_it(design):
    """Each contact's design carries its normal force, Kalker's C22 of its ellipse and the
    friction its longitudinal creep leaves; the chain's Hertz ellipse at that contact is
    the curving's (to 5e-3: the curving's angle includes the wheelset's roll of a few mrad,
    and it interpolates the ellipse between tabulated shifts 0.05 mm apart where the chain
    takes the nearest one's curvatures, which on S1002's curved tread differ by up to 4.1e-3
    over 150-1000 m; a jump of the contact across the wheel is two contacts, each its own);
    the sliding speed is V |xi_y|. A standard profile's contact angle is the frame's (the
    force's direction), the outline's point its place on the FE wheel."""
    from wheel_squeal.api import hertz_of
    from wheel_squeal.curve import contact_geometry, wheel_sites

    geometry = contact_geometry(design)
    wheels = steady_curving(geometry, Vehicle(), 150.0, 40.0, wheel_load_n=50e3, friction_coefficient=0.3)
    for wheel in wheels:
        for site in wheel_sites(design, wheel, 40.0):
            c = site.state
            d = site.design
            assert d.contact.normal_load == c.normal_force_n and d.contact.c22 == c.c22
            assert d.contact.friction_coefficient == pytest.approx(c.lateral_friction_coefficient(0.3))
            assert d.contact.friction_coefficient <= 0.3
            h = hertz_of(d)
            assert h.semi_axis_a_m == pytest.approx(c.semi_axis_a_m, rel=5e-3)
            assert h.semi_axis_b_m == pytest.approx(c.semi_axis_b_m, rel=5e-3)
            assert site.op.crabbing_velocity_m_s == pytest.approx(40 / 3.6 * abs(c.lateral_creepage))
            assert d.contact_frame.z_m == c.point.wheel_lateral_m
            if design is RAILWAY:
                assert d.contact_frame.angle_rad == c.point.contact_angle_rad


def test_the_shipped_wheel_s_s1002_steers_its_bogie_without_flanging_in_wide_curves():
    """S1002 on UIC60 1:40 (the shipped wheel's [contact] wheel_profile): its rolling-radius
    difference grows far faster than the 1:20 cone's beyond a few mm, so the default stiff
    bogie keeps both axles off their flanges at 1000 m and beyond (the cone flanges there),
    and its leading outer wheel flanges in a tight curve on the 70 deg flank."""
    from wheel_squeal.curve import contact_geometry

    geometry = contact_geometry(RAILWAY)
    assert geometry.wheel.name == "S1002"
    for radius in (1000.0, 3000.0):
        wheels = steady_curving(
            geometry, Vehicle(), radius, 40.0, wheel_load_n=50e3, friction_coefficient=0.3
        )
        assert not any(w.flange_contact for w in wheels)
    cone = steady_curving(
        contact_geometry(CONE), Vehicle(), 1000.0, 40.0, wheel_load_n=50e3, friction_coefficient=0.3
    )
    assert cone[1].flange_contact
    tight = steady_curving(geometry, Vehicle(), 150.0, 40.0, wheel_load_n=50e3, friction_coefficient=0.3)
    assert (
        tight[1].flange_contact and math.degrees(max(c.contact_angle_rad for c in tight[1].contacts)) > 65.0
    )


@pytest.mark.slow  # two FE solves of the Table 1 wheel (about 4 s)
def test_modes_read_at_a_moved_contact_match_a_solve_at_that_contact():
    """The Table 1 wheel's modes solved at the tread apex and read at a contact 80 % of the
    way to its crown's edge, against the same modes solved with the contact there: lateral
    modal masses within 0.5 %, normal ones within 2 % (the visualisation mesh's linear
    interpolation between nodes a few mm apart; the solver reads its own element's shape
    functions). At its own contact the mode set is returned as it is."""
    from contact.frames import largest_contact_angle_rad
    from fem.moved_contact import modes_at_contact

    d = ws.load_design("table1")
    own = ws.compute_modes(d, "fast")
    assert modes_at_contact(own, d.contact_frame) is own
    moved = d.replace(contact_angle=0.8 * largest_contact_angle_rad(d.wheel))
    direct = ws.compute_modes(moved, "fast")
    read = modes_at_contact(own, moved.contact_frame)
    for a, b in zip(direct.modes, read.modes):
        assert a.label() == b.label()
        if math.isfinite(a.modal_mass) and a.modal_mass < 100.0:
            assert b.modal_mass == pytest.approx(a.modal_mass, rel=5e-3), a.label()
        if math.isfinite(a.normal_modal_mass) and a.normal_modal_mass < 1e4:
            assert b.normal_modal_mass == pytest.approx(a.normal_modal_mass, rel=0.02), a.label()


def test_a_lubricated_flange_holds_its_own_friction(geometry):
    """The gauge face lubricated (mu 0.1, the rail head's 0.3) at 150 m, 40 km/h: the
    leading outer wheel still flanges; its flange contact's creep force is at most 0.1 N
    (the saturation's bound, to round-off) while its tread's may use the head's 0.3; the
    chain sees the flange's friction there; the four lateral forces still sum to the
    bogie's mass times its unbalanced acceleration (to the solver's force tolerance)."""
    from track.bogie_curving import FORCE_TOLERANCE
    from track.curving import GRAVITY_M_S2
    from wheel_squeal.curve import wheel_sites

    load = 50e3
    wheels = steady_curving(
        geometry,
        Vehicle(),
        150.0,
        40.0,
        wheel_load_n=load,
        friction_coefficient=0.3,
        flange_friction_coefficient=0.1,
    )
    outer = wheels[1]
    assert outer.flange_contact
    flange = [c for c in outer.contacts if c.on_flange]
    assert all(c.adhesion_used <= 1.0 + 1e-9 for c in flange)
    for c in flange:
        assert abs(c.longitudinal_force_n) <= 0.1 * c.normal_force_n * (1 + 1e-9)
    lubricated = RAILWAY.replace(flange_friction_coefficient=0.1)
    for site in wheel_sites(lubricated, outer, 40.0):
        left = site.state.lateral_friction_coefficient(0.1 if site.state.on_flange else 0.3)
        assert site.design.contact.friction_coefficient == pytest.approx(left)
    unbalanced = (40 / 3.6) ** 2 / 150.0
    total = sum(w.lateral_force_n for w in wheels)  # the rail's forces, toward the centre
    mass = 4 * load / GRAVITY_M_S2
    assert total == pytest.approx(mass * unbalanced, abs=8 * FORCE_TOLERANCE * load)


def test_a_run_of_curves_started_from_its_neighbour_finds_the_same_equilibrium(geometry):
    """Curves from 3000 m down to 120 m, each solve started from the last one's equilibrium
    (what a map and a line do): every wheel's shift and angle of attack equal the cold
    solve's to 1e-9 (one equilibrium; the solver's tolerance is far below)."""
    from track.bogie_curving import contact_table, solve_curving

    table = contact_table(geometry)
    last = None
    for radius in (3000.0, 1000.0, 450.0, 200.0, 120.0):
        kwargs = dict(wheel_load_n=50e3, friction_coefficient=0.4, table=table)
        cold = solve_curving(geometry, Vehicle(), radius, 60.0, **kwargs)
        last = solve_curving(geometry, Vehicle(), radius, 60.0, start=last, **kwargs)
        for a, b in zip(cold.wheels, last.wheels):
            assert b.lateral_shift_m == pytest.approx(a.lateral_shift_m, abs=1e-9)
            assert b.angle_of_attack_rad == pytest.approx(a.angle_of_attack_rad, abs=1e-9)


@pytest.mark.parametrize("guess_factor", [1.0, 1.0 + 3e-7, 0.7, 1.9])
def test_a_contact_s_normal_force_from_a_guess_is_the_bracketed_one(guess_factor):
    """The normal force of each contact of the S1002 wheel across its shifts (tread and
    flange, both rails) found from a guess (the secant step the Jacobian's differences
    take, from the force itself, a little off, or far off: then bracketed as without one)
    balances the vertical load as the bracketed solve does: the same force to the
    bracketing's tolerance, 1e-9 of the load."""
    from track import bogie_curving as bc
    from wheel_squeal.curve import contact_geometry

    geometry = contact_geometry(RAILWAY)
    table = bc.contact_table(geometry)
    scene = bc._Scene(
        geometry, 200.0, 11.1, 0.6, 50e3, 0.4, 0.4, table.youngs_modulus_pa, table.poissons_ratio
    )
    for k in range(0, len(table.shifts_m), 7):
        for side, sign in ((0, 1), (1, -1)):
            row = table.values[k, side]
            alone = bc._side_forces(scene, row, sign, 50e3, 4e-3, 1e-4)[3][0]
            guessed = bc._side_forces(scene, row, sign, 50e3, 4e-3, 1e-4, guess_factor * alone)[3][0]
            assert guessed == pytest.approx(alone, abs=2e-9 * 50e3)


def test_an_equilibrium_with_its_jacobian_kept_is_newton_s_own(monkeypatch):
    """A run of curves (1000 m down to 120 m, each from the last one's equilibrium, at both
    ends of the friction range) solved with Newton's Jacobian kept (Broyden's update, from
    the last curve's) while a step cuts the forces fourfold is the equilibrium a new
    Jacobian at every step finds: the same unknowns to Newton's convergence step (1e-9,
    scaled), with fewer evaluations of the contact forces (equal if it were never kept)."""
    from track import bogie_curving as bc
    from wheel_squeal.curve import contact_geometry

    geometry = contact_geometry(RAILWAY)
    table = bc.contact_table(geometry)
    vehicle = RAILWAY.vehicle.vehicle()
    evaluations = [0]
    wheelset = bc._wheelset

    def counted(*args, **kwargs):
        evaluations[0] += 1
        return wheelset(*args, **kwargs)

    monkeypatch.setattr(bc, "_wheelset", counted)

    def run(keep: bool) -> tuple[list[np.ndarray], int]:
        evaluations[0], out = 0, []
        for mu in (0.2, 0.5):
            last = None
            for radius in (1000.0, 700.0, 450.0, 300.0, 200.0, 150.0, 120.0):
                start = last if keep or last is None else bc.BogieCurving(last.wheels, last.unknowns)
                last = bc.solve_curving(
                    geometry,
                    vehicle,
                    radius,
                    40.0,
                    wheel_load_n=50e3,
                    friction_coefficient=mu,
                    table=table,
                    start=start,
                )
                out.append(last.unknowns)
        return out, evaluations[0]

    kept, kept_count = run(keep=True)
    monkeypatch.setattr(bc, "KEPT_JACOBIAN_CONTRACTION", 0.0)  # a new Jacobian at every step
    fresh, fresh_count = run(keep=False)
    assert kept_count < 0.8 * fresh_count  # measured 0.74 here, 0.52 over a line's 3,312 curvings
    for a, b in zip(kept, fresh):
        np.testing.assert_allclose(a, b, rtol=0, atol=bc.NEWTON_STEP)


def test_an_outline_given_as_lists_is_the_same_hashable_outline():
    """An outline built from lists (a script's, a TOML table's) equals and hashes as the
    one built from tuples (its polygon and contact frames are kept per outline, by hash;
    lists were refused with a TypeError), and a point that is no (r, z) pair is named."""
    from geometry.outline import Outline, OutlineError

    assert OUTLINE is not None
    listed = Outline(
        [list(p) for p in OUTLINE.points], list(OUTLINE.bulges), list(OUTLINE.clamp), list(OUTLINE.contact)
    )
    assert listed == OUTLINE and hash(listed) == hash(OUTLINE)
    assert frame_on_running_surface(listed, 0.01) == frame_on_running_surface(OUTLINE, 0.01)
    with pytest.raises(OutlineError, match="pairs of numbers"):
        bad = [(*OUTLINE.points[0], 0.0), *OUTLINE.points[1:]]
        Outline(bad, OUTLINE.bulges, OUTLINE.clamp, OUTLINE.contact)
