"""The ``mesh`` command: mesh a design (2-D profile or 3-D revolved)."""

from __future__ import annotations

import argparse
import time

from .. import api
from ..outputs import write_json
from ..plan import MESH_BYTES_PER_ELEMENT, MESH_SECONDS_PER_ELEMENT
from ..runtime.progress import Progress
from ..runtime.request_errors import RequestError
from ..runtime.result_folders import result_folder
from .arguments import positive
from .common import budget_of, design_of, out_of
from .options import add_common

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("mesh", help="mesh a design (2-D profile or 3-D revolved)")
    add_common(p, cache=False)
    p.add_argument("--size", type=positive, help="characteristic element length [m]")
    p.add_argument("--elements-through-web", type=int, help="elements across the web thickness")
    p.add_argument("--order", type=int, choices=[1, 2], default=2, help="geometry order")
    p.add_argument("--dim", type=int, choices=[2, 3], default=3, help="2-D profile or 3-D solid")


def run(args: argparse.Namespace) -> int:
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
