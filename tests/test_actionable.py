"""A verdict an engineer can act on, end to end through the command line: the model's
multi-mode outcome as the answer, the sound at the tone heard, fair comparisons, the
friction coefficient on every command with an operating point, no round-off presented
as a requirement, figures without clipped or overlapping text, a WAV without clicks and
CSV files any reader takes."""

from __future__ import annotations

import json
import math
import wave
from pathlib import Path

import numpy as np
import pytest
from conftest import DESIGNS, TABLE1_MODE_ARGS, run_cli, run_here

from acoustics.harmonics import RADIATION_STEP

SHIPPED = sorted(p.stem for p in DESIGNS.glob("*.toml"))


def _one_mode(folder: Path, frequency_hz: float = 1143.4) -> Path:
    """A modal model of one mode (Table 1's lateral modal mass, 3.1 kg: no FE)."""
    path = folder / f"mode_{frequency_hz:g}.toml"
    lines = ["[[mode]]", f"frequency_hz = {frequency_hz}", "damping_ratio = 9.4e-4", f"lateral = {3.1**-0.5}"]
    path.write_text("\n".join([*lines, "normal = 0.0", ""]))
    return path


def _summary(folder: Path) -> dict:
    return json.loads((folder / "summary.json").read_text())


# -- the friction coefficient on every command with an operating point --------------------
@pytest.mark.parametrize(
    "command",
    [
        # two runs of the whole chain in subprocesses, the time domain's kernels loaded: ~3 s
        pytest.param(("run", "--modal-model"), marks=pytest.mark.slow),
        ("stability", "--modal-model"),
        ("sweep", *TABLE1_MODE_ARGS, "--crab-velocity", "0.39", "--rpm", "800"),
    ],
)
def test_friction_overrides_the_design_on_every_command(tmp_path, command):
    """--friction 0.6 reaches the contact: summary.json's contact says 0.6, or the
    sweep's amplitudes differ from 0.3's."""
    if command[-1] == "--modal-model":
        command = (*command, _one_mode(tmp_path))
    out = {mu: tmp_path / f"mu{mu}" for mu in ("0.3", "0.6")}
    for mu, folder in out.items():
        r = run_here(*command, "--friction", mu, "--quiet", "--out", folder)
        assert r.returncode == 0, r.stderr
    if command[0] == "sweep":
        a, b = ((out[m] / "sweep.csv").read_text() for m in ("0.3", "0.6"))
        assert a != b
        return
    contact = _summary(out["0.6"]).get("contact", {})
    assert contact["friction_coefficient"] == 0.6


def test_friction_is_refused_in_one_line_when_absurd(tmp_path):
    r = run_here("run", "--modal-model", _one_mode(tmp_path), "--friction", "-1", "--out", tmp_path / "x")
    assert r.returncode == 2 and "Traceback" not in r.stderr and len(r.stderr.strip().splitlines()) == 1


# -- the multi-mode outcome -------------------------------------------------------------------
@pytest.mark.slow  # two FE runs of table1 with five modes integrated together (about 25 s)
def test_multimode_names_the_carrier_and_a_plain_run_reports_it_beside_the_override(tmp_path):
    multi = run_cli("run", "--multimode", "--render", "none", "--quiet", "--out", tmp_path / "m")
    assert multi.returncode == 0, multi.stderr
    v = _summary(tmp_path / "m")["verdict"]
    carrier = max(v["energy_shares"], key=v["energy_shares"].get)
    assert v["mode"] == carrier == "(1,0) axial"  # the paper's rig: its lowest mode carries it
    assert f"VERDICT: squeals in {carrier}" in multi.stdout
    plain = run_cli("run", "--render", "none", "--quiet", "--out", tmp_path / "p")
    p = _summary(tmp_path / "p")["verdict"]
    assert p["mode"] == "(3,0) axial" and p["model_pick"]["mode"] == carrier  # the override, beside it
    assert "the model alone: (1,0) axial carries the limit cycle" in plain.stdout
    html = (tmp_path / "p" / "report.html").read_text()
    assert "The modes that grow together" in html and "carries the limit cycle" in html


# -- the sound at the tone heard -------------------------------------------------------------
def _wav(path: Path) -> tuple[np.ndarray, int]:
    with wave.open(str(path)) as w:
        rate = w.getframerate()
        x = np.frombuffer(w.readframes(w.getnframes()), dtype="<i2").astype(float)
    return x, rate


