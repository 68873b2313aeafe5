"""The cost plan of every request: each command's whole work estimated before any of it
runs (``budget.CostPlan``, refused in one line with its estimate and largest parts).

Each stage prices itself where its physics lives (``fem.cost`` the modal solve,
``reduced.stability`` an eigen-solve, ``acoustics.radiation_cost`` a sound solve, the
squeal model its steps); this module adds those up per command:

- a verdict (``run``, ``stability``, ``simulate``, ``compare``, ``sweep``'s points): in two
  steps, since which modes squeal is known only once the stability is solved
  (:func:`stability_plan`, then :func:`verdict_plan`);
- the ``stability`` command's bounds and envelope (:func:`stability_request_plan`);
- ``mesh`` (:func:`mesh_plan`), ``track`` (:func:`track_plan`);
- ``curve``: radii x speeds x wheels, their verdicts, the time domain's steps, the sound
  solves, the pass-by, the memory it keeps and the files it writes (:func:`curve_plan`),
  in three steps: on counts, with the modes, and with each sliding axle's stability
  (:func:`squealing_axles`);
- ``study``: its cases on the workers found (:func:`study_plan`).

The constants that are not a stage's own are measured on this project's shipped designs
(``benchmarks/bench_estimates.py`` checks every plan against the time it took).

One module per kind of request: :mod:`.verdict` (a verdict and the stability command),
:mod:`.fe` (meshing, and the FE's estimates the others take), :mod:`.field` (the track and
curves), :mod:`.study`.
"""

from __future__ import annotations

from .fe_cost import MESH_BYTES_PER_ELEMENT, MESH_SECONDS_PER_ELEMENT, mesh_plan
from .field_cost import (
    CurveSize,
    SquealingAxles,
    check_curve_files,
    curve_plan,
    line_plan,
    squealing_axles,
    track_plan,
)
from .study_cost import StudyCost, estimate_study, study_plan
from .verdict_cost import (
    NO_REMEDY_HINT,
    stability_plan,
    stability_request_plan,
    verdict_plan,
)

__all__ = [
    "MESH_BYTES_PER_ELEMENT",
    "MESH_SECONDS_PER_ELEMENT",
    "NO_REMEDY_HINT",
    "CurveSize",
    "SquealingAxles",
    "StudyCost",
    "check_curve_files",
    "line_plan",
    "curve_plan",
    "estimate_study",
    "mesh_plan",
    "stability_plan",
    "stability_request_plan",
    "squealing_axles",
    "study_plan",
    "track_plan",
    "verdict_plan",
]
