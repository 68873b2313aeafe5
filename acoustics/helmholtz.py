"""Sound radiated by a vibrating axisymmetric body, one circumferential harmonic at a
time: the exterior Helmholtz problem on the meridian half-plane (docs/theory.md, sound radiation).

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

import dataclasses
import functools
import json
import math
import weakref
from dataclasses import dataclass
from typing import Any

import numpy as np

from geometry.files import stored_array, stored_json

from .air_mesh import AirMesh, air_mesh
from .medium import AIR, Air
from .surface import Surface

__all__ = [
    "BodyTraces",
    "MeshSizes",
    "RadiationCost",
    "RadiationSettings",
    "SoundField",
    "far_field",
    "forget_air_meshes",
    "kirchhoff_pressure",
    "mesh_sizes",
    "radiate",
    "radiation_cost",
]


@dataclass(frozen=True)
class RadiationSettings:
    """How the air is discretised.

    elements_per_wavelength : P2 triangles per acoustic wavelength away from the body.
    margin : the physical region's radius R is the body's extent times (1 + margin)
        (and beyond every requested field point).
    pml_wavelengths, pml_min_fraction : the layer's thickness d, the larger of that
        many wavelengths and that fraction of R.
    pml_ladder : where the wavelengths set d (low frequencies), d is rounded up to
        pml_min_fraction R times a power of this ratio: neighbouring tones then mesh
        the same air (a layer thicker than needed absorbs as well or better).
    size_ladder : where the wavelength sets the far element size (high frequencies), it
        is rounded down to R / 4 over a power of this ratio: neighbouring tones then mesh
        the same air (elements smaller than needed resolve as well or better), at most
        ``size_ladder**2`` the unknowns.
    pml_elements : elements across the layer at least.
    pml_attenuation : A, nepers at the layer's outer edge.
    boundary : "pml" or "abc" (see the module docstring).
    """

    elements_per_wavelength: float = 8.0
    margin: float = 0.25
    pml_wavelengths: float = 0.25
    pml_min_fraction: float = 0.5
    pml_ladder: float = 1.25
    size_ladder: float = 1.05
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
        for name in ("pml_ladder", "size_ladder"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 1.0):
                raise ValueError(f"RadiationSettings.{name} must exceed 1, got {v!r}")


@dataclass(frozen=True, eq=False)
class BodyTraces:
    """The pressure and its normal derivative on the body, at quadrature points of its
    outline (what the Kirchhoff-Helmholtz integral needs): points (2, Q) (r, z) [m],
    normals (2, Q) out of the body, pressure (Q,) [Pa], normal_derivative (Q,) [Pa/m]
    (dP/dn = -j w rho0 vn), weights (Q,) [m] (ds; the r of the measure not included)."""

    points: np.ndarray
    normals: np.ndarray
    pressure: np.ndarray
    normal_derivative: np.ndarray
    weights: np.ndarray

    def as_tuple(self) -> tuple:
        return (self.points, self.normals, self.pressure, self.normal_derivative, self.weights)


#: The names of a :class:`SoundField`'s arrays (:meth:`SoundField.to_arrays`): another
#: layout is another cache entry.
FIELD_ARRAYS = (
    "points",
    "triangles",
    "dof_points",
    "pressure",
    "body_points",
    "body_normals",
    "body_pressure",
    "body_normal_derivative",
    "body_weights",
    "scalars",
)


@dataclass(frozen=True, eq=False)
class SoundField:
    """The pressure around the body for one harmonic, and what it radiates.

    mesh : the air mesh; pressure : P at the P2 nodes of ``dof_points`` (complex, Pa,
    amplitude of cos(n theta)); body : the pressure on the body (:class:`BodyTraces`),
    from which :meth:`pressure_at` finds the pressure beyond the mesh and
    :meth:`far_field` the directivity; sound_power_w : time-averaged radiated power [W],
    from the far field (the Kirchhoff-Helmholtz integral over the body), which stays
    accurate for a poor radiator whose near field is almost all reactive;
    radiation_efficiency : W / (rho c S <vn^2>); surface_power_w : (pi or 2 pi) / 2 Re
    integral P conj(vn) r ds over the body, and flux_power_w : the same through the
    circle rho = R (energy checks: equal to W for a good radiator); frequency_hz, harmonic.
    """

    mesh: AirMesh
    dof_points: np.ndarray
    pressure: np.ndarray
    body: BodyTraces
    frequency_hz: float
    harmonic: int
    sound_power_w: float
    radiation_efficiency: float
    surface_power_w: float
    flux_power_w: float
    air: Air

    @property
    def wavenumber(self) -> float:
        """k = w / c [1/m]."""
        return self.air.wavenumber(self.frequency_hz)

    def pressure_at(self, points_rz: np.ndarray) -> np.ndarray:
        """P [Pa] (complex amplitude of cos(n theta)) at (r, z) points in the air: from
        the finite elements inside the physical region rho <= R, from the
        Kirchhoff-Helmholtz integral over the body beyond it (at any distance)."""
        points_rz = np.atleast_2d(np.asarray(points_rz, dtype=float))
        rho = np.hypot(points_rz[:, 0], points_rz[:, 1])
        out = np.empty(len(points_rz), dtype=complex)
        near = rho <= self.mesh.radius * (1 - 1e-9)
        if np.any(near):
            out[near] = _basis(self.mesh).probes(points_rz[near].T) @ self.pressure
        if np.any(~near):
            out[~near] = kirchhoff_pressure(self.body, self.harmonic, self.wavenumber, points_rz[~near])
        return out

    def far_field(self, cos_theta: np.ndarray) -> np.ndarray:
        """D(theta) [Pa m] with p ~ D(theta) cos(n phi) e^{-j k R} / R far from the body
        (theta from the +z axis)."""
        return far_field(self.body.as_tuple(), self.harmonic, self.wavenumber, np.asarray(cos_theta, float))

    def scaled(self, factor: float) -> SoundField:
        """The field of the same surface vibrating ``factor`` times as fast (factor > 0):
        the pressures scale by it, the powers by its square, the efficiency not at all."""
        b = self.body
        body = dataclasses.replace(
            b, pressure=factor * b.pressure, normal_derivative=factor * b.normal_derivative
        )
        f2 = factor * factor
        return dataclasses.replace(
            self,
            pressure=factor * self.pressure,
            body=body,
            sound_power_w=f2 * self.sound_power_w,
            surface_power_w=f2 * self.surface_power_w,
            flux_power_w=f2 * self.flux_power_w,
        )

    def vertex_pressure(self) -> np.ndarray:
        """P [Pa] at the air mesh's vertices (its first P2 unknowns), shape (N,)."""
        return self.pressure[: len(self.mesh.points)]

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The field as named arrays (:data:`FIELD_ARRAYS`); :meth:`from_arrays` reads
        them back exactly."""
        b = self.body
        scalars = {
            "frequency_hz": self.frequency_hz,
            "harmonic": float(self.harmonic),
            "sound_power_w": self.sound_power_w,
            "radiation_efficiency": self.radiation_efficiency,
            "surface_power_w": self.surface_power_w,
            "flux_power_w": self.flux_power_w,
            "radius_m": self.mesh.radius,
            "pml_thickness_m": self.mesh.pml_thickness,
            "density_kg_m3": self.air.density_kg_m3,
            "sound_speed_m_s": self.air.sound_speed_m_s,
        }
        return {
            "points": self.mesh.points,
            "triangles": self.mesh.triangles,
            "dof_points": self.dof_points,
            "pressure": self.pressure,
            "body_points": b.points,
            "body_normals": b.normals,
            "body_pressure": b.pressure,
            "body_normal_derivative": b.normal_derivative,
            "body_weights": b.weights,
            "scalars": np.array(json.dumps(scalars)),
        }

    @classmethod
    def from_arrays(cls, arrays: dict[str, np.ndarray]) -> SoundField:
        """The field of :meth:`to_arrays`, checked before use (a stored field is read back
        from a cache: ``ValueError`` or ``KeyError`` where it is not a field)."""
        s = stored_json(arrays, "scalars")
        points = stored_array(arrays, "points", "f", ndim=2, columns=2)
        triangles = stored_array(arrays, "triangles", "iu", ndim=2, columns=(3, 6), index_below=len(points))
        mesh = AirMesh(points, triangles, float(s["radius_m"]), float(s["pml_thickness_m"]))
        body_points = stored_array(arrays, "body_points", "f", ndim=2)
        quadrature = body_points.shape[1]
        traces = [
            stored_array(arrays, name, kinds, ndim=1)
            for name, kinds in (
                ("body_pressure", "fc"),
                ("body_normal_derivative", "fc"),
                ("body_weights", "f"),
            )
        ]
        normals = stored_array(arrays, "body_normals", "f", ndim=2)
        if (
            len(body_points) != 2
            or normals.shape != body_points.shape
            or any(len(t) != quadrature for t in traces)
        ):
            raise ValueError("a stored field's body traces are not over one outline")
        dof_points = stored_array(arrays, "dof_points", "f", ndim=2)
        pressure = stored_array(arrays, "pressure", "fc", ndim=1)
        if len(pressure) != len(dof_points):
            raise ValueError("a stored field's pressure is not one per degree of freedom")
        return cls(
            mesh,
            dof_points,
            pressure,
            BodyTraces(body_points, normals, *traces),
            float(s["frequency_hz"]),
            int(s["harmonic"]),
            float(s["sound_power_w"]),
            float(s["radiation_efficiency"]),
            float(s["surface_power_w"]),
            float(s["flux_power_w"]),
            Air(float(s["density_kg_m3"]), float(s["sound_speed_m_s"])),
        )


@dataclass(frozen=True)
class MeshSizes:
    """The air region of a radiation: its radius R and layer thickness d [m], and the
    element sizes far from and along the body [m]."""

    radius_m: float
    pml_thickness_m: float
    size_far_m: float
    size_near_m: float

    def dofs(self) -> float:
        """The estimated number of P2 unknowns of the air mesh: about
        :data:`DOFS_PER_AREA` per element area over the half-disc of radius R + d, with
        the refinement along the body (measured, ``benchmarks/run_all.py``)."""
        outer = self.radius_m + self.pml_thickness_m
        return DOFS_PER_AREA * (0.5 * math.pi * outer**2) / self.size_far_m**2 + DOFS_NEAR * (
            self.radius_m / self.size_near_m
        )


#: P2 unknowns per square element size of air (gmsh's frontal-Delaunay triangles: about
#: 2.3 triangles per h^2 and 2 unknowns per triangle), and per body length over the near
#: element size (the refined band along the wheel): fitted to the measured meshes of the
#: wheel's modes from 260 Hz to 20 kHz within 30 %.
DOFS_PER_AREA = 4.6
DOFS_NEAR = 60.0
#: Seconds and bytes per unknown of a radiation solve (gmsh, assembly and the sparse LU
#: of the 2-D problem), both growing beyond :data:`LU_FILL_DOFS` unknowns as the LU's
#: fill does: fitted from 5k to 180k unknowns on the Table 1 wheel's modes (260 Hz to
#: 17 kHz), with the far field in blocks and the bases kept per mesh
#: (``benchmarks/bench_estimates.py`` checks it on the shipped designs' squeal modes).
SECONDS_PER_DOF = 2.5e-5
BYTES_PER_DOF = 7000.0
LU_FILL_DOFS = 1e5


def _layer_thickness(wavelength_m: float, radius_m: float, settings: RadiationSettings) -> float:
    """The layer's thickness d [m] (:class:`RadiationSettings`: the rung of its ladder at
    or above the wavelengths' thickness, at least the fraction of R)."""
    floor = settings.pml_min_fraction * radius_m
    wanted = settings.pml_wavelengths * wavelength_m
    if wanted <= floor:
        return floor
    rung = math.ceil(math.log(wanted / floor) / math.log(settings.pml_ladder) - 1e-9)
    return floor * settings.pml_ladder**rung


