"""The normal contact's Hertz spring and the friction-law registry: the inputs of the
two-direction contact (the falling law is the paper's and stays the default)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

import reduced as r
import wheel_squeal as ws
from geometry import DesignError

TABLE1_HERTZ = dict(r1=0.213, r1t=0.300, r2=0.085, r2t=0.040, e=175e9, nu=0.28, w=1000.0)


def _table1_hertz() -> r.HertzContact:
    h = TABLE1_HERTZ
    return r.hertz_contact(h["r1"], h["r1t"], h["r2"], h["r2t"], h["e"], h["nu"], h["w"])


def test_hertz_approach_and_normal_stiffness_of_table1():
    # Table 1's contact: delta0 = 11.0 um, k_H = 3W/(2 delta0) = 1.36e8 N/m (quoted to
    # 3 significant figures: the tolerances are half a unit of the last figure)
    h = _table1_hertz()
    assert h.approach_m == pytest.approx(11.0e-6, abs=0.05e-6)
    assert h.normal_stiffness_n_m == pytest.approx(1.36e8, abs=0.005e8)


def test_hertz_approach_of_two_spheres_is_the_closed_form():
    # equal spheres: delta = (9 W^2 / (16 R* E*^2))^(1/3), R* the relative radius; the
    # elliptic-integral route must give it to round-off (1e-9: the AGM converges to 1e-15)
    e, nu, w, radius = 210e9, 0.3, 500.0, 0.05
    h = r.hertz_contact(radius, radius, radius, radius, e, nu, w)
    e_star = e / (2 * (1 - nu**2))
    r_star = radius / 2
    assert h.approach_m == pytest.approx((9 * w**2 / (16 * r_star * e_star**2)) ** (1 / 3), rel=1e-9)


def test_the_constant_law_has_no_falling_friction():
    law = r.ContactLaw.from_hertz(_table1_hertz(), 0.3, friction_law="constant")
    assert law.friction_law == "constant"
    s = np.array([0.0, 1e-9, 1e-3, 0.138, 1.0, 6.9, 100.0])
    assert np.array_equal(r.falling_friction_factor(s, law), np.ones_like(s))  # exactly 1
    zeta = np.linspace(-0.2, 0.2, 2001)
    slope = r.adhesion_ratio_slope(zeta, law, 17.84)
    assert np.all(slope >= 0.0) and np.all(np.isfinite(slope))
    # beyond saturation the adhesion ratio is mu_s itself
    assert float(r.adhesion_ratio(0.1, law, 17.84)) == 0.3


def test_the_fig6_point_squeals_with_falling_friction_only():
    """Constant friction leaves the contact a pure (positive) damper at the Fig. 6 point:
    the mode decays from rest; the paper's law makes it squeal."""
    hertz = _table1_hertz()
    op = r.OperatingPoint.from_rpm(800, 0.213, 0.39)
    mode = r.ModalDOF(3.1, 1.6e8, 42.0)
    out = {}
    for name in r.FRICTION_LAWS:
        law = r.ContactLaw.from_hertz(hertz, 0.3, friction_law=name)
        out[name] = r.limit_cycle(r.simulate(mode, law, op, 0.6))
    assert out["falling"].squeal and not out["constant"].squeal
    assert out["falling"].velocity_amplitude_m_s == pytest.approx(0.367, abs=0.002)  # the paper's case


def test_the_default_law_is_the_papers_and_designs_keep_their_hash():
    d = ws.load_design("table1")
    assert d.contact.friction_law == "falling"
    assert ws.contact_law(d).friction_law == "falling"
    assert ws.contact_law(d) == r.ContactLaw.from_hertz(_table1_hertz(), 0.3, friction_law="falling")
    assert d.replace(friction_law="falling").content_hash() == d.content_hash()
    constant = d.replace(friction_law="constant")
    assert constant.content_hash() != d.content_hash()
    assert ws.contact_law(d, friction_law="constant").friction_law == "constant"


