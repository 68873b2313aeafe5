"""The contact in two directions (reduced.coupling): the lateral model is its limit with
no normal motion, the two-mode coalescence condition matches the eigen-solver, and each
growing eigenvalue is given the mechanism that makes it grow."""

from __future__ import annotations

import math

import numpy as np
import pytest

import reduced as r
from reduced.coupling import coupling_matrices, two_mode_coalesces

HERTZ = r.hertz_contact(0.213, 0.300, 0.085, 0.040, 175e9, 0.28, 1000.0)
K_H = HERTZ.normal_stiffness_n_m  # 1.36e8 N/m
OP = r.OperatingPoint.from_rpm(800, 0.213, 0.39)
#: (phi_t, phi_n) [1/sqrt(kg)] of two modes whose friction couplings have opposite signs
#: (S12 S21 < 0): with mu0 = 0.3 they coalesce when their stiffened frequencies are
#: within about 50 Hz of each other near 1 kHz (1025 Hz against 1000 Hz does)
PAIR = ((0.5, 0.05), (0.5, -0.05))


def _contact_mode(dof: r.ModalDOF, phi_n: float = 0.0) -> r.ContactMode:
    zeta = dof.damping_ns_m / (2 * math.sqrt(dof.stiffness_n_m * dof.mass_kg))
    return r.ContactMode(dof.frequency_hz, zeta, 1 / math.sqrt(dof.mass_kg), phi_n)


def test_without_normal_motion_it_is_the_lateral_model():
    """phi_n = 0: the growth rates of linear_stability (the same matrices: to round-off)."""
    law = r.ContactLaw.from_hertz(HERTZ, 0.3)
    dofs = [r.ModalDOF(3.1, 1.6e8, 42.0), r.ModalDOF(6.0, 2.0e7, 20.0), r.ModalDOF(2.0, 6.0e8, 90.0)]
    lateral = sorted(m.growth_rate_1_s for m in r.linear_stability(dofs, law, OP).modes)
    coupled = r.coupled_stability([_contact_mode(d) for d in dofs], law, OP, K_H)
    assert sorted(coupled.growth_rate_1_s) == pytest.approx(lateral, rel=1e-9, abs=1e-9)
    assert coupled.mechanisms[0] == "falling friction"


@pytest.mark.parametrize("detune", [-0.2, -0.05, -0.01, 0.0, 0.01, 0.05, 0.2])
def test_the_two_mode_condition_matches_the_eigen_solver(detune):
    """Two undamped modes, no friction damping: they grow exactly when the coupled
    stiffness has complex eigenvalues, (S11 - S22)^2 + 4 S12 S21 < 0. Near the boundary
    the growth rate tends to 0: a margin of 1e-6 of the frequency separates the cases."""
    f1 = 1000.0
    modes = [r.ContactMode(f1, 0.0, *PAIR[0]), r.ContactMode(f1 * (1 + detune) + 25.0, 0.0, *PAIR[1])]
    damping, stiffness = coupling_matrices(modes, 0.0, 0.3, K_H)
    lam = np.linalg.eigvals(np.block([[np.zeros((2, 2)), np.eye(2)], [-stiffness, -damping]]))
    grows = lam.real.max() > 1e-6 * 2 * math.pi * f1
    assert grows == two_mode_coalesces(stiffness)
    # the closed form of the growth rate: lambda^2 = -s, s the eigenvalues of S
    s = np.linalg.eigvals(stiffness).astype(complex)
    assert lam.real.max() == pytest.approx(np.sqrt(-s).real.max(), rel=1e-9, abs=1e-9)


def test_the_boundary_is_crossed_where_the_closed_form_says():
    """Sweep the second mode's frequency through coalescence: the eigen-solver's growth
    switches on and off at the roots of the discriminant."""
    f = np.linspace(900.0, 1100.0, 4001)
    grows, closed = [], []
    for f2 in f:
        modes = [r.ContactMode(1000.0, 0.0, *PAIR[0]), r.ContactMode(f2, 0.0, *PAIR[1])]
        damping, stiffness = coupling_matrices(modes, 0.0, 0.3, K_H)
        lam = np.linalg.eigvals(np.block([[np.zeros((2, 2)), np.eye(2)], [-stiffness, -damping]]))
        grows.append(lam.real.max() > 1e-3)
        closed.append(two_mode_coalesces(stiffness))
    grows, closed = np.array(grows), np.array(closed)
    assert closed.any() and not closed.all()  # the sweep crosses the boundary both ways
    assert np.array_equal(grows, closed)


