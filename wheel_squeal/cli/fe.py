"""Commands about the FE model: mesh, modes, render."""

from __future__ import annotations

import argparse
import time

from .. import api
from ..errors import RequestError
from ..folders import result_folder
from ..outputs import write_json
from ..plan import MESH_BYTES_PER_ELEMENT, MESH_SECONDS_PER_ELEMENT
from ..present.summary import modes_summary
from ..present.text import modes_table
from ..progress import Progress
from .common import analysis_of, budget_of, context_of, design_of, modes_of, out_of, write_files
from .stops import uninterrupted

__all__ = ["cmd_mesh", "cmd_modes", "cmd_render"]


def cmd_mesh(args: argparse.Namespace) -> int:
    from geometry import estimate_element_count, profile_area, revolved_volume
    from geometry.mesh import mesh_size

    design = design_of(args)
    if args.elements_through_web is not None and args.elements_through_web < 1:
        raise RequestError("--elements-through-web must be at least 1")
    if args.size is not None and args.elements_through_web is not None:
        raise RequestError("give --size or --elements-through-web, not both")
    progress = Progress(args.quiet)
    out = out_of(args, design.name)
    with result_folder(out, "mesh") as tmp:
        h = mesh_size(design.wheel, args.size, args.elements_through_web, args.dim)
        n = estimate_element_count(design.wheel, h, args.dim)
        nodes_per_element = {(2, 1): 0.6, (2, 2): 2.2, (3, 1): 0.2, (3, 2): 1.9}[(args.dim, args.order)]
        budget_of(args).check_solve(
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
                "exact_area_m2": profile_area(design.wheel),
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
            "exact_volume_m3": revolved_volume(design.wheel),
            "seconds": seconds,
        }
        mesh.write(tmp / "mesh.msh")
        mesh.write(tmp / "mesh.vtu")
        write_json(tmp / "summary.json", summary)
    rel = summary["mesh_volume_m3"] / summary["exact_volume_m3"] - 1
    print(
        f"{design.name}: {summary['nodes']} nodes, {summary['elements']} elements, "
        f"volume {summary['mesh_volume_m3']:.6e} m^3 ({rel:+.3%} vs exact), "
        f"{seconds:.2f} s -> {out}"
    )
    return 0


def cmd_modes(args: argparse.Namespace) -> int:
    design = design_of(args)
    out = out_of(args, design.name)
    ctx = context_of(args)
    with result_folder(out, "modes") as tmp:
        ms = modes_of(args, design)
        if not ms.modes:
            raise RequestError(f"no modes below {ctx.fmax_hz:g} Hz for {design.name}")
        a = analysis_of(args, design, stop_after="stability", remedy=False, modes=ms)
        chosen = a.verdict.outcome or a.verdict.named or a.verdict.pick
        selected, why = (chosen.mode, a.verdict.reason) if chosen is not None else (None, a.verdict.reason)
        with uninterrupted():
            views = api.mode_views(
                design, ctx.fidelity, ctx.fmax_hz, ms, [], ctx.cache, ctx.budget.max_file_bytes
            )
        write_files(tmp, views)
        write_json(tmp / "summary.json", modes_summary(design, ms, selected, ctx.fidelity, why))
    print(modes_table(ms.modes, design, selected))
    if selected is not None:
        print(
            f"selected: mode {selected.index} ({why}), {selected.frequency_hz:.1f} Hz, "
            f"m = {selected.modal_mass:.3f} kg"
        )
    print(f"{ms.solver}, {ms.dofs} DOFs, {ctx.fidelity.name} -> {out}")
    return 0


def cmd_render(args: argparse.Namespace) -> int:
    from fem.render import render_modes

    design = design_of(args)
    out = out_of(args, design.name)
    progress = context_of(args).progress
    with result_folder(out, "render") as tmp:
        ms = modes_of(args, design)
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
            with uninterrupted():
                paths = render_modes(ms, tmp, indices=indices, gif=args.gif)
    print(f"{len(paths)} files -> {out}")
    return 0