def test_a_design_file_names_its_friction_law(tmp_path):
    d = ws.load_design("table1").replace(friction_law="constant")
    path = tmp_path / "c.toml"
    path.write_text(d.to_toml())
    assert 'friction_law = "constant"' in path.read_text()
    assert ws.load_design(path).contact.friction_law == "constant"
    path.write_text(d.to_toml().replace('"constant"', '"sticky"'))
    with pytest.raises(DesignError, match="friction_law must be one of"):
        ws.load_design(path)
    assert math.isinf(
        ws.contact_law(ws.load_design("table1"), friction_law="constant").friction.decay_speed_1_m_s
    )


@dataclass(frozen=True)
class SteeperFriction(r.FallingFriction):
    """A friction law of this test's own, in this file alone: 60 % of the fall by 0.5 m/s,
    30 % by 5 m/s (the paper's: 50 % by 0.138 m/s, 50 % by 6.9 m/s)."""

    name: ClassVar[str] = "steeper"
    weight_1: float = 0.6
    decay_speed_1_m_s: float = 0.5
    weight_2: float = 0.3
    decay_speed_2_m_s: float = 5.0


def test_a_friction_law_added_in_a_test_file_alone_runs_a_stability_and_a_limit_cycle(monkeypatch):
    """Registered as ``FRICTION_LAWS["steeper"]``, the law is taken by the design's contact,
    the linear stability and the compiled time domain. The one mode of Table 1 at the Fig. 6
    point: its growth rate is -(c + W/V0 dmu/dzeta) / 2m with the slope of this file's own
    mu (a central difference; 1e-6 relative: its truncation error at h = 1e-7 of a creepage
    of 0.022 is below 1e-9, the eigen-solve's round-off far below); the compiled RK4 record
    grows as solve_ivp's on the law's Python factor does (its amplitude over the last 10 ms
    of 50 ms within 1e-3: the records' sampling of the peak, 64 points a period, and RK4's
    step; the paper's law, growing at 8.6 1/s against 19.7, leaves it at less than half)."""
    monkeypatch.setitem(r.FRICTION_LAWS, SteeperFriction.name, SteeperFriction)
    law = ws.contact_law(ws.load_design("table1"), friction_law="steeper")
    assert law.friction == SteeperFriction() and law.friction_law == "steeper"
    op = r.OperatingPoint.from_rpm(800, 0.213, 0.39)
    mode = r.ModalDOF(3.1, 1.6e8, 42.0)

    def mu(zeta: float) -> float:  # Eq. 3 with this law's factor, written here again
        zp = abs(zeta) * law.normalised_creepage_per_creepage
        poly = zp * (1 - zp / 3 + zp * zp / 27) if zp < 3 else 1.0
        s = abs(zeta) * op.rolling_speed_m_s
        return math.copysign(
            law.friction_coefficient * poly * (1 - 0.6 * math.exp(-0.5 / s) - 0.3 * math.exp(-5 / s)), zeta
        )

    h = 1e-7
    slope = (mu(op.creepage + h) - mu(op.creepage - h)) / (2 * h)
    sigma = -(mode.damping_ns_m + law.normal_load_n / op.rolling_speed_m_s * slope) / (2 * mode.mass_kg)
    assert r.largest_growth_rate(mode, law, op) == pytest.approx(sigma, rel=1e-6)
    assert sigma > 0  # it squeals, and grows otherwise than with the paper's law
    paper = r.largest_growth_rate(mode, r.ContactLaw.from_hertz(_table1_hertz(), 0.3), op)
    assert abs(sigma - paper) > 0.1 * paper

    record = r.simulate(mode, law, op, 0.05)
    reference = r.simulate_reference(mode, law, op, 0.05, rtol=1e-10)
    last = [np.max(np.abs(h.v[h.t > 0.04])) for h in (record, reference)]  # the last 10 ms
    assert last[0] == pytest.approx(last[1], rel=1e-3)
    assert r.limit_cycle(r.simulate(mode, law, op, 0.6)).squeal
