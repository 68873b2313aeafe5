"""wheel-squeal: a railway test-rig wheel design -> gmsh mesh -> scikit-fem modes ->
contact modal parameters -> curve-squeal limit cycle, as a Python API and a command line.

This package is the application layer, the only one that knows every stage; below it
``geometry`` (designs, meshes), ``fem`` (modes), ``reduced`` (the squeal model) know
nothing of those downstream of them. The notebook API (plain functions on plain
objects, :mod:`wheel_squeal.api`)::

    import wheel_squeal as ws
    a = ws.analyse(ws.load_design("thin_web"), rpm=800, crabbing_velocity_m_s=0.39)
    print(ws.verdict_lines(a.verdict)[0])           # does it squeal, in which mode, how loud
    modes = a.modeset                               # fem.ModeSet; a.rows: every mode's stability
    sim = a.outcome.simulation                      # the limit cycle the verdict rests on

The command line: ``wheel-squeal --help`` (:mod:`wheel_squeal.cli`).
"""

from fem.modal_model import explicit_modes, load_modal_model

from .api import (
    build_mesh,
    compute_modes,
    contact_law,
    load_design,
    modal_dof,
    mode_views,
    operating_point,
    pick_mode,
    shipped_designs,
)
from .budget import Budget
from .cache import CacheMiss, StageCache
from .chain import Analysis, ChainOptions, analyse
from .context import RunContext
from .curve import curve
from .decision import Decision, decide
from .design import Design
from .envelope import envelope, mitigation
from .errors import BudgetError, BudgetExhausted, RequestError
from .listener import Listener
from .present.text import analysis_text, verdict_lines
from .presets import DEFAULT_DESIGN, DEFAULT_FIDELITY, FIDELITIES, Fidelity, fidelity_for
from .progress import Progress
from .simulation import Simulation, simulate
from .sound import Sound, mode_sound
from .stability import StabilityTable, stability_table
from .sweeps import VerdictGrid, sweep_verdicts
from .verdict import ModeOutcome, Verdict

__all__ = [
    "Analysis",
    "BudgetError",
    "BudgetExhausted",
    "ChainOptions",
    "Decision",
    "Design",
    "ModeOutcome",
    "RequestError",
    "RunContext",
    "StabilityTable",
    "Verdict",
    "VerdictGrid",
    "analyse",
    "analysis_text",
    "compute_modes",
    "curve",
    "decide",
    "envelope",
    "explicit_modes",
    "load_design",
    "load_modal_model",
    "mitigation",
    "operating_point",
    "shipped_designs",
    "stability_table",
    "sweep_verdicts",
    "verdict_lines",
]
#: Reachable as ``wheel_squeal.NAME`` too, for scripts and tests (documented where
#: they live): the stages' own functions and the settings' types.
_ALSO = (
    Budget,
    CacheMiss,
    Fidelity,
    Listener,
    Progress,
    Simulation,
    Sound,
    StageCache,
    build_mesh,
    contact_law,
    fidelity_for,
    modal_dof,
    mode_sound,
    mode_views,
    pick_mode,
    simulate,
    DEFAULT_DESIGN,
    DEFAULT_FIDELITY,
    FIDELITIES,
)
