"""Running a study: the cases on a local process pool or a dask.distributed cluster.

Each case is one task (:func:`~wheel_squeal.study.task.run_case`). Finished cases are
stored in the client's stage cache as they arrive, so a study that is interrupted and
started again computes only the cases still missing. A worker that dies takes its task
with it: on the local pool the pool is rebuilt and the unfinished cases are submitted
again (a case whose worker dies three times is recorded as failed); a dask scheduler
reschedules the tasks of a lost worker itself.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool

import numpy as np

from ..cache import CacheMiss, StageCache, code_version, library_versions
from ..errors import RequestError
from ..progress import Progress
from .spec import StudySpec
from .task import CODE_PACKAGES, CaseJob, run_case

__all__ = ["MAX_WORKER_DEATHS", "SCHEDULER_ENV", "case_results", "missing_dependencies"]

#: A case whose worker dies this many times is recorded as failed.
MAX_WORKER_DEATHS = 3
#: The environment variable dask itself reads for the scheduler's address.
SCHEDULER_ENV = "DASK_SCHEDULER_ADDRESS"


def _case_key(spec: StudySpec, changes) -> dict:
    return {
        "stage": "study-case",
        "spec": spec.digest(),
        "changes": [[k, repr(float(v))] for k, v in changes],
        "code": code_version(*CODE_PACKAGES),
        "libraries": library_versions("numpy", "scipy", "scikit-fem", "gmsh", "numba"),
    }


def case_results(
    spec: StudySpec,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    cache: StageCache | None = None,
    progress: Progress | None = None,
) -> list[dict]:
    """The result of every case of ``spec`` (in :meth:`StudySpec.cases` order).

    ``workers``: local processes (default: this machine's cores; 1 runs in this process);
    ``scheduler``: a dask.distributed scheduler address (default ``$DASK_SCHEDULER_ADDRESS``;
    then ``workers`` is not used); ``cache``: the stage cache of the FE and of the
    finished cases (None: neither is kept, and an interrupted study starts over).
    """
    progress = progress or Progress(quiet=True)
    scheduler = scheduler or os.environ.get(SCHEDULER_ENV) or None
    cases = spec.cases()
    keys = [_case_key(spec, c.changes) for c in cases]
    results: list[dict | None] = [None] * len(cases)
    if cache is not None:
        for i, key in enumerate(keys):
            try:
                results[i] = json.loads(str(cache.load("study", key)["result"]))
            except CacheMiss:
                pass
    todo = [i for i, r in enumerate(results) if r is None]
    # local workers share this machine's cache; a cluster's workers use their own
    # default one (a path here may not exist there)
    worker_cache = None if cache is None or not cache.enabled else ("" if scheduler else str(cache.root))
    jobs = {
        i: CaseJob(
            spec.base,
            cases[i].changes,
            spec.fidelity,
            spec.fmax_hz,
            spec.compute,
            spec.crab_velocities_m_s,
            spec.rpm,
            worker_cache,
        )  # fmt: skip
        for i in todo
    }
    where = f"dask scheduler {scheduler}" if scheduler else f"{_workers(workers)} local process(es)"
    progress.say(
        f"study {spec.name}: {len(cases)} cases, {len(cases) - len(todo)} from an earlier run, "
        f"{len(todo)} to compute on {where}"
    )
    report = progress.counter(f"study {spec.name}", "cases")

    def done(i: int, result: dict) -> None:
        results[i] = result
        if cache is not None:
            cache.store("study", keys[i], {"result": np.array(json.dumps(result))})
        report(sum(r is not None for r in results), len(results))

    if not todo:
        pass
    elif scheduler:
        _on_dask(scheduler, jobs, done)
    elif _workers(workers) == 1:
        for i, job in jobs.items():
            done(i, run_case(job))
    else:
        _on_pool(_workers(workers), jobs, done, progress)
    return results  # type: ignore[return-value]


def _workers(workers: int | None) -> int:
    if workers is None:
        return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    if workers < 1:
        raise RequestError(f"workers must be at least 1, got {workers}")
    return workers


def _on_pool(n: int, jobs: dict[int, CaseJob], done: Callable[[int, dict], None], progress: Progress) -> None:
    """Run ``jobs`` on ``n`` local processes; rebuild the pool when a worker dies."""
    deaths = dict.fromkeys(jobs, 0)
    pending = dict(jobs)
    while pending:
        with ProcessPoolExecutor(max_workers=min(n, len(pending))) as pool:
            futures = {pool.submit(run_case, job): i for i, job in pending.items()}
            broken = False
            while futures:
                finished, _ = wait(futures, return_when=FIRST_COMPLETED)
                for f in finished:
                    i = futures.pop(f)
                    try:
                        result = f.result()
                    except BrokenProcessPool:
                        broken = True
                        continue
                    del pending[i]
                    done(i, result)
                if broken:
                    break
        if broken:
            for f in futures:
                f.cancel()
            for i in list(pending):
                deaths[i] += 1
                if deaths[i] >= MAX_WORKER_DEATHS:
                    del pending[i]
                    done(
                        i,
                        {"status": "failed", "reason": f"its worker process died {MAX_WORKER_DEATHS} times"},
                    )
            progress.say(f"a worker process died: {len(pending)} case(s) submitted again")


def _on_dask(address: str, jobs: dict[int, CaseJob], done: Callable[[int, dict], None]) -> None:
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise RequestError(_MISSING) from None
    try:
        client = Client(address, timeout="20s")
    except (OSError, TimeoutError) as exc:
        raise RequestError(f"cannot reach the dask scheduler at {address}: {exc}") from None
    with client:
        order = list(jobs)
        futures = client.map(run_case, [jobs[i] for i in order], pure=False, retries=1)
        index = {f.key: i for f, i in zip(futures, order)}
        for future in as_completed(futures):
            done(index[future.key], future.result())


_MISSING = "the study command needs xarray and dask.distributed: pip install -e '.[study]'"


def missing_dependencies() -> str | None:
    """One line saying what to install, or None when the study extra is there."""
    try:
        import distributed  # noqa: F401
        import xarray  # noqa: F401
    except ImportError:
        return _MISSING
    return None
