"""Off-screen pictures of mode shapes (pyvista / VTK, no display needed).

Typical use, from a script, a notebook or CI::

    from .render import render_mode, render_modes, write_modes_vtu
    img = render_mode(modeset, 3, "mode3.png")  # image array; shows inline in Jupyter
    paths = render_modes(modeset, "results/table1", gif=True)
    write_modes_vtu(modeset, "results/table1/modes.vtu")

Every picture is made by a ``pv.Plotter(off_screen=True)`` created and closed inside
the call: nothing depends on ``pyvista.OFF_SCREEN``, a theme, ``DISPLAY`` or a Jupyter
backend (VTK >= 9.4 falls back to EGL / OSMesa when there is no X server).

What is drawn
-------------
- the deformed wheel (displacement exaggerated so the peak is ``amplitude`` times the
  outer radius) coloured by the displacement magnitude, with a scalar bar;
- the undeformed wheel's outline (its feature edges) as thin dark lines;
- the nodal lines: the zero contour of the mode's dominant component (u_z for an axial
  mode, u_r for a radial one, u_theta for a circumferential one) on the deformed
  surface, plus, for n >= 1, dashed tick marks outside the tread at the angles where the
  fitted harmonic ``cos(n (theta - theta0))`` vanishes, one pair per nodal diameter;
- the contact point (the tread apex, (R1, 0, 0) undeformed) as a red sphere + label;
- a title ``mode 3: n=3, 0 circles, axial, 1143 Hz``.

Which shape of a degenerate pair
--------------------------------
A mode with n >= 1 has two members (the cos / sin pair), and any rotation of the pair is
an equally valid solver output. The pictures (and the primary array of ``modes.vtu``)
use the combination of the pair whose displacement at the contact point is largest:
``phi = (a_c a + b_c b) / sqrt(a_c^2 + b_c^2)`` with ``a_c``, ``b_c`` the axial contact
displacements of the members (for radial / circumferential modes, whose axial contact
value is round-off, the combination maximising the whole contact displacement
vector). It is mass-normalised like the members, does not depend on how the solver rotated the pair, and
is the shape the contact
actually excites: its contact displacement squared is 1 / (contact modal mass), so the
contact point sits on an antinode and the nodal diameters are placed where the squeal
model sees them. Its partner (the orthogonal combination, a node at the contact) is kept
in ``modes.vtu`` as ``<name>_b``. ``member=0`` / ``member=1`` draws a raw member.
"""

from __future__ import annotations

import math
import os
import tempfile
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from io import BytesIO
from pathlib import Path
from typing import Any

import numpy as np

from geometry.files import write_atomic

from .modes import FAMILIES, ModeSet

__all__ = [
    "ModeImage",
    "RenderStyle",
    "contact_point_index",
    "mode_array_name",
    "mode_file_stem",
    "mode_shape",
    "mode_title",
    "render_mode",
    "render_modes",
    "to_pyvista",
    "modes_vtu_bytes",
    "write_modes_vtu",
]

#: meshio cell type -> VTK cell type id. The node orderings agree except for the linear
#: wedge: meshio (like gmsh, Abaqus, ...) orients the (0, 1, 2) triangle towards the
#: (3, 4, 5) one, VTK away from it (see meshio._vtk_common).
_VTK_CELL = {
    "vertex": 1,
    "line": 3,
    "triangle": 5,
    "quad": 9,
    "tetra": 10,
    "hexahedron": 12,
    "wedge": 13,
    "pyramid": 14,
    "line3": 21,
    "triangle6": 22,
    "quad8": 23,
    "tetra10": 24,
    "hexahedron20": 25,
    "wedge15": 26,
    "pyramid13": 27,
}

_MESHIO_TO_VTK_ORDER = {"wedge": [0, 2, 1, 3, 5, 4]}

CAMERAS = ("iso", "front", "side")


