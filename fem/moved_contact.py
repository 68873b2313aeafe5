"""The modes' contact values at another point of the wheel's surface, without a new solve.

A wheel in a curve touches its rail where the curving puts it: on the tread near the taping
line, or on the flange's flank at 60-70 deg. Its modes do not change; only where and in which
frame the contact reads them. A mode set carries every mode's mass-normalised shape on the
revolved visualisation mesh, whose first slice lies in the meridian half-plane at angle 0
(y = 0, x > 0), where the modes' contact values are read (``fem.labels``). The shape there is
interpolated linearly on that slice's triangles at the new point P = (r, z), and its (u_r,
u_z) projected on the new frame's tangent and normal (``contact.frames.ContactFrame``).

At a mesh node the value is the solver's own; between nodes the linear interpolation's error
is second order in the element size (a few mm on the default meshes: under 1 % of a
contact displacement that varies over the rim's width, tests/test_curving_contacts.py).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from contact.frames import ContactFrame

from .modes import ModeSet, clean_contact

__all__ = ["MeridianSlice", "MeridianSliceError", "modes_at_contact"]

#: A node lies in the meridian half-plane when |y| is below this fraction of the mesh's size
IN_PLANE_RTOL = 1e-9


class MeridianSliceError(ValueError):
    """The mode set's mesh has no faces in the meridian half-plane (a solid mesh that is
    not revolved): its contact cannot be moved without a new solve."""


def _meridian_triangles(modes: ModeSet) -> tuple[np.ndarray, np.ndarray]:
    """The node indices of the mesh's faces in the half-plane at angle 0, and the in-plane
    flags of every node."""
    p = np.asarray(modes.points, float)
    size = float(np.ptp(p, axis=0).max())
    in_plane = (np.abs(p[:, 1]) <= IN_PLANE_RTOL * size) & (p[:, 0] > 0.0)
    faces = []
    for cells in modes.cells.values():
        cells = np.asarray(cells)
        if cells.ndim != 2 or cells.shape[1] < 3:
            continue
        flags = in_plane[cells]
        rows = np.flatnonzero(flags.sum(axis=1) == 3)
        if rows.size:
            faces.append(cells[rows][flags[rows]].reshape(-1, 3))
    if not faces:
        raise MeridianSliceError(
            f"the {modes.solver} mode set's mesh has no faces in the meridian plane: "
            "its contact cannot be moved without solving the modes again"
        )
    return np.concatenate(faces), in_plane


def _barycentric(points: np.ndarray, triangles: np.ndarray, at: np.ndarray) -> tuple[int, np.ndarray]:
    """The triangle that holds ``at`` (r, z), or the nearest one where a curved boundary
    leaves it just outside every straight-edged triangle, and its weights there."""
    a, b, c = (points[triangles[:, k]] for k in range(3))
    v0, v1, v2 = b - a, c - a, at - a
    det = v0[:, 0] * v1[:, 1] - v0[:, 1] * v1[:, 0]
    det = np.where(np.abs(det) > 0, det, np.inf)
    w1 = (v2[:, 0] * v1[:, 1] - v2[:, 1] * v1[:, 0]) / det
    w2 = (v0[:, 0] * v2[:, 1] - v0[:, 1] * v2[:, 0]) / det
    w = np.stack([1.0 - w1 - w2, w1, w2], axis=1)
    k = int(np.argmax(w.min(axis=1)))
    weights = np.clip(w[k], 0.0, None)
    return k, weights / weights.sum()


def modes_at_contact(modes: ModeSet, frame: ContactFrame) -> ModeSet:
    """``modes`` with every mode's contact values read at ``frame``'s point and in its
    frame (module docstring); the shapes and the mesh are shared, not copied. For many
    contacts of one mode set, :class:`MeridianSlice` finds the slice once.

    Raises
    ------
    MeridianSliceError
        The mesh has no meridian slice to read the shapes on.
    ValueError
        The point is farther from the mesh than its nearest element's size.

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> from contact.frames import contact_frame
    >>> d = ws.load_design("table1")
    >>> modes = ws.compute_modes(d, "fast")
    >>> moved = modes_at_contact(modes, contact_frame(d.wheel, 0.0))
    >>> abs(moved.modes[0].modal_mass / modes.modes[0].modal_mass - 1) < 1e-9
    True
    """
    if _own(modes, frame):
        return modes  # the solver's own values, as it cleaned them
    return MeridianSlice(modes).modes_at(frame)


def _own(modes: ModeSet, frame: ContactFrame) -> bool:
    own = modes.contact_point
    return own is not None and (own[0], own[2], modes.contact_angle_rad) == (
        frame.r_m,
        frame.z_m,
        frame.angle_rad,
    )


class MeridianSlice:
    """A mode set's meridian slice (its triangles and each shape's peak), found once, to
    read the modes at many contacts (:meth:`modes_at`, what :func:`modes_at_contact` does)."""

    def __init__(self, modes: ModeSet) -> None:
        self.modes = modes
        self.triangles, _ = _meridian_triangles(modes)
        self.rz = np.asarray(modes.points, float)[:, [0, 2]]
        self.shapes = [np.asarray(shape, float) for shape in modes.shapes]  # (members, nodes, 3)
        self.peaks = [np.abs(shape).reshape(len(shape), -1).max(axis=1) for shape in self.shapes]

    def modes_at(self, frame: ContactFrame) -> ModeSet:
        """The modes read at ``frame`` (:func:`modes_at_contact`)."""
        modes, rz = self.modes, self.rz
        if _own(modes, frame):
            return modes
        at = np.array([frame.r_m, frame.z_m])
        k, weights = _barycentric(rz, self.triangles, at)
        nodes = self.triangles[k]
        reach = float(np.max(np.linalg.norm(rz[nodes] - rz[nodes].mean(axis=0), axis=1)))
        gap = float(np.linalg.norm(weights @ rz[nodes] - at))
        if gap > reach:
            point = f"({frame.r_m:.4g}, {frame.z_m:.4g}) m"
            raise ValueError(f"contact point {point} is {gap * 1e3:.2g} mm off the wheel's mesh")
        moved = []
        for mode, shape, peaks in zip(modes.modes, self.shapes, self.peaks):
            lateral, normal = [], []
            for member, peak in zip(shape, peaks):
                u = weights @ member[nodes]
                t, n = frame.components(float(u[0]), float(u[2]))
                lateral.append(clean_contact(t, float(peak)))
                normal.append(clean_contact(n, float(peak)))
            moved.append(
                dataclasses.replace(mode, contact_lateral=tuple(lateral), contact_normal=tuple(normal))
            )
        return dataclasses.replace(
            modes,
            modes=moved,
            contact_point=(frame.r_m, 0.0, frame.z_m),
            contact_angle_rad=frame.angle_rad,
        )
