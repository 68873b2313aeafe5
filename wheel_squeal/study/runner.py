"""Running a study: the cases on a local process pool or a dask.distributed cluster.

Each case is one task (:func:`~wheel_squeal.study.task.run_case`). Finished cases are
stored in the client's stage cache as they arrive, so a study that is interrupted and
started again computes only the cases still missing. An outcome the environment caused
(a worker that died, a refusal under a temporary budget) is reported but never stored:
the next run computes that case again. A local worker that dies is charged to the one
case it was running, which is submitted again (up to :data:`MAX_WORKER_DEATHS` times);
a dask scheduler reschedules the tasks of a lost worker itself.
"""

from __future__ import annotations

import functools
import json
import os
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from geometry.files import printable, stored_array

from ..api import check_modes_budget
from ..output_files import FLAG_FIELDS, LABEL_FIELDS, RESULT_FIELDS
from ..plan import estimate_study, study_plan
from ..presets import fidelity_for
from ..runtime.budget import Budget, usable_cores
from ..runtime.pools import KEPT_FREE_BYTES, Death, run_on_pool
from ..runtime.progress import Progress
from ..runtime.provenance import CODE_PACKAGES, code_version, library_versions
from ..runtime.request_errors import RequestError
from ..runtime.stage_cache import CacheMiss, StageCache
from .spec import StudySpec
from .task import CaseJob, run_case

__all__ = [
    "MAX_WORKER_DEATHS",
    "SCHEDULER_ENV",
    "case_results",
    "check_scheduler_address",
    "code_key",
    "local_workers",
    "missing_dependencies",
    "run_tasks",
    "scheduler_of",
    "store_result",
    "stored_results",
    "transient",
]

#: A case whose worker dies this many times is recorded as failed (for this run only).
MAX_WORKER_DEATHS = 3
#: The environment variable dask itself reads for the scheduler's address.
SCHEDULER_ENV = "DASK_SCHEDULER_ADDRESS"
#: Memory one local worker takes besides its case's modal solve [bytes]: the imports of
#: the chain and a case's arrays (measured about 300 MB, allowed 400 MB) and the freed
#: memory it keeps (``wheel_squeal.runtime.pools.KEPT_FREE_BYTES``).
WORKER_BYTES = 400e6 + KEPT_FREE_BYTES
#: Seconds to wait for a dask scheduler's handshake.
SCHEDULER_TIMEOUT_S = 5.0


def _key_base(spec: StudySpec) -> dict:
    """What every case key of ``spec`` holds (computed once per study)."""
    return {
        "spec": spec.digest(),
        **code_key(),
    }


def code_key() -> dict:
    """What every stored task's key holds of the code that computed it: this tool's
    packages and the numerical libraries."""
    return {
        "code": code_version(*CODE_PACKAGES),
        "libraries": library_versions("numpy", "scipy", "scikit-fem", "gmsh", "numba"),
    }


def scheduler_of(address: str | None) -> str | None:
    """The dask scheduler to use: ``address``, else ``$DASK_SCHEDULER_ADDRESS``, checked
    (:func:`check_scheduler_address`); None: none, the work stays on this machine."""
    address = address or os.environ.get(SCHEDULER_ENV) or None
    return check_scheduler_address(address) if address else None


def _case_key(base: dict, changes: Sequence[tuple[str, float]]) -> dict:
    return {"stage": "study-case", **base, "changes": [[k, repr(float(v))] for k, v in changes]}


def _started_key(base: dict) -> dict:
    """The key of the mark a study leaves in the cache when it starts computing: without
    it no case of the study is stored, and its estimate needs no look at its cases."""
    return {"stage": "study-started", **base}


