"""A whole result kept in the stage cache: a command asked again with nothing changed (its
arguments, every file they name, the design's content, the code and the libraries) puts
the files it wrote then in place again and says what it said, instead of solving,
integrating, radiating and drawing it all once more.

What a result holds that is not the result (summary.json's ``timings_s`` and ``cache``)
is the new request's: how long it took, and that the result came from the cache."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

import numpy as np

from .cache import CacheMiss, StageCache
from .provenance import CODE_PACKAGES, code_version, library_versions

__all__ = ["RESULT_STAGE", "restore_result", "result_key", "store_result"]

#: The cache's stage of whole results
RESULT_STAGE = "result"
#: A command's arguments that do not change its result
NOT_THE_RESULT = frozenset(
    {"out", "quiet", "cache_dir", "no_cache", "max_seconds", "max_dofs", "func", "command"}
)
#: The printed text's entry name (no file a command writes is named so)
TEXT = "__stdout__"


def _value(x: Any) -> Any:
    """A JSON value for an argument; a file it names by its content's hash too."""
    if isinstance(x, (bool, int, float, str)) or x is None:
        if isinstance(x, str) and Path(x).is_file():
            return {"file": x, "sha256": hashlib.sha256(Path(x).read_bytes()).hexdigest()}
        return x
    if isinstance(x, Path):
        return _value(str(x))
    if isinstance(x, (list, tuple)):
        return [_value(v) for v in x]
    return repr(x)


def result_key(command: str, args: dict[str, Any], design_hash: str) -> dict[str, Any]:
    """What ``command``'s result depends on: its arguments (files by content), the
    design's content, the code of every package and the libraries it runs on."""
    kept = {
        k: _value(v) for k, v in sorted(args.items()) if k not in NOT_THE_RESULT and not k.startswith("_")
    }
    return {
        "stage": RESULT_STAGE,
        "command": command,
        "arguments": kept,
        "design": design_hash,
        "code": code_version(*CODE_PACKAGES),
        "libraries": library_versions("numpy", "scipy", "scikit-fem", "gmsh", "matplotlib", "pyvista"),
    }


def store_result(cache: StageCache, key: dict[str, Any], folder: Path, text: str) -> None:
    """Keep every file of ``folder`` (the staged result) and the printed ``text``."""
    arrays = {
        p.name: np.frombuffer(p.read_bytes(), dtype=np.uint8)
        for p in sorted(folder.iterdir())
        if p.is_file() and not p.name.startswith(".")
    }
    arrays[TEXT] = np.frombuffer(text.encode(), dtype=np.uint8)
    cache.store(RESULT_STAGE, key, arrays)


def restore_result(
    cache: StageCache, key: dict[str, Any], folder: Path, timings_s: dict[str, float]
) -> str | None:
    """Put the kept result's files into ``folder`` (its summary.json with this request's
    ``timings_s`` and cache use) and return its printed text; None: not kept."""
    try:
        arrays = cache.load(RESULT_STAGE, key)
    except CacheMiss:
        return None
    for name, data in arrays.items():
        if name == TEXT:
            continue
        payload = data.tobytes()
        if name == "summary.json":
            summary = json.loads(payload)
            summary["timings_s"] = timings_s
            summary["cache"] = {"hits": [RESULT_STAGE], "misses": []}
            payload = (json.dumps(summary, indent=2) + "\n").encode()
        (folder / name).write_bytes(payload)
    return arrays[TEXT].tobytes().decode()
