"""The pipeline: CLI contract, error discipline, stage cache, only-what-is-needed."""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from conftest import DESIGNS, TABLE1_MODE_ARGS, run_cli as cli

import wheel_squeal as ws
from geometry import WheelDesign
from wheel_squeal.cli import main
from wheel_squeal.fe_stages import modes_cache_key
from wheel_squeal.runtime.result_folders import MARKER


# ---------------------------------------------------------------------------------------
# bad requests: one line, exit 2, no traceback, nothing written
# ---------------------------------------------------------------------------------------
def _bad_requests(tmp: Path) -> list[tuple[list[str], str]]:
    blocker = tmp / "a_file"
    blocker.write_text("not a folder")
    typo = tmp / "typo.toml"
    typo.write_text("[wheel]\nrim_dept = 0.03\n")
    return [
        (["run", "--design", str(tmp / "missing.toml")], "not found"),
        (["run", "--design", str(typo)], "rim_dept"),
        (["run", "--mode", "n=17"], "n=17"),
        (["run", "--mode", "banana"], "banana"),
        (["run", "--rpm", "-5"], "rpm"),
        (["run", "--crab-velocity", "0.2", "--angle-of-attack", "0.01"], "not both"),
        (["simulate", "--mass", "3.1", "--stiffness", "1.6e8"], "together"),
        (["simulate", "--mass", "-3", "--stiffness", "1.6e8", "--damping", "42"], "mass"),
        (["simulate", "--speed", "0", *TABLE1_MODE_ARGS], "speed"),
        (["mesh", "--size", "-1"], "size"),
        (["modes", "--fidelity", "ultra"], "fidelity"),
        (["sweep", "--crab-velocity", "0:1:x"], "START:STOP:N"),
        (["simulate", "--rotation", *TABLE1_MODE_ARGS], "nodal"),
        (["stability", "--envelope", "--envelope-rpm=0,400"], "envelope-rpm"),
        (["stability", "--envelope", "--envelope-crab-velocity", "0:1:200000"], "envelope"),
        (["run", "--multimode", "0"], "multimode"),
        (["run", "--out", str(blocker / "sub")], "not"),
    ]


@pytest.mark.slow
def test_bad_requests_exit_2_with_one_line_and_no_output(tmp_path):
    for args, needle in _bad_requests(tmp_path):
        out = tmp_path / "out"
        if "--out" not in args:
            args = [*args, "--out", str(out)]
        r = cli(*args, "--quiet", "--cache-dir", str(tmp_path / "cache"))
        msg = f"{args}: rc={r.returncode} stderr={r.stderr!r}"
        assert r.returncode == 2, msg
        lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
        assert len(lines) == 1, msg
        assert "Traceback" not in r.stderr, msg
        assert needle.lower() in lines[0].lower(), msg
        assert not out.exists(), msg
        # no temporary folders left beside the output either
        assert not list(tmp_path.glob(".out.tmp-*")), msg


@pytest.mark.slow
def test_every_command_has_help():
    for command in [
        "run",
        "mesh",
        "modes",
        "simulate",
        "sweep",
        "compare",
        "render",
        "calibrate",
        "converge",
        "cache",
    ]:
        r = cli(command, "--help")
        assert r.returncode == 0 and "usage" in r.stdout, command


@pytest.mark.slow
def test_failed_run_keeps_previous_results(tmp_path):
    """A failure after the output folder exists must not damage the earlier results."""
    out = tmp_path / "res"
    out.mkdir()
    (out / "summary.json").write_text('{"precious": true}')
    r = cli("run", "--mode", "n=17", "--out", str(out), "--quiet", "--cache-dir", str(tmp_path / "cache"))
    assert r.returncode == 2
    assert json.loads((out / "summary.json").read_text()) == {"precious": True}


