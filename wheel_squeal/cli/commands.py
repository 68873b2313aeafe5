"""The commands by name: each reads its arguments, calls the stages
(:mod:`wheel_squeal.api`), writes its result folder (:mod:`wheel_squeal.outputs`) and
prints a short report."""

from __future__ import annotations

from collections.abc import Callable

from .fe import cmd_mesh, cmd_modes, cmd_render
from .line import cmd_line
from .sound import cmd_sound
from .squeal import cmd_compare, cmd_run, cmd_simulate, cmd_stability, cmd_sweep
from .study import cmd_study
from .tools import cmd_cache, cmd_calibrate, cmd_converge, cmd_designs
from .track import cmd_curve, cmd_track

__all__ = ["COMMANDS"]

#: name -> command(args) or, for the commands that draw, command(args, plots): exit status
COMMANDS: dict[str, Callable[..., int]] = {
    "run": cmd_run,
    "mesh": cmd_mesh,
    "modes": cmd_modes,
    "stability": cmd_stability,
    "sound": cmd_sound,
    "track": cmd_track,
    "curve": cmd_curve,
    "line": cmd_line,
    "simulate": cmd_simulate,
    "sweep": cmd_sweep,
    "compare": cmd_compare,
    "study": cmd_study,
    "render": cmd_render,
    "calibrate": cmd_calibrate,
    "converge": cmd_converge,
    "designs": cmd_designs,
    "cache": cmd_cache,
}
