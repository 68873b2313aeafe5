"""The command line's arguments: every command, flag, default and help text.

Flag values are checked here (a flag's error names the flag: ``argument --rpm: must be
positive``); what needs the design or the modes is checked by the stages. Importing this
module imports numpy at most (no SciPy, matplotlib, numba, gmsh or scikit-fem), so
``--help`` is quick.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import NoReturn

from ..presets import (
    DEFAULT_ENVELOPE_CRAB_VELOCITIES,
    DEFAULT_SPEEDS_RPM,
    DEFAULT_SWEEP_CRAB_VELOCITIES,
    FIDELITIES,
    MAX_MULTIMODE,
)
from .arguments import c22_value, count, finite, grid_axis, non_negative, positive
from .options import (
    add_axis,
    add_budget,
    add_cache,
    add_common,
    add_contact,
    add_fe,
    add_friction_law,
    add_microphone,
    add_modal,
    add_modal_model,
    add_operating,
    add_out,
    add_record,
    add_remedy,
    add_rotation,
)

__all__ = ["CommandParser", "build_parser"]


class CommandParser(argparse.ArgumentParser):
    """argparse with one-line errors (exit status 2, no usage dump); ``subcommands``
    maps each command to its own parser (for errors that name the command)."""

    subcommands: dict[str, CommandParser]

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"error: {message} (see {self.prog} --help)\n")


#: The commands that draw figures: they run with a plot process started before them
#: (:mod:`wheel_squeal.plotting`) and take it as their second argument.
DRAWING_COMMANDS = frozenset({"run", "simulate"})


def build_parser(prog: str = "wheel-squeal") -> CommandParser:
    """The parser of every command; ``args.command`` names the one chosen."""
    parser = CommandParser(
        prog=prog,
        description="Railway test-rig wheel: design -> mesh -> modes -> "
        "contact modal parameters -> curve-squeal limit cycle.",
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=CommandParser)
    parser.subcommands = sub.choices

    for add in (
        _add_run_command,
        _add_mesh_command,
        _add_modes_command,
        _add_simulate_command,
        _add_sweep_command,
        _add_compare_command,
        _add_stability_command,
        _add_sound_command,
        _add_track_command,
        _add_curve_command,
        _add_line_command,
        _add_study_command,
        _add_render_command,
        _add_calibrate_command,
        _add_converge_command,
        _add_designs_command,
        _add_cache_command,
    ):
        add(sub)
    return parser


def _add_run_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("run", help="design -> modes -> squeal limit cycle -> report (default: Table 1)")
    add_common(p)
    add_fe(p)
    add_modal_model(p)
    add_operating(p)
    p.add_argument(
        "--render",
        choices=["selected", "all", "none"],
        default="selected",
        help="mode-shape PNGs to draw (default: the squeal mode)",
    )
    add_rotation(p)
    add_remedy(p)
    add_microphone(p)
    add_record(p)
    p.add_argument(
        "--multimode",
        type=count,
        nargs="?",
        const=MAX_MULTIMODE,
        metavar="K",
        help="the verdict is the model's own outcome (the design's named mode set aside; --mode still "
        "overrides): the modes of every growing eigenvalue integrated together, at most K of them "
        f"(default {MAX_MULTIMODE})",
    )


def _add_mesh_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("mesh", help="mesh a design (2-D profile or 3-D revolved)")
    add_common(p, cache=False)
    p.add_argument("--size", type=positive, help="characteristic element length [m]")
    p.add_argument("--elements-through-web", type=int, help="elements across the web thickness")
    p.add_argument("--order", type=int, choices=[1, 2], default=2, help="geometry order")
    p.add_argument("--dim", type=int, choices=[2, 3], default=3, help="2-D profile or 3-D solid")


def _add_modes_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("modes", help="eigenmodes, labels and contact modal parameters")
    add_common(p)
    add_fe(p)


def _add_simulate_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("simulate", help="time-domain squeal model at one operating point")
    add_common(p)
    add_fe(p)
    add_modal(p)
    add_modal_model(p)
    add_operating(p)
    add_rotation(p)
    p.add_argument(
        "--nodal-diameters", type=int, default=0, help="the --mass mode's nodal diameters (for --rotation)"
    )
    add_record(p)


def _add_sweep_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("sweep", help="limit cycles over crabbing velocity x speed (Fig. 5)")
    add_common(p)
    add_fe(p)
    add_modal(p)
    add_axis(p, "--crab-velocity", DEFAULT_SWEEP_CRAB_VELOCITIES, "crabbing velocities [m/s]", span=True)
    add_axis(p, "--rpm", DEFAULT_SPEEDS_RPM, "wheel speeds [rev/min]", filled=False)
    p.add_argument("--speed", type=grid_axis, help="rolling speeds at the contact [m/s], instead of --rpm")
    p.add_argument(
        "--duration",
        type=positive,
        help="simulated time per point [s] (default: each until its outcome is known, as run)",
    )
    p.add_argument("--c22", type=c22_value, help="C22 or 'kalker'")
    add_friction_law(p)
    add_contact(p)
    p.add_argument("--sound", action="store_true", help="also the SPL at the microphone (Fig. 5 in dB)")
    p.add_argument(
        "--measured",
        type=Path,
        metavar="FILE.csv",
        help="measured levels to draw over the --sound curves and compare (columns crab_velocity, rpm, "
        "spl_db, optional frequency_hz): measured.csv holds prediction minus measurement",
    )
    add_microphone(p)


def _add_compare_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("compare", help="several designs at the same operating point")
    p.add_argument("designs", nargs="+", type=Path, help="design TOML files")
    add_out(p)
    p.add_argument("--quiet", action="store_true")
    add_cache(p)
    add_budget(p)
    add_fe(p)
    add_operating(p)
    add_rotation(p)
    add_remedy(p)


def _add_stability_command(sub: argparse._SubParsersAction) -> None:
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


def _add_sound_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("sound", help="sound of one mode at a given contact velocity (no time domain)")
    add_common(p)
    add_fe(p)
    p.add_argument(
        "--velocity-amplitude",
        type=non_negative,
        default=1.0,
        help="contact velocity amplitude [m/s] (peak; default 1)",
    )
    p.add_argument("--frequency", type=positive, help="frequency [Hz] (default: the mode's)")
    add_microphone(p)


def _add_track_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("track", help="the rail's point receptances (a design on a track)")
    add_common(p, cache=False)
    p.add_argument("--fmin", type=positive, default=20.0, help="lowest frequency [Hz] (default %(default)g)")
    p.add_argument(
        "--fmax", type=positive, default=5000.0, help="highest frequency [Hz] (default %(default)g)"
    )
    p.add_argument("--points", type=count, default=300, help="frequencies, log-spaced (default %(default)d)")


def _add_curve_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("curve", help="each wheel of a bogie in curves of radius R at train speed V")
    add_common(p)
    add_fe(p, mode=False)
    p.add_argument(
        "--radius", type=grid_axis, required=True, help="curve radii [m]: a comma list or START:STOP:N"
    )
    p.add_argument(
        "--train-speed", type=grid_axis, required=True, help="train speeds [km/h]: a list or START:STOP:N"
    )
    p.add_argument(
        "--wheelbase", type=positive, help="the bogie's wheelbase 2a [m] (default: the design's [vehicle])"
    )
    p.add_argument(
        "--cant", type=finite, default=0.0, help="the curves' installed cant [mm] (default %(default)g)"
    )
    p.add_argument("--bogie", help=argparse.SUPPRESS)  # replaced by the steady curving: refused with why
    add_friction_law(p)
    p.add_argument(
        "--no-remedy",
        action="store_true",
        help="leave out what would stop the squeal: each treatment (friction modifier, lower friction, "
        "flange lubrication, both, wheel dampers, steering bogie, lower speed) is checked by running the "
        "map again with it",
    )
    p.add_argument(
        "--c22",
        type=c22_value,
        help="creep coefficient C22 of every contact: a number or 'kalker' (default: Kalker's of each "
        "contact's own ellipse)",
    )
    p.add_argument(
        "--time-domain",
        action="store_true",
        help="amplitudes and sound from the time domain (minutes per squealing axle; default: "
        "harmonic balance of the squeal mode)",
    )
    p.add_argument(
        "--ground-reflection",
        type=non_negative,
        help="also the pass-by over a ground 0.5 m below the rail head with this reflection "
        "factor (0 to 1; default: free field only)",
    )


def _add_line_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("line", help="every curve of a railway line: squeal probability and emission")
    add_common(p)
    add_fe(p, mode=False)
    p.add_argument(
        "--line",
        required=True,
        help="LINE.csv: id, radius_m, length_m, cant_mm, train_speed_km_h (x0, y0, x1, y1 or wkt optional)",
    )
    p.add_argument("--traffic", help="a TOML file with a [line] table: traffic per period and friction")
    p.add_argument("--crs", help="the coordinates' projected system, as line.geojson names it (EPSG:25832)")
    add_workers(p)


def add_workers(p: argparse.ArgumentParser) -> None:
    p.add_argument("--workers", type=count, help="local worker processes (default: the machine's cores)")
    p.add_argument(
        "--scheduler",
        help="dask.distributed scheduler address, e.g. tcp://host:8786 (default $DASK_SCHEDULER_ADDRESS)",
    )


def _add_study_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "study", help="many designs (grid or samples) over an operating grid, locally or on dask"
    )
    p.add_argument("spec", type=Path, help="study specification TOML (see studies/)")
    add_out(p)
    add_workers(p)
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    add_cache(p)
    add_budget(p)


def _add_render_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("render", help="mode-shape PNGs (and GIFs), off-screen")
    add_common(p)
    add_fe(p, mode=False)
    p.add_argument("--modes", help="comma list of mode indices (default: all)")
    p.add_argument("--gif", action="store_true", help="also an animated GIF per mode")


def _add_calibrate_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("calibrate", help="fit design parameters to measured modal data")
    p.add_argument("--design", type=Path)
    p.add_argument(
        "--free",
        action="append",
        required=True,
        help="design parameter(s) to fit, e.g. rim_depth (repeat or comma list)",
    )
    p.add_argument("--target-frequency", type=positive, help="measured frequency [Hz]")
    p.add_argument("--target-modal-mass", type=positive, help="measured contact modal mass [kg]")
    p.add_argument(
        "--frequency-uncertainty",
        type=positive,
        default=0.01,
        help="relative standard uncertainty of the measured frequency (default 0.01)",
    )
    p.add_argument(
        "--modal-mass-uncertainty",
        type=positive,
        default=0.10,
        help="relative standard uncertainty of the measured modal mass (default 0.10)",
    )
    p.add_argument("--fidelity", default="fast", choices=list(FIDELITIES))
    p.add_argument(
        "--mode",
        help="the measured mode: INDEX, n=3[,c=0] or f=HZ (default: the design's squeal mode, else n=3,c=0)",
    )
    p.add_argument("--out", type=Path, help="folder or .toml path for the calibrated design")
    p.add_argument("--quiet", action="store_true")


def _add_converge_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("converge", help="speed/accuracy study: mesh ladders, solvers, integrator")
    p.add_argument(
        "--design", type=Path, help="wheel design TOML or shipped name (default: the Table 1 wheel)"
    )
    add_out(p)
    p.add_argument("--quick", action="store_true", help="only the cheapest rungs")
    p.add_argument("--quiet", action="store_true")


def _add_designs_command(sub: argparse._SubParsersAction) -> None:
    sub.add_parser("designs", help="the designs shipped with the tool (give one by name: --design NAME)")


def _add_cache_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("cache", help="inspect, limit or clear the stage cache")
    p.add_argument("action", choices=["clear", "info", "limit"])
    p.add_argument("size", nargs="?", help="with limit: the cache's size limit, like 500M or 5G (default 2G)")
    p.add_argument("--cache-dir", type=Path)
