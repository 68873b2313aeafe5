#!/usr/bin/env python3
"""Wheel-squeal pipeline: design -> mesh -> modes -> contact modal parameters -> squeal.

The entry point of the command line (``python pipeline.py --help``; installed as
``wheel-squeal``). The code is the ``wheel_squeal`` package; ``import pipeline`` gives
its notebook API too::

    python pipeline.py run                      # Table 1 wheel, 800 RPM, Vc 0.39 m/s
    python pipeline.py run --design designs/thin_web.toml --rpm 600
    python pipeline.py sweep --crab-velocity 0:0.5:26 --rpm 400,600,800
"""

from wheel_squeal import *  # noqa: F403  (the notebook API: ``import pipeline as wp``)
from wheel_squeal.cli import main, run  # noqa: F401

if __name__ == "__main__":
    run(prog="pipeline.py")