# ---------------------------------------------------------------------------------------
# the cache
# ---------------------------------------------------------------------------------------
def test_changing_only_the_operating_point_reuses_mesh_and_modes(tmp_path, monkeypatch):
    cache = ws.StageCache(tmp_path / "cache")
    design = ws.Design()
    ms1 = ws.compute_modes(design, "fast", cache=cache)
    assert cache.misses == ["modes", "mesh2d"] and cache.hits == []

    # the second request (different crabbing velocity, friction and damping) must not
    # mesh or solve at all: make both impossible
    import fem.axisym
    import geometry.gmsh_mesh

    def boom(*a, **k):
        raise AssertionError("recomputed although cached")

    monkeypatch.setattr(geometry.gmsh_mesh, "mesh_profile", boom)
    monkeypatch.setattr(fem.axisym, "solve_axisymmetric", boom)
    other = design.replace(friction_coefficient=0.25, modal_damping_ratio=2e-3, normal_load=1500.0)
    ms2 = ws.compute_modes(other, "fast", cache=cache)
    assert cache.hits == ["modes"]
    mode1, _ = ws.pick_mode(ms1)
    mode2, _ = ws.pick_mode(ms2)
    assert mode2 == mode1
    for a, b in zip(ms1.shapes, ms2.shapes):
        np.testing.assert_array_equal(a, b)

    dof = ws.modal_dof(mode2, other)
    contact = ws.contact_law(other)
    for vc in (0.2, 0.39):
        sim = ws.simulate(dof, contact, ws.operating_point(other, crabbing_velocity_m_s=vc), 0.3)
        assert np.all(np.isfinite(sim.history.v))


def test_geometry_change_misses_the_cache(tmp_path):
    cache = ws.StageCache(tmp_path / "cache")
    ws.compute_modes(WheelDesign(), "fast", cache=cache)
    ws.compute_modes(WheelDesign(rim_depth=0.032), "fast", cache=cache)
    assert cache.hits == [] and cache.misses.count("modes") == 2


def test_corrupt_cache_entry_is_reported_and_recomputed_identically(tmp_path, capsys):
    cache = ws.StageCache(tmp_path / "cache")
    design = WheelDesign()
    fresh = ws.compute_modes(design, "fast", cache=cache)
    entries = sorted((tmp_path / "cache" / "modes").glob("*.npz"))
    assert len(entries) == 1
    # flip bytes in the middle of the file
    data = bytearray(entries[0].read_bytes())
    mid = len(data) // 2
    data[mid : mid + 64] = bytes(64)
    entries[0].write_bytes(bytes(data))

    again = ws.compute_modes(design, "fast", cache=cache)
    err = capsys.readouterr().err
    assert "corrupt" in err and len([ln for ln in err.splitlines() if "corrupt" in ln]) == 1
    assert [m.frequency_hz for m in again.modes] == [m.frequency_hz for m in fresh.modes]
    assert [m.contact_lateral for m in again.modes] == [m.contact_lateral for m in fresh.modes]
    # the entry was rewritten and now loads cleanly
    third = ws.compute_modes(design, "fast", cache=cache)
    assert cache.hits[-1] == "modes"
    assert [m.modal_mass for m in third.modes] == [m.modal_mass for m in fresh.modes]


def test_foreign_cache_entry_is_detected(tmp_path, capsys):
    cache = ws.StageCache(tmp_path / "cache")
    a, b = WheelDesign(), WheelDesign(rim_depth=0.035)
    ws.compute_modes(a, "fast", cache=cache)
    ws.compute_modes(b, "fast", cache=cache)
    key_a = modes_cache_key(a, ws.fidelity_for("fast"), 5000.0)
    key_b = modes_cache_key(b, ws.fidelity_for("fast"), 5000.0)
    # put b's entry where a's belongs
    cache.path("modes", key_a).write_bytes(cache.path("modes", key_b).read_bytes())
    ms = ws.compute_modes(a, "fast", cache=cache)
    assert "foreign" in capsys.readouterr().err
    ref = ws.compute_modes(a, "fast", cache=None)
    assert [m.frequency_hz for m in ms.modes] == [m.frequency_hz for m in ref.modes]


@pytest.mark.slow
def test_cache_clear_only_removes_cache_entries(tmp_path):
    root = tmp_path / "cache"
    cache = ws.StageCache(root)
    ws.compute_modes(WheelDesign(), "fast", cache=cache)
    (root / "keep.txt").write_text("user file")
    r = cli("cache", "clear", "--cache-dir", str(root))
    assert r.returncode == 0 and "removed 2" in r.stdout
    assert (root / "keep.txt").exists()
    assert not list(root.rglob("*.npz"))


