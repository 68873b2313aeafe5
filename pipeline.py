#!/usr/bin/env python3
"""Wheel-squeal pipeline: design -> mesh -> modes -> contact modal parameters -> squeal.

Command line (``python pipeline.py --help``)::

    python pipeline.py run                      # Table 1 wheel, 800 RPM, Vc 0.39 m/s
    python pipeline.py run --design designs/thin_web.toml --rpm 600
    python pipeline.py modes --fidelity accurate --out results/modes
    python pipeline.py sweep --crab-velocity 0:0.5:26 --rpm 400,600,800
    python pipeline.py compare designs/thin_web.toml designs/thick_web.toml

Python API (notebooks): :func:`load_design`, :func:`compute_modes`, :func:`pick_mode`,
:func:`modal_dof`, :func:`contact_law`, :func:`operating_point`, :func:`simulate`,
:func:`sweep`, :func:`render` - plain functions on plain objects.

This is the only module that knows every stage. Stages that are expensive (mesh, modes)
go through a content-addressed cache (:class:`StageCache`).
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import json
import math
import os
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator, Sequence

import numpy as np

from geometry import DesignError, WheelDesign, profile_area, revolved_volume
from geometry import load_design as _load_design
from wheel_squeal.budget import Budget
from wheel_squeal.cache import CacheMiss, StageCache
from wheel_squeal.errors import RequestError
from wheel_squeal.outputs import result_folder, write_csv, write_json, write_text_atomic

ROOT = Path(__file__).resolve().parent
DEFAULT_DESIGN = ROOT / "designs" / "table1.toml"

#: A bad request from the user: reported in one line, exit status 2.
UsageError = RequestError


# --------------------------------------------------------------------------------------
# progress and output folders
# --------------------------------------------------------------------------------------
class Progress:
    """Stage progress on stderr: ``[  3.2 s] modes: done (1.9 s)``. Silent if quiet."""

    def __init__(self, quiet: bool = False, stream=None) -> None:
        self.quiet = quiet
        self.stream = stream or sys.stderr
        self.t0 = time.perf_counter()
        self.timings: dict[str, float] = {}

    def say(self, text: str) -> None:
        if not self.quiet:
            print(f"[{time.perf_counter() - self.t0:6.1f} s] {text}", file=self.stream, flush=True)

    @contextlib.contextmanager
    def stage(self, name: str) -> Iterator[None]:
        self.say(f"{name} ...")
        t = time.perf_counter()
        yield
        dt = time.perf_counter() - t
        self.timings[name] = self.timings.get(name, 0.0) + dt
        self.say(f"{name}: done ({dt:.2f} s)")

    def counter(self, name: str, unit: str, every_s: float = 1.0) -> Callable[[int, int], None]:
        """A ``report(done, total)`` callback for long loops: ``name: 120/3000 cases (4 %),
        ~35 s left``, at most once every ``every_s`` seconds and at the end."""
        start = time.perf_counter()
        last = [start]

        def report(done: int, total: int) -> None:
            now = time.perf_counter()
            if done < total and now - last[0] < every_s:
                return
            last[0] = now
            rate = done / max(now - start, 1e-9)
            left = (total - done) / rate if rate > 0 else float("inf")
            self.say(f"{name}: {done:,}/{total:,} {unit} ({100 * done / total:.0f} %), "
                     f"{rate:.3g} {unit}/s, ~{left:.0f} s left")

        return report


# --------------------------------------------------------------------------------------
# stage cache
# --------------------------------------------------------------------------------------
def code_version(*packages: str) -> str:
    """Hash of the source of the given packages: a code change invalidates the cache."""
    h = hashlib.sha256()
    for pkg in packages:
        for f in sorted((ROOT / pkg).rglob("*.py")):
            h.update(f.relative_to(ROOT).as_posix().encode())
            h.update(f.read_bytes())
    return h.hexdigest()[:16]


# --------------------------------------------------------------------------------------
# fidelity presets
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Fidelity:
    """A solver, element order and mesh size, chosen together (see README's table)."""

    name: str
    solver: str  # "axisym" | "3d" (cyclic 3-D P2) | "3d-tet" (gmsh tetrahedra)
    order: int  # element order (2 = quadratic)
    elements_through_web: int
    mesh_order: int = 1  # geometry order of the mesh (1: straight P2 elements on it)

    def mesh_options(self) -> dict:
        return {"order": self.mesh_order, "elements_through_web": self.elements_through_web}


FIDELITIES: dict[str, Fidelity] = {
    "fast": Fidelity("fast", "axisym", 2, 1),
    "balanced": Fidelity("balanced", "axisym", 2, 2),
    "accurate": Fidelity("accurate", "axisym", 2, 4),
}
DEFAULT_FIDELITY = "balanced"
#: FE solvers: axisymmetric harmonics on the profile; 3-D P2 on the profile revolved in
#: identical sectors, solved by cyclic symmetry (fem.cyclic); 3-D P2 on a gmsh mesh
#: (fem.solid: the independent, unstructured check; 20-60x slower).
SOLVERS = ("axisym", "3d", "3d-tet")


def fidelity_for(name: str, solver: str | None = None) -> Fidelity:
    """The preset ``name``, optionally forcing the solver (one of :data:`SOLVERS`)."""
    if name not in FIDELITIES:
        raise UsageError(f"unknown fidelity {name!r}; choose from {', '.join(FIDELITIES)}")
    f = FIDELITIES[name]
    if solver is None or solver == f.solver:
        return f
    if solver not in SOLVERS:
        raise UsageError(f"unknown solver {solver!r}; choose {', '.join(SOLVERS)}")
    # 3-D P2 on the curved (isoparametric) mesh converges from above; straight tets
    # facet the tread and bore (measured: +0.34 % vs +0.26 % at 1 element per web).
    mesh_order = f.order if solver != "axisym" else f.mesh_order
    return Fidelity(f.name, solver, f.order, f.elements_through_web, mesh_order)


def load_design(path: str | Path | None = None) -> WheelDesign:
    """A wheel design from TOML; None gives the default, ``designs/table1.toml``."""
    return _load_design(DEFAULT_DESIGN if path is None else path)


# --------------------------------------------------------------------------------------
# stages: mesh and modes (cached)
# --------------------------------------------------------------------------------------
def _mesh_key(design: WheelDesign, dim: int, order: int, size: float | None,
              elements_through_web: int | None) -> dict:
    return {
        "stage": f"mesh{dim}d",
        "design": design.content_hash("structure"),
        "order": order,
        "size": size,
        "elements_through_web": elements_through_web,
        "code": code_version("geometry"),
    }


def build_mesh(design: WheelDesign, dim: int = 2, order: int = 2, size: float | None = None,
               elements_through_web: int | None = None, cache: StageCache | None = None):
    """Mesh the design: the 2-D half-profile (``dim=2``) or the revolved solid (``dim=3``)."""
    from geometry import mesh as gm

    cls = gm.ProfileMesh if dim == 2 else gm.SolidMesh
    mesher = gm.mesh_profile if dim == 2 else gm.mesh_wheel
    key = _mesh_key(design, dim, order, size, elements_through_web)
    if cache is not None:
        try:
            arrays = cache.load(f"mesh{dim}d", key)
            return _mesh_from_arrays(cls, arrays)
        except CacheMiss:
            pass
    mesh = mesher(design, size=size, elements_through_web=elements_through_web, order=order)
    if cache is not None:
        cache.store(f"mesh{dim}d", key, _mesh_to_arrays(mesh))
    return mesh


def _mesh_to_arrays(mesh) -> dict[str, np.ndarray]:
    import dataclasses

    out = {}
    for f in dataclasses.fields(mesh):
        if f.init:
            out[f.name] = np.asarray(getattr(mesh, f.name))
    return out


def _mesh_from_arrays(cls, arrays: dict[str, np.ndarray]):
    import dataclasses

    kwargs = {}
    for f in dataclasses.fields(cls):
        if not f.init:
            continue
        v = arrays[f.name]
        kwargs[f.name] = v.item() if v.ndim == 0 else v
    return cls(**kwargs)


def _modes_key(design: WheelDesign, fid: Fidelity, fmax_hz: float) -> dict:
    return {
        "stage": "modes",
        "design": design.content_hash("structure"),
        "solver": fid.solver,
        "order": fid.order,
        "mesh_order": fid.mesh_order,
        "elements_through_web": fid.elements_through_web,
        "fmax_hz": float(fmax_hz),
        "code": code_version("geometry", "fem"),
    }


def _modeset_to_arrays(ms) -> dict[str, np.ndarray]:
    import dataclasses

    meta = {
        "modes": [dataclasses.asdict(m) for m in ms.modes],
        "solver": ms.solver,
        "dofs": int(ms.dofs),
        "timings_s": ms.timings_s,
        "cell_types": list(ms.cells),
    }
    arrays = {"meta": np.array(json.dumps(meta)), "points": np.asarray(ms.points, float)}
    for name, conn in ms.cells.items():
        arrays[f"cells_{name}"] = np.asarray(conn)
    for i, s in enumerate(ms.shapes):
        arrays[f"shape_{i}"] = np.asarray(s, dtype=float)
    return arrays


def _modeset_from_arrays(arrays: dict[str, np.ndarray]):
    from fem.modes import Mode, ModeSet

    meta = json.loads(str(arrays["meta"]))
    modes = [Mode(**{**m, "contact_axial": tuple(m["contact_axial"])}) for m in meta["modes"]]
    return ModeSet(
        modes=modes,
        points=arrays["points"],
        cells={t: arrays[f"cells_{t}"] for t in meta["cell_types"]},
        shapes=[arrays[f"shape_{i}"] for i in range(len(modes))],
        solver=meta["solver"],
        dofs=meta["dofs"],
        timings_s=meta["timings_s"],
    )


def compute_modes(design: WheelDesign, fidelity: str | Fidelity = DEFAULT_FIDELITY,
                  solver: str | None = None, fmax_hz: float = 5000.0,
                  cache: StageCache | None = None, progress: Progress | None = None,
                  budget: Budget | None = None):
    """Eigenmodes of the bore-clamped wheel up to ``fmax_hz`` [Hz] as a ``fem.ModeSet``.

    ``fidelity`` is a preset name (fast | balanced | accurate) or a :class:`Fidelity`;
    ``solver`` forces one of :data:`SOLVERS`. With a ``cache`` the mesh and the modes are
    re-used whenever the geometry, material, fidelity and code are unchanged. A solve
    that is not cached is estimated first and refused (:class:`BudgetError`) beyond the
    ``budget`` (default: :meth:`Budget.from_environment`).
    """
    fid = fidelity if isinstance(fidelity, Fidelity) else fidelity_for(fidelity, solver)
    if not (math.isfinite(fmax_hz) and fmax_hz > 0):
        raise UsageError(f"--fmax must be a positive frequency in Hz, got {fmax_hz}")
    progress = progress or Progress(quiet=True)
    key = _modes_key(design, fid, fmax_hz)
    if cache is not None:
        try:
            ms = _modeset_from_arrays(cache.load("modes", key))
            progress.say("modes: loaded from cache")
            return ms
        except CacheMiss:
            pass
    check_modes_budget(design, fid, fmax_hz, budget or Budget.from_environment())
    dim = 3 if fid.solver == "3d-tet" else 2  # the cyclic mesh is revolved from the profile
    with progress.stage(f"mesh ({dim}-D, {fid.name})"):
        mesh = build_mesh(design, dim=dim, cache=cache, **fid.mesh_options())
    with progress.stage(f"modes ({fid.solver}, f <= {fmax_hz:g} Hz)"):
        if fid.solver == "axisym":
            from fem.axisym import solve_axisymmetric

            ms = solve_axisymmetric(design, mesh, order=fid.order, fmax_hz=fmax_hz,
                                    curved=fid.mesh_order == 2)
        elif fid.solver == "3d":
            from fem.cyclic import default_sectors, solve_cyclic
            from geometry.mesh import revolve_profile

            solid = revolve_profile(mesh, default_sectors(design, mesh.size))
            ms = solve_cyclic(design, solid, fmax_hz=fmax_hz)
        else:
            from fem.solid import solve_solid

            ms = solve_solid(design, mesh, order=fid.order, fmax_hz=fmax_hz)
    if cache is not None and ms.modes:
        # an empty band is not cached, so its warning is shown again on the next request
        cache.store("modes", key, _modeset_to_arrays(ms))
    return ms


def check_modes_budget(design: WheelDesign, fid: Fidelity, fmax_hz: float, budget: Budget):
    """Estimate the modal solve (``fem.cost``) and refuse it beyond ``budget``."""
    from fem.cost import estimate_cost
    from geometry.mesh import mesh_size

    h = mesh_size(design, elements_through_web=fid.elements_through_web)
    cost = estimate_cost(design, fid.solver, h, fmax_hz)
    cheaper = [n for n, f in FIDELITIES.items() if f.elements_through_web < fid.elements_through_web]
    remedy = (f"use --fidelity {cheaper[0]}" if cheaper else "use a coarser preset") + \
        (", the axisymmetric solver (--solver axisym)" if fid.solver != "axisym" else "") + \
        " or a lower --fmax"
    budget.check_solve(f"{design.name} with the {fid.name} preset ({fid.solver}, "
                       f"{fid.elements_through_web} per web, {h * 1e3:.3g} mm elements, "
                       f"modes <= {fmax_hz:g} Hz)", cost.dofs, cost.memory_bytes, cost.seconds, remedy)
    return cost


def pick_mode(modeset, mode: str = "auto"):
    """The squeal mode and why it was picked; ``mode`` is auto | INDEX | n=3[,c=0] | f=HZ."""
    from fem.modes import ModeSelection, select_mode

    try:
        selection = ModeSelection.parse(str(mode))
        return select_mode(modeset.modes, selection)
    except (ValueError, LookupError) as exc:
        raise UsageError(str(exc).strip("'\"").replace("(fmax)", "(--fmax)")) from None


# --------------------------------------------------------------------------------------
# commands
# --------------------------------------------------------------------------------------
def _design_from_args(args) -> WheelDesign:
    return load_design(args.design if args.design else DEFAULT_DESIGN)


def _cache_from_args(args) -> StageCache:
    return StageCache(args.cache_dir, enabled=not args.no_cache)


def _budget_from_args(args) -> Budget:
    return Budget.from_environment(getattr(args, "max_dofs", None), getattr(args, "max_seconds", None))


def cmd_mesh(args) -> int:
    design = _design_from_args(args)
    if args.size is not None and not (math.isfinite(args.size) and args.size > 0):
        raise UsageError(f"--size must be a positive length in m, got {args.size}")
    if args.elements_through_web is not None and args.elements_through_web < 1:
        raise UsageError("--elements-through-web must be at least 1")
    progress = Progress(args.quiet)
    with result_folder(args.out, "mesh") as tmp:
        _check_mesh_budget(design, args, _budget_from_args(args))
        t = time.perf_counter()
        with progress.stage(f"mesh ({args.dim}-D, order {args.order})"):
            mesh = build_mesh(design, dim=args.dim, order=args.order, size=args.size,
                              elements_through_web=args.elements_through_web)
        seconds = time.perf_counter() - t
        if args.dim == 2:
            extra = {"mesh_area_m2": mesh.area(), "exact_area_m2": profile_area(design),
                     "mesh_volume_m3": mesh.revolved_volume()}
        else:
            extra = {"mesh_volume_m3": mesh.volume()}
        summary = {
            "design": design.name,
            "dim": args.dim,
            "order": args.order,
            "nodes": int(mesh.n_nodes),
            "elements": int(mesh.n_elements),
            **extra,
            "exact_volume_m3": revolved_volume(design),
            "seconds": seconds,
        }
        mesh.write(tmp / "mesh.msh")
        mesh.write(tmp / "mesh.vtu")
        write_json(tmp / "summary.json", summary)
    rel = summary["mesh_volume_m3"] / summary["exact_volume_m3"] - 1
    print(f"{design.name}: {summary['nodes']} nodes, {summary['elements']} elements, "
          f"volume {summary['mesh_volume_m3']:.6e} m^3 ({rel:+.3%} vs exact), "
          f"{seconds:.2f} s -> {args.out}")
    return 0


def _check_mesh_budget(design: WheelDesign, args, budget: Budget) -> None:
    """The mesh command's own estimate (the solvers estimate in compute_modes)."""
    from geometry.mesh import estimate_element_count, mesh_size

    h = mesh_size(design, args.size, args.elements_through_web, args.dim)
    n = estimate_element_count(design, h, args.dim)
    nodes = n * (2.2 if args.dim == 2 else 1.9) if args.order == 2 else n * (0.6 if args.dim == 2 else 0.2)
    seconds = n * (2e-5 if args.dim == 2 else 6e-5)  # gmsh, measured on these wheels
    budget.check_solve(f"meshing {design.name} ({args.dim}-D, size {h * 1e3:.3g} mm)", 3 * nodes,
                       n * (2e3 if args.dim == 2 else 4e3), seconds,
                       "use a larger --size or fewer --elements-through-web")

def _modes_table(modes, damping_ratio: float, selected=None) -> str:
    lines = [f"{'#':>3} {'f [Hz]':>9} {'n':>2} {'c':>2} {'family':<15} {'m [kg]':>10} "
             f"{'k [N/m]':>10} {'c [Ns/m]':>9}"]
    for m in modes:
        d = m.to_dict(damping_ratio)
        mass = f"{d['modal_mass_kg']:10.3f}" if d["modal_mass_kg"] is not None else f"{'node':>10}"
        k = f"{d['modal_stiffness_n_m']:10.3e}" if d["modal_stiffness_n_m"] is not None else f"{'-':>10}"
        c = f"{d['modal_damping_ns_m']:9.2f}" if d["modal_damping_ns_m"] is not None else f"{'-':>9}"
        mark = " <- selected" if selected is not None and m.index == selected.index else ""
        lines.append(f"{m.index:>3} {m.frequency_hz:9.1f} {m.nodal_diameters:>2} "
                     f"{m.nodal_circles:>2} {m.family:<15} {mass} {k} {c}{mark}")
    return "\n".join(lines)


def modes_summary(design: WheelDesign, modeset, selected, fid: Fidelity) -> dict:
    zeta = design.modal_damping_ratio
    return {
        "design": design.name,
        "fidelity": fid.name,
        "solver": modeset.solver,
        "dofs": int(modeset.dofs),
        "modes": [m.to_dict(zeta) for m in modeset.modes],
        "selected_mode": selected.to_dict(zeta),
        "timings_s": dict(modeset.timings_s),
    }


def cmd_modes(args) -> int:
    design = _design_from_args(args)
    fid = fidelity_for(args.fidelity, args.solver)
    progress = Progress(args.quiet)
    with result_folder(args.out, "modes") as tmp:
        cache = _cache_from_args(args)
        ms = compute_modes(design, fid, fmax_hz=args.fmax, cache=cache, progress=progress,
                           budget=_budget_from_args(args))
        if not ms.modes:
            raise UsageError(f"no modes below {args.fmax:g} Hz for {design.name}")
        selected, why = pick_mode(ms, args.mode)
        summary = modes_summary(design, ms, selected, fid)
        write_mode_views(tmp, design, fid, args.fmax, ms, [], cache)
        write_json(tmp / "summary.json", summary)
    print(_modes_table(ms.modes, design.modal_damping_ratio, selected))
    print(f"selected: mode {selected.index} ({why}), {selected.frequency_hz:.1f} Hz, "
          f"m = {selected.modal_mass:.3f} kg")
    print(f"{ms.solver}, {ms.dofs} DOFs, {fid.name} -> {args.out}")
    return 0

# --------------------------------------------------------------------------------------
# reduced model: contact, operating point, simulation
# --------------------------------------------------------------------------------------
def contact_law(design: WheelDesign, c22: float | str | None = None):
    """Creep-law parameters of the design's wheel on its roller (Hertz + Eq. 3, 6).

    ``c22``: None for the design's value (Table 1: 3.14), a number, or ``"kalker"``.
    """
    from reduced import ContactLaw, hertz_contact

    hertz = hertz_contact(design.rolling_radius, design.crown_radius,
                          design.roller_rolling_radius, design.roller_crown_radius,
                          design.youngs_modulus, design.poissons_ratio, design.normal_load)
    return ContactLaw.from_hertz(hertz, friction_coefficient=design.friction_coefficient,
                                 c22=design.c22 if c22 is None else c22)


def operating_point(design: WheelDesign, *, rpm: float | None = None, speed: float | None = None,
                    crab_velocity: float | None = None, angle_of_attack: float | None = None):
    """Rolling speed (``rpm`` of the wheel or ``speed`` [m/s]; default 800 RPM) and
    crabbing velocity (``crab_velocity`` [m/s] or ``angle_of_attack`` [rad]; default
    0.39 m/s) as a ``reduced.OperatingPoint``."""
    from reduced import OperatingPoint

    if rpm is not None and speed is not None:
        raise UsageError("give --rpm or --speed, not both")
    if crab_velocity is not None and angle_of_attack is not None:
        raise UsageError("give --crab-velocity or --angle-of-attack, not both")
    for name, v in (("rpm", rpm), ("speed", speed)):
        if v is not None and not (math.isfinite(v) and v > 0):
            raise UsageError(f"--{name} must be positive, got {v:g}")
    for name, v in (("crab-velocity", crab_velocity), ("angle-of-attack", angle_of_attack)):
        if v is not None and not math.isfinite(v):
            raise UsageError(f"--{name} must be finite, got {v}")
    v0 = speed if speed is not None else (800.0 if rpm is None else rpm) * 2 * math.pi / 60 * design.rolling_radius
    if angle_of_attack is not None:
        return OperatingPoint.from_angle_of_attack(v0, angle_of_attack)
    return OperatingPoint(v0, 0.39 if crab_velocity is None else crab_velocity)


def modal_dof(mode, design: WheelDesign):
    """The selected FE mode as the reduced model's (m, k, c) at the contact point."""
    from reduced import ModalDOF

    if not math.isfinite(mode.modal_mass):
        raise UsageError(f"mode {mode.index} ({mode.label()}) has a node at the contact point: "
                         "it cannot be excited there; pick another mode")
    return ModalDOF.from_damping_ratio(mode.modal_mass, mode.modal_stiffness,
                                       design.modal_damping_ratio)


@dataclass
class Simulation:
    """A time-domain run and its limit-cycle metrics (plain objects from ``reduced``)."""

    history: Any
    limit_cycle: Any
    contact: Any
    operating_point: Any

    def summary(self) -> dict:
        from reduced import summary_dicts

        return summary_dicts(self.limit_cycle, self.operating_point, self.contact)


#: Samples per period of the highest mode kept in a simulation record (every RK4 step
#: at the default step, period / 48; fewer when a stiff contact shortens the step).
RECORD_SAMPLES_PER_PERIOD = 48


def simulate(dof, contact, op, duration: float | None = None, max_duration: float = 4.8) -> Simulation:
    """Integrate the squeal model from rest.

    ``duration`` [s]: fixed length; None runs 0.6 s (the paper's Fig. 6) and doubles it,
    up to ``max_duration``, while the oscillation is still growing, so slow cases reach
    their limit cycle.
    The first length is the larger of 0.6 s and an estimate of the time to saturate
    from the harmonic-balance prediction (growth from the start transient to the
    predicted amplitude at the linear rate, plus margin), so most runs integrate once.
    """
    import warnings

    from reduced import limit_cycle, predict_limit_cycle
    from reduced import simulate as integrate

    from reduced.model import MAX_STORED_SAMPLES

    if duration is not None and not (math.isfinite(duration) and duration > 0):
        raise UsageError(f"--duration must be positive, got {duration:g}")
    f_top = max(d.frequency_hz for d in dof) if isinstance(dof, (list, tuple)) else dof.frequency_hz
    longest = MAX_STORED_SAMPLES / (RECORD_SAMPLES_PER_PERIOD * f_top)
    if duration is not None and duration > longest:
        raise UsageError(f"--duration {duration:g} s is too long to record: {RECORD_SAMPLES_PER_PERIOD} "
                         f"samples per period of the {f_top:.4g} Hz mode fit at most {longest:.3g} s")
    max_duration = min(max_duration, longest)
    t = duration
    if t is None:
        t = 0.6
        if not isinstance(dof, (list, tuple)):  # the predictor takes one mode
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # distortion warning: only an estimate here
                pred = predict_limit_cycle(dof, contact, op)
            sigma = pred.growth_rate_analytic_1_s
            if pred.squeal and sigma > 0 and pred.initial_amplitude_m_s > 0:
                grow = math.log(max(pred.velocity_amplitude_m_s / pred.initial_amplitude_m_s, 1.0)) / sigma
                t = min(max(t, 1.5 * grow + 60.0 / pred.frequency_hz), max_duration)
    while True:
        hist = integrate(dof, contact, op, t, samples_per_period=RECORD_SAMPLES_PER_PERIOD)
        lc = limit_cycle(hist)
        if duration is not None or lc.saturated or not lc.squeal and lc.growth_rate_analytic_1_s <= 0 \
                or t * 2 > max_duration:
            return Simulation(hist, lc, contact, op)
        t *= 2


def _mode_source(args, design: WheelDesign, progress: Progress, cache: StageCache | None):
    """(dof, modes info or None) from the design's FE modes or --mass/--stiffness/--damping."""
    explicit = [getattr(args, "mass", None), getattr(args, "stiffness", None),
                getattr(args, "damping", None)]
    if any(v is not None for v in explicit):
        if any(v is None for v in explicit):
            raise UsageError("--mass, --stiffness and --damping go together: give all three")
        for name, v in zip(("mass", "stiffness", "damping"), explicit):
            if not math.isfinite(v) or v < 0 or (v == 0 and name != "damping"):
                raise UsageError(f"--{name} must be positive, got {v:g}")
        from reduced import ModalDOF

        progress.say("modal parameters given: no mesh, no FE")
        return ModalDOF(args.mass, args.stiffness, args.damping), None
    fid = fidelity_for(args.fidelity, getattr(args, "solver", None))
    ms = compute_modes(design, fid, fmax_hz=args.fmax, cache=cache, progress=progress)
    mode, why = pick_mode(ms, args.mode)
    progress.say(f"squeal mode: {mode.index} ({why}), {mode.frequency_hz:.1f} Hz")
    summary = modes_summary(design, ms, mode, fid)
    summary["selected_mode"]["why"] = why
    return modal_dof(mode, design), (ms, mode, summary)


def _simulate_outputs(tmp: Path, sim: Simulation) -> None:
    from reduced import write_time_history_plots, write_timeseries_csv

    write_timeseries_csv(sim.history, tmp)
    write_time_history_plots(sim.history, tmp, times_s=_plot_times(sim))


def _plot_times(sim: Simulation) -> tuple[float, float]:
    """Windows for the paper's Fig. 7-10: while growing (0.2 s) and at the limit cycle
    (0.4 s in the paper; later when this mode saturates later)."""
    lc = sim.limit_cycle
    end = float(sim.history.t[-1])
    if not (lc.saturated and math.isfinite(lc.time_to_saturation_s)):
        return (min(0.2, end / 3), min(0.4, end))
    period = 1.0 / lc.frequency_hz
    t_lc = max(0.4, lc.time_to_saturation_s + 20 * period)
    growing = min(0.2, 0.5 * lc.time_to_saturation_s)
    return (round(growing, 2), round(max(min(t_lc, end - 5 * period), 0.0), 2))


def _print_squeal(sim: Simulation, dof) -> None:
    s = sim.summary()
    lc, op, ct = s["limit_cycle"], s["operating_point"], s["contact"]
    print(f"modal parameters: f = {dof.frequency_hz:.1f} Hz, m = {dof.mass_kg:.3f} kg, "
          f"k = {dof.stiffness_n_m:.4g} N/m, c = {dof.damping_ns_m:.2f} N s/m")
    print(f"contact ellipse: a = {ct['semi_axis_a_m'] * 1e3:.3f} mm (rolling), "
          f"b = {ct['semi_axis_b_m'] * 1e3:.3f} mm, C22 = {ct['c22']:.3g}, mu = {ct['friction_coefficient']:.3g}")
    print(f"operating point: V0 = {op['rolling_speed_m_s']:.2f} m/s, "
          f"Vc = {op['crabbing_velocity_m_s']:.4g} m/s, creepage = {op['creepage']:.4g}")
    lcobj = sim.limit_cycle
    if lc["squeal"]:
        state = "limit cycle" if lcobj.saturated else "still growing at the end of the run"
        tsat = lc["time_to_saturation_s"]
        print(f"SQUEAL: velocity amplitude {lc['velocity_amplitude_m_s']:.4g} m/s ({state}), "
              f"{lc['frequency_hz']:.1f} Hz, growth rate {lc['growth_rate_1_s']:.3g} 1/s"
              + (f", saturated after {tsat:.3f} s" if tsat is not None else ""))
    else:
        print(f"no squeal (linear growth rate {lcobj.growth_rate_analytic_1_s:.3g} 1/s)")


def cmd_simulate(args) -> int:
    progress = Progress(args.quiet)
    with result_folder(args.out, "simulate") as tmp:
        cache = _cache_from_args(args)
        design = _design_from_args(args)
        dof, modes_info = _mode_source(args, design, progress, cache)
        contact = contact_law(design, args.c22)
        op = operating_point(design, rpm=args.rpm, speed=args.speed, crab_velocity=args.crab_velocity,
                             angle_of_attack=args.angle_of_attack)
        with progress.stage("squeal model"):
            sim = simulate(dof, contact, op, args.duration)
        summary = {"design": design.name, "modal_parameters": _dof_dict(dof), **sim.summary(),
                   "timings_s": progress.timings}
        if modes_info is not None:
            summary["selected_mode"] = modes_info[2]["selected_mode"]
        _simulate_outputs(tmp, sim)
        write_json(tmp / "summary.json", summary)
    _print_squeal(sim, dof)
    print(f"-> {args.out}")
    return 0

def _dof_dict(dof) -> dict:
    return {"mass_kg": dof.mass_kg, "stiffness_n_m": dof.stiffness_n_m,
            "damping_ns_m": dof.damping_ns_m, "frequency_hz": dof.frequency_hz}


def cmd_run(args) -> int:
    design = _design_from_args(args)
    out = args.out or Path("results") / design.name
    progress = Progress(args.quiet)
    t0 = time.perf_counter()
    with result_folder(out, "run") as tmp:
        cache = _cache_from_args(args)
        op = operating_point(design, rpm=args.rpm, crab_velocity=args.crab_velocity,
                             angle_of_attack=args.angle_of_attack)
        contact = contact_law(design, args.c22)
        dof, (ms, mode, msum) = _mode_source(args, design, progress, cache)
        with progress.stage("squeal model"):
            sim = simulate(dof, contact, op, args.duration)
        indices = [mode.index] if args.render == "selected" else (
            [] if args.render == "none" else list(range(len(ms.modes))))
        fid = fidelity_for(args.fidelity, args.solver)
        with progress.stage("report"):
            _simulate_outputs(tmp, sim)
        with progress.stage("mode views"):
            write_mode_views(tmp, design, fid, args.fmax, ms, indices, cache)
        summary = {**msum, **sim.summary(), "modal_parameters": _dof_dict(dof),
                   "timings_s": {**progress.timings, "total": time.perf_counter() - t0},
                   "cache": {"hits": cache.hits, "misses": cache.misses}}
        write_json(tmp / "summary.json", summary)
    print(f"{design.name}: squeal mode {mode.index}: {mode.label()} "
          f"({msum['selected_mode']['why']}), {mode.frequency_hz:.1f} Hz")
    _print_squeal(sim, dof)
    print(f"files: {out}/ (summary.json, timeseries.csv, *.png, modes.vtu)  "
          f"[{time.perf_counter() - t0:.1f} s]")
    return 0

def write_mode_views(directory: Path, design: WheelDesign, fid: Fidelity, fmax_hz: float, modeset,
                     indices: Sequence[int], cache: StageCache | None) -> list[Path]:
    """Write ``modes.vtu`` and a PNG per mode index into ``directory``.

    They depend on the modes only, so they are cached beside them: a run that changes
    the operating point copies them instead of starting VTK.
    """
    key = {**_modes_key(design, fid, fmax_hz), "stage": "views", "indices": list(indices)}
    files: dict[str, bytes] = {}
    if cache is not None:
        try:
            files = {name: arr.tobytes() for name, arr in cache.load("views", key).items()}
        except CacheMiss:
            pass
    if not files:
        from fem.render import mode_file_stem, render_mode, write_modes_vtu

        with tempfile.TemporaryDirectory() as scratch:
            scratch = Path(scratch)
            write_modes_vtu(modeset, scratch / "modes.vtu")
            for i in indices:
                render_mode(modeset, i, scratch / f"{mode_file_stem(modeset, i)}.png")
            files = {f.name: f.read_bytes() for f in scratch.iterdir()}
        if cache is not None:
            cache.store("views", key, {k: np.frombuffer(v, np.uint8) for k, v in files.items()})
    paths = []
    for name, data in files.items():
        (directory / name).write_bytes(data)
        paths.append(directory / name)
    return paths


def cmd_render(args) -> int:
    design = _design_from_args(args)
    progress = Progress(args.quiet)
    with result_folder(args.out, "render") as tmp:
        cache = _cache_from_args(args)
        ms = compute_modes(design, fidelity_for(args.fidelity, args.solver), fmax_hz=args.fmax,
                           cache=cache, progress=progress, budget=_budget_from_args(args))
        indices = None
        if args.modes:
            try:
                indices = [int(i) for i in args.modes.split(",")]
            except ValueError:
                raise UsageError(f"--modes takes indices like 0,3,4, got {args.modes!r}") from None
            bad = [i for i in indices if not 0 <= i < len(ms.modes)]
            if bad:
                raise UsageError(f"mode index {bad[0]} out of range 0..{len(ms.modes) - 1}")
        from fem.render import render_modes

        with progress.stage("render"):
            paths = render_modes(ms, tmp, indices=indices, gif=args.gif)
    print(f"{len(paths)} files -> {args.out}")
    return 0

#: Most points of one sweep axis (START:STOP:N): a typo like 0:1:1000000000 must not
#: allocate gigabytes before the budget has a say.
MAX_AXIS_POINTS = 1_000_000


def parse_range(text: str, flag: str = "--crab-velocity") -> np.ndarray:
    """``START:STOP:N`` (N points, inclusive) or a comma list -> array."""
    bad = UsageError(f"{flag}: expected START:STOP:N or a comma list of numbers, got {text!r}")
    try:
        if ":" in text:
            a, b, n = text.split(":")
            start, stop, n = float(a), float(b), int(n)
            if n < 1:
                raise bad
            if n > MAX_AXIS_POINTS:
                raise UsageError(f"{flag} {text}: {n:,} points is more than a sweep axis takes "
                                 f"({MAX_AXIS_POINTS:,})")
            values = np.linspace(start, stop, n)
        else:
            values = np.array([float(x) for x in text.split(",")])
    except UsageError:
        raise
    except ValueError:
        raise bad from None
    if not np.all(np.isfinite(values)):
        raise UsageError(f"{flag} values must be finite, got {text!r}")
    return values


def sweep(dof, contact, crab_velocities, rolling_speeds, duration: float = 1.5,
          budget: Budget | None = None, progress: Progress | None = None):
    """Limit cycles over a grid of crabbing velocities x rolling speeds [m/s] (one call),
    refused beforehand if the budget (default: this machine's) does not allow it."""
    from reduced import OperatingPoint, sweep as run_sweep
    from reduced.sweep import numba_threads, sweep_steps

    budget = budget or Budget.from_environment()
    speeds = np.atleast_1d(np.asarray(rolling_speeds, dtype=float))
    n_cases = len(np.atleast_1d(crab_velocities)) * len(speeds)
    steps = max(sweep_steps(dof, contact, OperatingPoint(float(v0), 0.0), duration) for v0 in speeds)
    n_modes = len(dof) if isinstance(dof, (list, tuple)) else 1
    seconds = budget.check_sweep(n_cases, steps, n_modes, numba_threads(),
                                 "use fewer points or a shorter duration")
    report = None
    if progress is not None and seconds > 2.0:
        report = progress.counter("sweep", "cases")
    return run_sweep(dof, contact, crab_velocities, speeds, duration, progress=report)

def cmd_sweep(args) -> int:
    vcs = parse_range(args.crab_velocity, "--crab-velocity")
    rpms = parse_range(args.rpm, "--rpm")
    if np.any(rpms <= 0):
        raise UsageError("--rpm values must be positive")
    if not (math.isfinite(args.duration) and args.duration > 0):
        raise UsageError(f"--duration must be positive, got {args.duration:g}")
    progress = Progress(args.quiet)
    with result_folder(args.out, "sweep") as tmp:
        cache = _cache_from_args(args)
        design = _design_from_args(args)
        dof, _ = _mode_source(args, design, progress, cache)
        contact = contact_law(design, args.c22)
        speeds = rpms * 2 * math.pi / 60 * design.rolling_radius
        with progress.stage(f"sweep {len(vcs)} x {len(speeds)} cases, {args.duration:g} s each"):
            result = sweep(dof, contact, vcs, speeds, args.duration, budget=_budget_from_args(args),
                           progress=progress)
        from reduced import write_sweep_csv, write_sweep_plot

        write_sweep_csv(result, tmp, wheel_radius_m=design.rolling_radius)
        write_sweep_plot(result, tmp, wheel_radius_m=design.rolling_radius)
        write_json(tmp / "summary.json", {"design": design.name, "modal_parameters": _dof_dict(dof),
                                          "duration_s": args.duration, "timings_s": progress.timings})
    print(f"{'Vc [m/s]':>9} " + " ".join(f"{r:>9.0f}rpm" for r in rpms))
    for i, vc in enumerate(vcs):
        cells = []
        for j in range(len(speeds)):
            a = result.velocity_amplitude_m_s[i, j]
            cells.append(f"{a:12.4f}" if result.squeal[i, j] else f"{'-':>12}")
        print(f"{vc:9.4f} " + " ".join(cells))
    print(f"velocity amplitude [m/s] ('-' = no squeal) -> {args.out}")
    return 0

def cmd_compare(args) -> int:
    progress = Progress(args.quiet)
    with result_folder(args.out, "compare") as tmp:
        cache = _cache_from_args(args)
        designs = []
        for p in args.designs:
            try:
                designs.append(load_design(p))
            except DesignError as exc:
                raise UsageError(f"design {p}: {exc}") from None
        names = [d.name for d in designs]
        if len(set(names)) != len(names):
            raise UsageError("two designs have the same name; give each a distinct name")
        rows, sims = [], []
        fid = fidelity_for(args.fidelity, args.solver)
        budget = _budget_from_args(args)
        for d in designs:
            progress.say(f"design {d.name}")
            try:
                ms = compute_modes(d, fid, fmax_hz=args.fmax, cache=cache, progress=progress,
                                   budget=budget)
                mode, why = pick_mode(ms, args.mode)
                dof = modal_dof(mode, d)
                contact = contact_law(d, args.c22)
                op = operating_point(d, rpm=args.rpm, crab_velocity=args.crab_velocity,
                                     angle_of_attack=args.angle_of_attack)
                sim = simulate(dof, contact, op, args.duration)
            except (UsageError, DesignError) as exc:
                raise UsageError(f"design {d.name}: {exc}") from None
            s = sim.summary()["limit_cycle"]
            rows.append({"design": d.name, "mode_index": mode.index, "mode": mode.label(),
                         "frequency_hz": mode.frequency_hz, "modal_mass_kg": dof.mass_kg,
                         "modal_stiffness_n_m": dof.stiffness_n_m, "modal_damping_ns_m": dof.damping_ns_m,
                         "growth_rate_1_s": s["growth_rate_1_s"], "squeal": s["squeal"],
                         "velocity_amplitude_m_s": s["velocity_amplitude_m_s"],
                         "time_to_saturation_s": s["time_to_saturation_s"]})
            sims.append(sim)
        write_csv(tmp / "compare.csv", rows)
        _compare_plot(tmp / "compare.png", rows, sims)
        write_json(tmp / "summary.json", {"designs": rows, "fidelity": fid.name,
                                          "operating_point": sims[0].summary()["operating_point"]})
    print(f"{'design':<16} {'mode':<14} {'f [Hz]':>8} {'m [kg]':>7} {'k [N/m]':>10} "
          f"{'growth [1/s]':>12} {'amp [m/s]':>9}")
    for r in rows:
        amp = f"{r['velocity_amplitude_m_s']:9.4f}" if r["squeal"] else f"{'-':>9}"
        g = r["growth_rate_1_s"]
        print(f"{r['design']:<16} {r['mode']:<14} {r['frequency_hz']:8.1f} {r['modal_mass_kg']:7.3f} "
              f"{r['modal_stiffness_n_m']:10.4g} {(g if g is not None else float('nan')):12.3g} {amp}")
    print(f"-> {args.out}")
    return 0



def _compare_plot(path: Path, rows: list[dict], sims: list[Simulation]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    for r, sim in zip(rows, sims):
        cyc = sim.limit_cycle.cycles
        axes[0].plot(cyc.start_s, cyc.amplitude_m_s, label=f"{r['design']} ({r['frequency_hz']:.0f} Hz)")
    vc = abs(sims[0].operating_point.crabbing_velocity_m_s)
    axes[0].axhline(vc, color="k", ls=":", lw=1, label="Vc")
    axes[0].set_ylim(0, 1.1 * max([vc] + [float(np.max(s.limit_cycle.cycles.amplitude_m_s, initial=0))
                                          for s in sims]))
    axes[0].set(xlabel="time [s]", ylabel="velocity amplitude [m/s]", title="growth to the limit cycle")
    axes[0].legend(fontsize=8)
    x = np.arange(len(rows))
    axes[1].bar(x, [r["frequency_hz"] for r in rows], color="tab:blue")
    axes[1].set(xticks=x, ylabel="frequency [Hz]", title="squeal mode frequency")
    axes[1].set_xticklabels([r["design"] for r in rows], rotation=30, ha="right")
    axes[2].bar(x, [r["modal_mass_kg"] for r in rows], color="tab:orange")
    axes[2].set(xticks=x, ylabel="modal mass at contact [kg]", title="contact modal mass")
    axes[2].set_xticklabels([r["design"] for r in rows], rotation=30, ha="right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# --------------------------------------------------------------------------------------
# calibration
# --------------------------------------------------------------------------------------
@dataclass
class Calibration:
    design: WheelDesign
    free: dict[str, float]
    frequency_hz: float
    modal_mass_kg: float
    residual: dict[str, float]
    evaluations: int


def calibrate(design: WheelDesign, free: Sequence[str], target_frequency_hz: float | None,
              target_modal_mass_kg: float | None, fidelity: str = "fast", mode: str = "auto",
              frequency_uncertainty: float = 0.01, modal_mass_uncertainty: float = 0.10,
              progress: Progress | None = None) -> Calibration:
    """Weighted least-squares fit of the free design parameters to measured modal data.

    Residuals are relative errors of the selected mode (default: the (3, 0) axial mode,
    computed with the ``fidelity`` preset) divided by the relative standard uncertainty
    of each measurement: ``(f / f_target - 1) / frequency_uncertainty`` and
    ``(m / m_target - 1) / modal_mass_uncertainty``. The defaults (1 % on a measured
    frequency, 10 % on a modal mass curve-fitted from a receptance) say that a modal
    test pins the frequency far better than the modal mass; equal values give the plain
    unweighted fit.
    """
    for name, u in (("frequency-uncertainty", frequency_uncertainty),
                    ("modal-mass-uncertainty", modal_mass_uncertainty)):
        if not (math.isfinite(u) and u > 0):
            raise UsageError(f"--{name} must be a positive relative uncertainty, got {u:g}")
    from scipy.optimize import least_squares

    from geometry.design import SECTIONS

    allowed = [k for keys in SECTIONS.values() for k in keys]
    for name in free:
        if name not in allowed:
            raise UsageError(f"--free {name}: not a design parameter; choose from {', '.join(allowed)}")
    if target_frequency_hz is None and target_modal_mass_kg is None:
        raise UsageError("give --target-frequency and/or --target-modal-mass")
    for name, v in (("target-frequency", target_frequency_hz), ("target-modal-mass", target_modal_mass_kg)):
        if v is not None and not (math.isfinite(v) and v > 0):
            raise UsageError(f"--{name} must be positive, got {v:g}")
    progress = progress or Progress(quiet=True)
    fid = fidelity_for(fidelity)
    x0 = np.array([getattr(design, k) for k in free], dtype=float)
    scale = np.where(x0 != 0, np.abs(x0), design.web_thickness)
    evaluations = 0

    def evaluate(x: np.ndarray):
        d = design.replace(**dict(zip(free, map(float, x))))
        ms = compute_modes(d, fid)
        m, _ = pick_mode(ms, mode)
        return d, m

    def residuals(x: np.ndarray) -> np.ndarray:
        nonlocal evaluations
        evaluations += 1
        try:
            d, m = evaluate(x)
        except DesignError:
            return np.full(2, 10.0)  # outside the valid design space
        r = [(m.frequency_hz / target_frequency_hz - 1) / frequency_uncertainty
             if target_frequency_hz else 0.0,
             (m.modal_mass / target_modal_mass_kg - 1) / modal_mass_uncertainty
             if target_modal_mass_kg else 0.0]
        progress.say("calibrate: " + ", ".join(f"{k} = {v:.6g}" for k, v in zip(free, x))
                     + f" -> f = {m.frequency_hz:.1f} Hz, m = {m.modal_mass:.3f} kg")
        return np.array(r)

    lower, upper = x0 - 0.9 * scale, x0 + 3.0 * scale
    # Re-meshing makes the objective piecewise smooth at the 1e-4 level: a finite
    # difference step of 1 % of the parameter keeps derivatives meaningful.
    sol = least_squares(residuals, x0, bounds=(lower, upper), x_scale=scale, diff_step=1e-2,
                        xtol=1e-4, ftol=1e-6)
    d, m = evaluate(sol.x)
    res = {}
    if target_frequency_hz:
        res["frequency_relative"] = m.frequency_hz / target_frequency_hz - 1
    if target_modal_mass_kg:
        res["modal_mass_relative"] = m.modal_mass / target_modal_mass_kg - 1
    res["weighted_rms"] = float(np.sqrt(np.mean(np.square(sol.fun[[bool(target_frequency_hz),
                                                                     bool(target_modal_mass_kg)]]))))
    return Calibration(d, dict(zip(free, map(float, sol.x))), m.frequency_hz, m.modal_mass, res,
                       evaluations)


def _calibrated_design_path(out: Path, name: str) -> Path:
    """Where calibrate writes its design: ``out`` itself (a .toml) or ``out/NAME.toml``.
    An existing file there is replaced only if calibrate wrote it."""
    path = out if out.suffix == ".toml" else out / f"{name}.toml"
    if path.exists():
        try:
            ours = CALIBRATED_MARK in load_design(path).description
        except DesignError:
            ours = False
        if not ours:
            raise UsageError(f"--out {path} exists and is not a design written by calibrate: "
                             "choose another path (nothing was written)")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=path.parent):
            pass  # the folder takes files: known before the fit runs
    except OSError as exc:
        raise UsageError(f"--out {out} cannot be written ({exc.strerror})") from None
    return path


#: Words in the description of every design calibrate writes (it may replace those).
CALIBRATED_MARK = " calibrated to f = "


def cmd_calibrate(args) -> int:
    design = _design_from_args(args)
    free = [f for part in args.free for f in part.split(",") if f]
    name = f"{design.name}_calibrated"
    design.replace(name=name)  # a valid name, checked before the work
    path = _calibrated_design_path(Path(args.out), name) if args.out else None
    progress = Progress(args.quiet)
    cal = calibrate(design, free, args.target_frequency, args.target_modal_mass,
                    fidelity=args.fidelity, mode=args.mode,
                    frequency_uncertainty=args.frequency_uncertainty,
                    modal_mass_uncertainty=args.modal_mass_uncertainty, progress=progress)
    cal_design = cal.design.replace(
        name=name,
        description=(f"{design.name} with {', '.join(free)}{CALIBRATED_MARK}"
                     f"{args.target_frequency} Hz, m = {args.target_modal_mass} kg "
                     f"({args.fidelity}); residual {cal.residual}"))
    for k, v in cal.free.items():
        print(f"{k} = {v:.6g} (was {getattr(design, k):.6g})")
    print(f"selected mode: f = {cal.frequency_hz:.1f} Hz, m = {cal.modal_mass_kg:.3f} kg; "
          f"residual " + ", ".join(f"{k} {v:+.2%}" for k, v in cal.residual.items()
                                   if k != "weighted_rms")
          + f", weighted rms {cal.residual['weighted_rms']:.3g} ({cal.evaluations} evaluations)")
    if path is not None:
        write_text_atomic(path, cal_design.to_toml())
        print(f"-> {path}")
    return 0


def cmd_converge(args) -> int:
    design = _design_from_args(args)
    progress = Progress(args.quiet)
    import convergence

    with result_folder(args.out, "converge") as tmp:
        rows = convergence.run_convergence(design, tmp, quick=args.quick, progress=progress.say)
    print(f"{len(rows)} rungs -> {args.out}/convergence.csv (and plots)")
    return 0


def cmd_cache(args) -> int:
    cache = StageCache(args.cache_dir)
    if args.action == "clear":
        n = cache.clear()
        print(f"removed {n} cache entries from {cache.root}")
    else:
        n, size = cache.info()
        print(f"{cache.root}: {n} entries, {size / 1e6:.1f} MB")
    return 0


# --------------------------------------------------------------------------------------
# command line
# --------------------------------------------------------------------------------------
class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit status 2, no usage dump)."""

    def error(self, message: str):  # type: ignore[override]
        self.exit(2, f"error: {message} (see {self.prog} --help)\n")


def _add_common(p: argparse.ArgumentParser, out_required: bool = True, out_default=None) -> None:
    p.add_argument("--design", type=Path, help="wheel design TOML (default designs/table1.toml)")
    if out_required:
        p.add_argument("--out", type=Path, required=True, help="output folder")
    else:
        p.add_argument("--out", type=Path, default=out_default, help="output folder")
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    p.add_argument("--no-cache", action="store_true", help="recompute mesh and modes")
    p.add_argument("--cache-dir", type=Path,
                   help="stage cache folder (default $WHEEL_SQUEAL_CACHE, else ~/.cache/wheel-squeal)")
    _add_budget(p)


def _add_budget(p: argparse.ArgumentParser) -> None:
    p.add_argument("--max-dofs", type=float,
                   help="refuse modal solves larger than this (default 2e6; env WHEEL_SQUEAL_MAX_DOFS)")
    p.add_argument("--max-seconds", type=float,
                   help="refuse work estimated to take longer (default 1800; env WHEEL_SQUEAL_MAX_SECONDS)")


def _add_fe(p: argparse.ArgumentParser, mode: bool = True) -> None:
    p.add_argument("--fidelity", default=DEFAULT_FIDELITY, choices=list(FIDELITIES),
                   help="speed/accuracy preset (default %(default)s; see README)")
    p.add_argument("--solver", choices=list(SOLVERS),
                   help="force the FE solver: axisym, 3d (3-D P2, cyclic symmetry) or 3d-tet "
                        "(3-D P2 on a gmsh tetrahedral mesh, slow)")
    p.add_argument("--fmax", type=float, default=5000.0, help="modes up to this frequency [Hz]")
    if mode:
        p.add_argument("--mode", default="auto",
                       help="squeal mode: auto (the (3,0) axial mode), INDEX, n=3[,c=0] or f=HZ")


def _add_operating(p: argparse.ArgumentParser, speed: bool = True) -> None:
    p.add_argument("--rpm", type=float, help="wheel speed [rev/min] (default 800)")
    if speed:
        p.add_argument("--speed", type=float, help="rolling speed at the contact [m/s]")
    p.add_argument("--crab-velocity", type=float, help="crabbing velocity Vc [m/s] (default 0.39)")
    p.add_argument("--angle-of-attack", type=float, help="angle of attack [rad] (Vc = theta V0)")
    p.add_argument("--duration", type=float,
                   help="simulated time [s] (default: 0.6 s, extended while still growing)")
    p.add_argument("--c22", type=lambda t: t if t == "kalker" else float(t),
                   help="creep coefficient C22: a number or 'kalker' (default: the design's)")


def _add_modal(p: argparse.ArgumentParser) -> None:
    p.add_argument("--mass", type=float, help="modal mass at the contact [kg] (with --stiffness, --damping: no FE)")
    p.add_argument("--stiffness", type=float, help="modal stiffness [N/m]")
    p.add_argument("--damping", type=float, help="modal damping [N s/m]")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="pipeline.py", description=__doc__.split("\n\n")[0],
                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("run", help="design -> modes -> squeal limit cycle -> report (default: Table 1)")
    _add_common(p, out_required=False)
    _add_fe(p)
    _add_operating(p, speed=False)
    p.add_argument("--render", choices=["selected", "all", "none"], default="selected",
                   help="mode-shape PNGs to draw (default: the squeal mode)")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("mesh", help="mesh a design (2-D profile or 3-D revolved)")
    _add_common(p)
    p.add_argument("--size", type=float, help="characteristic element length [m]")
    p.add_argument("--elements-through-web", type=int, help="elements across the web thickness")
    p.add_argument("--order", type=int, choices=[1, 2], default=2, help="geometry order")
    p.add_argument("--dim", type=int, choices=[2, 3], default=3, help="2-D profile or 3-D solid")
    p.set_defaults(func=cmd_mesh)

    p = sub.add_parser("modes", help="eigenmodes, labels and contact modal parameters")
    _add_common(p)
    _add_fe(p)
    p.set_defaults(func=cmd_modes)

    p = sub.add_parser("simulate", help="time-domain squeal model at one operating point")
    _add_common(p)
    _add_fe(p)
    _add_modal(p)
    _add_operating(p)
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser("sweep", help="limit cycles over crabbing velocity x speed (Fig. 5)")
    _add_common(p)
    _add_fe(p)
    _add_modal(p)
    p.add_argument("--crab-velocity", default="0:0.5:26", help="START:STOP:N or list [m/s]")
    p.add_argument("--rpm", default="400,600,800", help="list of speeds [rev/min]")
    p.add_argument("--duration", type=float, default=1.5, help="simulated time per case [s]")
    p.add_argument("--c22", type=lambda t: t if t == "kalker" else float(t), help="C22 or 'kalker'")
    p.set_defaults(func=cmd_sweep)

    p = sub.add_parser("compare", help="several designs at the same operating point")
    p.add_argument("designs", nargs="+", type=Path, help="design TOML files")
    p.add_argument("--out", type=Path, default=Path("results") / "compare", help="output folder")
    p.add_argument("--quiet", action="store_true")
    p.add_argument("--no-cache", action="store_true")
    p.add_argument("--cache-dir", type=Path)
    _add_budget(p)
    _add_fe(p)
    _add_operating(p, speed=False)
    p.set_defaults(func=cmd_compare)

    p = sub.add_parser("render", help="mode-shape PNGs (and GIFs), off-screen")
    _add_common(p)
    _add_fe(p, mode=False)
    p.add_argument("--modes", help="comma list of mode indices (default: all)")
    p.add_argument("--gif", action="store_true", help="also an animated GIF per mode")
    p.set_defaults(func=cmd_render)

    p = sub.add_parser("calibrate", help="fit design parameters to measured modal data")
    p.add_argument("--design", type=Path)
    p.add_argument("--free", action="append", required=True,
                   help="design parameter(s) to fit, e.g. rim_depth (repeat or comma list)")
    p.add_argument("--target-frequency", type=float, help="measured frequency [Hz]")
    p.add_argument("--target-modal-mass", type=float, help="measured contact modal mass [kg]")
    p.add_argument("--frequency-uncertainty", type=float, default=0.01,
                   help="relative standard uncertainty of the measured frequency (default 0.01)")
    p.add_argument("--modal-mass-uncertainty", type=float, default=0.10,
                   help="relative standard uncertainty of the measured modal mass (default 0.10)")
    p.add_argument("--fidelity", default="fast", choices=list(FIDELITIES))
    p.add_argument("--mode", default="auto")
    p.add_argument("--out", type=Path, help="folder or .toml path for the calibrated design")
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=cmd_calibrate)

    p = sub.add_parser("converge", help="speed/accuracy study: mesh ladders, solvers, integrator")
    p.add_argument("--design", type=Path, help="wheel design TOML (default designs/table1.toml)")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    p.add_argument("--quick", action="store_true", help="only the cheapest rungs")
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=cmd_converge)

    p = sub.add_parser("cache", help="inspect or clear the stage cache")
    p.add_argument("action", choices=["clear", "info"])
    p.add_argument("--cache-dir", type=Path)
    p.set_defaults(func=cmd_cache)
    return parser


def _one_line_warning(message, category, filename, lineno, file=None, line=None) -> None:
    print(f"warning: {str(message).splitlines()[0]}", file=sys.stderr)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 1 computation failed,
    2 bad request)."""
    import warnings

    from fem.eigen import EigenError
    from geometry.mesh import MeshError

    args = build_parser().parse_args(argv)
    if not os.environ.get("DISPLAY"):
        # Without an X server VTK tries X first and warns before falling back to EGL;
        # go straight to EGL (off-screen) so the terminal stays clean.
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    with warnings.catch_warnings():
        warnings.showwarning = _one_line_warning
        try:
            return args.func(args)
        except (UsageError, DesignError, ValueError, LookupError) as exc:
            # a bad request, or input the library rejected (e.g. a zero rolling speed)
            print(f"error: {exc}", file=sys.stderr)
            return 2
        except (MeshError, EigenError) as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 1
        except RuntimeError as exc:
            from reduced import IntegrationError

            if isinstance(exc, IntegrationError):
                print(f"error: {exc}", file=sys.stderr)
                return 1
            raise
        except KeyboardInterrupt:
            print("interrupted", file=sys.stderr)
            return 130


if __name__ == "__main__":
    sys.exit(main())
