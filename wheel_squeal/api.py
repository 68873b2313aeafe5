"""The stages as a plain Python API (what the command line calls, and a notebook too).

design -> mesh -> modes -> squeal mode -> modal parameters (m, k, c) -> contact law and
operating point -> simulation or sweep. Every function takes and returns plain objects
of the packages below: ``geometry.WheelDesign`` and meshes, ``fem.ModeSet`` and
``Mode``, ``reduced.ModalDOF``, ``ContactLaw``, ``OperatingPoint``, ``SweepResult``.
Bad input raises :class:`~wheel_squeal.errors.RequestError` in the API's own words;
expensive stages go through a :class:`~wheel_squeal.cache.StageCache` when one is given
and are estimated against a :class:`~wheel_squeal.budget.Budget` before they start.
"""

from __future__ import annotations

import math
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from geometry import WheelDesign
from geometry import load_design as _read_design

from .budget import Budget
from .cache import CacheMiss, StageCache, code_version, library_versions
from .errors import RequestError
from .presets import (
    DEFAULT_CRAB_VELOCITY_M_S,
    DEFAULT_DESIGN,
    DEFAULT_FIDELITY,
    DEFAULT_FMAX_HZ,
    DEFAULT_RPM,
    FIDELITIES,
    Fidelity,
    fidelity_for,
    rpm_to_speed,
)
from .progress import Progress

__all__ = [
    "Simulation",
    "build_mesh",
    "check_named_modes",
    "check_modes_budget",
    "compute_modes",
    "contact_law",
    "explicit_dof",
    "load_design",
    "modal_dof",
    "mode_views",
    "modes_cache_key",
    "operating_point",
    "pick_mode",
    "simulate",
    "sweep",
]


def load_design(path: str | Path | None = None) -> WheelDesign:
    """A wheel design from TOML; None gives the default, ``designs/table1.toml``."""
    return _read_design(DEFAULT_DESIGN if path is None else path)


# --------------------------------------------------------------------------------------
# mesh and modes (cached)
# --------------------------------------------------------------------------------------
def _mesh_key(
    design: WheelDesign, dim: int, order: int, size: float | None, elements_through_web: int | None
) -> dict:
    return {
        "stage": f"mesh{dim}d",
        "design": design.content_hash("structure"),
        "order": order,
        "size": size,
        "elements_through_web": elements_through_web,
        "code": code_version("geometry"),
        "libraries": library_versions("numpy", "gmsh"),
    }


def build_mesh(
    design: WheelDesign,
    dim: int = 2,
    order: int = 2,
    size: float | None = None,
    elements_through_web: int | None = None,
    cache: StageCache | None = None,
):
    """Mesh the design: the 2-D half-profile (``dim=2``) or the revolved solid (``dim=3``);
    ``size`` [m] or ``elements_through_web`` (default ``geometry.mesh.mesh_size``)."""
    from geometry import gmsh_mesh
    from geometry.mesh import ProfileMesh, SolidMesh

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
    mesh = mesher(design, size=size, elements_through_web=elements_through_web, order=order)
    if cache is not None:
        cache.store(f"mesh{dim}d", key, mesh.to_arrays())
    return mesh


def modes_cache_key(design: WheelDesign, fid: Fidelity, fmax_hz: float) -> dict:
    """The cache key of a modal solve: what its result depends on, and nothing else."""
    return {
        "stage": "modes",
        "design": design.content_hash("structure"),
        "method": fid.method,
        "elements_through_web": fid.elements_through_web,
        "fmax_hz": float(fmax_hz),
        "code": code_version("geometry", "fem"),
        "libraries": library_versions("numpy", "scipy", "scikit-fem", "gmsh"),
    }


#: An outline with more segments than this shorter than half the element size is named
#: as the reason when its solve is refused.
DENSE_OUTLINE_SEGMENTS = 100