@pytest.mark.slow  # railway_920's FE modes and 12 modes integrated together (about 40 s)
def test_the_tone_the_wav_the_spectrum_and_the_sound_agree(tmp_path):
    """railway_920 at 11.1 m/s, 10 mrad: the limit cycle settles far from every natural
    frequency; the verdict's tone, the WAV's strongest frequency, the microphone
    spectrum's peak agree within one FFT bin of the WAV, and the radiated sound's
    frequency within half its grid step (``acoustics.harmonics.RADIATION_STEP``)."""
    r = run_cli(
        "run",
        "--design",
        "railway_920",
        "--speed",
        "11.1",
        "--crab-velocity",
        "0.111",
        "--render",
        "none",
        "--quiet",
        "--out",
        tmp_path / "r",
    )
    assert r.returncode == 0, r.stderr
    s = _summary(tmp_path / "r")
    tone = s["verdict"]["tone_hz"]
    x, rate = _wav(tmp_path / "r" / "squeal.wav")
    spectrum = np.abs(np.fft.rfft(x * np.hanning(len(x))))
    freqs = np.fft.rfftfreq(len(x), 1.0 / rate)
    bin_hz = rate / len(x)
    assert abs(freqs[np.argmax(spectrum)] - tone) <= bin_hz
    # the field is solved on a grid of 1 % steps through the mode's natural frequency
    assert abs(s["sound"]["frequency_hz"] / tone - 1) <= RADIATION_STEP / 2
    assert abs(s["sound"]["tone_hz"] - tone) <= bin_hz
    # no 330.9 Hz (the (2,0) mode's natural frequency) anywhere in what is heard
    assert abs(s["sound"]["frequency_hz"] - 330.9) > 50