# ---------------------------------------------------------------------------------------
# only what the request needs
# ---------------------------------------------------------------------------------------
def test_an_unchanged_request_reads_its_record_back(tmp_path):
    """The same squeal model twice with one cache: the second reads the record (a cache
    hit of the record stage) and its limit cycle is the first's to the bit; another
    crabbing velocity integrates again."""
    from wheel_squeal.simulation import simulate

    cache = ws.StageCache(tmp_path / "c")
    design = ws.load_design()
    mode = ws.modal_dof(ws.explicit_modes(3.1, 1.6e8, 42).modes[0], design)
    law, op = ws.contact_law(design), ws.operating_point(design)
    first = simulate(mode, law, op, 0.3, cache=cache)
    again = simulate(mode, law, op, 0.3, cache=cache)
    assert cache.hits == ["record"]
    assert np.array_equal(first.history.v, again.history.v)
    assert first.limit_cycle.velocity_amplitude_m_s == again.limit_cycle.velocity_amplitude_m_s
    other = simulate(mode, law, ws.operating_point(design, crabbing_velocity_m_s=0.3), 0.3, cache=cache)
    assert (
        cache.hits == ["record"]
        and other.limit_cycle.velocity_amplitude_m_s != first.limit_cycle.velocity_amplitude_m_s
    )


def test_simulate_with_explicit_modal_parameters_builds_no_mesh(tmp_path, monkeypatch):
    import geometry.gmsh_mesh

    def boom(*a, **k):
        raise AssertionError("meshed although m, k, c were given")

    monkeypatch.setattr(geometry.gmsh_mesh, "mesh_profile", boom)
    monkeypatch.setattr(geometry.gmsh_mesh, "mesh_wheel", boom)
    out = tmp_path / "sim"
    rc = main(
        [
            "simulate",
            *TABLE1_MODE_ARGS,
            "--rpm",
            "800",
            "--crab-velocity",
            "0.39",
            "--duration",
            "0.6",
            "--out",
            str(out),
            "--quiet",
            "--cache-dir",
            str(tmp_path / "c"),
        ]
    )
    assert rc == 0
    s = json.loads((out / "summary.json").read_text())
    assert set(s["limit_cycle"]) == {
        *("squeal", "state", "velocity_amplitude_m_s", "frequency_hz", "time_to_saturation_s"),
        *("envelope_growth_rate_1_s", "contact_lost_fraction"),
    }
    assert s["limit_cycle"]["state"] == "limit cycle"
    assert s["limit_cycle"]["contact_lost_fraction"] == 0.0  # no normal motion: never apart
    assert {"rolling_speed_m_s", "crabbing_velocity_m_s", "creepage", "rpm"} <= set(s["operating_point"])
    assert {"semi_axis_a_m", "semi_axis_b_m", "c22", "friction_coefficient", "friction_law"} <= set(
        s["contact"]
    )
    assert s["contact"]["friction_law"] == "falling"  # the paper's law by default
    # the paper's case: limit cycle marginally below Vc (docs/validation.md: ~0.367 m/s)
    assert s["limit_cycle"]["squeal"] is True
    assert 0.35 <= s["limit_cycle"]["velocity_amplitude_m_s"] <= 0.39
    assert abs(s["limit_cycle"]["frequency_hz"] / 1143.0 - 1) < 0.01
    assert abs(s["operating_point"]["creepage"] - 0.022) < 0.0005
    lines = (out / "timeseries.csv").read_text().splitlines()
    assert lines[0] == "t_s,y_m,v_m_s,creepage,Q_N,P_W,u_n_m,N_N,v_counter_body_m_s"
    assert s["timeseries_csv"]["sample_stride"] == 1
    # Fig. 7-10 windows: growing (0.2 s) and on the limit cycle: the record's last periods
    end_s = float(lines[-1].split(",")[0])
    for stem in ("force_velocity", "power"):
        times = sorted(float(p.stem.rsplit("_", 1)[1][:-1]) for p in out.glob(f"{stem}_*s.png"))
        assert times[0] == 0.2 and end_s - 5 / 1143.0 - 0.01 <= times[-1] <= end_s, (stem, times, end_s)
    for png in ["creep_curve", "velocity_history"]:
        assert (out / f"{png}.png").stat().st_size > 10_000, png
    # no FE: the cache holds the record alone (a second run reads it back)
    assert sorted(p.name for p in (tmp_path / "c").iterdir() if p.is_dir()) == ["record"]