def check_modes_budget(design: WheelDesign, fid: Fidelity, fmax_hz: float, budget: Budget):
    """Estimate the modal solve (``fem.cost``) and refuse it beyond ``budget``."""
    from fem.cost import estimate_cost
    from geometry.mesh import mesh_size, short_segment_lengths

    h = mesh_size(design, elements_through_web=fid.elements_through_web)
    cost = estimate_cost(design, fid.solver, h, fmax_hz)
    cheaper = [n for n, f in FIDELITIES.items() if f.elements_through_web < fid.elements_through_web]
    remedy = (
        (f"use the {cheaper[0]} preset" if cheaper else "use a coarser preset")
        + (", the axisymmetric solver" if fid.solver != "axisym" else "")
        + " or a lower fmax"
    )
    dense = len(short_segment_lengths(design, h))
    if design.profile is not None:
        thickness, (r, z) = design.profile.thinnest_wall()
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
    design: WheelDesign,
    fidelity: str | Fidelity = DEFAULT_FIDELITY,
    solver: str | None = None,
    fmax_hz: float = DEFAULT_FMAX_HZ,
    cache: StageCache | None = None,
    progress: Progress | None = None,
    budget: Budget | None = None,
):
    """Eigenmodes of the bore-clamped wheel up to ``fmax_hz`` [Hz] as a ``fem.ModeSet``.

    ``fidelity`` is a preset name (fast | balanced | accurate) or a :class:`Fidelity`;
    ``solver`` another solver for the preset (a name of ``fem.solvers.SOLVERS``). With a
    ``cache`` the mesh and the modes are re-used whenever geometry, material, fidelity,
    code and libraries are unchanged. A solve that is not cached is estimated first and
    refused (:class:`~wheel_squeal.errors.BudgetError`) beyond the ``budget`` (default:
    :meth:`Budget.from_environment`).
    """
    from fem.modes import ModeSet
    from fem.solvers import SOLVERS, solve_modes

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
        ms = solve_modes(design, mesh, fid.solver, order=fid.order, fmax_hz=fmax_hz)
    if cache is not None and ms.modes:
        # an empty band is not cached, so its warning is shown again on the next request
        cache.store("modes", key, ms.to_arrays())
    check_named_modes(design, ms, fmax_hz)
    return ms


def check_named_modes(design: WheelDesign, modeset, fmax_hz: float) -> None:
    """Refuse (:class:`RequestError`) a design whose ``[squeal.damping]`` names a mode
    that is not among ``modeset``'s: its damping would be silently unused."""
    labels = {f"n={m.nodal_diameters},c={m.nodal_circles}" for m in modeset.modes}
    missing = [k for k, _ in design.mode_damping if k not in labels]
    if missing:
        raise RequestError(
            f"{design.name}: [squeal.damping] names {', '.join(missing)}, not among the {len(modeset.modes)} "
            f"modes below {fmax_hz:g} Hz: raise --fmax or remove it"
        )


def pick_mode(modeset, mode: str = "default"):
    """A mode by its description, and why it was picked: ``mode`` is default (the (3, 0)
    axial mode) | INDEX | n=3[,c=0] | f=HZ. (The fastest-growing mode, ``auto``, needs
    an operating point: :func:`wheel_squeal.stability.choose_mode`.)"""
    from fem.modes import ModeSelection, select_mode

    try:
        return select_mode(modeset.modes, ModeSelection.parse(str(mode)))
    except (ValueError, LookupError) as exc:
        raise RequestError(str(exc).strip("'\"")) from None


def mode_views(
    design: WheelDesign,
    fid: Fidelity,
    fmax_hz: float,
    modeset,
    indices: Sequence[int],
    cache: StageCache | None,
) -> dict[str, bytes]:
    """``modes.vtu`` (every mode, for ParaView) and a PNG of each mode in ``indices``, as
    {file name: bytes}. They depend on the modes only, so they are cached beside them:
    a run that changes the operating point copies them instead of starting VTK."""
    key = {
        **modes_cache_key(design, fid, fmax_hz),
        "stage": "views",
        "indices": list(indices),
        "view_libraries": library_versions("pyvista", "vtk", "meshio"),
    }
    if cache is not None:
        try:
            return {name: arr.tobytes() for name, arr in cache.load("views", key).items()}
        except CacheMiss:
            pass
    from fem.render import mode_file_stem, render_mode, write_modes_vtu

    with tempfile.TemporaryDirectory() as scratch:
        scratch = Path(scratch)
        write_modes_vtu(modeset, scratch / "modes.vtu")
        for i in indices:
            render_mode(modeset, i, scratch / f"{mode_file_stem(modeset, i)}.png")
        files = {f.name: f.read_bytes() for f in scratch.iterdir()}
    if cache is not None:
        cache.store("views", key, {k: np.frombuffer(v, np.uint8) for k, v in files.items()})
    return files


# --------------------------------------------------------------------------------------
# the reduced model: modal parameters, contact, operating point, simulation
# --------------------------------------------------------------------------------------
def modal_dof(mode, design: WheelDesign):
    """The FE mode as the reduced model's (m, k, c) at the contact point, with its
    damping ratio (the design's ``[squeal.damping]`` for it, else ``modal_damping_ratio``)
    and its nodal diameters (a pair, on a turning wheel)."""
    from reduced import ModalDOF

    if not math.isfinite(mode.modal_mass):
        raise RequestError(
            f"mode {mode.index} ({mode.label()}) has a node at the contact point: "
            "it cannot be excited there; pick another mode"
        )
    zeta = design.damping_ratio(mode.nodal_diameters, mode.nodal_circles)
    return ModalDOF.from_damping_ratio(mode.modal_mass, mode.modal_stiffness, zeta, mode.nodal_diameters)