# --------------------------------------------------------------------------- shapes
def contact_point_index(modeset: ModeSet) -> int:
    """Index of the mesh point nearest the contact point (``modeset.contact_point``; if
    the mode set does not say, (R1, 0, 0) with R1 the largest radius of the mesh)."""
    p = np.asarray(modeset.points, dtype=float)
    target = modeset.contact_point
    if target is None:
        target = (float(np.hypot(p[:, 0], p[:, 1]).max()), 0.0, 0.0)
    return int(np.argmin(np.sum((p - np.asarray(target)) ** 2, axis=1)))


def _pair_basis(modeset: ModeSet, i: int) -> tuple[np.ndarray, np.ndarray | None]:
    """(primary, partner) shapes (N, 3): primary maximal at the contact point."""
    S = np.asarray(modeset.shapes[i], dtype=float)
    if S.ndim == 2:
        S = S[None]
    k = contact_point_index(modeset)
    d = S[:, k, :]  # (members, 3) contact displacement of each member
    tiny = 1e-9 * (float(np.abs(S).max()) or 1.0)
    # Axial modes: align on the axial contact displacement (what the contact model
    # uses); in-plane modes, whose axial contact value is round-off: on the whole
    # contact displacement vector.
    if modeset.modes[i].family == "axial" and np.linalg.norm(d[:, 2]) > tiny:
        d = d[:, 2:3]
    if np.linalg.norm(d) <= tiny:  # the contact point is a node of the whole mode
        return S[0], (S[1] if S.shape[0] == 2 else None)
    vals, vecs = np.linalg.eigh(d @ d.T)  # w maximises |sum_j w_j d_j| with |w| = 1
    w = vecs[:, -1]
    c = w @ d
    if c[int(np.argmax(np.abs(c)))] < 0:  # the largest contact component positive
        w = -w
    primary = np.tensordot(w, S, axes=1)
    partner = None
    if S.shape[0] == 2:
        partner = np.tensordot([-w[1], w[0]], S, axes=1)
    return primary, partner


def mode_shape(modeset: ModeSet, i: int, member: int | str = "contact") -> np.ndarray:
    """Displacement (N, 3) drawn for mode ``i``.

    ``member="contact"`` (default): the combination of a degenerate pair that is
    maximal at the contact point (see the module docstring); an integer picks a raw
    member of ``modeset.shapes[i]``.
    """
    if member == "contact":
        return _pair_basis(modeset, i)[0]
    S = np.asarray(modeset.shapes[i], dtype=float)
    return S[int(member)] if S.ndim == 3 else S


def mode_title(modeset: ModeSet, i: int) -> str:
    """``mode 3: n=3, 0 circles, axial, 1143 Hz``."""
    m = modeset.modes[i]
    c = m.nodal_circles
    return (
        f"mode {i}: n={m.nodal_diameters}, {c} circle{'' if c == 1 else 's'}, "
        f"{m.family}, {m.frequency_hz:.0f} Hz"
    )


def mode_file_stem(modeset: ModeSet, i: int) -> str:
    """``mode_03_n3_c0_axial`` (file names of the PNG / GIF of mode ``i``)."""
    m = modeset.modes[i]
    return f"mode_{i:02d}_n{m.nodal_diameters}_c{m.nodal_circles}_{m.family}"


def mode_array_name(modeset: ModeSet, i: int) -> str:
    """Point-data name of mode ``i``: ``mode_03_n3_c0_axial_1143Hz``."""
    return f"{mode_file_stem(modeset, i)}_{modeset.modes[i].frequency_hz:.0f}Hz"


# ------------------------------------------------------------------ grid and .vtu
def _vtk_cells(modeset: ModeSet) -> dict[int, np.ndarray]:
    """{VTK cell type: connectivity in VTK node order} from the meshio-style cells."""
    out = {}
    for ctype, conn in modeset.cells.items():
        if ctype not in _VTK_CELL:
            raise ValueError(f"cannot render cell type {ctype!r}")
        conn = np.asarray(conn, dtype=np.int64)
        if ctype in _MESHIO_TO_VTK_ORDER:
            conn = conn[:, _MESHIO_TO_VTK_ORDER[ctype]]
        out[_VTK_CELL[ctype]] = conn
    return out


