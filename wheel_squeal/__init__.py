"""wheel-squeal: a railway test-rig wheel design -> gmsh mesh -> scikit-fem modes ->
contact modal parameters -> curve-squeal limit cycle, as a Python API and a command line.

This package is the application layer, the only one that knows every stage; below it
``geometry`` (designs, meshes), ``fem`` (modes), ``reduced`` (the squeal model) know
nothing of those downstream of them. The notebook API (plain functions on plain
objects, :mod:`wheel_squeal.api`)::

    import wheel_squeal as ws
    a = ws.analyse(ws.load_design("thin_web"), rpm=800, crab_velocity=0.39)
    print(a.verdict.lines()[0])                     # does it squeal, in which mode, how loud
    modes = a.modeset                               # fem.ModeSet; a.rows: every mode's stability
    sim = a.outcome.simulation                      # the limit cycle the verdict rests on

The command line: ``wheel-squeal --help`` (:mod:`wheel_squeal.cli`).
"""

from .api import (
    Simulation,
    build_mesh,
    check_modes_budget,
    compute_modes,
    contact_law,
    explicit_dof,
    load_design,
    modal_dof,
    mode_views,
    modes_cache_key,
    operating_point,
    pick_mode,
    shipped_designs,
    simulate,
    sweep,
)
from .budget import Budget
from .cache import CacheMiss, StageCache
from .chain import Analysis, analyse
from .design import Design
from .envelope import envelope, mitigation
from .errors import BudgetError, RequestError
from .presets import DEFAULT_DESIGN, DEFAULT_FIDELITY, FIDELITIES, Fidelity, fidelity_for
from .progress import Progress
from .sound import Listener, Sound, mode_sound
from .stability import choose_mode, multimode, stability_table
from .sweeps import VerdictGrid, sweep_verdicts
from .verdict import ModeOutcome, Verdict

__all__ = [
    "Analysis",
    "Budget",
    "Design",
    "Listener",
    "ModeOutcome",
    "Sound",
    "Verdict",
    "VerdictGrid",
    "analyse",
    "mode_sound",
    "shipped_designs",
    "sweep_verdicts",
    "BudgetError",
    "CacheMiss",
    "DEFAULT_DESIGN",
    "DEFAULT_FIDELITY",
    "FIDELITIES",
    "Fidelity",
    "Progress",
    "RequestError",
    "Simulation",
    "StageCache",
    "build_mesh",
    "check_modes_budget",
    "choose_mode",
    "compute_modes",
    "contact_law",
    "envelope",
    "explicit_dof",
    "fidelity_for",
    "load_design",
    "mitigation",
    "modal_dof",
    "mode_views",
    "modes_cache_key",
    "multimode",
    "operating_point",
    "pick_mode",
    "simulate",
    "stability_table",
    "sweep",
]
