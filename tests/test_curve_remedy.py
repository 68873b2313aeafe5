"""What stops squeal over a curve map, checked by running the map again, and the pass-by's
spectra and level over time."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from acoustics.passby import HALF_TRACK_M, PassbySource, passby
from acoustics.signal import spectrogram_db

ANGLES = np.linspace(0.0, math.pi, 181)


def test_the_fast_level_peaks_at_the_passby_maximum():
    """A monopole passing at 10 m/s: its level averaged over 0.125 s peaks within 0.05 dB
    below L_pAmax (the closest approach's curvature over an eighth of a second)."""
    res = passby([PassbySource(0.0, HALF_TRACK_M, 0.46, 500.0, np.ones(181), ANGLES, 0, -3.2)], 10.0)
    fast = res.fast_level_dba()
    assert fast.shape == res.t.shape
    assert res.lpamax_dba - 0.05 < fast.max() <= res.lpamax_dba + 1e-9


def test_the_spectrogram_finds_a_tone():
    """A 1 kHz tone of 1 Pa amplitude: its spectrogram peaks in the bin nearest 1 kHz
    (48 kHz, 4096 samples: 11.7 Hz bins) at every time."""
    rate = 48000.0
    t = np.arange(int(rate)) / rate
    f, times, db = spectrogram_db(np.sin(2 * math.pi * 1000.0 * t), rate)
    assert np.all(np.abs(f[np.argmax(db, axis=0)] - 1000.0) <= rate / 4096)
    assert abs(times.mean()) < 0.05  # centred on the signal's middle


@pytest.mark.slow  # railway_920's modes and the map run eight times (about 45 s cold)
def test_the_recommended_treatment_run_again_squeals_where_the_remedy_says(tmp_path):
    """The shipped wheel's map at 150 and 600 m, 40 km/h: the remedy recommends a
    treatment that leaves nothing squealing; its design file, run over the same map,
    squeals in exactly the cases the remedy says are still squealing; every treatment's
    design file loads; remedy.toml holds the recommended change; curve.nc holds each
    case's one-third-octave spectrum, whose largest band is the wheel's own L_pAmax where
    it has one tone."""
    import xarray as xr
    from conftest import run_here

    out = tmp_path / "c"
    args = ["--design", "railway_920_track", "--radius", "150,600", "--train-speed", "40", "--quiet"]
    r = run_here("curve", *args, "--out", out)
    assert r.returncode == 0, r.stderr
    summary = json.loads((out / "summary.json").read_text())
    remedy = summary["remedy"]
    best = next(t for t in remedy["treatments"] if t["name"] == remedy["recommended"])
    assert best["cases_squealing_before"] > 0 and best["design_file"]
    # a realistic treatment stops it all: the friction modifier for the treads' falling
    # friction, the lubricated gauge face for the flange's mode coupling at 150 m
    assert best["cases_still_squealing"] == 0
    assert remedy["words"].startswith("remedy: " + best["name"])
    assert r.stdout.lstrip().startswith("remedy: ")
    assert (out / "remedy.toml").read_text().split("\n", 1)[1].strip() in best["paste"]
    again = tmp_path / "again"
    r2 = run_here("curve", *args, "--no-remedy", "--design", out / best["design_file"], "--out", again)
    assert r2.returncode == 0, r2.stderr
    cases = json.loads((again / "summary.json").read_text())["cases"]
    assert sum(c["squeals"] for c in cases) == best["cases_still_squealing"]
    assert "remedy" not in json.loads((again / "summary.json").read_text())
    with xr.open_dataset(out / "curve.nc") as ds:
        assert ds["band_lpamax_dba"].dims == ("radius_m", "train_speed_km_h", "wheel", "band_hz")
        assert float(ds["band_hz"][0]) == 50.0 and float(ds["band_hz"][-1]) == 10000.0
        for c in summary["cases"]:
            if c["passby_lpamax_dba"] is None:
                continue
            spectrum = ds["band_lpamax_dba"].sel(
                radius_m=c["radius_m"],
                train_speed_km_h=c["train_speed_km_h"],
                wheel=f"{c['axle']} {c['rail']}",
            )
            levels = spectrum.values[np.isfinite(spectrum.values)]
            energy = 10 * math.log10(float(np.sum(10 ** (levels / 10))))
            # the band maxima's energy sum bounds the wheel's L_pAmax from above (each band's
            # maximum may come at another time), the largest band from below
            assert levels.max() - 1e-6 <= c["passby_lpamax_dba"] <= energy + 1e-6
    for t in remedy["treatments"]:
        if t["design_file"]:
            assert (out / t["design_file"]).stat().st_size > 100
    assert (out / "passby.png").stat().st_size > 1000
