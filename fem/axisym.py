"""Axisymmetric-harmonic (Fourier) finite elements for the wheel's natural modes.

The wheel is a body of revolution about the z axis. Its displacement is expanded in
circumferential harmonics; for ``n`` nodal diameters the *cos member* is

    u_r = U(r, z) cos(n t),   u_z = V(r, z) cos(n t),   u_t = W(r, z) sin(n t)

and the *sin member* (the same 2-D problem, so the same frequency for n >= 1) is
``u_r = U sin, u_z = V sin, u_t = -W cos``. Each n gives one 2-D eigenproblem on the
(r, z) half-profile with three unknowns (U, V, W) per node. With
``(r, t, z)`` cylindrical coordinates the engineering strains of the cos member are

    eps_r    = U_r                          cos(n t)
    eps_z    = V_z                          cos(n t)
    eps_t    = (U + n W) / r                cos(n t)
    gamma_rz = U_z + V_r                    cos(n t)
    gamma_zt = W_z - n V / r                sin(n t)
    gamma_rt = W_r - W / r - n U / r        sin(n t)

(``gamma_zt = du_t/dz + (1/r) du_z/dt``, ``gamma_rt = (1/r) du_r/dt + du_t/dr - u_t/r``).
For an isotropic material the cos-strains and the sin-strains do not couple, so the
integral over the angle gives a factor ``pi`` on every term for n >= 1. For n = 0 the
problem splits: (U, V) (radial/axial, u_t = 0) and W alone (torsion, ``u_t = W``, no
sin factor); both are integrated with ``2 pi``. With these factors the mass matrix
is the 3-D kinetic-energy mass of the cos member, so a mass-normalised 2-D vector is
a mass-normalised 3-D shape and ``V`` at the contact point is the ``phi_z`` of
"Modal parameters at the contact" in docs/theory.md.

Because every strain is affine in n (``eps = eps0 + n eps1``), the stiffness is
``K_n = c_n (K0 + n K1 + n^2 K2)`` with ``c_n = pi`` (n >= 1) or ``2 pi`` (n = 0);
K0, K1, K2 and M are assembled once (r-weighted, ``w.x[0]`` is r) and combined per n.

Quadrature: the terms ``(U/r)^2 r = U^2 / r`` are not polynomial. The bore keeps
``r >= r_bore > 0`` and an element adjacent to the bore spans at most ``h / r_bore``
(about 0.1 for the wheels here) of its radius, so ``1/r`` is smooth on every element
and a Gauss rule a few orders above the polynomial part converges geometrically. The
polynomial parts need order 5 (P2 mass ``U V r``: 2 + 2 + 1). We use ``intorder = 2p + 3``
(7 for P2); see ``tests/test_fem_axisym.py::test_quadrature_converged`` for the
measured effect on the coarsest Table 1 mesh (1 element across the web): relative
frequency change vs order 12 is 5e-7 at order 4 (scikit-fem's default for P2), 6e-10 at
order 7).

Boundary conditions: ``boundary="clamped"`` fixes U = V = W = 0 at the bore
(r = bore radius); ``"free"`` leaves the wheel free. Free-free rigid-body modes --
n = 0: axial translation (V = const) and spin about the axis (W = r); n = 1: lateral
translations (U = 1, W = -1) and tilts (U = z, V = -r, W = -z) -- come out at
numerically zero frequency; they are recognised by ``fem.rules.rigid_frequency`` and
dropped.

Labels: :mod:`fem.labels` (family, nodal circles, contact, in-plane parity; the rules
in :mod:`fem.rules`). Warnings: :mod:`fem.fidelity` (locking, resolution) and
``EmptyBandWarning`` (nothing at or below ``fmax_hz``: an empty ModeSet whose message
gives the lowest natural frequency). Shapes for visualisation: :mod:`fem.shapes`.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
import skfem as fe
from skfem.helpers import dot

from contact.frames import ContactFrame
from geometry.wheel_design import WheelDesign

from .eigen import blas_threads, small_problem_factorization, solve_band, solve_eigen
from .fidelity import fidelity_warnings, mesh_element_size
from .labels import ProfileLabeller
from .meshes import to_skfem_mesh
from .modes import DEFAULT_FMAX_HZ, EmptyBandWarning, Mode, ModeSet
from .rules import free_shift, harmonics_done, lame, rigid_frequency
from .shapes import expand_harmonic, revolved_mesh

__all__ = ["HarmonicModel", "assemble_harmonic", "solve_axisymmetric"]

#: hard cap on the harmonic index when none is given
N_MAX_DEFAULT = 60


# ------------------------------------------------------------------------------------
# forms
# ------------------------------------------------------------------------------------
def _strains(u, r):
    """(eps0, eps1): the n-independent part and the coefficient of n of the six
    engineering strains (eps_r, eps_z, eps_t, gamma_rz, gamma_zt, gamma_rt)."""
    U, V, W = u[0], u[1], u[2]
    gU, gV, gW = u.grad[0], u.grad[1], u.grad[2]
    z = 0.0 * U
    eps0 = (gU[0], gV[1], U / r, gU[1] + gV[0], gW[1], gW[0] - W / r)
    eps1 = (z, z, W / r, z, -V / r, -U / r)
    return eps0, eps1


def _energy(a, b, lam, mu):
    """a : C b for engineering strain tuples (isotropic C)."""
    tra = a[0] + a[1] + a[2]
    trb = b[0] + b[1] + b[2]
    return (
        lam * tra * trb
        + 2.0 * mu * (a[0] * b[0] + a[1] * b[1] + a[2] * b[2])
        + mu * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5])
    )


def _make_forms(E: float, nu: float, rho: float):
    lam, mu = lame(E, nu)

    @fe.BilinearForm
    def k0(u, v, w):
        r = w.x[0]
        e0u, _ = _strains(u, r)
        e0v, _ = _strains(v, r)
        return _energy(e0u, e0v, lam, mu) * r

    @fe.BilinearForm
    def k1(u, v, w):
        r = w.x[0]
        e0u, e1u = _strains(u, r)
        e0v, e1v = _strains(v, r)
        return (_energy(e0u, e1v, lam, mu) + _energy(e1u, e0v, lam, mu)) * r

    @fe.BilinearForm
    def k2(u, v, w):
        r = w.x[0]
        _, e1u = _strains(u, r)
        _, e1v = _strains(v, r)
        return _energy(e1u, e1v, lam, mu) * r

    @fe.BilinearForm
    def mass(u, v, w):
        return rho * dot(u, v) * w.x[0]

    return k0, k1, k2, mass


# ------------------------------------------------------------------------------------
# the harmonic model (assembled once)
# ------------------------------------------------------------------------------------
@dataclass
class HarmonicModel:
    """The n-independent matrices of the harmonic problem on one profile mesh."""

    mesh: fe.Mesh
    basis: fe.CellBasis
    K0: sp.csr_matrix
    K1: sp.csr_matrix
    K2: sp.csr_matrix
    M: sp.csr_matrix
    free: np.ndarray  # free DOF indices (clamp removed)
    comp: np.ndarray  # component (0 U, 1 V, 2 W) of every global DOF

    def matrices(self, n: int, dofs: np.ndarray | None = None) -> tuple[sp.csr_matrix, sp.csr_matrix]:
        """(K_n, M_n) restricted to ``dofs`` (default: the free DOFs)."""
        c = 2 * math.pi if n == 0 else math.pi
        d = self.free if dofs is None else dofs
        K = (self.K0 + n * self.K1 + (n * n) * self.K2)[d][:, d]
        return (c * K).tocsc(), (c * self.M[d][:, d]).tocsc()


def _assemble_forms(basis: fe.CellBasis, E: float, nu: float, rho: float):
    """K0, K1, K2, M with scikit-fem ``BilinearForm``s (reference path, slower: the
    forms are called once per pair of the 18 local basis functions)."""
    k0, k1, k2, mass = _make_forms(E, nu, rho)
    return tuple(f.assemble(basis).tocsr() for f in (k0, k1, k2, mass))


def _assemble_einsum(mesh: fe.Mesh, scalar: fe.Element, intorder: int, E: float, nu: float, rho: float):
    """The same matrices as :func:`_assemble_forms`, with the element matrices of all
    elements computed at once (numpy einsum over quadrature points) from the scalar
    basis, then scattered. The local vector DOF ``3 i + c`` is component c of scalar
    function i, and the global one ``3 I + c`` (scikit-fem's ElementVector numbering)."""
    sb = fe.Basis(mesh, scalar, intorder=intorder)
    nb = sb.Nbfun
    N = np.array([np.asarray(sb.basis[i][0]) for i in range(nb)])  # (nb, nel, nq)
    dN = np.array([sb.basis[i][0].grad for i in range(nb)])  # (nb, 2, nel, nq)
    r = np.asarray(sb.global_coordinates())[0]  # (nel, nq)
    dx = sb.dx  # (nel, nq) includes the quadrature weights and |J|
    nel, nq = r.shape
    ir = 1.0 / r
    # B[s, a] with a = 3 i + c: engineering strain s of local vector function a
    B0 = np.zeros((6, nb, 3, nel, nq))
    B1 = np.zeros((6, nb, 3, nel, nq))
    dr, dz = dN[:, 0], dN[:, 1]
    B0[0, :, 0] = dr  # eps_r = U_r
    B0[1, :, 1] = dz  # eps_z = V_z
    B0[2, :, 0] = N * ir  # eps_t = U / r (+ n W / r)
    B1[2, :, 2] = N * ir
    B0[3, :, 0] = dz  # gamma_rz = U_z + V_r
    B0[3, :, 1] = dr
    B0[4, :, 2] = dz  # gamma_zt = W_z (- n V / r)
    B1[4, :, 1] = -N * ir
    B0[5, :, 2] = dr - N * ir  # gamma_rt = W_r - W / r (- n U / r)
    B1[5, :, 0] = -N * ir
    B0 = B0.reshape(6, 3 * nb, nel, nq)
    B1 = B1.reshape(6, 3 * nb, nel, nq)
    lam, mu = lame(E, nu)
    C = np.diag([2 * mu] * 3 + [mu] * 3)
    C[:3, :3] += lam
    w = r * dx
    CB0 = np.einsum("st,tanq->sanq", C, B0) * w
    CB1 = np.einsum("st,tanq->sanq", C, B1) * w
    k0 = np.einsum("sanq,sbnq->nab", B0, CB0, optimize=True)
    k1 = np.einsum("sanq,sbnq->nab", B1, CB0, optimize=True)
    k1 = k1 + k1.transpose(0, 2, 1)
    k2 = np.einsum("sanq,sbnq->nab", B1, CB1, optimize=True)
    ms = np.einsum("inq,jnq,nq->nij", N, N, rho * w)  # scalar mass (nel, nb, nb)
    mv = np.zeros((nel, nb, 3, nb, 3))
    for c in range(3):
        mv[:, :, c, :, c] = ms
    mv = mv.reshape(nel, 3 * nb, 3 * nb)
    edofs = (3 * sb.element_dofs[:, None, :] + np.arange(3)[None, :, None]).reshape(3 * nb, nel)
    rows = np.broadcast_to(edofs.T[:, :, None], (nel, 3 * nb, 3 * nb)).ravel()
    cols = np.broadcast_to(edofs.T[:, None, :], (nel, 3 * nb, 3 * nb)).ravel()
    ndof = 3 * sb.N
    out = []
    for loc in (k0, k1, k2, mv):
        A = sp.coo_matrix((loc.ravel(), (rows, cols)), shape=(ndof, ndof)).tocsr()
        A.sum_duplicates()
        out.append(A)
    return tuple(out)


def assemble_harmonic(
    design: WheelDesign,
    mesh: fe.Mesh,
    order: int = 2,
    boundary: str = "clamped",
    intorder: int | None = None,
    method: str = "einsum",
) -> HarmonicModel:
    """Assemble K0, K1, K2 (K_n = K0 + n K1 + n^2 K2) and M, r-weighted, without the
    pi / 2 pi factor. ``method``: "einsum" (vectorised, default) or "forms" (scikit-fem
    BilinearForms; the reference the einsum path is tested against)."""
    if order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order}")
    if boundary not in ("clamped", "free"):
        raise ValueError(f"boundary must be 'clamped' or 'free', got {boundary!r}")
    scalar = fe.ElementTriP2() if order == 2 else fe.ElementTriP1()
    if isinstance(mesh, fe.MeshTri2) and order != 2:
        raise ValueError("a curved MeshTri2 needs order=2")
    if intorder is None:
        intorder = 2 * order + 3
    basis = fe.Basis(mesh, fe.ElementVector(scalar, 3), intorder=intorder)
    E, nu, rho = design.youngs_modulus, design.poissons_ratio, design.density
    if method == "einsum":
        K0, K1, K2, M = _assemble_einsum(mesh, scalar, intorder, E, nu, rho)
    elif method == "forms":
        K0, K1, K2, M = _assemble_forms(basis, E, nu, rho)
    else:
        raise ValueError(f"method must be 'einsum' or 'forms', got {method!r}")
    comp = np.arange(basis.N) % 3  # ElementVector numbering: DOF 3 I + c
    if boundary == "clamped":
        rmin = float(mesh.doflocs[0].min())
        tol = 1e-9 * float(np.ptp(mesh.doflocs[0]) + rmin)
        fixed = basis.get_dofs(lambda x: x[0] < rmin + tol).all()
        if fixed.size == 0:
            raise ValueError("no mesh nodes on the bore to clamp")
        free = np.setdiff1d(np.arange(basis.N), fixed)
    else:
        free = np.arange(basis.N)
    return HarmonicModel(mesh, basis, K0, K1, K2, M, free, comp)


