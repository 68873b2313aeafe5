"""The whole wheel's remedy: against the closed form of one mode far from the others, on
a coalesced pair (where one partner's damping cannot stop it), and end to end: the
remedy.toml a run writes, pasted into the design, gives "no squeal"."""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from conftest import COUPLED_PAIR_TOML, DESIGNS, run_cli, run_here

import reduced as r
from reduced.remedy import (
    DECAY_RATE_1_S,
    damping_to_stop,
    friction_coefficient_to_stop,
    friction_slope_to_stop,
    round_up,
    separation_to_stop,
)

TABLE1 = r.ModalDOF(3.1, 1.6e8, 42.0)


def test_round_up_keeps_two_digits_and_never_lowers():
    assert round_up(0.001648) == 0.0017
    assert round_up(0.0017) == 0.0017  # already two digits: unchanged, not 0.0018
    assert round_up(0.13) == 0.13 and round_up(12.01) == 13.0
    for x in np.geomspace(1e-7, 0.9, 200):
        assert x <= round_up(x) <= x * 1.1 + 1e-18


def test_one_mode_gets_the_closed_form_damping(law, op_fig6):
    """Far from every other mode sigma = -(c + g) / (2 m): the damping with which it
    decays at DECAY_RATE_1_S is c = 2 m DECAY - g, i.e. zeta = c / (2 sqrt(k m)); the
    remedy is that, rounded up to two digits (so at most 10 % above it) and bisected to
    1e-3."""
    g = r.friction_damping_ns_m(law, op_fig6)
    c = 2 * TABLE1.mass_kg * DECAY_RATE_1_S - g
    exact = c / (2 * math.sqrt(TABLE1.stiffness_n_m * TABLE1.mass_kg))
    found = damping_to_stop([TABLE1], law, op_fig6)
    assert found.settled and found.raised == (0,)
    assert exact * (1 - 1e-3) <= found.damping_ratio[0] <= exact * 1.1 * (1 + 1e-3)
    assert found.growth_rate_1_s <= -DECAY_RATE_1_S


def test_a_growing_counter_body_eigenvalue_is_never_settled(law, op_fig6):
    """A counter-body mode whose own damping is half the contact's negative damping grows
    at about -(c + g) / (2 m) with the wheel far from it in frequency (300 Hz against
    1143 Hz: within 5 %, the wheel's coupling); no damping of the wheel moves it, so the
    remedy is not settled and says why: never "no mode grows" beside it."""
    g = r.friction_damping_ns_m(law, op_fig6)
    m, f = 100.0, 300.0
    c = -g / 2
    body = r.BodyModel.from_modes([(r.LATERAL, f, c / (2 * m * 2 * math.pi * f), m)], "a test body")
    found = damping_to_stop([TABLE1], law, op_fig6, body=body)
    expected = -(c + g) / (2 * m)
    assert found.counter_body_growth_rate_1_s == pytest.approx(expected, rel=0.05)
    assert not found.settled and "counter-body's own eigenvalue grows" in found.reason
    assert found.growth_rate_1_s <= -DECAY_RATE_1_S  # the wheel's own mode is damped all the same


def _coalesced_pair(law, op):
    """Two modes 2 % apart coupled through the normal contact (the mode-coupling case of
    the coupled-pair modal model, on a constant friction law)."""
    contact = r.ContactLaw.from_hertz(
        r.hertz_contact(0.213, 0.300, 0.085, 0.040, 175e9, 0.28, 1000.0), 0.3, friction_law="constant"
    )
    pair = [
        r.ModalDOF.from_damping_ratio(4.0, 4.0 * (2 * math.pi * 1000.0) ** 2, 0.001, 0, 1.0, -0.1),
        r.ModalDOF.from_damping_ratio(44.4, 44.4 * (2 * math.pi * 960.0) ** 2, 0.001, 0, 2 / 3, 1.0),
    ]
    return pair, contact


def test_a_coalesced_pair_is_stopped_by_both_partners_damping(law, op_fig6):
    """One partner's critical damping (the old per-mode remedy) leaves the pair growing;
    the remedy raises both, and with it every eigenvalue decays."""
    pair, contact = _coalesced_pair(law, op_fig6)
    assert r.largest_growth_rate(pair, contact, op_fig6) > 50.0  # it grows fast by mode coupling
    found = damping_to_stop(pair, contact, op_fig6)
    assert found.settled and found.raised == (0, 1)
    damped = [m.with_damping_ratio(z) for m, z in zip(pair, found.damping_ratio)]
    assert r.largest_growth_rate(damped, contact, op_fig6) <= -DECAY_RATE_1_S
    one = r.critical_damping_ratio(pair, contact, op_fig6, 0)
    alone = [pair[0].with_damping_ratio(one * 1.01), pair[1]]
    assert r.largest_growth_rate(alone, contact, op_fig6) > 0.0  # one partner alone: still grows


