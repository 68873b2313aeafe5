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
- contact: ``V`` at the contact point (rolling_radius, 0) of the cos member
  (interpolated, no node needed there), or exactly 0.0 when (a) the wheel is
  mirror-symmetric and the mode is in-plane by parity (:func:`fem.rules.in_plane_fraction`
  above 1/2: an unstructured mesh is not symmetric and otherwise leaves a spurious V of
  up to 1e-2 of the peak at z = 0), or (b) ``|V| <= fem.modes.CONTACT_NODE_RTOL`` times
  the largest DOF magnitude. A dished wheel's in-plane modes keep their genuine axial
  coupling (1e-2 of the peak and more at a 4 mm offset).
"""

from __future__ import annotations

import numpy as np

from geometry.design import WheelDesign
from geometry.profile import half_profile

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

    def __init__(self, design: WheelDesign, model):
        basis, skm = model.basis, model.mesh
        rl, zl, _ = half_profile(design).mid_surface(CIRCLE_SAMPLES)
        self.P_contact = probe_matrix(basis, np.array([[design.rolling_radius], [0.0]]))  # U, V, W
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

    def label(self, x: np.ndarray) -> tuple[str, int, float]:
        """(family, nodal circles, axial contact displacement) of profile vector x."""
        energy = np.array([x[i] @ (Mb @ x[i]) for i, Mb in zip(self.split, self.M_blocks)])
        dom = int(np.argmax(energy))
        family = ("radial", "axial", "circumferential")[dom]
        circles = count_sign_changes((self.P_line @ x).reshape(3, -1)[dom])
        v_c = float((self.P_contact @ x)[1])
        if self.symmetric and self.in_plane_fraction(x) > 0.5:
            v_c = 0.0  # in-plane mode of a symmetric wheel: the contact is a node
        return family, circles, clean_contact(v_c, float(np.abs(x).max()))

    def radial_at_contact(self, x: np.ndarray) -> float:
        """The radial displacement U of profile vector x at the contact point."""
        return clean_contact(float((self.P_contact @ x)[0]), float(np.abs(x).max()))

    def in_plane_fraction(self, x: np.ndarray) -> float:
        """Share of the mode's (r-weighted, nodal) squared amplitude with in-plane
        parity (:func:`fem.rules.in_plane_fraction`); only for a mirror-symmetric wheel."""
        u, um = x[self.nodal], (self.P_mirror @ x).reshape(3, -1)  # rows U = u_r, V = u_z, W = u_theta
        return in_plane_fraction(u, um, self.pts_rz[:, 0])
