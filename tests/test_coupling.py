"""The contact in two directions: the lateral model is its limit with no normal motion
(bit for bit), the two-mode coalescence condition matches the eigen-solver, each growing
eigenvalue is given the mechanism that makes it grow, and the time domain (the
production RK4 kernels and an independent solve_ivp integration) grows at the linear
rate and balances its power."""

from __future__ import annotations

import math

import numpy as np
import pytest

import reduced as r
from reduced.coupling import coupling_stiffness, two_mode_coalesces
from reduced.model import static_normal_approach_m

HERTZ = r.hertz_contact(0.213, 0.300, 0.085, 0.040, 175e9, 0.28, 1000.0)
K_H = HERTZ.normal_stiffness_n_m  # 1.36e8 N/m
OP = r.OperatingPoint.from_rpm(800, 0.213, 0.39)
#: (phi_t, phi_n) [1/sqrt(kg)] of two modes whose friction couplings have opposite signs
#: (S12 S21 < 0): with mu0 = 0.3 they coalesce when their stiffened frequencies are
#: within about 50 Hz of each other near 1 kHz (1025 Hz against 1000 Hz does)
PAIR = ((0.5, 0.05), (0.5, -0.05))
TABLE1 = r.ModalDOF(3.1, 1.6e8, 42.0)


def _mode(f_hz: float, zeta: float, phi_t: float, phi_n: float) -> r.ModalDOF:
    return r.ModalDOF.from_components(f_hz, zeta, phi_t, phi_n)


def _undamped_growth(modes: list[r.ModalDOF], mu0: float) -> float:
    """The largest growth rate of the undamped pair with the friction's stiffness
    coupling only (g = 0), from the eigen-solver of reduced.stability."""
    lin = r.LinearContact(0.0, mu0, K_H)
    return float(r.stability.growth_rates(modes, [0.0, 0.0], lin).max())


def test_without_normal_motion_it_is_the_lateral_model_bit_for_bit():
    """Normal direction switched off (a constant normal load) or no mode moving the
    contact normally: the growth rates, frequencies and bounds of the paper's lateral
    model, to the last bit, with and without rotation."""
    dofs = [TABLE1, r.ModalDOF(6.0, 2.0e7, 20.0, 2), r.ModalDOF(2.0, 6.0e8, 90.0, 3)]
    hertz_on = r.ContactLaw.from_hertz(HERTZ, 0.3)
    hertz_off = r.ContactLaw.from_hertz(HERTZ, 0.3, normal=False)
    assert hertz_on.normal_stiffness_n_m == pytest.approx(K_H) and hertz_off.normal_stiffness_n_m == 0.0
    for omega in (0.0, OP.wheel_speed_rad_s(0.213)):
        on = r.linear_stability(dofs, hertz_on, OP, omega, bounds="all")
        off = r.linear_stability(dofs, hertz_off, OP, omega, bounds="all")
        assert on.modes == off.modes  # every field, exactly
        assert np.array_equal(on.eigenvalues, off.eigenvalues)
        assert {m.mechanism for m in on.modes if m.unstable} == {"falling friction"}


def test_the_time_domain_without_normal_motion_is_the_lateral_kernel_bit_for_bit():
    """The general kernel (contact gains, the Hertz spring, the lagged force) with the
    paper's lateral mode is the scalar kernel of the paper's model, to the last bit."""
    from reduced import _kernels
    from reduced.model import choose_time_step, law_vector

    law = r.ContactLaw.from_hertz(HERTZ, 0.3)
    lv = law_vector(law, OP)
    h, n = choose_time_step(TABLE1, law, OP), 20000
    y1, u1 = np.empty(n + 1), np.empty(n + 1)
    _kernels.integrate_store_1(0.0, 0.0, 3.1, 42.0, 1.6e8, tuple(lv.tolist()), h, n, 1, y1, u1)
    y, u, q = np.empty((n + 1, 1)), np.empty((n + 1, 1)), np.empty(n + 1)
    one, zero = np.ones(1), np.zeros(1)
    args = (np.zeros(1), np.zeros(1), np.array([3.1]), np.array([42.0]), np.array([1.6e8]))
    _kernels.integrate_store(*args, one, zero, zero, zero, lv, h, n, 1, y, u, q)
    assert np.abs(u1).max() > 0.1  # it squeals: the nonlinear creep law is exercised
    assert np.array_equal(y[:, 0], y1) and np.array_equal(u[:, 0], u1)


