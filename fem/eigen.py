"""Generalised symmetric eigenproblem K x = lambda M x by shift-invert Lanczos.

One entry point, :func:`solve_eigen`, used by every FE solver. The factorisation of
``K - sigma M`` is pluggable (``factorization=``); results are deterministic (fixed
start vector).

Why not block shift-invert (41k DOFs, 25 eigenpairs <= 5.1 kHz, interleaved medians of
3 on these 2-core machines): a block Lanczos with full
reorthogonalisation and Rayleigh-Ritz (deterministic Gaussian start block, residual
tolerance 1e-7..1e-8; same eigenvalues to 1e-11, M-orthonormal to 1e-15) needs 88-128
solve columns (block 4-8) against ARPACK's 75 single solves, which eats the 2.5-3x
cheaper per-column block solves: 3.15-3.4 s vs 3.7 s with PARDISO, 2.1-2.5 s vs 2.3 s
with SuperLU-sym; block subspace iteration needs ~10 iterations of a 45-column block
(450 columns) at 1e-10. Not worth a second eigensolver path.
"""

from __future__ import annotations

import contextlib
import functools
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
    #: every eigenvalue computed, in the band or not (ascending): names the lowest
    #: natural frequency when the band is empty
    computed: np.ndarray | None = None

    def lowest_hz(self, skip: int = 0) -> float | None:
        """Lowest computed frequency [Hz] after skipping ``skip`` (e.g. rigid) ones."""
        lam = self.eigenvalues if self.computed is None else self.computed
        if lam.size <= skip:
            return None
        return float(np.sqrt(max(lam[skip], 0.0)) / (2 * math.pi))

    @property
    def frequencies_hz(self) -> np.ndarray:
        return np.sqrt(np.maximum(self.eigenvalues, 0.0)) / (2 * math.pi)


#: Preference of ``factorization="auto"``, first available wins (CHOLMOD only for a
#: definite matrix); without either, SciPy's SuperLU (:data:`SCIPY_AUTO_DEFINITE`).
#: CHOLMOD (scikit-sparse, needs libsuitesparse-dev and a compiler) is the fastest on
#: the wheels' 3-D P2 matrices; PARDISO (pypardiso, the ``fast3d`` extra) factorises
#: fastest but each single-vector solve of the Lanczos loop costs more; SuperLU in
#: symmetric mode is the fastest of SciPy's (``benchmarks/bench_modes.py`` compares them
#: on the same mesh, interleaved).
AUTO_ORDER: tuple[str, ...] = ("cholmod", "pardiso", "splu")
#: Without pypardiso (the ``fast3d`` extra) and scikit-sparse, ``auto`` uses SciPy's
#: SuperLU; with a definite matrix (shift below the spectrum) in symmetric mode
#: (MMD on A^T + A, diagonal pivots: no row interchanges, so the symmetric ordering
#: is kept). See :func:`auto_factorization` for the measurements.
SCIPY_AUTO_DEFINITE = "superlu-sym"

#: BLAS/OpenMP threads while factorising and iterating: one, since ARPACK's many small
#: BLAS calls gain nothing from threads, and OpenBLAS and MKL/OpenMP threads otherwise
#: spin against each other and against other processes on a shared machine
#: (``benchmarks/bench_modes.py`` measures both). ``None`` leaves the defaults.
BLAS_THREADS: int | None = 1

FACTORIZATIONS: tuple[str, ...] = ("auto", "pardiso", "cholmod", "splu", "superlu-sym", "superlu-colamd")


def available_factorizations() -> list[str]:
    """The factorisations usable here (optional packages installed)."""
    out = []
    for name in ("pardiso", "cholmod"):
        try:
            _import_backend(name)
        except ImportError:
            continue
        out.append(name)
    return out + ["splu", "superlu-sym", "superlu-colamd"]


def auto_factorization(n: int, definite: bool) -> str:
    """The factorisation ``"auto"`` uses for an ``n``-DOF matrix.

    The first installed of :data:`AUTO_ORDER` (CHOLMOD only for a definite matrix),
    else SciPy's SuperLU: ``"superlu-sym"`` for a definite matrix (MMD on A^T + A with
    diagonal pivots: the fill of COLAMD's half, and no off-diagonal pivoting to slow it),
    ``"splu"`` otherwise (``benchmarks/bench_modes.py`` times them). The 2-D harmonic problems of
    :mod:`fem.axisym` pick their own (``small_problem_factorization``) and never see
    this choice. ``n`` is accepted for a size-dependent rule (none is needed so far).
    """
    for name in AUTO_ORDER:
        if name == "splu":
            break
        if name == "cholmod" and not definite:
            continue  # LL^T needs a definite matrix; no pivoting LDL^T here
        try:
            _import_backend(name)
        except (ImportError, OSError):
            continue
        return name
    return SCIPY_AUTO_DEFINITE if definite else "splu"


