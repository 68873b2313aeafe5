"""The radiating body seen by the air: its outline in the meridian half-plane and the
velocity of that outline for one circumferential harmonic."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Surface"]

#: A point is on the axis when r is below this fraction of the body's size.
AXIS_TOL = 1e-9


@dataclass(frozen=True, eq=False)
class Surface:
    """The body's outline in the (r, z) half-plane and its motion.

    points : (K, 2) [m], (r, z) of the outline's vertices, in order: a closed loop (the
        last vertex joins the first; a body off the axis, like a wheel with its bore), or
        a chain from the axis back to the axis (a body on the axis, like a sphere: the
        axis closes it). Either orientation.
    velocity : (K, 2) complex [m/s], the (r, z) velocity amplitude at the vertices for
        the harmonic ``cos(n theta)`` (time convention e^{j w t}); linear in between.
    harmonic : n, the number of nodal diameters (0: axisymmetric motion).
    """

    points: np.ndarray
    velocity: np.ndarray
    harmonic: int

    def __post_init__(self) -> None:
        pts = np.asarray(self.points, dtype=float)
        vel = np.asarray(self.velocity, dtype=complex)
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 3:
            raise ValueError("Surface.points must be (K >= 3, 2) (r, z) coordinates")
        if vel.shape != pts.shape:
            raise ValueError(f"Surface.velocity must be {pts.shape}, got {vel.shape}")
        if not (np.all(np.isfinite(pts)) and np.all(np.isfinite(vel))):
            raise ValueError("Surface points and velocities must be finite")
        if np.any(pts[:, 0] < -self.scale * AXIS_TOL):
            raise ValueError("Surface points must have r >= 0 (the meridian half-plane)")
        n = self.harmonic
        if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 0:
            raise ValueError(f"Surface.harmonic must be a whole number >= 0, got {n!r}")
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "velocity", vel)
        if self.signed_area() == 0.0:
            raise ValueError("Surface outline encloses no area")

    @property
    def scale(self) -> float:
        """The body's largest distance from the origin [m]."""
        return float(np.max(np.hypot(*np.asarray(self.points, dtype=float).T)))

    @property
    def on_axis(self) -> bool:
        """Whether the outline is a chain from the axis to the axis."""
        tol = AXIS_TOL * self.scale
        return bool(self.points[0, 0] <= tol and self.points[-1, 0] <= tol)

    def segments(self) -> np.ndarray:
        """(S, 2) vertex indices of the radiating segments (the axis closure excluded)."""
        k = len(self.points)
        a = np.arange(k if not self.on_axis else k - 1)
        return np.stack([a, (a + 1) % k], axis=1)

    def signed_area(self) -> float:
        """Shoelace area of the closed outline in (r, z) [m^2] (> 0: counter-clockwise)."""
        r, z = self.points.T
        return 0.5 * float(np.sum(r * np.roll(z, -1) - np.roll(r, -1) * z))

    def normals(self) -> np.ndarray:
        """(S, 2) unit normals of the segments, pointing out of the body."""
        seg = self.segments()
        d = self.points[seg[:, 1]] - self.points[seg[:, 0]]
        n = np.stack([d[:, 1], -d[:, 0]], axis=1)  # right of the direction of travel
        if self.signed_area() < 0:
            n = -n
        return n / np.linalg.norm(n, axis=1, keepdims=True)

    def locate(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Where points ``x`` (N, 2) on the outline lie: each one's nearest segment (an
        index of :meth:`segments`) and its place along it (0 to 1). It depends on the
        outline alone: the surfaces of one outline (a body's modes) share it."""
        x = np.asarray(x, dtype=float).reshape(-1, 2)
        seg = self.segments()
        a, b = self.points[seg[:, 0]], self.points[seg[:, 1]]
        d = b - a
        t = np.einsum("nsk,sk->ns", x[:, None, :] - a[None], d) / np.einsum("sk,sk->s", d, d)
        t = np.clip(t, 0.0, 1.0)
        foot = a[None] + t[..., None] * d[None]
        nearest = np.argmin(np.linalg.norm(x[:, None, :] - foot, axis=2), axis=1)
        return nearest, t[np.arange(len(x)), nearest]

    def normal_velocity_at(
        self, x: np.ndarray, located: tuple[np.ndarray, np.ndarray] | None = None
    ) -> np.ndarray:
        """The outward normal velocity [m/s] at points ``x`` (N, 2) on the outline (each
        taken on its nearest segment, the velocity linear along it); ``located``: the
        points' :meth:`locate`, where known."""
        nearest, t = self.locate(x) if located is None else located
        seg = self.segments()
        tt = t[:, None]
        va, vb = self.velocity[seg[nearest, 0]], self.velocity[seg[nearest, 1]]
        v = (1 - tt) * va + tt * vb
        return np.einsum("nk,nk->n", v, self.normals()[nearest])

    def area(self) -> float:
        """The body's surface area in 3-D, 2 pi times the integral of r ds [m^2]."""
        seg = self.segments()
        a, b = self.points[seg[:, 0]], self.points[seg[:, 1]]
        return float(2 * math.pi * np.sum(0.5 * (a[:, 0] + b[:, 0]) * np.linalg.norm(b - a, axis=1)))