def test_mode_coupling_vanishes_with_the_normal_coupling_and_needs_no_falling_friction():
    law = r.ContactLaw.from_hertz(HERTZ, 0.3, friction_law="constant")  # no falling friction

    def pair(scale: float) -> list[r.ContactMode]:
        (pt1, pn1), (pt2, pn2) = PAIR
        return [r.ContactMode(1000.0, 1e-4, pt1, pn1 * scale), r.ContactMode(1025.0, 1e-4, pt2, pn2 * scale)]

    strong = r.coupled_stability(pair(1.0), law, OP, K_H)
    assert strong.unstable and strong.mechanisms[0] == "mode coupling"
    rates = [r.coupled_stability(pair(s), law, OP, K_H).growth_rate_1_s.max() for s in (1.0, 0.1, 0.01, 0.0)]
    assert rates[0] > 0 and all(x < 0 for x in rates[1:])  # once the pair separates it decays


def test_falling_friction_growth_does_not_depend_on_the_hertz_spring():
    """A mode with no normal motion at the contact grows by falling friction alone: the
    normal spring does not enter (to round-off)."""
    law = r.ContactLaw.from_hertz(HERTZ, 0.3)
    mode = [_contact_mode(r.ModalDOF(3.1, 1.6e8, 42.0))]
    rates = [r.coupled_stability(mode, law, OP, k).growth_rate_1_s[0] for k in (1e6, K_H, 1e10)]
    assert rates == pytest.approx([rates[0]] * 3, rel=1e-12)
    assert rates[0] > 0


# -- the FE's components at the contact ------------------------------------------------------
def _axisym(design_name: str, etw: int):
    import warnings

    import wheel_squeal as ws
    from fem.axisym import solve_axisymmetric
    from geometry.gmsh_mesh import mesh_profile

    wheel = ws.load_design(design_name).wheel
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return wheel, solve_axisymmetric(
            wheel, mesh_profile(wheel, elements_through_web=etw, order=2), curved=True, fmax_hz=2500.0
        )


def test_a_mirror_symmetric_wheel_has_no_mode_with_both_components():
    """Table 1's wheel is symmetric about its mid-plane: at the tread apex an axial mode
    has no radial motion and an in-plane mode no axial motion, so nothing couples
    through the normal contact at angle 0. The gmsh mesh is symmetric only to its
    meshing: the smaller component is within 1e-4 of the larger (measured: 2e-6)."""
    _, ms = _axisym("table1", 2)
    for m in ms.modes:
        t, n = m.contact_components
        assert min(abs(t), abs(n)) <= 1e-4 * max(abs(t), abs(n)), (m.label(), t, n)
    assert any(m.contact_components[1] > 0 for m in ms.modes)  # in-plane modes do move it radially


def test_the_normal_components_converge_with_the_mesh():
    """A dished web couples both directions: phi_n of its axial modes is a few % of phi_t
    and changes by under 1 % from one to three elements across the web (measured:
    0.2 %), as phi_t does."""
    _, coarse = _axisym("dished_web", 1)
    _, fine = _axisym("dished_web", 3)
    for a, b in zip(coarse.modes[:6], fine.modes[:6]):
        assert a.label() == b.label()
        ta, na = a.contact_components
        tb, nb = b.contact_components
        assert ta == pytest.approx(tb, rel=0.01, abs=1e-9)
        assert na == pytest.approx(nb, rel=0.01, abs=1e-9)
    assert fine.modes[4].label() == "(3,0) axial" and fine.modes[4].contact_components[1] > 0.01