def case_results(
    spec: StudySpec,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    cache: StageCache | None = None,
    progress: Progress | None = None,
    budget: Budget | None = None,
) -> list[dict]:
    """The result of every case of ``spec`` (in :meth:`StudySpec.cases` order).

    ``workers``: local processes (default: this machine's cores, at most what its
    memory holds, :func:`local_workers`; 1 runs in this process); ``scheduler``: a
    dask.distributed scheduler address (default ``$DASK_SCHEDULER_ADDRESS``; then
    ``workers`` is not used); ``cache``: the stage cache of the finished cases and, for a
    grid study, of the FE (None: neither is kept, and an interrupted study starts over);
    ``budget``: the limits the study is estimated against before any case runs (its
    time on the workers found, its results' memory) and each case's modal solve
    (default: :meth:`Budget.from_environment`).
    """
    progress = progress or Progress(quiet=True)
    budget = budget or Budget.from_environment()
    scheduler = scheduler_of(scheduler)
    cost = estimate_study(spec)
    check_modes_budget(spec.base, fidelity_for(spec.fidelity), spec.fmax_hz, budget)
    n_local = 1 if scheduler else local_workers(workers, progress)
    where = f"dask scheduler {scheduler}" if scheduler else f"{n_local} local process(es)"
    base = _key_base(spec)

    def check_time(parallel: int, count: int) -> None:
        study_plan(spec, cost, parallel, count).check(budget, "the study", "ask for less")

    if scheduler or _started(base, cache):
        study_plan(spec, cost, 1, 0).check(budget, "the study", "ask for less")  # its results' memory
    else:
        check_time(n_local, spec.n_cases)  # nothing stored: refused before its cases are made
    cases = spec.cases()
    keys = [_case_key(base, c.changes) for c in cases]
    grid = (len(spec.crabbing_velocities_m_s), len(spec.rpm))
    results = stored_results(keys, cache, lambda i, r: check_case_result(r, grid))
    todo = [i for i, r in enumerate(results) if r is None]
    if not scheduler:
        check_time(n_local, len(todo))
    if cache is not None and todo:
        cache.store("study", _started_key(base), {"started": np.array(True)})
    jobs = {i: _job(spec, cases[i].changes, _worker_cache(spec, cache, scheduler), budget) for i in todo}
    progress.say(
        f"study {spec.name}: {len(cases)} cases, {len(cases) - len(todo)} from an earlier run, "
        f"{len(todo)} to compute on {where}"
    )
    report = progress.counter(f"study {spec.name}", "cases")

    def done(i: int, result: dict) -> None:
        budget.checkpoint(f"the study's case {i}")
        results[i] = result
        store_result(cache, keys[i], result)
        report(sum(r is not None for r in results), len(results))

    run_tasks(jobs, run_case, done, n_local, scheduler, progress, lambda p: check_time(p, len(todo)))
    return results  # type: ignore[return-value]


def run_tasks(
    jobs: dict[int, Any],
    task: Callable[[Any], dict],
    done: Callable[[int, dict], None],
    n_local: int,
    scheduler: str | None,
    progress: Progress,
    check_time: Callable[[int], None],
) -> None:
    """``task(job)`` for every job, ``done(i, result)`` as each finishes: on the dask
    scheduler at ``scheduler``, in this process (``n_local`` 1) or on ``n_local`` local
    processes. A local worker that dies is charged to its job, which is run again up to
    :data:`MAX_WORKER_DEATHS` times, then given a transient failure; ``check_time(n)``
    refuses the work on n parallel workers once a cluster's size is known."""

    def died(death: Death) -> bool:
        if death.count >= MAX_WORKER_DEATHS:
            done(death.case, transient(f"its worker process died {death.count} times"))
            return False
        progress.say(f"a worker process died: case {death.case} submitted again")
        return True

    if not jobs:
        return
    if scheduler:
        _on_dask(scheduler, jobs, task, done, check_time)
    elif n_local == 1:
        for i, job in jobs.items():
            done(i, task(job))
    else:
        run_on_pool(n_local, jobs, task, done, died)


def store_result(cache: StageCache | None, key: dict, result: dict) -> None:
    """Keep a finished task's ``result`` under ``key``, unless the environment caused it."""
    if cache is not None and not result.get("transient"):
        cache.store("study", key, {"result": np.array(json.dumps(result))})