def _lowest_frequency(
    model: HarmonicModel, boundary: str, sigma: float, f_rigid: float, factorization: str, n_last: int
) -> float:
    """The lowest natural frequency [Hz] over the harmonics 0..n_last (for messages)."""
    comp = model.comp
    best = math.inf
    for n in range(n_last + 1):
        if n == 0:
            sets = [model.free[comp[model.free] != 2], model.free[comp[model.free] == 2]]
        else:
            sets = [model.free]
        for dofs in sets:
            K, M = model.matrices(n, dofs)
            res = solve_eigen(K, M, k=min(4, K.shape[0] - 2), sigma=sigma, factorization=factorization)
            f = res.frequencies_hz
            f = f[f >= f_rigid] if boundary == "free" else f
            if f.size:
                best = min(best, float(f.min()))
    return best


# ------------------------------------------------------------------------------------
# the solver
# ------------------------------------------------------------------------------------
def solve_axisymmetric(
    design: WheelDesign,
    mesh: Any,
    *,
    order: int = 2,
    fmax_hz: float | None = DEFAULT_FMAX_HZ,
    k: int | None = None,
    n_max: int | None = None,
    boundary: str = "clamped",
    n_theta: int = 64,
    curved: bool = False,
    intorder: int | None = None,
    factorization: str | None = None,
    contact: ContactFrame | None = None,
) -> ModeSet:
    """Natural modes of the wheel by the axisymmetric-harmonic method.

    Parameters
    ----------
    design: the wheel (geometry and material, SI).
    mesh: a ``geometry.mesh.ProfileMesh`` (``geometry.gmsh_mesh.mesh_profile``: order 1
        for straight P2, order 2 for ``curved``) or a scikit-fem ``MeshTri1``/``MeshTri2``
        of the (r, z) half-profile.
    order: 1 or 2, the Lagrange element order (P2 is the baseline; P1 locks).
    fmax_hz: keep the modes with f <= fmax_hz (``None``: no band, give ``k``).
    k: the k lowest modes (a degenerate pair counts once); with ``fmax_hz`` too, at
        most k modes in the band.
    n_max: highest harmonic solved (default: stop at the first n >= 2 with no mode in
        the band / below the k-th lowest so far).
    boundary: "clamped" (bore fixed) or "free" (rigid-body modes dropped).
    n_theta: angular divisions of the revolved visualisation mesh.
    curved: use the curved (isoparametric) MeshTri2 of a second-order ProfileMesh
        instead of straight P2 triangles on its corner nodes.
    intorder: quadrature order (default 2 * order + 3, see the module docstring).
    factorization: passed to :func:`fem.eigen.solve_eigen`; default
        :func:`small_problem_factorization` (cholmod if installed, else splu).
    contact: the contact point and frame the modes' contact components are given in
        (``contact.frames``; default: the design's, the tread apex for a parametric
        wheel).

    Returns a :class:`fem.modes.ModeSet` sorted by frequency with ``solver="axisym"``;
    ``dofs`` is the number of free DOFs summed over the harmonic problems solved (n = 0
    counts the (U, V) and the W problem); ``timings_s`` has "mesh", "assemble",
    "eigen", "expand" and "total" [s].
    """
    # The harmonic problems are small (1e3-1e4 DOFs): multi-threaded BLAS only adds
    # synchronisation cost there, several times the work on a loaded machine
    with blas_threads(1):
        return _solve_axisymmetric(
            design,
            mesh,
            order=order,
            fmax_hz=fmax_hz,
            k=k,
            n_max=n_max,
            boundary=boundary,
            n_theta=n_theta,
            curved=curved,
            intorder=intorder,
            factorization=factorization,
            contact=contact,
        )


