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

from geometry import DesignError, MeshError, WheelDesign

from ..errors import BudgetError, RequestError

__all__ = ["CODE_PACKAGES", "CaseJob", "run_case", "RESULT_FIELDS"]

#: The packages whose code a case's result depends on (its cache key, the dataset's
#: provenance).
CODE_PACKAGES = ("geometry", "fem", "reduced", "acoustics", "wheel_squeal")

#: The per-operating-point results of a case, each (n_crab_velocities, n_rpm).
RESULT_FIELDS = ("growth_rate_1_s", "frequency_hz", "amplitude_m_s", "spl_db", "sound_power_level_db")


@dataclass(frozen=True)
class CaseJob:
    """What one task needs: the base design and its changes, the FE preset and band, what
    to compute, the operating grid, the worker's cache folder (None: no cache; "": the
    worker's default one, :func:`wheel_squeal.cache.default_cache_root`) and the limit
    of its modal solve (None: the worker's environment's)."""

    base: WheelDesign
    changes: tuple[tuple[str, float], ...]
    fidelity: str
    fmax_hz: float
    compute: tuple[str, ...]
    crab_velocities_m_s: tuple[float, ...]
    rpm: tuple[float, ...]
    cache_dir: str | None = None
    max_dofs: float | None = None


def _failure(status: str, reason: str) -> dict:
    return {"status": status, "reason": " ".join(str(reason).split())}


def run_case(job: CaseJob) -> dict:
    """Mesh, modes, the stability map, the limit cycle of the fastest-growing mode and its
    sound at every operating point. Returns ``status`` ("ok", "invalid", "failed"),
    ``reason`` (``transient``: True when the environment caused the outcome, a budget
    refusal) and, when ok, the mass, the modes found, and per operating point the
    squeal mode's label (``squeal_mode``, "" where nothing grows) and
    :data:`RESULT_FIELDS` (NaN where they do not apply)."""
    from fem.eigen import EigenError, blas_threads
    from reduced.model import IntegrationError

    try:
        design = job.base.replace(**dict(job.changes))
    except DesignError as exc:
        return _failure("invalid", exc)
    try:
        # one thread per task: a study's parallelism is across its tasks
        with blas_threads(1):
            return _run(design, job)
    except BudgetError as exc:  # the limit of this run, not the design: not final
        return {**_failure("failed", f"refused by the budget: {exc}"), "transient": True}
    except (MeshError, EigenError, IntegrationError, RequestError) as exc:
        return _failure("failed", f"{type(exc).__name__}: {exc}")


def _run(design: WheelDesign, job: CaseJob) -> dict:
    from geometry import wheel_mass
    from reduced import load_compiled_kernels

    from .. import api
    from ..budget import Budget
    from ..cache import StageCache
    from ..presets import fidelity_for
    from ..sound import Radiation, default_microphone, mode_radiation, sound_of
    from ..stability import envelope

    cache = None if job.cache_dir is None else StageCache(job.cache_dir or None)
    if "limit_cycle" in job.compute:
        load_compiled_kernels()  # a worker runs many simulations: compiled, from the first
    budget = Budget.from_environment(job.max_dofs)
    modes = api.compute_modes(design, job.fidelity, fmax_hz=job.fmax_hz, cache=cache, budget=budget)
    shape = (len(job.crab_velocities_m_s), len(job.rpm))
    out: dict = {"status": "ok", "reason": "", "mass_kg": wheel_mass(design), "modes": len(modes.modes)}
    nan = np.full(shape, np.nan)
    results = {k: nan.copy() for k in RESULT_FIELDS}
    label = np.full(shape, "", dtype=object)
    if "stability" in job.compute:
        contact = api.contact_law(design)
        env = envelope(design, modes, contact, job.crab_velocities_m_s, job.rpm)
        results["growth_rate_1_s"] = env.growth_rate_1_s
        microphone = default_microphone(design)
        key = api.modes_cache_key(design, fidelity_for(job.fidelity), job.fmax_hz)
        radiation: dict[int, Radiation] = {}
        for (i, j), w in np.ndenumerate(env.winner):
            if env.growth_rate_1_s[i, j] <= 0:
                continue  # nothing grows: no squeal here
            mode = env.modes[w]
            label[i, j] = f"n={mode.nodal_diameters},c={mode.nodal_circles},{mode.family}"
            results["frequency_hz"][i, j] = mode.frequency_hz
            if "limit_cycle" not in job.compute:
                continue
            op = api.operating_point(design, rpm=job.rpm[j], crab_velocity=job.crab_velocities_m_s[i])
            sim = api.simulate(api.modal_dof(mode, design), contact, op)
            amp = float(sim.limit_cycle.velocity_amplitude_m_s)
            results["amplitude_m_s"][i, j] = amp
            if "sound" in job.compute and amp > 0:
                if w not in radiation:
                    radiation[w] = mode_radiation(
                        design, modes, mode, mode.frequency_hz, microphone, cache, key
                    )
                levels = sound_of(radiation[w], amp, microphone).summary()
                results["spl_db"][i, j] = levels["spl_db"]
                results["sound_power_level_db"][i, j] = levels["sound_power_level_db"]
    out |= {k: v.tolist() for k, v in results.items()}
    out["squeal_mode"] = label.tolist()
    return out
