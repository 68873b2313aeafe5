"""Where the wheel touches the roller: the contact frame on the crown arc or an outline's
normal, its limits, the Hertz contact there, the FE components along t and n at a
moved contact (converged, and equal to the 3-D solver's), the design keys, the
counter-body and the modal model without FE."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import reduced as r
import wheel_squeal as ws
from contact.frames import ContactPointError, contact_frame, largest_contact_angle_rad
from geometry import DesignError
from geometry.outline import MAX_CONTACT_ANGLE_DEG

TABLE1 = ws.load_design("table1")


# -- the frame ---------------------------------------------------------------------------
@pytest.mark.parametrize("deg", [-2.0, -0.5, 0.7, 2.4])
def test_the_contact_moves_along_the_crown_arc_to_its_normal_angle(deg):
    """The point lies on the crown circle (radius R1t about (R1 - R1t, 0)) where the
    circle's outward normal makes the angle: (P - centre) / R1t is the normal."""
    w = TABLE1.wheel
    f = contact_frame(w, math.radians(deg))
    centre = np.array([w.rolling_radius - w.crown_radius, 0.0])
    radial = (np.array([f.r_m, f.z_m]) - centre) / w.crown_radius
    assert np.hypot(*radial) == pytest.approx(1.0, abs=1e-14)
    assert radial == pytest.approx(np.array(f.normal), abs=1e-14)
    assert np.dot(f.normal, f.tangent) == pytest.approx(0.0, abs=1e-16)
    assert f.crown_radius_m == w.crown_radius


def test_the_apex_frame_is_the_papers_exactly():
    f = contact_frame(TABLE1.wheel, 0.0)
    assert (f.r_m, f.z_m, f.angle_rad) == (TABLE1.wheel.rolling_radius, 0.0, 0.0)
    assert f.components(0.3, -0.7) == (-0.7, 0.3)  # (u_t, u_n) = (u_z, u_r), exactly
    assert f.rolling_curvature_radius_m == TABLE1.wheel.rolling_radius


def test_an_angle_off_the_tread_is_refused_naming_the_reach():
    """Table 1's 0.3 m crown over a 26 mm rim reaches asin(0.013 / 0.3) = 2.48 deg."""
    top = largest_contact_angle_rad(TABLE1.wheel)
    assert math.degrees(top) == pytest.approx(math.degrees(math.asin(0.013 / 0.3)), rel=2e-3)
    with pytest.raises(ContactPointError, match="at most 2.48 deg"):
        contact_frame(TABLE1.wheel, math.radians(5.0))
    with pytest.raises(DesignError, match="off the tread"):
        TABLE1.replace(contact_angle=math.radians(20.0))
    # a tighter crown reaches further, up to the model's limit
    crowned = TABLE1.replace(crown_radius=0.03)
    assert contact_frame(crowned.wheel, math.radians(20.0)).angle_rad == pytest.approx(math.radians(20.0))


def _conical_outline_design(tilt_deg: float):
    """A Table 1-like ring whose tread is a cone tilted by ``tilt_deg``: the contact on
    the cone has that contact angle."""
    t = math.tan(math.radians(tilt_deg))
    pts = [
        [0.05, -0.0075],
        [0.05, 0.0075],
        [0.18, 0.0075],
        [0.18, 0.013],
        [0.213 - 0.013 * t, 0.013],
        [0.213 + 0.013 * t, -0.013],
        [0.18, -0.013],
        [0.18, -0.0075],
        [0.05, -0.0075],
    ]
    data = {"name": "cone", "profile": {"points": pts, "contact": [0.213, 0.0]}}
    return ws.Design.from_mapping(data)


def test_an_outline_sets_its_own_angle_and_the_limit_is_the_models():
    d = _conical_outline_design(30.0)
    assert math.degrees(d.contact_frame.angle_rad) == pytest.approx(30.0, abs=1e-9)
    with pytest.raises(DesignError, match="sets its own angle"):
        d.replace(contact_angle=0.1)
    with pytest.raises((DesignError, ValueError), match=f"at most {MAX_CONTACT_ANGLE_DEG:g}"):
        _conical_outline_design(MAX_CONTACT_ANGLE_DEG + 5.0)


