"""Curving kinematics and the pass-by geometry against direct calculations."""

from __future__ import annotations

import math

import numpy as np
import pytest

import wheel_squeal as ws
from acoustics.passby import HALF_TRACK_M, PassbySource, passby, passby_pressure
from track.curving import WHEELS, check_curve


def test_curves_beyond_what_a_bogie_runs_are_refused_with_the_limit():
    """A rigid bogie's leading axle reaches psi = 2a / R: beyond 50 mrad (R < 50 m for 2.5 m)
    the request is refused naming the tightest radius; a speed beyond 400 km/h and an
    unbalanced acceleration beyond 3 m/s^2 too; cant lowers the unbalanced acceleration
    (150 mm at 80 km/h on 150 m: 3.29 - 0.98 = 2.31 m/s^2, accepted)."""
    check_curve(50.0, 40.0, 2.5)
    with pytest.raises(ValueError, match="R >= 50 m"):
        check_curve(49.0, 40.0, 2.5)
    with pytest.raises(ValueError, match="wheelbase"):
        check_curve(150.0, 40.0, 0.1)
    with pytest.raises(ValueError, match="radius"):
        check_curve(-5.0, 40.0, 2.5)
    with pytest.raises(ValueError, match="faster than any train"):
        check_curve(5000.0, 450.0, 2.5)
    with pytest.raises(ValueError, match="unbalanced"):
        check_curve(150.0, 80.0, 2.5)
    check_curve(150.0, 80.0, 2.5, cant_mm=150.0)
    assert len(WHEELS) == 4


ANGLES = np.linspace(0.0, math.pi, 181)


def _source(across: float, height: float = 0.46, f: float = 500.0, n: int = 0, d: np.ndarray | None = None):
    return PassbySource(0.0, across, height, f, np.ones(181) if d is None else d, ANGLES, n)


def test_the_closest_approach_of_a_monopole_is_spherical_spreading():
    """A source with |D| = 1 Pa m passes 6.75 m away horizontally and 0.74 m below the
    microphone: L_pmax is |D| / r_min / sqrt(2) (rms) to 1e-6 dB (the time grid samples
    the closest approach), and the SEL is the integral of 1 / (2 r(t)^2) over the
    pass-by's span X = 20 distances each way, atan(X / r_min) / (V r_min) in closed form
    (the infinite pass-by's pi / (2 V r_min) is 2.9 % more): within 0.1 % (the sum over
    the time grid)."""
    r_min = math.hypot(7.5 - HALF_TRACK_M, 1.2 - 0.46)
    res = passby([_source(HALF_TRACK_M)], 10.0)
    assert res.lpmax_db == pytest.approx(20 * math.log10(1 / r_min / math.sqrt(2) / 20e-6), abs=1e-6)
    exposure = math.atan(20 * 7.5 / r_min) / (10.0 * r_min) / (20e-6) ** 2
    assert 10 ** (res.sel_db / 10) == pytest.approx(exposure, rel=1e-3)


def test_a_rigid_ground_adds_six_decibels_where_the_paths_coincide():
    """Source and microphone on a rigid ground: the image's path is the direct one, the
    pressures add in phase: +6.02 dB; a ground at 0.5 m with |Q| = 1 lies between
    -inf and +6 dB and the free field (Q = 0) is unchanged."""
    free = passby([_source(HALF_TRACK_M, 0.0)], 10.0, height_m=0.0, ground_depth_m=0.0)
    rigid = passby([_source(HALF_TRACK_M, 0.0)], 10.0, height_m=0.0, ground_depth_m=0.0, reflection=1.0)
    assert rigid.lpmax_db - free.lpmax_db == pytest.approx(20 * math.log10(2), abs=1e-9)
    some = passby([_source(HALF_TRACK_M)], 10.0, reflection=1.0)
    assert some.lpmax_db <= passby([_source(HALF_TRACK_M)], 10.0).lpmax_db + 6.03


