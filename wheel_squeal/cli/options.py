"""The option groups several commands share (output folder, cache, budget, FE preset,
operating point, rotation, microphone, modal parameters, friction law)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from acoustics.medium import AIR
from contact.creep import FRICTION_LAWS
from fem.solvers import SOLVERS

from ..model_sections import NORMAL_CONTACTS
from ..presets import (
    DEFAULT_CRAB_VELOCITY_M_S,
    DEFAULT_FIDELITY,
    DEFAULT_FMAX_HZ,
    DEFAULT_RPM,
    FIDELITIES,
)
from ..runtime.budget import DEFAULT_MAX_DOFS, DEFAULT_MAX_SECONDS, ENV_MAX_DOFS, ENV_MAX_SECONDS
from ..runtime.stage_cache import ENV_VAR as CACHE_ENV_VAR
from .arguments import (
    angle_deg,
    c22_value,
    count,
    finite,
    friction_value,
    grid_axis,
    microphone,
    non_negative,
    positive,
)

__all__ = [
    "add_axis",
    "add_out",
    "add_common",
    "add_cache",
    "add_budget",
    "add_fe",
    "add_operating",
    "add_rotation",
    "add_microphone",
    "add_modal",
    "add_contact",
    "add_friction_law",
    "add_modal_model",
    "add_remedy",
]


def add_axis(
    p: argparse.ArgumentParser,
    flag: str,
    default: Any,
    what: str,
    span: bool = False,
    filled: bool = True,
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


def add_out(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, help=OUT_HELP)


def add_common(p: argparse.ArgumentParser, cache: bool = True) -> None:
    p.add_argument(
        "--design",
        type=Path,
        help="wheel design: a TOML file, or the name of a shipped design (see the designs command; "
        "default: the Table 1 wheel)",
    )
    add_out(p)
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    if cache:
        add_cache(p)
    add_budget(p)


def add_cache(p: argparse.ArgumentParser) -> None:
    p.add_argument("--no-cache", action="store_true", help="recompute mesh and modes")
    p.add_argument(
        "--cache-dir",
        type=Path,
        help=f"stage cache folder (default ${CACHE_ENV_VAR}, else ~/.cache/wheel-squeal)",
    )


def add_budget(p: argparse.ArgumentParser) -> None:
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


def add_fe(p: argparse.ArgumentParser, mode: bool = True) -> None:
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
            help="squeal mode: auto (the one the design names, else the model's own outcome at "
            "the operating point), model (the model's own outcome, whatever the design names), "
            "INDEX, n=3[,c=0] or f=HZ",
        )


def add_operating(p: argparse.ArgumentParser, speed: bool = True, duration: bool = True) -> None:
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
    add_friction_law(p)
    add_contact(p)


def add_contact(p: argparse.ArgumentParser) -> None:
    """Where and how the wheel touches the roller (each overrides the design's [contact])."""
    p.add_argument(
        "--contact-angle",
        type=angle_deg,
        metavar="DEG",
        help="move the contact along the tread's crown to this contact angle [deg] (the design "
        "file's contact_angle is in rad; default: the design's)",
    )
    p.add_argument(
        "--normal-contact",
        choices=list(NORMAL_CONTACTS),
        help="'hertz' (the normal force follows the contact's normal motion) or 'constant' (the "
        "paper's fixed normal load); default: the design's [contact] normal_contact",
    )
    p.add_argument(
        "--transient-creep",
        action="store_true",
        help="the creep force lags its steady value by L / V0 (L: the Hertz semi-axis along "
        "rolling, or the design's relaxation_length); default: the paper's steady law",
    )


def add_rotation(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--rotation",
        action="store_true",
        help="model the wheel's rotation: each n-diameter pair as two travelling waves "
        "(tone f0 -/+ n Omega / 2 pi at the contact; default off, the paper's model)",
    )


def add_record(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--full-record",
        action="store_true",
        help="timeseries.csv with every sample of the record (up to the 200 MB a file may "
        "take; default: every k-th sample within 20 MB, summary.json gives k)",
    )


def add_microphone(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--microphone",
        type=microphone,
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


def add_modal(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--mass", type=positive, help="modal mass at the contact [kg] (with --stiffness, --damping: no FE)"
    )
    p.add_argument("--stiffness", type=positive, help="modal stiffness [N/m]")
    p.add_argument("--damping", type=non_negative, help="modal damping [N s/m]")


def add_modal_model(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--modal-model",
        type=Path,
        metavar="FILE.toml",
        help="the wheel's modes from a modal test instead of the FE: one [[mode]] table per mode "
        "(frequency_hz, damping_ratio, lateral, normal [1/sqrt(kg)], optional nodal_diameters, label); "
        "the design gives the contact",
    )


def add_friction_law(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--friction",
        type=friction_value,
        metavar="MU",
        help="the friction coefficient mu_s = mu_0 [-] (default: the design's [contact] "
        "friction_coefficient)",
    )
    p.add_argument(
        "--friction-law",
        choices=list(FRICTION_LAWS),
        help="'falling' (the paper's) or 'constant' (no falling friction: only mode coupling "
        "can drive squeal); default: the design's [contact] friction_law",
    )


def add_remedy(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--no-remedy",
        action="store_true",
        help="leave out what would stop the squeal (or, with none, start it): its bounds cost "
        "some 20 eigen-solves of all the modes",
    )


def add_workers(p: argparse.ArgumentParser) -> None:
    p.add_argument("--workers", type=count, help="local worker processes (default: the machine's cores)")
    p.add_argument(
        "--scheduler",
        help="dask.distributed scheduler address, e.g. tcp://host:8786 (default $DASK_SCHEDULER_ADDRESS)",
    )
