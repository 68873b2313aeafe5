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
MODEL.md section 4.

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
numerically zero frequency; they are recognised by ``f < RIGID_TOL * f_ref``
(``f_ref = c_s / (2 pi R1)``, c_s the shear wave speed) and dropped.

Labels (documented rules):
- ``family``: the component with the largest share of the mode's kinetic energy
  (``x_c^T M_cc x_c`` for c = U, V, W): V -> "axial", U -> "radial",
  W -> "circumferential".
- ``nodal_circles``: the number of sign changes of that dominant component along the
  web mid-surface line ``z = web_offset`` from the bore to the tread, sampled at 161
  points; samples below 5 % of the line's peak magnitude are ignored (the rule of the 3-D solver), so a clamp or a
  numerically tiny lobe does not count as a circle.
- ``contact_axial``: ``V`` at the contact point (r, z) = (rolling_radius, 0) of the
  mass-normalised cos member (evaluated by interpolation, no node needed there), and
  0.0 for the sin member (it has a nodal diameter through the contact angle):
  ``(V, 0.0)`` for n >= 1, ``(V,)`` for n = 0. The contact is a node (``V`` reported
  as exactly 0.0, modal mass ``inf``) when (a) the wheel is mirror-symmetric about
  z = 0 (``web_offset == 0``) and the mode is in-plane by parity (more than half of
  its r-weighted nodal squared amplitude has U, W even and V odd in z; an
  unstructured mesh is not symmetric and otherwise leaves a spurious V of up to 1e-2
  of the peak at z = 0), or (b) ``|V| <= fem.modes.CONTACT_NODE_RTOL`` (1e-6) times
  the largest DOF magnitude of the mode. A dished wheel's in-plane modes keep their
  genuine axial coupling (1e-2 of the peak and more at a 4 mm offset).

Warnings (``fem.modes``; the modes are still returned):
- ``LockingWarning``: P1 with nu > ``LOCKING_NU`` (volumetric locking) or with fewer
  than ``P1_ELEMENTS_THROUGH_WEB`` elements through the web (bending);
- ``ResolutionWarning``: P2 with an element size above the web thickness, or a band
  whose shortest wavelength (:func:`shortest_wavelength` at ``fmax_hz``, or at the
  highest mode found when only ``k`` is given) spans fewer than
  ``RESOLUTION_ELEMENTS[order]`` elements;
- ``EmptyBandWarning``: nothing at or below ``fmax_hz``; the ModeSet is empty and the
  message gives the lowest natural frequency (``select_mode`` on it raises LookupError).

