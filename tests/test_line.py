"""A railway line for the noise-mapping tools: its CSV and traffic read with one-line
errors, the emission's convention against the pass-by it comes from, and the line command's
files."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import one_line_error, run_cli

from acoustics.emission import (
    CNOSSOS_OCTAVES_HZ,
    band_emission_power,
    cnossos_curve_correction_db,
    exposure_from_emission,
    line_emission_db,
)
from acoustics.medium import AIR
from acoustics.passby import PassbySource, passby
from track.alignment import count_rows
from wheel_squeal.line import LineSpec, load_line, load_line_spec
from wheel_squeal.runtime.request_errors import RequestError

ANGLES = np.linspace(0.0, math.pi, 361)
HEADER = "id,radius_m,length_m,cant_mm,train_speed_km_h"


def test_the_emission_of_a_dipole_passby_gives_its_exposure_back_at_any_distance():
    """A source radiating along its axle, |D| = |cos theta| Pa m (a horizontal dipole across
    the track: CNOSSOS-EU's rolling source's pattern), on the track's centre line at the
    microphone's height: the emission found from its pass-by at 7.5 m is its intensity
    toward the perpendicular, 4 pi |D|^2 / (2 rho c), within 1 % (the dipole's 0.01 floor
    and the pass-by's finite span of 20 distances each way), and it gives back the exposure
    at 25 m within 0.1 dB."""
    src = PassbySource(0.0, 1e-9, 1.2, 500.0, np.abs(np.cos(ANGLES)), ANGLES, 0)
    speed = 20.0
    near = passby([src], speed, distance_m=7.5, samples=20001)
    power = band_emission_power(near, speed, 7.5)
    expected = 4 * math.pi / (2 * AIR.density_kg_m3 * AIR.sound_speed_m_s)
    assert power.octaves[CNOSSOS_OCTAVES_HZ.index(500.0)] == pytest.approx(expected, rel=0.01)
    far = passby([src], speed, distance_m=25.0, samples=20001)
    assert exposure_from_emission(float(power.octaves.sum()), speed, 25.0) == pytest.approx(
        far.sel_db, abs=0.1
    )


def test_a_line_source_of_one_watt_bogie_an_hour():
    """L_W' = 10 lg(p Q W / (3600 V) / 1 pW): 1 W, 1 bogie an hour at 10 m/s, always: 74.4 dB;
    squealing half the time: 3.0 dB less; nothing emitted: -inf."""
    full = line_emission_db(np.array([1.0, 0.0]), 1.0, 1.0, 10.0)
    assert full[0] == pytest.approx(10 * math.log10(1 / 36000 / 1e-12), abs=1e-9)
    assert line_emission_db(np.array([1.0]), 0.5, 1.0, 10.0)[0] == pytest.approx(full[0] - 10 * math.log10(2))
    assert full[1] == -math.inf


def test_cnossos_gives_curves_its_flat_correction():
    assert [cnossos_curve_correction_db(r) for r in (100.0, 299.0, 300.0, 499.0, 500.0, 3000.0)] == [
        8.0,
        8.0,
        5.0,
        5.0,
        0.0,
        0.0,
    ]


def test_the_friction_states_share_the_time():
    """Four coefficients equally, a modifier 30 % of the time: eight states whose shares add
    to 1, the modifier's (a flat creep curve) 0.3 of it."""
    states = LineSpec(modifier_share=0.3).states()
    assert len(states) == 8 and sum(s for _, _, s in states) == pytest.approx(1.0, abs=1e-12)
    assert sum(s for _, law, s in states if law == "constant") == pytest.approx(0.3, abs=1e-12)
    with pytest.raises(RequestError, match="friction_weight"):
        load_line_spec({"friction_weight": [1.0]}, "t.toml")
    with pytest.raises(RequestError, match="a share of the time"):
        LineSpec(modifier_share=1.5)


def test_the_radius_grid_rounds_each_curve_to_its_nearest_point():
    """A step of 10 %: 100 m stays, 104 m goes to 100, 106 m to 110, 3000 m to 100 * 1.1^36
    (3091 m, within half a step); a step of 0 leaves every radius its own; 0.8 is refused."""
    spec = LineSpec(radius_step=0.1)
    assert [spec.grid_radius_m(r) for r in (100.0, 104.0, 106.0)] == [100.0, 100.0, 110.0]
    assert spec.grid_radius_m(3000.0) == pytest.approx(100.0 * 1.1**36, rel=1e-6)
    assert LineSpec().grid_radius_m(123.4) == 123.4
    with pytest.raises(RequestError, match="radius_step"):
        LineSpec(radius_step=0.8)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("id,radius_m\nc,100\n", "missing length_m"),
        (f"{HEADER},colour\nc,100,10,0,40,red\n", "'colour'"),
        (f"{HEADER}\nc,100,10,0,40\nc,200,10,0,40\n", "not unique"),
        (f"{HEADER}\nc,abc,10,0,40\n", "radius_m = 'abc'"),
        (f"{HEADER},wkt\nc,100,10,0,40,POINT (1 2)\n", "LINESTRING"),
        (f"{HEADER}\n", "no curve"),
    ],
)
def test_a_bad_line_is_one_line(tmp_path, text, message):
    path = tmp_path / "line.csv"
    path.write_text(text)
    with pytest.raises(RequestError, match=message) as err:
        load_line(path)
    assert "\n" not in str(err.value)


