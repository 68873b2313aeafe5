"""The commands by name: one module each (``cli/NAME_command.py``), with its flags
(``add_parser``) and its run (``run``: reads its arguments, calls the stages, writes its
result folder and prints a short report)."""

from __future__ import annotations

from collections.abc import Callable
from types import ModuleType

from . import (
    cache_command,
    calibrate_command,
    compare_command,
    converge_command,
    curve_command,
    designs_command,
    line_command,
    mesh_command,
    modes_command,
    render_command,
    run_command,
    simulate_command,
    sound_command,
    stability_command,
    study_command,
    sweep_command,
    track_command,
)

__all__ = ["COMMANDS", "COMMAND_MODULES"]

#: name -> the command's module, in the order of ``--help``
COMMAND_MODULES: dict[str, ModuleType] = {
    "run": run_command,
    "mesh": mesh_command,
    "modes": modes_command,
    "simulate": simulate_command,
    "sweep": sweep_command,
    "compare": compare_command,
    "stability": stability_command,
    "sound": sound_command,
    "track": track_command,
    "curve": curve_command,
    "line": line_command,
    "study": study_command,
    "render": render_command,
    "calibrate": calibrate_command,
    "converge": converge_command,
    "designs": designs_command,
    "cache": cache_command,
}
#: name -> run(args) or, for the commands that draw, run(args, plots): exit status
COMMANDS: dict[str, Callable[..., int]] = {name: module.run for name, module in COMMAND_MODULES.items()}
