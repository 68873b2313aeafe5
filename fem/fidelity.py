"""Fidelity checks of a harmonic (profile) mesh: warnings when the discretisation cannot
give the ~1 % the presets promise (``fem.modes.FidelityWarning`` subclasses).

- ``LockingWarning``: P1 with nu > ``LOCKING_NU`` (volumetric locking) or with fewer
  than ``P1_ELEMENTS_THROUGH_WEB`` elements through the web (bending);
- ``ResolutionWarning``: P2 with an element size above the web thickness, or a band
  whose shortest wavelength (:func:`shortest_wavelength`) spans fewer than
  ``RESOLUTION_ELEMENTS[order]`` elements.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import skfem as fe

from geometry.wheel_design import WheelDesign

from .meshes import to_skfem_mesh
from .modes import LockingWarning, ResolutionWarning

__all__ = [
    "LOCKING_NU",
    "P1_ELEMENTS_THROUGH_WEB",
    "RESOLUTION_ELEMENTS",
    "fidelity_warnings",
    "mesh_element_size",
    "shortest_wavelength",
]

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


def shortest_wavelength(design: WheelDesign, f_hz: float) -> float:
    """The shortest wavelength [m] the (r, z) mesh must resolve at ``f_hz``: the smaller
    of the Kirchhoff bending wavelength of the web plate,
    ``2 pi (D / (rho t))^(1/4) / sqrt(omega)`` with ``D = E t^3 / 12 (1 - nu^2)``, and
    the shear wavelength ``c_s / f``."""
    t, E, nu, rho = design.wall_thickness, design.youngs_modulus, design.poissons_ratio, design.density
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


def fidelity_warnings(design: WheelDesign, h: float, order: int, f_top: float | None, before: bool) -> None:
    """Warn (FidelityWarning subclasses) when the discretisation cannot give ~1 %.
    ``before``: the checks that do not need the solution (mesh, order, material);
    otherwise only the wavelength check at ``f_top``."""
    t = design.wall_thickness
    per_web = t / h
    if before:
        if order == 1 and design.poissons_ratio > LOCKING_NU:
            warnings.warn(
                f"nu = {design.poissons_ratio:g} > {LOCKING_NU:g} with linear (P1) elements: "
                "volumetric locking makes the frequencies too high (Table 1: +7 % at "
                "nu = 0.49, +47 % at 0.499); use order=2",
                LockingWarning,
                stacklevel=4,
            )
        if order == 1 and per_web < P1_ELEMENTS_THROUGH_WEB * (1 - 1e-9):
            warnings.warn(
                f"linear (P1) elements with {per_web:.3g} elements through the "
                f"{t * 1e3:.3g} mm web lock in bending: frequencies too high by more than "
                f"1 % (Table 1: +3 % with 4, +0.8 % with {P1_ELEMENTS_THROUGH_WEB}); use order=2",
                LockingWarning,
                stacklevel=4,
            )
        elif order == 2 and h > t * (1 + 1e-9):
            warnings.warn(
                f"mesh size {h * 1e3:.3g} mm exceeds the web thickness {t * 1e3:.3g} mm "
                "(fewer than one element through the web): frequency errors of several % "
                "(Table 1: 1.4 % at twice the thickness, 6 % at 8 times); use "
                "elements_through_web >= 1",
                ResolutionWarning,
                stacklevel=4,
            )
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
                ResolutionWarning,
                stacklevel=4,
            )