def explicit_dof(mass_kg: float, stiffness_n_m: float, damping_ns_m: float, nodal_diameters: int = 0):
    """A mode given directly by its modal mass [kg], stiffness [N/m], damping [N s/m]
    and nodal diameters (needed on a turning wheel only)."""
    from reduced import ModalDOF

    for name, v, zero_ok in (
        ("mass_kg", mass_kg, False),
        ("stiffness_n_m", stiffness_n_m, False),
        ("damping_ns_m", damping_ns_m, True),
    ):
        if not (math.isfinite(v) and (v > 0 or (zero_ok and v == 0))):
            raise RequestError(f"{name} must be {'non-negative' if zero_ok else 'positive'}, got {v:g}")
    if nodal_diameters < 0:
        raise RequestError(f"nodal diameters must be 0 or more, got {nodal_diameters}")
    return ModalDOF(mass_kg, stiffness_n_m, damping_ns_m, int(nodal_diameters))


def contact_law(design: WheelDesign, c22: float | str | None = None):
    """Creep-law parameters of the design's wheel on its roller (Hertz + Eq. 3, 6).

    ``c22``: None for the design's value (Table 1: 3.14), a number, or ``"kalker"``.
    """
    from reduced import ContactLaw, hertz_contact

    if isinstance(c22, str):
        if c22.lower() != "kalker":
            raise RequestError(f"c22 must be a number or 'kalker', got {c22!r}")
        c22 = "kalker"
    elif c22 is not None and not (math.isfinite(c22) and c22 > 0):
        raise RequestError(f"c22 must be a positive number or 'kalker', got {c22}")
    hertz = hertz_contact(
        design.rolling_radius,
        design.crown_radius,
        design.roller_rolling_radius,
        design.roller_crown_radius,
        design.youngs_modulus,
        design.poissons_ratio,
        design.normal_load,
    )
    return ContactLaw.from_hertz(
        hertz, friction_coefficient=design.friction_coefficient, c22=design.c22 if c22 is None else c22
    )


def operating_point(
    design: WheelDesign,
    *,
    rpm: float | None = None,
    speed: float | None = None,
    crab_velocity: float | None = None,
    angle_of_attack: float | None = None,
):
    """Rolling speed (``rpm`` of the wheel or ``speed`` [m/s]; default 800 RPM) and
    crabbing velocity (``crab_velocity`` [m/s] or ``angle_of_attack`` [rad]; default
    0.39 m/s) as a ``reduced.OperatingPoint``."""
    from reduced import OperatingPoint

    if rpm is not None and speed is not None:
        raise RequestError("give rpm or speed, not both")
    if crab_velocity is not None and angle_of_attack is not None:
        raise RequestError("give crab_velocity or angle_of_attack, not both")
    for name, v in (("rpm", rpm), ("speed", speed)):
        if v is not None and not (math.isfinite(v) and v > 0):
            raise RequestError(f"{name} must be positive, got {v:g}")
    for name, v in (("crab_velocity", crab_velocity), ("angle_of_attack", angle_of_attack)):
        if v is not None and not math.isfinite(v):
            raise RequestError(f"{name} must be finite, got {v}")
    v0 = (
        speed
        if speed is not None
        else rpm_to_speed(DEFAULT_RPM if rpm is None else rpm, design.rolling_radius)
    )
    if angle_of_attack is not None:
        return OperatingPoint.from_angle_of_attack(v0, angle_of_attack)
    return OperatingPoint(v0, DEFAULT_CRAB_VELOCITY_M_S if crab_velocity is None else crab_velocity)


@dataclass
class Simulation:
    """A time-domain run and its limit-cycle metrics (plain objects from ``reduced``)."""

    history: Any
    limit_cycle: Any
    contact: Any
    operating_point: Any

    def summary(self) -> dict:
        """JSON-ready {limit_cycle, operating_point, contact} (SI units, NaN -> None)."""
        from reduced import summary_dicts

        return summary_dicts(self.limit_cycle, self.operating_point, self.contact)


