"""Sound radiated by a vibrating axisymmetric body, one circumferential harmonic at a
time: the exterior Helmholtz problem on the meridian half-plane (MODEL.md section 9).

For a normal velocity ``vn(r, z) cos(n theta)`` (time convention e^{j w t}) the
pressure is ``P(r, z) cos(n theta)`` with, on the air region A of the (r, z) half-plane,

    integral_A (grad P . L grad Q + a (n^2 / r^2) P Q - k^2 a b^2 P Q) r dA
        = j w rho0 integral_body vn Q r ds,

quadratic triangles (P2). Outside the circle rho = R (rho = sqrt(r^2 + z^2)) a
perfectly matched layer of thickness d stretches rho into
``rho~ = rho - (j / k) F(rho)``, ``F' = sigma0 ((rho - R) / d)^2``: an outgoing wave
e^{-j k rho} decays there as e^{-F}, by e^{-A} at its outer edge (A, the layer's
attenuation in nepers, frequency independent), where P = 0. The stretching of the 3-D
radial coordinate gives ``a = drho~/drho``, ``b = rho~/rho`` and the tensor
``L = (b^2 / a) e e^T + a (I - e e^T)`` (e the radial unit vector); inside R, a = b = 1
and L = I. On the axis P = 0 for n >= 1 (natural for n = 0).

Alternatively (``boundary="abc"``) the mesh ends at R with the first-order
Bayliss-Turkel condition dP/drho = -(j k + 1/rho) P, exact for a monopole only: kept as
the measured reason for the layer (README).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .medium import AIR, Air
from .mesh import AirMesh, air_mesh
from .surface import Surface

__all__ = ["RadiationSettings", "SoundField", "far_field", "radiate"]


@dataclass(frozen=True)
class RadiationSettings:
    """How the air is discretised.

    elements_per_wavelength : P2 triangles per acoustic wavelength away from the body.
    margin : the physical region's radius R is the body's extent times (1 + margin)
        (and beyond every requested field point).
    pml_wavelengths, pml_min_fraction : the layer's thickness d, the larger of that
        many wavelengths and that fraction of R.
    pml_elements : elements across the layer at least.
    pml_attenuation : A, nepers at the layer's outer edge.
    boundary : "pml" or "abc" (see the module docstring).
    """

    elements_per_wavelength: float = 8.0
    margin: float = 0.25
    pml_wavelengths: float = 0.25
    pml_min_fraction: float = 0.5
    pml_elements: int = 8
    pml_attenuation: float = 12.0
    boundary: str = "pml"

    def __post_init__(self) -> None:
        if self.boundary not in ("pml", "abc"):
            raise ValueError(f"boundary must be 'pml' or 'abc', got {self.boundary!r}")
        for name in ("elements_per_wavelength", "margin", "pml_attenuation", "pml_elements"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise ValueError(f"RadiationSettings.{name} must be positive, got {v!r}")


@dataclass(frozen=True, eq=False)
class SoundField:
    """The pressure around the body for one harmonic, and what it radiates.

    mesh : the air mesh; pressure : P at the P2 nodes of ``dof_points`` (complex, Pa,
    amplitude of cos(n theta)); sound_power_w : time-averaged radiated power [W], from
    the far field (the Kirchhoff-Helmholtz integral over the circle rho = R), which
    stays accurate for a poor radiator whose near field is almost all reactive;
    radiation_efficiency : W / (rho c S <vn^2>); surface_power_w : (pi or 2 pi) / 2 Re
    integral P conj(vn) r ds over the body, and flux_power_w : the same through the
    circle rho = R (energy checks: equal to W for a good radiator); frequency_hz, harmonic.
    """

    mesh: AirMesh
    dof_points: np.ndarray
    pressure: np.ndarray
    frequency_hz: float
    harmonic: int
    sound_power_w: float
    radiation_efficiency: float
    surface_power_w: float
    flux_power_w: float
    air: Air

    def pressure_at(self, points_rz: np.ndarray) -> np.ndarray:
        """P [Pa] (complex amplitude of cos(n theta)) at (r, z) points inside R."""
        points_rz = np.atleast_2d(np.asarray(points_rz, dtype=float))
        rho = np.hypot(points_rz[:, 0], points_rz[:, 1])
        if np.any(rho > self.mesh.radius * (1 + 1e-9)):
            raise ValueError(
                f"field points beyond the physical region (rho <= {self.mesh.radius:.3g} m): "
                "give them to radiate() so that it is made large enough"
            )
        basis = _basis(self.mesh)
        return basis.probes(points_rz.T) @ self.pressure


def _skfem_mesh(mesh: AirMesh):
    import skfem as fe

    return fe.MeshTri(np.ascontiguousarray(mesh.points.T), np.ascontiguousarray(mesh.triangles.T))


def _basis(mesh: AirMesh, intorder: int = 4):
    import skfem as fe

    return fe.Basis(_skfem_mesh(mesh), fe.ElementTriP2(), intorder=intorder)


def _stretch(x, radius: float, thickness: float, attenuation: float, k: float):
    """(a, b, e_r, e_z) of the layer at quadrature points x (2, ...)."""
    r, z = x[0], x[1]
    rho = np.hypot(r, z)
    s = np.clip((rho - radius) / thickness, 0.0, None)
    sigma0 = 3.0 * attenuation / thickness
    a = 1.0 - 1j * sigma0 * s**2 / k
    b = 1.0 - 1j * sigma0 * thickness * s**3 / (3.0 * k * np.maximum(rho, 1e-300))
    return a, b, r / rho, z / rho


def _facets(mesh, where) -> np.ndarray:
    """Boundary facets whose both end points satisfy ``where(r, z)``."""
    f = mesh.boundary_facets()
    p = mesh.p[:, mesh.facets[:, f]]  # (2, 2, F)
    return f[where(p[0, 0], p[1, 0]) & where(p[0, 1], p[1, 1])]


def radiate(
    surface: Surface,
    frequency_hz: float,
    air: Air = AIR,
    settings: RadiationSettings | None = None,
    field_points: np.ndarray | None = None,
) -> SoundField:
    """The sound field of ``surface`` vibrating at ``frequency_hz`` [Hz]."""
    import scipy.sparse.linalg as spla
    import skfem as fe

    if not (math.isfinite(frequency_hz) and frequency_hz > 0):
        raise ValueError(f"frequency must be positive, got {frequency_hz!r}")
    settings = settings or RadiationSettings()
    k = air.wavenumber(frequency_hz)
    lam = air.wavelength(frequency_hz)
    n = int(surface.harmonic)
    extent = surface.scale
    radius = extent * (1 + settings.margin)
    if field_points is not None and len(field_points):
        radius = max(radius, 1.05 * float(np.max(np.hypot(*np.atleast_2d(field_points).T))))
    seg = surface.segments()
    seg_len = np.linalg.norm(surface.points[seg[:, 1]] - surface.points[seg[:, 0]], axis=1)
    size_far = min(lam / settings.elements_per_wavelength, radius / 4)
    size_near = min(size_far, float(np.median(seg_len)))
    pml = settings.boundary == "pml"
    thickness = max(settings.pml_wavelengths * lam, settings.pml_min_fraction * radius) if pml else 0.0
    size_far = min(size_far, thickness / settings.pml_elements) if pml else size_far
    mesh = air_mesh(surface, radius, thickness, size_far, size_near)
    skm = _skfem_mesh(mesh)
    basis = fe.Basis(skm, fe.ElementTriP2(), intorder=4)
    tol = 1e-6 * (radius + thickness)

    @fe.BilinearForm(dtype=np.complex128)
    def operator(u, v, w):
        r = w.x[0]
        a, b, er, ez = _stretch(w.x, radius, max(thickness, 1e-300), settings.pml_attenuation, k)
        c = b * b / a - a  # L = a I + (b^2/a - a) e e^T
        gu, gv = u.grad, v.grad
        grads = a * (gu[0] * gv[0] + gu[1] * gv[1]) + c * (er * gu[0] + ez * gu[1]) * (
            er * gv[0] + ez * gv[1]
        )
        return (grads + (a * n * n / (r * r) - k * k * a * b * b) * u * v) * r

    A = operator.assemble(basis)
    body = _facets(skm, lambda r, z: (r > tol) & (np.hypot(r, z) < radius - tol))
    fb = fe.FacetBasis(skm, fe.ElementTriP2(), facets=body, intorder=6)
    x = np.asarray(fb.global_coordinates())
    vn = surface.normal_velocity_at(np.stack([x[0].ravel(), x[1].ravel()], axis=1)).reshape(x[0].shape)
    omega = 2 * math.pi * frequency_hz

    @fe.LinearForm(dtype=np.complex128)
    def load(v, w):
        return 1j * omega * air.density_kg_m3 * w.vn * v * w.x[0]

    rhs = load.assemble(fb, vn=vn)
    if not pml:
        edge = _facets(skm, lambda r, z: (r > tol) & (np.abs(np.hypot(r, z) - radius) < tol))
        eb = fe.FacetBasis(skm, fe.ElementTriP2(), facets=edge, intorder=4)

        @fe.BilinearForm(dtype=np.complex128)
        def robin(u, v, w):
            rho = np.hypot(w.x[0], w.x[1])
            return (1j * k + 1.0 / rho) * u * v * w.x[0]

        A = A + robin.assemble(eb)
    fixed = []
    if pml:
        fixed.append(
            basis.get_dofs(_facets(skm, lambda r, z: np.abs(np.hypot(r, z) - radius - thickness) < tol))
        )
    if n >= 1:
        fixed.append(basis.get_dofs(_facets(skm, lambda r, z: r <= tol)))
    D = np.unique(np.concatenate([f.all() for f in fixed])) if fixed else np.array([], dtype=np.int64)
    P = np.zeros(basis.N, dtype=complex)
    free = np.setdiff1d(np.arange(basis.N), D)
    A = A.tocsr()
    P[free] = spla.spsolve(A[free][:, free].tocsc(), rhs[free])

    angular = 2 * math.pi if n == 0 else math.pi
    p_surf = np.asarray(fb.interpolate(P))
    jac = fb.dx  # quadrature weights times facet Jacobian, (facets, points)
    r_q = x[0]
    power = angular * 0.5 * float(np.real(np.sum(p_surf * np.conj(vn) * r_q * jac)))
    mean_sq = angular * 0.5 * float(np.sum(np.abs(vn) ** 2 * r_q * jac))
    normal = -np.asarray(fb.normals)  # out of the body, into the air
    body_traces = (
        x.reshape(2, -1),
        normal.reshape(2, -1),
        p_surf.ravel(),
        (-1j * omega * air.density_kg_m3 * vn).ravel(),
        np.asarray(jac).ravel(),
    )
    flux = _flux(_circle_traces(skm, P, radius, tol), omega, air, angular)
    far = _far_field_power(body_traces, n, k, air, angular)
    return SoundField(
        mesh,
        basis.doflocs.T.copy(),
        P,
        float(frequency_hz),
        n,
        far,
        far / (air.impedance * mean_sq),
        power,
        flux,
        air,
    )


def _circle_traces(skm, P, radius: float, tol: float):
    """(x, normal, P, dP/dn, weights) at quadrature points of the circle rho = R (the
    normal radial), taken from the elements inside it; weights are ds (the r of the
    measure not included)."""
    import skfem as fe

    f = skm.facets
    p = skm.p[:, f]
    on = (np.abs(np.hypot(p[0, 0], p[1, 0]) - radius) < tol) & (
        np.abs(np.hypot(p[0, 1], p[1, 1]) - radius) < tol
    )
    facets = np.nonzero(on)[0]
    centroid = skm.p[:, skm.t].mean(axis=1)
    inside_first = np.hypot(*centroid[:, skm.f2t[0, facets]]) < radius
    parts = []
    for side, sel in ((0, inside_first), (1, ~inside_first)):
        if not np.any(sel):
            continue
        fb = fe.FacetBasis(skm, fe.ElementTriP2(), facets=facets[sel], side=side, intorder=8)
        field = fb.interpolate(P)
        x = np.asarray(fb.global_coordinates())
        normal = x / np.hypot(x[0], x[1])
        dp = normal[0] * field.grad[0] + normal[1] * field.grad[1]
        parts.append(
            (
                x.reshape(2, -1),
                normal.reshape(2, -1),
                np.asarray(field).ravel(),
                dp.ravel(),
                np.asarray(fb.dx).ravel(),
            )
        )
    return tuple(np.concatenate([q[i] for q in parts], axis=-1) for i in range(5))


def _flux(traces, omega: float, air: Air, angular: float) -> float:
    """The time-averaged power through the circle: (pi or 2 pi) / 2 Re integral P conj(v_rho) r ds."""
    x, _, p, dp, ds = traces
    v_rho = -dp / (1j * omega * air.density_kg_m3)
    return angular * 0.5 * float(np.real(np.sum(p * np.conj(v_rho) * x[0] * ds)))


def far_field(traces, n: int, k: float, cos_theta: np.ndarray) -> np.ndarray:
    """D(theta) [Pa m]: p ~ D(theta) cos(n phi) e^{-j k R} / R far away, from the
    Kirchhoff-Helmholtz integral over a closed surface of revolution around the sources
    (``traces``: points, normals pointing away from the sources, P, dP/dn, ds), its
    angular part in closed form: the integral of cos(n phi) e^{j a cos phi} over phi is
    2 pi j^n J_n(a)."""
    from scipy.special import jv, jvp

    x, (nr, nz), p, dp, ds = traces
    r, z = x
    st, ct = np.sqrt(1.0 - cos_theta**2)[:, None], cos_theta[:, None]
    kappa = k * r[None, :] * st
    jn, jnp_ = jv(n, kappa), jvp(n, kappa)
    phase = np.exp(1j * k * z[None, :] * ct)
    ring_cos = 2 * np.pi * (1j**n) * jn  # integral of cos(n phi) e^{j kappa cos phi}
    ring_cos1 = 2 * np.pi * (1j ** (n - 1)) * jnp_  # ... times cos(phi)
    dG = 1j * k * p[None, :] * (st * nr[None, :] * ring_cos1 + ct * nz[None, :] * ring_cos)
    integrand = phase * (dG - dp[None, :] * ring_cos) * (r * ds)[None, :]
    return integrand.sum(axis=1) / (4 * np.pi)


def _far_field_power(traces, n: int, k: float, air: Air, angular: float, points: int = 96) -> float:
    """W = (pi or 2 pi) / (2 rho c) integral |D|^2 d(cos theta)."""
    c, w = np.polynomial.legendre.leggauss(points)
    d = far_field(traces, n, k, c)
    return angular / (2 * air.impedance) * float(np.sum(w * np.abs(d) ** 2))