def _far_size(wanted_m: float, largest_m: float, ladder: float) -> float:
    """The far element size [m]: ``largest_m``, or where the wavelength asks for less
    (``wanted_m``), the rung of ``largest_m`` / ladder^k at or below it."""
    if wanted_m >= largest_m:
        return largest_m
    rung = math.ceil(math.log(largest_m / wanted_m) / math.log(ladder) - 1e-9)
    return largest_m / ladder**rung


def mesh_sizes(
    surface: Surface, frequency_hz: float, air: Air = AIR, settings: RadiationSettings | None = None
) -> MeshSizes:
    """The air region and element sizes :func:`radiate` uses for ``surface`` at
    ``frequency_hz`` [Hz]."""
    settings = settings or RadiationSettings()
    lam = air.wavelength(frequency_hz)
    radius = surface.scale * (1 + settings.margin)
    seg = surface.segments()
    seg_len = np.linalg.norm(surface.points[seg[:, 1]] - surface.points[seg[:, 0]], axis=1)
    size_far = _far_size(lam / settings.elements_per_wavelength, radius / 4, settings.size_ladder)
    size_near = min(size_far, float(np.median(seg_len)))
    pml = settings.boundary == "pml"
    thickness = _layer_thickness(lam, radius, settings) if pml else 0.0
    size_far = min(size_far, thickness / settings.pml_elements) if pml else size_far
    return MeshSizes(radius, thickness, size_far, size_near)


