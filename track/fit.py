"""A receptance as a sum of passive modal terms: the form a time-domain model and a
linear eigen-solver take.

Each term is a mass, spring and damper, alpha_j(w) = r_j / (w_j^2 - w^2 + 2 i zeta_j w_j w)
with r_j = 1 / m_j >= 0: stable and passive by construction (its imaginary part is never
positive). The poles w_j sit on a logarithmic grid over the band (two frequencies per
octave, one below and one above it for the stiffness-like and mass-like ends), each
offered with damping ratios from light to overdamped; where the fit is still off, the
same set is offered at the worst frequency (a resonance such as the rail's on its pads,
or the pinned-pinned one), until the error is within the target or the additions run
out. The residues r_j come from a non-negative least squares fit of the error relative
to the receptance's level (its rms magnitude over a third of an octave: a relative error
at an anti-resonance's zero would weigh a dip no model resolves above everything else).
It is a vector fit with its poles placed rather than relocated: simpler, and passive
without a constraint to enforce. Hysteretic supports are not exactly causal, which a sum
of causal terms cannot follow everywhere: the error is stated with every fit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import nnls

__all__ = ["ModalFit", "fit_receptance", "level"]

#: Pole frequencies per octave on the grid (one below and one above the band too), each
#: offered with every damping ratio of DAMPING_RATIOS: the fit keeps those it needs
POLES_PER_OCTAVE, DAMPING_RATIOS = 2, (0.03, 0.1, 0.3, 1.0)
#: The largest error of a fit relative to the receptance's level [-], and the most pole
#: frequencies it may add for it (each at the frequency where the fit is worst)
TARGET_ERROR, MAX_ADDED_POLES = 0.1, 16


@dataclass(frozen=True)
class ModalFit:
    """A receptance fitted by modal terms (module docstring).

    Attributes
    ----------
    frequency_hz, damping_ratio, modal_mass_kg : numpy.ndarray
        Each term's natural frequency [Hz], damping ratio [-] and modal mass [kg].
    band_hz : tuple of float
        The band fitted [Hz].
    max_relative_error : float
        The largest |fit - alpha| over the fitted frequencies, relative to alpha's rms
        magnitude over a third of an octave around each [-].
    """

    frequency_hz: np.ndarray
    damping_ratio: np.ndarray
    modal_mass_kg: np.ndarray
    band_hz: tuple[float, float]
    max_relative_error: float

    def __call__(self, frequencies_hz: ArrayLike) -> np.ndarray:
        """The fitted receptance [m/N] at ``frequencies_hz`` (complex allowed: s / 2 pi i)."""
        w = 2 * math.pi * np.asarray(frequencies_hz)[..., None]
        wj = 2 * math.pi * self.frequency_hz
        terms = 1.0 / (self.modal_mass_kg * (wj**2 - w**2 + 2j * self.damping_ratio * wj * w))
        return terms.sum(axis=-1)

    @property
    def poles(self) -> int:
        return len(self.frequency_hz)


def _columns(f: np.ndarray, fj: np.ndarray, zj: np.ndarray) -> np.ndarray:
    w, wj = 2 * math.pi * f[:, None], 2 * math.pi * fj[None, :]
    return 1.0 / (wj**2 - w**2 + 2j * zj[None, :] * wj * w)


def level(f: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """The rms magnitude of ``alpha`` over a third of an octave around each frequency."""
    mag2 = np.abs(alpha) ** 2
    out = np.empty(len(f))
    for i, fi in enumerate(f):
        sel = (f > fi * 2 ** (-1 / 6)) & (f < fi * 2 ** (1 / 6))
        out[i] = math.sqrt(float(mag2[sel].mean()))
    return out


def _solve(
    f: np.ndarray, alpha: np.ndarray, ref: np.ndarray, fj: np.ndarray, zj: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Non-negative residues minimising the error relative to ``ref``; the errors."""
    c = _columns(f, fj, zj)
    a = c / ref[:, None]
    b = alpha / ref
    scale = np.abs(a).max(axis=0)
    r, _ = nnls(np.vstack([a.real, a.imag]) / scale, np.concatenate([b.real, b.imag]), maxiter=20 * len(fj))
    r = r / scale
    return r, np.abs(c @ r - alpha) / ref


def fit_receptance(frequencies_hz: ArrayLike, alpha: ArrayLike) -> ModalFit:
    """Fit ``alpha`` [m/N] (complex, exp(+i w t), at ``frequencies_hz`` [Hz], ascending)
    by passive modal terms (module docstring).

    Examples
    --------
    >>> import numpy as np
    >>> f = np.geomspace(20, 5000, 200)
    >>> w = 2 * np.pi * f
    >>> one = 1 / (1e3 * ((2 * np.pi * 300) ** 2 - w**2 + 2j * 0.1 * 2 * np.pi * 300 * w))
    >>> fit = fit_receptance(f, one)
    >>> fit.max_relative_error < 0.1
    True
    """
    f = np.asarray(frequencies_hz, float)
    alpha = np.asarray(alpha, complex)
    ref = level(f, alpha)
    lo, hi = float(f[0]), float(f[-1])
    n = max(2, int(math.ceil(math.log2(hi / lo) * POLES_PER_OCTAVE)) + 1)
    grid = np.concatenate([[lo / 4], np.geomspace(lo, hi, n), [hi * 1.5]])
    zetas = np.asarray(DAMPING_RATIOS, float)
    fj, zj = np.repeat(grid, len(zetas)), np.tile(zetas, len(grid))
    r, error = _solve(f, alpha, ref, fj, zj)
    for _ in range(MAX_ADDED_POLES):
        if error.max() <= TARGET_ERROR:
            break
        worst = float(f[int(np.argmax(error))])
        fj, zj = np.append(fj, np.full(len(zetas), worst)), np.append(zj, zetas)
        r, error = _solve(f, alpha, ref, fj, zj)
    keep = r > 0
    return ModalFit(fj[keep], zj[keep], 1.0 / r[keep], (lo, hi), float(error.max()))
