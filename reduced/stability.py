"""Linear stability of every mode at an operating point: which mode squeals.

Linearised about steady sliding at the quasi-static creepage zeta0 = Vc/V0, the contact
force is ``Q = Q0 - g v`` with the friction damping ``g = (W/V0) dmu/dzeta(zeta0)`` [N s/m]
(the full slope of Eq. 3, the falling factor included; g < 0 on the falling branch)
and ``v`` the contact velocity. The N modes seen at the contact then obey

    M q'' + (D + g b a^T) q' + (S + g b e^T) q = 0,

a rank-one coupling through the contact. Without rotation ``q`` are the modal
coordinates, ``D = C``, ``S = K``, ``a = b = 1`` and ``e = 0`` (docs/theory.md, linear stability). With
the wheel turning at Omega, a mode with n >= 1 nodal diameters is a pair whose
coordinates in the frame of the (fixed) contact, ``x`` and ``w``, see Coriolis-like
terms (docs/theory.md, rotation, written for p = (a + i b) e^{i n Omega t}):

    m x'' + c x' + 2 m n Omega w' + (k - m n^2 Omega^2) x + c n Omega w = Q
    m w'' + c w' - 2 m n Omega x' + (k - m n^2 Omega^2) w - c n Omega x = 0

with the contact velocity ``v = x' + n Omega w``. Gyroscopic and centrifugal terms of
the wheel itself are neglected (of order Omega / w0, about 1 %). Its 2N (or 2N + 2 per
pair) eigenvalues ``sigma + i omega_d`` are those of a real matrix; each is assigned to
the mode that holds most of its vibration energy.

Per mode (:class:`ModeStability`): the growth rate sigma [1/s] (the largest of the
mode's eigenvalues: a pair under rotation has two travelling waves at f0 -/+ n Omega /
2 pi), the damped frequency [Hz], the critical damping ratio (the modal damping ratio
above which the mode is stable at this point, the others as given) and the critical
friction slope (the dmu/dzeta at zeta0 above which it is stable). For a mode far from
the others in frequency these tend to ``sigma = -(c + g) / (2 m)`` (``-(c + g/2) / (2 m)``
for a rotating pair when n Omega >> |sigma|), ``zeta_crit = -g / (2 m w)`` and
``dmu/dzeta_crit = -c V0 / W``; near another mode the coupling moves them, and the
exact values are found by root finding on the coupled eigenvalues.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from contact.creep import ContactLaw, adhesion_ratio, adhesion_ratio_slope
from contact.numerics import find_root

from ._numerics import one_blas_thread
from .counter_body import NORMAL, BodyModel
from .model import ModalDOF, Modes, OperatingPoint, as_modes

__all__ = [
    "bound_solves",
    "Mitigation",
    "ModeStability",
    "StabilityMap",
    "StabilityResult",
    "critical_damping_ratio",
    "critical_friction_slope",
    "eigen_shares",
    "eigen_solve_bytes",
    "eigen_solve_seconds",
    "friction_damping_ns_m",
    "growth_rates",
    "leading_mode",
    "linear_stability",
    "mitigation",
    "mitigation_seconds",
    "stability_map",
    "stability_seconds",
]


def friction_damping_ns_m(contact: ContactLaw, op: OperatingPoint) -> float:
    """g = (W / V0) dmu/dzeta at the quasi-static creepage [N s/m] (< 0: destabilising)."""
    slope = float(adhesion_ratio_slope(op.creepage, contact, op.rolling_speed_m_s))
    return contact.normal_load_n / op.rolling_speed_m_s * slope


@dataclass(frozen=True)
class LinearContact:
    """The contact linearised about steady sliding at an operating point.

    friction_damping_ns_m : g = (W / V0) dmu/dzeta, N s/m (falling friction: g < 0).
    adhesion_ratio : mu0 = mu(zeta0), the lateral force per unit normal force.
    normal_stiffness_n_m : k_H, the Hertz spring (0: a constant normal load).
    relaxation_time_s : tau = L / V0, the creep force's lag (0: steady creep).
    """

    friction_damping_ns_m: float
    adhesion_ratio: float = 0.0
    normal_stiffness_n_m: float = 0.0
    relaxation_time_s: float = 0.0

    @classmethod
    def at(cls, contact: ContactLaw, op: OperatingPoint) -> LinearContact:
        """The contact ``contact`` linearised at ``op`` (kept per process for the last
        :data:`LINEARISED_KEPT` pairs: a squealing contact's analysis asks for it at every
        eigen-solve of its stability, competition and balance)."""
        return _linearised(contact, op)

    @classmethod
    def of(cls, linear: LinearContact | float) -> LinearContact:
        """``linear``, or a bare friction damping g [N s/m] as the paper's lateral contact."""
        return linear if isinstance(linear, LinearContact) else cls(float(linear))

    def couples(self, modes: Sequence[ModalDOF]) -> bool:
        """Whether the friction's stiffness coupling mu0 k_H phi_t phi_n^T acts on ``modes``
        (the other mechanism, mode coupling, is possible)."""
        return (
            self.normal_stiffness_n_m != 0.0
            and self.adhesion_ratio != 0.0
            and any(md.normal != 0.0 for md in modes)
        )


#: The linearised contacts a process keeps (:meth:`LinearContact.at`)
LINEARISED_KEPT = 64


@functools.lru_cache(maxsize=LINEARISED_KEPT)
def _linearised(contact: ContactLaw, op: OperatingPoint) -> LinearContact:
    mu0 = float(adhesion_ratio(op.creepage, contact, op.rolling_speed_m_s))
    return LinearContact(
        friction_damping_ns_m(contact, op),
        mu0,
        contact.normal_stiffness_n_m,
        contact.relaxation_time_s(op.rolling_speed_m_s),
    )


Mechanism = Literal["falling friction", "mode coupling", "both"]

#: An eigenvalue's participating modes: those holding at least this share of its
#: vibration energy (a mode-coupling pair shares it about evenly; a falling-friction
#: eigenvalue of a mode far from the others has one at over 99 %)
PARTNER_SHARE = 0.05


@dataclass(frozen=True)
class ModeStability:
    """One mode's linear stability at an operating point (see the module docstring).

    growth_rate_1_s : sigma, 1/s (> 0: the mode grows, it can squeal): of the fastest-
        growing eigenvalue it takes part in (:data:`PARTNER_SHARE`; a coupled pair's
        growing eigenvalue for both its modes), else of its own slowest-decaying one.
    damped_frequency_hz : the frequency of that eigenvalue, Hz (in the frame of the
        contact: f0 -/+ n Omega / 2 pi for a rotating pair).
    critical_damping_ratio : modal damping ratio above which it is stable here (0 if it
        is stable without damping).
    critical_friction_slope : dmu/dzeta at zeta0 above which it is stable here.
    mechanism : what makes its fastest eigenvalue grow ("falling friction", "mode
        coupling", "both"; None while it decays).
    partners : the input indices of the modes that take part in that eigenvalue's
        motion (:data:`PARTNER_SHARE`), this one first.
    """

    growth_rate_1_s: float
    damped_frequency_hz: float
    critical_damping_ratio: float
    critical_friction_slope: float
    mechanism: Mechanism | None = None
    partners: tuple[int, ...] = ()

    @property
    def unstable(self) -> bool:
        return self.growth_rate_1_s > 0.0