def test_the_directivity_is_read_at_the_angle_from_the_axle():
    """A wheel radiating only along its axis (|D| = cos(theta)) towards the microphone's
    side: at closest approach theta is the angle between the axle and the line to the
    microphone; on the far rail it faces away (theta -> pi - theta, |D| the same for a
    symmetric pattern), and the incoherent sum of two equal wheels is 3 dB up."""
    d = np.abs(np.cos(ANGLES))
    near = passby([_source(HALF_TRACK_M, d=d)], 10.0)
    dy, dz = 7.5 - HALF_TRACK_M, 1.2 - 0.46
    r = math.hypot(dy, dz)
    assert near.lpmax_db == pytest.approx(20 * math.log10((dy / r) / r / math.sqrt(2) / 20e-6), abs=0.01)
    two = passby([_source(HALF_TRACK_M), _source(HALF_TRACK_M)], 10.0)
    assert two.lpmax_db - passby([_source(HALF_TRACK_M)], 10.0).lpmax_db == pytest.approx(
        10 * math.log10(2), abs=1e-9
    )
    assert passby([_source(HALF_TRACK_M, n=3)], 10.0).lpmax_db == pytest.approx(
        passby([_source(HALF_TRACK_M)], 10.0).lpmax_db - 10 * math.log10(2), abs=1e-9
    )  # cos(n phi) averaged over phi: half the mean square


def test_the_passby_signal_has_the_passby_level_and_the_doppler_shift():
    """A 500 Hz monopole passing at 30 m/s: the synthesised pressure's mean square over
    20 ms at the closest approach of its sound (the pass-by's peak, retarded by r_min/c)
    is the pass-by's largest mean square within 1 % (the window's 10 periods hold the
    level's curvature); 2 s before, its zero crossings give the Doppler frequency
    f / (1 - V cos(beta) / c) at the emission time within 0.2 % (cos(beta) the
    approaching component of the direction to the microphone)."""
    from acoustics.medium import AIR

    c, speed, f = AIR.sound_speed_m_s, 30.0, 500.0
    src = _source(HALF_TRACK_M, f=f)
    rate = 48000.0
    t, p = passby_pressure([src], speed, 8.0, rate)
    ref = passby([src], speed)
    dy, dz = 7.5 - HALF_TRACK_M, 1.2 - 0.46
    r_min = math.hypot(dy, dz)
    window = np.abs(t - r_min / c) <= 0.01
    assert np.mean(p[window] ** 2) == pytest.approx(ref.mean_square_pa2.max(), rel=0.01)
    late = (t > -2.05) & (t < -1.95)
    x = p[late]
    crossings = np.nonzero((x[:-1] < 0) & (x[1:] >= 0))[0]
    exact = t[late][crossings] - x[crossings] / (x[crossings + 1] - x[crossings]) / rate
    measured = (len(exact) - 1) / (exact[-1] - exact[0])
    t_e = -2.0 - 62.0 / c  # emission time for this reception, iterated once by hand below
    for _ in range(5):
        along = speed * t_e
        t_e = -2.0 - math.sqrt(along**2 + r_min**2) / c
    along = speed * t_e
    cos_beta = -along / math.sqrt(along**2 + r_min**2)
    assert measured == pytest.approx(f / (1 - speed * cos_beta / c), rel=2e-3)


def test_two_wheels_of_one_tone_sound_as_loud_as_their_levels_say():
    """The two wheels of an axle squealing at one tone, 1.5 m apart: the signal's largest
    mean square over 20 ms is the pass-by's largest (their energy sum) within 5 % (the
    window, and the two arrivals' retarded times differing by a few ms), not up to twice
    it as a sum in phase would be."""
    speed, f = 30.0, 500.0
    near = _source(HALF_TRACK_M, f=f)
    far = PassbySource(0.0, -HALF_TRACK_M, 0.46, f, np.ones(181), ANGLES, 0)
    t, p = passby_pressure([near, far], speed, 8.0, 48000.0)
    ref = passby([near, far], speed)
    window = int(0.02 * 48000.0)
    running = np.convolve(p**2, np.ones(window) / window, mode="valid")
    assert running.max() == pytest.approx(ref.mean_square_pa2.max(), rel=0.05)


