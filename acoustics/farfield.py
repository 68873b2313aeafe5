"""Far from the wheel: the directivity, the pressure at a distance from the wheel centre,
and the sound power as the intensity integrated over a sphere.

Beyond a few wavelengths and wheel sizes the pressure of a harmonic is
``p ~ D(theta) cos(n phi) e^{-jkR} / R`` (``SoundField.far_field``): ``D`` is the
directivity in the meridian plane (theta from the +z axis, the wheel's axis) and
``cos(n phi)`` its variation around the axis (n nodal diameters: 2n lobes). A harmonic
with n >= 1 is silent on the axis. The pressure at a finite distance comes from the
Kirchhoff-Helmholtz integral over the body (``SoundField.pressure_at``), exact at any
distance; integrating its intensity over a sphere gives the sound power independently
of the far-field formula the solver uses.
"""

from __future__ import annotations

import math

import numpy as np

from .helmholtz import SoundField

__all__ = [
    "DIRECTIVITY_ANGLES",
    "directivity",
    "distant_mean_squares_pa2",
    "loudest_angle_rad",
    "pressure_at_distance",
    "sphere_power_w",
]

#: The meridian angles the directivity is sampled at, 0 (+z axis) to pi (-z axis)
DIRECTIVITY_ANGLES = np.linspace(0.0, math.pi, 361)


def directivity(field: SoundField, angles_rad: np.ndarray = DIRECTIVITY_ANGLES) -> np.ndarray:
    """|D(theta)| [Pa m] at meridian angles from the +z axis (p ~ |D| / R far away, at an
    antinode of cos(n phi))."""
    return np.abs(field.far_field(np.cos(np.asarray(angles_rad, float))))


def loudest_angle_rad(directivities, amplitudes, angles_rad: np.ndarray = DIRECTIVITY_ANGLES) -> float:
    """The meridian angle [rad] where the far-field intensity of several harmonics
    together (their |D| on ``angles_rad`` and the amplitudes they are scaled by) is
    largest."""
    total = sum((a * np.asarray(d)) ** 2 for d, a in zip(directivities, amplitudes))
    return float(np.asarray(angles_rad)[int(np.argmax(total))])


def pressure_at_distance(field: SoundField, distance_m: float, angle_rad: float) -> complex:
    """P [Pa] (complex amplitude of cos(n phi)) at ``distance_m`` from the wheel centre,
    at meridian angle ``angle_rad`` from the +z axis."""
    point = distance_m * np.array([[math.sin(angle_rad), math.cos(angle_rad)]])
    return complex(field.pressure_at(point)[0])


def distant_mean_squares_pa2(
    fields: list[SoundField], amplitudes, distance_m: float, angle_rad: float
) -> np.ndarray:
    """The mean-square pressure [Pa^2] of each field (scaled by its amplitude) at
    ``distance_m`` from the wheel centre at meridian angle ``angle_rad``, at an antinode
    of cos(n phi)."""
    return np.array(
        [
            0.5 * (abs(pressure_at_distance(f, distance_m, angle_rad)) * a) ** 2
            for f, a in zip(fields, amplitudes)
        ]
    )


def sphere_power_w(field: SoundField, radius_m: float, points: int = 181) -> float:
    """The time-averaged power [W] through a sphere of ``radius_m`` about the wheel
    centre: the intensity |p|^2 / (2 rho c) of the exact pressure there, integrated
    over the sphere (trapezoids in theta on ``points`` angles, the cos(n phi)^2 average
    over phi in closed form: pi for n >= 1, 2 pi for n = 0). Far enough out (k R >> 1)
    it is the radiated power."""
    theta = np.linspace(0.0, math.pi, points)
    rz = radius_m * np.stack([np.sin(theta), np.cos(theta)], axis=1)
    p = field.pressure_at(rz)
    angular = 2 * math.pi if field.harmonic == 0 else math.pi
    intensity = np.abs(p) ** 2 / (2 * field.air.impedance)
    return float(angular * radius_m**2 * np.trapezoid(intensity * np.sin(theta), theta))
