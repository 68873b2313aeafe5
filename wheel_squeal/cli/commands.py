"""The commands: each reads its arguments, calls the stages (:mod:`wheel_squeal.api`),
writes its result folder (:mod:`wheel_squeal.outputs`) and prints a short report."""

from __future__ import annotations

import contextlib
import time
from pathlib import Path

from geometry import DesignError, WheelDesign

from .. import api, writers
from ..budget import Budget
from ..cache import StageCache
from ..errors import RequestError
from ..outputs import result_folder, write_csv, write_json, write_text_atomic
from ..presets import fidelity_for, rpm_to_speed
from ..progress import Progress

__all__ = ["COMMANDS"]


def _design(args) -> WheelDesign:
    return api.load_design(args.design)


def _cache(args) -> StageCache:
    return StageCache(args.cache_dir, enabled=not getattr(args, "no_cache", False))


def _budget(args) -> Budget:
    return Budget.from_environment(getattr(args, "max_dofs", None), getattr(args, "max_seconds", None))


def _write_files(directory: Path, files: dict[str, bytes]) -> None:
    for name, data in files.items():
        (directory / name).write_bytes(data)


def _squeal_mode(args, design: WheelDesign, progress: Progress, cache: StageCache):
    """(dof, (modeset, mode, modes summary) or None): from ``--mass/--stiffness/
    --damping`` when given (no FE at all), else the design's FE modes."""
    explicit = (args.mass, args.stiffness, args.damping) if hasattr(args, "mass") else (None,) * 3
    if any(v is not None for v in explicit):
        if any(v is None for v in explicit):
            raise RequestError("--mass, --stiffness and --damping go together: give all three")
        progress.say("modal parameters given: no mesh, no FE")
        return api.explicit_dof(*explicit), None
    fid = fidelity_for(args.fidelity, args.solver)
    ms = api.compute_modes(
        design, fid, fmax_hz=args.fmax, cache=cache, progress=progress, budget=_budget(args)
    )
    mode, why = api.pick_mode(ms, args.mode)
    progress.say(f"squeal mode: {mode.index} ({why}), {mode.frequency_hz:.1f} Hz")
    return api.modal_dof(mode, design), (ms, mode, writers.modes_summary(design, ms, mode, fid, why))


def _operating_point(args, design: WheelDesign):
    return api.operating_point(
        design,
        rpm=args.rpm,
        speed=getattr(args, "speed", None),
        crab_velocity=args.crab_velocity,
        angle_of_attack=args.angle_of_attack,
    )


def cmd_run(args) -> int:
    design = _design(args)
    out = args.out or Path("results") / design.name
    progress = Progress(args.quiet)
    t0 = time.perf_counter()
    with result_folder(out, "run") as tmp, contextlib.ExitStack() as stack:
        cache = _cache(args)
        op = _operating_point(args, design)
        contact = api.contact_law(design, args.c22)
        dof, (ms, mode, msum) = _squeal_mode(args, design, progress, cache)
        plots = stack.enter_context(writers.plot_workers())  # after numba's import: children need it
        with progress.stage("squeal model"):
            sim = api.simulate(dof, contact, op, args.duration)
        with progress.stage("report"):
            writers.write_simulation_files(tmp, sim, plots)
        indices = {"selected": [mode.index], "none": [], "all": list(range(len(ms.modes)))}[args.render]
        with progress.stage("mode views"):
            fid = fidelity_for(args.fidelity, args.solver)
            _write_files(tmp, api.mode_views(design, fid, args.fmax, ms, indices, cache))
        with progress.stage("plots"):
            plots.wait()
        write_json(
            tmp / "summary.json",
            {
                **msum,
                **sim.summary(),
                "modal_parameters": writers.dof_summary(dof),
                "timings_s": {**progress.timings, "total": time.perf_counter() - t0},
                "cache": {"hits": cache.hits, "misses": cache.misses},
            },
        )
    print(
        f"{design.name}: squeal mode {mode.index}: {mode.label()} "
        f"({msum['selected_mode']['why']}), {mode.frequency_hz:.1f} Hz"
    )
    print(writers.squeal_report(sim, dof))
    print(
        f"files: {out}/ (summary.json, timeseries.csv, *.png, modes.vtu)  [{time.perf_counter() - t0:.1f} s]"
    )
    return 0


#: gmsh per element: about 7e-5 s and 3 kB (measured on these wheels up to 2e5 elements).
MESH_SECONDS_PER_ELEMENT = 7e-5
MESH_BYTES_PER_ELEMENT = 3e3


