"""One decision, one chain: every command's decision path gives the same answer.

For five cases (the rig wheel, which names its mode; the thin web, which does not; the
rig wheel damped until it is quiet; a two-mode modal model that squeals by mode
coupling; the rig wheel on a roller with a lateral mode), the paths of ``run``,
``simulate``, ``stability``, ``compare``, ``sweep``, ``study``, ``sound`` and ``modes``
(the functions those commands call, in-process) give the same mode, mechanism and
growth rate, and where they go so far the same tone, amplitude and level.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from conftest import COUPLED_PAIR_TOML

import wheel_squeal as ws
from wheel_squeal.chain import ChainOptions
from wheel_squeal.study.task import CaseJob, run_case

VC, RPM = 0.39, 800.0


@pytest.fixture(scope="module")
def context(tmp_path_factory) -> ws.RunContext:
    return ws.RunContext.of("fast", fmax_hz=1500.0, cache=ws.StageCache(tmp_path_factory.mktemp("cache")))


def _case(name: str, tmp: Path):
    """(design, modes or None for the FE's)."""
    table1 = ws.load_design("table1")
    if name == "table1":
        return table1, None
    if name == "thin_web":
        return ws.load_design("thin_web"), None
    if name == "damped":
        return table1.replace(modal_damping_ratio=0.05, squeal_mode=""), None
    if name == "coupled_pair":
        path = tmp / "pair.toml"
        path.write_text(COUPLED_PAIR_TOML)
        return table1.replace(friction_law="constant", squeal_mode=""), ws.load_modal_model(path)
    roller = dict(lateral_frequency_hz=1100.0, lateral_damping_ratio=0.01, lateral_modal_mass_kg=2.0)
    return table1.replace(**roller), None


def _same(a, b) -> bool:
    a, b = (None if isinstance(x, float) and math.isnan(x) else x for x in (a, b))
    if a is None or b is None or isinstance(a, str) or isinstance(a, bool):
        return a == b
    return math.isclose(a, b, rel_tol=1e-12, abs_tol=0.0) or (math.isnan(a) and math.isnan(b))


@pytest.mark.parametrize("name", ["table1", "thin_web", "damped", "coupled_pair", "roller_mode"])
def test_every_command_answers_from_the_one_chain(name, context, tmp_path):
    design, given = _case(name, tmp_path)
    op = ws.operating_point(design, rpm=RPM, crabbing_velocity_m_s=VC)
    modes = (
        given
        if given is not None
        else ws.compute_modes(design, context.fidelity, fmax_hz=context.fmax_hz, cache=context.cache)
    )

    def chain(stop: str, **kw):
        return ws.analyse(
            design, op=op, options=ChainOptions(stop_after=stop, **kw), context=context, modes=modes
        )

    run = chain("sound").to_record()  # run, and compare (one record per design)
    simulate = chain("limit_cycle").to_record()
    stability = chain("stability", remedy=False).to_record()
    grid = ws.sweep_verdicts(design, [VC], [RPM], modeset=modes, context=context, sound=given is None)
    sweep = {
        "verdict_mode": grid.mode[0, 0],
        "mechanism": grid.mechanism[0, 0],
        "tone_hz": grid.tone_hz[0, 0],
        "amplitude_m_s": grid.amplitude_m_s[0, 0],
        "growth_rate_1_s": grid.growth_rate_1_s[0, 0],
        "spl_db": grid.spl_db[0, 0],
    }
    full = ("stability", "limit_cycle", "sound") if given is None else ("stability", "limit_cycle")
    study = (
        run_case(CaseJob(design, (), "fast", context.fmax_hz, full, (VC,), (RPM,), str(context.cache.root)))
        if given is None
        else None
    )  # a study varies FE designs (a modal model has no design to vary)

    for key in ("verdict_mode", "mechanism", "growth_rate_1_s"):
        for where, got in (("simulate", simulate), ("stability", stability), ("sweep", sweep)):
            assert _same(got[key], run[key]), (where, key, got[key], run[key])
    for key in ("tone_hz", "amplitude_m_s", "saturated", "squeals"):
        for where, got in (("simulate", simulate), ("sweep", sweep)):
            if key in got:
                assert _same(got[key], run[key]), (where, key, got[key], run[key])
    if given is None:
        assert _same(sweep["spl_db"] if not math.isnan(sweep["spl_db"]) else None, run["spl_db"]), (
            "sweep level"
        )
    if study is not None:
        assert study["status"] == "ok", study
        for key in ("tone_hz", "amplitude_m_s", "growth_rate_1_s", "spl_db"):
            value = study[key][0][0]
            assert _same(None if isinstance(value, float) and math.isnan(value) else value, run[key]), (
                "study",
                key,
            )
        assert (
            study["verdict_mode"][0][0] == run["verdict_mode"]
            and study["mechanism"][0][0] == run["mechanism"]
        )
    # the mode sound and modes --mode take: the decision's, as the linear verdict names it
    assert stability["verdict_mode"] == run["verdict_mode"]

    expected = {
        "table1": ("(3,0) axial", "falling friction"),
        "thin_web": ("(1,0) axial", "falling friction"),
        "damped": ("", ""),
        "coupled_pair": (run["verdict_mode"], "mode coupling"),
        "roller_mode": ("(3,0) axial", "falling friction"),
    }[name]
    assert (run["verdict_mode"], run["mechanism"]) == expected
    assert run["squeals"] == (name != "damped")


def test_a_coupled_pair_grows_at_its_linear_rate_in_the_time_domain(tmp_path):
    """``simulate --modal-model`` of the pair: its record grows at the linear growth rate
    of the coupled eigenvalue within 5 % (a small kick from rest grows linearly first)."""
    design, modes = _case("coupled_pair", tmp_path)
    a = ws.analyse(design, modes=modes, stop_after="limit_cycle", remedy=False)
    o = a.verdict.outcome
    assert o is not None and o.mechanism == "mode coupling" and len(o.group) == 2
    assert o.growth_rate_1_s == pytest.approx(109.0, rel=0.02)  # the 109 1/s
    fitted = o.simulation.limit_cycle.envelope_growth_rate_1_s
    assert fitted == pytest.approx(o.growth_rate_1_s, rel=0.05)


def test_the_coupled_pair_has_one_leading_mode_everywhere_it_is_written(tmp_path):
    """The stability command's winner, its mark in the table and the verdict's mode are
    the decision's one leading mode (the one holding most of the fastest-growing
    eigenvalue), and its growth rate is that eigenvalue's."""
    import json

    from conftest import run_here

    path = tmp_path / "pair.toml"
    path.write_text(COUPLED_PAIR_TOML)
    r = run_here(
        "stability", "--modal-model", path, "--friction-law", "constant", "--out", tmp_path / "s", "--quiet"
    )
    assert r.returncode == 0, r.stderr
    s = json.loads((tmp_path / "s" / "summary.json").read_text())
    winner, verdict = s["winner"], s["verdict"]
    assert winner["index"] == verdict["mode_index"] and verdict["mechanism"] == "mode coupling"
    assert winner["growth_rate_1_s"] == pytest.approx(verdict["growth_rate_1_s"], rel=1e-12)
    assert verdict["growth_rate_1_s"] == pytest.approx(109.0, rel=0.02)  # the coupled eigenvalue's
    marked = [ln for ln in r.stdout.splitlines() if "<- leads" in ln]
    assert len(marked) == 1 and marked[0].split()[0] == str(winner["index"])


@pytest.mark.slow  # 8 s of the Table 1 mode rotating (about 4 s)
def test_the_records_growth_is_the_verdicts_on_a_slowly_growing_wave(tmp_path):
    """The Table 1 mode as a rotating n = 3 pair grows at 0.93 1/s (its backward wave):
    the record's envelope, fitted over its exponential phase, within 10 % (measured 5 %:
    a small kick from rest, then the wave's beat with the decaying one)."""
    import json

    from conftest import TABLE1_MODE_ARGS, run_here

    args = ["--rotation", "--nodal-diameters", "3", "--rpm", "800", "--crab-velocity", "0.39"]
    args += ["--duration", "8"]
    r = run_here("simulate", *TABLE1_MODE_ARGS, *args, "--out", tmp_path / "s", "--quiet")
    assert r.returncode == 0, r.stderr
    s = json.loads((tmp_path / "s" / "summary.json").read_text())
    verdict = s["verdict"]["growth_rate_1_s"]
    assert verdict == pytest.approx(0.93, abs=0.01)
    assert s["limit_cycle"]["envelope_growth_rate_1_s"] == pytest.approx(verdict, rel=0.10)


def test_a_balanced_amplitude_is_the_verdicts(tmp_path):
    """With the harmonic balance the verdict carries the balance's amplitude (not None),
    and says so."""
    design = ws.load_design("table1")
    a = ws.analyse(
        design,
        modes=ws.explicit_modes(3.1, 1.6e8, 42),
        amplitude="harmonic balance",
        stop_after="limit_cycle",
        remedy=False,
    )
    v = a.verdict
    assert v.squeals and v.outcome is not None and v.outcome.balance is not None
    assert v.amplitude_m_s == pytest.approx(v.outcome.balance.amplitude_m_s, rel=1e-12)
    assert v.amplitude_m_s > 0


@pytest.mark.slow  # railway_920's modes (fast preset) and one curve (about 10 s cold)
def test_a_curve_row_is_the_chain_at_its_contact():
    """Each row of a curve is the chain at that wheel's contact: ``analyse`` of the contact's
    design (its own modes read there, solved afresh) at its operating point gives the same
    mode, mechanism, tone, growth rate, amplitude and sound as the row."""
    from track.bogie_curving import steady_curving
    from wheel_squeal.curve import contact_geometry, wheel_sites

    design = ws.load_design("railway_920_track")
    ctx = ws.RunContext.of("fast")
    cases = ws.curve(design, [150.0], [40.0], context=ctx)
    wheels = steady_curving(
        contact_geometry(design),
        design.vehicle.vehicle(),
        150.0,
        40.0,
        wheel_load_n=design.contact.normal_load,
        friction_coefficient=design.contact.friction_coefficient,
    )
    options = ChainOptions(mode="model", stop_after="sound", remedy=False, amplitude="harmonic balance")
    for case, wheel in zip(cases, wheels):
        sites = wheel_sites(design, wheel, 40.0)
        site = sites[case.deciding]
        alone = ws.analyse(site.design, op=site.op, options=options, context=ctx).verdict
        row = case.analysis.verdict
        for key in ("squeals", "mode", "mechanism", "tone_hz", "growth_rate_1_s", "amplitude_m_s", "spl_dba"):
            assert _same(alone.get(key), row.get(key)), (case, key, alone.get(key), row.get(key))