def test_the_hertz_contact_follows_the_point():
    """At angle g the wheel's rolling-direction radius of curvature is r / cos(g)
    (Meusnier): the ellipse is the one hertz_contact gives for those radii."""
    g = math.radians(2.0)
    d = TABLE1.replace(contact_angle=g)
    f = d.contact_frame
    expected = r.hertz_contact(f.r_m / math.cos(g), 0.3, 0.085, 0.040, 175e9, 0.28, 1000.0)
    assert ws.api.hertz_of(d) == expected
    assert ws.api.hertz_of(TABLE1).semi_axis_a_m != expected.semi_axis_a_m
    radius = ws.operating_point(d, rpm=800).rolling_speed_m_s / r.model.rpm_to_speed(800.0, 1.0)
    assert radius == pytest.approx(f.r_m, rel=1e-12)  # 800 RPM rolls on the contact's own radius


# -- the FE at a moved contact -----------------------------------------------------------
def _axisym(etw: int, frame):
    from fem.axisym import solve_axisymmetric
    from geometry.gmsh_mesh import mesh_profile

    w = TABLE1.wheel
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mesh = mesh_profile(w, elements_through_web=etw, order=2)
        return mesh, solve_axisymmetric(w, mesh, curved=True, fmax_hz=2500.0, contact=frame)


@pytest.mark.slow
def test_components_at_a_moved_contact_converge_and_agree_with_the_3d_solver():
    """At 2 deg the symmetric wheel's axial modes move the contact normally (the rim
    tilts): phi_n is 2-27 % of phi_t (the (3,0) mode's: 6 %). From one to three elements across the web each
    component changes by under 1 % of the mode's contact motion |phi| (measured: 0.08 %),
    and the cyclic 3-D P2 model of the same profile, probed at the same point, agrees
    with the axisymmetric one on the same mesh within 1 % of |phi| (measured: 0.06 %, its
    sectors are straight)."""
    from fem.cyclic import default_sectors, solve_cyclic
    from geometry.revolve import revolve_profile

    frame = contact_frame(TABLE1.wheel, math.radians(2.0))
    _, coarse = _axisym(1, frame)
    _, fine = _axisym(3, frame)
    mesh2, mid = _axisym(2, frame)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cyclic = solve_cyclic(
            TABLE1.wheel,
            revolve_profile(mesh2, default_sectors(TABLE1.wheel, mesh2.size)),
            fmax_hz=2500.0,
            contact=frame,
        )
    for a, b, c, m in zip(coarse.modes[:6], fine.modes[:6], cyclic.modes[:6], mid.modes[:6]):
        assert a.label() == b.label() == c.label()
        size = np.hypot(*b.contact_components)
        assert np.abs(np.subtract(a.contact_components, b.contact_components)).max() <= 0.01 * size
        assert np.abs(np.subtract(c.contact_components, m.contact_components)).max() <= 0.01 * size
    three = next(m for m in fine.modes if m.label() == "(3,0) axial")
    t, n = three.contact_components
    assert 0.03 < abs(n / t) < 0.1
    assert fine.contact_angle_rad == frame.angle_rad
    assert fine.contact_point == (frame.r_m, 0.0, frame.z_m)


def test_the_in_plane_displacement_at_the_point_is_the_frames_rotation():
    """(phi_t, phi_n) of a mode at the moved point is the rotation by the contact angle
    of its (u_z, u_r) there: with the same point and a frame of angle 0, the modal
    components come out rotated back."""
    from contact.frames import ContactFrame

    frame = contact_frame(TABLE1.wheel, math.radians(-1.5))
    flat = ContactFrame(frame.r_m, frame.z_m, 0.0, frame.crown_radius_m)
    _, tilted = _axisym(1, frame)
    _, upright = _axisym(1, flat)
    for a, b in zip(tilted.modes, upright.modes):
        if a.family != "axial":
            continue
        u_z, u_r = b.contact_lateral[0], b.contact_normal[0]
        t, n = frame.components(u_r, u_z)
        assert (a.contact_lateral[0], a.contact_normal[0]) == pytest.approx((t, n), rel=1e-9, abs=1e-12)