def _import_backend(name: str):
    if name == "pardiso":
        import pypardiso  # noqa: PLC0415 (optional)

        pypardiso.PyPardisoSolver()  # raises if MKL's runtime cannot be loaded
        return pypardiso
    if name == "cholmod":
        from sksparse import cholmod  # noqa: PLC0415 (optional)

        return cholmod
    raise ImportError(name)


class _PardisoSolve:
    """MKL PARDISO (via pypardiso): factorise once, then solve (phase 33) per call.

    pypardiso's ``solve(A, b)`` hashes or compares ``A`` on every call to decide
    whether to refactorise; in a Lanczos loop that check costs more than the solve,
    so after ``factorize`` the solve phase is called directly.
    """

    def __init__(self, A: sp.spmatrix, definite: bool):
        import pypardiso  # noqa: PLC0415

        # Symmetric matrices: PARDISO reads the upper triangle of a CSR matrix.
        self.A = sp.triu(sp.csr_matrix(A), format="csr")
        self.A.sort_indices()
        self.solver = pypardiso.PyPardisoSolver(mtype=2 if definite else -2)
        self.solver.factorize(self.A)
        self.solver.set_phase(33)

    def __call__(self, b: np.ndarray) -> np.ndarray:
        x = self.solver._call_pardiso(self.A, np.asfortranarray(b, dtype=np.float64))
        return x

    def __del__(self):  # release MKL's memory now, not at exit
        try:
            self.solver.free_memory(everything=True)
        except Exception:  # pragma: no cover
            pass


def _factorize(A: sp.spmatrix, factorization: str, definite: bool = False):
    """Return a callable b -> A^{-1} b (b a vector or an (n, m) block).

    ``definite``: A is known to be symmetric positive definite (shift below the
    spectrum), which lets PARDISO and CHOLMOD use a Cholesky factorisation.
    """
    if factorization == "auto":
        name = auto_factorization(A.shape[0], definite)
        try:
            return _factorize(A, name, definite)
        except Exception:  # e.g. not positive definite after all: fall back
            return _factorize(A, "splu", definite)
    if factorization == "splu":
        lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A")
        return lu.solve
    if factorization == "superlu-sym":
        # symmetric mode: MMD on A^T + A and diagonal pivots (threshold 0), stable for
        # a definite matrix; for an indefinite one SuperLU still pivots where needed.
        lu = spla.splu(
            A.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True}
        )
        return lu.solve
    if factorization == "superlu-colamd":
        lu = spla.splu(A.tocsc())
        return lu.solve
    if factorization == "pardiso":
        return _PardisoSolve(A, definite)
    if factorization == "cholmod":
        cholmod = _import_backend("cholmod")
        return cholmod.cholesky(sp.csc_matrix(A))
    raise ValueError(f"unknown factorization {factorization!r}; use one of {FACTORIZATIONS}")


def solve_eigen(
    K: sp.spmatrix,
    M: sp.spmatrix,
    k: int | None = None,
    fmax_hz: float | None = None,
    sigma: float = 0.0,
    factorization: str = "splu",
    tol: float = 1e-10,
    guess: int | None = None,
) -> EigenResult:
    """Lowest eigenpairs of ``K x = omega^2 M x`` near the shift ``sigma`` [rad^2/s^2].

    Give ``k`` (number of modes) or ``fmax_hz`` (all modes up to that frequency; the
    count is grown until the band is closed), or both (at most ``k`` in the band).
    Vectors are M-normalised. Start vector is fixed, so results are repeatable.

    ``factorization`` of ``K - sigma M``: ``"splu"`` (SuperLU, MMD on A^T + A),
    ``"superlu-colamd"`` (SuperLU with SciPy's default ordering, what a plain ``eigsh``
    call uses), ``"cholmod"`` (scikit-sparse, optional), ``"pardiso"`` (pypardiso,
    optional) or ``"auto"``: the first available of :data:`AUTO_ORDER`. All give the
    same eigenvalues to ~1e-11 relative. ``guess``: expected number of eigenpairs in the
    band (first Lanczos run; the count still grows until the band is closed).
    """
    with blas_threads():
        return _solve_eigen(K, M, k, fmax_hz, sigma, factorization, tol, guess)


