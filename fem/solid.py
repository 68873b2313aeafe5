"""3-D tetrahedral modal solver for the whole wheel (scikit-fem, P1 or P2).

Linear elasticity ``K`` (``linear_elasticity(*fem.rules.lame(E, nu))``) and the
consistent mass ``M`` (``rho u.v``) are assembled on a tetrahedral mesh of the revolved
profile (z is the wheel axis, the contact point is the tread apex at (R1, 0, 0)).
The bore is clamped (every DOF on a boundary facet lying on r = bore_radius, so the
P2 edge DOFs too), or the wheel is left free-free, in which case the shift is a small
negative number and the six rigid-body modes are recognised (near-zero eigenvalue and
a shape inside the span of the rigid motions) and left out.

Mesh / element choices (see :func:`solve_solid`):

- a second-order mesh (``tetra10``, mid-edge nodes on the true curved tread and bore)
  with isoparametric P2 elements, or
- a first-order mesh with P2 elements on straight-edged tets (the revolution faceted).

Each eigenvector is labelled in cylindrical components (r, theta, z):

- nodal diameters ``n``: the dominant circumferential harmonic. The nodes are binned in
  small (r, z) cells; in each cell a discrete Fourier sum over the nodes' angles gives
  the harmonic content of every component, and the energies are added over cells and
  components (binning avoids cancellation where a component changes sign over the
  cross-section, e.g. across a nodal circle);
- family: the cylindrical component with the largest share of the kinetic energy
  ``phi_c^T M phi_c`` (axial -> z, radial -> r, circumferential -> theta);
- nodal circles: sign changes of the family's component along the profile's
  mid-surface line from the bore to the tread (as :mod:`fem.labels`), at the angle where the
  n-th harmonic of that component peaks; samples below 5 % of the largest magnitude
  on the line are ignored (the clamped bore is not a nodal circle).

Degenerate cos/sin pairs (same n >= 1, same family, relative frequency gap below
``pair_rtol``) become one :class:`~fem.modes.Mode` with two members; the frequency is
their mean, and ``contact_lateral`` holds both members' axial displacement at the
contact point, so the pair-combined modal mass does not depend on the rotation.

The contact is a node (``contact_lateral`` exactly 0.0, modal mass ``inf``), as in
:mod:`fem.axisym`, when (a) the wheel is mirror-symmetric about z = 0
(its profile its own mirror image) and more than half of the mode's nodal squared amplitude has
u_r, u_theta even and u_z odd in z (an in-plane mode; the unstructured mesh is not
symmetric and otherwise leaves a spurious u_z at the contact, i.e. modal masses of
1e6-1e10 kg), or (b) a member's ``|u_z|`` there is at most
``fem.modes.CONTACT_NODE_RTOL`` times its largest DOF magnitude.

Empty band: nothing at or below ``fmax_hz`` gives an empty ModeSet and an
``EmptyBandWarning`` naming the lowest natural frequency (from the eigenpairs the
solve computed anyway: no extra cost). The free-free shift and the rigid-mode
threshold are the scale-free rules of :mod:`fem.rules`.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from skfem import Basis, BilinearForm, ElementTetP1, ElementTetP2, ElementVector, MeshTet1, asm
from skfem.helpers import dot
from skfem.models.elasticity import linear_elasticity

from contact.frames import ContactFrame, contact_frame
from geometry.profile import half_profile

from .eigen import blas_threads, solve_eigen
from .elasticity import assemble_elasticity
from .meshes import to_skfem_tet
from .modes import DEFAULT_FMAX_HZ, EmptyBandWarning, Mode, ModeSet, clean_contact
from .rules import (
    count_sign_changes,
    free_shift,
    in_plane_fraction,
    is_mirror_symmetric,
    lame,
    rigid_frequency,
)

#: Relative frequency gap below which two consecutive modes with the same labels
#: (n >= 1, nodal circles, family) are a degenerate cos/sin pair. The unstructured
#: mesh splits a pair: measured on the Table 1 wheel up to ~1e-4 with P2 and ~1e-2 with
#: P1 on the coarse CI mesh (1.2 %); distinct modes with the same labels are much further apart.
PAIR_RTOL = 2e-2

#: Harmonics searched for the nodal-diameter label.
N_HARMONICS = 40


@dataclass
class SolidModel:
    """Assembled 3-D model: full K, M (all DOFs), the basis and the clamped/free DOFs."""

    mesh: Any  # skfem mesh
    basis: Any
    K: sp.csr_matrix
    M: sp.csr_matrix
    fixed: np.ndarray  # clamped DOFs (empty when free-free)
    free: np.ndarray
    curved: bool


def assemble(
    design, points, tetra, order: int = 2, boundary: str = "clamped", fast: bool = True
) -> SolidModel:
    """Stiffness and mass of the wheel on a tetrahedral mesh, and the clamped DOFs.

    ``fast``: vectorised assembly (:func:`_assemble_elasticity`); ``False`` uses
    scikit-fem's form assembly (the reference, same matrices to round-off)."""
    if order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order}")
    if boundary not in ("clamped", "free"):
        raise ValueError(f"boundary must be 'clamped' or 'free', got {boundary!r}")
    mesh, curved = to_skfem_tet(points, tetra, order)
    elem = ElementVector(ElementTetP2() if order == 2 else ElementTetP1())
    basis = Basis(mesh, elem)
    lam, mu = lame(design.youngs_modulus, design.poissons_ratio)
    rho = design.density

    @BilinearForm
    def mass(u, v, w):
        return rho * dot(u, v)

    if fast:
        K, M = assemble_elasticity(mesh, basis, elem, lam, mu, rho)
    else:
        K = asm(linear_elasticity(lam, mu), basis)
        M = asm(mass, basis)
    n = basis.N
    if boundary == "clamped":
        rb = design.bore_radius
        # Bore facets: boundary facets whose corner centroid lies on (or, for straight
        # chords, just inside) r = bore_radius; interior facets are h away.
        tol = 1e-6 * design.rolling_radius
        facets = mesh.facets_satisfying(lambda x: np.hypot(x[0], x[1]) <= rb + tol, boundaries_only=True)
        if len(facets) == 0:
            raise ValueError("no boundary facet found on the bore (r = bore_radius)")
        fixed = np.unique(basis.get_dofs(facets).all())
    else:
        fixed = np.zeros(0, dtype=np.int64)
    free = np.setdiff1d(np.arange(n), fixed)
    return SolidModel(mesh, basis, K, M, fixed, free, curved)


