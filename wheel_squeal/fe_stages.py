"""The FE stages: the design's mesh and modes (cached, estimated against the budget),
a mode by its description, and the views of the modes (VTU, PNG)."""

from __future__ import annotations

import math
import tempfile
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from geometry import WheelDesign

from .design import Design, as_design
from .presets import DEFAULT_FIDELITY, DEFAULT_FMAX_HZ, FIDELITIES, Fidelity, fidelity_for
from .runtime.budget import MAX_FILE_BYTES, Budget
from .runtime.entry_reading import kept_files
from .runtime.interrupts import uninterrupted
from .runtime.progress import Progress
from .runtime.provenance import code_version, library_versions
from .runtime.request_errors import RequestError
from .runtime.stage_cache import CacheMiss, StageCache
from .types import FidelityName, SolverName

if TYPE_CHECKING:
    from fem.cost import SolveCost
    from fem.modes import ModeSet, SelectedMode

    from .context import RunContext

__all__ = [
    "DENSE_OUTLINE_SEGMENTS",
    "build_mesh",
    "check_modes_budget",
    "check_named_modes",
    "compute_modes",
    "context_modes",
    "mode_views",
    "modes_cache_key",
    "pick_mode",
]


# --------------------------------------------------------------------------------------
def _mesh_key(
    design: Design, dim: int, order: int, size: float | None, elements_through_web: int | None
) -> dict:
    return {
        "stage": f"mesh{dim}d",
        "design": design.wheel.content_hash("structure"),
        "order": order,
        "size": size,
        "elements_through_web": elements_through_web,
        "code": code_version("geometry"),
        "libraries": library_versions("numpy", "gmsh"),
    }


def build_mesh(
    design: Design | WheelDesign,
    dim: int = 2,
    order: int = 2,
    size: float | None = None,
    elements_through_web: int | None = None,
    cache: StageCache | None = None,
) -> Any:
    """Mesh the design: the 2-D half-profile (``dim=2``) or the revolved solid (``dim=3``);
    ``size`` [m] or ``elements_through_web`` (default ``geometry.mesh.mesh_size``)."""
    from geometry import gmsh_mesh
    from geometry.mesh import ProfileMesh, SolidMesh

    design = as_design(design)

    if size is not None and not (math.isfinite(size) and size > 0):
        raise RequestError(f"size must be a positive length in m, got {size}")
    if elements_through_web is not None and elements_through_web < 1:
        raise RequestError(f"elements_through_web must be at least 1, got {elements_through_web}")
    cls = ProfileMesh if dim == 2 else SolidMesh
    key = _mesh_key(design, dim, order, size, elements_through_web)
    if cache is not None:
        try:
            return cls.from_arrays(cache.load(f"mesh{dim}d", key))
        except CacheMiss:
            pass
    mesher = gmsh_mesh.mesh_profile if dim == 2 else gmsh_mesh.mesh_wheel
    # gmsh calls back into Python to size the mesh: a stop raised in that callback would
    # be swallowed and printed by ctypes, so it waits for the mesh (a second or two)
    with uninterrupted():
        mesh = mesher(design.wheel, size=size, elements_through_web=elements_through_web, order=order)
    if cache is not None:
        cache.store(f"mesh{dim}d", key, mesh.to_arrays())
    return mesh


def modes_cache_key(design: Design | WheelDesign, fid: Fidelity, fmax_hz: float) -> dict:
    """The cache key of a modal solve: what its result depends on, and nothing else (at
    the design's own contact point: a curving's contact site reads the same solve)."""
    design = as_design(design).own
    return {
        "stage": "modes",
        "design": design.wheel.content_hash("structure"),
        "method": fid.method,
        "elements_through_web": fid.elements_through_web,
        "fmax_hz": float(fmax_hz),
        "contact": [design.contact_frame.r_m, design.contact_frame.z_m, design.contact_frame.angle_rad],
        "code": code_version("geometry", "fem"),
        "libraries": library_versions("numpy", "scipy", "scikit-fem", "gmsh"),
    }


#: An outline with more segments than this shorter than half the element size is named
#: as the reason when its solve is refused.
DENSE_OUTLINE_SEGMENTS = 100