#: sha256 of the Fig. 6 record's contact velocity (Table 1 mode, 800 RPM, Vc = 0.39 m/s,
#: 0.5 s from rest) as the lateral model computed it before the contact's normal direction
#: was added: the RK4 kernels' own IEEE arithmetic
FIG6_V_SHA256 = "f5e8f7e45104b487a5f3c700bbfb1540621dde9bc7531e457b583f842aa8a96a"
#: The lateral force of that record at samples 1000, 5000, 10000 and the last [N], and the
#: sum of its magnitudes: the force is evaluated after the run by numpy's vectorised exp,
#: whose last bit differs between numpy builds (2.4 and earlier differ), so it is compared
#: to 1e-12 rather than to the bit
FIG6_Q_SAMPLES_N = {1000: -193.87054589345013, 5000: -196.3399432097547, 10000: -198.54812180074904}
FIG6_Q_LAST_N, FIG6_Q_ABS_SUM_N = -175.5739565366413, 5374060.402943479


@pytest.mark.parametrize("normal", [True, False])
def test_the_fig6_record_is_unchanged_to_the_bit(normal):
    """The paper's mode with the Hertz spring on (it has no normal motion) or off gives
    the record of the lateral model before the normal direction existed: its velocity to
    the bit (the RK4 kernels use IEEE arithmetic and the platform's exp, as then), its
    force to 1e-12 (numpy's exp after the run)."""
    import hashlib

    law = r.ContactLaw.from_hertz(HERTZ, 0.3, normal=normal)
    hist = r.simulate(TABLE1, law, OP, 0.5)
    assert hashlib.sha256(hist.v.tobytes()).hexdigest() == FIG6_V_SHA256
    for i, q in FIG6_Q_SAMPLES_N.items():
        assert hist.Q[i] == pytest.approx(q, rel=1e-12)
    assert hist.Q[-1] == pytest.approx(FIG6_Q_LAST_N, rel=1e-12)
    assert np.abs(hist.Q).sum() == pytest.approx(FIG6_Q_ABS_SUM_N, rel=1e-12)


@pytest.mark.parametrize("detune", [-0.2, -0.05, -0.01, 0.0, 0.01, 0.05, 0.2])
def test_the_two_mode_condition_matches_the_eigen_solver(detune):
    """Two undamped modes, no friction damping: they grow exactly when the coupled
    stiffness has complex eigenvalues, (S11 - S22)^2 + 4 S12 S21 < 0. Near the boundary
    the growth rate tends to 0: a margin of 1e-6 of the frequency separates the cases.
    And the growth rate is the closed form's: lambda^2 = -s, s the eigenvalues of S."""
    f1 = 1000.0
    modes = [_mode(f1, 0.0, *PAIR[0]), _mode(f1 * (1 + detune) + 25.0, 0.0, *PAIR[1])]
    stiffness = coupling_stiffness(modes, K_H, 0.3)
    sigma = _undamped_growth(modes, 0.3)
    assert (sigma > 1e-6 * 2 * math.pi * f1) == two_mode_coalesces(stiffness)
    s = np.linalg.eigvals(stiffness).astype(complex)
    assert sigma == pytest.approx(np.sqrt(-s).real.max(), rel=1e-9, abs=1e-9)


