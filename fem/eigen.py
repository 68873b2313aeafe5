"""Generalised symmetric eigenproblem K x = lambda M x by shift-invert Lanczos.

One entry point, :func:`solve_eigen`, used by every FE solver. The factorisation of
``K - sigma M`` is pluggable (``factorization=``); results are deterministic (fixed
start vector).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


class EigenError(RuntimeError):
    """The eigen-solve failed or found nothing in the requested band."""


@dataclass(frozen=True)
class EigenResult:
    eigenvalues: np.ndarray  # omega^2 [rad^2/s^2], ascending
    vectors: np.ndarray  # (n_dofs, n_modes), M-orthonormal

    @property
    def frequencies_hz(self) -> np.ndarray:
        return np.sqrt(np.maximum(self.eigenvalues, 0.0)) / (2 * math.pi)


def _factorize(A: sp.spmatrix, factorization: str):
    """Return a callable b -> A^{-1} b."""
    if factorization == "splu":
        lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A")
        return lu.solve
    if factorization == "superlu-colamd":
        lu = spla.splu(A.tocsc())
        return lu.solve
    raise ValueError(f"unknown factorization {factorization!r}")


def solve_eigen(
    K: sp.spmatrix,
    M: sp.spmatrix,
    k: int | None = None,
    fmax_hz: float | None = None,
    sigma: float = 0.0,
    factorization: str = "splu",
    tol: float = 1e-10,
) -> EigenResult:
    """Lowest eigenpairs of ``K x = omega^2 M x`` near the shift ``sigma`` [rad^2/s^2].

    Give ``k`` (number of modes) or ``fmax_hz`` (all modes up to that frequency; the
    count is grown until the band is closed), or both (at most ``k`` in the band).
    Vectors are M-normalised. Start vector is fixed, so results are repeatable.
    """
    n = K.shape[0]
    if k is None and fmax_hz is None:
        raise ValueError("give k or fmax_hz")
    A = (K - sigma * M).tocsc()
    solve = _factorize(A, factorization)
    OPinv = spla.LinearOperator(A.shape, matvec=solve, dtype=float)
    v0 = np.ones(n) / math.sqrt(n)
    want = k if fmax_hz is None else (min(k, 20) if k else 20)
    lam_max = None if fmax_hz is None else (2 * math.pi * fmax_hz) ** 2
    while True:
        nev = min(want, n - 2)
        vals, vecs = spla.eigsh(
            K, k=nev, M=M, sigma=sigma, which="LM", OPinv=OPinv, v0=v0, tol=tol,
            ncv=min(n - 1, max(2 * nev + 1, nev + 20)),
        )
        order = np.argsort(vals)
        vals, vecs = vals[order], vecs[:, order]
        if lam_max is None or vals[-1] > lam_max or nev >= n - 2 or (k and nev >= k):
            break
        want = int(want * 1.8) + 4
    if lam_max is not None:
        keep = vals <= lam_max
        vals, vecs = vals[keep], vecs[:, keep]
    # M-normalise explicitly (eigsh does, but be robust to the operator path)
    norms = np.sqrt(np.einsum("ij,ij->j", vecs, M @ vecs))
    vecs = vecs / norms
    # fix the sign convention so results are repeatable: largest entry positive
    idx = np.argmax(np.abs(vecs), axis=0)
    vecs = vecs * np.sign(vecs[idx, np.arange(vecs.shape[1])])
    return EigenResult(eigenvalues=vals, vectors=vecs)


__all__ = ["EigenError", "EigenResult", "solve_eigen"]