# -- design keys, counter-body, modal model ----------------------------------------------------
def test_contact_keys_round_trip_and_leave_old_hashes_alone(tmp_path):
    d = TABLE1.replace(
        contact_angle=0.03,
        normal_contact="constant",
        transient_creep=True,
        relaxation_length=0.001,
        normal_frequency_hz=3000.0,
        normal_damping_ratio=0.02,
        normal_modal_mass_kg=40.0,
    )
    path = tmp_path / "moved.toml"
    path.write_text(d.to_toml())
    back = ws.load_design(str(path))
    assert back.contact == d.contact and back.counter_body == d.counter_body
    assert d.content_hash() != TABLE1.content_hash()
    assert "contact_angle" not in TABLE1.to_toml() and "normal_frequency_hz" not in TABLE1.to_toml()


@pytest.mark.parametrize(
    "changes, message",
    [
        ({"relaxation_length": 0.001}, "needs transient_creep"),
        ({"normal_frequency_hz": 3000.0}, "needs normal_damping_ratio, normal_modal_mass_kg"),
        ({"normal_contact": "soft"}, "normal_contact must be one of"),
        ({"contact_angle": 20.0}, "in rad"),
    ],
)
def test_bad_contact_keys_are_refused_in_one_line(changes, message):
    with pytest.raises(DesignError, match=message):
        TABLE1.replace(**changes)


def test_the_roller_takes_part_in_the_eigenvalues():
    """A soft lateral roller mode in series: it shows among the participants of the
    growing eigenvalues, and the table keeps one row per FE mode."""
    d = TABLE1.replace(lateral_frequency_hz=1100.0, lateral_damping_ratio=0.01, lateral_modal_mass_kg=5.0)
    modes = ws.compute_modes(d, "fast")
    op = ws.operating_point(d)
    from wheel_squeal.mode_stability import eigenvalue_list, excitable, stability_table

    table = stability_table(d, modes, ws.contact_law(d), op)
    assert len(table.rows) == len(excitable(modes, ws.contact_law(d)))
    names = {p["mode"] for e in eigenvalue_list(table) for p in e["participants"]}
    assert "the roller" in names


def test_a_modal_model_reproduces_the_papers_mode_without_fe(tmp_path):
    """Table 1's mode as a modal test gives it (lateral 1/sqrt(3.1), normal 0): the run
    is the paper's model, 0.367 m/s at the Fig. 6 point (94 % of Vc)."""
    from fem.modal_model import load_modal_model

    path = tmp_path / "rig.toml"
    path.write_text(
        "[[mode]]\nfrequency_hz = 1143.0\ndamping_ratio = 9.4e-4\n"
        f'lateral = {1 / math.sqrt(3.1)!r}\nnormal = 0.0\nnodal_diameters = 3\nlabel = "rig"\n'
    )
    ms = load_modal_model(path)
    assert ms.modes[0].modal_mass == pytest.approx(3.1, rel=1e-12)
    a = ws.analyse(TABLE1.replace(squeal_mode=""), modes=ms, stop_after="limit_cycle", remedy=False)
    assert a.verdict.squeals and a.verdict.outcome.label == "rig"
    assert a.verdict.outcome.amplitude_m_s == pytest.approx(0.367, abs=0.002)
    assert a.verdict.outcome.mechanism == "falling friction"


@pytest.mark.parametrize(
    "text, message",
    [
        ("", "no \\[\\[mode\\]\\] table"),
        ("[[mode]]\nfrequency_hz = 1e3\n", "needs damping_ratio, lateral, normal"),
        ("[[mode]]\nfrequency_hz = 1e3\ndamping_ratio = 2.0\nlateral = 1\nnormal = 0\n", "damping ratio"),
        (
            "[[mode]]\nfrequency_hz = 1e3\ndamping_ratio = 0.01\nlateral = 1\nnormal = 0\nshape = 1\n",
            "unknown",
        ),
        ("[[mode]]\nfrequency_hz = 1e3\ndamping_ratio = 0.01\nlateral = 'a'\nnormal = 0\n", "finite number"),
        ("mode = 3", "no \\[\\[mode\\]\\] table"),
    ],
)
def test_a_bad_modal_model_is_one_line(tmp_path, text, message):
    from fem.modal_model import load_modal_model

    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(DesignError, match=message) as err:
        load_modal_model(path)
    assert "\n" not in str(err.value)
