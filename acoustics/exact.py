"""Exact radiation of a sphere: the reference the axisymmetric solver is checked against.

A sphere of radius a whose radial surface velocity is ``V0 P_l^m(cos t) cos(m phi)``
(time convention e^{j w t}) radiates ``p = A h_l(k rho) P_l^m(cos t) cos(m phi)`` with
h_l = j_l - j y_l the outgoing spherical Hankel function and
``A = -j rho0 c0 V0 / h_l'(k a)`` (docs/theory.md, sound radiation). P_l^m is SciPy's associated
Legendre function (Condon-Shortley phase included, on both sides alike).
"""

from __future__ import annotations

import math

import numpy as np

from .medium import AIR, Air
from .surface import Surface

__all__ = ["sphere_pressure", "sphere_sound_power", "sphere_surface"]


def _hankel(l_: int, x, derivative: bool = False):
    from scipy.special import spherical_jn, spherical_yn

    return spherical_jn(l_, x, derivative) - 1j * spherical_yn(l_, x, derivative)


def _amplitude(l_: int, radius: float, k: float, v0: float, air: Air) -> complex:
    return -1j * air.impedance * v0 / _hankel(l_, k * radius, derivative=True)


def sphere_pressure(
    l_: int, m: int, radius: float, k: float, points_rz, v0: float = 1.0, air: Air = AIR
) -> np.ndarray:
    """p [Pa] (amplitude of cos(m phi)) at (r, z) points outside the sphere."""
    from scipy.special import lpmv

    pts = np.atleast_2d(np.asarray(points_rz, dtype=float))
    rho = np.hypot(pts[:, 0], pts[:, 1])
    return _amplitude(l_, radius, k, v0, air) * _hankel(l_, k * rho) * lpmv(m, l_, pts[:, 1] / rho)


def sphere_sound_power(l_: int, m: int, radius: float, k: float, v0: float = 1.0, air: Air = AIR) -> float:
    """Radiated power [W]: (pi or 2 pi) / 2 Re(p conj(v)) a^2 integral of (P_l^m)^2 sin t dt."""
    norm = 2.0 / (2 * l_ + 1) * math.factorial(l_ + m) / math.factorial(l_ - m)
    angular = 2 * math.pi if m == 0 else math.pi
    p_over_v = _amplitude(l_, radius, k, v0, air) * _hankel(l_, k * radius) / v0
    return angular * 0.5 * float(np.real(p_over_v)) * v0 * v0 * radius * radius * norm


def sphere_surface(l_: int, m: int, radius: float, v0: float = 1.0, segments: int = 120) -> Surface:
    """The sphere's meridian (a chain from the south pole to the north pole on the axis)
    with the radial velocity ``v0 P_l^m(cos t)``."""
    from scipy.special import lpmv

    t = np.linspace(math.pi, 0.0, segments + 1)
    pts = np.stack([radius * np.sin(t), radius * np.cos(t)], axis=1)
    vr = v0 * lpmv(m, l_, np.cos(t))
    vel = np.stack([vr * np.sin(t), vr * np.cos(t)], axis=1).astype(complex)
    return Surface(pts, vel, m)