Shapes for visualisation are expanded onto a revolved mesh made of the profile's corner
nodes rotated to ``n_theta`` angles (meshio "wedge" cells), in Cartesian (x, y, z); the
contact point is at (x, y, z) = (R1, 0, 0), angle 0.
"""

from __future__ import annotations

import functools
import math
import time
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

try:  # optional: one BLAS thread for the many small harmonic problems (see below)
    from threadpoolctl import threadpool_limits
except ImportError:  # pragma: no cover - the solver works without it, just slower
    threadpool_limits = None

import skfem as fe
from skfem.helpers import dot

from geometry.design import WheelDesign, tread_radius

from . import eigen as _eigen
from .eigen import solve_eigen
from .modes import (
    EmptyBandWarning,
    LockingWarning,
    Mode,
    ModeSet,
    ResolutionWarning,
    clean_contact,
)

#: a mode with f < RIGID_TOL * c_s / (2 pi R1) is a rigid-body mode (free-free only)
RIGID_TOL = 1e-3
#: sign changes of samples below this fraction of the peak are ignored (nodal circles)
CIRCLE_THRESHOLD = 0.05
#: number of samples along the web mid-surface line for the nodal-circle count
CIRCLE_SAMPLES = 161
#: hard cap on the harmonic index when none is given
N_MAX_DEFAULT = 60
#: P2 elements across the web when the solver meshes the design itself (mesh=None,
#: no size given). Measured on Table 1 against a 10-per-web curved reference: every
#: mode <= 5 kHz within 0.15 % (1 per web: 0.47 %, 3 per web: 0.07 %), 9.6k DOFs
#: summed over the harmonics, about 0.1-0.4 s (benchmarks/bench_axisym.py).
DEFAULT_ELEMENTS_THROUGH_WEB = 2

# -- fidelity checks (warnings, see fem.modes.FidelityWarning) --------------------------
#: Elements of size h per shortest wavelength at fmax_hz needed for about 1 % frequency
#: error, by element order. The shortest wavelength is ``shortest_wavelength``: the
#: smaller of the web's Kirchhoff bending wavelength and the shear wavelength (the true
#: bending wavelength of a thick plate tends to the shear/Rayleigh one at high
#: frequency, where Kirchhoff's keeps shrinking, so the minimum of the two is a simple
#: lower bound of what the mesh must resolve in the (r, z) plane; the circumferential
#: direction is exact, a Fourier harmonic). Measured on the Table 1 wheel against a
#: 6-per-web reference, P2 with h = web thickness (the ``fast`` preset): every mode
#: within 0.45 % up to 5 kHz (lambda / h = 11), 0.64 % up to 10 kHz (7.7), 1.2 % up to
#: 15 kHz (6.3), 1.8 % up to 20 kHz (5.5), 2.2 % up to 30 kHz (4.5): 1 % at about
#: lambda = 6 h. That is twice the 1-D estimate for P2 with consistent mass (error
#: (kh)^4 / 1440 = 1 % at lambda = 3.2 h; bending and the through-thickness field cost
#: the factor 2); for P1 the 1-D estimate (error (kh)^2 / 24 = 1 % at lambda = 12.8 h)
#: times the same factor 2 gives 24 (P1 warns for locking anyway).
RESOLUTION_ELEMENTS: dict[int, float] = {1: 24.0, 2: 6.0}
#: P1 with fewer elements than this through the web: shear locking in bending, frequency
#: errors above 1 % (Table 1, nu = 0.28: +3.1 % with 4 per web, +0.8 % with 8).
P1_ELEMENTS_THROUGH_WEB = 8
#: Poisson's ratio above which P1 locks volumetrically (Table 1, 8 P1 per web: max error
#: +0.8 % at nu = 0.28, +1.8 % at 0.45, +6.9 % at 0.49, +47 % at 0.499; P2 with 1 per web
#: stays within 2.3 % up to nu = 0.499).
LOCKING_NU = 0.45
#: A design with |web_offset| below this fraction of the rolling radius is mirror
#: symmetric about z = 0: its modes are even (in-plane) or odd (out-of-plane) in z.
SYMMETRY_RTOL = 1e-12


# ------------------------------------------------------------------------------------
# mesh handling
# ------------------------------------------------------------------------------------
def to_skfem_mesh(mesh: Any, curved: bool = False) -> fe.Mesh:
    """A scikit-fem triangle mesh of the (r, z) profile from a ``ProfileMesh`` or a
    scikit-fem ``MeshTri1`` / ``MeshTri2`` (returned as is).

    A second-order ``ProfileMesh`` becomes a curved ``MeshTri2`` (mid-edge nodes on the
    true tread arc) with ``curved=True``, otherwise a straight-sided ``MeshTri1`` built
    from its corner nodes (renumbered), on which ElementTriP2 is used.
    """
    if isinstance(mesh, fe.Mesh):
        return mesh
    pts = np.asarray(mesh.points, dtype=float)[:, :2]
    tri = np.asarray(mesh.triangles, dtype=np.int64)
    if tri.shape[1] == 6 and curved:
        return fe.MeshTri2(np.ascontiguousarray(pts.T), np.ascontiguousarray(tri.T))
    corners = tri[:, :3]
    used, inv = np.unique(corners, return_inverse=True)
    t = inv.reshape(corners.shape)
    p = pts[used]
    # scikit-fem expects counter-clockwise triangles for a positive Jacobian sign only
    # in some places; orient them consistently anyway.
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    t[cross < 0] = t[cross < 0][:, [0, 2, 1]]
    return fe.MeshTri1(np.ascontiguousarray(p.T), np.ascontiguousarray(t.T))


def _corner_mesh(m: fe.Mesh) -> tuple[np.ndarray, np.ndarray]:
    """Corner points (Np, 2) and triangles (M, 3) of a scikit-fem triangle mesh."""
    nv = m.nvertices
    p = np.asarray(m.doflocs[:, :nv].T)
    t = np.array(m.t[:3].T)  # scikit-fem sorts t: orientation is lost, restore CCW
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    cw = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]) < 0
    t[cw] = t[cw][:, [0, 2, 1]]
    return p, t


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
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))

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
# point evaluation (robust for points on, or a hair outside, a curved boundary)
# ------------------------------------------------------------------------------------
def _clip_to_triangle(X: np.ndarray) -> np.ndarray:
    """Project reference coordinates (2, ...) onto the reference triangle."""
    x, y = X[0].copy(), X[1].copy()
    s = x + y
    over = s > 1
    x[over] -= (s[over] - 1) / 2
    y[over] -= (s[over] - 1) / 2
    x, y = np.clip(x, 0, 1), np.clip(y, 0, 1)
    s = x + y
    over = s > 1
    x[over] /= s[over]
    y[over] /= s[over]
    return np.array([x, y])


def probe_matrix(basis: fe.CellBasis, pts: np.ndarray, n_cand: int = 8) -> sp.csr_matrix:
    """Matrix P with ``(P @ x)[c * n + i]`` = component c of the field x at point i.

    Like ``CellBasis.probes`` but robust on the boundary: the element is the nearest
    candidate after projecting the point onto each candidate's straight-sided (corner)
    triangle, and the reference coordinates are clipped to the element. A point on a
    curved boundary, or a chord height outside it, is evaluated at the closest point
    of the mesh (scikit-fem's own finder rejects such points and has no MeshTri2
    version).
    """
    pts = np.atleast_2d(np.asarray(pts, dtype=float))
    if pts.shape[0] != 2:
        pts = pts.T
    npts = pts.shape[1]
    m = basis.mesh
    corners = m.doflocs[:, m.t[:3]]  # (2, 3, nel)
    kc = min(n_cand, m.t.shape[1])
    _, cand = cKDTree(corners.mean(axis=1).T).query(pts.T, kc)
    cand = np.asarray(cand).reshape(npts, kc)
    # affine reference coordinates in each candidate (straight-sided) triangle
    p0 = corners[:, 0, cand]  # (2, npts, kc)
    e1 = corners[:, 1, cand] - p0
    e2 = corners[:, 2, cand] - p0
    det = e1[0] * e2[1] - e1[1] * e2[0]
    d = pts[:, :, None] - p0
    X = np.array([(d[0] * e2[1] - d[1] * e2[0]) / det, (e1[0] * d[1] - e1[1] * d[0]) / det])
    Xc = _clip_to_triangle(X)
    proj = p0 + Xc[0] * e1 + Xc[1] * e2
    dist = np.linalg.norm(proj - pts[:, :, None], axis=0)
    best = np.argmin(dist, axis=1)
    ii = np.arange(npts)
    cells = cand[ii, best]
    Xb = Xc[:, ii, best]
    if not isinstance(basis.mapping, fe.MappingAffine):
        # curved elements: Newton on the isoparametric map from the affine guess
        try:
            Xn = basis.mapping.invF(pts[:, :, None], tind=cells)[:, :, 0]
            Xb = _clip_to_triangle(Xn)
        except Exception:  # noqa: BLE001 (no convergence: keep the affine estimate)
            pass
    Xb = Xb[:, :, None]
    phis = np.array(
        [np.asarray(basis.elem.gbasis(basis.mapping, Xb, k, tind=cells)[0]) for k in range(basis.Nbfun)]
    )  # (Nbfun, comp, npts, 1) or (Nbfun, npts, 1)
    comp = phis.shape[1] if phis.ndim == 4 else 1
    rows = np.tile(np.arange(comp * npts), basis.Nbfun)
    cols = basis.element_dofs[:, np.tile(cells, comp)].ravel()
    return sp.coo_matrix((phis.ravel(), (rows, cols)), shape=(comp * npts, basis.N)).tocsr()


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


def _assemble_einsum(mesh: fe.Mesh, scalar: fe.Element, intorder: int, E: float, nu: float,
                     rho: float):
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
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
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
    design: WheelDesign, mesh: fe.Mesh, order: int = 2, boundary: str = "clamped",
    intorder: int | None = None, method: str = "einsum",
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


# ------------------------------------------------------------------------------------
# revolved visualisation mesh
# ------------------------------------------------------------------------------------
def revolved_mesh(points_rz: np.ndarray, triangles: np.ndarray, n_theta: int):
    """Revolve a profile (corner points (Np, 2), CCW triangles (M, 3)) about z.

    Returns (points (n_theta*Np, 3), wedges (n_theta*M, 6), theta (n_theta,)); point
    ``j*Np + i`` is profile node i at angle ``theta_j = 2 pi j / n_theta``.
    """
    np_ = points_rz.shape[0]
    th = 2 * math.pi * np.arange(n_theta) / n_theta
    r, z = points_rz[:, 0], points_rz[:, 1]
    pts = np.empty((n_theta, np_, 3))
    pts[:, :, 0] = np.cos(th)[:, None] * r
    pts[:, :, 1] = np.sin(th)[:, None] * r
    pts[:, :, 2] = z
    j = np.arange(n_theta)[:, None, None]
    # VTK/meshio wedge: (0, 1, 2) and (3, 4, 5) the same triangle one angular step
    # apart, with (0, 1, 2) ordered so that its right-hand normal points towards (3, 4, 5)
    # (+t): that is a clockwise triangle in the (r, z) plane (checked: positive
    # volumes in VTK, total = the revolved volume of the chordal profile).
    tri = np.asarray(triangles)[None, :, [0, 2, 1]]
    wedges = np.concatenate([tri + j * np_, tri + ((j + 1) % n_theta) * np_], axis=2)
    return pts.reshape(-1, 3), wedges.reshape(-1, 6), th


def _expand(UVW: np.ndarray, n: int, theta: np.ndarray, member: str, torsion: bool) -> np.ndarray:
    """Cartesian displacement (n_theta*Np, 3) of one member from nodal (U, V, W) (Np, 3)."""
    U, V, W = UVW[:, 0], UVW[:, 1], UVW[:, 2]
    if n == 0:
        cr = np.ones_like(theta)
        ct = np.ones_like(theta)
    elif member == "cos":
        cr, ct = np.cos(n * theta), np.sin(n * theta)
    else:  # sin member: u_r = U sin, u_z = V sin, u_t = -W cos
        cr, ct = np.sin(n * theta), -np.cos(n * theta)
    ur = cr[:, None] * U[None, :]
    uz = cr[:, None] * V[None, :]
    ut = ct[:, None] * W[None, :]
    c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]
    out = np.empty(ur.shape + (3,))
    out[..., 0] = ur * c - ut * s
    out[..., 1] = ur * s + ut * c
    out[..., 2] = uz
    return out.reshape(-1, 3)


# ------------------------------------------------------------------------------------
# fidelity checks
# ------------------------------------------------------------------------------------
def shortest_wavelength(design: WheelDesign, f_hz: float) -> float:
    """The shortest wavelength [m] the (r, z) mesh must resolve at ``f_hz``: the smaller
    of the Kirchhoff bending wavelength of the web plate,
    ``2 pi (D / (rho t))^(1/4) / sqrt(omega)`` with ``D = E t^3 / 12 (1 - nu^2)``, and
    the shear wavelength ``c_s / f``."""
    t, E, nu, rho = design.web_thickness, design.youngs_modulus, design.poissons_ratio, design.density
    omega = 2 * math.pi * f_hz
    D = E * t**3 / (12 * (1 - nu * nu))
    bending = 2 * math.pi * (D / (rho * t)) ** 0.25 / math.sqrt(omega)
    shear = math.sqrt(design.shear_modulus / rho) / f_hz
    return min(bending, shear)


def mesh_element_size(mesh: Any) -> float:
    """Characteristic element size h [m] of a profile mesh: ``size`` of a gmsh
    ``ProfileMesh``; for a scikit-fem mesh the median over the elements of the longest
    corner-to-corner edge (on gmsh meshes that is 0.94-0.98 x ``size``)."""
    size = getattr(mesh, "size", None)
    if not isinstance(mesh, fe.Mesh) and isinstance(size, (int, float)) and size > 0:
        return float(size)
    m = to_skfem_mesh(mesh)
    p, t = np.asarray(m.p), np.asarray(m.t[:3])
    edges = np.stack([np.linalg.norm(p[:, t[i]] - p[:, t[(i + 1) % 3]], axis=0) for i in range(3)])
    return float(np.median(edges.max(axis=0)))


def _fidelity_warnings(design: WheelDesign, h: float, order: int, f_top: float | None,
                       before: bool) -> None:
    """Warn (FidelityWarning subclasses) when the discretisation cannot give ~1 %.
    ``before``: the checks that do not need the solution (mesh, order, material);
    otherwise only the wavelength check at ``f_top``."""
    t = design.web_thickness
    per_web = t / h
    if before:
        if order == 1 and design.poissons_ratio > LOCKING_NU:
            warnings.warn(
                f"nu = {design.poissons_ratio:g} > {LOCKING_NU:g} with linear (P1) elements: "
                "volumetric locking makes the frequencies too high (Table 1: +7 % at "
                "nu = 0.49, +47 % at 0.499); use order=2",
                LockingWarning, stacklevel=4)
        if order == 1 and per_web < P1_ELEMENTS_THROUGH_WEB * (1 - 1e-9):
            warnings.warn(
                f"linear (P1) elements with {per_web:.3g} elements through the "
                f"{t * 1e3:.3g} mm web lock in bending: frequencies too high by more than "
                f"1 % (Table 1: +3 % with 4, +0.8 % with {P1_ELEMENTS_THROUGH_WEB}); use order=2",
                LockingWarning, stacklevel=4)
        elif order == 2 and h > t * (1 + 1e-9):
            warnings.warn(
                f"mesh size {h * 1e3:.3g} mm exceeds the web thickness {t * 1e3:.3g} mm "
                "(fewer than one element through the web): frequency errors of several % "
                "(Table 1: 1.4 % at twice the thickness, 6 % at 8 times); use "
                "elements_through_web >= 1",
                ResolutionWarning, stacklevel=4)
    if f_top is not None and f_top > 0:
        lam = shortest_wavelength(design, f_top)
        need = RESOLUTION_ELEMENTS[order]
        if lam < need * h:
            warnings.warn(
                f"the mesh (element size {h * 1e3:.3g} mm, P{order}) does not resolve "
                f"{f_top:.4g} Hz: the shortest wavelength there ({lam * 1e3:.3g} mm, web "
                f"bending or shear) spans {lam / h:.2g} elements, fewer than {need:g} "
                f"(about 1 % frequency error); refine the mesh to size <= "
                f"{lam / need * 1e3:.3g} mm or lower fmax_hz",
                ResolutionWarning, stacklevel=4)


def _in_plane_parity(x_nodes: np.ndarray, x_mirror: np.ndarray, r: np.ndarray) -> float:
    """Fraction of the mode's (r-weighted, nodal) squared amplitude that is even in z for
    U and W and odd for V: 1 for an in-plane mode of a mirror-symmetric wheel (V = 0 on
    the plane z = 0), 0 for an out-of-plane one. ``x_nodes`` / ``x_mirror``: (3, Np)
    values (U, V, W) at the nodes (r, z) and at their mirror images (r, -z)."""
    even = 0.5 * (x_nodes + x_mirror)
    odd = 0.5 * (x_nodes - x_mirror)
    sq_in = r @ (even[0] ** 2 + odd[1] ** 2 + even[2] ** 2)
    sq_out = r @ (odd[0] ** 2 + even[1] ** 2 + odd[2] ** 2)
    total = sq_in + sq_out
    return float(sq_in / total) if total > 0 else 0.0



class ProfileLabeller:
    """Labels of a harmonic mode from its profile field (U, V, W at every DOF of
    ``model.basis``; real: the cos member), shared by this solver and
    :mod:`fem.cyclic`.

    - family: the component with the largest (r-weighted) kinetic energy share;
    - nodal circles: sign changes of that component along the web mid-line
      z = web_offset from the bore to the tread (samples below ``CIRCLE_THRESHOLD`` of
      the peak ignored: the clamped bore is not a nodal circle);
    - contact: V (axial displacement) at the contact point (rolling_radius, 0), or 0.0
      for an in-plane mode of a mirror-symmetric wheel (V = 0 exactly on z = 0; an
      unstructured mesh is not symmetric and leaves a spurious V there, measured up to
      1e-2 of the peak on a coarse thick-web mesh, so the mode's parity decides, from
      the values at the nodes and at their mirror images).
    """

    def __init__(self, design: WheelDesign, model: "HarmonicModel"):
        basis, skm = model.basis, model.mesh
        zc = design.web_offset
        rmin = float(skm.doflocs[0].min())
        rl = np.linspace(rmin, tread_radius(design, zc), CIRCLE_SAMPLES)
        self.P_contact = probe_matrix(basis, np.array([[design.rolling_radius], [0.0]]))  # U, V, W
        self.P_line = probe_matrix(basis, np.vstack([rl, np.full_like(rl, zc)]))
        self.pts_rz, self.tris = _corner_mesh(skm)
        self.nodal = basis.nodal_dofs[:, : skm.nvertices]  # (3, Nv) DOFs at the corners
        self.symmetric = abs(design.web_offset) <= SYMMETRY_RTOL * design.rolling_radius
        self.P_mirror = (probe_matrix(basis, np.vstack([self.pts_rz[:, 0], -self.pts_rz[:, 1]]))
                         if self.symmetric else None)
        self.split = [np.nonzero(model.comp == c)[0] for c in range(3)]
        self.M_blocks = [model.M[idx][:, idx] for idx in self.split]

    def label(self, x: np.ndarray) -> tuple[str, int, float]:
        """(family, nodal circles, axial contact displacement) of profile vector x."""
        energy = np.array([x[i] @ (Mb @ x[i]) for i, Mb in zip(self.split, self.M_blocks)])
        dom = int(np.argmax(energy))
        family = ("radial", "axial", "circumferential")[dom]
        circles = count_sign_changes((self.P_line @ x).reshape(3, -1)[dom], CIRCLE_THRESHOLD)
        v_c = float((self.P_contact @ x)[1])
        if self.symmetric and self.in_plane_fraction(x) > 0.5:
            v_c = 0.0  # in-plane mode of a symmetric wheel: the contact is a node
        return family, circles, clean_contact(v_c, float(np.abs(x).max()))

    def in_plane_fraction(self, x: np.ndarray) -> float:
        """Share of the mode's nodal squared amplitude with in-plane parity (see
        :func:`_in_plane_parity`); only for a mirror-symmetric wheel."""
        return _in_plane_parity(x[self.nodal], (self.P_mirror @ x).reshape(3, -1), self.pts_rz[:, 0])


def _lowest_frequency(model: "HarmonicModel", boundary: str, sigma: float, f_rigid: float,
                      factorization: str, n_last: int) -> float:
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
            res = solve_eigen(K, M, k=min(4, K.shape[0] - 2), sigma=sigma,
                              factorization=factorization)
            f = res.frequencies_hz
            f = f[f >= f_rigid] if boundary == "free" else f
            if f.size:
                best = min(best, float(f.min()))
    return best


# ------------------------------------------------------------------------------------
# the solver
# ------------------------------------------------------------------------------------
def small_problem_factorization() -> str:
    """Factorisation for the harmonic problems (1e3-1e4 DOFs, 2-D fill pattern).

    Measured on Table 1, n = 3, one BLAS thread, 4 modes, median of 5 (1170 / 3930
    DOFs): cholmod 11 / 65 ms, splu (MMD) 23 / 89 ms, pypardiso 300 / 410 ms (its
    set-up cost dominates at this size). So: cholmod if installed, else splu, never
    the 3-D solver's "auto" choice."""
    return _small_problem_factorization()


