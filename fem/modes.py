"""Modes and their contact-point modal parameters.

A :class:`Mode` is what every solver returns: frequency, labels, and the axial
displacement at the contact point of each mass-normalised member of the mode (one
member for n = 0, the cos/sin pair for n >= 1). The contact-point modal mass combines
the pair, ``m = 1 / (phi_a^2 + phi_b^2)``, so it does not depend on how the solver
rotated a degenerate pair.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from geometry.files import stored_array, stored_json

FAMILIES = ("axial", "radial", "circumferential")
#: Default upper end of the band every solver computes [Hz]: the squeal tones of these
#: rigs lie near 1-3 kHz; 5 kHz keeps every mode a squeal could pick.
DEFAULT_FMAX_HZ = 5000.0


# ------------------------------------------------------------------------------------
# warnings of the FE solvers (the pipeline prints each on one line)
# ------------------------------------------------------------------------------------
class FidelityWarning(UserWarning):
    """The modes were computed, but the discretisation is known to be too coarse for
    the accuracy the presets promise (about 1 % on frequencies): the message names the
    cause and the remedy. Subclasses say which kind."""


class LockingWarning(FidelityWarning):
    """Linear (P1) elements lock: shear locking in bending of the thin web, and
    volumetric locking for a nearly incompressible material (nu > 0.45). Frequencies
    come out too high; use quadratic (P2) elements."""


class ResolutionWarning(FidelityWarning):
    """The mesh cannot resolve the requested band or the geometry: fewer than one
    element through the web, or the shortest wavelength at ``fmax_hz`` spans too few
    elements."""


class EmptyBandWarning(UserWarning):
    """No natural frequency lies in the requested band: the solver returns an empty
    ModeSet; the message gives the lowest natural frequency found."""


#: A member's axial contact displacement below this fraction of the member's peak
#: displacement (largest nodal DOF magnitude of the mass-normalised shape) is a node:
#: reported as 0.0, so the modal mass is ``inf``. Far below any physical coupling
#: (dished wheels: 1e-2 and more), above the round-off of a symmetric mesh (1e-12).
CONTACT_NODE_RTOL = 1e-6


def clean_contact(value: float, peak: float, rtol: float = CONTACT_NODE_RTOL) -> float:
    """``value`` (a contact displacement), or 0.0 if ``|value| <= rtol * peak``."""
    value = float(value)
    return 0.0 if abs(value) <= rtol * abs(float(peak)) else value


@dataclass(frozen=True)
class Mode:
    """One natural mode (a degenerate pair is one Mode with two members).

    Attributes
    ----------
    index: position in the ascending list of modes (0-based).
    frequency_hz: natural frequency [Hz].
    nodal_diameters: n, the circumferential harmonic.
    nodal_circles: number of nodal circles of the dominant displacement component.
    family: "axial" (out-of-plane), "radial" or "circumferential" (in-plane).
    contact_lateral: displacement at the contact point along the lateral tangent t of
        each mass-normalised member [m / sqrt(kg)] (axial for a contact at the tread
        apex, ``contact.frames``); its squares sum to 1 / modal mass.
    contact_normal: displacement there along the contact normal n (radial at the
        apex), member by member [m / sqrt(kg)] (empty: not computed).
    name: a label of its own (a measured mode's), instead of "(n,c) family".
    damping_ratio: its own modal damping ratio (a modal test's), None: the design's.
    """

    index: int
    frequency_hz: float
    nodal_diameters: int
    nodal_circles: int
    family: str
    contact_lateral: tuple[float, ...]
    contact_normal: tuple[float, ...] = ()
    name: str = ""
    damping_ratio: float | None = None

    @property
    def omega(self) -> float:
        """Circular frequency [rad/s]."""
        return 2.0 * math.pi * self.frequency_hz

    @property
    def multiplicity(self) -> int:
        return len(self.contact_lateral)

    @property
    def modal_mass(self) -> float:
        """Contact-point modal mass in the lateral direction [kg] (inf at a node)."""
        return contact_modal_mass(self.contact_lateral)

    @property
    def normal_modal_mass(self) -> float:
        """Contact-point modal mass in the normal direction [kg] (inf at a node)."""
        return contact_modal_mass(self.contact_normal)

    @property
    def modal_stiffness(self) -> float:
        """k = omega^2 m [N/m]."""
        return self.omega**2 * self.modal_mass

    def modal_damping(self, damping_ratio: float) -> float:
        """c = 2 zeta sqrt(k m) [N s/m] for a modal damping ratio zeta [-]."""
        return modal_damping(self.modal_mass, self.modal_stiffness, damping_ratio)

    def label(self) -> str:
        return self.name or f"({self.nodal_diameters},{self.nodal_circles}) {self.family}"

    @functools.cached_property
    def contact_components(self) -> tuple[float, float]:
        """(phi_t, phi_n) [1/sqrt(kg)]: the lateral and normal displacement at the contact
        of the member combination with the largest lateral motion there (phi_t >= 0;
        both do not depend on how the solver rotated a pair); with no lateral motion,
        (0, the normal one's size). (0, 0): a node."""
        a = np.asarray(self.contact_lateral, float)
        r = np.asarray(self.contact_normal or (0.0,) * len(a), float)
        t = float(np.linalg.norm(a))
        if t == 0.0:
            return 0.0, float(np.linalg.norm(r))
        return t, float(a @ r) / t

    def to_dict(self, damping_ratio: float) -> dict:
        """JSON-ready summary (the keys of ``summary.json``'s ``modes``)."""
        m = self.modal_mass
        finite = math.isfinite(m)
        return {
            "index": self.index,
            "frequency_hz": self.frequency_hz,
            "nodal_diameters": self.nodal_diameters,
            "nodal_circles": self.nodal_circles,
            "family": self.family,
            "modal_mass_kg": m if finite else None,
            "modal_stiffness_n_m": self.modal_stiffness if finite else None,
            "modal_damping_ns_m": self.modal_damping(damping_ratio) if finite else None,
        }


def contact_modal_mass(contact_lateral: Iterable[float]) -> float:
    """m = 1 / sum(phi_i^2) over the members of a (possibly degenerate) mode [kg].

    ``phi_i`` are the axial contact displacements of mass-normalised shapes
    [m / sqrt(kg)]. Returns ``inf`` when the contact point is a node of the mode.
    """
    s = float(np.sum(np.square(np.asarray(tuple(contact_lateral), dtype=float))))
    return math.inf if s <= 0.0 else 1.0 / s


def modal_damping(mass: float, stiffness: float, damping_ratio: float) -> float:
    """Viscous modal damping c = 2 zeta sqrt(k m) [N s/m]."""
    return 2.0 * damping_ratio * math.sqrt(stiffness * mass)


@dataclass(frozen=True)
class ModeSelection:
    """How to pick the squeal mode. Exactly one criterion is used:

    - ``index``: position in the mode list;
    - ``nodal_diameters`` (and optionally ``nodal_circles``, ``family``): a label;
    - ``near_hz``: the axial mode nearest to a frequency.

    The default is the axial mode with 3 nodal diameters and no nodal circle.
    """

    index: int | None = None
    nodal_diameters: int | None = 3
    nodal_circles: int | None = 0
    family: str | None = "axial"
    near_hz: float | None = None

    @classmethod
    def parse(cls, text: str) -> ModeSelection:
        """Parse ``default`` (the (3, 0) axial mode), an index ``5``, a label ``n=3`` /
        ``n=3,c=1`` or ``f=1100``. (``auto``, the fastest-growing mode, needs the
        contact and an operating point: the application chooses it.)"""
        t = text.strip().lower().replace(" ", "")
        if t in ("", "default"):
            return cls()
        if t == "auto":
            raise ValueError(
                "mode 'auto' (the fastest-growing) needs an operating point; here give "
                "n=3[,c=0], an index or f=HZ"
            )
        if t.isdigit():
            return cls(index=int(t), nodal_diameters=None, nodal_circles=None, family=None)
        parts = dict(p.split("=", 1) for p in t.split(",") if "=" in p)
        if not parts or len(parts) != len(t.split(",")):
            raise ValueError(f"unknown mode {text!r}: use an index (e.g. 4), n=3[,c=0] or f=1100")
        try:
            if "f" in parts:
                near = float(parts["f"])
                if not (math.isfinite(near) and near > 0):
                    raise ValueError(f"mode {text!r}: f=HZ needs a positive frequency in Hz")
                return cls(nodal_diameters=None, nodal_circles=None, near_hz=near)
            n = int(parts["n"])
            c = int(parts["c"]) if "c" in parts else 0
        except KeyError:
            raise ValueError(f"unknown mode {text!r}: use an index (e.g. 4), n=3[,c=0] or f=1100") from None
        except ValueError as exc:
            if "f=HZ" in str(exc):
                raise
            raise ValueError(f"unknown mode {text!r}: use an index (e.g. 4), n=3[,c=0] or f=1100") from None
        return cls(nodal_diameters=n, nodal_circles=c)


class SelectedMode(NamedTuple):
    """A mode and the sentence that says why it was selected."""

    mode: Mode
    reason: str


def select_mode(modes: Sequence[Mode], selection: ModeSelection | None = None) -> SelectedMode:
    """Pick the squeal mode; returns the mode and a sentence saying why it was picked.

    Raises ``LookupError`` with a one-line message when nothing matches.
    """
    sel = selection or ModeSelection()
    if not modes:
        raise LookupError(
            "no modes to select from: the mode set is empty (no natural frequency in the "
            "requested band); raise the band's upper frequency (fmax)"
        )
    if sel.index is not None:
        if not 0 <= sel.index < len(modes):
            raise LookupError(f"mode index {sel.index} out of range 0..{len(modes) - 1}")
        m = modes[sel.index]
        return SelectedMode(m, f"mode {sel.index} requested by index")
    if sel.near_hz is not None:
        axial = [m for m in modes if m.family == "axial"] or list(modes)
        near = sel.near_hz
        m = min(axial, key=lambda m: abs(m.frequency_hz - near))
        if abs(m.frequency_hz - near) > NEAREST_MODE_RTOL * near:
            raise LookupError(
                f"no mode near {near:g} Hz: the nearest is {m.label()} at {m.frequency_hz:.1f} Hz "
                f"(f=HZ picks a mode within {NEAREST_MODE_RTOL:.0%})"
            )
        return SelectedMode(m, f"axial mode nearest to {near:g} Hz")
    cands = [
        m
        for m in modes
        if m.nodal_diameters == sel.nodal_diameters
        and (sel.nodal_circles is None or m.nodal_circles == sel.nodal_circles)
        and (sel.family is None or m.family == sel.family)
    ]
    if not cands:
        what = f"n={sel.nodal_diameters}" + (
            f", {sel.nodal_circles} nodal circles" if sel.nodal_circles is not None else ""
        )
        top = max(m.frequency_hz for m in modes)
        raise LookupError(
            f"no {sel.family or ''} mode with {what} among the {len(modes)} computed modes "
            f"(up to {top:.0f} Hz): raise the band (fmax) or pick another mode".replace("  ", " ")
        )
    m = cands[0]
    why = (
        f"lowest {m.family} mode with {m.nodal_diameters} nodal diameters and {m.nodal_circles} nodal circles"
    )
    return SelectedMode(m, why)


#: ``f=HZ`` picks the axial mode nearest HZ if it lies within this fraction of it.
NEAREST_MODE_RTOL = 0.25


@dataclass
class ModeSet:
    """The result of a modal analysis: modes plus their shapes on a mesh.

    ``shapes[i]`` holds the mass-normalised shapes of ``modes[i]`` with shape
    ``(members, n_points, 3)``: Cartesian displacement (x, y, z) at ``points`` of the
    visualisation mesh (for the axisymmetric solver: the shapes expanded onto a
    revolved mesh). ``cells`` are that mesh's cells as ``{meshio cell type: array}``.
    ``contact_point``: (r, 0, z), the contact point [m] ((R1, 0, 0) at the tread apex;
    None: the mesh's largest radius at z = 0, right for a wheel whose tread apex is its
    largest radius); ``contact_angle_rad``: the contact angle of the frame the modes'
    contact components are given in (``contact.frames``).
    """

    modes: list[Mode]
    points: np.ndarray
    cells: dict[str, np.ndarray]
    shapes: list[np.ndarray]
    solver: str
    dofs: int
    timings_s: dict[str, float] = field(default_factory=dict)
    contact_point: tuple[float, float, float] | None = None
    contact_angle_rad: float = 0.0

    @functools.cached_property
    def meridian_loop(self) -> np.ndarray:
        """The nodes of the profile's outline, in order (``fem.shapes.outline_loop``; the
        axisymmetric solver's mode sets only), found once."""
        from .shapes import outline_loop

        return outline_loop(self)

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The mode set as plain arrays (the metadata as one JSON string), for ``.npz``
        files: :meth:`from_arrays` gives it back exactly."""
        meta = {
            "modes": [dataclasses.asdict(m) for m in self.modes],
            "solver": self.solver,
            "dofs": int(self.dofs),
            "timings_s": self.timings_s,
            "cell_types": list(self.cells),
            "contact_point": self.contact_point,
            "contact_angle_rad": self.contact_angle_rad,
        }
        arrays = {"meta": np.array(json.dumps(meta)), "points": np.asarray(self.points, float)}
        for name, conn in self.cells.items():
            arrays[f"cells_{name}"] = np.asarray(conn)
        for i, s in enumerate(self.shapes):
            arrays[f"shape_{i}"] = np.asarray(s, dtype=float)
        return arrays

    @classmethod
    def from_arrays(cls, arrays: dict[str, np.ndarray]) -> ModeSet:
        """The mode set :meth:`to_arrays` wrote, checked before use (a stored mode set is
        read back from a cache: ``ValueError``, ``KeyError`` or ``TypeError`` where it is
        not one)."""
        meta = stored_json(arrays, "meta")
        points = stored_array(arrays, "points", "f", ndim=2, columns=3)
        modes = [
            Mode(
                **{
                    **m,
                    "contact_lateral": tuple(float(v) for v in m["contact_lateral"]),
                    "contact_normal": tuple(float(v) for v in m["contact_normal"]),
                }
            )
            for m in meta["modes"]
        ]
        for m in modes:
            if not (isinstance(m.index, int) and isinstance(m.nodal_diameters, int) and m.frequency_hz >= 0):
                raise ValueError(f"stored mode {m.index!r} is not a mode")
            if not (m.family in FAMILIES and isinstance(m.name, str) and isinstance(m.nodal_circles, int)):
                raise ValueError(f"stored mode {m.index} is not a mode")
        shapes = [stored_array(arrays, f"shape_{i}", "f", ndim=3) for i in range(len(modes))]
        if any(
            s.shape[1:] != (len(points), 3) or len(s) != m.multiplicity
            for s, m in zip(shapes, modes, strict=True)
        ):
            raise ValueError("a stored mode shape does not match its mesh")
        return cls(
            modes=modes,
            points=points,
            cells={
                str(t): stored_array(arrays, f"cells_{t}", "iu", ndim=2, index_below=len(points))
                for t in meta["cell_types"]
            },
            shapes=shapes,
            solver=str(meta["solver"]),
            dofs=int(meta["dofs"]),
            timings_s={str(k): float(v) for k, v in meta["timings_s"].items()},
            contact_point=_stored_point(meta.get("contact_point")),
            contact_angle_rad=float(meta.get("contact_angle_rad", 0.0)),
        )


def _stored_point(point: object) -> tuple[float, float, float] | None:
    """A stored contact point (r, 0, z) [m], or None."""
    if point is None:
        return None
    if not isinstance(point, list) or len(point) != 3:
        raise ValueError("a stored contact point is not a point")
    r, y, z = (float(v) for v in point)
    return (r, y, z)


__all__ = [
    "CONTACT_NODE_RTOL",
    "DEFAULT_FMAX_HZ",
    "EmptyBandWarning",
    "FAMILIES",
    "FidelityWarning",
    "LockingWarning",
    "ResolutionWarning",
    "clean_contact",
    "Mode",
    "ModeSelection",
    "ModeSet",
    "contact_modal_mass",
    "modal_damping",
    "SelectedMode",
    "select_mode",
]
