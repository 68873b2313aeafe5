"""The track: the rail on supports against closed forms, its fit by a passive rational
function without feedthrough, and the roots of the wheel on the fitted rail against the
roots of the characteristic equation with the rail model's own receptance."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import DESIGNS, run_here, table1_law

import reduced as r
from track import (
    TEST_TRACK_LATERAL,
    TEST_TRACK_VERTICAL,
    UIC60_LATERAL,
    UIC60_VERTICAL,
    BeamSection,
    continuous_receptance,
    pinned_pinned_frequency_hz,
    receptance,
)
from track.fit import fit_receptance

#: The pad alone as a continuous support [N/m^2]: 300 MN/m per 0.6 m, loss factor 0.25
PAD_ONLY = 300e6 * (1 + 0.25j) / 0.6


def test_the_timoshenko_rail_meets_its_closed_form_on_a_continuous_support():
    """The finite model (Timoshenko elements, absorbing ends) against the infinite
    beam's closed form: within 3 % up to 4 kHz (the elements' dispersion error grows
    with frequency: 0.2 % at 1 kHz, 2 % at 4 kHz, measured)."""
    f = np.array([50.0, 300.0, 1000.0, 2000.0, 4000.0])
    fe = receptance(UIC60_VERTICAL, None, f, continuous_stiffness_n_m2=PAD_ONLY)
    exact = continuous_receptance(UIC60_VERTICAL, PAD_ONLY, f)
    np.testing.assert_allclose(fe, exact, rtol=0.03)


def test_the_euler_bernoulli_limit_meets_its_closed_form():
    """With the shear stiffness made huge the elements are Euler-Bernoulli's; the closed
    form -(1 + i) / (4 EI lambda^3) of the beam without shear or rotatory inertia is met
    within 3 % to 1 kHz (the rotatory inertia the model keeps: 2 % there)."""
    eb = BeamSection(210e9, 1e16, 7850.0, 76.7e-4, 3038.3e-8, 0.4, 0.01)
    f = np.array([50.0, 200.0, 500.0, 1000.0])
    fe = receptance(eb, None, f, continuous_stiffness_n_m2=PAD_ONLY)
    np.testing.assert_allclose(fe, continuous_receptance(eb, PAD_ONLY, f, timoshenko=False), rtol=0.03)
    q = eb.mass_per_length * (2 * math.pi * 50.0) ** 2 - PAD_ONLY
    lam = next(x for x in np.roots([1, 0, 0, 0, -q / eb.bending_stiffness]) if x.real > 0 and x.imag < 0)
    closed = -(1 + 1j) / (4 * eb.bending_stiffness * lam**3)
    assert continuous_receptance(eb, PAD_ONLY, [50.0], timoshenko=False)[0] == pytest.approx(closed, rel=1e-9)


@pytest.mark.parametrize("at", [0.0, 0.5])
def test_discrete_supports_meet_the_continuous_one_at_low_frequency(at):
    """Far below the pinned-pinned frequency the sleepers act as a continuous support of
    their dynamic stiffness per metre: within 5 % at 20-80 Hz (measured 2 % at a sleeper,
    3 % at midspan)."""
    s = TEST_TRACK_VERTICAL
    f = np.array([20.0, 40.0, 80.0])
    discrete = receptance(UIC60_VERTICAL, s, f, at)
    smeared = [
        continuous_receptance(UIC60_VERTICAL, s.stiffness_n_m(2 * math.pi * x) / s.spacing_m, [x])[0]
        for x in f
    ]
    np.testing.assert_allclose(discrete, smeared, rtol=0.05)


@pytest.mark.parametrize(
    "beam, support", [(UIC60_VERTICAL, TEST_TRACK_VERTICAL), (UIC60_LATERAL, TEST_TRACK_LATERAL)]
)
def test_the_midspan_peak_is_the_pinned_pinned_frequency(beam, support):
    """The midspan receptance peaks where a simply supported bay of Timoshenko beam
    resonates (1068 Hz vertically, 555 Hz laterally for UIC60 at 0.6 m), within 1 %."""
    f_pp = pinned_pinned_frequency_hz(beam, support.spacing_m)
    f = np.linspace(0.85 * f_pp, 1.15 * f_pp, 301)
    peak = f[np.argmax(np.abs(receptance(beam, support, f, 0.5)))]
    assert peak == pytest.approx(f_pp, rel=0.01)
    assert 1000 < pinned_pinned_frequency_hz(UIC60_VERTICAL, 0.6) < 1150  # a UIC60 rail's, published ~1 kHz


def test_the_receptance_is_passive_and_of_the_published_size():
    """Im(alpha) <= 0 everywhere (exp(+i w t)); laterally about 1e-8 m/N near 300 Hz
    and 1e-9 m/N near 1 kHz for a ballasted UIC60 track (within a factor 2)."""
    f = np.geomspace(20, 5000, 200)
    for beam, support in ((UIC60_VERTICAL, TEST_TRACK_VERTICAL), (UIC60_LATERAL, TEST_TRACK_LATERAL)):
        for at in (0.0, 0.5):
            assert (receptance(beam, support, f, at).imag <= 0).all()
    lateral = np.abs(receptance(UIC60_LATERAL, TEST_TRACK_LATERAL, [300.0, 1000.0], 0.5))
    assert 0.5e-8 < lateral[0] < 2e-8 and 0.5e-9 < lateral[1] < 2e-9


def _exact_root(s, g, wheel, alpha, tol=1e-10):
    """The root of 1 + g s (H_wheel(s) + alpha(s)) = 0 nearest ``s`` by Newton's method
    (``wheel``: (m, c, k) per mode, each seen laterally at the contact), None where it
    does not converge."""

    def d(x):
        return 1 + g * x * (sum(1 / (m * x * x + c * x + k) for m, c, k in wheel) + alpha(x))

    for _ in range(60):
        h = 1e-6 * abs(s)
        slope = (d(s + h) - d(s - h)) / (2 * h)
        if slope == 0 or not np.isfinite(slope):
            return None
        step = d(s) / slope
        s = s - step
        if abs(step) < tol * abs(s):
            return s
    return None


def _rail_alpha(beam, support, at=0.5):
    return lambda s: receptance(beam, support, [s / (2j * math.pi)], at, complex_frequency=True)[0]


#: A root of the fitted rail matches the rail model's own within 1 % in frequency and 5 %
#: in growth; a growth near zero, where a relative tolerance means nothing, within a
#: damping ratio of 0.001 (the issue's misfit was 0.003)
ROOT_FREQUENCY, ROOT_GROWTH, ROOT_DAMPING = 0.01, 0.05, 0.001


def _matches(fit_root, exact_root) -> bool:
    w = abs(exact_root.imag)
    return (
        abs(fit_root.imag - exact_root.imag) <= ROOT_FREQUENCY * w
        and abs(fit_root.real - exact_root.real) <= ROOT_GROWTH * abs(exact_root.real) + ROOT_DAMPING * w
    )


def test_the_fit_is_stable_passive_and_without_feedthrough():
    """Both directions of the test track at midspan fitted over 2-8000 Hz: every pole in
    the left half-plane, Im(alpha) <= 0 from a decade below to a decade above the band
    (passive), the leading coefficients summing to zero (no feedthrough: the counter-body
    model takes it), and the error in the weights' norm under 2 % (measured 0.97 % and
    0.28 %). Where the weights are small (below 50 Hz, and above 1 kHz where the rail's
    receptance is small beside a wheel mode's) the relative error is larger: what it does
    to the contact is checked by the roots below, not by a bound on it here. No pole
    repeats another (relocation clamps several to the slowest allowed: kept once, or
    the counter-body's state space holds a repeated eigenvalue no force reaches)."""
    f = np.geomspace(2, 8000, 391)
    for direction, (beam, support) in enumerate(
        ((UIC60_VERTICAL, TEST_TRACK_VERTICAL), (UIC60_LATERAL, TEST_TRACK_LATERAL))
    ):
        alpha = receptance(beam, support, f, 0.5)
        fit = fit_receptance(f, alpha)
        assert (fit.poles.real < 0).all()
        gaps = np.abs(fit.poles[:, None] - fit.poles[None, :]) + np.diag(np.full(len(fit.poles), np.inf))
        assert gaps.min() > 1e-6 * np.abs(fit.poles).min()
        grid = np.geomspace(0.2, 80000, 4000)
        assert (fit(grid).imag <= 0).all()
        body = r.BodyModel.from_rational([(direction, fit.poles, fit.residues)])  # no feedthrough, or refused
        s = 2j * math.pi * f
        assert np.allclose(body.receptance(s, direction), fit(f), rtol=1e-9)
        assert fit.weighted_error < 0.02


def test_a_wheel_mode_on_the_rail_grows_at_the_frequency_domain_root():
    """The Table 1 mode on the lateral test track at midspan (constant normal load): the
    eigenvalue of the linear model with the rail's fitted state space is the root of
    1 + g s (H_wheel(s) + alpha_fit(s)) = 0 to 1e-9 (the two forms agree), and the root
    with the rail's own receptance (the finite model at complex frequency) within 1 % in
    frequency and 5 % in growth."""
    law, op = table1_law(), r.OperatingPoint.from_rpm(800, 0.213, 0.39)
    m, k, c = 3.1, 1.6e8, 42.0
    f = np.geomspace(2, 8000, 391)
    fit = fit_receptance(f, receptance(UIC60_LATERAL, TEST_TRACK_LATERAL, f, 0.5))
    body = r.BodyModel.from_rational([(r.LATERAL, fit.poles, fit.residues)], "the rail")
    result = r.linear_stability([r.ModalDOF(m, k, c)], law, op, body=body)
    lam = result.eigenvalues[int(np.argmax(result.eigenvalues.real))]
    g = result.friction_damping_ns_m
    fitted = _exact_root(lam, g, [(m, c, k)], lambda x: complex(fit(x / (2j * math.pi))[0]))
    assert fitted == pytest.approx(lam, rel=1e-9)
    exact = _exact_root(lam, g, [(m, c, k)], _rail_alpha(UIC60_LATERAL, TEST_TRACK_LATERAL))
    assert exact is not None and _matches(lam, exact), (lam, exact)


@pytest.mark.slow  # the shipped wheel's modes, the rail's fits and some 40 Newton solves (about 4 s)
# an eigenvector found by inverse iteration at an exactly singular shift is the method's own:
# no warning reaches the user (it did, four times in this test)
@pytest.mark.filterwarnings("error::scipy.linalg.LinAlgWarning")
def test_every_root_the_contact_reaches_matches_the_rail_models_own():
    """railway_920_track at 300 m and 30 km/h, constant normal load (the contact's
    steepest falling friction on this track, g = -29.4 kN s/m): every growing root of the
    wheel's 31 modes with the fitted rail, and of the rail alone under a rigid wheel, is
    a root of the characteristic equation with the rail model's own receptance, within 1 %
    in frequency and 5 % in growth (a damping ratio of 0.001 near zero); Newton's method
    from starts over the right half-plane finds no growing exact root the fit misses; and
    the fit has no lightly damped term below the band the contact destabilises (no growing
    root below 20 Hz)."""
    import wheel_squeal as ws
    from wheel_squeal.mode_stability import body_of, excitable, mode_dofs

    design = ws.load_design("railway_920_track").replace(normal_contact="constant")
    modes = ws.compute_modes(design, "balanced")
    contact = ws.contact_law(design)
    op = r.OperatingPoint(8.333044, 0.069443)  # the 300 m, 30 km/h
    dofs = mode_dofs(excitable(modes, contact), design)
    body = body_of(design)
    alpha = _rail_alpha(UIC60_LATERAL, TEST_TRACK_LATERAL)
    for wheel in (dofs, []):
        result = r.linear_stability(wheel, contact, op, body=body) if wheel else None
        if wheel:
            lam = result.eigenvalues
        else:
            lam = r.linear_stability([r.ModalDOF(1e9, 1e20, 0.0)], contact, op, body=body).eigenvalues
        g = r.friction_damping_ns_m(contact, op)
        # a mode's lateral receptance at the contact: its participation squared over its
        # modal impedance (the normal load constant, its normal motion feeds nothing back)
        mck = [
            (d.mass_kg / d.lateral**2, d.damping_ns_m / d.lateral**2, d.stiffness_n_m / d.lateral**2)
            for d in wheel
        ]
        # in the fit's band: the rigid wheel's stand-in (a 50 kHz mode) is no root to check
        growing = [x for x in lam if x.real > 0 and 0 < x.imag < 2 * math.pi * 8000]
        assert all(x.imag / (2 * math.pi) > 20 for x in growing), growing
        for x in growing:
            exact = _exact_root(x, g, mck, alpha)
            assert exact is not None and _matches(x, exact), (x, exact)
        if wheel:  # no growing exact root away from the fit's: Newton from starts near each band
            for f0 in (60, 150, 220, 260, 320, 450, 600, 900):
                for sigma in (50.0, 200.0, 400.0):
                    exact = _exact_root(complex(sigma, 2 * math.pi * f0), g, mck, alpha)
                    if exact is None or exact.real <= 0 or exact.imag <= 0:
                        continue
                    assert any(_matches(x, exact) for x in growing), exact


# -- the track as a counter-body of a design -------------------------------------------------
def test_the_test_track_design_loads_and_its_position_is_checked(tmp_path):
    import wheel_squeal as ws

    d = ws.load_design("railway_920_track")
    assert d.counter_body.KIND == "track" and d.counter_body.position_fraction() == 0.5
    assert d.counter_body.contact_radii() == (math.inf, 0.3)
    text = (
        (DESIGNS / "railway_920_track.toml").read_text().replace('position = "midspan"', 'position = "1.5"')
    )
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    result = run_here("track", "--design", bad, "--out", tmp_path / "x")
    assert (
        result.returncode == 2
        and "position" in result.stderr
        and len(result.stderr.strip().splitlines()) == 1
    )


@pytest.mark.slow  # the fits of both directions and the grid: about 3 s
def test_the_track_command_writes_the_receptances(tmp_path):
    result = run_here(
        "track", "--design", "railway_920_track", "--points", "40", "--quiet", "--out", tmp_path / "t"
    )
    assert result.returncode == 0, result.stderr
    rows = (tmp_path / "t" / "receptance.csv").read_text().splitlines()
    assert rows[0].startswith("frequency_hz,vertical_support_re,vertical_support_im") and len(rows) == 41
    summary = json.loads((tmp_path / "t" / "summary.json").read_text())
    assert "exp(+i omega t)" in summary["convention"]
    assert summary["pinned_pinned_vertical_hz"] == pytest.approx(1067.9, abs=0.5)
    assert (tmp_path / "t" / "receptance.png").stat().st_size > 20_000
    assert "pinned-pinned: 1068 Hz vertical, 555 Hz lateral" in result.stdout
    refused = run_here("track", "--design", "table1", "--out", tmp_path / "r")
    assert refused.returncode == 2 and "not a track" in refused.stderr


@pytest.mark.slow  # the test track's fits and a time domain with its 52 terms (about 15 s)
def test_stability_and_simulate_on_the_track_agree_and_report_the_rail(tmp_path):
    """The Table 1 mode (a modal model) on the test track: `stability` and `simulate` give
    the same linear growth rate (the one chain), the record's growth matches it, the
    verdict says what the rail adds, timeseries.csv carries the rail's velocity and
    summary.json its share of the slip velocity and the power into it."""
    model = tmp_path / "mode.toml"
    model.write_text(
        "[[mode]]\nfrequency_hz = 1143.4\ndamping_ratio = 9.4e-4\nlateral = 0.568\nnormal = 0.0\n"
    )
    common = ("--design", "railway_920_track", "--modal-model", model, "--quiet")
    stab = run_here("stability", *common, "--out", tmp_path / "s")
    sim = run_here("simulate", *common, "--out", tmp_path / "m")
    assert stab.returncode == 0 and sim.returncode == 0, (stab.stderr, sim.stderr)
    vs = json.loads((tmp_path / "s" / "summary.json").read_text())["verdict"]
    vm = json.loads((tmp_path / "m" / "summary.json").read_text())
    assert vs["growth_rate_1_s"] == pytest.approx(vm["verdict"]["growth_rate_1_s"], rel=1e-12)
    assert "the rail" in vs["reason"] and vs["counter_body_effect_1_s"] is not None
    motion = vm["counter_body_motion"]
    assert 0 < motion["counter_body_velocity_share"] < 1 and motion["counter_body_velocity_rms_m_s"] > 0
    header, *rows = (tmp_path / "m" / "timeseries.csv").read_text().splitlines()
    rail = [float(r.split(",")[-1]) for r in rows[-200:]]
    assert header.endswith(",v_counter_body_m_s") and max(abs(x) for x in rail) > 0