def test_band_maxima_sum_the_tones_of_each_band():
    """Two equal tones in one third-octave band are 3 dB above either alone; a band with
    no tone is -inf; A-weighting applies each tone's own weight."""
    a, b, other = (
        _source(HALF_TRACK_M, f=490.0),
        _source(HALF_TRACK_M, f=510.0),
        _source(HALF_TRACK_M, f=2000.0),
    )
    res = passby([a, b, other], 10.0)
    one = passby([a], 10.0)
    bands = res.band_maxima_db([500.0, 1000.0, 2000.0])
    assert bands[0] == pytest.approx(one.lpmax_db + 10 * math.log10(2), abs=1e-3)
    assert bands[1] == -math.inf
    assert bands[2] == pytest.approx(one.lpmax_db, abs=1e-3)
    weighted = passby([PassbySource(0.0, HALF_TRACK_M, 0.46, 500.0, np.ones(181), ANGLES, 0, -3.2)], 10.0)
    assert weighted.band_maxima_db([500.0], a_weighted=True)[0] == pytest.approx(one.lpmax_db - 3.2, abs=1e-3)


@pytest.mark.slow  # railway_920's FE modes, the test track's fits and 4 radii (about 40 s cold)
def test_the_railway_wheel_squeals_in_tight_curves_at_its_tread_and_its_flange_root(tmp_path):
    """railway_920 on the test track at 40 km/h in its bogie ([vehicle]), touching with
    S1002: the leading inner wheel squeals at its tread by falling friction at R = 150 and
    300 m and not at 600 and 1000 m (lateral creepage 1.6e-3 and 8e-4 there, below the creep
    curve's falling branch; the field's threshold near 4.5e-3 and its "rarely above 300 m");
    the leading outer wheel runs on two points, its flange root and its 70 deg flank, at 150
    and 300 m (and squeals at the root) and off its flange at 600 and 1000 m, quiet; the
    trailing axle, nearly radial, never squeals."""
    import json

    from conftest import run_here

    r = run_here(
        "curve",
        "--design",
        "railway_920_track",
        "--radius",
        "150,300,600,1000",
        "--train-speed",
        "40",
        "--quiet",
        "--out",
        tmp_path / "c",
    )
    assert r.returncode == 0, r.stderr
    cases = json.loads((tmp_path / "c" / "summary.json").read_text())["cases"]
    assert len(cases) == 16
    by = {(c["radius_m"], c["axle"], c["rail"]): c for c in cases}
    inner = [by[(radius, "leading", "inner")] for radius in (150.0, 300.0, 600.0, 1000.0)]
    assert [c["squeals"] for c in inner] == [True, True, False, False]
    assert all(c["mechanism"] == "falling friction" and not c["flange_contact"] for c in inner[:2])
    outer = [by[(radius, "leading", "outer")] for radius in (150.0, 300.0, 600.0, 1000.0)]
    assert [c["flange_contact"] for c in outer] == [True, True, False, False]
    assert all(c["flange_angle_deg"] > 65.0 and c["squeals"] for c in outer[:2])
    assert not any(c["squeals"] for c in outer[2:])
    assert "flanging noise" in outer[0]["amplitude_note"]
    assert not any(c["squeals"] for c in cases if c["axle"] == "trailing")
    # the loads: the outer wheels carry more (the cant deficiency's transfer)
    assert by[(150.0, "leading", "outer")]["wheel_load_n"] > by[(150.0, "leading", "inner")]["wheel_load_n"]
    assert (tmp_path / "c" / "curve.csv").read_text().startswith("radius_m,train_speed_km_h,axle,rail")
    # the levels: each squealing wheel's own pass-by, the bogie's at least the loudest
    # wheel's and at most their sum (the wheels' peaks come at different times)
    for radius in (150.0, 300.0):
        wheels = [c for c in cases if c["radius_m"] == radius and c["axle"] == "leading"]
        own = [c["passby_lpamax_dba"] for c in wheels]
        bogie = wheels[0]["bogie_lpamax_dba"]
        assert max(own) <= bogie <= 10 * math.log10(sum(10 ** (x / 10) for x in own)) + 1e-9
        assert 0 < wheels[0]["amplitude_m_s"] < 1.2 * wheels[0]["crabbing_velocity_m_s"]
        assert wheels[0]["amplitude_method"] == "harmonic balance" and wheels[0]["harmonic_distortion"] < 0.1
    summary = json.loads((tmp_path / "c" / "summary.json").read_text())
    assert "at a tread up to R = 300 m and not from 600 m" in summary["findings"][0]
    assert summary["wheel_profile"] == "S1002"
    import xarray as xr

    with xr.open_dataset(tmp_path / "c" / "curve.nc") as ds:
        assert ds["passby_lpamax_dba"].attrs["units"] == "dB(A) re 20 uPa"
        assert int(ds["squeals"].sel(radius_m=150.0, train_speed_km_h=40.0, wheel="leading inner")) == 1
        assert ds["contact_angle_deg"].attrs["units"] == "deg"
    for name in ("occurrence.png", "lpamax.png", "passby.wav", "report.html"):
        assert (tmp_path / "c" / name).stat().st_size > 1000, name