@dataclass(frozen=True)
class RadiationCost:
    """The estimated size of a radiation solve: unknowns, memory [bytes], time [s]."""

    dofs: float
    memory_bytes: float
    seconds: float


def radiation_cost(
    surface: Surface, frequency_hz: float, air: Air = AIR, settings: RadiationSettings | None = None
) -> RadiationCost:
    """The estimated cost of :func:`radiate` (:data:`SECONDS_PER_DOF`,
    :data:`BYTES_PER_DOF`), without meshing."""
    dofs = mesh_sizes(surface, frequency_hz, air, settings).dofs()
    fill = max(1.0, dofs / LU_FILL_DOFS)
    return RadiationCost(dofs, BYTES_PER_DOF * dofs * fill**0.25, SECONDS_PER_DOF * dofs * fill)


def kirchhoff_pressure(body: BodyTraces, n: int, k: float, points_rz: np.ndarray) -> np.ndarray:
    """P [Pa] (amplitude of cos(n theta)) at (r, z) points outside the body, from the
    Kirchhoff-Helmholtz integral over it:

        p(x) = integral_S (p dG/dn_y - G dp/dn_y) dS,  G = e^{-j k d} / (4 pi d),

    d = |x - y|, the normal out of the body. The angular integral is taken by the
    trapezoidal rule over the full circle, exact to round-off for a smooth periodic
    integrand once its points resolve cos(n phi), the phase k d and the peak of 1/d
    (their number follows from n, k r and the point's distance from the body)."""
    (r, z), (nr, nz), p, dp, ds = body.as_tuple()
    points_rz = np.atleast_2d(np.asarray(points_rz, float))
    out = np.empty(len(points_rz), dtype=complex)
    r_max = float(np.max(r))
    for m, (rx, zx) in enumerate(points_rz):
        gap = float(np.min(np.hypot(r - rx, z - zx)))
        count = 4 * (n + k * r_max) + 16 * r_max / max(gap, 1e-6 * r_max) + 64
        phi = np.linspace(0.0, 2 * np.pi, int(min(count, 8192)), endpoint=False)[:, None]
        c = np.cos(phi)
        dx, dy, dz = rx - r[None, :] * c, -r[None, :] * np.sin(phi), zx - z[None, :]
        d = np.sqrt(dx * dx + dy * dy + dz * dz)
        G = np.exp(-1j * k * d) / (4 * np.pi * d)
        towards = nr[None, :] * (rx * c - r[None, :]) + nz[None, :] * dz  # (x - y) . n_y
        dG = (1j * k + 1.0 / d) * G * towards / d
        ring = np.cos(n * phi)
        integrand = ring * (p[None, :] * dG - dp[None, :] * G) * (r * ds)[None, :]
        out[m] = integrand.sum() * (2 * np.pi / len(phi))
    return out