def simulate(
    dof,
    contact,
    op,
    duration: float | None = None,
    wheel_speed_rad_s: float = 0.0,
    budget: Budget | None = None,
) -> Simulation:
    """Integrate the squeal model from rest (``reduced.simulate_to_limit_cycle``): one
    mode or several together (a list), ``duration`` [s] fixed or None to run until the
    outcome is known, on a wheel turning at ``wheel_speed_rad_s`` (0: the paper's model).
    The RK4 steps are counted first and the run refused beyond ``budget`` (default:
    :meth:`Budget.from_environment`): a very low rolling speed makes the contact stiff
    and the step tiny."""
    from reduced import longest_record_s, simulate_to_limit_cycle
    from reduced.model import MAX_STORED_SAMPLES
    from reduced.saturate import FIRST_DURATION_S
    from reduced.sweep import sweep_steps

    dofs = list(dof) if isinstance(dof, list | tuple) else [dof]
    for d in dofs:
        split = d.nodal_diameters * abs(wheel_speed_rad_s)
        if split >= d.angular_frequency_rad_s:
            raise RequestError(
                f"a mode of {d.frequency_hz:.4g} Hz with {d.nodal_diameters} nodal diameters on a wheel "
                f"turning at {wheel_speed_rad_s:.4g} rad/s would split by +-{split / (2 * math.pi):.4g} Hz, "
                "more than its frequency: give the mode's true nodal diameters"
            )
    if duration is not None:
        if not (math.isfinite(duration) and duration > 0):
            raise RequestError(f"duration must be positive, got {duration:g}")
        shortest = MIN_RECORD_PERIODS / min(d.frequency_hz for d in dofs)
        if duration < shortest:
            raise RequestError(
                f"duration {duration:g} s is shorter than {MIN_RECORD_PERIODS} periods of the lowest mode "
                f"({shortest:.3g} s): a limit cycle needs them"
            )
        longest = longest_record_s(dof, wheel_speed_rad_s=wheel_speed_rad_s)
        if duration > longest:
            raise RequestError(
                f"duration {duration:g} s is too long to record: at most {longest:.3g} s "
                "fit (48 samples per period of the highest mode, 10 million samples)"
            )
    steps = sweep_steps(dof, contact, op, duration or FIRST_DURATION_S)
    (budget or Budget.from_environment()).check_sweep(
        1,
        steps,
        len(dofs),
        1,
        "a higher rolling speed (the contact stiffens as it falls) or a shorter duration",
        stored_steps=MAX_STORED_SAMPLES,
    )
    try:
        history, lc = simulate_to_limit_cycle(dof, contact, op, duration, wheel_speed_rad_s=wheel_speed_rad_s)
    except ValueError as exc:  # the model refuses what it cannot integrate, in its own words
        raise RequestError(str(exc)) from None
    return Simulation(history, lc, contact, op)


#: A simulated record covers at least this many periods of its lowest mode (the
#: limit-cycle analysis fits an envelope over cycles).
MIN_RECORD_PERIODS = 10


def sweep(
    dof,
    contact,
    crab_velocities,
    rolling_speeds,
    duration: float = 1.5,
    budget: Budget | None = None,
    progress: Progress | None = None,
):
    """Limit cycles over a grid of crabbing velocities x rolling speeds [m/s] from rest,
    each run ``duration`` [s]; estimated first and refused beyond the ``budget``
    (default: this machine's). Long sweeps report progress."""
    from reduced import OperatingPoint
    from reduced import sweep as run_sweep
    from reduced.sweep import MAX_SWEEP_STEPS, numba_threads, sweep_steps

    if not (math.isfinite(duration) and duration > 0):
        raise RequestError(f"duration must be positive, got {duration:g}")
    vcs = np.atleast_1d(np.asarray(crab_velocities, dtype=float))
    speeds = np.atleast_1d(np.asarray(rolling_speeds, dtype=float))
    if not (np.all(np.isfinite(vcs)) and np.all(np.isfinite(speeds)) and np.all(speeds > 0)):
        raise RequestError("crabbing velocities must be finite and rolling speeds positive")
    steps = max(sweep_steps(dof, contact, OperatingPoint(float(v0), 0.0), duration) for v0 in speeds)
    if steps > MAX_SWEEP_STEPS:
        raise RequestError(
            f"a sweep case needs {steps:,} RK4 steps (limit {MAX_SWEEP_STEPS:,}): a very "
            "stiff or light mode or a very low rolling speed; shorten the duration"
        )
    n_modes = len(dof) if isinstance(dof, (list, tuple)) else 1
    seconds = (budget or Budget.from_environment()).check_sweep(
        len(vcs) * len(speeds), steps, n_modes, numba_threads(), "use fewer points or a shorter duration"
    )
    report = progress.counter("sweep", "cases") if progress is not None and seconds > 2.0 else None
    return run_sweep(dof, contact, vcs, speeds, duration, progress=report)
