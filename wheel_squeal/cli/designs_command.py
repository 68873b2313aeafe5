"""The ``designs`` command: the designs shipped with the tool (give one by name: --design NAME)."""

from __future__ import annotations

import argparse

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    sub.add_parser("designs", help="the designs shipped with the tool (give one by name: --design NAME)")


def run(args: argparse.Namespace) -> int:
    from ..api import shipped_designs

    for name, description in shipped_designs().items():
        first = description.split(". ")[0].split(": ")[0]
        print(f"{name:<16} {first if len(first) <= 90 else first[:89] + '...'}")
    print("give one by name from any folder: --design NAME")
    return 0
