"""Mode competition (``reduced.competition``): each mode's growth rate is the one the linear
stability gives it, also where a counter-body holds most of its growing eigenvalue; a cycle
that damps every other mode is the answer."""

from __future__ import annotations

import numpy as np
import pytest

import reduced as r
from reduced.competition import growth_on_cycle, saturation_time_s, surviving_cycle
from reduced.counter_body import ModalCounterBody
from reduced.stability import LinearContact, growth_rates

LAW = r.ContactLaw.from_hertz(
    r.hertz_contact(0.213, 0.3, 0.085, 0.04, 175e9, 0.28, 1000.0), friction_coefficient=0.3
)
OP = r.OperatingPoint.from_rpm(800, 0.213, 0.39)


PAPER_MODE = r.ModalDOF(3.1, 1.6e8, 42.0)


def _wheel_on_a_soft_body():
    """The paper's (3,0) mode and a well-damped one at 1.3 kHz that decays alone, on a
    lateral counter-body mode at 1.3 kHz, light and lightly damped: an eigenvalue the
    counter-body holds most of grows, and the second mode takes part in it."""
    second = r.ModalDOF(2.0, 2.0 * (2 * np.pi * 1300.0) ** 2, 300.0)
    return [PAPER_MODE, second], ModalCounterBody(lateral=((1300.0, 0.0005, 1.0),)).model()


def test_each_modes_rate_is_the_linear_stabilitys():
    """The competition's rates and the decision's (``linear_stability``) are one rule: the
    fastest-growing eigenvalue a mode takes part in speaks for it (exact: the same
    eigen-solve)."""
    modes, body = _wheel_on_a_soft_body()
    damping = np.array([m.damping_ns_m for m in modes])
    linear = LinearContact.at(LAW, OP)
    rates = growth_rates(modes, damping, linear, body=body, speaking=True)
    assert growth_rates(modes, damping, linear, body=body)[1] < 0.0 < rates[1]  # its own decays
    expected = [s.growth_rate_1_s for s in r.linear_stability(modes, LAW, OP, body=body).modes]
    np.testing.assert_allclose(rates, expected, rtol=1e-12)
    np.testing.assert_allclose(growth_on_cycle(0.0, modes, LAW, OP, body=body), expected, rtol=1e-9)


def test_a_large_cycle_damps_the_others():
    """On the paper's mode's cycle the contact sweeps the creep curve's steep branch: the
    averaged slope is no longer falling and the other mode decays on it; the invasion
    stops at the first mode's cycle."""
    modes = [PAPER_MODE, r.ModalDOF(2.0, 2.0 * (2 * np.pi * 1300.0) ** 2, 30.0)]
    result = r.linear_stability(modes, LAW, OP)
    assert result.modes[0].growth_rate_1_s > 0 and result.modes[1].growth_rate_1_s > 0
    cycle, visited = surviving_cycle(modes, [0, 1], LAW, OP, start=0)
    assert cycle is not None and cycle.index == 0 and len(visited) == 1
    assert cycle.amplitude_m_s > 0 and cycle.growth_on_cycle_1_s[1] < 0
    assert cycle.growth_on_cycle_1_s[0] == pytest.approx(0.0)
    # from rest the second mode, growing six times faster, is there first, and holds too
    cycle, visited = surviving_cycle(modes, [0, 1], LAW, OP)
    assert cycle is not None and cycle.index == 1 and len(visited) == 1


def test_of_two_modes_growing_alike_the_lower_reaches_its_cycle_first():
    """The creep force's step from rest gives each mode a0 = |Q| / sqrt(k m): of two modes
    with the same mass and growth rate, the one at 300 Hz starts 8.3 times (2500 / 300)
    larger than the one at 2.5 kHz and reaches its cycle first; the invasion starts there,
    not at the (marginally) faster-growing one."""
    low = r.ModalDOF(1.0, (2 * np.pi * 300.0) ** 2, 45.0)
    high = r.ModalDOF(1.0, (2 * np.pi * 2500.0) ** 2, 44.0)  # a little less damped: faster
    modes = [low, high]
    rates = growth_on_cycle(0.0, modes, LAW, OP)
    assert 0.0 < rates[0] < rates[1] < 1.05 * rates[0]
    amplitude = surviving_cycle(modes, [0, 1], LAW, OP, start=1)[1][0].amplitude_m_s
    times = [saturation_time_s(k, modes, LAW, OP, rates, amplitude) for k in range(2)]
    assert times[0] < times[1]
    cycle, visited = surviving_cycle(modes, [0, 1], LAW, OP)
    assert visited[0].index == 0


def test_the_steps_amplitude_goes_with_the_square_of_the_lateral_participation():
    """A mode seen at the contact with lateral displacement l takes the step's modal force
    Q l and shows l q' there: a0 = |Q| l^2 / sqrt(k m); l = 1 is the paper's mode."""
    from reduced.predictor import initial_amplitude

    paper = initial_amplitude(PAPER_MODE, LAW, OP)
    q = abs(float(r.adhesion_ratio(OP.creepage, LAW, OP.rolling_speed_m_s))) * LAW.normal_load_n
    assert paper == pytest.approx(q / np.sqrt(1.6e8 * 3.1), rel=1e-12)
    seen_a_little = r.ModalDOF(3.1, 1.6e8, 42.0, lateral=0.1, normal=1.0)
    assert initial_amplitude(seen_a_little, LAW, OP) == pytest.approx(0.01 * paper, rel=1e-12)
