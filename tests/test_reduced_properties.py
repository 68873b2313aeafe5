"""Property-based invariants of the reduced squeal model.

* the creep law is odd, bounded by mu_s and opposes sliding over a wide parameter box,
  and the compiled kernel evaluates the same law;
* the time domain is exactly mirror-symmetric in Vc;
* the fitted envelope growth rate has the sign (and value) of the analytic rate;
* at a saturated limit cycle the mean power per cycle vanishes (energy balance), and
  the harmonic-balance predictor agrees with the time domain there.
Examples are few and runs short (deadline=None): the whole file takes a few seconds.
"""

import math
import warnings

import numpy as np
from hypothesis import HealthCheck, assume, given, settings, strategies as st

import reduced as r
from reduced import _kernels
from reduced.model import law_vector

TABLE1_LAW = r.ContactLaw.from_hertz(
    r.hertz_contact(0.213, 0.300, 0.085, 0.040, 175e9, 0.28, 1000.0), friction_coefficient=0.3
)


def _pos(lo, hi):
    """Log-uniform-ish positive floats in [lo, hi]."""
    return st.floats(math.log10(lo), math.log10(hi)).map(lambda e: 10.0**e)


creepage = st.one_of(
    st.floats(-10.0, 10.0), st.floats(-1e-6, 1e-6), _pos(1e-300, 1e-3), st.sampled_from([0.0, -0.0, 5e-324])
)

contact_laws = st.builds(
    r.ContactLaw,
    normal_load_n=_pos(1.0, 1e6),
    friction_coefficient=_pos(0.01, 1.5),
    stationary_friction_coefficient=_pos(0.01, 1.5),
    shear_modulus_pa=_pos(1e9, 2e11),
    semi_axis_a_m=_pos(1e-6, 0.1),
    semi_axis_b_m=_pos(1e-6, 0.1),
    c22=_pos(1.0, 20.0),
    friction=st.builds(
        r.FallingFriction, decay_speed_1_m_s=_pos(1e-3, 10.0), decay_speed_2_m_s=_pos(1e-3, 100.0)
    ),
)


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(zetas=st.lists(creepage, min_size=1, max_size=8), law=contact_laws, v0=_pos(1e-3, 300.0))
def test_creep_law_odd_bounded_and_opposing_sliding(zetas, law, v0):
    z = np.array(zetas)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mu = r.adhesion_ratio(z, law, v0)
        mu_neg = r.adhesion_ratio(-z, law, v0)
        slope = r.adhesion_ratio_slope(z, law, v0)
        slope_neg = r.adhesion_ratio_slope(-z, law, v0)
    assert np.all(np.isfinite(mu)) and np.all(np.isfinite(slope))
    np.testing.assert_array_equal(mu_neg, -mu)  # odd, bit for bit
    np.testing.assert_array_equal(slope_neg, slope)  # so the slope is even
    assert np.all(np.abs(mu) <= law.friction_coefficient)
    assert np.all(mu * z >= 0.0)  # friction opposes the sliding
    # the RK4 kernels evaluate the same law: Q(v) = -mu((Vc + v)/V0) W with Vc = 0
    lv = tuple(law_vector(law, r.OperatingPoint(v0, 0.0)).tolist())  # as simulate passes it
    for zi, mi in zip(z[:3], mu[:3]):
        q = _kernels.lateral_force(float(zi) * v0, lv)
        # (absolute: F(s) = 1 - e/2 - e/2 cancels when s >> s1, s2, amplifying round-off in s)
        assert math.isclose(
            q,
            -mi * law.normal_load_n,
            rel_tol=1e-12,
            abs_tol=1e-12 * law.friction_coefficient * law.normal_load_n,
        )


