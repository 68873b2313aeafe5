"""Where the libraries the tool runs on keep their own files: in the stage cache, never in
the user's home folder or beside the installed package.

numba keeps the squeal model's compiled kernels, matplotlib its font list and settings,
Mesa (the off-screen rendering) its compiled shaders: each, left alone, writes into
``~/.cache``, ``~/.config`` or the package's ``__pycache__``, which the tool does not own.
Each reads its folder from an environment variable when it starts, so a command sets them
once, at its start and before any of the three is loaded (:func:`keep_library_files`):

- with a cache, in the cache's own folders (``CACHE/libraries/numba``, ``.../matplotlib``,
  ``.../mesa``), written through its one path for failed writes (``StageCache.folder``:
  a cache that cannot be written gives one warning, then the files go to a temporary
  folder);
- without one (``--no-cache``) or where it cannot be written, in one temporary folder that
  the command removes when it ends (:meth:`LibraryFolders.remove`), however it ends.

A variable the user has set is left as it is (their choice of folder), as is a library
already loaded (a notebook's matplotlib). gmsh's own preference files are its session's
(``geometry.gmsh_mesh``)."""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from .stage_cache import StageCache

__all__ = ["LIBRARY_FOLDERS", "LibraryFolders", "keep_library_files"]

#: library -> (the module whose import reads the variable, the variable, the cache folder)
LIBRARY_FOLDERS = {
    "numba": ("numba", "NUMBA_CACHE_DIR", "numba"),
    "matplotlib": ("matplotlib", "MPLCONFIGDIR", "matplotlib"),
    "mesa": ("vtkmodules", "MESA_SHADER_CACHE_DIR", "mesa"),
}
#: Mesa's own bound on its shader cache (its default is 1 GB); the tool's few shaders take
#: a few MB
MESA_SHADER_CACHE_MAX_SIZE = "50M"


@dataclass
class LibraryFolders:
    """The folders a command gave the libraries (library -> folder) and the temporary
    folder it made for them, if any (removed by :meth:`remove`)."""

    folders: dict[str, Path] = field(default_factory=dict)
    temporary: Path | None = None

    def remove(self) -> None:
        """Remove the temporary folder (the cache's folders stay: they are the cache)."""
        if self.temporary is not None:
            shutil.rmtree(self.temporary, ignore_errors=True)
            self.temporary = None


def keep_library_files(cache: StageCache | None) -> LibraryFolders:
    """Point each library's own files into ``cache`` (module docstring), or into one
    temporary folder where there is no usable cache; returns what was chosen."""
    chosen = LibraryFolders()
    for library, (module, variable, name) in LIBRARY_FOLDERS.items():
        if module in sys.modules or os.environ.get(variable, "").strip():
            continue
        folder = cache.folder(name) if cache is not None and cache.enabled else None
        if folder is None:
            if chosen.temporary is None:
                chosen.temporary = Path(tempfile.mkdtemp(prefix="wheel-squeal-libraries-"))
            folder = chosen.temporary / name
            folder.mkdir()
        os.environ[variable] = str(folder)
        chosen.folders[library] = folder
    if "mesa" in chosen.folders:
        os.environ.setdefault("MESA_SHADER_CACHE_MAX_SIZE", MESA_SHADER_CACHE_MAX_SIZE)
    return chosen