@pytest.mark.slow  # a balanced run of table1 (about 6 s)
def test_the_wav_fades_and_is_scaled_on_the_limit_cycle(tmp_path):
    r = run_cli("run", "--render", "none", "--quiet", "--out", tmp_path / "r")
    assert r.returncode == 0, r.stderr
    x, rate = _wav(tmp_path / "r" / "squeal.wav")
    edge = int(0.005 * rate)
    assert abs(x[0]) < 1 and abs(x[-1]) < 1  # faded to silence at both ends: no click
    assert np.max(np.abs(x[-edge:])) < 0.5 * 32767
    steady = x[len(x) // 2 :]  # the limit cycle's part (it saturates in the first half)
    assert np.max(np.abs(steady)) == 32767  # its peak is full scale
    assert np.mean(np.abs(steady) >= 32767) < 0.001  # and nothing of it is clipped but the peaks


def test_an_instability_below_20_hz_is_not_a_squeal(tmp_path):
    """A 5 Hz mode that grows: the verdict says it is an instability, not a squeal, and
    writes no sound."""
    r = run_here("run", "--modal-model", _one_mode(tmp_path, 5.0), "--quiet", "--out", tmp_path / "low")
    assert r.returncode == 0, r.stderr
    v = _summary(tmp_path / "low")["verdict"]
    assert v["squeals"] is False and "not a squeal" in v["reason"]
    assert not (tmp_path / "low" / "squeal.wav").exists()


# -- fair comparisons -------------------------------------------------------------------------
@pytest.mark.slow  # two designs' FE modes and runs (about 20 s)
def test_compare_states_each_operating_point_and_ranks_by_sound_power(tmp_path):
    r = run_cli("compare", "table1", "railway_920", "--quiet", "--out", tmp_path / "c")
    assert r.returncode == 0, r.stderr
    rows = _summary(tmp_path / "c")["designs"]
    radius = {"table1": 0.213, "railway_920": 0.46}
    for row in rows:  # each design at 800 RPM: its own rolling speed
        assert row["rpm"] == pytest.approx(800.0)
        assert row["rolling_speed_m_s"] == pytest.approx(
            800 * 2 * math.pi / 60 * radius[row["design"]], rel=0.01
        )
    levels = [row["sound_power_level_db"] for row in rows if row["sound_power_level_db"] is not None]
    assert levels == sorted(levels, reverse=True)
    assert all(row["spl_7_5m_db"] is not None for row in rows if row["sound_power_level_db"] is not None)
    assert "38.5" in r.stdout and "17.84" in r.stdout  # both speeds printed


# -- no meaningless numbers -------------------------------------------------------------------
def _numbers(x: object, key: str = ""):
    if isinstance(x, dict):
        for k, v in x.items():
            yield from _numbers(v, str(k))
    elif isinstance(x, list):
        for v in x:
            yield from _numbers(v, key)
    elif isinstance(x, (int, float)) and not isinstance(x, bool):
        yield key, float(x)


@pytest.mark.slow  # the stability and a small envelope of every shipped design (about 2 min)
@pytest.mark.parametrize("design", SHIPPED)
def test_no_round_off_is_presented_as_a_requirement(tmp_path, design):
    """Every number the stability and its envelope write (summary.json, stability.csv,
    the printed tables): nothing past 1e20 and no damping "needed" below 1e-8."""
    r = run_cli(
        "stability",
        "--design",
        design,
        "--envelope",
        "--envelope-crab-velocity",
        "0.1:0.4:3",
        "--envelope-rpm",
        "400,800",
        "--fidelity",
        "fast",
        "--quiet",
        "--out",
        tmp_path / "s",
    )
    assert r.returncode == 0, r.stderr
    for key, x in _numbers(_summary(tmp_path / "s")):
        assert abs(x) <= 1e20, (key, x)
        if "required_damping" in key or "needed" in key or key.startswith("grows_below_damping"):
            assert x == 0 or x >= 1e-8, (key, x)
    for token in r.stdout.replace(",", " ").split():
        try:
            value = float(token)
        except ValueError:
            continue
        assert abs(value) <= 1e20, token


# -- figures and files ------------------------------------------------------------------------
def _text_problems(fig) -> list[str]:
    """Texts (titles, axis labels, tick labels in view, legends, figure texts) outside
    the figure or overlapping another by more than 2 pixels each way."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig).draw()
    renderer = fig.canvas.get_renderer()
    items = []
    for ax in fig.axes:
        items += [("label", ax, t) for t in (ax.title, ax.xaxis.label, ax.yaxis.label)]
        for axis in (ax.xaxis, ax.yaxis):
            lo, hi = sorted(axis.get_view_interval())
            for tick in axis.get_major_ticks():
                if lo - 1e-6 * (hi - lo) <= tick.get_loc() <= hi + 1e-6 * (hi - lo):
                    items += [("tick", ax, tick.label1), ("tick", ax, tick.label2)]
        if ax.get_legend() is not None:
            items += [("legend", ax, t) for t in ax.get_legend().get_texts()]
    items += [("label", None, t) for t in fig.texts]
    boxes = [
        (k, a, t, t.get_window_extent(renderer))
        for k, a, t in items
        if t.get_visible() and t.get_text().strip()
    ]
    frame = fig.bbox
    problems = [
        f"clipped: {t.get_text()!r}"
        for _, _, t, b in boxes
        if b.x0 < frame.x0 - 1 or b.y0 < frame.y0 - 1 or b.x1 > frame.x1 + 1 or b.y1 > frame.y1 + 1
    ]
    for i, (ki, ai, ti, bi) in enumerate(boxes):
        for kj, aj, tj, bj in boxes[i + 1 :]:
            if ki == kj == "legend" and ai is aj:
                continue
            w = min(bi.x1, bj.x1) - max(bi.x0, bj.x0)
            h = min(bi.y1, bj.y1) - max(bi.y0, bj.y0)
            if w > 2 and h > 2:
                problems.append(f"overlap: {ti.get_text()!r} / {tj.get_text()!r}")
    return problems


@pytest.mark.slow  # run, multimode, stability envelope, compare, sweep and a study (about 1 min)
def test_no_figure_has_clipped_or_overlapping_text(tmp_path, monkeypatch):
    """Every figure the commands draw, checked as it is saved (the plot processes are
    forked from this one, so they check too): problems are appended to a file."""
    from matplotlib.figure import Figure

    log = tmp_path / "problems.txt"
    save = Figure.savefig

    def checked(self, path, *args, **kwargs):
        problems = _text_problems(self)
        if problems:
            with open(log, "a") as f:
                f.write(f"{Path(path).name}: {problems[:4]}\n")
        return save(self, path, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", checked)
    commands = [
        ("run", "--render", "none"),
        ("run", "--multimode", "--render", "none"),
        ("stability", "--envelope", "--envelope-crab-velocity", "0.1:0.4:3", "--envelope-rpm", "400,800"),
        ("compare", "table1", "thin_web"),
        ("sweep", "--crab-velocity", "0.2,0.4", "--rpm", "800", "--sound"),
        ("study", DESIGNS.parent / "studies" / "smoke.toml"),
    ]
    for k, command in enumerate(commands):
        r = run_here(*command, "--quiet", "--out", tmp_path / f"c{k}")
        assert r.returncode == 0, (command, r.stderr)
    assert not log.exists(), log.read_text()


@pytest.mark.slow  # as above: one run, a sweep, a compare, a stability envelope and a study
def test_every_csv_reads_as_it_is_with_pandas(tmp_path):
    import pandas  # with xarray, in the study extra the test extra installs

    commands = [
        ("run", "--modal-model", _one_mode(tmp_path)),
        ("sweep", *TABLE1_MODE_ARGS, "--crab-velocity", "0.2,0.4", "--rpm", "800"),
        ("stability", "--envelope", "--envelope-crab-velocity", "0.1:0.4:3", "--envelope-rpm", "800"),
        ("study", DESIGNS.parent / "studies" / "smoke.toml"),
    ]
    from wheel_squeal.output_files import FILES

    seen = 0
    for k, command in enumerate(commands):
        r = run_here(*command, "--quiet", "--out", tmp_path / f"c{k}")
        assert r.returncode == 0, (command, r.stderr)
        for csv in (tmp_path / f"c{k}").glob("*.csv"):
            frame = pandas.read_csv(csv)
            assert len(frame) > 0 and all(isinstance(c, str) and not c.startswith("#") for c in frame.columns)
            if csv.name in FILES:
                columns = list(frame.columns)
                if csv.name == "study.csv":  # the design axes first and design_<field> last: the study's own
                    columns = [c for c in columns if c in FILES[csv.name].fields]
                assert columns == list(FILES[csv.name].fields), csv.name
            seen += 1
    assert seen >= 4
