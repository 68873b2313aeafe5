"""Hertz contact, Kalker C22 and the creep law (Eq. 3, 6) of the reduced model."""

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import reduced as r

TABLE1 = dict(
    R1=0.213, R1t=0.300, R2=0.085, R2t=0.040, youngs_modulus=175e9, poissons_ratio=0.28, normal_load=1000.0
)
V0_800 = 800 * 2 * math.pi / 60 * 0.213


@pytest.fixture(scope="module")
def hertz():
    return r.hertz_contact(**TABLE1)


@pytest.fixture(scope="module")
def law(hertz):
    return r.ContactLaw.from_hertz(hertz, friction_coefficient=0.3)


def test_hertz_table1_semi_axes(hertz):
    # Table 1 quotes 3 significant figures: 0.853 mm and 0.594 mm -> half a unit in
    # the last digit is 0.06 % and 0.08 %; allow 0.1 %.
    assert hertz.semi_axis_a_m == pytest.approx(0.853e-3, rel=1e-3)
    assert hertz.semi_axis_b_m == pytest.approx(0.594e-3, rel=1e-3)
    assert hertz.a_over_b == pytest.approx(1.44, abs=0.01)
    assert hertz.orientation == "major axis along rolling" and hertz.orientation_angle_rad == 0.0
    # load balance: p0 = 3W/(2 pi a b), mean = W/(pi a b)
    assert hertz.max_pressure_pa * hertz.area_m2 * 2 / 3 == pytest.approx(1000.0, rel=1e-12)
    assert hertz.mean_pressure_pa == pytest.approx(hertz.max_pressure_pa * 2 / 3, rel=1e-12)


def test_hertz_sphere_matches_closed_form():
    # two equal spheres R: relative radius R/2, a = (3 W (R/2) / (4 E*))^(1/3), E* = E/2(1-nu^2)
    R, E, nu, W = 0.1, 200e9, 0.3, 100.0
    h = r.hertz_contact(R, R, R, R, E, nu, W)
    a_exact = (3 * W * (R / 2) / (4 * E / (2 * (1 - nu**2)))) ** (1 / 3)
    assert h.semi_axis_a_m == pytest.approx(a_exact, rel=1e-12)
    assert h.semi_axis_b_m == pytest.approx(a_exact, rel=1e-12)


def test_hertz_swapping_directions_swaps_axes(hertz):
    # exchanging rolling and transverse radii must exchange a and b and rotate the ellipse
    s = r.hertz_contact(
        TABLE1["R1t"],
        TABLE1["R1"],
        TABLE1["R2t"],
        TABLE1["R2"],
        TABLE1["youngs_modulus"],
        TABLE1["poissons_ratio"],
        TABLE1["normal_load"],
    )
    assert s.semi_axis_a_m == pytest.approx(hertz.semi_axis_b_m, rel=1e-10)
    assert s.semi_axis_b_m == pytest.approx(hertz.semi_axis_a_m, rel=1e-10)
    assert s.orientation == "major axis across rolling"
    # and the elliptic-integral solution scales like W^(1/3)
    h8 = r.hertz_contact(**{**TABLE1, "normal_load": 8000.0})
    assert h8.semi_axis_a_m == pytest.approx(2 * hertz.semi_axis_a_m, rel=1e-9)


def test_hertz_rejects_bad_input():
    with pytest.raises(ValueError, match="normal_load"):
        r.hertz_contact(**{**TABLE1, "normal_load": -1.0})
    with pytest.raises(ValueError, match="R2t"):
        r.hertz_contact(**{**TABLE1, "R2t": 0.0})


def test_kalker_c22_table_points_and_table1(hertz):
    assert r.kalker_c22(1.0, 0.25) == pytest.approx(3.67)  # circle, nu = 0.25
    assert r.kalker_c22(1 / 0.5, 0.5) == pytest.approx(5.56)  # b/a = 0.5 (a along rolling longer)
    assert r.kalker_c22(0.5, 0.0) == pytest.approx(2.88)  # a/b = 0.5
    c = r.kalker_c22(hertz.a_over_b, 0.28)
    # Kalker's table: about 4.3 for a/b = 1.44 at nu = 0.28 (docs/validation.md); bilinear
    # interpolation gives 4.27
    assert 4.2 < c < 4.35
    # reading the wrong side of the table (b/a instead of a/b) gives about 3.3: axes matter
    assert r.kalker_c22(1 / hertz.a_over_b, 0.28) < 3.4
    law_k = r.ContactLaw.from_hertz(hertz, c22="kalker")
    assert law_k.c22 == pytest.approx(c)
    with pytest.raises(ValueError):
        r.kalker_c22(20.0, 0.28)


def test_saturation_creepage_table1(law):
    # Table 1 (docs/validation.md): z' = 3 at creepage 0.0083 for Table 1 at mu 0.3 (quoted to 2 s.f.)
    assert law.saturation_creepage == pytest.approx(0.0083, abs=5e-5)
    assert law.normalised_creepage_per_creepage * law.saturation_creepage == pytest.approx(3.0)