def test_the_boundary_is_crossed_where_the_closed_form_says():
    """Sweep the second mode's frequency through coalescence: the eigen-solver's growth
    switches on and off at the roots of the discriminant."""
    f = np.linspace(900.0, 1100.0, 4001)
    grows, closed = [], []
    for f2 in f:
        modes = [_mode(1000.0, 0.0, *PAIR[0]), _mode(f2, 0.0, *PAIR[1])]
        grows.append(_undamped_growth(modes, 0.3) > 1e-3)
        closed.append(two_mode_coalesces(coupling_stiffness(modes, K_H, 0.3)))
    grows, closed = np.array(grows), np.array(closed)
    assert closed.any() and not closed.all()  # the sweep crosses the boundary both ways
    assert np.array_equal(grows, closed)


def test_mode_coupling_vanishes_with_the_normal_coupling_and_needs_no_falling_friction():
    law = r.ContactLaw.from_hertz(HERTZ, 0.3, friction_law="constant")  # no falling friction

    def pair(scale: float) -> list[r.ModalDOF]:
        (pt1, pn1), (pt2, pn2) = PAIR
        return [_mode(1000.0, 1e-4, pt1, pn1 * scale), _mode(1025.0, 1e-4, pt2, pn2 * scale)]

    strong = r.linear_stability(pair(1.0), law, OP)
    assert strong.modes[0].unstable and strong.modes[0].mechanism == "mode coupling"
    assert set(strong.modes[0].partners) == {0, 1}  # both modes take part
    rates = [r.linear_stability(pair(s), law, OP).growth_rate_1_s for s in (1.0, 0.1, 0.01, 0.0)]
    assert rates[0] > 0 and all(x < 0 for x in rates[1:])  # once the pair separates it decays


def test_both_mechanisms_are_told_apart_in_one_system():
    """A coupled pair and, far from it, the Table 1 mode with the paper's falling law:
    the pair's eigenvalue grows by mode coupling, the Table 1 mode's by falling friction."""
    law = r.ContactLaw.from_hertz(HERTZ, 0.3)
    modes = [_mode(1000.0, 1e-3, *PAIR[0]), _mode(1025.0, 1e-3, *PAIR[1]), r.ModalDOF(3.1, 7.0e8, 42.0)]
    res = r.linear_stability(modes, law, OP)
    assert res.modes[2].unstable and res.modes[2].mechanism == "falling friction"
    assert res.modes[2].partners == (2,)
    assert res.modes[0].mechanism in ("mode coupling", "both") and res.modes[0].unstable


def test_falling_friction_growth_does_not_depend_on_the_hertz_spring():
    """A mode with no normal motion at the contact grows by falling friction alone: the
    normal spring does not enter (exactly)."""
    rates = []
    for k in (1e6, K_H, 1e10):
        law = r.ContactLaw(**{**r.ContactLaw.from_hertz(HERTZ, 0.3).__dict__, "hertz_approach_m": 1500.0 / k})
        rates.append(r.linear_stability([TABLE1], law, OP).growth_rate_1_s)
    assert rates == [rates[0]] * 3 and rates[0] > 0


def test_transient_creep_lowers_the_falling_friction_growth_as_the_lag_predicts():
    """With the creep force lagging by tau, a mode far from the others sees the friction
    damping g / (1 + (omega tau)^2) (and a stiffness that shifts it slightly): its growth
    rate tends to -(c + g / (1 + (w tau)^2)) / (2 m), within 1 % here (the shift is of
    order g w tau / (2 m w) against the mode's w: 1e-4)."""
    from reduced.stability import friction_damping_ns_m

    a = HERTZ.semi_axis_a_m
    law = r.ContactLaw.from_hertz(HERTZ, 0.3, relaxation_length_m=a)
    g = friction_damping_ns_m(law, OP)
    w, tau = TABLE1.angular_frequency_rad_s, a / OP.rolling_speed_m_s
    expected = -(TABLE1.damping_ns_m + g / (1 + (w * tau) ** 2)) / (2 * TABLE1.mass_kg)
    sigma = r.linear_stability([TABLE1], law, OP).growth_rate_1_s
    assert sigma == pytest.approx(expected, rel=0.01)
    steady = r.linear_stability([TABLE1], r.ContactLaw.from_hertz(HERTZ, 0.3), OP).growth_rate_1_s
    assert sigma < steady