def _skfem_mesh(mesh: AirMesh):
    import skfem as fe

    return fe.MeshTri(np.ascontiguousarray(mesh.points.T), np.ascontiguousarray(mesh.triangles.T))


@dataclass(frozen=True, eq=False)
class _Discretised:
    """What :func:`radiate` builds on an air mesh whatever the frequency and the surface:
    the P2 basis, the body's facet basis and its quadrature points, the circle rho = R's
    facet bases (each side), the degrees of freedom on the layer's outer edge and on the
    axis, the basis on the layer's elements (None: no layer) and the operator's parts on
    the elements inside the circle (:func:`_interior_parts`)."""

    skm: Any
    basis: Any
    body: Any
    body_points: np.ndarray
    circle: tuple[Any, ...]
    outer_dofs: np.ndarray
    axis_dofs: np.ndarray
    tolerance_m: float
    layer: Any
    interior: tuple[Any, Any, Any]

    @functools.cached_property
    def free_dofs(self) -> np.ndarray:
        """The unknowns of an axisymmetric harmonic (n = 0): all but the layer's outer edge
        (where the air has a layer; without one its edge is the Robin boundary's)."""
        if self.layer is None:
            return np.arange(self.basis.N)
        return np.setdiff1d(np.arange(self.basis.N), self.outer_dofs)

    @functools.cached_property
    def free_dofs_off_axis(self) -> np.ndarray:
        """The unknowns of a harmonic n >= 1, which vanishes on the axis too."""
        return np.setdiff1d(self.free_dofs, self.axis_dofs)


