"""The levels of a circumferential harmonic seen by a fixed microphone."""

import math

import pytest

from acoustics.waves import pressure_amplitude, radiated_power


def test_standing_wave_follows_cos_n_theta():
    # exact: |P cos(n theta)|; at theta = pi/(2n) a node
    assert pressure_amplitude(2.0, 3, 0.0) == pytest.approx(2.0)
    assert pressure_amplitude(2.0, 3, math.pi / 6) == pytest.approx(0.0, abs=1e-12)
    assert pressure_amplitude(2.0, 2, math.pi / 8) == pytest.approx(2.0 * math.cos(math.pi / 4))


def test_travelling_wave_has_the_antinode_everywhere_and_twice_the_power():
    assert pressure_amplitude(1.5j, 3, math.pi / 6, travelling=True) == pytest.approx(1.5)
    assert radiated_power(1e-3, 2, travelling=True) == pytest.approx(2e-3)
    # an axisymmetric (n = 0) wave has no partner: it does not travel
    assert radiated_power(1e-3, 0, travelling=True) == pytest.approx(1e-3)
    assert radiated_power(1e-3, 2) == pytest.approx(1e-3)