@dataclass(frozen=True)
class StabilityResult:
    """The linear stability of every mode at one operating point.

    modes : one :class:`ModeStability` per input mode, in input order (none where
        ``linear_stability`` was asked for no stable modes and nothing grows).
    eigenvalues : every eigenvalue of the coupled system with Im >= 0, 1/s.
    friction_damping_ns_m : g, N s/m.
    wheel_speed_rad_s : Omega (0: rotation off), rad/s.
    shares : (modes, eigenvalues), each mode's share of each eigenvalue's vibration
        energy.
    mechanisms : per eigenvalue, what makes it grow (None where it decays).
    linear : the linearised contact (:class:`LinearContact`).
    assigned : per mode, the eigenvalues assigned to it (one; two for a rotating pair).
    speaking : per mode, the eigenvalue that speaks for it (its growth rate and frequency:
        the fastest-growing one it takes part in, else its own slowest-decaying one).
    """

    modes: tuple[ModeStability, ...]
    eigenvalues: np.ndarray
    friction_damping_ns_m: float
    wheel_speed_rad_s: float
    shares: np.ndarray | None = None
    mechanisms: tuple[Mechanism | None, ...] = ()
    linear: LinearContact | None = None
    assigned: tuple[tuple[int, ...], ...] = ()
    speaking: tuple[int, ...] = ()

    @property
    def winner(self) -> int:
        """Index of the leading mode: the one holding the largest share of the vibration
        energy of the fastest-growing eigenvalue (of a coupled pair, the partner that holds
        more of it, whichever of the two is assigned the faster of its own); where nothing
        grows, the mode that grows fastest (decays slowest)."""
        return leading_mode(self.eigenvalues, self.shares, [m.growth_rate_1_s for m in self.modes])

    @property
    def growth_rate_1_s(self) -> float:
        """The largest growth rate of the system, 1/s (of its modes; without them, of
        its eigenvalues)."""
        if not self.modes:
            return float(self.eigenvalues.real.max())
        return max(m.growth_rate_1_s for m in self.modes)

    def ranked(self) -> list[int]:
        """The eigenvalues' indices, fastest-growing first."""
        return [int(j) for j in np.argsort(-self.eigenvalues.real, kind="stable")]


def leading_mode(
    eigenvalues: np.ndarray,
    shares: np.ndarray | None,
    growth_rates: Sequence[float],
    candidates: int | None = None,
) -> int:
    """The leading mode among the first ``candidates`` (default all): the largest share of
    the fastest-growing eigenvalue they take part in, else the largest growth rate."""
    k = len(growth_rates) if candidates is None else candidates
    if shares is not None:
        for j in np.argsort(-eigenvalues.real, kind="stable"):
            if eigenvalues[j].real <= 0.0:
                break
            if np.max(shares[:k, j]) >= PARTNER_SHARE:
                return int(np.argmax(shares[:k, j]))
    return int(np.argmax(growth_rates[:k]))


# --------------------------------------------------------------------------------------
# the coupled linear system
# --------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class _Layout:
    """Where each mode's coordinates lie in the state (``blocks``: (first, count), 2 for
    a rotating pair) and the counter-body's model after them (None: rigid)."""

    blocks: list[tuple[int, int]]
    body: BodyModel | None = None

    @property
    def coordinates(self) -> int:
        return sum(size for _, size in self.blocks)

    @property
    def body_states(self) -> int:
        return 0 if self.body is None else self.body.states


def _blocks(modes: Sequence[ModalDOF], wheel_speed_rad_s: float, body: BodyModel | None = None) -> _Layout:
    """The layout of ``modes`` (2 coordinates for a pair on a turning wheel) and ``body``."""
    out, at = [], 0
    for md in modes:
        size = 2 if (wheel_speed_rad_s != 0.0 and md.nodal_diameters >= 1) else 1
        out.append((at, size))
        at += size
    return _Layout(out, body if body is not None and body.states else None)


