"""The ``cache`` command: inspect, limit or clear the stage cache."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from ..runtime.request_errors import RequestError
from ..runtime.stage_cache import ENV_SIZE, StageCache, parse_size

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("cache", help="inspect, limit or clear the stage cache")
    p.add_argument("action", choices=["clear", "info", "limit"])
    p.add_argument("size", nargs="?", help="with limit: the cache's size limit, like 500M or 5G (default 2G)")
    p.add_argument("--cache-dir", type=Path)


def run(args: argparse.Namespace) -> int:
    cache = StageCache(args.cache_dir)
    if args.action == "clear":
        print(f"removed {cache.clear()} cache entries from {cache.root}")
        return 0
    if args.action == "limit":
        if args.size is None:
            raise RequestError("cache limit takes a size, like 500M or 5G")
        cache.set_limit(parse_size(args.size))
    elif args.size is not None:
        raise RequestError(f"cache {args.action} takes no size")
    n, size = cache.info()
    limit = cache.max_bytes
    source = f" (from ${ENV_SIZE})" if os.environ.get(ENV_SIZE, "").strip() else ""
    print(
        f"{cache.root}: {n} entries, {size / 1e6:.1f} MB of {limit / 1e6:.0f} MB{source}; "
        "the least recently used go beyond it"
    )
    return 0