@functools.lru_cache(maxsize=1)
def _small_problem_factorization() -> str:
    # only probe cholmod: asking fem.eigen for all back-ends would load MKL (pardiso),
    # about 0.3 s, more than the whole solve.
    if "cholmod" not in getattr(_eigen, "FACTORIZATIONS", ()):
        return "splu"
    try:
        import sksparse.cholmod  # noqa: F401, PLC0415 (optional)
    except ImportError:
        return "splu"
    return "cholmod"


def _solve_band(K, M, fmax_hz, k, sigma, guess, factorization="splu"):
    """Eigenpairs of one harmonic: all with f <= fmax_hz (at most k), or the k lowest.

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


def solve_axisymmetric(
    design: WheelDesign,
    mesh: Any = None,
    *,
    order: int = 2,
    size: float | None = None,
    elements_through_web: int | None = None,
    fmax_hz: float | None = 5000.0,
    k: int | None = None,
    n_max: int | None = None,
    boundary: str = "clamped",
    n_theta: int = 64,
    curved: bool = False,
    intorder: int | None = None,
    factorization: str | None = None,
) -> ModeSet:
    """Natural modes of the wheel by the axisymmetric-harmonic method.

    Parameters
    ----------
    design: the wheel (geometry and material, SI).
    mesh: a ``geometry.mesh.ProfileMesh`` or a scikit-fem ``MeshTri1``/``MeshTri2`` of
        the (r, z) half-profile; ``None`` meshes the design with
        ``geometry.mesh.mesh_profile(design, size, elements_through_web, order)``
        (straight order-1 mesh + P2 unless ``curved``; neither size given:
        ``DEFAULT_ELEMENTS_THROUGH_WEB`` = 2 elements across the web).
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

    Returns a :class:`fem.modes.ModeSet` sorted by frequency with ``solver="axisym"``;
    ``dofs`` is the number of free DOFs summed over the harmonic problems solved (n = 0
    counts the (U, V) and the W problem); ``timings_s`` has "mesh", "assemble",
    "eigen", "expand" and "total" [s].
    """
    # The harmonic problems are small (1e3-1e4 DOFs): multi-threaded BLAS only adds
    # synchronisation cost there, several times the work on a loaded 2-core machine
    # (measured: 0.12 s vs 0.85 s for Table 1). Limit BLAS to one thread if we can.
    if threadpool_limits is not None:
        with threadpool_limits(limits=1, user_api="blas"):
            return _solve_axisymmetric(design, mesh, order=order, size=size,
                                       elements_through_web=elements_through_web,
                                       fmax_hz=fmax_hz, k=k, n_max=n_max, boundary=boundary,
                                       n_theta=n_theta, curved=curved, intorder=intorder,
                                       factorization=factorization)
    return _solve_axisymmetric(design, mesh, order=order, size=size,
                               elements_through_web=elements_through_web, fmax_hz=fmax_hz,
                               k=k, n_max=n_max, boundary=boundary, n_theta=n_theta,
                               curved=curved, intorder=intorder, factorization=factorization)


def _solve_axisymmetric(design, mesh, *, order, size, elements_through_web, fmax_hz, k,
                        n_max, boundary, n_theta, curved, intorder, factorization) -> ModeSet:
    t_start = time.perf_counter()
    if factorization is None:
        factorization = small_problem_factorization()
    if fmax_hz is None and k is None:
        raise ValueError("give fmax_hz or k")
    if k is not None and k < 1:
        raise ValueError(f"k must be positive, got {k}")
    if mesh is None:
        from geometry.mesh import mesh_profile  # noqa: PLC0415 (optional, lands separately)

        kwargs: dict[str, Any] = {"order": 2 if (curved and order == 2) else 1}
        if size is not None:
            kwargs["size"] = size
        if elements_through_web is not None:
            kwargs["elements_through_web"] = elements_through_web
        elif size is None:
            kwargs["elements_through_web"] = DEFAULT_ELEMENTS_THROUGH_WEB
        mesh = mesh_profile(design, **kwargs)
    h = mesh_element_size(mesh)
    skm = to_skfem_mesh(mesh, curved=curved)
    t_mesh = time.perf_counter()
    _fidelity_warnings(design, h, order, fmax_hz, before=True)

    model = assemble_harmonic(design, skm, order=order, boundary=boundary, intorder=intorder)
    basis = model.basis
    labeller = ProfileLabeller(design, model)
    pts_rz, tris = labeller.pts_rz, labeller.tris
    nodal = labeller.nodal
    R1 = design.rolling_radius
    t_asm = time.perf_counter()

    G = design.shear_modulus
    f_ref = math.sqrt(G / design.density) / (2 * math.pi * R1)
    sigma = 0.0 if boundary == "clamped" else -((2 * math.pi * 0.05 * f_ref) ** 2)
    f_rigid = RIGID_TOL * f_ref
    cap = N_MAX_DEFAULT if n_max is None else n_max

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
            res = _solve_band(K, M, fmax_hz, k, sigma, guess, factorization)
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
        # stopping rule (n >= 2): the harmonic has nothing in the band, or, for the
        # k lowest, its lowest mode is above the k-th lowest found so far.
        if n >= 2:
            if not found:
                break
            if k is not None and len(raw) >= k:
                kth = sorted(r[0] for r in raw)[k - 1]
                if min(found) > kth:
                    break
        n += 1
    t_eig = time.perf_counter()

    raw.sort(key=lambda r: r[0])
    if k is not None:
        raw = raw[:k]
    if fmax_hz is None and raw:
        _fidelity_warnings(design, h, order, raw[-1][0], before=False)
    if not raw and fmax_hz is not None:
        f_low = _lowest_frequency(model, boundary, sigma, f_rigid, factorization, min(n, cap))
        warnings.warn(
            f"no natural frequency at or below fmax_hz = {fmax_hz:g} Hz ({boundary} wheel "
            f"{design.name!r}): the lowest is {f_low:.4g} Hz; returning an empty ModeSet "
            "(raise fmax_hz)",
            EmptyBandWarning, stacklevel=3)

    points, wedges, theta = revolved_mesh(pts_rz, tris, n_theta)

    modes: list[Mode] = []
    shapes: list[np.ndarray] = []
    for i, (f, n, x, torsion) in enumerate(raw):
        family, circles, v_c = labeller.label(x)
        contact = (v_c,) if n == 0 else (v_c, 0.0)
        modes.append(Mode(i, f, n, circles, family, contact))
        UVW = x[nodal].T
        members = ["cos"] if n == 0 else ["cos", "sin"]
        shapes.append(np.stack([_expand(UVW, n, theta, m, torsion) for m in members]))
    t_end = time.perf_counter()

    return ModeSet(
        modes=modes,
        points=points,
        cells={"wedge": wedges},
        shapes=shapes,
        solver="axisym",
        dofs=int(dofs_total),
        timings_s={
            "mesh": t_mesh - t_start,
            "assemble": t_asm - t_mesh,
            "eigen": t_eig - t_asm,
            "expand": t_end - t_eig,
            "total": t_end - t_start,
        },
    )


def count_sign_changes(values: np.ndarray, threshold: float = CIRCLE_THRESHOLD) -> int:
    """Sign changes of ``values`` ignoring samples below ``threshold * max|values|``."""
    v = np.asarray(values, dtype=float)
    peak = float(np.max(np.abs(v))) if v.size else 0.0
    if peak == 0.0:
        return 0
    s = np.sign(v[np.abs(v) >= threshold * peak])
    return int(np.count_nonzero(s[1:] != s[:-1]))


__all__ = [
    "HarmonicModel",
    "ProfileLabeller",
    "assemble_harmonic",
    "count_sign_changes",
    "probe_matrix",
    "revolved_mesh",
    "small_problem_factorization",
    "solve_axisymmetric",
    "to_skfem_mesh",
]
