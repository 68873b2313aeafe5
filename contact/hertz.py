"""Hertz contact ellipse and Kalker's lateral creep coefficient C22.

Geometry convention (Johnson, *Contact Mechanics*, 1985, ch. 4): the gap between
two convex bodies near the first point of contact is ``h = A x^2 + B y^2`` with
x the rolling (longitudinal) direction and y the lateral (axial) direction::

    A = (1/R1  + 1/R2 ) / 2      curvatures in the rolling plane
    B = (1/R1t + 1/R2t) / 2      curvatures in the transverse plane

The contact is an ellipse with semi-axis ``a`` along rolling and ``b`` across.
The *larger* semi-axis lies along the direction of the *smaller* relative curvature.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .numerics import elliptic_ke, find_root

__all__ = ["HertzContact", "KalkerCoefficients", "hertz_contact", "kalker_c22", "kalker_coefficients"]


@dataclass(frozen=True)
class HertzContact:
    """Hertz contact ellipse between two elastic bodies of the same material.

    Attributes
    ----------
    semi_axis_a_m : semi-axis along the rolling direction, m.
    semi_axis_b_m : semi-axis across rolling (lateral / axial), m.
    max_pressure_pa : peak pressure p0 = 3 W / (2 pi a b), Pa.
    mean_pressure_pa : W / (pi a b), Pa.
    eccentricity : e = sqrt(1 - (minor/major)^2), dimensionless.
    orientation : "major axis along rolling" or "major axis across rolling".
    orientation_angle_rad : angle of the major axis from the rolling direction, rad
        (0 or pi/2; the principal curvature planes are assumed aligned).
    normal_load_n, youngs_modulus_pa, poissons_ratio : the inputs, N, Pa, -.

    Examples
    --------
    >>> h = hertz_contact(0.213, 0.3, 0.085, 0.04, 175e9, 0.28, 1000.0)
    >>> round(1e3 * h.semi_axis_a_m, 3), round(1e3 * h.semi_axis_b_m, 3)  # Table 1: 0.853, 0.594 mm
    (0.853, 0.594)
    """

    semi_axis_a_m: float
    semi_axis_b_m: float
    max_pressure_pa: float
    mean_pressure_pa: float
    eccentricity: float
    orientation: str
    orientation_angle_rad: float
    normal_load_n: float
    youngs_modulus_pa: float
    poissons_ratio: float

    @property
    def a_over_b(self) -> float:
        """Aspect ratio a/b (rolling over lateral semi-axis), dimensionless."""
        return self.semi_axis_a_m / self.semi_axis_b_m

    @property
    def area_m2(self) -> float:
        """Contact area pi a b, m^2."""
        return math.pi * self.semi_axis_a_m * self.semi_axis_b_m

    @property
    def shear_modulus_pa(self) -> float:
        """G = E / 2(1 + nu), Pa."""
        return self.youngs_modulus_pa / (2.0 * (1.0 + self.poissons_ratio))

    @property
    def approach_m(self) -> float:
        """Hertz approach of the two bodies' distant points, delta0 = p0 b K(e) / E* [m],
        b the semi-minor axis, K the complete elliptic integral of the first kind and
        E* = E / (2 (1 - nu^2)) for two bodies of the same material (Johnson 1985,
        ch. 4)."""
        minor = min(self.semi_axis_a_m, self.semi_axis_b_m)
        k, _ = elliptic_ke(self.eccentricity**2)
        e_star = self.youngs_modulus_pa / (2.0 * (1.0 - self.poissons_ratio**2))
        return self.max_pressure_pa * minor * k / e_star

    @property
    def normal_stiffness_n_m(self) -> float:
        """The linearised Hertz spring k_H = dN/d(delta) = 3 W / (2 delta0) [N/m]
        (N = W (delta / delta0)^(3/2))."""
        return 1.5 * self.normal_load_n / self.approach_m


#: Below this elliptic parameter m = e^2, K(m) - E(m) (about pi m / 4) is evaluated from
#: its power series: from ``K - E`` it would lose log10(1/m) digits, and the
#: near-circular contact (curvature sums a hair apart) would be computed from noise.
_M_SERIES = 1e-3


def _k_minus_e_over_m(m: float) -> float:
    """(K(m) - E(m)) / m, m = e^2 (pi / 4 at m = 0)."""
    if m < _M_SERIES:  # K - E = pi/2 (m/2 + 3m^2/16 + 15m^3/128 + 175m^4/2048 + ...)
        return 0.5 * math.pi * (0.5 + m * (3 / 16 + m * (15 / 128 + m * 175 / 2048)))
    K, E = elliptic_ke(m)
    return (K - E) / m


def _curvature_excess(m: float) -> float:
    """B'/A' - 1 = [E/(1 - m) - K] / (K - E) - 1 of the Hertz ellipse with parameter m
    (Johnson eq. 4.39), ~ 3m/4 for a near circle."""
    if m < _M_SERIES:  # ratio of the two series, truncated at m^4 (error < 1e-12)
        return (
            0.75 * m * (1 + m * (1.25 + m * 175 / 128)) / (1 + m * (0.375 + m * (15 / 64 + m * 175 / 1024)))
        )
    K, Ee = elliptic_ke(m)
    return (Ee / (1.0 - m) - K) / (K - Ee) - 1.0


def _check_positive(name: str, value: float) -> float:
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return value


def hertz_contact(
    R1: float,
    R1t: float,
    R2: float,
    R2t: float,
    youngs_modulus: float,
    poissons_ratio: float,
    normal_load: float,
) -> HertzContact:
    """Hertz elliptical contact of two convex bodies of the same elastic material.

    Parameters
    ----------
    R1, R1t : rolling radius and transverse (crown) radius of body 1, m.
    R2, R2t : rolling radius and transverse radius of body 2, m.
        Use ``math.inf`` for a flat direction.
    youngs_modulus : E of both bodies, Pa.
    poissons_ratio : nu of both bodies, dimensionless (0 <= nu < 0.5).
    normal_load : W, N.

    Returns
    -------
    HertzContact
        The ellipse, its pressure and approach.

    Notes
    -----
    Method (Johnson 1985, sec. 4.2, eqs 4.39-4.40): with the major semi-axis
    ``c1``, minor ``c2``, ``e^2 = 1 - (c2/c1)^2`` and complete elliptic integrals
    K(m), E(m) of the parameter m = e^2 (arithmetic-geometric mean, contact.numerics)::

        B'/A' = [(c1/c2)^2 E - K] / (K - E)      (A' <= B' the two curvature sums)
        c1^3  = 3 W (K - E) / (2 pi E* e^2 A')   E* = E / 2(1 - nu^2)

    e is found with Brent's method. Table 1 of Liu & Meehan gives a = 0.853 mm (rolling),
    b = 0.594 mm; this returns 0.8534 mm and 0.5945 mm.

    Examples
    --------
    >>> h = hertz_contact(0.213, 0.3, 0.085, 0.04, 175e9, 0.28, 1000.0)
    >>> round(1e3 * h.semi_axis_a_m, 4), round(1e3 * h.semi_axis_b_m, 4)
    (0.8534, 0.5945)
    """
    E = _check_positive("youngs_modulus", youngs_modulus)
    W = _check_positive("normal_load", normal_load)
    nu = float(poissons_ratio)
    if not (0.0 <= nu < 0.5):
        raise ValueError(f"poissons_ratio must lie in [0, 0.5), got {nu!r}")
    radii = {"R1": R1, "R1t": R1t, "R2": R2, "R2t": R2t}
    for name, r in radii.items():
        if not (float(r) > 0.0):
            raise ValueError(f"{name} must be positive (convex body) or inf, got {r!r}")
    A = 0.5 * (1.0 / R1 + 1.0 / R2)  # rolling plane
    B = 0.5 * (1.0 / R1t + 1.0 / R2t)  # transverse plane
    if A <= 0.0 or B <= 0.0:
        raise ValueError("both relative curvatures must be positive (point contact)")
    e_star = E / (2.0 * (1.0 - nu * nu))
    small, large = (A, B) if A <= B else (B, A)
    excess = large / small - 1.0
    m = (
        0.0
        if excess <= 0.0
        else find_root(lambda x: _curvature_excess(x) - excess, 0.0, 1.0 - 1e-15, xtol=1e-300, rtol=1e-14)
    )
    major = (3.0 * W * _k_minus_e_over_m(m) / (2.0 * math.pi * e_star * small)) ** (1.0 / 3.0)
    minor = major * math.sqrt(1.0 - m)
    # the major axis lies along the direction of the smaller curvature sum
    if A <= B:
        a, b, orientation, angle = major, minor, "major axis along rolling", 0.0
    else:
        a, b, orientation, angle = minor, major, "major axis across rolling", math.pi / 2
    area = math.pi * a * b
    return HertzContact(
        semi_axis_a_m=float(a),
        semi_axis_b_m=float(b),
        max_pressure_pa=float(1.5 * W / area),
        mean_pressure_pa=float(W / area),
        eccentricity=float(math.sqrt(m)),
        orientation=orientation,
        orientation_angle_rad=angle,
        normal_load_n=W,
        youngs_modulus_pa=E,
        poissons_ratio=nu,
    )


# Kalker's lateral creep coefficient C22 (Kalker 1967 thesis, "On the rolling
# contact of two elastic bodies in the presence of dry friction"; Kalker 1990,
# "Three-dimensional elastic bodies in rolling contact", Kluwer; table reproduced
# in Johnson, Contact Mechanics, 1985, Table 8.1). Columns nu = 0, 0.25, 0.5.
# a: semi-axis along rolling, b: lateral. Rows first for a/b = 0.1 .. 0.9 (a < b),
# then the circle, then b/a = 0.9 .. 0.1 (a > b).
_KALKER_NU = np.array([0.0, 0.25, 0.5])
_KALKER_C22_A_LT_B = np.array(
    [  # a/b = 0.1, 0.2, ..., 0.9
        [2.51, 2.52, 2.53],
        [2.59, 2.63, 2.66],
        [2.68, 2.75, 2.81],
        [2.78, 2.88, 2.98],
        [2.88, 3.01, 3.14],
        [2.98, 3.14, 3.31],
        [3.09, 3.28, 3.48],
        [3.19, 3.41, 3.65],
        [3.29, 3.54, 3.82],
    ]
)
_KALKER_C22_CIRCLE = np.array([3.40, 3.67, 3.98])
_KALKER_C22_A_GT_B = np.array(
    [  # b/a = 0.9, 0.8, ..., 0.1
        [3.51, 3.81, 4.16],
        [3.65, 3.99, 4.39],
        [3.82, 4.21, 4.67],
        [4.06, 4.50, 5.04],
        [4.37, 4.90, 5.56],
        [4.84, 5.48, 6.31],
        [5.57, 6.40, 7.51],
        [6.96, 8.14, 9.79],
        [10.7, 12.8, 16.0],
    ]
)
# abscissa u: u = a/b - 1 for a <= b (-0.9 .. 0), u = 1 - b/a for a >= b (0 .. 0.9)
_KALKER_U = np.concatenate([np.arange(1, 10) / 10.0 - 1.0, [0.0], 1.0 - np.arange(9, 0, -1) / 10.0])
_KALKER_C22 = np.vstack([_KALKER_C22_A_LT_B, _KALKER_C22_CIRCLE, _KALKER_C22_A_GT_B])


def kalker_c22(a_over_b: float, poissons_ratio: float) -> float:
    """Kalker's lateral creep coefficient C22 for an ellipse of aspect a/b.

    Parameters
    ----------
    a_over_b : semi-axis along rolling over lateral semi-axis, dimensionless,
        within [0.1, 10] (Kalker's table range).
    poissons_ratio : nu, within [0, 0.5].

    Returns
    -------
    C22, dimensionless (lateral creep force = G a b C22 * lateral creepage).

    Source: Kalker, J.J. (1967), *On the rolling contact of two elastic bodies in
    the presence of dry friction*, thesis, TH Delft; Kalker (1990),
    *Three-dimensional elastic bodies in rolling contact*, Kluwer; tabulated in
    Johnson, *Contact Mechanics* (1985), Table 8.1, for nu = 0, 0.25, 0.5 against
    g = min(a/b, b/a). Which axis is the rolling one matters: the table is
    indexed by a/b on the a < b side and by b/a on the a > b side. Interpolation is
    linear in g within each side and linear in nu (bilinear). For Table 1
    (a/b = 1.436, i.e. b/a = 0.696, nu = 0.28) this gives 4.27 (Liu & Meehan use
    3.14); reading the table on the wrong side (a/b = 0.696) would give 3.30.

    Examples
    --------
    >>> kalker_c22(1.0, 0.25)
    3.67
    """
    g = float(a_over_b)
    nu = float(poissons_ratio)
    if not (0.1 - 1e-12 <= g <= 10.0 + 1e-12):
        raise ValueError(f"a_over_b must lie in [0.1, 10] (Kalker's table), got {g!r}")
    if not (0.0 <= nu <= 0.5):
        raise ValueError(f"poissons_ratio must lie in [0, 0.5], got {nu!r}")
    u = g - 1.0 if g <= 1.0 else 1.0 - 1.0 / g
    per_nu = np.array([np.interp(u, _KALKER_U, _KALKER_C22[:, j]) for j in range(3)])
    return float(np.interp(nu, _KALKER_NU, per_nu))


# Kalker's longitudinal C11 and lateral-spin C23 coefficients (the same table: Kalker 1967;
# Johnson 1985, Table 8.1; Iwnicki (ed.) 2006, Handbook of Railway Vehicle Dynamics, ch. 4),
# in the rows and columns of C22 above. At nu = 0, C11 = C22 (Kalker).
_KALKER_C11 = np.array(
    [
        [2.51, 3.31, 4.85],
        [2.59, 3.37, 4.81],
        [2.68, 3.44, 4.80],
        [2.78, 3.53, 4.82],
        [2.88, 3.62, 4.83],
        [2.98, 3.72, 4.91],
        [3.09, 3.81, 4.97],
        [3.19, 3.91, 5.05],
        [3.29, 4.01, 5.12],
        [3.40, 4.12, 5.20],
        [3.51, 4.22, 5.30],
        [3.65, 4.36, 5.42],
        [3.82, 4.54, 5.58],
        [4.06, 4.78, 5.80],
        [4.37, 5.10, 6.11],
        [4.84, 5.57, 6.57],
        [5.57, 6.34, 7.34],
        [6.96, 7.78, 8.82],
        [10.7, 11.7, 12.9],
    ]
)
_KALKER_C23 = np.array(
    [
        [0.334, 0.473, 0.731],
        [0.483, 0.603, 0.809],
        [0.607, 0.715, 0.889],
        [0.720, 0.823, 0.977],
        [0.827, 0.929, 1.07],
        [0.930, 1.03, 1.18],
        [1.03, 1.14, 1.29],
        [1.13, 1.25, 1.40],
        [1.23, 1.36, 1.51],
        [1.33, 1.47, 1.63],
        [1.44, 1.59, 1.77],
        [1.58, 1.75, 1.94],
        [1.76, 1.95, 2.18],
        [2.01, 2.23, 2.50],
        [2.35, 2.62, 2.96],
        [2.88, 3.24, 3.70],
        [3.79, 4.32, 5.01],
        [5.72, 6.63, 7.89],
        [12.2, 14.6, 18.0],
    ]
)


@dataclass(frozen=True)
class KalkerCoefficients:
    """Kalker's linear creep coefficients of one ellipse [-]: the longitudinal force is
    G a b C11 xi_x, the lateral G a b C22 xi_y + G (a b)^(3/2) C23 phi (spin phi [1/m]).

    Attributes
    ----------
    c11, c22, c23 : float
        The longitudinal, lateral and lateral-spin coefficients, dimensionless.

    Examples
    --------
    >>> KalkerCoefficients(4.12, 3.67, 1.47).c22
    3.67"""

    c11: float
    c22: float
    c23: float


def kalker_coefficients(a_over_b: float, poissons_ratio: float) -> KalkerCoefficients:
    """C11, C22 and C23 for an ellipse of aspect ``a_over_b`` (rolling over lateral),
    clamped to Kalker's table (0.1 to 10), interpolated as :func:`kalker_c22`.

    Parameters
    ----------
    a_over_b : float
        The ellipse's semi-axis along rolling over the lateral one, dimensionless.
    poissons_ratio : float
        nu, dimensionless.

    Returns
    -------
    KalkerCoefficients
        C11, C22, C23, dimensionless.

    Examples
    --------
    >>> k = kalker_coefficients(1.0, 0.25)
    >>> k.c11, k.c22, k.c23
    (4.12, 3.67, 1.47)
    """
    g = min(max(float(a_over_b), 0.1), 10.0)
    nu = float(poissons_ratio)
    if not (0.0 <= nu <= 0.5):
        raise ValueError(f"poissons_ratio must lie in [0, 0.5], got {nu!r}")
    u = g - 1.0 if g <= 1.0 else 1.0 - 1.0 / g

    def read(table: np.ndarray) -> float:
        per_nu = np.array([np.interp(u, _KALKER_U, table[:, j]) for j in range(3)])
        return round(float(np.interp(nu, _KALKER_NU, per_nu)), 12)

    return KalkerCoefficients(read(_KALKER_C11), read(_KALKER_C22), read(_KALKER_C23))
