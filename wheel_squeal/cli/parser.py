"""The command line's arguments: every command, flag, default and help text.

Flag values are checked here (a flag's error names the flag: ``argument --rpm: must be
positive``); what needs the design or the modes is checked by the stages. Importing this
module imports numpy at most (no SciPy, matplotlib, numba, gmsh or scikit-fem), so
``--help`` is quick.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from acoustics.medium import AIR
from fem.solvers import SOLVERS

from ..budget import DEFAULT_MAX_DOFS, DEFAULT_MAX_SECONDS, ENV_MAX_DOFS, ENV_MAX_SECONDS
from ..cache import ENV_VAR as CACHE_ENV_VAR
from ..presets import (
    DEFAULT_CRAB_VELOCITY_M_S,
    DEFAULT_ENVELOPE_CRAB_VELOCITIES,
    DEFAULT_FIDELITY,
    DEFAULT_FMAX_HZ,
    DEFAULT_RPM,
    DEFAULT_SPEEDS_RPM,
    DEFAULT_SWEEP_CRAB_VELOCITIES,
    DEFAULT_SWEEP_DURATION_S,
    FIDELITIES,
    MAX_MULTIMODE,
)
from .arguments import c22_value, count, finite, grid_axis, non_negative, positive

__all__ = ["CommandParser", "build_parser"]


class CommandParser(argparse.ArgumentParser):
    """argparse with one-line errors (exit status 2, no usage dump); ``subcommands``
    maps each command to its own parser (for errors that name the command)."""

    subcommands: dict[str, CommandParser]

    def error(self, message: str):
        self.exit(2, f"error: {message} (see {self.prog} --help)\n")


def _add_axis(
    p: argparse.ArgumentParser, flag: str, default, what: str, span: bool = False, filled: bool = True
) -> None:
    """A sweep axis flag (:func:`grid_axis`); ``default``: (start, stop, points) when
    ``span``, else the values; ``filled=False`` leaves it None when not given (the
    command fills it in, and can tell whether it was given)."""
    text = (":" if span else ",").join(f"{x:g}" for x in default)
    p.add_argument(
        flag,
        type=grid_axis,
        default=grid_axis(text) if filled else None,
        help=f"{what}: START:STOP:N or list (default {text})",
    )


#: Where a command writes when ``--out`` is not given (below the working folder).
OUT_HELP = "result folder (default: results/COMMAND/NAME, NAME the design's or the study's)"


def _add_out(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, help=OUT_HELP)


def _add_common(p: argparse.ArgumentParser, cache: bool = True) -> None:
    p.add_argument(
        "--design",
        type=Path,
        help="wheel design: a TOML file, or the name of a shipped design (see the designs command; "
        "default: the Table 1 wheel)",
    )
    _add_out(p)
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    if cache:
        _add_cache(p)
    _add_budget(p)


def _add_cache(p: argparse.ArgumentParser) -> None:
    p.add_argument("--no-cache", action="store_true", help="recompute mesh and modes")
    p.add_argument(
        "--cache-dir",
        type=Path,
        help=f"stage cache folder (default ${CACHE_ENV_VAR}, else ~/.cache/wheel-squeal)",
    )


def _add_budget(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--max-dofs",
        type=positive,
        help=f"refuse modal solves larger than this (default {DEFAULT_MAX_DOFS:.0e}; env {ENV_MAX_DOFS})",
    )
    p.add_argument(
        "--max-seconds",
        type=positive,
        help=f"refuse work estimated to take longer (default {DEFAULT_MAX_SECONDS:g}; env {ENV_MAX_SECONDS})",
    )


def _add_fe(p: argparse.ArgumentParser, mode: bool = True) -> None:
    p.add_argument(
        "--fidelity",
        default=DEFAULT_FIDELITY,
        choices=list(FIDELITIES),
        help="speed/accuracy preset (default %(default)s; see README)",
    )
    p.add_argument(
        "--solver",
        choices=list(SOLVERS),
        help="force the FE solver: axisym, 3d (3-D P2, cyclic symmetry) or 3d-tet "
        "(3-D P2 on a gmsh tetrahedral mesh, slow)",
    )
    p.add_argument(
        "--fmax",
        type=positive,
        default=DEFAULT_FMAX_HZ,
        help="modes up to this frequency [Hz] (default %(default)g)",
    )
    if mode:
        p.add_argument(
            "--mode",
            default="auto",
            help="squeal mode: auto (the one the design names, else the fastest-growing at "
            "the operating point), INDEX, n=3[,c=0] or f=HZ",
        )


def _add_operating(p: argparse.ArgumentParser, speed: bool = True, duration: bool = True) -> None:
    p.add_argument("--rpm", type=positive, help=f"wheel speed [rev/min] (default {DEFAULT_RPM:g})")
    if speed:
        p.add_argument("--speed", type=positive, help="rolling speed at the contact [m/s]")
    p.add_argument(
        "--crab-velocity",
        type=finite,
        help=f"crabbing velocity Vc [m/s] (default {DEFAULT_CRAB_VELOCITY_M_S:g})",
    )
    p.add_argument("--angle-of-attack", type=finite, help="angle of attack [rad] (Vc = theta V0)")
    if duration:
        p.add_argument(
            "--duration",
            type=positive,
            help="simulated time [s] (default: 0.6 s, extended while still growing)",
        )
    p.add_argument(
        "--c22", type=c22_value, help="creep coefficient C22: a number or 'kalker' (default: the design's)"
    )


def _add_rotation(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--rotation",
        action="store_true",
        help="model the wheel's rotation: each n-diameter pair as two travelling waves "
        "(tone f0 -/+ n Omega / 2 pi at the contact; default off, the paper's model)",
    )


def _add_microphone(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--microphone",
        metavar="R,Z,THETA",
        help="microphone position [m, m, rad] (default: 0.05 m off the rim face at the "
        "rolling radius, theta 0)",
    )
    p.add_argument(
        "--air-density", type=positive, default=AIR.density_kg_m3, help="kg/m^3 (default %(default)g)"
    )
    p.add_argument(
        "--sound-speed", type=positive, default=AIR.sound_speed_m_s, help="m/s (default %(default)g)"
    )


def _add_modal(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--mass", type=positive, help="modal mass at the contact [kg] (with --stiffness, --damping: no FE)"
    )
    p.add_argument("--stiffness", type=positive, help="modal stiffness [N/m]")
    p.add_argument("--damping", type=non_negative, help="modal damping [N s/m]")


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
    _add_common(p)
    _add_fe(p)
    _add_operating(p)
    p.add_argument(
        "--render",
        choices=["selected", "all", "none"],
        default="selected",
        help="mode-shape PNGs to draw (default: the squeal mode)",
    )
    _add_rotation(p)
    _add_microphone(p)
    p.add_argument(
        "--multimode",
        type=count,
        nargs="?",
        const=MAX_MULTIMODE,
        metavar="K",
        help="also integrate the K most unstable modes together "
        f"(default K: every unstable mode, at most {MAX_MULTIMODE})",
    )


def _add_mesh_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("mesh", help="mesh a design (2-D profile or 3-D revolved)")
    _add_common(p, cache=False)
    p.add_argument("--size", type=positive, help="characteristic element length [m]")
    p.add_argument("--elements-through-web", type=int, help="elements across the web thickness")
    p.add_argument("--order", type=int, choices=[1, 2], default=2, help="geometry order")
    p.add_argument("--dim", type=int, choices=[2, 3], default=3, help="2-D profile or 3-D solid")


def _add_modes_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("modes", help="eigenmodes, labels and contact modal parameters")
    _add_common(p)
    _add_fe(p)


def _add_simulate_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("simulate", help="time-domain squeal model at one operating point")
    _add_common(p)
    _add_fe(p)
    _add_modal(p)
    _add_operating(p)
    _add_rotation(p)
    p.add_argument(
        "--nodal-diameters", type=int, default=0, help="the --mass mode's nodal diameters (for --rotation)"
    )


def _add_sweep_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("sweep", help="limit cycles over crabbing velocity x speed (Fig. 5)")
    _add_common(p)
    _add_fe(p)
    _add_modal(p)
    _add_axis(p, "--crab-velocity", DEFAULT_SWEEP_CRAB_VELOCITIES, "crabbing velocities [m/s]", span=True)
    _add_axis(p, "--rpm", DEFAULT_SPEEDS_RPM, "wheel speeds [rev/min]", filled=False)
    p.add_argument("--speed", type=grid_axis, help="rolling speeds at the contact [m/s], instead of --rpm")
    p.add_argument(
        "--duration",
        type=positive,
        default=DEFAULT_SWEEP_DURATION_S,
        help="simulated time per case [s] (default %(default)g)",
    )
    p.add_argument("--c22", type=c22_value, help="C22 or 'kalker'")
    p.add_argument("--sound", action="store_true", help="also the SPL at the microphone (Fig. 5 in dB)")
    _add_microphone(p)


def _add_compare_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("compare", help="several designs at the same operating point")
    p.add_argument("designs", nargs="+", type=Path, help="design TOML files")
    _add_out(p)
    p.add_argument("--quiet", action="store_true")
    _add_cache(p)
    _add_budget(p)
    _add_fe(p)
    _add_operating(p)
    _add_rotation(p)


def _add_stability_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("stability", help="linear stability of every mode: which squeals, what stops it")
    _add_common(p)
    _add_fe(p)
    _add_operating(p, duration=False)
    _add_rotation(p)
    p.add_argument(
        "--envelope",
        action="store_true",
        help="also the map over the envelope (stability.csv, stability.png) and the mitigation",
    )
    vcs = DEFAULT_ENVELOPE_CRAB_VELOCITIES
    _add_axis(p, "--envelope-crab-velocity", vcs, "the envelope's Vc [m/s]", span=True, filled=False)
    _add_axis(p, "--envelope-rpm", DEFAULT_SPEEDS_RPM, "the envelope's wheel speeds [rev/min]", filled=False)
    p.add_argument(
        "--no-bounds",
        action="store_true",
        help="growth rates only: skip each mode's critical damping and friction slope "
        "(some 15-30 eigen-solves per mode)",
    )


def _add_sound_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("sound", help="sound of one mode at a given contact velocity (no time domain)")
    _add_common(p)
    _add_fe(p)
    p.add_argument(
        "--velocity-amplitude",
        type=non_negative,
        default=1.0,
        help="contact velocity amplitude [m/s] (peak; default 1)",
    )
    p.add_argument("--frequency", type=positive, help="frequency [Hz] (default: the mode's)")
    _add_microphone(p)


def _add_study_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "study", help="many designs (grid or samples) over an operating grid, locally or on dask"
    )
    p.add_argument("spec", type=Path, help="study specification TOML (see studies/)")
    _add_out(p)
    p.add_argument("--workers", type=count, help="local worker processes (default: the machine's cores)")
    p.add_argument(
        "--scheduler",
        help="dask.distributed scheduler address, e.g. tcp://host:8786 (default $DASK_SCHEDULER_ADDRESS)",
    )
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    _add_cache(p)
    _add_budget(p)


def _add_render_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("render", help="mode-shape PNGs (and GIFs), off-screen")
    _add_common(p)
    _add_fe(p, mode=False)
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
    _add_out(p)
    p.add_argument("--quick", action="store_true", help="only the cheapest rungs")
    p.add_argument("--quiet", action="store_true")


def _add_designs_command(sub: argparse._SubParsersAction) -> None:
    sub.add_parser("designs", help="the designs shipped with the tool (give one by name: --design NAME)")


def _add_cache_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("cache", help="inspect, limit or clear the stage cache")
    p.add_argument("action", choices=["clear", "info", "limit"])
    p.add_argument("size", nargs="?", help="with limit: the cache's size limit, like 500M or 5G (default 2G)")
    p.add_argument("--cache-dir", type=Path)