@pytest.mark.slow
def test_run_default_writes_the_full_report(tmp_path):
    out = tmp_path / "run"
    r = cli("run", "--out", str(out), "--quiet", "--cache-dir", str(tmp_path / "cache"))
    assert r.returncode == 0, r.stderr
    s = json.loads((out / "summary.json").read_text())
    for key in (
        "design",
        "fidelity",
        "modes",
        "selected_mode",
        "contact",
        "operating_point",
        "limit_cycle",
        "timings_s",
    ):
        assert key in s, key
    sel = s["selected_mode"]
    assert (sel["nodal_diameters"], sel["nodal_circles"], sel["family"]) == (3, 0, "axial")
    # docs/validation.md: the (3,0) axial mode near 1.1 kHz with a contact modal mass near 4 kg
    assert 1000 < sel["frequency_hz"] < 1250
    assert 2.5 < sel["modal_mass_kg"] < 5.0
    assert math.isclose(
        sel["modal_stiffness_n_m"],
        (2 * math.pi * sel["frequency_hz"]) ** 2 * sel["modal_mass_kg"],
        rel_tol=1e-9,
    )
    assert s["limit_cycle"]["squeal"] is True
    assert (out / "modes.vtu").exists() and (out / "timeseries.csv").exists()
    assert list(out.glob("mode_*_n3_c0_axial.png"))
    assert "VERDICT: squeals in (3,0) axial" in r.stdout and str(out) in r.stdout
    # the answer is the last thing said: the verdict, why, what would stop it, then the files
    assert r.stdout.strip().splitlines()[-4].startswith("VERDICT:")
    v = s["verdict"]
    assert {
        "squeals",
        "mode",
        "tone_hz",
        "growth_rate_1_s",
        "amplitude_m_s",
        "saturated",
        "spl_db",
        "sound_power_level_db",
        "reason",
        "override",
        "model_pick",
    } <= set(v)
    assert v["mode"] == "(3,0) axial" and v["model_pick"]["mode"] == "(1,0) axial"  # table1 names (3,0)
    assert v["amplitude_m_s"] == s["limit_cycle"]["velocity_amplitude_m_s"] and v["saturated"] is True
    assert s["cache"]["hits"] == []

    # only the crabbing velocity changes: mesh, modes, mode views and the sound come from the
    # cache (the limit cycle's frequency moves with Vc, within 1 % of the mode's natural
    # frequency, where the mode is radiated: levels.RADIATION_SNAP)
    out2 = tmp_path / "run2"
    r = cli(
        "run", "--crab-velocity", "0.3", "--out", str(out2), "--quiet", "--cache-dir", str(tmp_path / "cache")
    )
    assert r.returncode == 0, r.stderr
    s2 = json.loads((out2 / "summary.json").read_text())
    assert s2["cache"]["hits"] == ["modes", "sound", "sound-at", "views"]
    assert set(s2["cache"]["misses"]) == {"result", "record"}  # a new operating point: a new limit cycle
    assert s2["verdict"]["tone_hz"] != s["verdict"]["tone_hz"]
    assert s2["modes"] == s["modes"] and s2["selected_mode"] == s["selected_mode"]
    assert s2["operating_point"]["crabbing_velocity_m_s"] == 0.3
    assert s2["limit_cycle"]["velocity_amplitude_m_s"] < s["limit_cycle"]["velocity_amplitude_m_s"]
    for f in out.glob("mode_*.png"):
        assert (out2 / f.name).read_bytes() == f.read_bytes()


@pytest.mark.slow
def test_compare_shows_geometry_moves_the_squeal_prediction(tmp_path):
    out = tmp_path / "cmp"
    r = cli(
        *("compare", str(DESIGNS / "thin_web.toml"), str(DESIGNS / "thick_web.toml"), "--fidelity", "fast"),
        *("--out", str(out), "--quiet", "--cache-dir", str(tmp_path / "c")),
    )
    assert r.returncode == 0, r.stderr
    rows = {row["design"]: row for row in json.loads((out / "summary.json").read_text())["designs"]}
    thin, thick = rows["thin_web"], rows["thick_web"]
    # a thicker web is a stiffer plate: the (3,0) mode moves up by far more than 10 %
    assert thick["mode_frequency_hz"] / thin["mode_frequency_hz"] - 1 > 0.10
    assert thin["modal_mass_kg"] != pytest.approx(thick["modal_mass_kg"], rel=0.02)
    assert thin["growth_rate_1_s"] != pytest.approx(thick["growth_rate_1_s"], rel=0.02)
    assert (out / "compare.png").stat().st_size > 10_000
    assert (out / "compare.csv").read_text().count("\n") == 3


@pytest.mark.slow
def test_mesh_command_summary(tmp_path):
    out = tmp_path / "mesh"
    r = cli("mesh", "--dim", "2", "--out", str(out), "--quiet")
    assert r.returncode == 0, r.stderr
    s = json.loads((out / "summary.json").read_text())
    assert {"design", "nodes", "elements", "mesh_volume_m3", "exact_volume_m3", "seconds"} <= set(s)
    assert abs(s["mesh_volume_m3"] / s["exact_volume_m3"] - 1) < 1e-3
    assert (out / "mesh.msh").exists() and (out / "mesh.vtu").exists()