def _solve_eigen(K, M, k, fmax_hz, sigma, factorization, tol, guess) -> EigenResult:
    n = K.shape[0]
    if k is None and fmax_hz is None:
        raise ValueError("give k or fmax_hz")
    A = (K - sigma * M).tocsc()
    # K is positive semi-definite and M positive definite: for sigma < 0 (or sigma = 0
    # with K non-singular, a clamped structure) K - sigma M is positive definite.
    solve = _factorize(A, factorization, definite=sigma <= 0.0)
    OPinv = spla.LinearOperator(A.shape, matvec=solve, dtype=float)
    v0 = np.ones(n) / math.sqrt(n)
    first = 20 if guess is None else max(int(guess), 1)
    want = k if fmax_hz is None else (min(k, first) if k else first)
    lam_max = None if fmax_hz is None else (2 * math.pi * fmax_hz) ** 2
    while True:
        nev = min(want, n - 2)
        vals, vecs = spla.eigsh(
            K,
            k=nev,
            M=M,
            sigma=sigma,
            which="LM",
            OPinv=OPinv,
            v0=v0,
            tol=tol,
            ncv=min(n - 1, max(2 * nev + 1, nev + 20)),
        )
        order = np.argsort(vals)
        vals, vecs = vals[order], vecs[:, order]
        if lam_max is None or vals[-1] > lam_max or nev >= n - 2 or (k and nev >= k):
            break
        want = int(want * 1.8) + 4
    computed = vals.copy()
    if lam_max is not None:
        keep = vals <= lam_max
        vals, vecs = vals[keep], vecs[:, keep]
    # M-normalise explicitly (eigsh does, but be robust to the operator path)
    norms = np.sqrt(np.einsum("ij,ij->j", vecs, M @ vecs))
    vecs = vecs / norms
    # fix the sign convention so results are repeatable: largest entry positive
    idx = np.argmax(np.abs(vecs), axis=0)
    vecs = vecs * np.sign(vecs[idx, np.arange(vecs.shape[1])])
    return EigenResult(eigenvalues=vals, vectors=vecs, computed=computed)


def blas_threads(limit: int | None = None):
    """Context limiting BLAS/OpenMP threads to ``limit`` (default :data:`BLAS_THREADS`;
    no limit if that is None): the one way every FE solver does it."""
    limit = BLAS_THREADS if limit is None else limit
    if limit is None:
        return contextlib.nullcontext()
    from threadpoolctl import threadpool_limits  # noqa: PLC0415 (imports BLAS libraries)

    return threadpool_limits(limits=limit)


def small_problem_factorization() -> str:
    """Factorisation for the harmonic problems (1e3-1e4 DOFs, 2-D fill pattern).

    CHOLMOD if installed, else SciPy's splu; never PARDISO, whose set-up cost dominates
    at this size, nor the 3-D solver's "auto" choice (``benchmarks/bench_axisym.py``)."""
    return _small_problem_factorization()


@functools.lru_cache(maxsize=1)
def _small_problem_factorization() -> str:
    # only probe cholmod: asking fem.eigen for all back-ends would load MKL (pardiso),
    # which takes longer than the whole solve
    try:
        import sksparse.cholmod  # noqa: F401, PLC0415 (optional)
    except ImportError:
        return "splu"
    return "cholmod"


def solve_band(K, M, fmax_hz, k, sigma, guess, factorization="splu"):
    """Eigenpairs of one small problem (one harmonic): all with f <= fmax_hz (at most
    k), or the k lowest.

    Calls :func:`fem.eigen.solve_eigen` with a modest mode count and grows it until
    the band is closed (fewer in-band modes returned than asked for)."""
    n = K.shape[0]
    if fmax_hz is None:
        return solve_eigen(K, M, k=min(k, n - 2), sigma=sigma, factorization=factorization)
    want = max(2, guess)
    while True:
        want = min(want, n - 2) if k is None else min(want, k, n - 2)
        res = solve_eigen(K, M, k=want, fmax_hz=fmax_hz, sigma=sigma, factorization=factorization)
        if len(res.eigenvalues) < want or want >= n - 2 or (k is not None and want >= k):
            return res
        want = 2 * want + 2


__all__ = [
    "AUTO_ORDER",
    "FACTORIZATIONS",
    "SCIPY_AUTO_DEFINITE",
    "EigenError",
    "EigenResult",
    "auto_factorization",
    "available_factorizations",
    "blas_threads",
    "small_problem_factorization",
    "solve_band",
    "solve_eigen",
]
