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
    build_mesh as build_mesh,
    compute_modes,
    contact_law as contact_law,
    load_design,
    modal_dof as modal_dof,
    mode_views as mode_views,
    operating_point,
    pick_mode as pick_mode,
    shipped_designs,
)
from .chain import Analysis, ChainOptions, analyse
from .context import RunContext
from .curve import curve
from .decision import Decision, decide
from .design import Design
from .envelope import envelope, mitigation
from .listener import Listener as Listener
from .mode_stability import StabilityTable, stability_table
from .present.text import analysis_text, verdict_lines
from .presets import (
    DEFAULT_DESIGN as DEFAULT_DESIGN,
    DEFAULT_FIDELITY as DEFAULT_FIDELITY,
    FIDELITIES as FIDELITIES,
    Fidelity as Fidelity,
    fidelity_for as fidelity_for,
)
from .runtime.budget import Budget as Budget
from .runtime.progress import Progress as Progress
from .runtime.request_errors import BudgetError, BudgetExhausted, RequestError
from .runtime.stage_cache import CacheMiss as CacheMiss, StageCache as StageCache
from .simulation import Simulation as Simulation, simulate as simulate
from .sound import Sound as Sound, mode_sound as mode_sound
from .sweeps import VerdictGrid, sweep_verdicts
from .verdict import ModeOutcome, Verdict

#: The notebook API (documented, with examples run by the tests); the stages' own functions
#: and the settings' types are re-exported too (``import X as X`` above), for scripts and tests.
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
