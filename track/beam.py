"""A rail as a Timoshenko beam (shear and rotatory inertia) on supports, in one bending
direction, and its receptance at a point: the frequency-domain model of the track.

The rail is discretised by two-node Timoshenko elements (the interdependent-interpolation
stiffness, free of shear locking, with phi = 12 EI / (kappa G A l^2); the consistent
translational and rotatory mass), a finite length ``spans`` sleeper bays long with the
load at its middle, so that the waves the load sends out have decayed before they return
(the ends absorb: :data:`ABSORBING_SPANS`). Each support is a rail pad (complex stiffness
k_p (1 + i eta_p)) on a sleeper mass on ballast (k_b (1 + i eta_b)) to the ground; a
continuous support is a distributed complex stiffness s per unit length. The rail's own
loss factor eta_r makes its bending stiffness complex. Time dependence exp(+i omega t): a
receptance alpha = u / F, and its imaginary part is negative for a passive point.

:func:`continuous_receptance` is the closed form of the infinite beam on a continuous
support (the Euler-Bernoulli and the Timoshenko beam), which the finite model meets.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "BeamSection",
    "Supports",
    "continuous_receptance",
    "pinned_pinned_frequency_hz",
    "receptance",
]


@dataclass(frozen=True)
class BeamSection:
    """The rail bending in one direction.

    Attributes
    ----------
    youngs_modulus_pa, shear_modulus_pa, density_kg_m3 : float
    area_m2 : float
        Cross-section A [m^2].
    second_moment_m4 : float
        I about the bending axis [m^4].
    shear_coefficient : float
        kappa [-] (0.4 vertical, 0.538 lateral for UIC60).
    loss_factor : float
        eta_r of the rail's bending stiffness [-].
    """

    youngs_modulus_pa: float
    shear_modulus_pa: float
    density_kg_m3: float
    area_m2: float
    second_moment_m4: float
    shear_coefficient: float
    loss_factor: float = 0.01

    @property
    def bending_stiffness(self) -> complex:
        return self.youngs_modulus_pa * self.second_moment_m4 * (1 + 1j * self.loss_factor)

    @property
    def shear_stiffness(self) -> complex:
        return self.shear_coefficient * self.shear_modulus_pa * self.area_m2 * (1 + 1j * self.loss_factor)

    @property
    def mass_per_length(self) -> float:
        return self.density_kg_m3 * self.area_m2

    @property
    def rotatory_inertia(self) -> float:
        return self.density_kg_m3 * self.second_moment_m4


@dataclass(frozen=True)
class Supports:
    """Discrete supports every ``spacing_m``: a pad, a sleeper mass (per rail seat) and
    the ballast, in series to the ground.

    Attributes
    ----------
    spacing_m, pad_stiffness_n_m, pad_loss_factor, sleeper_mass_kg,
    ballast_stiffness_n_m, ballast_loss_factor : float
    """

    spacing_m: float
    pad_stiffness_n_m: float
    pad_loss_factor: float
    sleeper_mass_kg: float
    ballast_stiffness_n_m: float
    ballast_loss_factor: float

    def stiffness_n_m(self, omega: complex) -> complex:
        """The support's dynamic stiffness under the rail [N/m] at the complex
        frequency s = i omega (pad in series with the sleeper on the ballast)."""
        kp = self.pad_stiffness_n_m * (1 + 1j * self.pad_loss_factor)
        kb = self.ballast_stiffness_n_m * (1 + 1j * self.ballast_loss_factor)
        below = kb - self.sleeper_mass_kg * omega**2
        return kp * below / (kp + below)


def _element(beam: BeamSection, length: float) -> tuple[np.ndarray, np.ndarray]:
    """(stiffness, mass) of one Timoshenko element, DOFs (w1, theta1, w2, theta2)."""
    h, ei = length, beam.bending_stiffness
    phi = 12.0 * ei / (beam.shear_stiffness * h * h)
    k = (ei / ((1 + phi) * h**3)) * np.array(
        [
            [12, 6 * h, -12, 6 * h],
            [6 * h, (4 + phi) * h * h, -6 * h, (2 - phi) * h * h],
            [-12, -6 * h, 12, -6 * h],
            [6 * h, (2 - phi) * h * h, -6 * h, (4 + phi) * h * h],
        ]
    )
    # the consistent mass of the same interpolation (Friedman & Kosmatka 1993): the
    # Euler-Bernoulli element's at phi = 0; an element far shorter than the rail's
    # height has phi >> 1, where the Euler-Bernoulli mass would be wrong
    p, c = phi, beam.mass_per_length * h / (210.0 * (1 + phi) ** 2)
    a, b = 70 * p * p + 147 * p + 78, (35 * p * p + 77 * p + 44) * h / 4
    d, e = 35 * p * p + 63 * p + 27, (35 * p * p + 63 * p + 26) * h / 4
    g, o = (7 * p * p + 14 * p + 8) * h * h / 4, (7 * p * p + 14 * p + 6) * h * h / 4
    m_t = c * np.array([[a, b, d, -e], [b, g, e, -o], [d, e, a, -b], [-e, -o, -b, g]])
    r, t = beam.rotatory_inertia / (30.0 * (1 + phi) ** 2 * h), (15 * p - 3) * h
    u, v = (10 * p * p + 5 * p + 4) * h * h, (5 * p * p - 5 * p - 1) * h * h
    m_r = r * np.array([[36, -t, -36, -t], [-t, u, t, v], [-36, t, 36, t], [-t, v, t, u]])
    return k, m_t + m_r


#: The model's ends absorb: over this many bays at each end the rail's loss factor rises
#: (quadratically, to ABSORBING_LOSS), so that a wave reaching an end fades instead of
#: returning to the load (above the support's resonances the rail's own loss hardly
#: attenuates it over the model's length)
ABSORBING_SPANS, ABSORBING_LOSS = 40, 2.0


def _assembly(
    beam: BeamSection, n_el: int, l_e: float, index: np.ndarray, n: int, bw: int, absorbing: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The band storage of the rail's stiffness, mass and consistent unit-foundation
    matrices (each (2 bw + 1, n)), the end elements' stiffness made lossy."""
    k_el, m_el = _element(beam, l_e)
    f_el = m_el_translational(l_e)
    x = np.arange(n_el) + 0.5
    depth = np.clip(np.maximum(absorbing - x, x - (n_el - absorbing)) / max(absorbing, 1), 0.0, 1.0)
    lossy = 1 + 1j * ABSORBING_LOSS * depth**2
    dofs = np.stack([index[:-1], index[:-1] + 1, index[1:], index[1:] + 1], axis=1)  # (n_el, 4)
    rows = bw + dofs[:, :, None] - dofs[:, None, :]
    cols = np.broadcast_to(dofs[:, None, :], rows.shape)
    bands = []
    for el, scale in ((k_el, lossy), (m_el, np.ones(n_el)), (f_el, np.ones(n_el))):
        ab = np.zeros((2 * bw + 1, n), dtype=complex)
        np.add.at(ab, (rows, cols), scale[:, None, None] * el[None, :, :])
        bands.append(ab)
    return bands[0], bands[1], bands[2]