@pytest.mark.slow
def test_modes_command_summary(tmp_path):
    out = tmp_path / "modes"
    r = cli(
        *"modes --fidelity fast --fmax 3000 --quiet".split(),
        "--out",
        str(out),
        "--cache-dir",
        str(tmp_path / "c"),
    )
    assert r.returncode == 0, r.stderr
    s = json.loads((out / "summary.json").read_text())
    keys = {
        "index",
        "frequency_hz",
        "nodal_diameters",
        "nodal_circles",
        "family",
        "modal_mass_kg",
        "modal_stiffness_n_m",
        "modal_damping_ns_m",
    }
    assert all(set(m) == keys for m in s["modes"])
    assert {"selected_mode", "fidelity", "solver", "dofs", "timings_s"} <= set(s)
    assert all(m["frequency_hz"] <= 3000 for m in s["modes"])
    freqs = [m["frequency_hz"] for m in s["modes"]]
    assert freqs == sorted(freqs)
    import meshio

    vtu = meshio.read(out / "modes.vtu")
    assert len([k for k in vtu.point_data if k.startswith("mode_")]) >= len(s["modes"])


def test_3d_solver_agrees_with_axisym_preset(tmp_path):
    """``--solver 3d`` (cyclic 3-D P2, same preset) selects the same squeal mode as the
    axisymmetric default, within 0.5 % in frequency and 2 % in modal mass; the modes.vtu
    holds the whole wheel's tetrahedra."""
    d = WheelDesign()
    ax = ws.compute_modes(d, "fast", fmax_hz=2000.0)
    cy = ws.compute_modes(d, "fast", solver="3d", fmax_hz=2000.0)
    assert cy.solver == "3d-cyclic-p2" and cy.dofs > 10 * ax.dofs
    a, c = ws.pick_mode(ax)[0], ws.pick_mode(cy)[0]
    assert (c.nodal_diameters, c.nodal_circles, c.family) == (3, 0, "axial")
    assert c.frequency_hz == pytest.approx(a.frequency_hz, rel=5e-3)
    assert c.modal_mass == pytest.approx(a.modal_mass, rel=2e-2)
    with pytest.raises(ws.RequestError, match="3d-tet"):
        ws.fidelity_for("fast", "4d")
    assert ws.fidelity_for("fast", "3d-tet").mesh_order == 2


@pytest.mark.slow
def test_sweep_command(tmp_path):
    out = tmp_path / "sweep"
    r = cli(
        "sweep",
        *TABLE1_MODE_ARGS,
        *"--crab-velocity 0:0.4:5 --rpm 400,800 --duration 0.8 --quiet".split(),
        "--out",
        str(out),
    )
    assert r.returncode == 0, r.stderr
    lines = (out / "sweep.csv").read_text().splitlines()
    assert lines[0] == (
        "crabbing_velocity_m_s,rpm,rolling_speed_m_s,verdict_mode,squeals,saturated,amplitude_m_s,"
        "tone_hz,growth_rate_1_s,time_to_saturation_s"
    )
    assert len(lines) == 1 + 5 * 2
    first = lines[1].split(",")
    assert float(first[0]) == 0.0 and first[4] == "False"  # Vc = 0: no squeal
    assert (out / "sweep.png").exists()


@pytest.mark.slow
def test_render_command(tmp_path):
    out = tmp_path / "render"
    r = cli(
        *"render --fidelity fast --fmax 1500 --modes 0,4 --quiet".split(),
        "--out",
        out,
        "--cache-dir",
        tmp_path / "c",
    )
    assert r.returncode == 0, r.stderr
    pngs = sorted(p.name for p in out.glob("mode_*.png"))
    assert len(pngs) == 2 and any("_n3_c0_axial" in p for p in pngs), pngs
    assert all((out / p).stat().st_size > 10_000 for p in pngs) and (out / MARKER).is_file()
    assert r.stdout.strip().endswith(f"2 files -> {out}")


