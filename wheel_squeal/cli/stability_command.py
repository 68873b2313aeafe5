"""The ``stability`` command: linear stability of every mode: which squeals, what stops it."""

from __future__ import annotations

import argparse

import numpy as np

from .. import api
from ..envelope import envelope, mitigation_summary
from ..mode_stability import eigenvalue_list, excitable, stability_table
from ..outputs import write_json
from ..plan import stability_request_plan
from ..present.figures import write_envelope_plot
from ..present.results import write_remedy_toml
from ..present.summary import contact_summary, operating_point_summary
from ..present.tables import write_envelope_csv
from ..present.text import eigenvalues_text, mitigation_text, stability_text, verdict_lines
from ..presets import DEFAULT_ENVELOPE_CRAB_VELOCITIES, DEFAULT_SPEEDS_RPM
from ..runtime.request_errors import RequestError
from ..runtime.result_folders import result_folder
from .arguments import grid_axis
from .common import analysis_of, context_of, design_of, modes_of, operating_point_of, out_of
from .options import add_axis, add_common, add_fe, add_modal_model, add_operating, add_remedy, add_rotation

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("stability", help="linear stability of every mode: which squeals, what stops it")
    add_common(p)
    add_fe(p)
    add_modal_model(p)
    add_operating(p, duration=False)
    add_rotation(p)
    add_remedy(p)
    p.add_argument(
        "--envelope",
        action="store_true",
        help="also the map over the envelope (stability.csv, stability.png) and the mitigation",
    )
    vcs = DEFAULT_ENVELOPE_CRAB_VELOCITIES
    add_axis(p, "--envelope-crab-velocity", vcs, "the envelope's Vc [m/s]", span=True, filled=False)
    add_axis(p, "--envelope-rpm", DEFAULT_SPEEDS_RPM, "the envelope's wheel speeds [rev/min]", filled=False)
    p.add_argument(
        "--no-bounds",
        action="store_true",
        help="growth rates only: skip each mode's critical damping and friction slope "
        "(some 15-30 eigen-solves per mode)",
    )


def run(args: argparse.Namespace) -> int:
    design = design_of(args)
    axes = _envelope_axes(args)
    out = out_of(args, design.name)
    ctx = context_of(args)
    with result_folder(out, "stability") as tmp:
        op = operating_point_of(args, design)
        contact = api.contact_law(design, args.c22, args.friction_law)
        ms = modes_of(args, design)
        n = len(excitable(ms, contact))
        bounds = None if args.no_bounds else "all"
        sizes = None if axes is None else (len(axes[0]), len(axes[1]))
        plan = stability_request_plan(design, ms, contact, args.rotation, bounds is not None, sizes)
        seconds = plan.check(ctx.budget, "the stability", "ask for less")
        with ctx.progress.stage(
            f"linear stability of {n} modes" + (f" (about {seconds:.2g} s)" if seconds > 2 else "")
        ):
            table = stability_table(design, ms, contact, op, args.rotation, bounds=bounds)
        with ctx.progress.stage("verdict"):
            a = analysis_of(args, design, stop_after="stability", modes=ms, table=table)
        rows = [r.to_dict(design) for r in table.rows]
        summary = {
            "verdict": a.verdict.to_dict(),
            "design": design.name,
            "fidelity": ctx.fidelity.name,
            "solver": ms.solver,
            "rotation": bool(args.rotation),
            "operating_point": operating_point_summary(op, design),
            "contact": contact_summary(design, contact, op),
            "friction_damping_ns_m": table.result.friction_damping_ns_m,
            "modes": rows,
            "winner": rows[table.fastest],
            "eigenvalues": eigenvalue_list(table),
        }
        if axes is not None:
            vcs, rpms = axes
            with ctx.progress.stage(f"envelope {len(vcs)} x {len(rpms)} points"):
                env = envelope(design, ms, contact, vcs, rpms, args.rotation)
            with ctx.progress.stage("mitigation (rotation off and on)"):
                summary["mitigation"] = mitigation_summary(design, ms, contact, vcs, rpms)
            write_envelope_csv(tmp / "stability.csv", env)
            write_envelope_plot(tmp / "stability.png", env, summary["mitigation"])
        write_remedy_toml(tmp, a)
        write_json(tmp / "summary.json", summary)
    print(stability_text(table.rows, table.fastest, bounds is not None))
    print(eigenvalues_text(summary["eigenvalues"], summary["contact"]))
    if axes is not None:
        print(mitigation_text(summary["mitigation"]))
    print("\n".join(verdict_lines(a.verdict)))
    print(f"-> {out}")
    return 0


def _envelope_axes(args: argparse.Namespace) -> tuple[np.ndarray, list[float]] | None:
    """The envelope's axes, or None without --envelope (whose axes flags then refuse)."""
    given = [
        f
        for f, v in (
            ("--envelope-crab-velocity", args.envelope_crab_velocity),
            ("--envelope-rpm", args.envelope_rpm),
        )
        if v is not None
    ]
    if not args.envelope:
        if given:
            raise RequestError(f"{given[0]} shapes the envelope: give it with --envelope")
        return None
    vcs = args.envelope_crab_velocity or grid_axis(
        ":".join(f"{x:g}" for x in DEFAULT_ENVELOPE_CRAB_VELOCITIES)
    )
    rpms = args.envelope_rpm or list(DEFAULT_SPEEDS_RPM)
    if min(rpms) <= 0:
        raise RequestError("--envelope-rpm: wheel speeds must be positive")
    return np.asarray(vcs, float), rpms