def _state_parts(
    modes: Sequence[ModalDOF],
    damping: np.ndarray,
    linear: LinearContact,
    wheel_speed_rad_s: float,
    layout: _Layout,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A of z' = A z as ``A0 + U V^T`` (returned as A0, U, V): A0 the uncoupled modes and
    counter-body terms (block diagonal, :func:`_state_blocks`), U V^T the contact's coupling
    (rank 2, 3 with the lag). z = (q, q', x) with a steady creep force, (q, q', x, the
    lagged force) with transient creep. Linearised: the normal force dN = k_H u_n,
    u_n = b.q - Cn x; the lateral force dQ = -g v - mu0 dN, v = a.q' + e.q - Cvt x; the modes
    take a dQ - b dN, the counter-body -dQ laterally and +dN normally."""
    blocks, nq, nb = layout.blocks, layout.coordinates, layout.body_states
    M, D, S = np.zeros(nq), np.zeros((nq, nq)), np.zeros((nq, nq))
    a, b, e = np.zeros(nq), np.zeros(nq), np.zeros(nq)
    for md, c, (i, size) in zip(modes, damping, blocks):
        m, k = md.mass_kg, md.stiffness_n_m
        M[i : i + size] = m
        a[i], b[i] = md.lateral, md.normal
        if size == 1:
            D[i, i], S[i, i] = c, k
            continue
        w = md.nodal_diameters * wheel_speed_rad_s  # n Omega
        D[i : i + 2, i : i + 2] = [[c, 2 * m * w], [-2 * m * w, c]]
        S[i : i + 2, i : i + 2] = [[k - m * w * w, c * w], [-c * w, k - m * w * w]]
        e[i + 1] = w * md.lateral
    g, k_h, mu0, tau = (
        linear.friction_damping_ns_m,
        linear.normal_stiffness_n_m,
        linear.adhesion_ratio,
        linear.relaxation_time_s,
    )
    n_state = 2 * nq + nb
    # the forces as rows over z = (q, q', x): the normal one dN and the steady lateral one dQ
    d_n, d_q = np.zeros(n_state), np.zeros(n_state)
    A_b, B_b, C_b, Cv_b = (
        layout.body.state_space()
        if layout.body is not None
        else (np.zeros((0, 0)), np.zeros((0, 2)), np.zeros((2, 0)), np.zeros((2, 0)))
    )
    body_normal = bool(np.any(C_b[0]))
    if k_h != 0.0 and (bool(np.any(b)) or body_normal):
        d_n[:nq] = k_h * b
        if layout.body is not None:
            d_n[2 * nq :] = -k_h * C_b[0]
    d_q[:nq] = -g * e
    d_q[nq : 2 * nq] = -g * a
    if layout.body is not None:
        d_q[2 * nq :] = g * Cv_b[1]
    d_q -= mu0 * d_n
    lag = tau > 0.0
    n = n_state + int(lag)
    A0 = np.zeros((n, n))
    A0[:nq, nq : 2 * nq] = np.eye(nq)
    A0[nq : 2 * nq, :nq] = -S / M[:, None]
    A0[nq : 2 * nq, nq : 2 * nq] = -D / M[:, None]
    A0[2 * nq : n_state, 2 * nq : n_state] = A_b
    # the normal force's column: the modes take -b dN, the counter-body +dN
    takes_n = np.concatenate([np.zeros(nq), -b / M, B_b[:, 0], np.zeros(int(lag))])
    # the lateral force's column: the modes take a Q, the counter-body -Q (Q = dQ, or the lagged f)
    takes_q = np.concatenate([np.zeros(nq), a / M, -B_b[:, 1], np.zeros(int(lag))])
    if not lag:
        return A0, np.column_stack([takes_n, takes_q]), np.column_stack([d_n, d_q])
    # the lagged force f: tau f' = -f + dQ
    A0[n_state, n_state] = -1.0 / tau
    lag_row = np.zeros(n)
    lag_row[n_state] = 1.0
    U = np.column_stack([takes_n, takes_q, lag_row])
    V = np.column_stack([np.append(d_n, 0.0), lag_row, np.append(d_q / tau, 0.0)])
    return A0, U, V


def _state_matrix(
    modes: Sequence[ModalDOF],
    damping: np.ndarray,
    linear: LinearContact,
    wheel_speed_rad_s: float,
    layout: _Layout,
) -> np.ndarray:
    """A of z' = A z (:func:`_state_parts`: A0 + U V^T)."""
    A0, U, V = _state_parts(modes, damping, linear, wheel_speed_rad_s, layout)
    return A0 + U @ V.T


def _state_blocks(layout: _Layout, lag: bool) -> list[np.ndarray]:
    """The states of each diagonal block of A0 (:func:`_state_parts`), as index arrays of
    shape (blocks, size) grouped by size: a mode's (q, q') (its two coordinates' for a
    rotating pair), a counter-body pair's (q, q'), a first-order term's and the lag's."""
    nq = layout.coordinates
    by_size: dict[int, list[np.ndarray]] = {}
    starts = np.array([i for i, _ in layout.blocks], dtype=np.intp)
    sizes = np.array([size for _, size in layout.blocks], dtype=np.intp)
    for size in (1, 2):
        i = starts[sizes == size][:, None] + np.arange(size)
        if len(i):
            by_size.setdefault(2 * size, []).append(np.hstack([i, nq + i]))
    at = 2 * nq
    if layout.body is not None:
        for order, offsets in _body_blocks(layout.body).items():
            by_size.setdefault(order, []).append(at + offsets)
        at += layout.body.states
    if lag:
        by_size.setdefault(1, []).append(np.array([[at]], dtype=np.intp))
    return [np.vstack(parts) for parts in by_size.values()]


@functools.lru_cache(maxsize=8)
def _body_blocks(body: BodyModel) -> dict[int, np.ndarray]:
    """A counter-body's terms' states, (terms, order) per order, from its first state."""
    first = np.concatenate([[0], np.cumsum(body.order)[:-1]]).astype(np.intp)
    return {int(k): first[body.order == k][:, None] + np.arange(k) for k in np.unique(body.order)}


#: An eigenvector found from its eigenvalue (:func:`_secular_vectors`) is kept when its
#: backward error ||A x - lambda x|| / (||A|| ||x||) is at most this (LAPACK's own are
#: about 1e-15); a larger one is found by inverse iteration, or else by LAPACK
SECULAR_BACKWARD_ERROR = 1e-10
#: Steps of inverse iteration for an eigenvector the low-rank coupling does not give
INVERSE_STEPS = 3


def _backward_errors(A: np.ndarray, X: np.ndarray, lam: np.ndarray) -> np.ndarray:
    """||A x - lambda x|| / (||A|| ||x||) per column x of ``X`` (inf where not finite)."""
    with np.errstate(invalid="ignore", over="ignore"):
        AX = A @ X.real + 1j * (A @ X.imag)  # two real products: A is real
        out = np.linalg.norm(AX - X * lam, axis=0) / (np.linalg.norm(A) * np.linalg.norm(X, axis=0))
    return np.where(np.isfinite(out), out, np.inf)


def _block_solve(A0: np.ndarray, states: np.ndarray, U: np.ndarray, lam: np.ndarray) -> np.ndarray:
    """(B - lambda)^-1 U_B for every diagonal block B of ``A0`` on ``states`` (blocks, size)
    and every eigenvalue of ``lam``: shape (eigenvalues, blocks, size, columns of U). In
    closed form up to 2 x 2; a singular one gives inf or nan, not an error (the eigenvalue
    is the block's own)."""
    size = states.shape[1]
    z = lam[:, None, None]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if size == 1:
            i = states[:, 0]
            return (U[i] / (A0[i, i][None, :, None] - z))[:, :, None, :]
        if size == 2:
            i, j = states[:, 0], states[:, 1]
            a, b = A0[i, i][None, :, None] - z, A0[i, j][None, :, None]
            c, d = A0[j, i][None, :, None], A0[j, j][None, :, None] - z
            det = a * d - b * c
            return np.stack([(d * U[i] - b * U[j]) / det, (a * U[j] - c * U[i]) / det], axis=2)
    shifted = A0[states[:, :, None], states[:, None, :]][None] - lam[:, None, None, None] * np.eye(size)
    try:
        return np.linalg.solve(shifted, np.broadcast_to(U[states][None], (len(lam), *U[states].shape)))
    except np.linalg.LinAlgError:
        return np.full((len(lam), *U[states].shape), np.nan, complex)


def _secular_vectors(
    A0: np.ndarray, U: np.ndarray, V: np.ndarray, lam: np.ndarray, blocks: Sequence[np.ndarray]
) -> np.ndarray:
    """The eigenvectors (columns) of A = A0 + U V^T for its eigenvalues ``lam``, from the
    low-rank coupling: (A0 - lambda) x = -U c with c = V^T x, so x = -W c with
    W = (A0 - lambda)^-1 U (A0's small diagonal blocks solved per eigenvalue) and c the null
    vector of I + V^T W. Not accurate for an eigenvalue of a block the contact does not
    move (W is then infinite): the caller checks each column's backward error."""
    n, r = U.shape
    W = np.zeros((len(lam), n, r), complex)
    for states in blocks:
        W[:, states] = _block_solve(A0, states, U, lam)
    with np.errstate(invalid="ignore", over="ignore"):
        K = np.eye(r) + V.T @ W  # (eigenvalues, r, r)
        K = np.where(np.isfinite(K), K, 0.0)
        if r == 2:  # the null vector of a singular 2 x 2: either row turned, the longer
            first = np.stack([-K[:, 0, 1], K[:, 0, 0]], axis=1)
            second = np.stack([-K[:, 1, 1], K[:, 1, 0]], axis=1)
            longer = np.linalg.norm(first, axis=1) >= np.linalg.norm(second, axis=1)
            c = np.where(longer[:, None], first, second)
        else:
            c = np.linalg.svd(K)[2][:, -1, :].conj()  # the smallest singular value's
        return (W @ c[:, :, None])[:, :, 0].T


def _inverse_iteration(A: np.ndarray, lam: np.ndarray, columns: np.ndarray) -> np.ndarray:
    """Eigenvectors of ``A`` for ``lam[columns]`` by inverse iteration, shifted by the
    eigenvalue itself (nudged by 1e-13 ||A|| if that is singular to the last bit), from
    starts that differ between equal eigenvalues (a repeated eigenvalue's vectors span its
    eigenspace rather than repeat one vector)."""
    import warnings

    import scipy.linalg

    n = A.shape[0]
    out = np.zeros((n, len(columns)), complex)
    scale = np.linalg.norm(A)
    for k, j in enumerate(columns):
        twin = int(np.sum(np.abs(lam[columns[:k]] - lam[j]) <= 1e-8 * scale))
        x = np.cos((twin + 1) * np.arange(1, n + 1)) + 0j
        for nudge in (0.0, 1e-13 * scale):
            # singular to the last bit is what the shift aims at: said by the nudge, not a warning
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"), warnings.catch_warnings():
                warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
                lu = scipy.linalg.lu_factor(A - (lam[j] + nudge) * np.eye(n), check_finite=False)
                y = x
                for _ in range(INVERSE_STEPS):
                    y = scipy.linalg.lu_solve(lu, y / np.linalg.norm(y), check_finite=False)
            if np.all(np.isfinite(y)):
                break
        out[:, k] = y / np.linalg.norm(y)
    return out


def _eigen(
    A: np.ndarray, relaxation_time_s: float, vectors: bool = True
) -> tuple[np.ndarray, np.ndarray | None]:
    """The eigenvalues with Im >= 0 and their eigenvectors (columns; None unless
    ``vectors``); with transient creep the lag's own real eigenvalue (the one nearest
    -1/tau) is left out. LAPACK runs on one thread (``_numerics.one_blas_thread``)."""
    with one_blas_thread():
        if vectors:
            lam, vec = np.linalg.eig(A)
        else:
            lam, vec = np.linalg.eigvals(A), None
    keep = _kept(lam, relaxation_time_s)
    return lam[keep], (vec[:, keep] if vec is not None else None)


def _kept(lam: np.ndarray, relaxation_time_s: float) -> np.ndarray:
    """Which of ``lam`` :func:`_eigen` keeps: Im >= 0, less the lag's own real one."""
    keep = lam.imag >= 0.0
    if relaxation_time_s > 0.0:
        real = np.flatnonzero(lam.imag == 0.0)
        if len(real):
            keep[real[np.argmin(np.abs(lam[real].real + 1.0 / relaxation_time_s))]] = False
    return keep


#: From this many states on, the eigenvectors come from the contact's low rank
#: (:func:`_eigen_vectors`): 0.74x LAPACK's time at 134 states (a wheel on the rail), the
#: same at about 90, 2.3x at 26 (a wheel on the rigid roller), where LAPACK's are taken
LOW_RANK_STATES = 96


def _apart(U: np.ndarray, V: np.ndarray, blocks: Sequence[np.ndarray]) -> bool:
    """Whether a block of A0 (:func:`_state_blocks`) lies apart from the coupling U V^T
    (no force reaches its states and they move none): each of its eigenvalues is then one
    of A's whose vector the low rank cannot give (a rail's normal terms under a constant
    normal load: LAPACK's vectors are cheaper than an inverse iteration for each)."""
    touched = np.any(U != 0.0, axis=1) | np.any(V != 0.0, axis=1)
    return any(bool(np.any(~np.any(touched[states], axis=1))) for states in blocks)


def _eigen_vectors(
    modes: Sequence[ModalDOF],
    damping: np.ndarray,
    linear: LinearContact,
    wheel_speed_rad_s: float,
    layout: _Layout,
    low_rank: bool | None = None,
    known: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The eigenvalues with Im >= 0 of the coupled system and their eigenvectors: with
    ``low_rank`` (None: from :data:`LOW_RANK_STATES` states on) and no block apart from the
    coupling (:func:`_apart`), the eigenvalues by LAPACK (``known``: already found by
    :func:`_eigen` on the same matrix), the vectors from the coupling's low rank
    (:func:`_secular_vectors`, its forces that act) or, where those are not accurate, by
    inverse iteration, and all of them by LAPACK if that fails too; else all of them by
    LAPACK."""
    tau = linear.relaxation_time_s
    A0, U, V = _state_parts(modes, damping, linear, wheel_speed_rad_s, layout)
    A = A0 + U @ V.T

    def lapack() -> tuple[np.ndarray, np.ndarray]:
        lam, vec = _eigen(A, tau)
        assert vec is not None
        return lam, vec

    if not (A.shape[0] >= LOW_RANK_STATES if low_rank is None else low_rank):
        return lapack()  # small: the low rank's bookkeeping costs more than it saves
    acting = np.any(U != 0.0, axis=0) & np.any(V != 0.0, axis=0)  # a force that is exerted and felt
    U, V = U[:, acting], V[:, acting]
    blocks = _state_blocks(layout, tau > 0.0)
    if _apart(U, V, blocks):
        return lapack()
    lam = _eigen(A, tau, vectors=False)[0] if known is None else known
    with one_blas_thread():
        vec = _secular_vectors(A0, U, V, lam, blocks)
        bad = np.flatnonzero(_backward_errors(A, vec, lam) > SECULAR_BACKWARD_ERROR)
        if len(bad):
            vec[:, bad] = _inverse_iteration(A, lam, bad)
            if np.any(_backward_errors(A, vec[:, bad], lam[bad]) > SECULAR_BACKWARD_ERROR):
                return lapack()
    return lam, vec


def _eigen_shares(
    modes: Sequence[ModalDOF],
    damping: np.ndarray,
    linear: LinearContact | float,
    wheel_speed_rad_s: float,
    blocks: _Layout,
    known: np.ndarray | None = None,
) -> tuple[np.ndarray, list[list[int]], np.ndarray]:
    """The eigenvalues with Im >= 0, for each mode the ones assigned to it, and each
    mode's share of each eigenvalue's vibration energy, shape (modes, eigenvalues)
    (``known``: the eigenvalues, where :func:`_eigen` found them already)."""
    linear = LinearContact.of(linear)
    lam, vec = _eigen_vectors(modes, damping, linear, wheel_speed_rad_s, blocks, known=known)
    nq = blocks.coordinates
    q = vec[:nq]
    k = np.concatenate([[md.stiffness_n_m] * size for md, (_, size) in zip(modes, blocks.blocks)])
    m = np.concatenate([[md.mass_kg] * size for md, (_, size) in zip(modes, blocks.blocks)])
    energy = (k[:, None] + m[:, None] * np.abs(lam[None, :]) ** 2) * np.abs(q) ** 2  # (nq, n_lambda)
    per_mode = [energy[i : i + size].sum(axis=0) for i, size in blocks.blocks]  # (modes, n_lambda)
    if blocks.body is not None:  # the counter-body as one more participant
        x = vec[2 * nq : 2 * nq + blocks.body_states]
        per_mode.append((blocks.body.energy_weights()[:, None] * np.abs(x) ** 2).sum(axis=0))
    per = np.array(per_mode)
    share = per / np.maximum(per.sum(axis=0, keepdims=True), 1e-300)
    capacity = [size for _, size in blocks.blocks]
    assigned: list[list[int]] = [[] for _ in modes]
    taken = np.zeros(len(lam), dtype=bool)
    left = min(sum(capacity), len(lam))
    for flat in np.argsort(-share[: len(modes)], axis=None):
        i, j = divmod(int(flat), share.shape[1])
        if not taken[j] and len(assigned[i]) < capacity[i]:
            assigned[i].append(j)
            taken[j] = True
            left -= 1
            if left == 0:
                break
    return lam, assigned, share


def eigen_shares(
    modes: Modes, linear: LinearContact, wheel_speed_rad_s: float = 0.0, body: BodyModel | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """The eigenvalues with Im >= 0 [1/s] of the modes on the linearised contact (with the
    counter-body ``body``), and each mode's share of each one's vibration energy, shape
    (modes (and the counter-body), eigenvalues): one eigen-solve."""
    modes = as_modes(modes)
    damping = np.array([md.damping_ns_m for md in modes])
    lam, _, share = _eigen_shares(
        modes, damping, linear, wheel_speed_rad_s, _blocks(modes, wheel_speed_rad_s, body)
    )
    return lam, share


def _mechanisms(
    modes: Sequence[ModalDOF],
    damping: np.ndarray,
    linear: LinearContact,
    wheel_speed_rad_s: float,
    blocks: _Layout,
    lam: np.ndarray,
) -> list[Mechanism | None]:
    """What makes each eigenvalue of ``lam`` grow, decided by the limits: the same
    eigenvalue (the nearest) of the system without the friction's stiffness coupling
    (mu0 k_H -> 0: falling friction alone) and of the one without the friction damping
    (g -> 0: mode coupling alone). Growing in exactly one of them names that mechanism;
    in both, or only with both terms, "both". None where it decays."""
    grows = lam.real > 0.0
    if not np.any(grows):
        return [None] * len(lam)
    body_normal = blocks.body is not None and bool(np.any(blocks.body.direction == NORMAL))
    if not (linear.couples(modes) or (body_normal and linear.normal_stiffness_n_m and linear.adhesion_ratio)):
        return ["falling friction" if x else None for x in grows]  # no coupling term
    limits: tuple[tuple[Mechanism, LinearContact], ...] = (
        ("falling friction", replace(linear, adhesion_ratio=0.0)),
        ("mode coupling", replace(linear, friction_damping_ns_m=0.0)),
    )
    alone: list[tuple[Mechanism, np.ndarray]] = []
    for name, lin in limits:
        A0, U, V = _state_parts(modes, damping, lin, wheel_speed_rad_s, blocks)
        parts = _state_blocks(blocks, lin.relaxation_time_s > 0.0)
        alone.append((name, _triangular_eigenvalues(A0, U, V, parts, lin.relaxation_time_s)))
    out: list[Mechanism | None] = []
    for x, up in zip(lam, grows):
        if not up:
            out.append(None)
            continue
        names: list[Mechanism] = [name for name, ev in alone if ev[np.argmin(np.abs(ev - x))].real > 0.0]
        out.append(names[0] if len(names) == 1 else "both")
    return out


def _triangular_eigenvalues(
    A0: np.ndarray, U: np.ndarray, V: np.ndarray, blocks: Sequence[np.ndarray], relaxation_time_s: float
) -> np.ndarray:
    """The eigenvalues of A = A0 + U V^T that :func:`_eigen` keeps, the blocks of A0
    (:func:`_state_blocks`) that feed no force (V naught on their states) or take none (U
    naught) solved apart: A's columns (rows) on such a block hold that block alone, so A
    is block triangular and its eigenvalues are theirs and those of the coupled rest,
    one smaller LAPACK solve (the mode-coupling limit, g = 0: the rail's lateral terms take
    mu0 dN and feed nothing, a third of a wheel on the rail's states)."""
    feeds, takes = np.any(V != 0.0, axis=1), np.any(U != 0.0, axis=1)
    coupled = np.zeros(A0.shape[0], dtype=bool)
    apart = []
    for states in blocks:
        inside = np.any(feeds[states], axis=1) & np.any(takes[states], axis=1)
        coupled[states[inside].ravel()] = True
        if not np.all(inside):
            alone = states[~inside]
            apart.append(np.linalg.eigvals(A0[alone[:, :, None], alone[:, None, :]]).ravel())
    rest = np.flatnonzero(coupled)
    with one_blas_thread():
        lam = np.concatenate([np.linalg.eigvals(A0[np.ix_(rest, rest)] + U[rest] @ V[rest].T), *apart])
    return lam[_kept(lam, relaxation_time_s)]


def _speaking(lam: np.ndarray, assigned: Sequence[Sequence[int]], share: np.ndarray) -> list[int]:
    """Per mode, the eigenvalue that speaks for it: the fastest-growing one it takes part in
    (a share of at least :data:`PARTNER_SHARE`: a coupled pair's, or one the counter-body
    holds most of, for each of its modes), else its own slowest-decaying one."""
    ranked = np.argsort(-lam.real, kind="stable")
    growing = ranked[lam.real[ranked] > 0.0]  # the fastest first
    out = []
    for i, own in enumerate(assigned):
        j = max(own, key=lambda jj: lam[jj].real)
        partners = growing[share[i, growing] >= PARTNER_SHARE]
        out.append(int(partners[0]) if len(partners) else j)
    return out


def growth_rates(
    modes: Modes,
    damping: ArrayLike,
    linear: LinearContact | float,
    wheel_speed_rad_s: float = 0.0,
    body: BodyModel | None = None,
    *,
    speaking: bool = False,
) -> np.ndarray:
    """sigma [1/s] of each mode for dampings ``damping`` [N s/m] and the linearised
    contact ``linear`` (a :class:`LinearContact`, or the friction damping g [N s/m] of
    the paper's lateral contact), with the counter-body ``body``: its own slowest-decaying
    eigenvalue each, or with ``speaking`` the one :func:`linear_stability` gives it (the
    fastest-growing eigenvalue it takes part in, a counter-body's too)."""
    modes = as_modes(modes)
    blocks = _blocks(modes, wheel_speed_rad_s, body)
    lam, assigned, share = _eigen_shares(modes, np.asarray(damping, float), linear, wheel_speed_rad_s, blocks)
    if speaking:
        return np.array([lam[j].real for j in _speaking(lam, assigned, share)])
    return np.array([max((lam[j].real for j in js), default=-math.inf) for js in assigned])


def largest_growth_rate(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    wheel_speed_rad_s: float = 0.0,
    body: BodyModel | None = None,
) -> float:
    """The largest growth rate of every eigenvalue at ``op`` [1/s] (> 0: something
    grows), the counter-body ``body``'s own included: what :func:`linear_stability`'s
    fastest eigenvalue grows at, from the eigenvalues alone (no eigenvectors, shares or
    mechanisms)."""
    modes = as_modes(modes)
    linear = LinearContact.at(contact, op)
    damping = np.array([md.damping_ns_m for md in modes])
    A = _state_matrix(modes, damping, linear, wheel_speed_rad_s, _blocks(modes, wheel_speed_rad_s, body))
    lam, _ = _eigen(A, linear.relaxation_time_s, vectors=False)
    return float(lam.real.max())


def _decreasing_root(fn: Callable[[float], float], lo: float, hi: float, floor: float = -math.inf) -> float:
    """The root of a decreasing ``fn``: the bracket [lo, hi] is widened (never below
    ``floor``) until fn(lo) > 0 > fn(hi), then refined by Brent's method; ``floor`` if
    fn is already <= 0 there."""
    for _ in range(80):
        f_lo = fn(lo)
        if f_lo > 0.0:
            break
        if lo <= floor:
            return floor
        lo = max(floor, lo - 2.0 * (hi - lo))
    else:
        return -math.inf
    for _ in range(80):
        if fn(hi) < 0.0:
            return find_root(fn, lo, hi, xtol=1e-15, rtol=1e-10)
        lo, hi = hi, hi + 2.0 * (hi - lo)
    return math.inf


Bounds = str | Iterable[int] | None


def _bound_indices(bounds: Bounds, n: int) -> set[int]:
    if bounds is None:
        return set()
    if isinstance(bounds, str):
        if bounds != "all":
            raise ValueError(f"bounds must be 'all', None or mode indices, got {bounds!r}")
        return set(range(n))
    wanted = {int(i) for i in bounds}
    if any(not 0 <= i < n for i in wanted):
        raise ValueError(f"bounds: mode indices must lie in 0..{n - 1}, got {sorted(wanted)}")
    return wanted


def critical_damping_ratio(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    i: int,
    wheel_speed_rad_s: float = 0.0,
    body: BodyModel | None = None,
) -> float:
    """The modal damping ratio of mode ``i`` above which it is stable at ``op``, the
    other modes at their damping (0 if it is stable without damping): a root of its
    growth rate, found on the coupled eigenvalues (about half :func:`bound_solves`
    eigen-solves)."""
    modes = as_modes(modes)
    linear = LinearContact.at(contact, op)
    damping = np.array([md.damping_ns_m for md in modes])
    crit_c = math.sqrt(modes[i].stiffness_n_m * modes[i].mass_kg)  # c = 2 zeta crit_c

    def sigma_at_zeta(zeta: float) -> float:
        d = damping.copy()
        d[i] = 2.0 * zeta * crit_c
        return float(growth_rates(modes, d, linear, wheel_speed_rad_s, body)[i])

    g = linear.friction_damping_ns_m * modes[i].lateral ** 2
    zeta_sep = -g / (2.0 * crit_c)  # the separated-mode value: the first bracket
    return _decreasing_root(sigma_at_zeta, 0.0, max(2.0 * zeta_sep, 1e-6), floor=0.0)


def critical_friction_slope(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    i: int,
    wheel_speed_rad_s: float = 0.0,
    body: BodyModel | None = None,
) -> float:
    """The friction slope dmu/dzeta at the quasi-static creepage above which mode ``i``
    is stable at ``op`` (a root of its growth rate, as :func:`critical_damping_ratio`)."""
    modes = as_modes(modes)
    linear = LinearContact.at(contact, op)
    damping = np.array([md.damping_ns_m for md in modes])
    scale = contact.normal_load_n / op.rolling_speed_m_s  # g per unit of dmu/dzeta

    def sigma_at_slope(slope: float) -> float:
        lin = replace(linear, friction_damping_ns_m=scale * slope)
        return float(growth_rates(modes, damping, lin, wheel_speed_rad_s, body)[i])

    slope_sep = -modes[i].damping_ns_m / scale
    width = abs(slope_sep) + 1e-3
    return _decreasing_root(sigma_at_slope, slope_sep - width, slope_sep + width)


def linear_stability(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    wheel_speed_rad_s: float = 0.0,
    bounds: Bounds = None,
    body: BodyModel | None = None,
    *,
    stable_modes: bool = True,
) -> StabilityResult:
    """The linear stability of every mode at ``op`` (see the module docstring).

    ``modes``: a ModalDOF or a sequence of them (all seen at the same contact point);
    ``wheel_speed_rad_s``: Omega, rotation of the wheel [rad/s] (0: the paper's model,
    no rotation; a rotating wheel needs the modes' ``nodal_diameters``); ``bounds``:
    the modes whose critical damping ratio and friction slope are found (``"all"``, a
    sequence of indices, or None): growth rates and frequencies take one eigen-solve,
    each mode's bounds :func:`bound_solves` more
    (:func:`stability_seconds`); the others' bounds are NaN. ``stable_modes`` False (no
    bounds asked): where no eigenvalue grows, the eigenvalues alone, without the
    eigenvectors that give each mode its own (``modes`` empty, no shares): what a caller
    needs that reads only whether something grows, at about half the cost.
    """
    modes = as_modes(modes)
    wanted = _bound_indices(bounds, len(modes))
    linear = LinearContact.at(contact, op)
    damping = np.array([md.damping_ns_m for md in modes])
    blocks = _blocks(modes, wheel_speed_rad_s, body)
    known = None
    if not (stable_modes or wanted):
        A = _state_matrix(modes, damping, linear, wheel_speed_rad_s, blocks)
        known = _eigen(A, linear.relaxation_time_s, vectors=False)[0]
        if not np.any(known.real > 0.0):
            return StabilityResult(
                (), known, linear.friction_damping_ns_m, float(wheel_speed_rad_s), linear=linear
            )
    lam, assigned, share = _eigen_shares(modes, damping, linear, wheel_speed_rad_s, blocks, known)
    mechanisms = _mechanisms(modes, damping, linear, wheel_speed_rad_s, blocks, lam)
    result = []
    speaking = _speaking(lam, assigned, share)
    for i in range(len(modes)):
        j = speaking[i]
        sigma, fd = float(lam[j].real), float(abs(lam[j].imag)) / (2 * math.pi)
        zeta_crit = slope_crit = math.nan
        if i in wanted and modes[i].lateral != 0.0:  # else the friction's slope cannot act on it
            zeta_crit = critical_damping_ratio(modes, contact, op, i, wheel_speed_rad_s, body)
            slope_crit = critical_friction_slope(modes, contact, op, i, wheel_speed_rad_s, body)
        order = np.argsort(-share[:, j])
        partners = [i] + [int(k) for k in order[share[order, j] >= PARTNER_SHARE] if k != i]
        result.append(ModeStability(sigma, fd, zeta_crit, slope_crit, mechanisms[j], tuple(partners)))
    return StabilityResult(
        tuple(result),
        lam,
        linear.friction_damping_ns_m,
        float(wheel_speed_rad_s),
        share,
        tuple(mechanisms),
        linear,
        tuple(tuple(js) for js in assigned),
        tuple(speaking),
    )


# --------------------------------------------------------------------------------------
# cost: every analysis here is a count of eigen-solves of the 2N-state matrix
# --------------------------------------------------------------------------------------
#: Beyond this many modes a bound's bracket does not lengthen further (9 solves measured
#: at 581 modes, a wheel of 2.1 m radius to 3 kHz)
BOUND_SOLVES_MODES = 31


def bound_solves(n_modes: int) -> float:
    """Eigen-solves one mode's two bounds take (the bracket and Brent's method on each):
    more among more modes, whose eigenvalues lie closer: measured 14.5 to 15 at 11
    modes, 19 at 15, 23 to 27 at 31 on the shipped designs, rotation off and on; no more
    beyond :data:`BOUND_SOLVES_MODES`."""
    return 12.0 + 0.4 * min(n_modes, BOUND_SOLVES_MODES)


#: One eigen-solve of the n-state system with its eigenvectors, the energy shares and the
#: assignment of its eigenvalues to the modes, on one BLAS thread, costs about
#: EIGEN_SECONDS[0] + EIGEN_SECONDS[1] n^2 + EIGEN_SECONDS[2] n^3 [s] (LAPACK geev:
#: Python's overhead, the shares, then the cubic work, fitted from n = 10 to 800;
#: ``benchmarks/bench_estimates.py`` checks it).
#: Eigenvalues alone (the mechanisms' limits) take :data:`EIGENVALUES_ONLY` of it.
EIGEN_SECONDS = (1.2e-4, 2.5e-7, 6e-10)
EIGENVALUES_ONLY = 0.7
#: Bytes one eigen-solve of n states holds at its peak, per n^2: the state matrix,
#: LAPACK's copy and its real eigenvectors (8 bytes each), the complex eigenvectors and
#: the shares (16 and 8 bytes per entry of half of them).
EIGEN_BYTES_PER_STATE2 = 48.0
#: Rounds of raising a damping bound the mitigation takes, per mode: 0.5 to 1.0
#: measured on the shipped designs (rotation off and on).
MITIGATION_ROUNDS_PER_MODE = 0.8


def _states(modes: Sequence[ModalDOF], rotation: bool, body_states: int = 0) -> int:
    """The size of the state matrix: 2 per mode, 4 per rotating pair, and the
    counter-body's states."""
    return sum(4 if (rotation and md.nodal_diameters >= 1) else 2 for md in modes) + body_states


def eigen_solve_seconds(modes: Sequence[ModalDOF], rotation: bool = False, body_states: int = 0) -> float:
    """The estimated time of one eigen-solve of the coupled system of ``modes`` and a
    counter-body of ``body_states`` states [s]."""
    n = _states(modes, rotation, body_states)
    fixed, square, cubic = EIGEN_SECONDS
    return fixed + square * n**2 + cubic * n**3


def eigen_solve_bytes(modes: Sequence[ModalDOF], rotation: bool = False, body_states: int = 0) -> float:
    """The estimated peak memory of one eigen-solve of the coupled system of ``modes`` and
    a counter-body of ``body_states`` states [bytes] (:data:`EIGEN_BYTES_PER_STATE2`)."""
    return EIGEN_BYTES_PER_STATE2 * _states(modes, rotation, body_states) ** 2


def stability_seconds(
    modes: Sequence[ModalDOF],
    rotation: bool = False,
    bounds: int = 0,
    coupled: bool = True,
    body_states: int = 0,
) -> float:
    """The estimated time of :func:`linear_stability` with ``bounds`` modes' bounds [s]:
    one eigen-solve, the two limits that name the mechanisms where the contact can couple
    modes (``coupled``: some mode moves it normally under a Hertz spring), and
    :func:`bound_solves` per bound."""
    one = eigen_solve_seconds(modes, rotation, body_states)
    limits = 2 * EIGENVALUES_ONLY * one if coupled else 0.0
    return one + limits + one * bound_solves(len(modes)) * bounds


# --------------------------------------------------------------------------------------
# over an operating envelope: the map and what would stop the squeal
# --------------------------------------------------------------------------------------
def _wheel_speeds(speeds_m_s: np.ndarray, rolling_radius_m: float | None) -> np.ndarray:
    if rolling_radius_m is None:
        return np.zeros(len(speeds_m_s))
    return np.array([OperatingPoint(float(v), 0.0).wheel_speed_rad_s(rolling_radius_m) for v in speeds_m_s])


@dataclass(frozen=True)
class StabilityMap:
    """The linear stability over crabbing velocities x rolling speeds.

    crabbing_velocities_m_s (n_vc,), rolling_speeds_m_s (n_speeds,); growth_rate_1_s
    (n_vc, n_speeds): the largest growth rate, 1/s; winner (n_vc, n_speeds): the index
    of the fastest-growing mode; damped_frequency_hz (n_vc, n_speeds): its frequency in
    the frame of the contact, Hz.
    """

    crabbing_velocities_m_s: np.ndarray
    rolling_speeds_m_s: np.ndarray
    growth_rate_1_s: np.ndarray
    winner: np.ndarray
    damped_frequency_hz: np.ndarray


def stability_map(
    modes: Modes,
    contact: ContactLaw,
    crabbing_velocities_m_s: ArrayLike,
    rolling_speeds_m_s: ArrayLike,
    rolling_radius_m: float | None = None,
    candidates: int | None = None,
    body: BodyModel | None = None,
) -> StabilityMap:
    """Growth rate, leading mode and its frequency over crabbing velocities [m/s] x
    rolling speeds [m/s], one eigen-solve per point; ``rolling_radius_m``: the radius
    of a turning wheel (Omega = V0 / R), None for the paper's model (no rotation);
    ``candidates``: the leading mode is one of the first this many modes (default all);
    ``body``: the counter-body."""
    modes = as_modes(modes)
    k = len(modes) if candidates is None else int(candidates)
    vcs = np.asarray(crabbing_velocities_m_s, float)
    speeds = np.asarray(rolling_speeds_m_s, float)
    omegas = _wheel_speeds(speeds, rolling_radius_m)
    damping = np.array([md.damping_ns_m for md in modes])
    shape = (len(vcs), len(speeds))
    growth, freq = np.empty(shape), np.empty(shape)
    winner = np.empty(shape, dtype=np.int64)
    for j, (v0, omega) in enumerate(zip(speeds, omegas)):
        blocks = _blocks(modes, omega, body)
        for i, vc in enumerate(vcs):
            linear = LinearContact.at(contact, OperatingPoint(float(v0), float(vc)))
            lam, assigned, share = _eigen_shares(modes, damping, linear, omega, blocks)
            best = [max(js, key=lambda jj: lam[jj].real) for js in assigned[:k]]
            w = leading_mode(lam, share, [lam[b].real for b in best], k)
            fastest = int(np.argmax(lam.real))
            top = fastest if lam[fastest].real > 0.0 and share[w, fastest] >= PARTNER_SHARE else best[w]
            winner[i, j] = w
            growth[i, j] = lam[top].real
            freq[i, j] = abs(lam[top].imag) / (2 * math.pi)
    return StabilityMap(vcs, speeds, growth, winner, freq)


#: The damping bounds are raised by this fraction above the exact critical values, so
#: that the coupling between modes (each bound moves the others' by about 1e-5) cannot
#: leave a point marginally growing.
MITIGATION_MARGIN = 1e-3


@dataclass(frozen=True)
class Mitigation:
    """What would keep every mode stable over an envelope.

    damping_ratio (n_modes,) : per mode, the smallest modal damping ratio (to
        ``MITIGATION_MARGIN``) that keeps it stable at every point, the others at theirs:
        what a wheel damper must give; damping_worst_point (n_modes, 2): (crab velocity
        m/s, rolling speed m/s) where each bound binds;
    friction_slope : the dmu/dzeta (at the quasi-static creepage) the creep curve must
        not fall below anywhere, with the modes' own damping: what a friction modifier
        must achieve; friction_worst_speed_m_s : the rolling speed where it binds;
    settled : False when the damping bounds still left a point growing after the
        rounds allowed (``reason`` says where); the bounds are then the last ones found.
    """

    damping_ratio: np.ndarray
    damping_worst_point: np.ndarray
    friction_slope: float
    friction_worst_speed_m_s: float
    settled: bool
    reason: str = ""


#: A damping bound below this is the root finder's round-off about 0 (none is needed).
ROUNDOFF_DAMPING_RATIO = 1e-8

#: A damping ratio beyond which a wheel damper is not a remedy (critical damping).
MAX_DAMPING_RATIO = 1.0


#: An eigenvalue takes part in a mode's motion when the mode holds at least this share
#: of its vibration energy.
PARTICIPATION = 0.1


def _damping_to_stop(
    modes: Sequence[ModalDOF],
    linear: LinearContact,
    omega: float,
    i: int,
    zeta_now: float,
    body: BodyModel | None = None,
) -> float:
    """The damping ratio of mode ``i`` (above ``zeta_now``) at which no eigenvalue in
    whose motion it takes part (:data:`PARTICIPATION`) grows: bisection on their largest
    growth rate, after doubling to bracket it (:data:`MAX_DAMPING_RATIO` if even that
    leaves one growing). Used where two close modes trade their eigenvalues."""
    crit_c = math.sqrt(modes[i].stiffness_n_m * modes[i].mass_kg)
    damping = np.array([md.damping_ns_m for md in modes])
    blocks = _blocks(modes, omega, body)

    def largest(zeta: float) -> float:
        d = damping.copy()
        d[i] = 2.0 * zeta * crit_c
        lam, _, share = _eigen_shares(modes, d, linear, omega, blocks)
        return float(np.max(lam.real[share[i] >= PARTICIPATION], initial=-math.inf))

    lo = max(zeta_now, 1e-9)
    hi = 2.0 * lo
    while largest(hi) > 0.0:
        lo, hi = hi, 2.0 * hi
        if hi > MAX_DAMPING_RATIO:
            return MAX_DAMPING_RATIO
    while hi - lo > 1e-4 * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if largest(mid) > 0.0 else (lo, mid)
    return hi


def mitigation_rounds(n_modes: int) -> int:
    """Most rounds of raising a damping bound where a point still grows (each round
    one map of the envelope and one bound)."""
    return 4 * n_modes + 4


def mitigation_seconds(
    modes: Modes, n_crab_velocities: int, n_speeds: int, rotation: bool = False, body_states: int = 0
) -> float:
    """The estimated time of :func:`mitigation` [s]: a damping bound per mode at the
    worst point and a friction-slope bound per mode and speed, then rounds of one map of
    the envelope and one bound each (:data:`MITIGATION_ROUNDS_PER_MODE` per mode, as
    measured; at most :func:`mitigation_rounds`)."""
    modes = as_modes(modes)
    rounds = MITIGATION_ROUNDS_PER_MODE * len(modes)
    bounds = len(modes) * (1 + n_speeds) + rounds
    solves = bounds * bound_solves(len(modes)) / 2 + rounds * n_crab_velocities * n_speeds
    return eigen_solve_seconds(modes, rotation, body_states) * solves


def mitigation(
    modes: Modes,
    contact: ContactLaw,
    crabbing_velocities_m_s: ArrayLike,
    rolling_speeds_m_s: ArrayLike,
    rolling_radius_m: float | None = None,
    max_rounds: int | None = None,
    body: BodyModel | None = None,
) -> Mitigation:
    """The damping per mode and the friction slope that stop squeal over the envelope
    of crabbing velocities x rolling speeds [m/s] (``rolling_radius_m``: a turning
    wheel's radius, None for no rotation).

    Each damping bound is found where the friction damping is most negative by root
    finding on the coupled eigenvalues, then checked at every point of the envelope
    with all modes at their new damping and raised (never lowered) where a point still
    grows, for at most ``max_rounds`` rounds (:func:`mitigation_rounds`); the friction
    slope bound is found at each speed at the largest crabbing velocity."""
    modes = as_modes(modes)
    vcs = np.asarray(crabbing_velocities_m_s, float)
    speeds = np.asarray(rolling_speeds_m_s, float)
    omegas = dict(zip(speeds.tolist(), _wheel_speeds(speeds, rolling_radius_m).tolist()))
    points = [(float(vc), float(v0)) for vc in vcs for v0 in speeds]
    g_at = {p: LinearContact.at(contact, OperatingPoint(p[1], p[0])) for p in points}
    worst = min(points, key=lambda p: g_at[p].friction_damping_ns_m)
    zeta = np.array(
        [
            critical_damping_ratio(
                modes, contact, OperatingPoint(worst[1], worst[0]), i, omegas[worst[1]], body
            )
            for i in range(len(modes))
        ]
    )
    where = np.array([worst] * len(modes), dtype=float)
    rounds = mitigation_rounds(len(modes)) if max_rounds is None else max_rounds
    settled, reason = False, ""
    for _ in range(rounds):
        damped = [d.with_damping_ratio(z * (1 + MITIGATION_MARGIN)) for d, z in zip(modes, zeta)]
        damping = np.array([d.damping_ns_m for d in damped])
        sigma = {p: growth_rates(damped, damping, g_at[p], omegas[p[1]], body) for p in points}
        p, i = max(((p, int(np.argmax(s))) for p, s in sigma.items()), key=lambda pi: sigma[pi[0]][pi[1]])
        if sigma[p][i] <= 0.0:
            settled = True
            break
        op = OperatingPoint(p[1], p[0])
        new = critical_damping_ratio(damped, contact, op, i, omegas[p[1]], body)
        if not new > zeta[i] * (1 + 2 * MITIGATION_MARGIN):
            # two close modes trade their eigenvalues as one's damping changes, so the
            # mode's own growth rate is no longer a decreasing function of it: find
            # instead the damping at which no eigenvalue grows at this point
            new = _damping_to_stop(damped, g_at[p], omegas[p[1]], i, zeta[i], body)
        zeta[i] = new  # each round raises one bound, never lowers it
        where[i] = p
        reason = (
            f"mode {i} still grows ({sigma[p][i]:.3g} 1/s) at Vc = {p[0]:.4g} m/s, "
            f"V0 = {p[1]:.4g} m/s after {rounds} rounds of raising the damping bounds"
        )
    zeta = zeta * (1 + MITIGATION_MARGIN)
    zeta[zeta < ROUNDOFF_DAMPING_RATIO] = 0.0  # the root finder's round-off: none needed
    slopes = {
        v0: max(
            critical_friction_slope(modes, contact, OperatingPoint(v0, float(vcs[-1])), i, omegas[v0], body)
            for i in range(len(modes))
        )
        for v0 in speeds.tolist()
    }
    v_bind = max(slopes, key=lambda v: slopes[v])
    return Mitigation(zeta, where, float(slopes[v_bind]), float(v_bind), settled, "" if settled else reason)
