"""Two scalar numerical kernels of the contact and the squeal model, written out rather
than imported.

SciPy's ``scipy.optimize`` and ``scipy.special`` cost about half a second to import,
more than a whole squeal simulation; the Hertz contact and the model need only a bracketed
root and the complete elliptic integrals, which take a few lines each:

- :func:`find_root`: Brent's method (inverse quadratic interpolation, secant and
  bisection steps, Brent 1973 ch. 4) on a sign-changing bracket;
- :func:`elliptic_ke`: K(m) and E(m) by the arithmetic-geometric mean (Abramowitz &
  Stegun 17.6), m = k^2 the parameter as in ``scipy.special.ellipk``.

Both are tested against SciPy to round-off (tests/test_reduced_contact_creep.py).
"""

from __future__ import annotations

import math
from collections.abc import Callable

__all__ = ["elliptic_ke", "find_root"]


def elliptic_ke(m: float) -> tuple[float, float]:
    """Complete elliptic integrals (K(m), E(m)) of parameter 0 <= m < 1.

    Parameters
    ----------
    m : float
        The parameter m = k^2, dimensionless.

    Returns
    -------
    tuple of float
        K(m) and E(m), dimensionless.

    Examples
    --------
    >>> k, e = elliptic_ke(0.0)
    >>> round(k, 12) == round(e, 12) == round(math.pi / 2, 12)
    True
    """
    if not 0.0 <= m < 1.0:
        raise ValueError(f"elliptic parameter must lie in [0, 1), got {m!r}")
    a, b = 1.0, math.sqrt(1.0 - m)
    c2 = m  # c_0^2
    weight = 0.5  # 2^(n - 1) for n = 0
    total = weight * c2
    for _ in range(60):
        c = 0.5 * (a - b)
        a, b = 0.5 * (a + b), math.sqrt(a * b)
        weight *= 2.0
        total += weight * c * c
        if abs(c) <= 1e-17 * a:
            break
    K = math.pi / (2.0 * a)
    return K, K * (1.0 - total)


def find_root(
    f: Callable[[float], float],
    a: float,
    b: float,
    *,
    xtol: float = 1e-15,
    rtol: float = 1e-14,
    maxiter: int = 200,
) -> float:
    """A root of ``f`` in [a, b], where ``f(a)`` and ``f(b)`` differ in sign, to within
    ``xtol + rtol |x|`` (Brent's method).

    Parameters
    ----------
    f : callable
        A continuous function of one float.
    a, b : float
        The bracket.
    xtol, rtol : float
        Absolute and relative tolerance on the root.
    maxiter : int
        The most iterations.

    Returns
    -------
    float
        The root.

    Examples
    --------
    >>> round(find_root(lambda x: x * x - 2.0, 0.0, 2.0), 12)
    1.414213562373
    """
    fa, fb = f(a), f(b)
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if (fa > 0.0) == (fb > 0.0):
        raise ValueError(f"no sign change on [{a!r}, {b!r}]: f = {fa!r}, {fb!r}")
    c, fc = a, fa
    d = e = b - a
    for _ in range(maxiter):
        if (fb > 0.0) == (fc > 0.0):  # keep the root between b and c
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):  # b is the best estimate
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        tol = 0.5 * (xtol + rtol * abs(b))
        half = 0.5 * (c - b)
        if abs(half) <= tol or fb == 0.0:
            return b
        if abs(e) >= tol and abs(fa) > abs(fb):
            s = fb / fa
            if a == c:  # secant
                p, q = 2.0 * half * s, 1.0 - s
            else:  # inverse quadratic interpolation
                q, r = fa / fc, fb / fc
                p = s * (2.0 * half * q * (q - r) - (b - a) * (r - 1.0))
                q = (q - 1.0) * (r - 1.0) * (s - 1.0)
            if p > 0.0:
                q = -q
            p = abs(p)
            if 2.0 * p < min(3.0 * half * q - abs(tol * q), abs(e * q)):
                e, d = d, p / q  # accept the interpolation
            else:
                d = e = half  # bisect
        else:
            d = e = half
        a, fa = b, fb
        b += d if abs(d) > tol else math.copysign(tol, half)
        fb = f(b)
    raise RuntimeError(f"find_root: no convergence in {maxiter} iterations on [{a!r}, {b!r}]")