# -- labels -----------------------------------------------------------------------------


def _cyl(xyz: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cylindrical components (u_r, u_theta, u_z) of Cartesian u at points xyz (3, N)."""
    th = np.arctan2(xyz[1], xyz[0])
    c, s = np.cos(th), np.sin(th)
    return c * u[0] + s * u[1], -s * u[0] + c * u[1], u[2]


class _Labeller:
    """Precomputed geometry for labelling mode shapes on one assembled model."""

    def __init__(self, design, asm_: SolidModel):
        self.design = design
        b = asm_.basis
        self.basis = b
        self.M = asm_.M
        # component DOF index arrays (x, y, z) and their locations, all DOFs
        self.comp = [b.nodal_dofs[c] for c in range(3)]
        xyz = b.doflocs[:, self.comp[0]]
        if b.edge_dofs.size:
            self.comp = [np.concatenate([b.nodal_dofs[c], b.edge_dofs[c]]) for c in range(3)]
            xyz = b.doflocs[:, self.comp[0]]
        self.xyz = xyz
        self.theta = np.arctan2(xyz[1], xyz[0])
        r = np.hypot(xyz[0], xyz[1])
        z = xyz[2]
        # (r, z) bins for the harmonic analysis
        nr, nz = 24, 6
        ri = np.clip(((r - r.min()) / (np.ptp(r) + 1e-300) * nr).astype(int), 0, nr - 1)
        zi = np.clip(((z - z.min()) / (np.ptp(z) + 1e-300) * nz).astype(int), 0, nz - 1)
        self.bin = ri * nz + zi
        self.nbins = nr * nz
        self.count = np.bincount(self.bin, minlength=self.nbins).astype(float)
        nmax = N_HARMONICS
        self.harm = np.exp(-1j * np.outer(np.arange(nmax + 1), self.theta))  # (nh, N)
        # radial line along the profile's mid-surface for the nodal-circle count
        rl, zl, half = half_profile(design).mid_surface(200)
        near = np.abs(z - np.interp(r, rl, zl)) <= np.interp(r, rl, half) / 2
        self.line_sel = np.nonzero(near)[0]
        self.line_nbins = 40
        edges = np.linspace(rl[0], rl[-1], self.line_nbins + 1)
        self.line_bin = np.clip(np.searchsorted(edges, r[near]) - 1, 0, self.line_nbins - 1)

    def vectors(self, phi: np.ndarray) -> np.ndarray:
        """(3, N) Cartesian components at the DOF locations."""
        return np.stack([phi[c] for c in self.comp])

    def spectrum(self, phis: list[np.ndarray]) -> np.ndarray:
        """Energy per harmonic n (summed over members, components, (r, z) bins)."""
        E = np.zeros(N_HARMONICS + 1)
        for phi in phis:
            ur, ut, uz = _cyl(self.xyz, self.vectors(phi))
            for u in (ur, ut, uz):
                F = self.harm * u  # (nh, N)
                S = np.zeros((N_HARMONICS + 1, self.nbins), dtype=complex)
                for k in range(N_HARMONICS + 1):
                    S[k] = np.bincount(self.bin, weights=F[k].real, minlength=self.nbins) + 1j * np.bincount(
                        self.bin, weights=F[k].imag, minlength=self.nbins
                    )
                cnt = np.maximum(self.count, 1.0)
                # Parseval: mean square = c0^2 + 2 sum |c_n|^2, c_n = S / count
                e = np.abs(S) ** 2 / cnt
                e[1:] *= 2.0
                E += e.sum(axis=1)
        return E

    def family(self, phis: list[np.ndarray]) -> tuple[str, np.ndarray]:
        frac = np.zeros(3)
        for phi in phis:
            ur, ut, uz = _cyl(self.xyz, self.vectors(phi))
            th = self.theta
            for i, (vx, vy, vz) in enumerate(
                (
                    (ur * np.cos(th), ur * np.sin(th), 0 * ur),
                    (-ut * np.sin(th), ut * np.cos(th), 0 * ut),
                    (0 * uz, 0 * uz, uz),
                )
            ):
                v = np.zeros_like(phi)
                v[self.comp[0]], v[self.comp[1]], v[self.comp[2]] = vx, vy, vz
                frac[i] += v @ (self.M @ v)
        frac /= frac.sum()
        fam = ("radial", "circumferential", "axial")[int(np.argmax(frac))]
        return fam, frac

    def nodal_circles(self, phi: np.ndarray, n: int, family: str) -> int:
        """Sign changes of the family's component along the web mid-surface radius.

        The DOFs within a quarter of the local thickness of the mid-surface line are
        binned by radius; in each bin the n-th angular Fourier coefficient of the
        component is ``a(r) e^{i phi}`` with one phase for a standing wave, so
        ``Re(c(r) e^{-i phi})`` is the signed amplitude along the line at the angle of
        maximum response. Bins below 5 % of the peak are ignored.
        """
        ci = {"radial": 0, "circumferential": 1, "axial": 2}[family]
        u = _cyl(self.xyz, self.vectors(phi))[ci]
        sel = self.line_sel
        w = u[sel] * self.harm[n, sel]
        c = np.bincount(self.line_bin, weights=w.real, minlength=self.line_nbins) + 1j * np.bincount(
            self.line_bin, weights=w.imag, minlength=self.line_nbins
        )
        cnt = np.bincount(self.line_bin, minlength=self.line_nbins)
        ok = cnt > 0
        c = c[ok] / cnt[ok]
        if c.size == 0:
            return -1
        ref = c[np.argmax(np.abs(c))]
        line = (c * np.conj(ref) / abs(ref)).real
        return count_sign_changes(line)


def straight_basis(asm_: SolidModel):
    """A basis for point evaluation (``probes``) with the same DOF numbering.

    On a curved ``MeshTet2`` scikit-fem's ``probes`` inverts the isoparametric map by
    Newton on every candidate element and fails on elements far from the point. The
    straight-sided ``MeshTet1`` on the same corner nodes and cells numbers its P1/P2
    DOFs identically (vertices, then edges built from the same ``t``), so its
    ``probes`` matrix applies to the curved solution vector; the only approximation is
    the affine map in the few boundary elements whose mid-edge nodes are curved
    (displacement error of the order of the sagitta h^2 / 8R times the gradient).
    """
    m = asm_.mesh
    if not asm_.curved:
        return asm_.basis
    straight = Basis(MeshTet1(np.ascontiguousarray(m.p[:, : m.nvertices]), m.t), asm_.basis.elem)
    if straight.N != asm_.basis.N or not (
        np.array_equal(straight.nodal_dofs, asm_.basis.nodal_dofs)
        and np.array_equal(straight.edge_dofs, asm_.basis.edge_dofs)
    ):
        raise RuntimeError("straight and curved P2 bases number their DOFs differently")
    return straight


def _contact_operator(design, asm_: SolidModel, contact: ContactFrame) -> tuple[sp.csr_matrix, str]:
    """Rows giving u_z and u_x (axial, radial) at the contact point (r, 0, z), and how
    they were obtained.

    The gmsh mesh has a node at the tread apex: the P1/P2 nodal DOF there is the value
    itself (no interpolation). Otherwise interpolate with ``basis.probes``; if the point
    is outside the (faceted) mesh, take the nearest node and say so: the shape varies
    over a circumferential half-wavelength pi R1 / n >> h, so the nearest node is
    accurate to O((h n / R1)^2).
    """
    b = asm_.basis
    xc = np.array([contact.r_m, 0.0, contact.z_m])
    vert = b.doflocs[:, b.nodal_dofs[2]]
    dist = np.linalg.norm(vert - xc[:, None], axis=0)
    j = int(np.argmin(dist))
    rows = sp.csr_matrix(([1.0, 1.0], ([0, 1], [b.nodal_dofs[2, j], b.nodal_dofs[0, j]])), shape=(2, b.N))
    if dist[j] <= 1e-9 * design.rolling_radius:
        return rows, "node"
    try:
        P = sp.csr_matrix(straight_basis(asm_).probes(xc[:, None]))
        return sp.csr_matrix(sp.vstack([P[2:3], P[0:1]])), "probes"
    except Exception:
        return rows, f"nearest node ({dist[j] * 1e3:.3g} mm away)"


def _rigid_modes(xyz_by_comp: list[np.ndarray], comp: list[np.ndarray], n: int) -> np.ndarray:
    """(n, 6) rigid-body motions (3 translations, 3 rotations) as DOF vectors."""
    R = np.zeros((n, 6))
    x, y, z = xyz_by_comp
    for c in range(3):
        R[comp[c], c] = 1.0
    # rotation about x: (0, -z, y); about y: (z, 0, -x); about z: (-y, x, 0)
    R[comp[1], 3], R[comp[2], 3] = -z, y
    R[comp[0], 4], R[comp[2], 4] = z, -x
    R[comp[0], 5], R[comp[1], 5] = -y, x
    return R


def solve_solid(
    design,
    mesh,
    *,
    order: int = 2,
    fmax_hz: float | None = DEFAULT_FMAX_HZ,
    k: int | None = None,
    boundary: str = "clamped",
    factorization: str = "auto",
    contact: ContactFrame | None = None,
) -> ModeSet:
    """Natural modes of the wheel from a 3-D tetrahedral model.

    Parameters
    ----------
    design: a :class:`~geometry.wheel_design.WheelDesign`.
    mesh: a ``SolidMesh`` (``points``, ``tetra`` in meshio order, ``order``), from
        ``geometry.gmsh_mesh.mesh_wheel`` (``MESH_ORDER`` gives the mesh order to use).
    order: element order, 1 (P1, locks in bending: diagnostic only) or 2 (P2).
    fmax_hz / k: all modes up to ``fmax_hz``, or the ``k`` lowest modes (a degenerate
        pair counts as one mode), or both (the ``k`` lowest within the band).
    boundary: ``"clamped"`` (bore fixed) or ``"free"`` (six rigid modes dropped).
    factorization: passed to :func:`fem.eigen.solve_eigen` (``"auto"`` picks the
        fastest available).
    contact: the contact frame of the modes' contact components (``contact.frames``;
        default the design's).

    Returns a :class:`~fem.modes.ModeSet` whose ``points``/``cells`` are the corner
    nodes and ``"tetra"`` cells, ``shapes[i]`` of shape (members, n_points, 3).
    """
    contact = contact or contact_frame(design)
    if k is None and fmax_hz is None:
        raise ValueError("give k or fmax_hz")
    t0 = time.perf_counter()
    timings: dict[str, float] = {}
    timings["mesh"] = time.perf_counter() - t0

    t1 = time.perf_counter()
    model = assemble(design, mesh.points, mesh.tetra, order=order, boundary=boundary)
    timings["assemble"] = time.perf_counter() - t1
    ms, _ = solve_model(design, model, fmax_hz=fmax_hz, k=k, factorization=factorization, contact=contact)
    timings.update({key: v for key, v in ms.timings_s.items() if key != "total"})
    timings["total"] = time.perf_counter() - t0
    ms.timings_s = timings
    return ms


def eigen_guess(fmax_hz: float, n_rigid: int = 0) -> int:
    """Expected number of 3-D eigenpairs below ``fmax_hz`` (first Lanczos run).

    The Table 1 wheel has 25 below 5 kHz (plate-like: the count grows about linearly
    with f). A first run just above the count takes half the time of one that starts
    low and grows; an underestimate only costs a rerun.
    """
    return int(5.0 * fmax_hz / 1000.0) + 4 + n_rigid


def solve_model(
    design,
    model: SolidModel,
    *,
    fmax_hz: float | None = DEFAULT_FMAX_HZ,
    k: int | None = None,
    factorization: str = "auto",
    contact: ContactFrame | None = None,
) -> tuple[ModeSet, list[np.ndarray]]:
    """Eigen-solve and label an assembled model (``contact``: the contact frame of the
    modes' contact components, default the design's).

    Returns the :class:`~fem.modes.ModeSet` and, for each mode, its mass-normalised
    members as full DOF vectors, shape (n_dofs, members) (zeros on clamped DOFs), for
    checks that need the mass matrix (``model.M``).
    """
    if k is None and fmax_hz is None:
        raise ValueError("give k or fmax_hz")
    contact = contact or contact_frame(design)
    A = model
    t2 = time.perf_counter()
    Kf = A.K[A.free][:, A.free].tocsr()
    Mf = A.M[A.free][:, A.free].tocsr()
    free_free = A.fixed.size == 0
    sigma = free_shift(design) if free_free else 0.0
    n_rigid = 6 if free_free else 0
    # Band: solve slightly past fmax so a pair straddling the edge is not split.
    band = None if fmax_hz is None else fmax_hz * (1.0 + PAIR_RTOL)
    nvec = None if k is None else 2 * k + 1 + n_rigid
    guess = None if band is None else eigen_guess(band, n_rigid)
    res = solve_eigen(Kf, Mf, k=nvec, fmax_hz=band, sigma=sigma, factorization=factorization, guess=guess)
    t_eig = time.perf_counter() - t2

    t3 = time.perf_counter()
    lam = res.eigenvalues
    X = np.zeros((A.basis.N, res.vectors.shape[1]))
    X[A.free] = res.vectors
    # Labelling is many small BLAS calls (dots and matvecs on 1e4-1e5 entries): on a
    # shared machine several BLAS threads spin against each other and make it slower
    with blas_threads():
        if free_free:
            X, lam = _drop_rigid(A, X, lam, rigid_frequency(design))
        modes, shapes, groups = _build_modes(design, A, X, lam, fmax_hz, k, contact)
    if not modes and fmax_hz is not None:
        f_low = res.lowest_hz(skip=n_rigid)
        low = f"the lowest is {f_low:.4g} Hz" if f_low is not None else "none was found"
        warnings.warn(
            f"no natural frequency at or below fmax_hz = {fmax_hz:g} Hz "
            f"({'free' if free_free else 'clamped'} wheel {getattr(design, 'name', '')!r}): "
            f"{low}; returning an empty ModeSet (raise fmax_hz)",
            EmptyBandWarning,
            stacklevel=3,
        )
    t_lab = time.perf_counter() - t3
    order = 2 if A.basis.edge_dofs.size else 1
    ms = ModeSet(
        modes=modes,
        points=A.mesh.p[:, : A.mesh.nvertices].T.copy(),
        cells={"tetra": A.mesh.t.T.copy()},
        shapes=shapes,
        solver=f"3d-p{order}",
        contact_point=(contact.r_m, 0.0, contact.z_m),
        contact_angle_rad=contact.angle_rad,
        dofs=int(A.free.size),
        timings_s={"eigen": t_eig, "label": t_lab, "total": t_eig + t_lab},
    )
    return ms, [X[:, g] for g in groups]


#: Mesh order requested from ``mesh_wheel`` for each element order when ``mesh`` is None.
MESH_ORDER = {1: 1, 2: 2}


def _drop_rigid(
    A: SolidModel, X: np.ndarray, lam: np.ndarray, f_rigid: float
) -> tuple[np.ndarray, np.ndarray]:
    """Remove the six rigid-body modes of a free-free solve (checked, not assumed)."""
    b = A.basis
    comp = [
        np.concatenate([b.nodal_dofs[c], b.edge_dofs[c]]) if b.edge_dofs.size else b.nodal_dofs[c]
        for c in range(3)
    ]
    xyz = b.doflocs[:, comp[0]]
    R = _rigid_modes([xyz[0], xyz[1], xyz[2]], comp, b.N)
    # M-orthonormal basis of the rigid space
    G = R.T @ (A.M @ R)
    L = np.linalg.cholesky(G)
    Q = np.linalg.solve(L, R.T).T
    proj = Q.T @ (A.M @ X)  # (6, m)
    inside = np.sum(proj**2, axis=0)  # fraction of the (unit) M-norm in the rigid span
    rigid = (np.sqrt(np.maximum(lam, 0.0)) / (2 * math.pi) < f_rigid) & (inside > 0.999)
    if np.count_nonzero(rigid) != 6:
        raise RuntimeError(
            f"free-free solve: expected 6 rigid-body modes, recognised {np.count_nonzero(rigid)} "
            f"(lowest frequencies {np.sqrt(np.abs(lam[:8])) / (2 * math.pi)} Hz)"
        )
    return X[:, ~rigid], lam[~rigid]


def _mirror_map(design, A: SolidModel):
    """For a mirror-symmetric wheel: the DOF locations (3, N), the
    DOF indices of each component and, for each location, the nearest location to its
    mirror image (x, y, -z); ``None`` for a dished wheel.

    An unstructured mesh is not symmetric, so the mirror image of a node is generally
    not a node; the nearest one (at most about half an element away) is close enough
    for the parity test, which only separates ~1 (in-plane) from ~0 (out-of-plane).
    """
    if not is_mirror_symmetric(design):
        return None
    from scipy.spatial import cKDTree  # noqa: PLC0415

    b = A.basis
    comp = [
        np.concatenate([b.nodal_dofs[c], b.edge_dofs[c]]) if b.edge_dofs.size else b.nodal_dofs[c]
        for c in range(3)
    ]
    xyz = b.doflocs[:, comp[0]]
    mirrored = xyz * np.array([[1.0], [1.0], [-1.0]])
    _, j = cKDTree(xyz.T).query(mirrored.T)
    return xyz, comp, j


def _in_plane_parity(mirror, members: list[np.ndarray]) -> float:
    """:func:`fem.rules.in_plane_fraction` of the members, on the 3-D DOF locations and
    their nearest mirror images."""
    xyz, comp, j = mirror
    u = np.array([_cyl(xyz, np.stack([x[c] for c in comp])) for x in members])  # (m, 3, N): r, t, z
    u = u[:, [0, 2, 1]]  # (u_r, u_z, u_theta)
    return in_plane_fraction(u, u[:, :, j])


def _build_modes(design, A: SolidModel, X: np.ndarray, lam: np.ndarray, fmax_hz, k, contact: ContactFrame):
    lab = _Labeller(design, A)
    crow, _how = _contact_operator(design, A, contact)
    parity = _mirror_map(design, A) if contact.z_m == 0.0 else None
    f = np.sqrt(np.maximum(lam, 0.0)) / (2 * math.pi)
    m = X.shape[1]
    info = []
    for j in range(m):
        spec = lab.spectrum([X[:, j]])
        n = int(np.argmax(spec))
        fam, _ = lab.family([X[:, j]])
        info.append((n, lab.nodal_circles(X[:, j], n, fam), fam))
    groups: list[list[int]] = []
    j = 0
    while j < m:
        n = info[j][0]
        if (
            n >= 1
            and j + 1 < m
            and info[j + 1] == info[j]
            and abs(f[j + 1] - f[j]) <= PAIR_RTOL * max(f[j], 1e-300)
        ):
            groups.append([j, j + 1])
            j += 2
        else:
            groups.append([j])
            j += 1
    modes: list[Mode] = []
    shapes: list[np.ndarray] = []
    vdofs = A.basis.nodal_dofs  # (3, n_vertices)
    kept = []
    for g in groups:
        fr = float(np.mean(f[g]))
        if fmax_hz is not None and fr > fmax_hz:
            continue
        if k is not None and len(modes) >= k:
            break
        kept.append(g)
        members = [X[:, j] for j in g]
        n, circles, fam = info[g[0]]
        if len(g) == 1 and n >= 1:
            warnings.warn(
                f"3-D mode at {fr:.1f} Hz has n={n} but no degenerate partner within "
                f"{PAIR_RTOL:g}: reported with one member",
                RuntimeWarning,
                stacklevel=3,
            )
        at = np.array([crow @ x for x in members])  # (axial, radial) of each member
        if parity is not None:  # a symmetric wheel, the contact in its mirror plane
            # an in-plane mode has no axial motion there, an out-of-plane one no radial
            at[:, 0 if _in_plane_parity(parity, members) > 0.5 else 1] = 0.0
        tn = [contact.components(float(r_), float(z_)) for z_, r_ in at]
        peaks = [float(np.abs(x).max()) for x in members]
        lateral = tuple(clean_contact(t, p) for (t, _), p in zip(tn, peaks))
        normal = tuple(clean_contact(n_, p) for (_, n_), p in zip(tn, peaks))
        modes.append(Mode(len(modes), fr, n, circles, fam, lateral, normal))
        shapes.append(np.stack([x[vdofs].T for x in members]))
    return modes, shapes, kept


__all__ = [
    "PAIR_RTOL",
    "SolidModel",
    "assemble",
    "eigen_guess",
    "solve_model",
    "solve_solid",
    "straight_basis",
]