@pytest.mark.slow  # railway_920's modes (cached by the test above) and one curve (about 5 s)
def test_the_leading_outer_wheel_flanges_and_is_not_the_leading_inner_one():
    """150 m at 40 km/h: the leading outer wheel has a flange contact (over 45 deg) beside its
    tread; the two wheels' verdicts differ (tone, growth, contact force) and the flange
    contact's own verdict is another mode family than the inner wheel's."""
    cases = ws.curve(
        ws.load_design("railway_920_track"), [150.0], [40.0], context=ws.RunContext.of("balanced")
    )
    inner, outer = cases[0], cases[1]
    assert outer.wheel.flange_contact and math.degrees(outer.wheel.main.contact_angle_rad) > 45.0
    assert not inner.wheel.flange_contact
    vi, vo = inner.analysis.verdict, outer.analysis.verdict
    assert vi.to_dict() != vo.to_dict()
    assert abs(vi.get("tone_hz") / vo.get("tone_hz") - 1.0) > 0.01
    flange = outer.analyses[outer.contacts.index(outer.wheel.main)].verdict
    assert flange.get("mode") != vi.get("mode") and "radial" in (flange.get("mode") or "")


@pytest.mark.slow  # the fast preset's modes and the rail's fits (about 6 s cold)
def test_a_curve_case_reads_as_the_api_documents_it():
    """A case's repr is a line, not its meshes; its analysis's verdict carries the amplitude
    the case reports; its record makes curve.nc's dataset without further attributes."""
    from wheel_squeal.present.curve_files import curve_dataset

    cases = ws.curve(ws.load_design("railway_920_track"), [150.0], [40.0], context=ws.RunContext.of("fast"))
    lead = cases[0]
    with pytest.raises(ValueError, match="analyses for"):  # not aligned with the contacts: refused
        type(lead)(lead.radius_m, lead.train_speed_km_h, lead.wheel, lead.analyses * 2)
    text = repr(lead)
    assert text.startswith("CurveCase(") and len(text) < 400 and "\n" not in text, text
    v = lead.analysis.verdict
    record = lead.to_record()
    assert v.squeals and v.amplitude_m_s == pytest.approx(record["amplitude_m_s"], rel=1e-12)
    ds = curve_dataset([c.to_record() for c in cases])
    assert ds["squeals"].shape == (1, 1, 4)
    assert int(ds["squeals"].sum()) == sum(c.analysis.verdict.squeals for c in cases)


@pytest.mark.slow  # the fast preset's modes and the rail's fits, one curve (about 6 s cold)
def test_a_curve_request_solves_each_contact_s_stability_once(monkeypatch):
    """The pricing reads the analysis's own table of each sliding contact: one stability
    solve per contact analysed (a second solve for the price would count twice as many at
    the sliding ones), and the same verdicts as a request whose analysis solves its own."""
    import wheel_squeal.chain as chain
    import wheel_squeal.mode_stability as stability

    solves = []
    real = stability.stability_table

    def counted(*args, **kwargs):
        solves.append(args[3])  # the operating point
        return real(*args, **kwargs)

    monkeypatch.setattr(stability, "stability_table", counted)
    monkeypatch.setattr(chain, "stability_table", counted)
    design = ws.load_design("railway_920_track")
    ctx = ws.RunContext.of("fast")
    cases = ws.curve(design, [150.0], [40.0], context=ctx)
    contacts = sum(len(c.contacts) for c in cases)
    sliding = sum(1 for c in cases for a in c.analyses if a.operating_point.crabbing_velocity_m_s != 0.0)
    assert sliding > 0 and len(solves) == contacts
    priced = ws.curve(design, [150.0], [40.0], context=ctx, priced=True)  # a line's: no pricing
    assert [c.to_record() for c in priced] == [c.to_record() for c in cases]