def _harmonics(
    model: HarmonicModel,
    fmax_hz: float | None,
    k: int | None,
    cap: int,
    boundary: str,
    sigma: float,
    f_rigid: float,
    factorization: str,
) -> tuple[list[tuple[float, int, np.ndarray, bool]], int, int]:
    """The modes of each harmonic n = 0, 1, ... in the band (or the k lowest), as
    (frequency, n, full DOF vector, torsion), the DOFs solved, and the last n solved.
    Each harmonic is asked for the previous one's count plus two modes."""
    basis = model.basis
    raw: list[tuple[float, int, np.ndarray, bool]] = []  # (f, n, full vector, torsion)
    dofs_total = 0
    guess = 4  # modes asked of the next harmonic: last in-band count + 2 (grown if short)
    comp = model.comp
    n = 0
    while n <= cap:
        problems = []
        if n == 0:
            uv = model.free[comp[model.free] != 2]
            w_ = model.free[comp[model.free] == 2]
            problems = [(uv, False), (w_, True)]
        else:
            problems = [(model.free, False)]
        found: list[float] = []
        for dofs, torsion in problems:
            K, M = model.matrices(n, dofs)
            dofs_total += len(dofs)
            res = solve_band(K, M, fmax_hz, k, sigma, guess, factorization)
            for lam, vec in zip(res.eigenvalues, res.vectors.T):
                f = math.sqrt(max(lam, 0.0)) / (2 * math.pi)
                if boundary == "free" and f < f_rigid:
                    continue
                if fmax_hz is not None and f > fmax_hz:
                    continue
                x = np.zeros(basis.N)
                x[dofs] = vec
                raw.append((f, n, x, torsion))
                found.append(f)
        guess = max(3, len(found) + 2)
        if harmonics_done(n, found, [r[0] for r in raw], k):
            break
        n += 1
    return raw, dofs_total, n


