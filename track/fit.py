"""A receptance as a rational function of s: the form a time-domain model and a linear
eigen-solver take (``reduced.counter_body.BodyModel``).

The fit is a vector fit (Gustavsen & Semlyen 1999): poles relocated iteratively from a
logarithmic start over the band, each unstable one reflected into the left half-plane and
none slower than the band's lowest frequency (what the band does not show, a pole may not
model), then the residues by weighted least squares. Three constraints make it a counter-body:

- **no feedthrough**: the residues' leading coefficients sum to zero (the receptance falls
  as 1/s^2 far above the band, as a mass's does), so that the counter-body's velocity
  answers a force through its states only;
- **passive**: Im(alpha) <= 0 at every frequency on a grid a decade beyond the band each
  way and about every pole (a point of a passive structure only absorbs energy); where
  the least-squares fit is not, the offending frequencies are added as constraints
  Im(alpha) <= -1e-6 max|alpha| of a quadratic programme until it is;
- **where it matters**: the error is weighted by the receptance's own level and by its
  mobility |omega alpha| relative to its largest, cubed (:data:`MOBILITY_EMPHASIS`): the
  contact's negative damping g moves a root of 1 + g s (H_wheel + alpha) = 0 as far as the
  counter-body's mobility is comparable with 1/|g|, which is near its resonance on its
  supports (a rail's on its pads, 100-600 Hz); elsewhere the wheel's modes decide. A
  floor (:data:`WEIGHT_FLOOR`) keeps the rest of the band in view, loosely: below 50 Hz
  and above 1 kHz the relative error reaches tens of per cent (the rail's mobility there
  is small beside the contact's 1/|g| or a wheel mode's), and the static compliance is
  not the rail's (a hysteretic support has none a causal model can reach).

A hysteretic support (a loss factor independent of frequency) is not causal: no rational
fit meets it everywhere, and the few per cent it misses off its resonance are what the
weights leave there. The roots the contact reaches are checked against the receptance's
own at complex frequencies in the tests (``tests/test_track.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["RationalFit", "fit_receptance", "level"]

#: Complex pole pairs the fit starts from (and keeps: real poles count one each)
POLE_PAIRS = 20
#: Relocation iterations of the poles
ITERATIONS = 40
#: The weight's emphasis on the receptance's mobility relative to its largest, and the
#: floor it never falls below (relative)
MOBILITY_EMPHASIS, WEIGHT_FLOOR = 3.0, 1e-3
#: The passivity grid: this many frequencies per decade, a decade beyond the band each way
#: (and about each pole, :func:`_passivity_grid`)
PASSIVITY_POINTS_PER_DECADE, PASSIVITY_MARGIN_DECADES = 200, 1.0
#: At most this many rounds of adding passivity equations, each setting Im(alpha) to
#: minus this fraction of the receptance's largest magnitude where it was positive
PASSIVITY_ROUNDS, PASSIVITY_TOLERANCE = 40, 1e-6


@dataclass(frozen=True, eq=False)
class RationalFit:
    """A receptance fitted by a rational function (module docstring).

    Attributes
    ----------
    poles : numpy.ndarray
        Real poles and one of each complex pair (Im > 0) [1/s], all in the left half-plane.
    residues : numpy.ndarray
        Their residues [m/N /s] (complex for a pair, with its conjugate for the other).
    band_hz : tuple of float
        The band fitted [Hz].
    max_relative_error : float
        The largest |fit - alpha| / |alpha| over the band's frequencies [-].
    weighted_error : float
        The largest error in the weights' norm (relative to the weights' largest) [-].
    """

    poles: np.ndarray
    residues: np.ndarray
    band_hz: tuple[float, float]
    max_relative_error: float
    weighted_error: float

    def __call__(self, frequencies_hz: ArrayLike) -> np.ndarray:
        """The fitted receptance [m/N] at ``frequencies_hz`` (complex allowed: s / 2 pi i)."""
        s = 2j * math.pi * np.asarray(frequencies_hz, complex)
        return _basis(np.atleast_1d(s), self.poles) @ _coefficients(self.poles, self.residues)

    @property
    def order(self) -> int:
        """Its states (two per pair)."""
        return int(sum(1 if p.imag == 0.0 else 2 for p in self.poles))


def _basis(s: np.ndarray, poles: np.ndarray) -> np.ndarray:
    """Real-coefficient columns: 1/(s - p) for a real pole; 1/(s - p) + 1/(s - p*) and
    i/(s - p) - i/(s - p*) for a pair."""
    cols = []
    for p in poles:
        if p.imag == 0.0:
            cols.append(1.0 / (s - p.real))
        else:
            cols.append(1.0 / (s - p) + 1.0 / (s - np.conj(p)))
            cols.append(1j / (s - p) - 1j / (s - np.conj(p)))
    return np.array(cols).T


def _coefficients(poles: np.ndarray, residues: np.ndarray) -> np.ndarray:
    out: list[float] = []
    for p, r in zip(poles, residues):
        out += [r.real] if p.imag == 0.0 else [r.real, r.imag]
    return np.array(out)


def _residues(poles: np.ndarray, x: np.ndarray) -> np.ndarray:
    out, k = [], 0
    for p in poles:
        if p.imag == 0.0:
            out.append(complex(x[k]))
            k += 1
        else:
            out.append(complex(x[k], x[k + 1]))
            k += 2
    return np.array(out)


def _leading(poles: np.ndarray) -> np.ndarray:
    """The row whose product with the coefficients is the sum of the leading coefficients
    (a pair's 2 Re r, a real pole's r): zero for no feedthrough."""
    row: list[float] = []
    for p in poles:
        row += [1.0] if p.imag == 0.0 else [2.0, 0.0]
    return np.array(row)


def _state(poles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    n = sum(1 if p.imag == 0.0 else 2 for p in poles)
    a, b, k = np.zeros((n, n)), np.zeros(n), 0
    for p in poles:
        if p.imag == 0.0:
            a[k, k], b[k] = p.real, 1.0
            k += 1
        else:
            a[k : k + 2, k : k + 2] = [[p.real, p.imag], [-p.imag, p.real]]
            b[k] = 2.0
            k += 2
    return a, b


def _split(lam: np.ndarray, lowest: float) -> np.ndarray:
    """Real poles and one of each conjugate pair, every one in the left half-plane and none
    slower than ``lowest`` [1/s]."""
    lam = np.where(lam.real > 0, -lam.real + 1j * lam.imag, lam)
    lam = np.where(np.abs(lam) < lowest, -lowest + 0j, lam)
    out = [complex(x.real, 0.0) if abs(x.imag) <= 1e-12 * abs(x) else x for x in lam]
    return np.array([x for x in out if x.imag >= 0.0])


#: Poles closer than this (relative) are one: the fit's basis cannot tell them apart
REPEATED_POLE = 1e-9


def _distinct(poles: np.ndarray) -> np.ndarray:
    """``poles`` less those repeating an earlier one to :data:`REPEATED_POLE`: the slowest
    allowed pole comes back several times from relocation, and a repeated pole adds a state
    that no force moves apart from its twin's (an eigenvalue of the counter-body's model
    repeated, and no new function fitted)."""
    kept: list[complex] = []
    for p in poles.tolist():
        if all(abs(p - q) > REPEATED_POLE * abs(p) for q in kept):
            kept.append(p)
    return np.array(kept, complex)


def _relocate(s: np.ndarray, h: np.ndarray, poles: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """One vector-fitting step: the zeros of the weighting function sigma(s) = 1 + sum
    c~/(s - p) fitted with sigma h = sum c/(s - p) become the new poles."""
    p = _basis(s, poles)
    n = p.shape[1]
    a = np.hstack([p, -h[:, None] * p]) * weight[:, None]
    b = h * weight
    ar, br = np.vstack([a.real, a.imag]), np.concatenate([b.real, b.imag])
    scale = np.linalg.norm(ar, axis=0)
    scale[scale == 0.0] = 1.0
    x, *_ = np.linalg.lstsq(ar / scale, br, rcond=None)
    tilde = (x / scale)[n:]
    state, column = _state(poles)
    return _split(np.linalg.eigvals(state - np.outer(column, tilde)), float(np.abs(s).min()))


def _solve_residues(
    s: np.ndarray, h: np.ndarray, poles: np.ndarray, weight: np.ndarray, passive_at: np.ndarray, floor: float
) -> np.ndarray:
    """Weighted least squares for the coefficients, exactly with no feedthrough and with
    Im(alpha) <= -``floor`` at the frequencies ``passive_at`` [rad/s] where an earlier
    solution was not passive (a quadratic programme: the constraints hold where they
    bind, and leave the fit alone elsewhere)."""
    p = _basis(s, poles) * weight[:, None]
    a = np.vstack([p.real, p.imag])
    b = np.concatenate([(h * weight).real, (h * weight).imag])
    scale = np.linalg.norm(a, axis=0)
    scale[scale == 0.0] = 1.0
    a = a / scale
    lead = _leading(poles) / scale
    # the no-feedthrough constraint exactly: the coefficients in lead's null space
    basis, _ = np.linalg.qr(lead[:, None], mode="complete")
    null = basis[:, 1:]
    an = a @ null
    y, *_ = np.linalg.lstsq(an, b, rcond=None)
    if len(passive_at):
        from scipy.optimize import minimize

        q = (_basis(1j * passive_at, poles).imag / scale) @ null
        norm = float(np.abs(q).max()) or 1.0
        q, cap = q / norm, -floor / norm

        result = minimize(
            lambda z: float(np.sum((an @ z - b) ** 2)),
            y,
            jac=lambda z: 2.0 * an.T @ (an @ z - b),
            constraints=[{"type": "ineq", "fun": lambda z: cap - q @ z, "jac": lambda z: -q}],
            method="SLSQP",
            options={"maxiter": 500, "ftol": 1e-14},
        )
        y = result.x
    return (null @ y) / scale


def _passivity_grid(poles: np.ndarray, lo_hz: float, hi_hz: float) -> np.ndarray:
    """The frequencies [rad/s] passivity is checked at: a logarithmic grid a decade beyond
    the band each way, and about each pole's own frequency within a few half-power
    bandwidths (where a lightly damped term turns fastest)."""
    span = math.log10(hi_hz / lo_hz) + 2 * PASSIVITY_MARGIN_DECADES
    lo, hi = lo_hz * 10**-PASSIVITY_MARGIN_DECADES, hi_hz * 10**PASSIVITY_MARGIN_DECADES
    grid = [2 * math.pi * np.geomspace(lo, hi, int(PASSIVITY_POINTS_PER_DECADE * span))]
    around = np.linspace(-20.0, 20.0, 401)
    for p in poles:
        if p.imag > 0.0:
            zeta = max(-p.real / abs(p), 1e-6)
            grid.append(p.imag * (1.0 + zeta * around))
    out = np.concatenate(grid)
    return np.unique(out[out > 0.0])


def level(f: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """The rms magnitude of ``alpha`` over a third of an octave around each frequency."""
    mag2 = np.abs(alpha) ** 2
    out = np.empty(len(f))
    for i, fi in enumerate(f):
        sel = (f > fi * 2 ** (-1 / 6)) & (f < fi * 2 ** (1 / 6))
        out[i] = math.sqrt(float(mag2[sel].mean()))
    return out


def fit_receptance(frequencies_hz: ArrayLike, alpha: ArrayLike, pole_pairs: int = POLE_PAIRS) -> RationalFit:
    """Fit ``alpha`` [m/N] (complex, exp(+i w t), at ``frequencies_hz`` [Hz], ascending) by
    a stable, passive rational function without feedthrough (module docstring); its small
    dense problems on one BLAS thread (their threads would gain nothing alone and fight
    those of other processes on a busy machine).

    Examples
    --------
    >>> import numpy as np
    >>> f = np.geomspace(20, 5000, 200)
    >>> w = 2 * np.pi * f
    >>> one = 1 / (1e3 * ((2 * np.pi * 300) ** 2 - w**2 + 2j * 0.1 * 2 * np.pi * 300 * w))
    >>> fit = fit_receptance(f, one, pole_pairs=2)
    >>> fit.max_relative_error < 1e-3
    True
    """
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        return _fit(frequencies_hz, alpha, pole_pairs)


def _fit(frequencies_hz: ArrayLike, alpha: ArrayLike, pole_pairs: int) -> RationalFit:
    f = np.asarray(frequencies_hz, float)
    h = np.asarray(alpha, complex)
    s = 2j * math.pi * f
    mobility = np.abs(2 * math.pi * f * h)
    weight = ((mobility / mobility.max()) ** MOBILITY_EMPHASIS + WEIGHT_FLOOR) / np.abs(h)
    lo, hi = float(f[0]), float(f[-1])
    start = np.geomspace(max(lo, 1.0), hi, pole_pairs)
    poles = -2 * math.pi * start * 0.01 + 2j * math.pi * start
    for _ in range(ITERATIONS):
        poles = _relocate(s, h, poles, weight)
    poles = _distinct(poles)
    grid = _passivity_grid(poles, lo, hi)
    passive_at = np.zeros(0)
    floor = PASSIVITY_TOLERANCE * float(np.abs(h).max())
    x = _solve_residues(s, h, poles, weight, passive_at, floor)
    for _ in range(PASSIVITY_ROUNDS):
        im = (_basis(1j * grid, poles) @ x).imag
        bad = im > 0.0
        if not bad.any():
            break
        passive_at = np.union1d(passive_at, grid[bad][np.argsort(-im[bad])[:8]])
        x = _solve_residues(s, h, poles, weight, passive_at, floor)
    else:
        raise ValueError("the receptance's fit could not be made passive")
    fitted = _basis(s, poles) @ x
    err = np.abs(fitted - h)
    weighted = float((err * weight).max() / (np.abs(h) * weight).max())
    return RationalFit(poles, _residues(poles, x), (lo, hi), float((err / np.abs(h)).max()), weighted)