@pytest.mark.slow
def test_calibrate_command_fits_the_frequency(tmp_path):
    """Fit the rim depth to a measured (3,0) frequency alone: the written design gives
    that frequency within the 1 % uncertainty of the fit, and a rerun may replace it."""
    out = tmp_path / "cal"
    args = [
        "calibrate",
        "--free",
        "rim_depth",
        "--target-frequency",
        "1100",
        "--fidelity",
        "fast",
        "--out",
        out,
        "--quiet",
    ]
    r = cli(*args)
    assert r.returncode == 0, r.stderr
    path = out / "table1_calibrated.toml"
    data = tomllib.loads(path.read_text())
    assert data["wheel"]["rim_depth"] != 0.0335
    fitted = ws.load_design(path)
    mode, _ = ws.pick_mode(ws.compute_modes(fitted, "fast"))
    assert mode.frequency_hz == pytest.approx(1100, rel=0.01)
    assert cli(*args).returncode == 0  # its own earlier result may be replaced


@pytest.mark.slow
def test_converge_command_writes_the_study(tmp_path):
    out = tmp_path / "conv"
    r = cli("converge", "--quick", "--out", out, "--quiet")
    assert r.returncode == 0, r.stderr
    rows = (out / "convergence.csv").read_text().splitlines()
    assert rows[0].startswith("study,method,parameter_name") and len(rows) > 10
    methods = {line.split(",")[1] for line in rows[1:]}
    assert {"axisym-P2", "axisym-P2-curved", "3d-P2", "3d-tet-P2", "rk4"} <= methods
    summary = json.loads((out / "summary.json").read_text())
    assert summary["presets"]["fast"]["matches_current"] is True
    assert (out / "convergence_fe.png").stat().st_size > 10_000 and (out / "presets.md").is_file()


# --------------------------------------------------------------------------------------
# the plot process
# --------------------------------------------------------------------------------------
def _write_pid(path: Path) -> None:
    import os

    path.write_text(str(os.getpid()))


def _refuse(path: Path) -> None:
    raise ValueError(f"cannot draw {path.name}")


def test_plot_workers_write_in_other_processes_and_report_errors(tmp_path):
    import os

    from wheel_squeal.plotting import plot_workers

    files = [tmp_path / f"{i}.txt" for i in range(3)]
    with plot_workers(2) as plots:
        for f in files:
            plots.submit(_write_pid, f)
        assert not any(f.exists() for f in files)  # queued, not drawn
        plots.draw()
        pids = {int(f.read_text()) for f in files}
        assert os.getpid() not in pids
        plots.submit(_refuse, tmp_path / "bad.png")
        with pytest.raises(ValueError, match="cannot draw bad.png"):
            plots.draw()
        plots.submit(_write_pid, tmp_path / "never.txt")
    assert not (tmp_path / "never.txt").exists()  # leaving the block discards the queue


@pytest.mark.slow  # three runs of the coupled pair (about 8 s)
def test_an_unchanged_run_puts_its_result_back_and_a_changed_one_does_not(tmp_path):
    """The same ``run`` twice: the second takes the whole result from the cache (every
    file as it was, summary.json's timings and cache use its own, the same words); the
    modal model's file changed (one value), it is computed again."""
    from conftest import COUPLED_PAIR_TOML, run_here

    model = tmp_path / "pair.toml"
    model.write_text(COUPLED_PAIR_TOML)
    args = [
        "run",
        "--modal-model",
        model,
        "--friction-law",
        "constant",
        "--cache-dir",
        tmp_path / "c",
        "--quiet",
    ]
    first = run_here(*args, "--out", tmp_path / "a")
    again = run_here(*args, "--out", tmp_path / "b")
    assert first.returncode == again.returncode == 0, again.stderr
    assert first.stdout.splitlines()[:-1] == again.stdout.splitlines()[:-1]  # the files line: its own time
    a, b = (json.loads((tmp_path / x / "summary.json").read_text()) for x in "ab")
    assert b["cache"] == {"hits": ["result"], "misses": []} and "result" not in a["cache"]["hits"]
    assert {k: v for k, v in a.items() if k not in ("timings_s", "cache")} == {
        k: v for k, v in b.items() if k not in ("timings_s", "cache")
    }
    names = sorted(p.name for p in (tmp_path / "a").iterdir())
    assert names == sorted(p.name for p in (tmp_path / "b").iterdir())
    for name in names:
        if name not in ("summary.json", ".wheel-squeal-result"):
            assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes(), name
    model.write_text(COUPLED_PAIR_TOML.replace("0.001", "0.0011", 1))
    changed = run_here(*args, "--out", tmp_path / "c2")
    assert changed.returncode == 0
    assert "result" not in json.loads((tmp_path / "c2" / "summary.json").read_text())["cache"]["hits"]