def receptance(
    beam: BeamSection,
    supports: Supports | None,
    frequencies_hz: ArrayLike,
    at: float = 0.0,
    *,
    continuous_stiffness_n_m2: complex | None = None,
    spans: int = 160,
    elements_per_span: int = 10,
    complex_frequency: bool = False,
) -> np.ndarray:
    """The point receptance u / F [m/N] of the rail at ``at`` (a fraction of the span
    from a support: 0 at a support, 0.5 at midspan) for each frequency.

    Parameters
    ----------
    beam : BeamSection
    supports : Supports or None
        Discrete supports (None: a continuous support of ``continuous_stiffness_n_m2``
        per unit length, over the model's length).
    frequencies_hz : array_like
        Frequencies f [Hz]; with ``complex_frequency`` they are complex s / (2 pi i)
        (the receptance at s = 2 pi i f, for roots off the axis).
    at : float
        The load's position in the span [-], a multiple of 1 / ``elements_per_span``.
    spans, elements_per_span : int
        The finite model: its length in bays (its last :data:`ABSORBING_SPANS` at each
        end absorbing) and its elements per bay.

    Returns
    -------
    numpy.ndarray
        Complex receptances [m/N], exp(+i omega t).

    Examples
    --------
    >>> from track import UIC60_VERTICAL, TEST_TRACK_VERTICAL
    >>> a = receptance(UIC60_VERTICAL, TEST_TRACK_VERTICAL, [100.0])
    >>> bool(1e-9 < abs(a[0]) < 1e-8)
    True
    """
    f = np.atleast_1d(np.asarray(frequencies_hz, dtype=complex if complex_frequency else float))
    spacing = supports.spacing_m if supports is not None else 0.6
    ne = elements_per_span
    if abs(at * ne - round(at * ne)) > 1e-9 or not 0.0 <= at < 1.0:
        raise ValueError(f"at = {at:g}: the load sits on a node, a multiple of 1/{ne} of the span in [0, 1)")
    n_el = spans * ne
    n_nodes = n_el + 1
    supported = np.zeros(n_nodes, dtype=bool)
    if supports is not None:
        supported[::ne] = True
    # DOF order: node i's (w, theta), then its sleeper where supported: a band of 4
    index = np.concatenate([[0], np.cumsum(2 + supported[:-1])]).astype(int)
    n = int(index[-1] + 2 + supported[-1])
    bw = 4
    k_band, m_band, f_band = _assembly(
        beam, n_el, spacing / ne, index, n, bw, min(ABSORBING_SPANS, spans // 3) * ne
    )
    load = index[(spans // 2) * ne + int(round(at * ne))]
    from scipy.linalg import solve_banded  # here: a design's file is read without SciPy

    rhs = np.zeros(n, dtype=complex)
    rhs[load] = 1.0
    w_dofs = index[supported]
    s_dofs = w_dofs + 2
    out = np.empty(len(f), dtype=complex)
    for q, fq in enumerate(f):
        omega = 2 * math.pi * fq
        ab = k_band - omega**2 * m_band
        if continuous_stiffness_n_m2 is not None:
            ab = ab + continuous_stiffness_n_m2 * f_band
        if supports is not None:
            kp = supports.pad_stiffness_n_m * (1 + 1j * supports.pad_loss_factor)
            kb = supports.ballast_stiffness_n_m * (1 + 1j * supports.ballast_loss_factor)
            ab[bw, w_dofs] += kp
            ab[bw + 2, w_dofs] -= kp  # row s, column w
            ab[bw - 2, s_dofs] -= kp  # row w, column s
            ab[bw, s_dofs] += kp + kb - supports.sleeper_mass_kg * omega**2
        out[q] = solve_banded((bw, bw), ab, rhs, check_finite=False)[load]
    return out


def m_el_translational(length: float) -> np.ndarray:
    """The consistent matrix of a distributed spring of unit stiffness per length over one
    element (the translational mass matrix per unit mass per length)."""
    h = length
    return (
        h
        / 420.0
        * np.array(
            [
                [156, 22 * h, 54, -13 * h],
                [22 * h, 4 * h * h, 13 * h, -3 * h * h],
                [54, 13 * h, 156, -22 * h],
                [-13 * h, -3 * h * h, -22 * h, 4 * h * h],
            ]
        )
    )


def continuous_receptance(
    beam: BeamSection, stiffness_n_m2: complex, frequencies_hz: ArrayLike, timoshenko: bool = True
) -> np.ndarray:
    """The closed-form point receptance [m/N] of an infinite beam on a continuous support
    of complex stiffness ``stiffness_n_m2`` per unit length: the two wave pairs of the
    Timoshenko beam (or the Euler-Bernoulli beam: ``timoshenko`` False) that decay away
    from the load, their amplitudes from the symmetry (no slope under the load) and the
    shear force's jump.

    The wavenumbers k (waves exp(-i k x)) solve
    EI k^4 - (rho I w^2 + q EI / (kappa G A)) k^2 - q (1 - rho I w^2 / (kappa G A)) = 0,
    q = rho A w^2 - s."""
    f = np.atleast_1d(np.asarray(frequencies_hz, float))
    ei = beam.bending_stiffness
    gak = beam.shear_stiffness if timoshenko else np.inf
    rho_i = beam.rotatory_inertia if timoshenko else 0.0
    out = np.empty(len(f), dtype=complex)
    for n, fq in enumerate(f):
        w2 = (2 * math.pi * fq) ** 2
        q = beam.mass_per_length * w2 - stiffness_n_m2
        if math.isinf(abs(gak)):
            k2 = np.array([np.sqrt(q / ei), -np.sqrt(q / ei)], dtype=complex)
            shear = None
        else:
            b = -(rho_i * w2 + q * ei / gak)
            c = -q * (1 - rho_i * w2 / gak)
            k2 = np.roots([ei, b, c]).astype(complex)
            shear = gak
        ks = []
        for kk in k2:
            k = np.sqrt(kk)
            ks.append(k if k.imag < 0 else -k)  # exp(-i k x) decays for x > 0
        k1, k2_ = ks
        if shear is None:  # Euler-Bernoulli: theta = w', shear force -EI w'''
            # w = A1 e^{-i k1 x} + A2 e^{-i k2 x}; w'(0) = 0; the shear force -EI w'''(0+) is half the load
            m = np.array([[-1j * k1, -1j * k2_], [-ei * (1j * k1**3), -ei * (1j * k2_**3)]])
        else:
            # theta_j = r_j w_j with r_j = (kGA k_j^2 - q) / (i k_j kGA); theta(0) = 0;
            # the shear force kGA (w' - theta) at 0+ carries half the load
            r = [(shear * kj**2 - q) / (1j * kj * shear) for kj in (k1, k2_)]
            m = np.array([[r[0], r[1]], [shear * (-1j * k1 - r[0]), shear * (-1j * k2_ - r[1])]])
        amp = np.linalg.solve(m, np.array([0.0, -0.5]))
        out[n] = amp.sum()
    return out


def pinned_pinned_frequency_hz(beam: BeamSection, span_m: float) -> float:
    """The first bending frequency [Hz] of a simply supported Timoshenko span (mode
    sin(pi x / L)): the rail's pinned-pinned resonance between two sleepers."""
    k2 = (math.pi / span_m) ** 2
    ei, gak = (
        beam.youngs_modulus_pa * beam.second_moment_m4,
        beam.shear_coefficient * beam.shear_modulus_pa * beam.area_m2,
    )
    rho_a, rho_i = beam.mass_per_length, beam.rotatory_inertia
    # the dispersion relation with q = rho A w^2 (no support), a quadratic in w^2
    a = rho_a * rho_i / gak
    b = -(rho_i * k2 + rho_a + rho_a * ei * k2 / gak)
    c = ei * k2 * k2
    w2 = min(r.real for r in np.roots([a, b, c]) if r.real > 0)
    return math.sqrt(w2) / (2 * math.pi)