@settings(max_examples=10, deadline=None)
@given(vc=st.floats(0.0, 1.5), v0=st.floats(2.0, 30.0))
def test_time_domain_mirror_symmetric_in_vc(vc, v0):
    mode = r.ModalDOF(3.1, 1.6e8, 42.0)
    hp = r.simulate(mode, TABLE1_LAW, r.OperatingPoint(v0, vc), 0.02)
    hn = r.simulate(mode, TABLE1_LAW, r.OperatingPoint(v0, -vc), 0.02)
    np.testing.assert_array_equal(hn.v, -hp.v)
    np.testing.assert_array_equal(hn.P, hp.P)


@settings(max_examples=15, deadline=None)
@given(vc=st.floats(0.02, 1.2), v0=st.floats(6.0, 20.0), damping_ratio=st.floats(0.0, 3e-3))
def test_fitted_growth_rate_matches_analytic(vc, v0, damping_ratio):
    mode = r.ModalDOF.from_damping_ratio(3.1, 1.6e8, damping_ratio)
    op = r.OperatingPoint(v0, vc)
    sigma = r.largest_growth_rate(mode, TABLE1_LAW, op)
    assume(abs(sigma) > 3.0)  # resolvable within the run (|sigma| T > 0.9)
    # near the kink of the creep curve (saturation creepage zs) the linear regime ends
    # before the envelope reaches 30 % of its final value, where the fit stops, and the
    # fit underestimates sigma (by 9-35 % at creepage 0.94-1.3 zs): keep clear of it
    zs = TABLE1_LAW.saturation_creepage
    assume(not (0.5 * zs <= op.creepage <= 2.0 * zs))
    lc = r.limit_cycle(r.simulate(mode, TABLE1_LAW, op, 0.3))
    assert np.sign(lc.envelope_growth_rate_1_s) == np.sign(sigma)
    assert math.isclose(lc.envelope_growth_rate_1_s, sigma, rel_tol=0.05)
    if sigma < 0:
        assert not lc.squeal


@settings(max_examples=20, deadline=None)
@given(m=st.floats(2.0, 6.0), f=st.floats(900.0, 2000.0), vc=st.floats(0.2, 0.45), v0=st.floats(8.0, 18.0))
def test_energy_balance_and_predictor_at_the_limit_cycle(m, f, vc, v0):
    # box: heavy modes (distortion < 5 %, so harmonic balance holds) on the falling
    # branch (creepage >= 0.011, sigma > 0); the run length comes from the predictor
    mode = r.ModalDOF.from_frequency(m, f, 9.4e-4)
    op = r.OperatingPoint(v0, vc)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no harmonic-balance warning in this box
        pred = r.predict_limit_cycle(mode, TABLE1_LAW, op)
    sigma = pred.growth_rate_analytic_1_s
    assume(pred.squeal and sigma > 2.0)
    t_grow = math.log(pred.velocity_amplitude_m_s / pred.initial_amplitude_m_s) / sigma
    duration = min(3.0, 1.6 * t_grow + 100.0 / f)
    hist = r.simulate(mode, TABLE1_LAW, op, duration)
    emax = 0.5 * m * pred.velocity_amplitude_m_s**2
    assert hist.energy_mismatch_j < 1e-2 * emax
    lc = r.limit_cycle(hist)
    assert lc.saturated, (m, f, vc, v0, duration)
    c = lc.cycles
    # energy balance per cycle at the limit cycle: mean P within 2 % of mean |Q v|
    # (measured over 66 random cases of this box: < 8e-5)
    assert abs(c.mean_power_w[-50:].mean()) < 0.02 * c.mean_abs_qv_w[-50:].mean()
    assert np.all(np.abs(c.mean_power_w[-50:]) < 0.02 * c.mean_abs_qv_w[-50:])
    # the predictor agrees where the time domain saturates (acceptance 5 %; measured < 4e-4)
    assert math.isclose(lc.velocity_amplitude_m_s, pred.velocity_amplitude_m_s, rel_tol=0.01)
    assert math.isclose(lc.frequency_hz, mode.frequency_hz, rel_tol=0.01)