def stored_results(
    keys: list[dict], cache: StageCache | None, check: Callable[[int, dict], None] | None = None
) -> list[dict | None]:
    """The results of an earlier run of the same tasks (None where there is none).

    A stored result is read as untrusted (the cache is anyone's who can write it): a JSON
    object with a text ``status`` and ``reason``, and a finished one (``status`` "ok")
    what ``check(i, result)`` accepts for task ``i`` (it raises ``ValueError``,
    ``KeyError`` or ``TypeError`` otherwise); one that is not is a corrupt entry,
    computed again."""
    results: list[dict | None] = [None] * len(keys)
    if cache is None:
        return results

    def read(i: int, arrays: dict[str, np.ndarray]) -> dict:
        result = json.loads(str(stored_array(arrays, "result", "U", ndim=0)))
        if not (isinstance(result, dict) and isinstance(result.get("status"), str)):
            raise ValueError("a stored task result is not one")
        if not isinstance(result.get("reason"), str):
            raise ValueError("a stored task result has no reason")
        if check is not None and result["status"] == "ok":
            check(i, result)
        return result

    for i, key in enumerate(keys):
        try:
            results[i] = cache.load("study", key, functools.partial(read, i))
        except CacheMiss:
            pass
    return results


def check_case_result(result: dict, shape: tuple[int, int]) -> None:
    """A stored study case's ``result`` (:func:`.task.run_case`) as its writers read it:
    a grid of ``shape`` per field, of numbers, flags and printable labels."""
    float(result["mass_kg"])
    int(result["modes"])
    for fields, kinds in ((RESULT_FIELDS, "f"), (FLAG_FIELDS, "b"), (LABEL_FIELDS, "U")):
        for name in fields:
            grid = np.asarray(result[name])
            if grid.shape != shape or (
                grid.size and grid.dtype.kind not in (kinds + "i" if kinds == "f" else kinds)
            ):
                raise ValueError(f"a stored case's {name!r} is not a {shape} grid of its kind")
            if kinds == "U" and not all(printable(str(v)) for v in grid.flat):
                raise ValueError(f"a stored case's {name!r} holds a label that is not printable")


def _worker_cache(spec: StudySpec, cache: StageCache | None, scheduler: str | None) -> str | None:
    """The FE cache a worker uses: a grid's designs may be asked for again (another
    operating grid), a sample's not, so their modes are not kept. Local workers share
    this machine's cache; a cluster's workers use their own default one ("": a path
    here may not exist there)."""
    if cache is None or not cache.enabled or spec.samples:
        return None
    return "" if scheduler else str(cache.root)


def _job(spec: StudySpec, changes: tuple, worker_cache: str | None, budget: Budget) -> CaseJob:
    return CaseJob(
        spec.base,
        changes,
        spec.fidelity,
        spec.fmax_hz,
        spec.compute,
        spec.crabbing_velocities_m_s,
        spec.rpm,
        worker_cache,
        budget.max_dofs,
    )


def _started(base: dict, cache: StageCache | None) -> bool:
    """Whether a run of this study has stored its mark (:func:`_started_key`)."""
    if cache is None:
        return False
    try:
        cache.load("study", _started_key(base))
    except CacheMiss:
        return False
    return True


def transient(reason: str) -> dict:
    """A case's outcome caused by the environment: reported, never stored."""
    return {"status": "failed", "reason": reason, "transient": True}