def test_a_roller_mode_in_series_changes_the_growth_as_a_series_spring_predicts():
    """A stiff, heavy roller mode along the lateral direction far above the wheel mode
    leaves it as it was; a soft one in series below it takes the friction's damping
    share: the wheel mode no longer grows alone (the relative velocity is smaller)."""
    law = r.ContactLaw.from_hertz(HERTZ, 0.3)
    alone = r.linear_stability([TABLE1], law, OP).growth_rate_1_s
    stiff = r.counter_body(lateral=(20000.0, 0.01, 500.0))
    with_stiff = r.linear_stability([TABLE1], law, OP, body=stiff).modes[0].growth_rate_1_s
    assert with_stiff == pytest.approx(alone, rel=0.02)
    soft = r.counter_body(lateral=(200.0, 0.05, 0.5))
    with_soft = r.linear_stability([TABLE1], law, OP, body=soft).modes[0].growth_rate_1_s
    assert with_soft < alone


# -- the FE's components at the contact ------------------------------------------------------
def _axisym(design_name: str, etw: int, fmax_hz: float = 2500.0):
    import warnings

    import wheel_squeal as ws
    from fem.axisym import solve_axisymmetric
    from geometry.gmsh_mesh import mesh_profile

    wheel = ws.load_design(design_name).wheel
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return wheel, solve_axisymmetric(
            wheel, mesh_profile(wheel, elements_through_web=etw, order=2), curved=True, fmax_hz=fmax_hz
        )


def test_a_mirror_symmetric_wheel_has_no_mode_with_both_components():
    """Table 1's wheel is symmetric about its mid-plane: at the tread apex an axial mode
    has no radial motion and an in-plane mode no axial motion, so nothing couples
    through the normal contact at angle 0. The gmsh mesh is symmetric only to its
    meshing (it leaves the forbidden component at about 2e-6 of the other): parity sets
    it to exactly 0."""
    _, ms = _axisym("table1", 2, fmax_hz=4500.0)
    for m in ms.modes:
        t, n = m.contact_components
        assert t == 0.0 or n == 0.0, (m.label(), t, n)
    radial = [m for m in ms.modes if m.contact_components[1] > 0]
    assert radial and all(m.family != "axial" for m in radial)  # in-plane modes move it radially


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
    from wheel_squeal.mode_stability import eigenvalue_list, stability_table

    design = ws.load_design("table1")
    modes = ws.compute_modes(design, "fast")
    op = ws.operating_point(design, rpm=800, crabbing_velocity_m_s=0.39)
    contact = ws.contact_law(design)
    assert contact.normal_stiffness_n_m == pytest.approx(1.36e8, abs=0.005e8)
    table = stability_table(design, modes, contact, op)
    growing = [e for e in eigenvalue_list(table) if e["mechanism"]]
    assert growing and {e["mechanism"] for e in growing} == {"falling friction"}
    assert "(3,0) axial" in {e["participants"][0]["mode"] for e in growing}
    constant = stability_table(design, modes, ws.contact_law(design, friction_law="constant"), op)
    assert not any(row.stability.unstable for row in constant.rows)


# -- the time domain in two directions ------------------------------------------------------
def _envelope_rate(hist, period_s: float, after_s: float) -> float:
    """The growth rate [1/s] of the kinetic energy's peak per period (energy ~ e^{2 sigma t})."""
    coords = hist.coordinates
    ke = 0.5 * np.sum(coords.m * hist.v_modes**2, axis=1)
    n = int(round(period_s / (hist.t[1] - hist.t[0])))
    blocks = len(ke) // n
    t = np.array([hist.t[k * n + np.argmax(ke[k * n : (k + 1) * n])] for k in range(blocks)])
    peak = np.array([ke[k * n : (k + 1) * n].max() for k in range(blocks)])
    keep = t > after_s
    return float(np.polyfit(t[keep], np.log(peak[keep]), 1)[0] / 2)


