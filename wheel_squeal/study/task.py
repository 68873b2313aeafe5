"""One design of a study, start to finish, as one task: a plain function of plain data.

A worker (a local process or a dask worker on another machine) runs :func:`run_case`
on a :class:`CaseJob` and returns a JSON-ready dict; nothing else crosses. The FE goes
through the worker's stage cache (safe for concurrent writers: entries are written to a
temporary name and renamed). An invalid design or an anticipated failure of meshing or
solving is a result with its one-line reason; anything else is a bug and propagates.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from geometry import DesignError, MeshError

from ..design import Design
from ..output_files import FLAG_FIELDS, LABEL_FIELDS, RESULT_FIELDS
from ..runtime.request_errors import BudgetError, RequestError
from ..types import FidelityName, Stage

__all__ = ["FLAG_FIELDS", "LABEL_FIELDS", "CaseJob", "RESULT_FIELDS", "run_case"]


@dataclass(frozen=True)
class CaseJob:
    """What one task needs: the base design and its changes, the FE preset and band, what
    to compute, the operating grid, the worker's cache folder (None: no cache; "": the
    worker's default one, :func:`wheel_squeal.runtime.stage_cache.default_cache_root`) and the limit
    of its modal solve (None: the worker's environment's)."""

    base: Design
    changes: tuple[tuple[str, float], ...]
    fidelity: FidelityName
    fmax_hz: float
    compute: tuple[str, ...]
    crabbing_velocities_m_s: tuple[float, ...]
    rpm: tuple[float, ...]
    cache_dir: str | None = None
    max_dofs: float | None = None


def _failure(status: str, reason: str) -> dict:
    return {"status": status, "reason": " ".join(str(reason).split())}


def run_case(job: CaseJob) -> dict:
    """Mesh and modes once, then at every operating point the verdict of
    ``wheel_squeal.chain.analyse`` (stability, limit cycle, sound, as ``compute`` asks).
    Returns ``status`` ("ok", "invalid", "failed"), ``reason`` (``transient``: True when
    the environment caused the outcome, a budget refusal) and, when ok, the mass, the
    modes found, and per operating point :data:`RESULT_FIELDS`, :data:`FLAG_FIELDS` and
    :data:`LABEL_FIELDS`."""
    from fem.eigen import EigenError, blas_threads
    from reduced.model import IntegrationError

    try:
        design = job.base.replace(**dict(job.changes))
    except (DesignError, RequestError) as exc:
        return _failure("invalid", str(exc))
    try:
        # one thread per task: a study's parallelism is across its tasks
        with blas_threads(1):
            return _run(design, job)
    except BudgetError as exc:  # the limit of this run, not the design: not final
        return {**_failure("failed", f"refused by the budget: {exc}"), "transient": True}
    except (MeshError, EigenError, IntegrationError, RequestError) as exc:
        return _failure("failed", f"{type(exc).__name__}: {exc}")


def _run(design: Design, job: CaseJob) -> dict:
    from geometry import wheel_mass
    from reduced import OperatingPoint, load_compiled_kernels

    from .. import api
    from ..chain import ChainOptions, analyse
    from ..context import RunContext
    from ..presets import fidelity_for
    from ..runtime.budget import Budget
    from ..runtime.stage_cache import StageCache

    cache = None if job.cache_dir is None else StageCache(job.cache_dir or None)
    simulate = "limit_cycle" in job.compute
    if simulate:
        load_compiled_kernels()  # a worker runs many simulations: compiled, from the first
    budget = Budget.from_environment(job.max_dofs)
    modes = api.compute_modes(design, job.fidelity, fmax_hz=job.fmax_hz, cache=cache, budget=budget)
    shape = (len(job.crabbing_velocities_m_s), len(job.rpm))
    out: dict = {"status": "ok", "reason": "", "mass_kg": wheel_mass(design.wheel), "modes": len(modes.modes)}
    numbers = {k: np.full(shape, np.nan) for k in RESULT_FIELDS}
    flags = {k: np.zeros(shape, dtype=bool) for k in FLAG_FIELDS}
    labels = {k: np.full(shape, "", dtype=object) for k in LABEL_FIELDS}
    if "stability" in job.compute:
        stop: Stage = "sound" if "sound" in job.compute else "limit_cycle" if simulate else "stability"
        options = ChainOptions(stop_after=stop, remedy=False, simulate_stable=False, beside=False)
        ctx = RunContext(fidelity_for(job.fidelity), job.fmax_hz, cache, budget)  # one memo per design
        for (i, j), _ in np.ndenumerate(numbers["tone_hz"]):
            op = OperatingPoint.from_rpm(job.rpm[j], design.rolling_radius, job.crabbing_velocities_m_s[i])
            record = analyse(design, op=op, options=options, context=ctx, modes=modes).to_record()
            for k in numbers:
                numbers[k][i, j] = np.nan if record[k] is None else record[k]
            for k in flags:
                flags[k][i, j] = record[k]
            for k in labels:
                labels[k][i, j] = record[k]
    out |= {k: v.tolist() for k, v in numbers.items()}
    out |= {k: v.tolist() for k, v in flags.items()}
    out |= {k: v.tolist() for k, v in labels.items()}
    return out
