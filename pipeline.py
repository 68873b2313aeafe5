#!/usr/bin/env python3
"""Wheel-squeal pipeline: design -> mesh -> modes -> contact modal parameters -> squeal.

The entry point of the command line (``python pipeline.py --help``; installed as
``wheel-squeal``); ``import pipeline`` gives the notebook API of ``wheel_squeal``.
"""

import os
import signal
import sys
import time

_STARTED_S = time.monotonic()  # a request's time budget counts from here


def _stopped_early(signum: int, frame: object) -> None:
    # a stop before the command's own handlers (the imports): nothing is written yet
    print("terminated" if signum == signal.SIGTERM else "interrupted", file=sys.stderr, flush=True)
    os._exit(143 if signum == signal.SIGTERM else 130)


def run(prog: str = "wheel-squeal") -> None:
    """The command line, stoppable by SIGTERM or Ctrl-C with one line from its start."""
    for signum in (signal.SIGTERM, signal.SIGINT):
        signal.signal(signum, _stopped_early)
    from wheel_squeal.cli import run as run_command_line

    run_command_line(prog, started_s=_STARTED_S)


if __name__ == "__main__":
    run(prog="pipeline.py")
else:
    from wheel_squeal import *  # noqa: F403  (the notebook API: ``import pipeline as wp``)