def check_modes_budget(
    design: Design | WheelDesign, fid: Fidelity, fmax_hz: float, budget: Budget
) -> SolveCost:
    """Estimate the modal solve (``fem.cost``) and refuse it beyond ``budget``."""
    from fem.cost import estimate_cost
    from geometry.mesh import mesh_size, short_segment_lengths

    design = as_design(design)

    h = mesh_size(design.wheel, elements_through_web=fid.elements_through_web)
    cost = estimate_cost(design.wheel, fid.solver, h, fmax_hz)
    cheaper = [n for n, f in FIDELITIES.items() if f.elements_through_web < fid.elements_through_web]
    remedy = (
        (f"use the {cheaper[0]} preset" if cheaper else "use a coarser preset")
        + (", the axisymmetric solver" if fid.solver != "axisym" else "")
        + " or a lower fmax"
    )
    dense = len(short_segment_lengths(design.wheel, h))
    if design.wheel.profile is not None:
        thickness, (r, z) = design.wheel.profile.thinnest_wall()
        remedy += (
            f" (the mesh is sized by the outline's thinnest wall, {thickness * 1e3:.3g} mm at "
            f"r {r:.4g} m, z {z:.4g} m)"
        )
    if dense > DENSE_OUTLINE_SEGMENTS:
        remedy = (
            f"its outline has {dense:,} segments shorter than half the {h * 1e3:.3g} mm elements, and "
            "the mesh follows each: join them into fewer segments or arcs"
        )
    budget.check_solve(
        f"{design.name} with the {fid.name} preset ({fid.solver}, "
        f"{fid.elements_through_web} per web, {h * 1e3:.3g} mm elements, "
        f"modes <= {fmax_hz:g} Hz)",
        cost.dofs,
        cost.memory_bytes,
        cost.seconds,
        remedy,
    )
    return cost


def compute_modes(
    design: Design | WheelDesign,
    fidelity: FidelityName | Fidelity = DEFAULT_FIDELITY,
    solver: SolverName | None = None,
    fmax_hz: float = DEFAULT_FMAX_HZ,
    cache: StageCache | None = None,
    progress: Progress | None = None,
    budget: Budget | None = None,
) -> ModeSet:
    """Eigenmodes of the bore-clamped wheel up to ``fmax_hz``.

    With a ``cache`` the mesh and the modes are re-used whenever geometry, material,
    fidelity, code and libraries are unchanged. A solve that is not cached is estimated
    first and refused (:class:`~wheel_squeal.runtime.request_errors.BudgetError`) beyond the ``budget``.

    Parameters
    ----------
    design : Design or geometry.WheelDesign
    fidelity : str or Fidelity
        A preset ("fast", "balanced", "accurate").
    solver : str, optional
        Another solver for the preset (a name of ``fem.solvers.SOLVERS``).
    fmax_hz : float
        The band's top [Hz].
    cache : StageCache, optional
    progress : Progress, optional
    budget : Budget, optional
        Default: :meth:`Budget.from_environment`.

    Returns
    -------
    fem.ModeSet
        The modes, labelled, with their contact components [1/sqrt(kg)].

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> modes = ws.compute_modes(ws.load_design(), "fast", fmax_hz=1500.0)
    >>> [m.label() for m in modes.modes][:3]
    ['(1,0) axial', '(0,0) axial', '(2,0) axial']
    """
    from fem.modes import ModeSet
    from fem.solvers import SOLVERS, solve_modes

    design = as_design(design)
    if design.contact_site is not None:  # the design's own solve, read where the curving touches
        from fem.moved_contact import modes_at_contact

        own = compute_modes(design.own, fidelity, solver, fmax_hz, cache, progress, budget)
        return modes_at_contact(own, design.contact_frame)
    fid = fidelity if isinstance(fidelity, Fidelity) else fidelity_for(fidelity, solver)
    if not (math.isfinite(fmax_hz) and fmax_hz > 0):
        raise RequestError(f"fmax must be a positive frequency in Hz, got {fmax_hz}")
    progress = progress or Progress(quiet=True)
    key = modes_cache_key(design, fid, fmax_hz)
    if cache is not None:
        try:
            ms = ModeSet.from_arrays(cache.load("modes", key))
            progress.say("modes: loaded from cache")
            check_named_modes(design, ms, fmax_hz)
            return ms
        except CacheMiss:
            pass
    check_modes_budget(design, fid, fmax_hz, budget or Budget.from_environment())
    dim = SOLVERS[fid.solver].mesh_dim
    with progress.stage(f"mesh ({dim}-D, {fid.name})"):
        mesh = build_mesh(
            design, dim=dim, order=fid.mesh_order, elements_through_web=fid.elements_through_web, cache=cache
        )
    with progress.stage(f"modes ({fid.method}, f <= {fmax_hz:g} Hz)"):
        ms = solve_modes(
            design.wheel, mesh, fid.solver, order=fid.order, fmax_hz=fmax_hz, contact=design.contact_frame
        )
    if cache is not None and ms.modes:
        # an empty band is not cached, so its warning is shown again on the next request
        cache.store("modes", key, ms.to_arrays())
    check_named_modes(design, ms, fmax_hz)
    return ms