def _static_start(modes, law, op, kick: float):
    """The static equilibrium under the steady creep force Q0 = -mu0 W (the mean normal
    force is W there: k_i y_i = a_i Q0) and a small rate on every coordinate [m/s]: a
    start that stays in the linear range while an instability grows."""
    mu0 = float(r.adhesion_ratio(op.creepage, law, op.rolling_speed_m_s))
    y0 = np.array([-mu0 * law.normal_load_n * md.lateral / md.stiffness_n_m for md in modes])
    return y0, np.full(len(modes), kick)


@pytest.mark.parametrize(
    "law, pair",
    [
        ("constant", ((1000.0, 1e-3, 0.5, 0.05), (1025.0, 1e-3, 0.5, -0.05))),  # mode coupling
        ("constant", ((1000.0, 1e-3, 0.5, 0.03), (1012.0, 1e-3, 0.5, -0.03))),  # mode coupling
        ("falling", ((1143.0, 9.4e-4, 1 / math.sqrt(3.1), 0.0),)),  # falling friction, Table 1
        ("falling", ((1143.0, 9.4e-4, 1 / math.sqrt(3.1), 0.04),)),  # falling, with a normal part
    ],
)
def test_the_time_domain_grows_at_the_linear_rate(law, pair):
    """Started at the static equilibrium with a tiny kick (the normal approach moves by
    under 0.2 % of delta0 from there: linear), the production RK4 run's kinetic energy envelope grows at
    twice the fastest eigenvalue's real part within 3 % (measured: 0.01 to 0.6 %, the
    fit over the periods after the other eigenvalue has died out)."""
    contact = r.ContactLaw.from_hertz(HERTZ, 0.3, friction_law=law)
    modes = [_mode(*m) for m in pair]
    linear = r.linear_stability(modes, contact, OP)
    fastest = linear.modes[linear.winner]
    hist = r.simulate(modes, contact, OP, 0.12, _static_start(modes, contact, OP, 5e-8))
    assert np.abs(hist.u_n - hist.u_n[0]).max() < 2e-3 * HERTZ.approach_m and not hist.separated.any()
    rate = _envelope_rate(hist, 1 / fastest.damped_frequency_hz, 0.03)
    assert rate == pytest.approx(fastest.growth_rate_1_s, rel=0.03)


def test_the_kernel_agrees_with_an_independent_integration():
    """A coupled pair from rest through growth, contact loss and saturation: the RK4
    kernel and solve_ivp's DOP853 on a separate right-hand side agree on the contact
    velocity within 1 % of its peak over the whole record (measured: 0.4 %; 14 % of the
    record has lost contact)."""
    contact = r.ContactLaw.from_hertz(HERTZ, 0.3, friction_law="constant")
    modes = [_mode(1000.0, 1e-3, 0.5, 0.05), _mode(1025.0, 1e-3, 0.5, -0.05)]
    rk4 = r.simulate(modes, contact, OP, 0.12)
    ref = r.simulate_reference(modes, contact, OP, 0.12)
    assert rk4.separated.any() and ref.separated.any()
    v = np.interp(ref.t, rk4.t, rk4.v)
    assert np.abs(v - ref.v).max() < 0.01 * np.abs(ref.v).max()


def test_the_power_balance_closes_with_the_hertz_spring():
    """From rest (the creep force's step), with normal motion and the nonlinear Hertz
    spring: the run passes the kernel's own energy check (the energy of the modes and
    the Hertz spring changes by the integral of Q v minus the damping: measured 1.5e-5
    of the largest energy), and the record's trapezoidal balance closes to 1e-3 of it
    (measured: 6e-4; the creep force turns sharply where the contact sticks and slips,
    which the trapezoidal integral of the stored power follows only to that order)."""
    contact = r.ContactLaw.from_hertz(HERTZ, 0.3)
    modes = [_mode(1143.0, 9.4e-4, 0.57, 0.03), _mode(1600.0, 1e-3, 0.4, -0.04)]
    hist = r.simulate(modes, contact, OP, 0.05)
    c = hist.coordinates
    d = hist.u_n - static_normal_approach_m(modes, contact, OP)  # the mean normal force is W
    x = np.maximum(1.0 + d / HERTZ.approach_m, 0.0)
    hertz = 1000.0 * (0.4 * HERTZ.approach_m * (x**2.5 - 1.0) - d)
    energy = 0.5 * np.sum(c.m * hist.v_modes**2 + c.k * hist.y_modes**2, axis=1) + hertz
    work = np.concatenate([[0.0], np.cumsum(0.5 * (hist.P[1:] + hist.P[:-1]) * np.diff(hist.t))])
    assert np.abs(energy - energy[0] - work).max() < 1e-3 * np.abs(energy).max()
    assert hist.energy_mismatch_j < 1e-3 * np.abs(energy).max()


