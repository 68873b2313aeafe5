"""The convergence study behind the fidelity presets (``pipeline.py converge``): see
:mod:`.study` for what it runs and how it compares, :mod:`.ladders` for the rungs,
:mod:`.choice` for the errors and the preset choice, :mod:`.report` for its files and
:mod:`.measure` for timing and memory in a child process."""

from .choice import choose_presets, fill_errors, mark_pareto, pareto_front, presets_table, presets_verdict
from .ladder_study import ConvergenceError, run_convergence
from .ladders import COLUMNS, FERung, fe_ladder, integrator_ladder
from .measure import fork_available, measure, measure_repeated
from .preset_report import read_csv, write_csv, write_plots

__all__ = [
    "COLUMNS",
    "ConvergenceError",
    "FERung",
    "choose_presets",
    "fe_ladder",
    "fill_errors",
    "fork_available",
    "integrator_ladder",
    "mark_pareto",
    "measure",
    "measure_repeated",
    "pareto_front",
    "presets_table",
    "presets_verdict",
    "read_csv",
    "run_convergence",
    "write_csv",
    "write_plots",
]