def cmd_mesh(args) -> int:
    from geometry import estimate_element_count, profile_area, revolved_volume
    from geometry.mesh import mesh_size

    design = _design(args)
    if args.elements_through_web is not None and args.elements_through_web < 1:
        raise RequestError("--elements-through-web must be at least 1")
    if args.size is not None and args.elements_through_web is not None:
        raise RequestError("give --size or --elements-through-web, not both")
    progress = Progress(args.quiet)
    with result_folder(args.out, "mesh") as tmp:
        h = mesh_size(design, args.size, args.elements_through_web, args.dim)
        n = estimate_element_count(design, h, args.dim)
        nodes_per_element = {(2, 1): 0.6, (2, 2): 2.2, (3, 1): 0.2, (3, 2): 1.9}[(args.dim, args.order)]
        _budget(args).check_solve(
            f"meshing {design.name} ({args.dim}-D, size {h * 1e3:.3g} mm)",
            3 * nodes_per_element * n,
            MESH_BYTES_PER_ELEMENT * n,
            MESH_SECONDS_PER_ELEMENT * n,
            "use a larger --size or fewer --elements-through-web",
        )
        t = time.perf_counter()
        with progress.stage(f"mesh ({args.dim}-D, order {args.order})"):
            mesh = api.build_mesh(
                design,
                dim=args.dim,
                order=args.order,
                size=args.size,
                elements_through_web=args.elements_through_web,
            )
        seconds = time.perf_counter() - t
        if args.dim == 2:
            extra = {
                "mesh_area_m2": mesh.area(),
                "exact_area_m2": profile_area(design),
                "mesh_volume_m3": mesh.revolved_volume(),
            }
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
    print(
        f"{design.name}: {summary['nodes']} nodes, {summary['elements']} elements, "
        f"volume {summary['mesh_volume_m3']:.6e} m^3 ({rel:+.3%} vs exact), "
        f"{seconds:.2f} s -> {args.out}"
    )
    return 0


def cmd_modes(args) -> int:
    design = _design(args)
    fid = fidelity_for(args.fidelity, args.solver)
    progress = Progress(args.quiet)
    with result_folder(args.out, "modes") as tmp:
        cache = _cache(args)
        ms = api.compute_modes(
            design, fid, fmax_hz=args.fmax, cache=cache, progress=progress, budget=_budget(args)
        )
        if not ms.modes:
            raise RequestError(f"no modes below {args.fmax:g} Hz for {design.name}")
        selected, why = api.pick_mode(ms, args.mode)
        _write_files(tmp, api.mode_views(design, fid, args.fmax, ms, [], cache))
        write_json(tmp / "summary.json", writers.modes_summary(design, ms, selected, fid))
    print(writers.modes_table(ms.modes, design.modal_damping_ratio, selected))
    print(
        f"selected: mode {selected.index} ({why}), {selected.frequency_hz:.1f} Hz, "
        f"m = {selected.modal_mass:.3f} kg"
    )
    print(f"{ms.solver}, {ms.dofs} DOFs, {fid.name} -> {args.out}")
    return 0


def cmd_simulate(args) -> int:
    progress = Progress(args.quiet)
    with result_folder(args.out, "simulate") as tmp, contextlib.ExitStack() as stack:
        design = _design(args)
        dof, modes_info = _squeal_mode(args, design, progress, _cache(args))
        plots = stack.enter_context(writers.plot_workers())  # after numba's import: children need it
        contact = api.contact_law(design, args.c22)
        op = _operating_point(args, design)
        with progress.stage("squeal model"):
            sim = api.simulate(dof, contact, op, args.duration)
        summary = {
            "design": design.name,
            "modal_parameters": writers.dof_summary(dof),
            **sim.summary(),
            "timings_s": progress.timings,
        }
        if modes_info is not None:
            summary["selected_mode"] = modes_info[2]["selected_mode"]
        writers.write_simulation_files(tmp, sim, plots)
        write_json(tmp / "summary.json", summary)
        with progress.stage("plots"):
            plots.wait()
    print(writers.squeal_report(sim, dof))
    print(f"-> {args.out}")
    return 0


def cmd_sweep(args) -> int:
    from reduced import write_sweep_csv, write_sweep_plot

    progress = Progress(args.quiet)
    with result_folder(args.out, "sweep") as tmp:
        design = _design(args)
        dof, _ = _squeal_mode(args, design, progress, _cache(args))
        contact = api.contact_law(design, args.c22)
        speeds = [rpm_to_speed(r, design.rolling_radius) for r in args.rpm]
        vcs = args.crab_velocity
        with progress.stage(f"sweep {len(vcs)} x {len(speeds)} cases, {args.duration:g} s each"):
            result = api.sweep(
                dof, contact, vcs, speeds, args.duration, budget=_budget(args), progress=progress
            )
        write_sweep_csv(result, tmp, wheel_radius_m=design.rolling_radius)
        write_sweep_plot(result, tmp, wheel_radius_m=design.rolling_radius)
        write_json(
            tmp / "summary.json",
            {
                "design": design.name,
                "modal_parameters": writers.dof_summary(dof),
                "duration_s": args.duration,
                "timings_s": progress.timings,
            },
        )
    print(writers.sweep_table(vcs, args.rpm, result))
    print(f"velocity amplitude [m/s] ('-' = no squeal) -> {args.out}")
    return 0


