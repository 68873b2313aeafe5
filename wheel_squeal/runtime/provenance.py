"""What a result was computed with: the hash of the code that computed it and the
versions of the libraries whose numbers it holds (a stage cache's keys, a study's cases,
a report's inputs)."""

from __future__ import annotations

import functools
import hashlib
import importlib.metadata
import importlib.util
from pathlib import Path

__all__ = ["CODE_PACKAGES", "code_version", "library_versions"]

#: The packages whose code computes a result (a study case's cache key, a report's
#: provenance): every package of the tool but its designs
CODE_PACKAGES = ("geometry", "contact", "fem", "reduced", "acoustics", "track", "wheel_squeal")


@functools.cache
def code_version(*packages: str) -> str:
    """Hash of the source of the given packages: a change of the code that computes a
    stage invalidates its entries."""
    h = hashlib.sha256()
    for pkg in packages:
        spec = importlib.util.find_spec(pkg)
        if spec is None or not spec.submodule_search_locations:
            raise ValueError(f"{pkg!r} is not a package")
        root = Path(next(iter(spec.submodule_search_locations)))
        for f in sorted(root.rglob("*.py")):
            h.update(f.relative_to(root.parent).as_posix().encode())
            h.update(f.read_bytes())
    return h.hexdigest()[:16]


@functools.cache
def library_versions(*distributions: str) -> dict[str, str]:
    """Installed versions of the libraries whose results a stage stores (an upgrade of
    SciPy or scikit-fem may change the last digits of every mode)."""
    out = {}
    for name in distributions:
        try:
            out[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            out[name] = "absent"
    return out
