"""The track: the rail on supports against closed forms, its fit by passive modal terms,
and a wheel mode on the rail against the root of the frequency-domain characteristic
equation."""

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
from track.fit import fit_receptance, level

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


def test_the_fit_is_passive_and_close_over_the_band():
    """Every term a positive mass, spring and damper (so the fit is passive); its rms
    error over the band within 25 % of the receptance's level (the hysteretic supports
    are not exactly causal, and the fit cannot follow the sharpest band edges: measured
    13-20 %)."""
    f = np.geomspace(20, 6000, 300)
    for beam, support in ((UIC60_VERTICAL, TEST_TRACK_VERTICAL), (UIC60_LATERAL, TEST_TRACK_LATERAL)):
        alpha = receptance(beam, support, f, 0.5)
        fit = fit_receptance(f, alpha)
        assert (fit.modal_mass_kg > 0).all() and (fit.damping_ratio > 0).all()
        assert (fit(f).imag <= 0).all()
        error = np.abs(fit(f) - alpha) / level(f, alpha)
        assert np.sqrt(np.mean(error**2)) < 0.25
        assert fit.poles < 40


def test_a_wheel_mode_on_the_rail_grows_at_the_frequency_domain_root():
    """The Table 1 mode on the lateral test track at midspan (constant normal load): the
    eigenvalue of the squeal model with the rail's fitted terms is the root of
    1 + g s (H_wheel(s) + alpha_fit(s)) = 0 to 1e-9, and the rail's effect on the growth
    rate (the difference from the rigid roller's) is the one the exact receptance gives
    (the finite model at the complex root) within 10 % (the fit's error there: 3 %)."""
    law, op = table1_law(), r.OperatingPoint.from_rpm(800, 0.213, 0.39)
    m, k, c = 3.1, 1.6e8, 42.0
    f = np.geomspace(20, 6000, 300)
    fit = fit_receptance(f, receptance(UIC60_LATERAL, TEST_TRACK_LATERAL, f, 0.5))
    rail = r.ModalCounterBody((), tuple(zip(fit.frequency_hz, fit.damping_ratio, fit.modal_mass_kg))).dofs()
    result = r.linear_stability([r.ModalDOF(m, k, c), *rail], law, op)
    lam = result.eigenvalues[int(np.argmax(result.eigenvalues.real))]
    rigid = r.linear_stability([r.ModalDOF(m, k, c)], law, op).eigenvalues
    rigid = rigid[int(np.argmax(rigid.real))]
    g = result.friction_damping_ns_m

    def root(alpha, s):
        def d(x):
            return 1 + g * x * (1 / (m * x * x + c * x + k) + alpha(x))

        for _ in range(50):
            h = 1e-6 * abs(s)
            step = d(s) / ((d(s + h) - d(s - h)) / (2 * h))
            s -= step
            if abs(step) < 1e-12 * abs(s):
                break
        return s

    fitted = root(lambda s: fit(s / (2j * math.pi)), lam)
    assert fitted == pytest.approx(lam, rel=1e-9)
    exact = root(
        lambda s: receptance(
            UIC60_LATERAL, TEST_TRACK_LATERAL, [s / (2j * math.pi)], 0.5, complex_frequency=True
        )[0],
        lam,
    )
    assert lam.imag == pytest.approx(exact.imag, rel=1e-6)
    assert lam.real - rigid.real == pytest.approx(exact.real - rigid.real, rel=0.1)


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
