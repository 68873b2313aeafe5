"""Extremes of the reduced squeal model's operating and modal space.

Each test asserts finite, sensible, documented behaviour, or a clear error naming the
problem. Figures quoted as "measured" come from the runs below on the Table 1 contact
(W = 1000 N, mu = 0.3, C22 = 3.14) and mode (m = 3.1 kg, k = 1.6e8 N/m, c = 42 N s/m).
"""

import math
import warnings

import numpy as np
import pytest
from conftest import table1_law

import reduced as r
from reduced.model import MAX_STORED_SAMPLES, max_contact_damping_ns_m

MODE = r.ModalDOF(3.1, 1.6e8, 42.0)
V0_800 = 800 * 2 * math.pi / 60 * 0.213  # 17.84 m/s


def _strict(fn, *args, **kw):
    """Run fn with every warning raised as an error (no overflow/invalid/divide noise)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return fn(*args, **kw)


def _assert_finite(hist):
    for name in ("t", "y", "v", "creepage", "Q", "P"):
        assert np.all(np.isfinite(getattr(hist, name))), name


def _power_ratio(lc, n=50):
    """mean power per cycle over the last n cycles, relative to mean |Q v|."""
    c = lc.cycles
    return c.mean_power_w[-n:].mean() / c.mean_abs_qv_w[-n:].mean()


# --------------------------------------------------------------- crabbing velocity


def test_vc_zero_is_at_rest_and_finite(law):
    op = r.OperatingPoint(V0_800, 0.0)
    hist = _strict(r.simulate, MODE, law, op, 0.2)
    _assert_finite(hist)
    assert np.all(hist.v == 0.0) and np.all(hist.Q == 0.0)  # nothing excites the mode
    lc = r.limit_cycle(hist)
    assert not lc.squeal and not lc.saturated and lc.velocity_amplitude_m_s == 0.0
    assert math.isnan(lc.frequency_hz)
    pred = _strict(r.predict_limit_cycle, MODE, law, op)
    assert not pred.squeal and pred.initial_amplitude_m_s == 0.0
    assert pred.stable_amplitudes_m_s == () and pred.unstable_amplitudes_m_s == ()
    # creep region: the contact adds W/V0 mu_s K ~ 6.1e3 N s/m of damping
    assert lc.growth_rate_analytic_1_s == pytest.approx(
        -(42.0 + 1000.0 / V0_800 * 0.3 * law.normalised_creepage_per_creepage) / (2 * 3.1), rel=1e-12
    )


def test_vc_tiny_decays_to_round_off_and_mirrors(law):
    op = r.OperatingPoint(V0_800, 1e-9)
    hist = _strict(r.simulate, MODE, law, op, 0.1)
    _assert_finite(hist)
    lc = r.limit_cycle(hist)
    pred = r.predict_limit_cycle(MODE, law, op)
    assert not lc.squeal and not pred.squeal
    # the force step excites |Q(Vc)|/sqrt(km) = 2.7e-10 m/s, which decays at sigma = -991/s
    assert np.abs(hist.v).max() <= 1.01 * pred.initial_amplitude_m_s
    assert lc.envelope_growth_rate_1_s == pytest.approx(lc.growth_rate_analytic_1_s, rel=0.01)
    # after ~40 cycles the oscillation is below round-off and v stops crossing zero:
    # reported as died out (amplitude 0), not as the mean of the decaying cycles
    assert lc.velocity_amplitude_m_s == 0.0
    neg = _strict(r.simulate, MODE, law, r.OperatingPoint(V0_800, -1e-9), 0.1)
    np.testing.assert_array_equal(neg.v, -hist.v)


@pytest.mark.slow  # two records, two predictions and a sweep: 3.9-5.4 s measured
def test_vc_negative_mirrors_positive(law):
    hp = r.simulate(MODE, law, r.OperatingPoint(V0_800, 0.39), 0.6)
    hn = r.simulate(MODE, law, r.OperatingPoint(V0_800, -0.39), 0.6)
    # the creep law is exactly odd: the whole history is mirrored bit for bit
    np.testing.assert_array_equal(hn.v, -hp.v)
    np.testing.assert_array_equal(hn.Q, -hp.Q)
    np.testing.assert_array_equal(hn.P, hp.P)
    lp, ln = r.limit_cycle(hp), r.limit_cycle(hn)
    assert lp.saturated and ln.saturated
    # cycles start at upward zero crossings, half a period apart in the two runs
    assert ln.velocity_amplitude_m_s == pytest.approx(lp.velocity_amplitude_m_s, rel=1e-6)
    assert ln.frequency_hz == pytest.approx(lp.frequency_hz, rel=1e-6)
    pp = r.predict_limit_cycle(MODE, law, r.OperatingPoint(V0_800, 0.39))
    pn = r.predict_limit_cycle(MODE, law, r.OperatingPoint(V0_800, -0.39))
    assert pn.velocity_amplitude_m_s == pytest.approx(pp.velocity_amplitude_m_s, rel=1e-12)
    sw = r.sweep(MODE, law, [-0.39, 0.39], [V0_800], 0.6)
    assert sw.velocity_amplitude_m_s[0, 0] == pytest.approx(sw.velocity_amplitude_m_s[1, 0], rel=1e-6)


def test_vc_far_beyond_saturation_is_quiet(law):
    # Vc = 2 m/s: far into full sliding, the falling friction is too flat to beat c
    op = r.OperatingPoint(V0_800, 2.0)
    hist = _strict(r.simulate, MODE, law, op, 0.5)
    _assert_finite(hist)
    lc = r.limit_cycle(hist)
    pred = r.predict_limit_cycle(MODE, law, op)
    assert lc.growth_rate_analytic_1_s < 0  # measured -4.67 /s
    assert not lc.squeal and not lc.saturated
    assert not pred.squeal and pred.stable_amplitudes_m_s == ()  # no limit cycle at all
    # the step from rest excites 7.0 mm/s, which decays at the analytic rate
    assert lc.cycles.amplitude_m_s[0] == pytest.approx(pred.initial_amplitude_m_s, rel=0.05)
    assert lc.envelope_growth_rate_1_s == pytest.approx(lc.growth_rate_analytic_1_s, rel=0.01)
    assert lc.velocity_amplitude_m_s < 0.2 * pred.initial_amplitude_m_s
    assert np.all(np.abs(hist.Q) <= 0.3 * 1000.0)


def test_stability_boundary_near_0p63_is_not_a_limit_cycle(law):
    # beyond saturation W/V0 dmu/dzeta = W mu_s F'(Vc) does not depend on V0: the
    # equilibrium turns stable at Vc = 0.6295 m/s at every speed (subcritical above:
    # a stable and an unstable cycle up to Vc ~ 1.0-1.14 m/s, unreachable from rest).
    # Just either side the envelope moves by < 1 % in 50 cycles; it must be reported as
    # slow growth / decay, not as a limit cycle at the kick amplitude (~8 mm/s).
    for vc, growing in ((0.62, True), (0.635, False), (0.64, False)):
        op = r.OperatingPoint(V0_800, vc)
        lc = r.limit_cycle(r.simulate(MODE, law, op, 0.6))
        sigma = lc.growth_rate_analytic_1_s
        assert (sigma > 0) == growing and abs(sigma) < 0.25
        assert not lc.saturated and math.isnan(lc.time_to_saturation_s)
        assert lc.squeal == growing  # growing: squeal still building up; decaying: none
        assert lc.envelope_growth_rate_1_s == pytest.approx(sigma, rel=0.05)
        assert lc.velocity_amplitude_m_s < 0.02  # still near the 8 mm/s kick
        assert r.predict_limit_cycle(MODE, law, op).squeal == growing
    # the same boundary in rolling speed: identical sigma at 400 and 800 RPM
    s400 = r.largest_growth_rate(MODE, law, r.OperatingPoint(V0_800 / 2, 0.64))
    s800 = r.largest_growth_rate(MODE, law, r.OperatingPoint(V0_800, 0.64))
    assert s400 == pytest.approx(s800, rel=1e-9)


# ------------------------------------------------------------------- rolling speed


def test_rolling_speed_tiny_step_adapts(law):
    # V0 = 0.05 m/s: the creep region becomes a damper of W/V0 mu_s K ~ 2.2e6 N s/m.
    # The step is chosen from it (0.5/lambda, 7.1e-7 s instead of 1.8e-5 s).
    quiet = r.OperatingPoint(0.05, 0.001)
    h = r.choose_time_step(MODE, law, quiet)
    lam = max_contact_damping_ns_m(law, quiet) / 3.1 + 42.0 / 3.1
    assert h == pytest.approx(0.5 / lam, rel=1e-12) and h < 1e-6
    hq = _strict(r.simulate, MODE, law, quiet, 0.05)
    _assert_finite(hq)
    assert not r.limit_cycle(hq).squeal
    # creepage 1 (Vc = V0): full sliding on the falling branch, squeals; the
    # harmonic balance still holds (distortion 5 %): measured 0.0506 vs 0.0501 m/s
    op = r.OperatingPoint(0.05, 0.05)
    hist = _strict(r.simulate, MODE, law, op, 0.3, store_every=8)
    _assert_finite(hist)
    assert hist.energy_mismatch_j < 1e-3 * 0.5 * 3.1 * 0.05**2
    lc = r.limit_cycle(hist)
    pred = _strict(r.predict_limit_cycle, MODE, law, op)
    assert lc.squeal and lc.saturated and pred.squeal
    assert lc.velocity_amplitude_m_s == pytest.approx(pred.velocity_amplitude_m_s, rel=0.02)
    assert lc.frequency_hz == pytest.approx(MODE.frequency_hz, rel=0.01)


def test_rolling_speed_zero_is_a_clear_error(law):
    for bad in (0.0, -17.8, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="rolling_speed_m_s"):
            r.OperatingPoint(bad, 0.39)
    with pytest.raises(ValueError, match="rpm"):
        r.OperatingPoint.from_rpm(0.0, 0.213, 0.39)
    with pytest.raises(ValueError, match="rolling_speed_m_s"):
        r.OperatingPoint.from_angle_of_attack(0.0, 0.022)
    with pytest.raises(ValueError, match="rolling_speed_m_s"):
        r.sweep(MODE, law, [0.39], [V0_800, 0.0], 0.1)


# --------------------------------------------------------------------- normal load


def test_normal_load_tiny_and_large():
    ref = table1_law(1000.0)
    tiny, large = table1_law(1.0), table1_law(1e5)
    # Hertz: a, b ~ W^(1/3); K = G a b C22/(mu_0 W) ~ W^(-1/3): saturation creepage ~ W^(1/3)
    assert tiny.semi_axis_a_m == pytest.approx(ref.semi_axis_a_m / 10.0, rel=1e-9)
    assert large.semi_axis_b_m == pytest.approx(ref.semi_axis_b_m * 100 ** (1 / 3), rel=1e-9)
    assert tiny.saturation_creepage == pytest.approx(ref.saturation_creepage / 10.0, rel=1e-9)
    assert large.saturation_creepage == pytest.approx(0.0384, abs=1e-4)

    # 1 N: the falling friction's negative damping is at most W mu_s max|F'(s)| =
    # W mu_s 2 e^-2 (1/s1 + 1/s2) = 0.6 N s/m << c = 42 N s/m: no squeal at any Vc
    c_neg_max = 1.0 * 0.3 * 2 * math.exp(-2) * (1 / 0.138 + 1 / 6.9)
    assert c_neg_max < 0.7
    for vc in (0.1, 0.39, 0.6, 2.0):
        op = r.OperatingPoint(V0_800, vc)
        hist = _strict(r.simulate, MODE, tiny, op, 0.3)
        _assert_finite(hist)
        lc = r.limit_cycle(hist)
        assert not lc.squeal and not _strict(r.predict_limit_cycle, MODE, tiny, op).squeal
        assert lc.growth_rate_analytic_1_s <= -(42.0 - c_neg_max) / 6.2  # measured -6.69 /s at Vc 0.1

    # 1e5 N: Vc = 0.39 (creepage 0.022 < 0.038) sits in the creep region: strongly
    # damped; Vc = 0.6 (0.034, on the falling top of the curve) squeals. The step
    # from rest (0.81 m/s) overshoots the limit cycle, which is reached from above.
    op = r.OperatingPoint(V0_800, 0.39)
    lc = r.limit_cycle(_strict(r.simulate, MODE, large, op, 0.2))
    assert not lc.squeal and lc.growth_rate_analytic_1_s < -1000.0
    op = r.OperatingPoint(V0_800, 0.6)
    hist = _strict(r.simulate, MODE, large, op, 0.2)
    _assert_finite(hist)
    lc = r.limit_cycle(hist)
    pred = _strict(r.predict_limit_cycle, MODE, large, op)  # distortion 7 %: no warning
    assert lc.squeal and lc.saturated and pred.initial_amplitude_m_s > pred.velocity_amplitude_m_s
    assert lc.velocity_amplitude_m_s == pytest.approx(pred.velocity_amplitude_m_s, rel=0.02)  # 0.8 %
    assert abs(_power_ratio(lc)) < 0.02


# ------------------------------------------------------------------------- damping


def test_damping_zero_and_threshold_against_growth_rate(law):
    op = r.OperatingPoint(V0_800, 0.39)
    slope = float(r.adhesion_ratio_slope(op.creepage, law, op.rolling_speed_m_s))
    c_neg = -1000.0 / V0_800 * slope  # the friction's negative damping, 95.5 N s/m
    assert c_neg == pytest.approx(95.5, abs=0.1)
    # c = 0 is accepted: the largest amplitude (measured 0.3812 vs predictor 0.3812)
    hist = r.simulate(r.ModalDOF(3.1, 1.6e8, 0.0), law, op, 0.5)
    lc = r.limit_cycle(hist)
    pred = r.predict_limit_cycle(r.ModalDOF(3.1, 1.6e8, 0.0), law, op)
    assert lc.saturated and lc.velocity_amplitude_m_s == pytest.approx(pred.velocity_amplitude_m_s, rel=1e-3)
    assert abs(_power_ratio(lc)) < 0.02
    # 2 % either side of c_neg: the analytic growth rate changes sign, and so does
    # the fitted envelope; neither side is a limit cycle within 0.6 s
    for factor in (0.98, 1.02):
        mode = r.ModalDOF(3.1, 1.6e8, factor * c_neg)
        sigma = r.largest_growth_rate(mode, law, op)
        assert sigma == pytest.approx((c_neg - factor * c_neg) / 6.2, rel=1e-9)
        lc = r.limit_cycle(r.simulate(mode, law, op, 0.6))
        assert np.sign(lc.envelope_growth_rate_1_s) == np.sign(sigma)
        assert lc.envelope_growth_rate_1_s == pytest.approx(sigma, rel=0.05)
        assert not lc.saturated and lc.squeal == (sigma > 0)
        assert r.predict_limit_cycle(mode, law, op).squeal == (sigma > 0)


def test_damping_very_large_no_squeal(law):
    op = r.OperatingPoint(V0_800, 0.39)
    for c in (955.0, 1e5):  # 10 x c_neg; and overdamped (critical damping is 4.5e4 N s/m)
        mode = r.ModalDOF(3.1, 1.6e8, c)
        hist = _strict(r.simulate, mode, law, op, 0.3)
        _assert_finite(hist)
        lc = r.limit_cycle(hist)
        pred = r.predict_limit_cycle(mode, law, op)
        assert lc.growth_rate_analytic_1_s < 0 and not lc.squeal and not pred.squeal
        assert pred.stable_amplitudes_m_s == ()
        assert lc.velocity_amplitude_m_s < 1e-12  # decayed to round-off (1e-17) / never oscillated
        assert np.abs(hist.v[-len(hist.v) // 10 :]).max() < 1e-15
    # the underdamped one decays at the analytic rate (fit stops above the round-off floor)
    lc = r.limit_cycle(r.simulate(r.ModalDOF(3.1, 1.6e8, 955.0), law, op, 0.3))
    assert lc.envelope_growth_rate_1_s == pytest.approx(lc.growth_rate_analytic_1_s, rel=0.01)
    # c enters the step choice: c/m = 3.2e4 /s with the contact's 2.2e3 /s
    assert r.choose_time_step(r.ModalDOF(3.1, 1.6e8, 1e5), law, op) < r.choose_time_step(MODE, law, op)


# ------------------------------------------------------------- stiff / light modes


def test_very_stiff_mode_resolved_and_on_the_predicted_cycle(law):
    # k = 1e12 N/m: 90.4 kHz. The step follows the mode (48 steps per period, 2.3e-7 s);
    # the harmonic-balance amplitude does not depend on k, so the cycle is Table 1's.
    mode = r.ModalDOF(3.1, 1e12, 42.0)
    op = r.OperatingPoint(V0_800, 0.39)
    pred = _strict(r.predict_limit_cycle, mode, law, op)
    assert pred.velocity_amplitude_m_s == pytest.approx(
        r.predict_limit_cycle(MODE, law, op).velocity_amplitude_m_s, rel=1e-12
    )
    # from rest it takes ~1 s (8.7e6 steps) to grow: start on the cycle, run 900 periods
    hist = _strict(r.simulate, mode, law, op, 0.01, initial_state=(0.0, pred.velocity_amplitude_m_s))
    _assert_finite(hist)
    assert hist.step_s <= 1.0 / (48 * mode.frequency_hz) * (1 + 1e-9)
    emax = 0.5 * 3.1 * pred.velocity_amplitude_m_s**2
    assert hist.energy_mismatch_j < 1e-2 * emax  # measured 3e-3
    lc = r.limit_cycle(hist)
    assert lc.saturated and lc.frequency_hz == pytest.approx(mode.frequency_hz, rel=0.01)
    assert lc.velocity_amplitude_m_s == pytest.approx(pred.velocity_amplitude_m_s, rel=5e-3)  # 8e-4
    assert abs(_power_ratio(lc)) < 0.02


@pytest.mark.slow
def test_very_light_mode_matches_reference_and_predictor_warns(law):
    # m = 1e-4 kg (k = 1.6e8: 201 kHz). The contact's creep damping (~6e3 N s/m) is 24x
    # the mode's critical damping: the step comes from it (0.5/lambda = 7.4e-9 s), the
    # motion is far from harmonic (velocity amplitude 0.493 m/s > Vc, 169.5 kHz), and
    # the harmonic balance (0.367 m/s) is off by 25 %: it warns.
    mode = r.ModalDOF(1e-4, 1.6e8, 42.0)
    op = r.OperatingPoint(V0_800, 0.39)
    with pytest.warns(RuntimeWarning, match="harmonic-balance prediction unreliable"):
        r.predict_limit_cycle(mode, law, op)
    hist = r.simulate(mode, law, op, 5e-4, store_every=4)
    ref = r.simulate_reference(mode, law, op, 5e-4, samples_per_period=48)
    _assert_finite(hist)
    assert hist.step_s == pytest.approx(r.choose_time_step(mode, law, op), rel=1e-3)
    assert hist.step_s < 1e-8
    lc, lr = r.limit_cycle(hist), r.limit_cycle(ref)
    assert lc.saturated and lr.saturated
    assert lc.velocity_amplitude_m_s == pytest.approx(lr.velocity_amplitude_m_s, rel=0.01)  # 0.26 %
    assert lc.frequency_hz == pytest.approx(lr.frequency_hz, rel=1e-3)
    assert abs(_power_ratio(lc)) < 0.02
    # a run that would store more than MAX_STORED_SAMPLES is refused before integrating
    with pytest.raises(ValueError, match=r"store_every >= \d+"):
        r.simulate(mode, law, op, 0.2)
    n_steps = math.ceil(0.2 / r.choose_time_step(mode, law, op))
    assert n_steps > MAX_STORED_SAMPLES
    with pytest.raises(ValueError, match="MAX_SWEEP_STEPS"):
        r.sweep(mode, law, [0.39], [V0_800], 0.2)


def test_light_mode_at_squeal_frequency_sticks_to_the_roller(law):
    # m = 1e-4 kg at 1143 Hz (k = 5.2e3 N/m): the contact damps the mode 4000x over
    # critical. It does not oscillate at 1143 Hz: it sticks (creepage ~ 0, v ~ -Vc)
    # and loads its spring towards mu_s W / k = 58 mm (stick-slip, period ~ 0.15 s).
    mode = r.ModalDOF.from_frequency(1e-4, MODE.frequency_hz, 9.4e-4)
    op = r.OperatingPoint(V0_800, 0.39)
    with pytest.warns(RuntimeWarning, match="harmonic-balance"):
        r.predict_limit_cycle(mode, law, op)
    hist = _strict(r.simulate, mode, law, op, 2e-3, store_every=16)
    _assert_finite(hist)
    late = hist.t > 2e-4
    np.testing.assert_allclose(hist.v[late], -0.39, rtol=5e-3)  # creeps: measured 0.17 %
    assert np.all(np.abs(hist.creepage[late]) < law.saturation_creepage)
    assert not r.limit_cycle(hist).squeal  # no 1143 Hz squeal; the stick phase outlasts the run


# ------------------------------------------------------------------- long duration


def test_long_run_10s_no_drift(law):
    op = r.OperatingPoint(V0_800, 0.39)
    hist = r.simulate(MODE, law, op, 10.0)
    assert hist.energy_mismatch_j < 1e-4 * 0.5 * 3.1 * 0.39**2  # measured 2.5e-6 J
    lc = r.limit_cycle(hist)
    assert lc.saturated and lc.time_to_saturation_s < 0.5
    c = lc.cycles
    ratio = c.mean_power_w / c.mean_abs_qv_w

    def around(t, n=25):
        i = int(np.searchsorted(c.start_s, t))
        return slice(i - n, i + n)

    a2, a10 = c.amplitude_m_s[around(2.0)].mean(), c.amplitude_m_s[around(9.9)].mean()
    assert a10 == pytest.approx(a2, rel=1e-4)  # measured 1.2e-6
    f2, f10 = 1 / c.period_s[around(2.0)].mean(), 1 / c.period_s[around(9.9)].mean()
    assert f10 == pytest.approx(f2, rel=1e-6)
    # every cycle of the limit cycle balances its power (measured |P|/|Qv| < 2e-6)
    assert np.abs(ratio[c.start_s > 0.6]).max() < 1e-3
    pred = r.predict_limit_cycle(MODE, law, op)
    assert a10 == pytest.approx(pred.velocity_amplitude_m_s, rel=1e-3)  # measured 3e-5