def local_workers(requested: int | None, progress: Progress | None = None) -> int:
    """The local worker processes to use: ``requested`` (default: the cores), at most the
    cores this process may run on and what the free memory holds (:data:`WORKER_BYTES`
    each); a smaller number than requested is said on ``progress``."""
    from ..runtime.budget import MEMORY_FRACTION, available_memory

    if requested is not None and requested < 1:
        raise RequestError(f"workers must be at least 1, got {requested}")
    cores = usable_cores()
    memory = max(1, int(MEMORY_FRACTION * available_memory() // WORKER_BYTES))
    n = min(requested or cores, cores, memory)
    if requested is not None and n < requested and progress is not None:
        why = f"{cores} core(s)" if n == cores else f"memory for {memory}"
        progress.say(f"{requested} workers asked, {n} used ({why}): more would not run faster")
    return n


def check_scheduler_address(address: str) -> str:
    """``tcp://HOST:PORT`` (or ``HOST:PORT``) checked, as ``tcp://HOST:PORT``; any other
    form is refused (:class:`RequestError`) with what to give instead."""
    text = address.strip()
    what = f"scheduler {address!r}"
    if not text:
        raise RequestError(f"{what}: give the scheduler's address, tcp://HOST:8786")
    scheme, sep, rest = text.partition("://")
    if not sep:
        scheme, rest = "tcp", text
    if scheme in ("http", "https"):
        raise RequestError(
            f"{what} looks like the dashboard's web address; the scheduler listens on tcp://HOST:8786"
        )
    if scheme != "tcp":
        raise RequestError(f"{what}: only tcp://HOST:PORT schedulers are supported (not {scheme}://)")
    host, colon, port = rest.rstrip("/").rpartition(":")
    if not colon or not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise RequestError(f"{what}: expected tcp://HOST:PORT with a port from 1 to 65535")
    return f"tcp://{host}:{int(port)}"


def _reachable(address: str) -> None:
    """Refuse at once (RequestError) a scheduler whose port refuses or does not answer."""
    import socket

    host, _, port = address.removeprefix("tcp://").rpartition(":")
    try:
        socket.create_connection((host.strip("[]"), int(port)), timeout=SCHEDULER_TIMEOUT_S).close()
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise RequestError(f"cannot reach the dask scheduler at {address}: {reason}") from None


def _connect(client_type: Any, address: str) -> Any:
    """A dask Client of the scheduler at ``address``, or RequestError within a few
    seconds: the handshake runs in a thread given :data:`SCHEDULER_TIMEOUT_S` plus a
    margin, because a server that is not a scheduler (a web server on the port) can keep
    dask's own timeout from ever firing."""
    import threading

    outcome: dict = {}

    def connect() -> None:
        try:
            outcome["client"] = client_type(address, timeout=f"{SCHEDULER_TIMEOUT_S:g}s")
        except Exception as exc:  # reported below, in this thread
            outcome["error"] = exc

    thread = threading.Thread(target=connect, name="dask-handshake", daemon=True)
    thread.start()
    thread.join(SCHEDULER_TIMEOUT_S + 3.0)
    if "client" in outcome:
        return outcome["client"]
    error = outcome.get("error")
    why = (
        "no answer"
        if error is None or isinstance(error, TimeoutError)
        else f"the connection failed: {error.strerror}"
        if isinstance(error, OSError) and error.strerror
        else "something answers there, but not as a dask scheduler"
    )
    raise RequestError(f"no dask scheduler answers at {address} within {SCHEDULER_TIMEOUT_S:g} s ({why})")


def _on_dask(
    address: str,
    jobs: dict[int, Any],
    task: Callable[[Any], dict],
    done: Callable[[int, dict], None],
    check_time: Callable[[int], None],
) -> None:
    try:
        from distributed import Client, as_completed
        from distributed.scheduler import KilledWorker
    except ImportError:
        raise RequestError(_MISSING) from None
    _reachable(address)
    client = _connect(Client, address)
    with client:
        check_time(max(1, sum(client.nthreads().values())))
        order = list(jobs)
        futures = client.map(task, [jobs[i] for i in order], pure=False, retries=1)
        index = {f.key: i for f, i in zip(futures, order)}
        for future in as_completed(futures):
            try:
                result = future.result()
            except KilledWorker as exc:
                result = transient(f"its dask workers died ({exc})")
            done(index[future.key], result)


_MISSING = "the study command needs xarray and dask.distributed: pip install -e '.[study]'"


def missing_dependencies() -> str | None:
    """One line saying what to install, or None when the study extra is there."""
    try:
        import distributed  # noqa: F401
        import xarray  # noqa: F401
    except ImportError:
        return _MISSING
    return None