def test_creep_curve_finite_odd_at_special_points(law):
    z = np.array([-1.0, -0.022, -1e-300, 0.0, 1e-300, 0.022, 1.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mu = r.adhesion_ratio(z, law, V0_800)
        slope = r.adhesion_ratio_slope(z, law, V0_800)
        f0 = r.falling_friction_factor(0.0, law)
    assert np.all(np.isfinite(mu)) and np.all(np.isfinite(slope))
    assert mu[3] == 0.0 and f0 == 1.0
    np.testing.assert_array_equal(mu, -mu[::-1])
    # |zeta| = 1 at 800 RPM: full sliding at 17.8 m/s, F = 1 - e^(-0.138/17.8)/2 - e^(-6.9/17.8)/2
    s = V0_800
    expected = 0.3 * (1 - 0.5 * math.exp(-0.138 / s) - 0.5 * math.exp(-6.9 / s))
    assert mu[-1] == pytest.approx(expected, rel=1e-12)
    # slope at the origin: mu_s * G a b C22 / (mu_0 W)
    assert slope[3] == pytest.approx(0.3 * law.normalised_creepage_per_creepage, rel=1e-12)


def test_creep_curve_continuous_and_c1_at_saturation(law):
    zs = law.saturation_creepage
    eps = 1e-10
    below, above = r.adhesion_ratio(np.array([zs * (1 - eps), zs * (1 + eps)]), law, V0_800)
    assert abs(above - below) < 1e-9
    d_below, d_above = r.adhesion_ratio_slope(np.array([zs * (1 - 1e-9), zs * (1 + 1e-9)]), law, V0_800)
    assert abs(d_above - d_below) < 1e-5 * abs(r.adhesion_ratio_slope(0.0, law, V0_800))


def test_slope_matches_finite_difference(law):
    z = np.array([-0.05, -0.01, -0.004, 0.001, 0.006, 0.0125, 0.022, 0.3])
    h = 1e-8
    fd = (r.adhesion_ratio(z + h, law, V0_800) - r.adhesion_ratio(z - h, law, V0_800)) / (2 * h)
    np.testing.assert_allclose(r.adhesion_ratio_slope(z, law, V0_800), fd, rtol=1e-5, atol=1e-6)


@settings(max_examples=200, deadline=None)
@given(zeta=st.floats(-10, 10, allow_nan=False), v0=st.floats(0.1, 100), mus=st.floats(0.05, 1.0))
def test_creep_law_odd_and_bounded_property(zeta, v0, mus):
    law = r.ContactLaw(1000.0, mus, mus, 68.36e9, 0.853e-3, 0.594e-3, 3.14)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mu = float(r.adhesion_ratio(zeta, law, v0))
        mu_neg = float(r.adhesion_ratio(-zeta, law, v0))
    assert mu == -mu_neg
    assert abs(mu) <= mus * (1 + 1e-15)
    assert mu * zeta >= 0.0  # friction opposes sliding


def test_contact_law_validation():
    with pytest.raises(ValueError, match="normal_load_n"):
        r.ContactLaw(0.0, 0.3, 0.3, 68e9, 1e-3, 1e-3)
    with pytest.raises(ValueError, match="c22"):
        r.ContactLaw(1000.0, 0.3, 0.3, 68e9, 1e-3, 1e-3, c22=float("nan"))


@pytest.mark.parametrize("delta", [1e-12, 1e-9, 1e-6, 1e-4, 1e-2])
def test_hertz_near_a_circle_is_continuous(delta):
    """Curvature sums a hair apart (a roller crown radius that nearly matches the
    wheel): the ellipse tends to the circle. For small eccentricity Hertz gives
    a/b = (B/A)^(2/3) (1 + O(delta^2)); the circle's radius is (3 W / 8 E* A)^(1/3)."""
    R1, R2, R1t = 0.213, 0.085, 0.3
    A = 0.5 * (1 / R1 + 1 / R2)
    B = A * (1 + delta)  # across rolling, slightly more curved
    R2t = 1 / (2 * B - 1 / R1t)
    h = r.hertz_contact(R1, R1t, R2, R2t, 175e9, 0.28, 1000.0)
    assert h.a_over_b == pytest.approx((1 + delta) ** (2 / 3), rel=max(delta**2, 1e-12) * 10 + 1e-12)
    e_star = 175e9 / (2 * (1 - 0.28**2))
    radius = (3 * 1000.0 / (8 * e_star * A)) ** (1 / 3)
    assert math.sqrt(h.semi_axis_a_m * h.semi_axis_b_m) == pytest.approx(radius, rel=2 * delta + 1e-12)


def test_own_numerical_kernels_match_scipy():
    """contact.numerics replaces two SciPy imports (half a second of start-up): the
    AGM elliptic integrals and Brent's root agree with scipy.special / scipy.optimize
    to round-off."""
    from scipy.optimize import brentq
    from scipy.special import ellipe, ellipk

    from contact.numerics import elliptic_ke, find_root

    ms = np.concatenate(
        [[0.0, 1e-300, 1e-16, 1e-8], np.linspace(0, 1, 201)[1:-1], 1 - np.logspace(-3, -12, 10)]
    )
    for m in ms:
        K, E = elliptic_ke(float(m))
        assert K == pytest.approx(ellipk(m), rel=3e-14) and E == pytest.approx(ellipe(m), rel=3e-14)
    for f, a, b in [
        (lambda x: x**3 - 2 * x - 5, 2, 3),
        (lambda x: math.cos(x) - x, 0, 1),
        (lambda x: (x - 0.3) ** 3, 0, 1),
        (lambda x: math.tanh(50 * (x - 0.123456789)), 0, 1),
    ]:
        assert find_root(f, a, b) == pytest.approx(
            brentq(f, a, b, xtol=1e-15, rtol=1e-14, maxiter=1000), rel=1e-13
        )
    with pytest.raises(ValueError, match="sign"):
        find_root(lambda x: x * x + 1, -1, 1)