#: The discretised air meshes a process keeps (:func:`_discretised`): a radiation's
#: neighbouring tones of one mode share one below about a kilohertz
DISCRETISED_KEPT = 4


@functools.lru_cache(maxsize=DISCRETISED_KEPT)
def _discretised(mesh: AirMesh) -> _Discretised:
    import skfem as fe

    skm = _skfem_mesh(mesh)
    radius, thickness = mesh.radius, mesh.pml_thickness
    tol = 1e-6 * (radius + thickness)
    basis = fe.Basis(skm, fe.ElementTriP2(), intorder=4)
    body_facets = _facets(skm, lambda r, z: (r > tol) & (np.hypot(r, z) < radius - tol))
    body = fe.FacetBasis(skm, fe.ElementTriP2(), facets=body_facets, intorder=6)
    outer = basis.get_dofs(_facets(skm, lambda r, z: np.abs(np.hypot(r, z) - radius - thickness) < tol)).all()
    axis = basis.get_dofs(_facets(skm, lambda r, z: r <= tol)).all()
    # the mesh follows the circle rho = R: each element lies inside it or in the layer
    centroid = skm.p[:, skm.t].mean(axis=1)
    beyond = np.hypot(centroid[0], centroid[1]) > radius
    layer = (
        fe.CellBasis(skm, fe.ElementTriP2(), elements=np.flatnonzero(beyond), intorder=4)
        if np.any(beyond)
        else None
    )
    return _Discretised(
        skm,
        basis,
        body,
        np.asarray(body.global_coordinates()),
        _circle_bases(skm, radius, tol),
        outer,
        axis,
        tol,
        layer,
        _interior_parts(skm, np.flatnonzero(~beyond)),
    )


def _interior_parts(skm, elements: np.ndarray) -> tuple[Any, Any, Any]:
    """The operator inside the circle, where the layer's coefficients are those of the air
    itself (a = b = 1), in three parts made once per mesh: the integrals of r grad u .
    grad v, of r u v and of u v / r over ``elements`` (CSR), so that a tone's operator there
    is the first + n^2 the third - k^2 the second."""
    import skfem as fe

    inside = fe.CellBasis(skm, fe.ElementTriP2(), elements=elements, intorder=4)

    @fe.BilinearForm
    def stiffness(u, v, w):
        return w.x[0] * (u.grad[0] * v.grad[0] + u.grad[1] * v.grad[1])

    @fe.BilinearForm
    def mass(u, v, w):
        return w.x[0] * u * v

    @fe.BilinearForm
    def over_r(u, v, w):
        return u * v / w.x[0]

    return tuple(form.assemble(inside).tocsr() for form in (stiffness, mass, over_r))


#: Each kept air's body quadrature points located on its outline (``Surface.locate``), with
#: the outline's bytes: an air is meshed for one outline (``acoustics.air_mesh.air_mesh``), so
#: every mode of a body radiated on it shares them; an entry goes with its air
_LOCATED: weakref.WeakKeyDictionary[_Discretised, tuple[bytes, Any]] = weakref.WeakKeyDictionary()


def _body_location(air_fe: _Discretised, surface: Surface) -> tuple[np.ndarray, np.ndarray]:
    """Where the body's quadrature points of ``air_fe`` lie on ``surface``'s outline."""
    outline = np.ascontiguousarray(surface.points, dtype=float).tobytes()
    held = _LOCATED.get(air_fe)
    if held is None or held[0] != outline:
        x = air_fe.body_points
        held = _LOCATED[air_fe] = (outline, surface.locate(np.stack([x[0].ravel(), x[1].ravel()], axis=1)))
    return held[1]