def _point_arrays(
    modeset: ModeSet, magnitudes: bool, indices: Sequence[int] | None = None
) -> dict[str, np.ndarray]:
    out: dict[str, np.ndarray] = {}
    for i in range(len(modeset.modes)) if indices is None else indices:
        name = mode_array_name(modeset, i)
        a, b = _pair_basis(modeset, i)
        out[name] = a
        if magnitudes:
            out[name + "_mag"] = np.linalg.norm(a, axis=1)
        if b is not None:
            out[name + "_b"] = b
    return out


def _field_arrays(modeset: ModeSet) -> dict[str, np.ndarray]:
    ms = modeset.modes
    return {
        "frequency_hz": np.array([m.frequency_hz for m in ms], dtype=float),
        "nodal_diameters": np.array([m.nodal_diameters for m in ms], dtype=np.int64),
        "nodal_circles": np.array([m.nodal_circles for m in ms], dtype=np.int64),
        # index into ("axial", "radial", "circumferential")
        "family_code": np.array(
            [FAMILIES.index(m.family) if m.family in FAMILIES else -1 for m in ms],
            dtype=np.int64,
        ),
        "contact_modal_mass_kg": np.array(
            # NaN: the contact is on a node (no modal mass there), as null in summary.json
            [m.modal_mass if math.isfinite(m.modal_mass) else math.nan for m in ms],
            dtype=float,
        ),
    }


def to_pyvista(modeset: ModeSet):
    """The mode set as a ``pyvista.UnstructuredGrid``.

    Point data, per mode ``i`` (name from :func:`mode_array_name`, e.g.
    ``mode_03_n3_c0_axial_1143Hz``): the displacement vector drawn by
    :func:`render_mode` (mass-normalised [m/sqrt(kg)]), its magnitude ``<name>_mag``
    and, for a degenerate pair, the partner ``<name>_b``. Field data: frequency_hz,
    nodal_diameters, nodal_circles, family_code (index into ``fem.modes.FAMILIES``),
    contact_modal_mass_kg (-1 where infinite).
    """
    import pyvista as pv

    grid = pv.UnstructuredGrid(_vtk_cells(modeset), np.asarray(modeset.points, dtype=float))
    for name, arr in _point_arrays(modeset, magnitudes=True).items():
        grid.point_data[name] = arr
    for name, arr in _field_arrays(modeset).items():
        grid.field_data[name] = arr
    return grid


def modes_vtu_bytes(modeset: ModeSet, indices: Sequence[int] | None = None) -> float:
    """The size of :func:`write_modes_vtu`'s file [bytes], near enough: the points, the
    cells and 3 doubles per point for each member of each mode written."""
    members = sum(
        min(2, np.asarray(modeset.shapes[i]).shape[0] if np.asarray(modeset.shapes[i]).ndim == 3 else 1)
        for i in (range(len(modeset.modes)) if indices is None else indices)
    )
    cells = sum(np.asarray(c).size * 8 + len(c) * 9 for c in modeset.cells.values())
    return 24.0 * len(modeset.points) * (1 + members) + cells + 1e4


def write_modes_vtu(modeset: ModeSet, path: str | os.PathLike, indices: Sequence[int] | None = None) -> Path:
    """Write the mode shapes (``indices``: those modes only, default all) to a VTK XML
    ``.vtu`` (readable by meshio and ParaView).

    Point data as in :func:`to_pyvista` without the magnitudes (ParaView computes
    them); field data with the frequencies and labels (written by VTK's XML writer:
    meshio reads field data back but does not write it). The file is written to a
    temporary name in the same folder and renamed, so a reader never sees half a file.
    """
    import pyvista as pv

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    grid = pv.UnstructuredGrid(_vtk_cells(modeset), np.asarray(modeset.points, dtype=float))
    for name, arr in _point_arrays(modeset, magnitudes=False, indices=indices).items():
        grid.point_data[name] = arr
    for name, arr in _field_arrays(modeset).items():
        grid.field_data[name] = arr
    with tempfile.TemporaryDirectory() as scratch:  # VTK writes to a path
        tmp = Path(scratch) / path.name
        grid.save(tmp, binary=True)
        return write_atomic(path, tmp.read_bytes())