def cmd_compare(args) -> int:
    progress = Progress(args.quiet)
    with result_folder(args.out, "compare") as tmp:
        cache, budget = _cache(args), _budget(args)
        designs = []
        for path in args.designs:
            try:
                designs.append(api.load_design(path))
            except DesignError as exc:
                raise RequestError(f"design {path}: {exc}") from None
        if len({d.name for d in designs}) != len(designs):
            raise RequestError("two designs have the same name; give each a distinct name")
        fid = fidelity_for(args.fidelity, args.solver)
        rows, sims = [], []
        for d in designs:
            progress.say(f"design {d.name}")
            try:
                ms = api.compute_modes(
                    d, fid, fmax_hz=args.fmax, cache=cache, progress=progress, budget=budget
                )
                mode, _ = api.pick_mode(ms, args.mode)
                dof = api.modal_dof(mode, d)
                sim = api.simulate(
                    dof, api.contact_law(d, args.c22), _operating_point(args, d), args.duration
                )
            except (RequestError, DesignError) as exc:
                raise RequestError(f"design {d.name}: {exc}") from None
            rows.append(writers.compare_row(d, mode, dof, sim))
            sims.append(sim)
        write_csv(tmp / "compare.csv", rows)
        writers.write_compare_plot(tmp / "compare.png", rows, sims)
        write_json(
            tmp / "summary.json",
            {"designs": rows, "fidelity": fid.name, "operating_point": sims[0].summary()["operating_point"]},
        )
    print(writers.compare_table(rows))
    print(f"-> {args.out}")
    return 0


def cmd_render(args) -> int:
    from fem.render import render_modes

    design = _design(args)
    progress = Progress(args.quiet)
    with result_folder(args.out, "render") as tmp:
        ms = api.compute_modes(
            design,
            fidelity_for(args.fidelity, args.solver),
            fmax_hz=args.fmax,
            cache=_cache(args),
            progress=progress,
            budget=_budget(args),
        )
        indices = None
        if args.modes:
            try:
                indices = [int(i) for i in args.modes.split(",")]
            except ValueError:
                raise RequestError(f"--modes takes indices like 0,3,4, got {args.modes!r}") from None
            bad = [i for i in indices if not 0 <= i < len(ms.modes)]
            if bad:
                raise RequestError(f"mode index {bad[0]} out of range 0..{len(ms.modes) - 1}")
        with progress.stage("render"):
            paths = render_modes(ms, tmp, indices=indices, gif=args.gif)
    print(f"{len(paths)} files -> {args.out}")
    return 0


def cmd_calibrate(args) -> int:
    from ..calibration import CALIBRATED_MARK, calibrate, calibrated_design_path

    design = _design(args)
    free = [f for part in args.free for f in part.split(",") if f]
    name = f"{design.name}_calibrated"
    design.replace(name=name)  # a valid name, checked before the work
    path = calibrated_design_path(Path(args.out), name) if args.out else None
    cal = calibrate(
        design,
        free,
        args.target_frequency,
        args.target_modal_mass,
        fidelity=args.fidelity,
        mode=args.mode,
        frequency_uncertainty=args.frequency_uncertainty,
        modal_mass_uncertainty=args.modal_mass_uncertainty,
        progress=Progress(args.quiet),
    )
    cal_design = cal.design.replace(
        name=name,
        description=(
            f"{design.name} with {', '.join(free)}{CALIBRATED_MARK}"
            f"{args.target_frequency} Hz, m = {args.target_modal_mass} kg "
            f"({args.fidelity}); residual {cal.residual}"
        ),
    )
    for k, v in cal.free.items():
        print(f"{k} = {v:.6g} (was {getattr(design, k):.6g})")
    print(
        f"selected mode: f = {cal.frequency_hz:.1f} Hz, m = {cal.modal_mass_kg:.3f} kg; residual "
        + ", ".join(f"{k} {v:+.2%}" for k, v in cal.residual.items() if k != "weighted_rms")
        + f", weighted rms {cal.residual['weighted_rms']:.3g} ({cal.evaluations} evaluations)"
    )
    if path is not None:
        write_text_atomic(path, cal_design.to_toml())
        print(f"-> {path}")
    return 0


def cmd_converge(args) -> int:
    from ..convergence import run_convergence

    design = _design(args)
    with result_folder(args.out, "converge") as tmp:
        rows = run_convergence(design, tmp, quick=args.quick, progress=Progress(args.quiet).say)
    print(f"{len(rows)} rungs -> {args.out}/convergence.csv (and plots)")
    return 0


def cmd_cache(args) -> int:
    cache = StageCache(args.cache_dir)
    if args.action == "clear":
        print(f"removed {cache.clear()} cache entries from {cache.root}")
    else:
        n, size = cache.info()
        print(f"{cache.root}: {n} entries, {size / 1e6:.1f} MB")
    return 0


COMMANDS = {
    "run": cmd_run,
    "mesh": cmd_mesh,
    "modes": cmd_modes,
    "simulate": cmd_simulate,
    "sweep": cmd_sweep,
    "compare": cmd_compare,
    "render": cmd_render,
    "calibrate": cmd_calibrate,
    "converge": cmd_converge,
    "cache": cmd_cache,
}