def test_a_line_keeps_its_coordinates_and_is_counted_unread(tmp_path):
    path = tmp_path / "line.csv"
    wkt = '"LINESTRING (100 0, 150 20, 200 60)"'  # quoted: a CSV field with commas
    path.write_text(f"{HEADER},x0,y0,x1,y1,wkt\na,150,100,0,40,0,0,100,0,\nb,300,100,0,40,,,,,{wkt}\n")
    a, b = load_line(path)
    assert a.coordinates == ((0.0, 0.0), (100.0, 0.0)) and len(b.coordinates) == 3
    assert count_rows(path) == 2


def test_a_line_too_long_is_refused_before_it_is_read(tmp_path):
    """A million curves (16 MB): refused with the estimate, before parsing (how fast:
    benchmarks/bench_safety.py; the timeout only ends a hang)."""
    path = tmp_path / "long.csv"
    path.write_text(HEADER + "\n" + "c,150,100,0,40\n" * 1_000_000)
    r = run_cli(
        "line", "--design", "railway_920_track", "--line", path, "--out", tmp_path / "out", timeout=120
    )
    assert r.returncode == 2
    line = one_line_error(r)
    assert "1,000,000 curves" in line and "would take" in line
    assert not (tmp_path / "out").exists()


def test_the_issue_s_line_is_priced_within_the_default_budget_on_this_machine():
    """2,000 curves in four friction states on two local processes: estimated under the
    default half hour (measured: 500 curves in about a minute, ``benchmarks/bench_line.py``,
    which prints the estimate beside the time), at half the one process's time; on a
    cluster only its results' memory is priced, as a study's."""
    from wheel_squeal.plan import line_plan
    from wheel_squeal.runtime.budget import Budget

    two, one = line_plan(2000, 4, 2), line_plan(2000, 4, 1)
    assert two.seconds < Budget().max_seconds
    two.check(Budget(), "the line", "")  # not refused
    fixed = line_plan(0, 4, 1).seconds
    assert two.seconds - fixed == pytest.approx(0.5 * (one.seconds - fixed))
    assert line_plan(10**7, 4, None).seconds == fixed