def test_separation_is_reported_and_carries_no_force():
    contact = r.ContactLaw.from_hertz(HERTZ, 0.3, friction_law="constant")
    modes = [_mode(1000.0, 1e-3, 0.5, 0.05), _mode(1025.0, 1e-3, 0.5, -0.05)]
    hist = r.simulate(modes, contact, OP, 0.12)  # from rest: large
    assert hist.separated.any()
    assert np.all(hist.N[hist.separated] == 0.0)
    assert np.all(hist.Q[hist.separated] == 0.0)
    d = hist.u_n - static_normal_approach_m(modes, contact, OP)
    assert np.all(d[hist.separated] <= -HERTZ.approach_m)


def test_transient_creep_in_the_time_domain_grows_at_the_lagged_linear_rate():
    """The Table 1 mode with the creep force lagging by a / V0: the RK4 run's growth is
    the lagged linear rate within 3 % (measured: 0.05 %), and the independent
    integration agrees within 1 % of the peak velocity (measured: 0.5 %)."""
    contact = r.ContactLaw.from_hertz(HERTZ, 0.3, relaxation_length_m=HERTZ.semi_axis_a_m)
    linear = r.linear_stability([TABLE1], contact, OP).modes[0]
    hist = r.simulate([TABLE1], contact, OP, 0.15, _static_start([TABLE1], contact, OP, 1e-6))
    rate = _envelope_rate(hist, 1 / linear.damped_frequency_hz, 0.02)
    assert rate == pytest.approx(linear.growth_rate_1_s, rel=0.03)
    ref = r.simulate_reference([TABLE1], contact, OP, 0.15, _static_start([TABLE1], contact, OP, 1e-6))
    assert np.abs(np.interp(ref.t, hist.t, hist.v) - ref.v).max() < 0.01 * np.abs(ref.v).max()


@pytest.mark.parametrize("relaxation", [False, True], ids=["steady creep", "transient creep"])
def test_the_largest_growth_rate_from_the_eigenvalues_alone_is_linear_stability_s(relaxation):
    """``largest_growth_rate`` (eigenvalues only, for the verdict's rigid-rail comparison)
    is the fastest eigenvalue of ``linear_stability`` to round-off (1e-9 relative: the same
    matrix, LAPACK's eigenvalues with and without vectors), with a counter-body mode in
    series, a coupled pair and the Table 1 mode; and with transient creep, whose lag's own
    eigenvalue both leave out."""
    law = r.ContactLaw.from_hertz(HERTZ, 0.3, relaxation_length_m=HERTZ.semi_axis_a_m if relaxation else 0.0)
    modes = [_mode(1000.0, 1e-3, *PAIR[0]), _mode(1025.0, 1e-3, *PAIR[1]), r.ModalDOF(3.1, 7.0e8, 42.0)]
    body = r.BodyModel.from_modes([(r.NORMAL, 2500.0, 0.01, 7.0)], "a roller mode")
    for b in (None, body):
        full = r.linear_stability(modes, law, OP, body=b).eigenvalues.real.max()
        assert r.largest_growth_rate(modes, law, OP, body=b) == pytest.approx(full, rel=1e-9, abs=1e-9)
        assert full > 0  # a growing system: the comparison is not of two decays