def forget_air_meshes() -> None:
    """Drop the air meshes and their bases this process keeps (:data:`DISCRETISED_KEPT`,
    ``acoustics.air_mesh.MESHES_KEPT``): the next radiation meshes its air anew, as a cost
    estimate assumes."""
    from .air_mesh import forget_meshes

    _discretised.cache_clear()
    forget_meshes()


def _basis(mesh: AirMesh):
    """The P2 basis of the air mesh (:func:`_discretised`)."""
    return _discretised(mesh).basis


def _stretch(x, radius: float, thickness: float, attenuation: float, k: float):
    """(a, b, e_r, e_z) of the layer at quadrature points x (2, ...)."""
    r, z = x[0], x[1]
    rho = np.hypot(r, z)
    s = np.clip((rho - radius) / thickness, 0.0, None)
    sigma0 = 3.0 * attenuation / thickness
    a = 1.0 - 1j * sigma0 * s**2 / k
    b = 1.0 - 1j * sigma0 * thickness * s**3 / (3.0 * k * np.maximum(rho, 1e-300))
    return a, b, r / rho, z / rho


def _layer_coefficients(
    x: np.ndarray, n: int, k: float, radius: float, thickness: float, attenuation: float
) -> dict[str, np.ndarray]:
    """The operator's coefficients at the quadrature points ``x`` (2, elements, points):
    a r on the gradients, (b^2/a - a) r on their radial parts (along e_r, e_z), and
    (a n^2 / r^2 - k^2 a b^2) r on the values (:func:`_stretch`)."""
    a, b, er, ez = _stretch(x, radius, thickness, attenuation, k)
    r = x[0]
    return {
        "stiffness": a * r,
        "radial": (b * b / a - a) * r,
        "mass": (a * n * n / (r * r) - k * k * a * b * b) * r,
        "er": er,
        "ez": ez,
    }


#: The most unknowns of air factorised in SuperLU's symmetric mode (:func:`_factorised`);
#: beyond, its column ordering. On the railway wheel's air (3.4-9 kHz) the symmetric mode
#: took 0.5-0.8 of the time with 0.6 of the fill up to 121k unknowns (one run of five there
#: 1.2), 1.1-1.6x the time at 179k and 290k unknowns, where its fill catches up (0.76, 1.04).
SYMMETRIC_LU_MAX_DOFS = 150_000


