"""Mode shapes of the harmonic solver on a revolved mesh (for pictures and VTU).

The profile's corner nodes are rotated to ``n_theta`` angles (meshio "wedge" cells);
each member of a harmonic mode is expanded there in Cartesian (x, y, z), the contact
point at (R1, 0, 0), angle 0.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["expand_harmonic", "meridian_outline", "outline_loop", "revolved_mesh"]


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


def expand_harmonic(UVW: np.ndarray, n: int, theta: np.ndarray, member: str, torsion: bool) -> np.ndarray:
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


def meridian_outline(modeset, index: int) -> tuple[np.ndarray, np.ndarray]:
    """The profile's outline in (r, z) and the displacement (U, V) of mode ``index``
    there, for the cos member (u_r = U cos(n theta), u_z = V cos(n theta)).

    ``modeset`` from the axisymmetric-harmonic solver (its shapes live on the revolved
    mesh of :func:`revolved_mesh`, angle 0 first). Returns ((K, 2) points of the closed
    outline, counter-clockwise in (r, z); (K, 2) displacements). The outline's nodes are
    found once per mode set (``ModeSet.meridian_loop``, :func:`outline_loop`).
    """
    loop = modeset.meridian_loop
    pts = modeset.points[loop][:, [0, 2]]
    u = modeset.shapes[index][0][loop][:, [0, 2]]
    return np.ascontiguousarray(pts), np.ascontiguousarray(u)


def outline_loop(modeset) -> np.ndarray:
    """The nodes of the profile's outline on the revolved mesh of the axisymmetric
    solver's ``modeset`` (angle 0), in order, counter-clockwise in (r, z)."""
    if modeset.solver != "axisym" or "wedge" not in modeset.cells:
        raise ValueError(f"the outline needs the axisymmetric solver's modes, not {modeset.solver!r}")
    wedges = modeset.cells["wedge"]
    n_profile = int(wedges[0, 3] - wedges[0, 0])
    tris = wedges[np.all(wedges[:, :3] < n_profile, axis=1)][:, [0, 2, 1]]
    edges = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    unique, count = np.unique(edges, axis=0, return_counts=True)
    boundary = unique[count == 1]
    nxt: dict[int, list[int]] = {}
    for a, b in boundary:
        nxt.setdefault(int(a), []).append(int(b))
        nxt.setdefault(int(b), []).append(int(a))
    loop, prev = [int(boundary[0, 0])], -1
    while True:
        here = loop[-1]
        step = next(v for v in nxt[here] if v != prev)
        if step == loop[0]:
            break
        prev = here
        loop.append(step)
    if len(loop) != len(boundary):
        raise ValueError("the profile's outline is not one closed loop")
    r, z = modeset.points[loop][:, [0, 2]].T
    if np.sum(r * np.roll(z, -1) - np.roll(r, -1) * z) < 0:
        loop = loop[::-1]
    out = np.array(loop, dtype=np.intp)
    out.flags.writeable = False
    return out