def _expand(
    raw: list[tuple[float, int, np.ndarray, bool]], labeller: ProfileLabeller, n_theta: int
) -> tuple[list[Mode], list[np.ndarray], np.ndarray, np.ndarray]:
    """Each harmonic mode labelled, and its shape on the revolved visualisation mesh of
    ``n_theta`` divisions (cos member, and sin for n >= 1): (modes, shapes, points, wedges)."""
    points, wedges, theta = revolved_mesh(labeller.pts_rz, labeller.tris, n_theta)
    modes: list[Mode] = []
    shapes: list[np.ndarray] = []
    for i, (f, n, x, torsion) in enumerate(raw):
        family, circles = labeller.label(x)
        t_c, n_c = labeller.contact_of(x)
        # the cos member carries u_r and u_z at theta = 0; the sin member u_theta only
        lateral, normal = ((t_c,), (n_c,)) if n == 0 else ((t_c, 0.0), (n_c, 0.0))
        modes.append(Mode(i, f, n, circles, family, lateral, normal))
        UVW = x[labeller.nodal].T
        members = ["cos"] if n == 0 else ["cos", "sin"]
        shapes.append(np.stack([expand_harmonic(UVW, n, theta, m, torsion) for m in members]))
    return modes, shapes, points, wedges


def _solve_axisymmetric(
    design,
    mesh,
    *,
    order,
    fmax_hz,
    k,
    n_max,
    boundary,
    n_theta,
    curved,
    intorder,
    factorization,
    contact,
) -> ModeSet:
    t_start = time.perf_counter()
    if factorization is None:
        factorization = small_problem_factorization()
    if fmax_hz is None and k is None:
        raise ValueError("give fmax_hz or k")
    if k is not None and k < 1:
        raise ValueError(f"k must be positive, got {k}")
    h = mesh_element_size(mesh)
    skm = to_skfem_mesh(mesh, curved=curved)
    t_mesh = time.perf_counter()
    fidelity_warnings(design, h, order, fmax_hz, before=True)

    model = assemble_harmonic(design, skm, order=order, boundary=boundary, intorder=intorder)
    labeller = ProfileLabeller(design, model, contact)
    t_asm = time.perf_counter()

    sigma = 0.0 if boundary == "clamped" else free_shift(design)
    f_rigid = rigid_frequency(design)
    cap = N_MAX_DEFAULT if n_max is None else n_max

    raw, dofs_total, n = _harmonics(model, fmax_hz, k, cap, boundary, sigma, f_rigid, factorization)
    t_eig = time.perf_counter()

    raw.sort(key=lambda r: r[0])
    if k is not None:
        raw = raw[:k]
    if fmax_hz is None and raw:
        fidelity_warnings(design, h, order, raw[-1][0], before=False)
    if not raw and fmax_hz is not None:
        f_low = _lowest_frequency(model, boundary, sigma, f_rigid, factorization, min(n, cap))
        warnings.warn(
            f"no natural frequency at or below fmax_hz = {fmax_hz:g} Hz ({boundary} wheel "
            f"{design.name!r}): the lowest is {f_low:.4g} Hz; returning an empty ModeSet "
            "(raise fmax_hz)",
            EmptyBandWarning,
            stacklevel=3,
        )

    modes, shapes, points, wedges = _expand(raw, labeller, n_theta)
    t_end = time.perf_counter()
    return ModeSet(
        modes=modes,
        points=points,
        cells={"wedge": wedges},
        shapes=shapes,
        solver="axisym",
        contact_point=(labeller.contact.r_m, 0.0, labeller.contact.z_m),
        contact_angle_rad=labeller.contact.angle_rad,
        dofs=int(dofs_total),
        timings_s={
            "mesh": t_mesh - t_start,
            "assemble": t_asm - t_mesh,
            "eigen": t_eig - t_asm,
            "expand": t_end - t_eig,
            "total": t_end - t_start,
        },
    )