def _factorised(A):
    """The sparse LU of the air's operator ``A`` (CSC). The operator is complex symmetric:
    SuperLU's symmetric mode orders A^T + A by minimum degree and prefers diagonal pivots
    (its threshold still pivots where one is small), with less fill than the column
    ordering on these 2-D meshes up to :data:`SYMMETRIC_LU_MAX_DOFS` unknowns."""
    import scipy.sparse.linalg as spla

    if A.shape[0] <= SYMMETRIC_LU_MAX_DOFS:
        return spla.splu(A, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
    return spla.splu(A, permc_spec="COLAMD")


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
) -> SoundField:
    """The sound field of ``surface`` vibrating at ``frequency_hz`` [Hz] (its air region
    is sized by the body alone: :meth:`SoundField.pressure_at` reaches any distance)."""
    import skfem as fe

    if not (math.isfinite(frequency_hz) and frequency_hz > 0):
        raise ValueError(f"frequency must be positive, got {frequency_hz!r}")
    settings = settings or RadiationSettings()
    k = air.wavenumber(frequency_hz)
    n = int(surface.harmonic)
    sizes = mesh_sizes(surface, frequency_hz, air, settings)
    radius, thickness, pml = sizes.radius_m, sizes.pml_thickness_m, settings.boundary == "pml"
    mesh = air_mesh(surface, radius, thickness, sizes.size_far_m, sizes.size_near_m)
    air_fe = _discretised(mesh)
    skm, basis, fb, tol = air_fe.skm, air_fe.basis, air_fe.body, air_fe.tolerance_m

    @fe.BilinearForm(dtype=np.complex128)
    def operator(u, v, w):
        # L = a I + (b^2/a - a) e e^T; the layer's coefficients are made once per mesh
        # (:func:`_layer_coefficients`), not once per pair of basis functions
        gu, gv = u.grad, v.grad
        along = w.er * gu[0] + w.ez * gu[1]
        return (
            w.stiffness * (gu[0] * gv[0] + gu[1] * gv[1])
            + w.radial * along * (w.er * gv[0] + w.ez * gv[1])
            + w.mass * u * v
        )

    stiffness, mass, over_r = air_fe.interior
    A = (stiffness + (n * n) * over_r - (k * k) * mass).astype(np.complex128)
    if air_fe.layer is not None:
        coefficients = _layer_coefficients(
            np.asarray(air_fe.layer.global_coordinates()),
            n,
            k,
            radius,
            max(thickness, 1e-300),
            settings.pml_attenuation,
        )
        A = A + operator.assemble(air_fe.layer, **coefficients)
    x = air_fe.body_points
    located = _body_location(air_fe, surface)
    vn = surface.normal_velocity_at(np.stack([x[0].ravel(), x[1].ravel()], axis=1), located).reshape(
        x[0].shape
    )
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
    P = np.zeros(basis.N, dtype=complex)
    free = air_fe.free_dofs_off_axis if n >= 1 else air_fe.free_dofs
    A = A.tocsr()
    P[free] = _factorised(A[free][:, free].tocsc()).solve(rhs[free])

    angular = 2 * math.pi if n == 0 else math.pi
    p_surf = np.asarray(fb.interpolate(P))
    jac = fb.dx  # quadrature weights times facet Jacobian, (facets, points)
    r_q = x[0]
    power = angular * 0.5 * float(np.real(np.sum(p_surf * np.conj(vn) * r_q * jac)))
    mean_sq = angular * 0.5 * float(np.sum(np.abs(vn) ** 2 * r_q * jac))
    normal = -np.asarray(fb.normals)  # out of the body, into the air
    body = BodyTraces(
        x.reshape(2, -1),
        normal.reshape(2, -1),
        p_surf.ravel(),
        (-1j * omega * air.density_kg_m3 * vn).ravel(),
        np.asarray(jac).ravel(),
    )
    flux = _flux(_circle_traces(air_fe.circle, P), omega, air, angular)
    far = _far_field_power(body.as_tuple(), n, k, air, angular)
    return SoundField(
        mesh,
        basis.doflocs.T.copy(),
        P,
        body,
        float(frequency_hz),
        n,
        far,
        far / (air.impedance * mean_sq),
        power,
        flux,
        air,
    )


def _circle_bases(skm, radius: float, tol: float) -> tuple[Any, ...]:
    """The facet bases of the circle rho = R, taken from the elements inside it (per side:
    the facets whose first or second element lies inside)."""
    import skfem as fe

    f = skm.facets
    p = skm.p[:, f]
    on = (np.abs(np.hypot(p[0, 0], p[1, 0]) - radius) < tol) & (
        np.abs(np.hypot(p[0, 1], p[1, 1]) - radius) < tol
    )
    facets = np.nonzero(on)[0]
    centroid = skm.p[:, skm.t].mean(axis=1)
    inside_first = np.hypot(*centroid[:, skm.f2t[0, facets]]) < radius
    return tuple(
        fe.FacetBasis(skm, fe.ElementTriP2(), facets=facets[sel], side=side, intorder=8)
        for side, sel in ((0, inside_first), (1, ~inside_first))
        if np.any(sel)
    )


def _circle_traces(circle: tuple[Any, ...], P: np.ndarray):
    """(x, normal, P, dP/dn, weights) at quadrature points of the circle rho = R (the
    normal radial), taken from the elements inside it (:func:`_circle_bases`); weights
    are ds (the r of the measure not included)."""
    parts = []
    for fb in circle:
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


#: The far field is summed over this many (direction, point) pairs at a time: its
#: temporaries stay in the processor's cache (whole arrays of a few hundred thousand pairs
#: cost more in fresh memory's page faults than in arithmetic)
FAR_FIELD_CHUNK = 32768