# ---------------------------------------------------------------------- images
class ModeImage(np.ndarray):
    """An RGB image array (H, W, 3) uint8 that Jupyter displays as a picture."""

    def _repr_png_(self) -> bytes | None:
        if self.ndim != 3 or self.shape[2] not in (3, 4) or self.dtype != np.uint8:
            return None
        return _png_bytes(np.asarray(self))

    def save(self, path: str | os.PathLike) -> Path:
        """Write the image as PNG (atomically)."""
        return _write_bytes_atomic(Path(path), _png_bytes(np.asarray(self)))


def _png_bytes(img: np.ndarray) -> bytes:
    from PIL import Image

    buf = BytesIO()
    Image.fromarray(np.ascontiguousarray(img)).save(buf, format="PNG")
    return buf.getvalue()


def _write_bytes_atomic(path: Path, data: bytes) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    return write_atomic(path, data)


def _write_gif_atomic(path: Path, frames: Sequence[np.ndarray], fps: float) -> Path:
    """Animated GIF with one shared 255-colour palette (consistent colours, no dither)."""
    from PIL import Image

    rgb = [np.ascontiguousarray(f[..., :3]) for f in frames]
    # palette from the extreme frames (0 and half a period) side by side
    sample = Image.fromarray(np.concatenate([rgb[0], rgb[len(rgb) // 2]], axis=1))
    pal = sample.quantize(colors=255, method=Image.Quantize.MEDIANCUT)
    imgs = [Image.fromarray(f).quantize(palette=pal, dither=Image.Dither.NONE) for f in rgb]
    buf = BytesIO()
    imgs[0].save(
        buf,
        format="GIF",
        save_all=True,
        append_images=imgs[1:],
        duration=int(round(1000 / fps)),
        loop=0,
    )
    return _write_bytes_atomic(path, buf.getvalue())


# ---------------------------------------------------------------------- scene
def _cylindrical_component(points: np.ndarray, u: np.ndarray, family: str) -> np.ndarray:
    th = np.arctan2(points[:, 1], points[:, 0])
    if family == "radial":
        return u[:, 0] * np.cos(th) + u[:, 1] * np.sin(th)
    if family == "circumferential":
        return -u[:, 0] * np.sin(th) + u[:, 1] * np.cos(th)
    return u[:, 2]


#: the points whose radius is in the outer 15 % of the wheel's radial extent are the rim
#: (where the nodal diameters are fitted and drawn)
RIM_FRACTION = 0.85


def _nodal_angles(points: np.ndarray, comp: np.ndarray, n: int) -> np.ndarray:
    """Angles where the fitted rim harmonic a cos(n t) + b sin(n t) vanishes (2n)."""
    if n < 1:
        return np.empty(0)
    r = np.hypot(points[:, 0], points[:, 1])
    rim = r >= r.min() + RIM_FRACTION * (r.max() - r.min())
    th = np.arctan2(points[rim, 1], points[rim, 0])
    A = np.column_stack([np.cos(n * th), np.sin(n * th)])
    (a, b), *_ = np.linalg.lstsq(A, comp[rim], rcond=None)
    if math.hypot(a, b) <= 1e-12 * (np.abs(comp).max() or 1.0):
        return np.empty(0)
    theta0 = math.atan2(b, a) / n
    return theta0 + (np.arange(2 * n) + 0.5) * math.pi / n


@dataclass(frozen=True)
class RenderStyle:
    """How a mode is drawn.

    scale: factor applied to the mass-normalised displacement; by default (None) chosen
        so that the peak displacement is ``amplitude`` of the wheel's outer radius.
    member: ``"contact"`` (the pair combination maximal at the contact point) or the
        index of a raw member.
    window_size: (width, height) [pixels].
    camera: ``"iso"`` (oblique, shows axial deflection and the pattern), ``"front"``
        (along the axis), ``"side"`` (edge-on), or a pyvista camera position.
    cmap: a matplotlib colormap name for the displacement component.
    """

    scale: float | None = None
    amplitude: float = 0.08
    member: int | str = "contact"
    window_size: tuple[int, int] = (1024, 768)
    show_outline: bool = True
    show_contact: bool = True
    show_nodal_lines: bool = True
    camera: Any = "iso"
    cmap: str = "turbo"


@dataclass
class _Scene:
    plotter: Any
    base: np.ndarray  # surface points, undeformed
    disp: np.ndarray  # surface displacement (unscaled)
    scale: float
    moving: list  # [(polydata, base points, displacement)] warped every frame
    labels: list  # [(base point, displacement, text)] re-placed every frame
    fs: float  # font scale

    def set_phase(self, factor: float) -> None:
        """Deform everything to ``factor`` times the full (scaled) mode shape."""
        for mesh, p0, u in self.moving:
            mesh.points = p0 + (factor * self.scale) * u
        for j, (p0, u, text) in enumerate(self.labels):
            _add_label(self.plotter, p0 + (factor * self.scale) * u, text, f"label{j}", self.fs)


def _add_label(pl, point: np.ndarray, text: str, name: str, fs: float) -> None:
    pl.add_point_labels(
        np.asarray(point, dtype=float)[None, :],
        [text],
        font_size=max(8, round(18 * fs)),
        text_color="darkred",
        shape=None,
        show_points=False,
        always_visible=True,
        bold=True,
        name=name,
        reset_camera=False,
    )


def _camera(name, radius: float, width: float):
    """(position, focal point, view up) for a named view."""
    if not isinstance(name, str):
        return name
    d = 4.0 * radius
    if name == "iso":
        az, el = math.radians(-55.0), math.radians(28.0)
        pos = (d * math.cos(el) * math.cos(az), d * math.cos(el) * math.sin(az), d * math.sin(el))
        return [pos, (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)]
    if name == "front":  # along the axis: the nodal pattern
        return [(0.0, 0.0, d), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0)]
    if name == "side":  # edge-on, contact point in front: the axial deflection
        return [(0.0, -d, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)]
    raise ValueError(f"unknown camera {name!r}: use one of {CAMERAS} or a camera position")


@dataclass
class _Parts:
    """What the parts of a scene share: the plotter, the scaled deformation, the font
    scale, and the meshes and labels that move with the mode."""

    pl: Any
    scale: float
    fs: float
    moving: list = field(default_factory=list)
    labels: list = field(default_factory=list)

    def add_moving(self, mesh: Any, base: np.ndarray, u: np.ndarray, **kw: Any) -> None:
        mesh.points = base + self.scale * u
        self.moving.append((mesh, base, u))
        self.pl.add_mesh(mesh, **kw)


def _build_scene(modeset: ModeSet, i: int, style: RenderStyle) -> _Scene:
    import pyvista as pv

    mode = modeset.modes[i]
    pts = np.asarray(modeset.points, dtype=float)
    u_all = mode_shape(modeset, i, style.member)
    r_all = np.hypot(pts[:, 0], pts[:, 1])
    radius = float(r_all.max())
    umax = float(np.linalg.norm(u_all, axis=1).max())
    scale = style.scale
    if scale is None:
        scale = style.amplitude * radius / umax if umax > 0 else 0.0

    grid = pv.UnstructuredGrid(_vtk_cells(modeset), pts)
    grid.point_data["u"] = u_all
    grid.point_data["comp"] = _cylindrical_component(pts, u_all, mode.family)
    grid.point_data["r"] = r_all
    surf = grid.extract_surface(pass_pointid=False, pass_cellid=False, algorithm="dataset_surface")
    surf.point_data["|u|"] = np.linalg.norm(surf.point_data["u"], axis=1)

    pl = pv.Plotter(off_screen=True, window_size=list(style.window_size))
    try:
        parts = _Parts(pl, scale, min(style.window_size[0] / 1024, style.window_size[1] / 768))
        pl.set_background("white")
        u = np.asarray(surf.point_data["u"])
        base = np.array(surf.points)
        _add_shape(parts, surf, base, u, umax, style.cmap)
        if style.show_outline:
            edges = surf.extract_feature_edges(
                feature_angle=30.0, boundary_edges=True, non_manifold_edges=False, manifold_edges=False
            )
            if edges.n_points:
                pl.add_mesh(edges, color="#333333", line_width=1.2, opacity=0.8)
        if style.show_nodal_lines:
            _add_nodal_lines(parts, surf, pts, grid.point_data["comp"], mode.nodal_diameters)
        if style.show_contact:
            _add_contact(parts, pts, u_all, contact_point_index(modeset), radius)
        _add_captions(parts, mode_title(modeset, i), style, umax / radius)
        pl.camera_position = _camera(style.camera, radius, float(np.ptp(pts[:, 2])))
        pl.reset_camera()
        named = isinstance(style.camera, str)
        pl.camera.zoom({"iso": 1.45, "front": 1.05, "side": 1.35}.get(style.camera, 1.0) if named else 1.0)
        return _Scene(pl, base, u, scale, parts.moving, parts.labels, parts.fs)
    except BaseException:
        pl.close()
        raise


def _add_shape(parts: _Parts, surf: Any, base: np.ndarray, u: np.ndarray, umax: float, cmap: str) -> None:
    """The deformed surface coloured by the displacement magnitude, with its colour bar."""
    fs = parts.fs
    parts.add_moving(
        surf.copy(),
        base,
        u,
        scalars="|u|",
        cmap=cmap,
        clim=(0.0, umax if umax > 0 else 1.0),
        smooth_shading=True,
        show_scalar_bar=True,
        scalar_bar_args=dict(
            title="",
            color="black",
            vertical=False,
            position_x=0.3,
            position_y=0.045,
            height=0.11,
            width=0.4,
            fmt="%.2g",
            title_font_size=max(6, round(13 * fs)),
            label_font_size=max(6, round(11 * fs)),
        ),
    )
    # the bar's own title collides with its labels when horizontal: a text above it
    parts.pl.add_text(
        "displacement magnitude [m/sqrt(kg)]",
        position=(0.3, 0.118),
        viewport=True,
        font_size=max(6, round(9 * fs)),
        color="black",
    )


def _add_nodal_lines(parts: _Parts, surf: Any, pts: np.ndarray, comp: np.ndarray, n: int) -> None:
    """White nodal lines on the web and rim face, blue ticks at the nodal diameters."""
    import pyvista as pv

    r = np.hypot(pts[:, 0], pts[:, 1])
    r_in, radius = float(r.min()), float(r.max())
    cut = surf.clip_scalar(scalars="r", value=r_in + 0.12 * (radius - r_in), invert=False)
    if cut.n_points and np.ptp(cut.point_data["comp"]) > 0:
        lines = cut.contour([0.0], scalars="comp")
        if lines.n_points:
            lu, lp = np.asarray(lines.point_data["u"]), np.array(lines.points)
            parts.add_moving(lines, lp, lu, color="white", line_width=4.0, render_lines_as_tubes=True)
    angles = _nodal_angles(pts, comp, n)
    if angles.size:
        ends = [
            [(f * radius * math.cos(t), f * radius * math.sin(t), 0.0) for f in (1.04, 1.22)] for t in angles
        ]
        ticks = pv.line_segments_from_points(np.array(ends).reshape(-1, 3))
        parts.pl.add_mesh(ticks, color="#1f3fbf", line_width=5.0)


def _add_contact(parts: _Parts, pts: np.ndarray, u_all: np.ndarray, k: int, radius: float) -> None:
    """A red ball at the contact point and an arrow pressing on it radially, as the
    roller does, with a label; all move with the mode."""
    import pyvista as pv

    p0 = pts[k]
    sphere = pv.Sphere(radius=0.03 * radius, center=p0)
    parts.add_moving(
        sphere,
        np.array(sphere.points),
        np.tile(u_all[k], (sphere.n_points, 1)),
        color="red",
        smooth_shading=True,
    )
    arrow = pv.Arrow(
        start=p0 + [0.30 * radius, 0.0, 0.0],
        direction=(-1.0, 0.0, 0.0),
        scale=0.26 * radius,
        tip_length=0.3,
        tip_radius=0.12,
        shaft_radius=0.04,
    )
    parts.add_moving(arrow, np.array(arrow.points), np.tile(u_all[k], (arrow.n_points, 1)), color="red")
    lab0 = p0 + [0.31 * radius, 0.0, 0.0]
    parts.labels.append((lab0, u_all[k], "contact"))
    _add_label(parts.pl, lab0 + parts.scale * u_all[k], "contact", f"label{len(parts.labels) - 1}", parts.fs)


def _add_captions(parts: _Parts, title: str, style: RenderStyle, peak_per_radius: float) -> None:
    fs, scale = parts.fs, parts.scale
    parts.pl.add_text(title, position="upper_edge", font_size=max(7, round(14 * fs)), color="black")
    member_txt = "contact-aligned combination" if style.member == "contact" else f"member {style.member}"
    parts.pl.add_text(
        f"deformation x{scale:.3g} (peak = {100 * scale * peak_per_radius:.0f} % of R); "
        f"{member_txt}; white: nodal lines, blue ticks: nodal diameters",
        position="lower_left",
        font_size=max(5, round(8 * fs)),
        color="#444444",
    )


def render_mode(
    modeset: ModeSet,
    i: int,
    path: str | os.PathLike | None = None,
    style: RenderStyle | None = None,
    **changes,
) -> ModeImage:
    """Render mode ``i`` off-screen; returns the RGB image, writes a PNG if ``path``.

    style: the picture (:class:`RenderStyle`); ``changes`` replace its fields, as in
    ``render_mode(ms, 3, camera="front")``.

    The returned :class:`ModeImage` is an ``(H, W, 3)`` uint8 array that a Jupyter
    notebook displays as a picture.
    """
    sc = _build_scene(modeset, i, replace(style or RenderStyle(), **changes))
    try:
        img = np.asarray(sc.plotter.screenshot(return_img=True))[..., :3].copy()
    finally:
        sc.plotter.close()
    out = img.view(ModeImage)
    if path is not None:
        out.save(path)
    return out


def render_modes(
    modeset: ModeSet,
    out_dir: str | os.PathLike,
    indices: Iterable[int] | None = None,
    gif: bool = False,
    *,
    frames: int = 20,
    fps: float = 12.0,
    gif_window_size: tuple[int, int] = (640, 480),
    style: RenderStyle | None = None,
    **changes,
) -> list[Path]:
    """One PNG per mode (``mode_03_n3_c0_axial.png``) and optionally an animated GIF
    (``.gif``, ``frames`` frames of one oscillation period, ``gif_window_size``
    pixels, ``fps`` frames per second), drawn in ``style`` with ``changes`` as in
    :func:`render_mode`. Returns the written paths (PNG, then GIF, per mode).
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    idx = range(len(modeset.modes)) if indices is None else list(indices)
    opts = replace(style or RenderStyle(), **changes)
    written: list[Path] = []
    for i in idx:
        stem = mode_file_stem(modeset, i)
        sc = _build_scene(modeset, i, opts)
        try:
            img = np.asarray(sc.plotter.screenshot(return_img=True))[..., :3].copy()
        finally:
            sc.plotter.close()
        written.append(_write_bytes_atomic(out_dir / f"{stem}.png", _png_bytes(img)))
        if gif:
            gif_style = replace(opts, window_size=gif_window_size)
            written.append(_animate(modeset, i, out_dir / f"{stem}.gif", frames, fps, gif_style))
    return written


def _animate(modeset: ModeSet, i: int, path: Path, frames: int, fps: float, style: RenderStyle) -> Path:
    sc = _build_scene(modeset, i, style)
    try:
        imgs = []
        n = max(2, int(frames))
        for k in range(n):
            sc.set_phase(math.cos(2 * math.pi * k / n))
            sc.plotter.render()
            imgs.append(np.asarray(sc.plotter.screenshot(return_img=True))[..., :3].copy())
    finally:
        sc.plotter.close()
    return _write_gif_atomic(path, imgs, fps)