@pytest.mark.slow  # railway_920's modes and four curves in four friction states (about 60 s cold)
def test_a_line_writes_what_the_mapping_tools_read(tmp_path):
    """Four curves with coordinates: the tight one squeals some of the time, the 2000 m one
    never (no emission, no level); line.geojson opens with GeoPandas in the CRS given, its
    properties line.csv's; the emission gives the pass-by's SEL back at the ISO 3095
    position (0.01 dB: the same exposure); line.nc holds the bands per period."""
    import geopandas as gpd
    import xarray as xr

    path = tmp_path / "line.csv"
    path.write_text(
        f"{HEADER},x0,y0,x1,y1\n"
        "tight,150,200,0,40,0,0,150,130\nmid,300,300,0,40,150,130,400,300\n"
        "wide,2000,500,0,40,400,300,900,300\nwider,3000,500,0,40,900,300,1400,300\n"
    )
    out = tmp_path / "out"
    r = run_cli(
        "line",
        "--design",
        "railway_920_track",
        "--line",
        path,
        "--crs",
        "EPSG:25832",
        "--quiet",
        "--out",
        out,
    )
    assert r.returncode == 0, r.stderr
    rows = {row["id"]: row for row in gpd.read_file(out / "line.geojson").to_dict("records")}
    assert gpd.read_file(out / "line.geojson").crs.to_epsg() == 25832
    assert rows["tight"]["squeal_probability"] > 0
    assert rows["wide"]["squeal_probability"] == 0 and rows["wider"]["squeal_probability"] == 0
    assert rows["wide"]["bogie_lpamax_dba"] is None or math.isnan(rows["wide"]["bogie_lpamax_dba"])
    assert rows["tight"]["cnossos_correction_db"] == 8.0
    assert rows["tight"]["sel_from_emission_dba"] == pytest.approx(rows["tight"]["bogie_sel_dba"], abs=0.01)
    with xr.open_dataset(out / "line.nc") as ds:
        assert ds["lw_m_db"].dims == ("curve", "period", "octave_hz")
        day, night = (float(ds["laeq_dba"].sel(curve="tight", period=p)) for p in ("day", "night"))
        assert day - night == pytest.approx(10 * math.log10(6.0 / 1.0), abs=0.01)  # 6 against 1 train/h
    summary = json.loads((out / "summary.json").read_text())
    assert summary["curves"] == 4
    for name in ("line.csv", "line.png", "report.html"):
        assert (out / name).stat().st_size > 200, name


@pytest.mark.slow  # railway_920's modes in a new cache, then two curves in two states (~40 s)
def test_a_line_on_local_processes_gives_the_same_numbers_and_resumes(tmp_path, monkeypatch):
    """Two curves in two friction states: on two local processes the same numbers as in
    this process; each task kept in the cache, so that the line run again computes nothing
    (every task from the earlier run: a task that ran again would fail here)."""
    import wheel_squeal as ws
    import wheel_squeal.line as line_module
    from wheel_squeal.line import LineSpec, line, load_line
    from wheel_squeal.runtime.stage_cache import StageCache

    path = tmp_path / "line.csv"
    path.write_text(f"{HEADER}\ntight,150,200,0,40\nwide,2000,500,0,40\n")
    curves = load_line(path)
    design = ws.load_design("railway_920_track")
    spec = LineSpec(friction_coefficients=(0.3, 0.5), friction_weights=(1.0, 1.0))
    cache = StageCache(tmp_path / "cache")
    ctx = ws.RunContext.of("balanced", cache=cache)
    pool = line(design, curves, spec, context=ctx, workers=2)
    import shutil

    shutil.rmtree(cache.root / "study")  # the tasks forgotten, the modes kept
    here = line(design, curves, spec, context=ws.RunContext.of("balanced", cache=cache), workers=1)

    def ran_again(*args, **kwargs):
        raise AssertionError("a stored task ran again")

    monkeypatch.setattr(line_module, "run_line_job", ran_again)
    again = line(design, curves, spec, context=ctx, workers=2)
    for a, b, c in zip(here, pool, again):
        assert a.emission.probability == b.emission.probability == c.emission.probability
        assert a.emission.laeq_dba == b.emission.laeq_dba == c.emission.laeq_dba
        assert np.array_equal(a.emission.thirds_db["day"], b.emission.thirds_db["day"])
    assert here[0].emission.probability > 0 and here[1].emission.probability == 0
