"""The rules every FE solver applies the same way, each in one place.

- material: the Lame constants of an isotropic material;
- free wheels: the eigen-solver's negative shift and the rigid-body threshold, as
  fractions of the scale-free reference frequency ``c_s / (2 pi R1)`` (c_s the shear
  wave speed, R1 the rolling radius; 2.4 kHz for Table 1), so a 20 mm and a 2 m wheel
  are treated alike;
- symmetry: a wheel is mirror-symmetric about z = 0 when its web is centred on the rim;
  a mode of such a wheel is in-plane (a node at the contact) when most of its squared
  amplitude has u_r, u_theta even and u_z odd in z;
- labels: nodal circles are the sign changes of the dominant component along the web's
  mid-surface, samples below :data:`CIRCLE_THRESHOLD` of the peak ignored (the clamped
  bore, or a numerically tiny lobe, is not a circle).
"""

from __future__ import annotations

import math

import numpy as np

from geometry.profile import half_profile

__all__ = [
    "harmonics_done",
    "CIRCLE_THRESHOLD",
    "FREE_SHIFT_REL",
    "RIGID_TOL",
    "SYMMETRY_RTOL",
    "count_sign_changes",
    "free_shift",
    "in_plane_fraction",
    "is_mirror_symmetric",
    "lame",
    "reference_frequency",
    "rigid_frequency",
]

#: A free-free mode below ``RIGID_TOL * reference_frequency`` is a rigid-body mode
#: (numerically they come out at ~1e-7 of it; the first elastic mode of a free wheel is
#: at ~0.1 of it and more).
RIGID_TOL = 1e-3
#: Shift of a free-free solve, ``-(2 pi FREE_SHIFT_REL f_ref)^2``: K is singular there.
FREE_SHIFT_REL = 0.05
#: A profile within this fraction of the rolling radius of its mirror image is symmetric.
SYMMETRY_RTOL = 1e-12
#: Sign changes of samples below this fraction of the peak are not nodal circles.
CIRCLE_THRESHOLD = 0.05


def lame(youngs_modulus: float, poissons_ratio: float) -> tuple[float, float]:
    """(lambda, mu) [Pa] of an isotropic material from E [Pa] and nu [-]."""
    E, nu = youngs_modulus, poissons_ratio
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


def reference_frequency(design) -> float:
    """``c_s / (2 pi R1)`` [Hz]: the frequency scale of the scale-free thresholds."""
    return math.sqrt(design.shear_modulus / design.density) / (2 * math.pi * design.rolling_radius)


def free_shift(design) -> float:
    """Eigenvalue shift [rad^2/s^2] of a free-free solve (a clamped one uses 0)."""
    return -((2 * math.pi * FREE_SHIFT_REL * reference_frequency(design)) ** 2)


def rigid_frequency(design) -> float:
    """Frequency [Hz] below which a free-free mode is a rigid-body motion."""
    return RIGID_TOL * reference_frequency(design)


def is_mirror_symmetric(design) -> bool:
    """True when the wheel's profile is its own mirror image about z = 0 (a centred,
    flat web; an outline drawn symmetric), to ``SYMMETRY_RTOL`` of the rolling radius."""
    return half_profile(design).is_mirror_symmetric(SYMMETRY_RTOL)


def count_sign_changes(values: np.ndarray, threshold: float = CIRCLE_THRESHOLD) -> int:
    """Sign changes of ``values`` ignoring samples below ``threshold * max|values|``."""
    v = np.asarray(values, dtype=float)
    peak = float(np.max(np.abs(v))) if v.size else 0.0
    if peak == 0.0:
        return 0
    s = np.sign(v[np.abs(v) >= threshold * peak])
    return int(np.count_nonzero(s[1:] != s[:-1]))


def in_plane_fraction(u: np.ndarray, u_mirror: np.ndarray, weight: np.ndarray | float = 1.0) -> float:
    """Share of a mode's squared amplitude with in-plane parity about z = 0.

    ``u`` and ``u_mirror``: cylindrical components ``(u_r, u_z, u_theta)`` along axis -2
    (shape ``(..., 3, N)``, leading axes e.g. the members of a pair) at N points and at
    their mirror images (r, -z); ``weight`` per point (e.g. r). In-plane parity: u_r and
    u_theta even, u_z odd. Returns ~1 for an in-plane mode of a mirror-symmetric wheel
    (u_z = 0 on the mid-plane, so at the contact), ~0 for an out-of-plane one.
    """
    u, um = np.asarray(u), np.asarray(u_mirror)
    even, odd = 0.5 * (u + um), 0.5 * (u - um)
    sq_in = np.sum(weight * (even[..., 0, :] ** 2 + odd[..., 1, :] ** 2 + even[..., 2, :] ** 2))
    sq_out = np.sum(weight * (odd[..., 0, :] ** 2 + even[..., 1, :] ** 2 + odd[..., 2, :] ** 2))
    total = float(sq_in + sq_out)
    return float(sq_in) / total if total > 0 else 0.0


def harmonics_done(n: int, found_hz: list[float], all_hz: list[float], k: int | None) -> bool:
    """Whether the search over circumferential harmonics stops after harmonic ``n``
    (whose in-band frequencies are ``found_hz``; ``all_hz`` holds every harmonic's so
    far): from n = 2 on, when the harmonic has nothing in the band, or, for the ``k``
    lowest, when its lowest mode is above the k-th lowest found. Frequencies rise with
    n beyond the first few harmonics of a wheel."""
    if n < 2:
        return False
    if not found_hz:
        return True
    return k is not None and len(all_hz) >= k and min(found_hz) > sorted(all_hz)[k - 1]