def test_the_friction_levers_bracket_the_boundary(law, op_fig6):
    """Below the friction coefficient found nothing grows, above the unrounded boundary
    (twice the two-digit rounding step) something does; the same for the slope."""
    mu = friction_coefficient_to_stop([TABLE1], law, op_fig6)
    assert mu is not None and 0 < mu < 0.3

    def grows(m: float) -> float:
        c = r.ContactLaw.from_hertz(r.hertz_contact(0.213, 0.300, 0.085, 0.040, 175e9, 0.28, 1000.0), m)
        return r.largest_growth_rate([TABLE1], c, op_fig6)

    assert grows(mu) <= 0.0 and grows(mu * 0.5) <= 0.0
    assert grows(mu + 2 * 10 ** (math.floor(math.log10(mu)) - 1)) > 0.0
    slope = friction_slope_to_stop([TABLE1], law, op_fig6)
    # the closed form: sigma = 0 where g = -c, i.e. dmu/dzeta = -c V0 / W
    assert slope == pytest.approx(-42.0 * op_fig6.rolling_speed_m_s / 1000.0, rel=2e-3)


def test_the_separation_stops_the_pair(law, op_fig6):
    pair, contact = _coalesced_pair(law, op_fig6)
    f = separation_to_stop(pair, contact, op_fig6, (0, 1))
    assert f is not None and f > 1000.0
    moved = [r.ModalDOF.from_damping_ratio(4.0, 4.0 * (2 * math.pi * f) ** 2, 0.001, 0, 1.0, -0.1), pair[1]]
    assert r.largest_growth_rate(moved, contact, op_fig6) <= 0.0


def _paste(design: Path, remedy_toml: Path, into: Path, name: str) -> Path:
    """The design file with the remedy's [squeal.damping] table pasted at its end (a new
    name, so that its result folder is its own)."""
    text = design.read_text()
    text = text.replace(tomllib.loads(text)["name"], name, 1)
    into.write_text(text + "\n" + remedy_toml.read_text())
    return into


@pytest.mark.slow  # the run, then again with the remedy pasted: two chains in subprocesses (~3 s)
def test_the_coupled_pairs_remedy_pasted_stops_it(tmp_path):
    """The modal model's pair squeals by mode coupling; its remedy.toml names both
    partners by their labels; pasted into the design, the same run says no squeal."""
    model = tmp_path / "pair.toml"
    model.write_text(COUPLED_PAIR_TOML)
    args = ("run", "--modal-model", model, "--friction-law", "constant", "--quiet")
    first = run_here(*args, "--out", tmp_path / "a")
    assert first.returncode == 0, first.stderr
    remedy = json.loads((tmp_path / "a" / "summary.json").read_text())["verdict"]["remedy"]
    assert set(remedy["damping"]) == {"m1", "m2"} and remedy["settled"]
    assert remedy["time_domain"] == "quiet"  # the check: the pair integrated with it decays
    assert remedy["separations"] and remedy["separations"][0]["frequency_hz"] > 1000.0
    pasted = _paste(DESIGNS / "table1.toml", tmp_path / "a" / "remedy.toml", tmp_path / "d.toml", "pasted")
    second = run_here(*args, "--design", pasted, "--out", tmp_path / "b")
    assert second.returncode == 0, second.stderr
    assert "VERDICT: no squeal" in second.stdout


@pytest.mark.slow  # three FE runs and three more with the remedy (about 60 s)
@pytest.mark.parametrize(
    "design, point",
    [
        ("table1", ()),
        ("railway_920", ("--speed", "11.1", "--crab-velocity", "0.111")),
    ],
)
def test_a_remedy_pasted_into_the_design_stops_the_squeal(tmp_path, design, point):
    """The issue's cases: table1 at the Fig. 6 point and railway_920 at 11.1 m/s, Vc =
    0.111 m/s squeal; their remedy.toml pasted into the design gives "no squeal"."""
    first = run_cli("run", "--design", design, *point, "--render", "none", "--quiet", "--out", tmp_path / "a")
    assert first.returncode == 0, first.stderr
    assert "VERDICT: squeals" in first.stdout and "with these damping ratios no mode grows" in first.stdout
    pasted = _paste(DESIGNS / f"{design}.toml", tmp_path / "a" / "remedy.toml", tmp_path / "d.toml", "pasted")
    second = run_cli(
        "run", "--design", pasted, *point, "--render", "none", "--quiet", "--out", tmp_path / "b"
    )
    assert second.returncode == 0, second.stderr
    assert "VERDICT: no squeal" in second.stdout, second.stdout
