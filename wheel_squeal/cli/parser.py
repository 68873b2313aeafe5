"""The command line's parser: each command's module adds its own flags (``add_parser``,
:mod:`.commands`), from the flags they share (:mod:`.options`).

Flag values are checked by argparse (a flag's error names the flag: ``argument --rpm:
must be positive``); what needs the design or the modes is checked by the stages.
Importing the parser imports numpy at most (no SciPy, matplotlib, numba, gmsh or scikit-fem), so
``--help`` is quick.
"""

from __future__ import annotations

import argparse
from typing import NoReturn

from .commands import COMMAND_MODULES

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

    for command in COMMAND_MODULES.values():  # in the order of --help
        command.add_parser(sub)
    return parser