def far_field(traces, n: int, k: float, cos_theta: np.ndarray) -> np.ndarray:
    """D(theta) [Pa m]: p ~ D(theta) cos(n phi) e^{-j k R} / R far away, from the
    Kirchhoff-Helmholtz integral over a closed surface of revolution around the sources
    (``traces``: points, normals pointing away from the sources, P, dP/dn, ds), its
    angular part in closed form: the integral of cos(n phi) e^{j a cos phi} over phi is
    2 pi j^n J_n(a), and of cos(n phi) cos(phi) e^{j a cos phi} 2 pi j^(n-1) J_n'(a).

    Per direction and point the integrand is e^{j k z cos(theta)} (J_n (a0 + cos(theta) a1)
    + sin(theta) J_n' b) with a0, a1, b of the point alone: the real arrays (the phase's
    cosine and sine times J_n and J_n') are summed against them as matrix products, a
    block of directions at a time (:data:`FAR_FIELD_CHUNK`). The directions theta and
    pi - theta share their Bessel factors and their phase's cosine (its sine changes sign):
    each |cos(theta)| is summed once for both."""
    x, (nr, nz), p, dp, ds = traces
    r, z = x
    weight = r * ds / (4 * np.pi)
    ring, ring1 = 2 * np.pi * (1j**n), 2 * np.pi * (1j ** (n - 1))
    a0 = -dp * ring * weight
    a1 = 1j * k * p * nz * ring * weight
    b = 1j * k * p * nr * ring1 * weight
    # the real and imaginary parts of the three coefficients as six columns
    columns = np.stack([a0.real, a0.imag, a1.real, a1.imag, b.real, b.imag], axis=1)
    from .bessel import BesselTable

    # J_n' = J_{n-1} - (n / x) J_n: two orders instead of three (at x = 0, J_n' is 1/2 for
    # n = 1, else 0)
    table = BesselTable((n, n - 1), k * float(np.max(r, initial=0.0)))
    cos_theta = np.asarray(cos_theta, float)
    # a direction and its mirror pi - theta computed in floating point differ in the last
    # bit of their cosines: rounded to 1e-15 they are one |cos(theta)|
    magnitudes, which = np.unique(np.round(np.abs(cos_theta), 15), return_inverse=True)
    mirrored = cos_theta < 0.0
    out = np.zeros(len(cos_theta), complex)
    rows = max(1, FAR_FIELD_CHUNK // max(len(r), 1))
    for start in range(0, len(magnitudes), rows):
        ct = magnitudes[start : start + rows]
        st = np.sqrt(1.0 - ct**2)
        kappa = np.outer(st, k * r)
        jn, below = table(kappa)
        with np.errstate(divide="ignore", invalid="ignore"):
            jnp_ = np.where(kappa > 0.0, below - n * jn / kappa, 0.5 * (n == 1))
        angle = np.outer(ct, k * z)
        cos_phase, sin_phase = np.cos(angle), np.sin(angle)
        # (cos + j sin)(J_n (a0 + ct a1)) + st (cos + j sin) J_n' b, each real block times
        # the real and imaginary parts of its coefficients; the mirror: sin -> -sin, ct -> -ct
        cn, sn = (cos_phase * jn) @ columns[:, :4], (sin_phase * jn) @ columns[:, :4]
        cd, sd = (cos_phase * jnp_) @ columns[:, 4:], (sin_phase * jnp_) @ columns[:, 4:]
        block = (which >= start) & (which < start + len(ct))
        at = which[block] - start
        sign = np.where(mirrored[block], -1.0, 1.0)
        cn, sn, cd, sd = cn[at], sn[at] * sign[:, None], cd[at], sd[at] * sign[:, None]
        a0_sum = cn[:, 0] - sn[:, 1] + 1j * (cn[:, 1] + sn[:, 0])
        a1_sum = cn[:, 2] - sn[:, 3] + 1j * (cn[:, 3] + sn[:, 2])
        b_sum = cd[:, 0] - sd[:, 1] + 1j * (cd[:, 1] + sd[:, 0])
        out[block] = a0_sum + sign * ct[at] * a1_sum + st[at] * b_sum
    return out


@functools.lru_cache(maxsize=4)
def _gauss_legendre(points: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [-1, 1] (made once: an eigenvalue problem)."""
    nodes, weights = np.polynomial.legendre.leggauss(points)
    nodes.setflags(write=False)
    weights.setflags(write=False)
    return nodes, weights


def _far_field_power(traces, n: int, k: float, air: Air, angular: float, points: int = 96) -> float:
    """W = (pi or 2 pi) / (2 rho c) integral |D|^2 d(cos theta)."""
    c, w = _gauss_legendre(points)
    d = far_field(traces, n, k, c)
    return angular / (2 * air.impedance) * float(np.sum(w * np.abs(d) ** 2))
