"""A whole result kept in the stage cache: a command asked again with nothing changed (its
arguments, every file they name, the design's content, the code and the libraries) puts
the files it wrote then in place again and says what it said, instead of solving,
integrating, radiating and drawing it all once more.

What a result holds that is not the result (summary.json's ``timings_s`` and ``cache``)
is the new request's: how long it took, and that the result came from the cache."""

from __future__ import annotations

import hashlib
import json
import os
import stat
from pathlib import Path
from typing import Any

import numpy as np

from geometry.files import MAX_TEXT_BYTES

from .runtime.entry_reading import kept_files
from .runtime.provenance import CODE_PACKAGES, code_version, library_versions
from .runtime.stage_cache import CacheMiss, StageCache

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
    """A JSON value for an argument; a file argument (the parser's ``type=Path``) by its
    content's hash too. Only a file argument is read, and only a regular file within the
    input files' size limit: a larger one, or a pipe or a device, is refused by its own
    reader, whatever the key says."""
    if isinstance(x, Path):
        digest = _file_digest(x)
        return str(x) if digest is None else {"file": str(x), "sha256": digest}
    if isinstance(x, (bool, int, float, str)) or x is None:
        return x
    if isinstance(x, (list, tuple)):
        return [_value(v) for v in x]
    return repr(x)


def _file_digest(path: Path) -> str | None:
    """The SHA-256 of the regular file ``path`` of at most :data:`MAX_TEXT_BYTES`; None
    for anything else (no file, a folder, a pipe, a device, too large)."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except OSError:
        return None
    with os.fdopen(fd, "rb") as f:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode) or st.st_size > MAX_TEXT_BYTES:
            return None
        return hashlib.sha256(f.read(MAX_TEXT_BYTES + 1)).hexdigest()


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
        files = cache.load(RESULT_STAGE, key, _kept_result)
    except CacheMiss:
        return None
    text = files.pop(TEXT).decode()
    for name, payload in files.items():
        if name == "summary.json":
            summary = json.loads(payload)
            summary["timings_s"] = timings_s
            summary["cache"] = {"hits": [RESULT_STAGE], "misses": []}
            payload = (json.dumps(summary, indent=2) + "\n").encode()
        (folder / name).write_bytes(payload)
    return text


def _kept_result(arrays: dict[str, np.ndarray]) -> dict[str, bytes]:
    """A kept result's files and printed text, checked before any is written or shown
    (:func:`.cache.kept_files`: plain names within the result, printable text)."""
    files = kept_files(arrays, text=TEXT)
    if "summary.json" in files and not isinstance(json.loads(files["summary.json"]), dict):
        raise ValueError("the kept summary.json is not a summary")
    return files
