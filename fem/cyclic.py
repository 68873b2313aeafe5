"""3-D P2 modes of the whole wheel by cyclic symmetry (the harmonic split in 3-D).

The mesh is :func:`geometry.revolve.revolve_profile`: N identical sectors of curved P2
tetrahedra. Its stiffness and mass are invariant under a rotation by ``Delta = 2 pi /
N``, so in each sector's own rotated frame the global matrices are block-circulant and
the full 3-D eigenproblem splits exactly into N/2 + 1 independent sector problems,
one per harmonic index p (the nodal diameters):

    K_p = E00 + J^T E11 J + e^{i p Delta} E01 J + e^{-i p Delta} J^T E10,

where ``E`` is the stiffness of sector 0's tetrahedra alone, split between the nodes
sector 0 owns (0) and those on its far face (1, rotated into sector 1's frame), and
``J`` maps a far-face node to the same profile node on face 0 (a Bloch wave:
``u_(s+1) = e^{i p Delta} u_s``); the same for M. ``K_p = A + iB`` is Hermitian (A
symmetric, B antisymmetric). p = 0 and p = N/2 are real problems; every other p is
solved as the real symmetric problem ``[[A, -B], [B, A]]`` of twice the size, whose
eigenvalues come in exact pairs: the cos/sin pair of the wheel. The eigenvalues are
those of the full 3-D problem on the same mesh (tested against :mod:`fem.solid` to
round-off), at the cost of ~p_max small problems instead of one large one.

Only sector 0 is assembled (scikit-fem basis, :func:`fem.elasticity.assemble_elasticity`).
Labels: n = p exactly; family, nodal circles and the in-plane parity from the mode's
(complex) amplitude on face 0, which is the profile mesh, with
:class:`fem.labels.ProfileLabeller` (the axisymmetric solver's own rules). Contact
modal mass: the contact point is a node of face 0; a pair is reported with its two
members ``sqrt(2/N) Re, Im`` of the Bloch wave, so ``m = 1 / (phi_a^2 + phi_b^2) = N /
(2 |x_z|^2)`` for ``x^H M_p x = 1``: independent of the pair's rotation by construction.

Harmonics are solved from p = 0 upwards and stop, as in :mod:`fem.axisym`, at the
first p >= 2 with nothing in the band. An N-sector mesh represents p <= N/2 only: a
band reaching p = N/2 gets a :class:`~fem.modes.ResolutionWarning`.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from contact.frames import ContactFrame

from .axisym import assemble_harmonic
from .eigen import blas_threads, small_problem_factorization, solve_band
from .elasticity import assemble_elasticity
from .labels import ProfileLabeller
from .meshes import to_skfem_tet, to_skfem_tri
from .modes import DEFAULT_FMAX_HZ, EmptyBandWarning, Mode, ModeSet, ResolutionWarning
from .rules import free_shift, harmonics_done, lame, rigid_frequency

#: Default circumferential element length, in units of the profile element size: the
#: sector elements are smooth along theta (P2, 2 pi R1 / N long), so they can be longer
#: than across the section; see :func:`default_sectors`.
SECTOR_ASPECT = 2.0
#: Fewest sectors by default (resolves n <= 8 with 3 P2 elements per half-wave).
MIN_SECTORS = 48


def default_sectors(design, size: float) -> int:
    """Default N: circumferential element length about ``SECTOR_ASPECT`` profile element
    sizes at the rolling radius, at least ``MIN_SECTORS``, rounded up to a multiple of 4."""
    n = max(MIN_SECTORS, math.ceil(2 * math.pi * design.rolling_radius / (SECTOR_ASPECT * size)))
    return int(4 * math.ceil(n / 4))


class SectorModel:
    """Assembled sector-0 matrices of a cyclic mesh, split for the Bloch reduction."""

    def __init__(self, design, mesh, boundary: str = "clamped"):
        if getattr(mesh, "n_sectors", 0) <= 0:
            raise ValueError(
                "solve_cyclic needs a cyclic mesh from geometry.revolve.revolve_profile "
                "(n_sectors > 0); for a gmsh mesh use fem.solid.solve_solid"
            )
        if boundary not in ("clamped", "free"):
            raise ValueError(f"boundary must be 'clamped' or 'free', got {boundary!r}")
        from skfem import Basis, ElementTetP1, ElementTetP2, ElementVector  # noqa: PLC0415

        L = mesh.sector_layout()
        self.layout = L
        self.n_sectors = N = L.n_sectors
        self.delta = 2 * math.pi / N
        no, nf = len(L.owned), len(L.next_face)
        slab = np.concatenate([L.owned, L.next_face])
        local = np.full(mesh.n_nodes, -1, dtype=np.int64)
        local[slab] = np.arange(len(slab))
        tet = local[np.asarray(mesh.tetra)[L.tetra]]
        pts = np.asarray(mesh.points)[slab]
        # scikit-fem wants the vertices first (SolidMesh convention)
        corner = np.unique(tet[:, :4])
        rest = np.setdiff1d(np.arange(len(slab)), corner)
        perm = np.concatenate([corner, rest])
        inv = np.empty_like(perm)
        inv[perm] = np.arange(len(perm))
        order = 2 if mesh.order == 2 else 1
        skm, _ = to_skfem_tet(pts[perm], inv[tet], order if tet.shape[1] == 10 else 1)
        elem = ElementVector(ElementTetP2() if order == 2 else ElementTetP1())
        basis = Basis(skm, elem)
        lam, mu = lame(design.youngs_modulus, design.poissons_ratio)
        K, M = assemble_elasticity(skm, basis, elem, lam, mu, design.density)
        # scikit-fem DOF -> (slab node, component), by location
        comp = np.empty(basis.N, dtype=np.int64)
        for k in range(3):
            comp[basis.nodal_dofs[k]] = k
            if basis.edge_dofs.size:
                comp[basis.edge_dofs[k]] = k
        dist, node = cKDTree(pts).query(basis.doflocs.T)
        if dist.max() > 1e-9 * design.rolling_radius or np.unique(3 * node + comp).size != basis.N:
            raise RuntimeError("sector DOFs do not match the mesh nodes")
        n_slab = 3 * len(slab)
        P = sp.csr_matrix((np.ones(basis.N), (3 * node + comp, np.arange(basis.N))), shape=(n_slab, basis.N))
        # far-face nodes: Cartesian = R(Delta) * (sector 1's own frame)
        c, s = math.cos(self.delta), math.sin(self.delta)
        R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        rot = sp.block_diag([sp.identity(3 * no), sp.block_diag([R] * nf)], format="csr")
        T = P.T @ rot  # skfem DOFs <- local-frame slab DOFs
        J = sp.csr_matrix(
            (np.ones(3 * nf), (np.arange(3 * nf), (3 * L.next_face_local[:, None] + np.arange(3)).ravel())),
            shape=(3 * nf, 3 * no),
        )
        self.parts = {}
        for name, A in (("K", K), ("M", M)):
            Al = (T.T @ A @ T).tocsr()
            E00, E01, E11 = Al[: 3 * no, : 3 * no], Al[: 3 * no, 3 * no :], Al[3 * no :, 3 * no :]
            X = (E01 @ J).tocsr()
            self.parts[name] = ((E00 + J.T @ E11 @ J).tocsr(), X)
        xyz = pts[:no]
        if boundary == "clamped":
            r = np.hypot(xyz[:, 0], xyz[:, 1])
            bore = np.nonzero(r <= design.bore_radius + 1e-6 * design.rolling_radius)[0]
            if bore.size == 0:
                raise ValueError("no mesh node on the bore (r = bore_radius) to clamp")
            fixed = (3 * bore[:, None] + np.arange(3)).ravel()
        else:
            fixed = np.zeros(0, dtype=np.int64)
        self.free = np.setdiff1d(np.arange(3 * no), fixed)
        self.n_owned = no

    def matrices(self, p: int) -> tuple[sp.csr_matrix, sp.csr_matrix, bool]:
        """Real (K, M) of harmonic p on the free DOFs, and whether it is the doubled
        real form ``[[A, -B], [B, A]]`` of the Hermitian ``A + iB`` (0 < p < N/2)."""
        phi = p * self.delta
        f = self.free
        out = []
        real = p == 0 or 2 * p == self.n_sectors
        for name in ("K", "M"):
            D, X = self.parts[name]
            A = (D + math.cos(phi) * (X + X.T))[f][:, f]
            if real:
                out.append(A.tocsc())
                continue
            B = (math.sin(phi) * (X - X.T))[f][:, f]
            out.append(sp.bmat([[A, -B], [B, A]], format="csc"))
        return out[0], out[1], not real


def _complex_modes(K2, M2, vals, vecs, nf: int, rtol: float = 1e-6):
    """Eigenpairs of the Hermitian problem from those of its doubled real form.

    The doubled problem's eigenvalues come in exact pairs whose real vectors span a
    space closed under multiplication by i; a Rayleigh-Ritz step in the complex span of
    the computed vectors returns one M-orthonormal complex vector per pair (robust
    when distinct pairs are close)."""
    Z = vecs[:nf] + 1j * vecs[nf:]
    if Z.shape[1] == 0:
        return vals[:0], Z
    A = K2[:nf, :nf] + 1j * K2[nf:, :nf]
    Mh = M2[:nf, :nf] + 1j * M2[nf:, :nf]
    G = Z.conj().T @ (Mh @ Z)
    w, U = np.linalg.eigh((G + G.conj().T) / 2)
    keep = w > 0.5 * w.max()
    Y = Z @ (U[:, keep] / np.sqrt(w[keep]))
    H = Y.conj().T @ (A @ Y)
    lam, V = np.linalg.eigh((H + H.conj().T) / 2)
    return lam, Y @ V


def solve_cyclic(
    design,
    mesh,
    *,
    fmax_hz: float | None = DEFAULT_FMAX_HZ,
    k: int | None = None,
    boundary: str = "clamped",
    factorization: str | None = None,
    contact: ContactFrame | None = None,
) -> ModeSet:
    """Natural modes of the wheel from the 3-D P2 model, by cyclic symmetry.

    Parameters
    ----------
    design: a :class:`~geometry.wheel_design.WheelDesign`.
    mesh: a cyclic ``SolidMesh``: a second-order profile mesh revolved in sectors
        (:func:`geometry.revolve.revolve_profile`, :func:`default_sectors` of them).
    fmax_hz / k: all modes up to ``fmax_hz``, or the ``k`` lowest (a pair counts once).
    boundary: ``"clamped"`` (bore fixed) or ``"free"`` (rigid-body modes dropped: two
        at p = 0, two pairs at p = 1).
    factorization: of each harmonic problem (:func:`fem.eigen.solve_eigen`); default
        :func:`fem.eigen.small_problem_factorization`.
    contact: the contact frame of the modes' contact components (``contact.frames``;
        default the design's).

    Returns a :class:`~fem.modes.ModeSet` (``solver="3d-cyclic-p2"``), points and
    ``"tetra"`` cells of the whole wheel's corner nodes, ``shapes[i]`` (members,
    n_points, 3); ``dofs`` is the size of the equivalent full 3-D problem (free DOFs);
    ``timings_s`` has "mesh", "assemble", "eigen", "label", "total".
    """
    if k is None and fmax_hz is None:
        raise ValueError("give k or fmax_hz")
    if k is not None and k < 1:
        raise ValueError(f"k must be positive, got {k}")
    t0 = time.perf_counter()
    t_mesh = time.perf_counter()
    with blas_threads(1):  # small problems (see fem.axisym.solve_axisymmetric)
        return _solve(design, mesh, fmax_hz, k, boundary, factorization, t0, t_mesh, contact)


def _profile_labeller(design, mesh, layout, boundary, contact):
    """The axisymmetric labeller on face 0 (the profile mesh) and the map from its
    DOFs (U, V, W at each node) to the owned-local nodes."""
    tri = layout.face_triangles  # local indices 0..n-1 = the profile's own numbering
    rz = np.asarray(mesh.points)[layout.owned[: int(tri.max()) + 1]][:, [0, 2]].T.copy()
    skm = to_skfem_tri(rz.T, tri, curved=True)
    model = assemble_harmonic(design, skm, order=2 if tri.shape[1] == 6 else 1, boundary=boundary)
    dist, node = cKDTree(rz.T).query(model.basis.doflocs.T)
    if dist.max() > 1e-9 * design.rolling_radius:
        raise RuntimeError("profile DOFs do not match the face-0 nodes")
    # profile component (0 U = u_r, 1 V = u_z, 2 W = u_theta) -> local Cartesian at theta=0
    cart = np.array([0, 2, 1])[model.comp]
    return ProfileLabeller(design, model, contact), 3 * node + cart


def _whole_wheel_mode(
    i: int, f: float, p: int, x: np.ndarray, S: SectorModel, mesh, labeller, prof_dof: np.ndarray
) -> tuple[Mode, np.ndarray]:
    """Mode ``i`` (frequency ``f``, harmonic ``p``, the owned-local Bloch vector ``x``)
    labelled on the profile, with its contact values and its shape on the whole wheel's
    corner nodes (members, n_points, 3)."""
    N = S.n_sectors
    nv = mesh.n_vertices // N
    theta = S.delta * np.arange(N)
    cos_t, sin_t = np.cos(theta)[:, None], np.sin(theta)[:, None]
    ic = 3 * mesh.contact_node + 2  # contact node = profile vertex on face 0 = local index
    ir = 3 * mesh.contact_node  # its x component: radial at (R1, 0, 0)
    real = p == 0 or 2 * p == N
    # the profile field, phased so that (u_r, u_z) are real: the cos member
    xp = x[prof_dof]
    if real:
        x2 = xp.real
    else:
        ur_uz = np.isin(prof_dof % 3, (0, 2))
        alpha = 0.5 * np.angle(np.sum(np.where(ur_uz, xp**2, -(xp**2))))
        xr = xp * np.exp(-1j * alpha)
        x2 = np.where(ur_uz, xr.real, -xr.imag)
    family, circles = labeller.label(x2)
    scale = math.sqrt((1.0 if real else 2.0) / N)
    peak = scale * float(np.abs(x).max())
    if labeller.at_apex:
        ur, uz = scale * x[ir], scale * x[ic]  # the contact is a node of face 0
    else:
        u = labeller.P_contact @ xp
        ur, uz = scale * u[0], scale * u[1]
    forbidden = labeller.parity_zero(x2)
    gate_t, gate_n = labeller.contact_of(x2, forbidden)  # a node of the cos member is one of the mode
    parts = [(ur.real, uz.real)] if real else [(ur.real, uz.real), (ur.imag, uz.imag)]
    comps = [labeller.contact_components(r_, z_, forbidden, peak) for r_, z_ in parts]
    contact = tuple(0.0 if gate_t == 0.0 else c[0] for c in comps)
    radial = tuple(0.0 if gate_n == 0.0 else c[1] for c in comps)
    # whole-wheel shapes at the corner nodes: sector s is the Bloch wave rotated by s Delta
    u = x[: 3 * nv].reshape(nv, 3)
    wave = np.exp(1j * p * theta)[:, None, None] * u[None]  # (N, nv, 3)
    members = [wave.real] if real else [wave.real, wave.imag]
    out = []
    for w in members:
        g = np.empty_like(w)
        g[..., 0] = cos_t * w[..., 0] - sin_t * w[..., 1]
        g[..., 1] = sin_t * w[..., 0] + cos_t * w[..., 1]
        g[..., 2] = w[..., 2]
        out.append(scale * g.reshape(-1, 3))
    return Mode(i, f, p, circles, family, contact, radial), np.stack(out)


def _solve(design, mesh, fmax_hz, k, boundary, factorization, t0, t_mesh, contact) -> ModeSet:
    if factorization is None:
        factorization = small_problem_factorization()
    S = SectorModel(design, mesh, boundary)
    N = S.n_sectors
    L = S.layout
    labeller, prof_dof = _profile_labeller(design, mesh, L, boundary, contact)
    t_asm = time.perf_counter()

    sigma = 0.0 if boundary == "clamped" else free_shift(design)
    f_rigid = rigid_frequency(design)
    lam_max = None if fmax_hz is None else (2 * math.pi * fmax_hz) ** 2
    nfree = S.free.size
    raw: list[tuple[float, int, np.ndarray]] = []  # (f, p, complex owned-local vector)
    n_rigid = 0
    guess = 4
    p_top = N // 2
    for p in range(p_top + 1):
        K, M, doubled = S.matrices(p)
        mult = 2 if doubled else 1
        res = solve_band(K, M, fmax_hz, None if k is None else mult * k, sigma, mult * guess, factorization)
        if doubled:
            lam, Z = _complex_modes(K, M, res.eigenvalues, res.vectors, nfree)
        else:
            lam, Z = res.eigenvalues, res.vectors.astype(complex)
        found = []
        for lam_j, z in zip(lam, Z.T):
            f = math.sqrt(max(lam_j, 0.0)) / (2 * math.pi)
            if boundary == "free" and f < f_rigid:
                n_rigid += 1
                continue
            if lam_max is not None and lam_j > lam_max:
                continue
            x = np.zeros(3 * S.n_owned, dtype=complex)
            x[S.free] = z
            raw.append((f, p, x))
            found.append(f)
        guess = max(3, len(found) + 2)
        if p == p_top and found:
            warnings.warn(
                f"modes in the band at the highest harmonic the {N}-sector mesh represents "
                f"(p = {p_top}): higher nodal diameters alias onto lower ones; use more sectors",
                ResolutionWarning,
                stacklevel=3,
            )
        if harmonics_done(p, found, [r[0] for r in raw], k):
            break
    if boundary == "free" and n_rigid != 4:  # p = 0: z-translation, z-rotation; p = 1: two pairs
        raise RuntimeError(f"free-free solve: expected 4 rigid-body eigenpairs (p = 0, 1), found {n_rigid}")
    t_eig = time.perf_counter()

    raw.sort(key=lambda r: r[0])
    if k is not None:
        raw = raw[:k]
    if not raw and fmax_hz is not None:
        warnings.warn(
            f"no natural frequency at or below fmax_hz = {fmax_hz:g} Hz ({boundary} wheel "
            f"{getattr(design, 'name', '')!r}): returning an empty ModeSet (raise fmax_hz)",
            EmptyBandWarning,
            stacklevel=3,
        )

    modes: list[Mode] = []
    shapes: list[np.ndarray] = []
    for i, (f, p, x) in enumerate(raw):
        mode, shape = _whole_wheel_mode(i, f, p, x, S, mesh, labeller, prof_dof)
        modes.append(mode)
        shapes.append(shape)
    t_end = time.perf_counter()
    return ModeSet(
        modes=modes,
        points=np.asarray(mesh.points)[: mesh.n_vertices].copy(),
        cells={"tetra": np.asarray(mesh.tetra)[:, :4].copy()},
        shapes=shapes,
        solver=f"3d-cyclic-p{2 if mesh.order == 2 else 1}",
        contact_point=(labeller.contact.r_m, 0.0, labeller.contact.z_m),
        contact_angle_rad=labeller.contact.angle_rad,
        dofs=int(N * nfree),
        timings_s={
            "mesh": t_mesh - t0,
            "assemble": t_asm - t_mesh,
            "eigen": t_eig - t_asm,
            "label": t_end - t_eig,
            "total": t_end - t0,
        },
    )


__all__ = ["MIN_SECTORS", "SECTOR_ASPECT", "SectorModel", "default_sectors", "solve_cyclic"]
