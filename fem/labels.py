"""Labels of a harmonic mode from its profile field: family, nodal circles, contact.

Used by the axisymmetric solver and by the cyclic 3-D solver (on its face-0 profile);
the rules themselves live in :mod:`fem.rules`.

- ``family``: the component with the largest share of the mode's kinetic energy
  (``x_c^T M_cc x_c`` for c = U, V, W): V -> "axial", U -> "radial",
  W -> "circumferential".
- ``nodal_circles``: sign changes of that component along the profile's mid-surface
  line from the bore to the contact radius (:meth:`geometry.outline.Outline.mid_surface`:
  the middle of the material at each radius, which follows a flat, conical or curved
  web, a hub and the rim), sampled at :data:`CIRCLE_SAMPLES` points
  (:func:`fem.rules.count_sign_changes`).
- contact: the displacement (U, V) = (u_r, u_z) of the cos member at the contact
  point of the frame (``contact.frames``: the tread apex (R1, 0) by default;
  interpolated, no node needed there), as its components along the lateral tangent t
  and the normal n. On a mirror-symmetric wheel with the contact in the mirror plane
  (z = 0) parity forbids one of them: an in-plane mode (:func:`fem.rules.in_plane_fraction`
  above 1/2) has no axial motion there and an out-of-plane mode no radial motion, and
  that component is exactly 0.0 (an unstructured mesh is not symmetric and otherwise
  leaves a spurious value of up to 1e-2 of the peak). A component at most
  ``fem.modes.CONTACT_NODE_RTOL`` times the largest DOF magnitude is 0.0 too. A dished
  wheel's modes keep their genuine coupling (1e-2 of the peak and more at a 4 mm offset),
  and so does a contact off the mirror plane.
"""

from __future__ import annotations

import numpy as np

from contact.frames import ContactFrame, contact_frame
from geometry.profile import half_profile
from geometry.wheel_design import WheelDesign

from .meshes import corner_mesh
from .modes import clean_contact
from .probe import probe_matrix
from .rules import count_sign_changes, in_plane_fraction, is_mirror_symmetric

__all__ = ["CIRCLE_SAMPLES", "ProfileLabeller"]

#: number of samples along the web mid-surface line for the nodal-circle count
CIRCLE_SAMPLES = 161


class ProfileLabeller:
    """Labels of a harmonic mode from its profile field: U, V, W at every DOF of
    ``model.basis`` (a :class:`fem.axisym.HarmonicModel`), real: the cos member. The
    rules are in the module docstring."""

    def __init__(self, design: WheelDesign, model, contact: ContactFrame | None = None):
        basis, skm = model.basis, model.mesh
        rl, zl, _ = half_profile(design).mid_surface(CIRCLE_SAMPLES)
        self.contact = contact or contact_frame(design)
        #: the contact is the tread apex (R1, 0), where the meshes have a node
        self.at_apex = self.contact.z_m == 0.0 and self.contact.r_m == design.rolling_radius
        self.P_contact = probe_matrix(basis, np.array([[self.contact.r_m], [self.contact.z_m]]))  # U, V, W
        self.P_line = probe_matrix(basis, np.vstack([rl, zl]))
        self.pts_rz, self.tris = corner_mesh(skm)
        self.nodal = basis.nodal_dofs[:, : skm.nvertices]  # (3, Nv) DOFs at the corners
        self.symmetric = is_mirror_symmetric(design)
        self.P_mirror = (
            probe_matrix(basis, np.vstack([self.pts_rz[:, 0], -self.pts_rz[:, 1]]))
            if self.symmetric
            else None
        )
        self.split = [np.nonzero(model.comp == c)[0] for c in range(3)]
        self.M_blocks = [model.M[idx][:, idx] for idx in self.split]

    def label(self, x: np.ndarray) -> tuple[str, int]:
        """(family, nodal circles) of profile vector x."""
        energy = np.array([x[i] @ (Mb @ x[i]) for i, Mb in zip(self.split, self.M_blocks)])
        dom = int(np.argmax(energy))
        family = ("radial", "axial", "circumferential")[dom]
        circles = count_sign_changes((self.P_line @ x).reshape(3, -1)[dom])
        return family, circles

    def parity_zero(self, x: np.ndarray) -> str | None:
        """The component parity forbids at the contact ("axial" for an in-plane mode,
        "radial" for an out-of-plane one) on a mirror-symmetric wheel whose contact lies
        in the mirror plane; None otherwise."""
        if not (self.symmetric and self.contact.z_m == 0.0):
            return None
        return "axial" if self.in_plane_fraction(x) > 0.5 else "radial"

    def contact_components(self, u_r, u_z, forbidden: str | None, peak: float) -> tuple[float, float]:
        """(u_t, u_n) of a member whose displacement at the contact is (u_r, u_z), with the
        parity rule (:meth:`parity_zero`) and the node rule applied."""
        u_r = 0.0 if forbidden == "radial" else float(u_r)
        u_z = 0.0 if forbidden == "axial" else float(u_z)
        t, n = self.contact.components(u_r, u_z)
        return clean_contact(t, peak), clean_contact(n, peak)

    def contact_of(self, x: np.ndarray, forbidden: str | None = None) -> tuple[float, float]:
        """(u_t, u_n) at the contact of the real profile vector x (the cos member);
        ``forbidden``: :meth:`parity_zero` of x when the caller has it already."""
        u = self.P_contact @ x
        forbidden = self.parity_zero(x) if forbidden is None else forbidden
        return self.contact_components(u[0], u[1], forbidden, float(np.abs(x).max()))

    def in_plane_fraction(self, x: np.ndarray) -> float:
        """Share of the mode's (r-weighted, nodal) squared amplitude with in-plane
        parity (:func:`fem.rules.in_plane_fraction`); only for a mirror-symmetric wheel."""
        u, um = x[self.nodal], (self.P_mirror @ x).reshape(3, -1)  # rows U = u_r, V = u_z, W = u_theta
        return in_plane_fraction(u, um, self.pts_rz[:, 0])
