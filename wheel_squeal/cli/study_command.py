"""The ``study`` command: many designs (grid or samples) over an operating grid, locally or on dask."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..runtime.progress import Progress
from ..runtime.request_errors import RequestError
from ..runtime.result_folders import result_folder
from .common import budget_of, cache_of, out_of
from .options import add_budget, add_cache, add_out, add_workers

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser(
        "study", help="many designs (grid or samples) over an operating grid, locally or on dask"
    )
    p.add_argument("spec", type=Path, help="study specification TOML (see studies/)")
    add_out(p)
    add_workers(p)
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    add_cache(p)
    add_budget(p)


def run(args: argparse.Namespace) -> int:
    from ..study.runner import missing_dependencies

    missing = missing_dependencies()
    if missing:
        raise RequestError(missing)
    from ..study import load_spec
    from ..study.dataset import study_dataset, write_study_files
    from ..study.runner import case_results

    spec = load_spec(args.spec)
    progress = Progress(args.quiet)
    cache = None if args.no_cache else cache_of(args)
    # the staging folder exists before the work: an unusable --out is refused at once
    out = out_of(args, spec.name)
    with result_folder(out, "study") as tmp:
        results = case_results(
            spec,
            workers=args.workers,
            scheduler=args.scheduler,
            cache=cache,
            progress=progress,
            budget=budget_of(args),
        )
        ds = study_dataset(spec, results)
        files = write_study_files(ds, spec, tmp)
    status = ds["status"].values.ravel()
    counts = {s: int((status == s).sum()) for s in ("ok", "invalid", "failed")}
    print(
        f"study {spec.name}: {status.size} designs ({counts['ok']} ok, {counts['invalid']} invalid, "
        f"{counts['failed']} failed) x {ds.sizes['crab_velocity']} crabbing velocities x "
        f"{ds.sizes['rpm']} speeds"
    )
    from ..study.dataset import study_summary

    print("\n".join(study_summary(ds, spec)))
    print(f"files: {out}/ ({', '.join(files)})")
    return 0