def context_modes(design: Design, context: RunContext) -> ModeSet:
    """The design's modes as ``context`` computes them (:func:`compute_modes` with its
    preset, band, stage cache, progress and budget)."""
    return compute_modes(
        design,
        context.fidelity,
        fmax_hz=context.fmax_hz,
        cache=context.cache,
        progress=context.progress,
        budget=context.budget,
    )


def check_named_modes(design: Design, modeset: ModeSet, fmax_hz: float) -> None:
    """Refuse (:class:`RequestError`) a design whose ``[squeal.damping]`` names a mode
    that is not among ``modeset``'s: its damping would be silently unused."""
    labels = {f"n={m.nodal_diameters},c={m.nodal_circles}" for m in modeset.modes}
    labels |= {m.name for m in modeset.modes if m.name}
    from .model_sections import DAMPING_KEYS, FAMILY_KEYS

    missing = [k for k, _ in design.damping.by_mode if k not in labels and k not in FAMILY_KEYS]
    if missing:
        raise RequestError(
            f"{design.name}: [squeal.damping] names {', '.join(missing)}, not among the {len(modeset.modes)} "
            f"modes below {fmax_hz:g} Hz (the keys are {DAMPING_KEYS}): raise fmax_hz or remove it"
        )


def pick_mode(modeset: ModeSet, mode: str = "default") -> SelectedMode:
    """A mode by its description, and why it was picked: ``mode`` is default (the (3, 0)
    axial mode) | INDEX | n=3[,c=0] | f=HZ. (The fastest-growing mode, ``auto``, needs
    an operating point: the chain's decision, :mod:`wheel_squeal.decision`.)"""
    from fem.modes import ModeSelection, select_mode

    try:
        return select_mode(modeset.modes, ModeSelection.parse(str(mode)))
    except (ValueError, LookupError) as exc:
        raise RequestError(str(exc).strip("'\"")) from None


def mode_views(
    design: Design,
    fid: Fidelity,
    fmax_hz: float,
    modeset: ModeSet,
    indices: Sequence[int],
    cache: StageCache | None,
    max_file_bytes: float = MAX_FILE_BYTES,
) -> dict[str, bytes]:
    """``modes.vtu`` (every mode, for ParaView; only those of ``indices`` where every mode
    would exceed ``max_file_bytes``) and a PNG of each mode in ``indices``, as {file
    name: bytes}. They depend on the modes only, so they are cached beside them: a run
    that changes the operating point copies them instead of starting VTK."""
    from fem.render import modes_vtu_bytes

    whole = modes_vtu_bytes(modeset)
    written = None if whole <= max_file_bytes else list(indices)
    if written is not None and modes_vtu_bytes(modeset, written) > max_file_bytes:
        written = []  # not even the shown modes fit: the mesh alone is too large
    if written is not None:
        held = "is not written" if not written else "holds the modes drawn only"
        warnings.warn(
            f"modes.vtu {held}: all {len(modeset.modes)} modes would take {whole / 1e6:,.0f} MB, "
            f"over the {max_file_bytes / 1e6:.0f} MB a file may take",
            stacklevel=2,
        )
    key = {
        **modes_cache_key(design, fid, fmax_hz),
        "stage": "views",
        "indices": list(indices),
        "vtu_modes": written,
        "view_libraries": library_versions("pyvista", "vtk", "meshio"),
    }
    if cache is not None:
        try:
            return cache.load("views", key, kept_files)  # plain file names only: written as they are
        except CacheMiss:
            pass
    from fem.render import mode_file_stem, render_mode, write_modes_vtu

    with tempfile.TemporaryDirectory() as tmp:
        scratch = Path(tmp)
        if written != []:
            write_modes_vtu(modeset, scratch / "modes.vtu", written)
        for i in indices:
            render_mode(modeset, i, scratch / f"{mode_file_stem(modeset, i)}.png")
        files = {f.name: f.read_bytes() for f in scratch.iterdir()}
    if cache is not None:
        cache.store("views", key, {k: np.frombuffer(v, np.uint8) for k, v in files.items()})
    return files