def test_the_normal_components_agree_with_the_3d_solver():
    """The cyclic 3-D P2 model of the same profile gives the same (phi_t, phi_n) within
    0.5 % (measured: under 0.1 %; the 3-D mesh revolves the profile in straight sectors)."""
    import warnings

    from fem.cyclic import default_sectors, solve_cyclic
    from geometry.gmsh_mesh import mesh_profile
    from geometry.revolve import revolve_profile

    wheel, ax = _axisym("dished_web", 2)
    profile = mesh_profile(wheel, elements_through_web=2, order=2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cy = solve_cyclic(
            wheel, revolve_profile(profile, default_sectors(wheel, profile.size)), fmax_hz=2500.0
        )
    for a in ax.modes:
        c = min(
            cy.modes,
            key=lambda m: (m.nodal_diameters != a.nodal_diameters, abs(m.frequency_hz - a.frequency_hz)),
        )
        for x, y in zip(a.contact_components, c.contact_components):
            assert x == pytest.approx(y, rel=5e-3, abs=1e-4), a.label()


def test_the_rig_wheel_squeals_by_falling_friction_only_at_contact_angle_zero():
    """With the normal contact included, every growing eigenvalue of the Table 1 wheel at
    the Fig. 6 point grows by falling friction, and with constant friction nothing grows:
    at the tread apex no mode couples through the normal direction (the wheel is
    symmetric), so mode coupling needs a contact angle."""
    import wheel_squeal as ws
    from wheel_squeal.stability import two_directions

    design = ws.load_design("table1")
    modes = ws.compute_modes(design, "fast")
    op = ws.operating_point(design, rpm=800, crab_velocity=0.39)
    falling = two_directions(design, modes, ws.contact_law(design), op)
    assert falling["normal_stiffness_n_m"] == pytest.approx(1.36e8, abs=0.005e8)
    assert falling["growing"] and {g["mechanism"] for g in falling["growing"]} == {"falling friction"}
    assert "(3,0) axial" in {g["mode"] for g in falling["growing"]}
    constant = two_directions(design, modes, ws.contact_law(design, friction_law="constant"), op)
    assert constant["growing"] == []


# -- the time domain in two directions ------------------------------------------------------
def _envelope_rate(hist, period_s: float, after_s: float) -> float:
    """The growth rate [1/s] of the kinetic energy's peak per period (energy ~ e^{2 sigma t})."""
    ke = 0.5 * np.sum(hist.qd**2, axis=1)
    n = int(round(period_s / (hist.t[1] - hist.t[0])))
    blocks = len(ke) // n
    t = np.array([hist.t[k * n + np.argmax(ke[k * n : (k + 1) * n])] for k in range(blocks)])
    peak = np.array([ke[k * n : (k + 1) * n].max() for k in range(blocks)])
    keep = t > after_s
    return float(np.polyfit(t[keep], np.log(peak[keep]), 1)[0] / 2)


@pytest.mark.parametrize(
    "law, pair",
    [
        ("constant", ((1000.0, 1e-3, 0.5, 0.05), (1025.0, 1e-3, 0.5, -0.05))),  # mode coupling
        ("constant", ((1000.0, 1e-3, 0.5, 0.03), (1012.0, 1e-3, 0.5, -0.03))),  # mode coupling
        ("falling", ((1143.0, 9.4e-4, 1 / math.sqrt(3.1), 0.0),)),  # falling friction, Table 1
    ],
)
def test_the_time_domain_grows_at_the_linear_rate(law, pair):
    """Started at the static equilibrium with a tiny kick (the normal approach stays below
    0.2 % of delta0: linear), the kinetic energy's envelope grows at twice the fastest
    eigenvalue's real part within 3 % (measured: 0.7 %, the fit over the periods after
    the other eigenvalue has died out)."""
    contact = r.ContactLaw.from_hertz(HERTZ, 0.3, friction_law=law)
    modes = [r.ContactMode(*m) for m in pair]
    linear = r.coupled_stability(modes, contact, OP, K_H)
    hist = r.simulate_two_directions(modes, contact, OP, HERTZ.approach_m, 0.12, kick=1e-7)
    assert np.abs(hist.u_n).max() < 2e-3 * HERTZ.approach_m and not hist.separated.any()
    rate = _envelope_rate(hist, 1 / linear.frequency_hz[0], 0.03)
    assert rate == pytest.approx(linear.growth_rate_1_s[0], rel=0.03)


def test_the_power_balance_closes_with_the_hertz_spring():
    """From rest (the creep force's step), with normal motion and the nonlinear Hertz
    spring: the energy (modes + Hertz spring) changes by the integral of the power Q v_t
    minus the damping, to 1e-3 of the largest energy (measured: 4e-4; the creep force
    turns sharply where the contact sticks and slips, which the trapezoidal integral of
    the power at 64 steps per period follows only to that order)."""
    contact = r.ContactLaw.from_hertz(HERTZ, 0.3)
    modes = [r.ContactMode(1143.0, 9.4e-4, 0.57, 0.03), r.ContactMode(1600.0, 1e-3, 0.4, -0.04)]
    hist = r.simulate_two_directions(modes, contact, OP, HERTZ.approach_m, 0.05)
    work = np.concatenate([[0.0], np.cumsum(0.5 * (hist.power_w[1:] + hist.power_w[:-1]) * np.diff(hist.t))])
    mismatch = np.abs(hist.energy_j - hist.energy_j[0] - work).max()
    assert mismatch < 1e-3 * np.abs(hist.energy_j).max()


def test_separation_is_reported_and_carries_no_force():
    contact = r.ContactLaw.from_hertz(HERTZ, 0.3, friction_law="constant")
    modes = [r.ContactMode(1000.0, 1e-3, 0.5, 0.05), r.ContactMode(1025.0, 1e-3, 0.5, -0.05)]
    hist = r.simulate_two_directions(modes, contact, OP, HERTZ.approach_m, 0.12)  # from rest: large
    assert hist.separated.any()
    assert np.all(hist.normal_force_n[hist.separated] == 0.0)
    assert np.all(hist.lateral_force_n[hist.separated] == 0.0)
    assert np.all(hist.u_n[hist.separated] <= -HERTZ.approach_m)
