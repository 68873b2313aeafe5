"""The stage cache: content-addressed results of the expensive stages (mesh, modes, views).

An entry is ``ROOT/STAGE/DIGEST.npz``: DIGEST is the SHA-256 of the entry's key (a JSON
dict of everything the stage depends on); the file carries its key, a checksum of its
arrays and the tool's name (:data:`ENTRY_TOOL`), so a corrupt, truncated or foreign entry
is reported in one line and recomputed. Writes are atomic (a temporary file, then a
rename), so concurrent runs sharing a cache never see half an entry, and two runs
storing the same entry store the same bytes.

The cache touches only what it wrote. Its root holds the marker :data:`MARKER`; a folder
that is neither empty nor marked is refused as a cache (:class:`RequestError`), and
:meth:`StageCache.clear` deletes only entries that carry the tool's name, in stage
folders of a marked root. A cache that cannot be written (read-only, full, or an entry
path taken by a folder) is used for reading; the first failed store gives one warning
and the run goes on without storing.

Location: ``--cache-dir``, else ``$WHEEL_SQUEAL_CACHE`` (an empty value counts as unset),
else ``$XDG_CACHE_HOME/wheel-squeal`` (``~/.cache/wheel-squeal``).

Size: the entries are kept under a limit (:data:`DEFAULT_MAX_BYTES`, or the cache's
own setting, ``cache limit SIZE``, or ``$WHEEL_SQUEAL_CACHE_SIZE``); after a store
beyond it the least recently used entries are removed (a load refreshes an entry's
time), except those used in the last :data:`IN_USE_S` seconds, which a running process
may still read back. An entry larger than :data:`MAX_ENTRY_FRACTION` of the limit is
not stored at all (one warning): it would evict everything else and be evicted next. An
entry is written straight from its arrays to the file (no copy of it in memory).
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import math
import os
import re
import shutil
import stat
import sys
import time
import typing
import zipfile
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from geometry.files import atomic_file, quoted, write_atomic

from .entry_reading import checksum, entry_bytes, is_regular, read_entry, read_small
from .request_errors import RequestError

__all__ = [
    "DEFAULT_MAX_BYTES",
    "ENV_SIZE",
    "CacheMiss",
    "ENV_VAR",
    "MARKER",
    "StageCache",
    "LIBRARIES_FOLDER",
    "default_cache_root",
    "parse_size",
]

ENV_VAR = "WHEEL_SQUEAL_CACHE"
#: The size limit's environment variable, and its default (a few hundred designs'
#: modes and sound fields, small beside a laptop's disk).
ENV_SIZE = "WHEEL_SQUEAL_CACHE_SIZE"
DEFAULT_MAX_BYTES = 2 * 10**9
#: Entries used this recently [s] are never evicted: a running process may read them.
IN_USE_S = 600.0
#: The largest entry stored, as a fraction of the cache's size limit.
MAX_ENTRY_FRACTION = 0.5
_UNITS = {"": 1, "B": 1} | {
    u + b: 10**e for e, u in ((3, "K"), (6, "M"), (9, "G"), (12, "T")) for b in ("", "B")
}
#: The file that marks a folder as a stage cache of this tool.
MARKER = ".wheel-squeal-cache"
#: The tool's name in every entry's metadata.
ENTRY_TOOL = "wheel-squeal"
_ENTRY = re.compile(r"[0-9a-f]{32}\.npz")
_TMP = re.compile(r"[0-9a-f]{32}\.npz\..+\.tmp")
#: Stage folders an unmarked cache written by an earlier version may hold (adopted).
_LEGACY_STAGES = {"mesh2d", "mesh3d", "modes", "views"}


#: The folder of the libraries' own caches (numba's compiled kernels, matplotlib's font
#: list, Mesa's shaders: ``wheel_squeal.runtime.library_folders``), and the folder an earlier
#: version kept numba's kernels in (a cache that holds it is still a cache)
LIBRARIES_FOLDER, LEGACY_COMPILED_FOLDER = "libraries", "compiled"


def default_cache_root() -> Path:
    """``$WHEEL_SQUEAL_CACHE`` if set and not empty, else the user's cache folder."""
    env = os.environ.get(ENV_VAR, "").strip()
    if env:
        return Path(env).expanduser()
    base = os.environ.get("XDG_CACHE_HOME", "").strip()
    return (Path(base) if base else Path.home() / ".cache") / "wheel-squeal"


def parse_size(text: str) -> int:
    """Bytes of a size like ``500M``, ``2G``, ``1.5GB`` or ``1000000``; RequestError
    otherwise."""
    m = re.fullmatch(r"\s*([0-9]*\.?[0-9]+(?:[eE][+-]?[0-9]+)?)\s*([A-Za-z]*)\s*", text)
    unit = m.group(2).upper() if m else None
    if m is None or unit not in _UNITS:
        raise RequestError(f"cache size {text!r}: give bytes or a size like 500M or 2G")
    size = float(m.group(1)) * _UNITS[unit]
    if not size >= 1e6:
        raise RequestError(f"cache size {text!r}: at least 1M")
    return int(size)


class CacheMiss(Exception):
    """No usable entry for the key (absent, corrupt or foreign)."""


class StageCache:
    """Content-addressed store for expensive stages (see the module docstring).

    ``root``: the cache folder (default :func:`default_cache_root`); ``enabled=False``
    makes every load a miss and every store a no-op without touching the disk.
    ``hits`` / ``misses`` list the stages served and recomputed, in order.
    """

    def __init__(
        self, root: Path | str | None = None, enabled: bool = True, warn: Callable[[str], None] | None = None
    ) -> None:
        self.root = Path(root).expanduser() if root is not None else default_cache_root()
        self.enabled = enabled
        self.warn = warn or (lambda msg: print(f"warning: {msg}", file=sys.stderr))
        self.hits: list[str] = []
        self.misses: list[str] = []
        self.writable = True
        self._too_large_warned = False
        if enabled:
            self._check_root()
            self.max_bytes  # noqa: B018 (a bad $WHEEL_SQUEAL_CACHE_SIZE is refused before any work)

    # -- the root -----------------------------------------------------------------------
    def _check_root(self) -> None:
        root = self.root
        for p in (root, *root.parents):
            if p.exists() or p.is_symlink():
                if not p.is_dir():
                    raise RequestError(f"cache folder {root}: {p} is not a folder")
                break
        if root.is_dir() and not (root / MARKER).is_file():
            try:
                children = {c.name for c in os.scandir(root)}
            except OSError as exc:
                raise RequestError(f"cache folder {root} cannot be read ({exc.strerror})") from None
            # a concurrent run may have made the libraries' folder before its first store
            # writes the marker: that folder is ours too
            if children - _LEGACY_STAGES - {LIBRARIES_FOLDER, LEGACY_COMPILED_FOLDER}:
                raise RequestError(
                    f"cache folder {root} is not empty and not a wheel-squeal cache (no {MARKER}): "
                    f"choose an empty or new folder for the cache"
                )

    def _ensure_root(self) -> bool:
        """Create the root and its marker on the first store; False if it cannot be."""
        if is_regular(self.root / MARKER):
            return True
        try:
            self.root.mkdir(parents=True, exist_ok=True)
            write_atomic(self.root / MARKER, json.dumps({"tool": ENTRY_TOOL}) + "\n")
        except OSError as exc:
            self.cannot_store(exc)
            return False
        return True

    def cannot_store(self, exc: OSError) -> None:
        """The one path of every write that failed (an entry, the marker, a library's
        own cache): the first gives one warning, and the run goes on without storing."""
        if self.writable:
            self.warn(
                f"cache folder {self.root} cannot be written ({exc.strerror or exc}); "
                "going on without storing results"
            )
        self.writable = False

    def folder(self, name: str) -> Path | None:
        """The cache's own folder ``name`` below :data:`LIBRARIES_FOLDER` (a library's
        cache), made if need be; None where the cache is off or cannot be written (after
        :meth:`cannot_store`'s one warning), or where the folder is a link (never followed)."""
        if not (self.enabled and self.writable and self._ensure_root()):
            return None
        path = self.root / LIBRARIES_FOLDER / name
        try:
            for p in (path.parent, path):
                p.mkdir(exist_ok=True)
                if not stat.S_ISDIR(os.lstat(p).st_mode):
                    return None
        except OSError as exc:
            self.cannot_store(exc)
            return None
        return path

    # -- entries ------------------------------------------------------------------------
    @staticmethod
    def digest(key: dict) -> str:
        return hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()

    def path(self, stage: str, key: dict) -> Path:
        return self.root / stage / f"{self.digest(key)[:32]}.npz"

    @typing.overload
    def load(self, stage: str, key: dict) -> dict[str, np.ndarray]: ...

    @typing.overload
    def load(self, stage: str, key: dict, read: Callable[[dict[str, np.ndarray]], T]) -> T: ...

    def load(self, stage: str, key: dict, read: Callable[[dict[str, np.ndarray]], Any] | None = None) -> Any:
        """The entry's arrays, or what ``read`` makes of them; raises :class:`CacheMiss`.

        An entry is input that anyone who can write the cache could have made, so it is
        read as untrusted: a regular file only (a link, a pipe or a device is never
        opened, nor is a stage folder that is a link), at most the cache's size limit, an
        uncompressed archive of plain arrays whose every header (type, shape, size) is
        checked before its data is read, its key and checksum, and then ``read`` (the
        record's own checks: a ``ValueError``, ``KeyError``, ``TypeError`` or
        ``IndexError`` there means the entry does not hold what its stage holds). An
        entry that fails any of these is corrupt: one warning, and the stage is
        computed again."""
        if not self.enabled:
            raise CacheMiss
        p = self.path(stage, key)
        if not os.path.lexists(p):
            self.misses.append(stage)
            raise CacheMiss
        try:
            arrays = read_entry(p, self.max_bytes)
            meta = json.loads(str(arrays.pop("__meta__")))
            if not isinstance(meta, dict) or meta.get("key") != key:
                raise ValueError("entry belongs to another key")
            if meta.get("checksum") != checksum(arrays):
                raise ValueError("checksum mismatch")
            value = arrays if read is None else read(arrays)
        except (OSError, ValueError, KeyError, TypeError, IndexError, zipfile.BadZipFile, EOFError) as exc:
            reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            self.warn(f"cache entry {p} is corrupt or foreign ({quoted(reason)}); recomputing {stage}")
            self.misses.append(stage)
            raise CacheMiss from None
        self.hits.append(stage)
        with contextlib.suppress(OSError):
            os.utime(p, follow_symlinks=False)  # recently used: the last to be evicted
        return value

    def store(self, stage: str, key: dict, arrays: dict[str, np.ndarray]) -> None:
        """Store an entry atomically; a cache that cannot be written is warned about once."""
        if not (self.enabled and self.writable):
            return
        size, limit = entry_bytes(arrays), self.max_bytes
        if size > MAX_ENTRY_FRACTION * limit:
            if not self._too_large_warned:
                self.warn(
                    f"the {stage} entry ({size / 1e9:.3g} GB) is more than {MAX_ENTRY_FRACTION:.0%} of the "
                    f"cache's limit ({limit / 1e9:.3g} GB): not stored (raise the limit with "
                    f"'cache limit SIZE' or {ENV_SIZE})"
                )
                self._too_large_warned = True
            return
        if not self._ensure_root():
            return
        p = self.path(stage, key)
        meta = json.dumps({"tool": ENTRY_TOOL, "key": key, "checksum": checksum(arrays)})
        payload: dict[str, Any] = {"__meta__": np.array(meta), **arrays}
        try:
            p.parent.mkdir(exist_ok=True)
            if not stat.S_ISDIR(os.lstat(p.parent).st_mode):  # a link planted for the folder
                raise OSError(errno.ENOTDIR, "the stage folder is not a folder", str(p.parent))
            with atomic_file(p) as f:
                np.savez(f, **payload)
        except OSError as exc:
            self.cannot_store(exc)
            return
        self.evict()

    # -- housekeeping -------------------------------------------------------------------
    def _entries(self) -> list[Path]:
        if not self.root.is_dir():
            return []
        out = []
        for stage_dir in sorted(_stage_dirs(self.root)):
            out += [
                Path(stage_dir) / name
                for name in sorted(os.listdir(stage_dir))
                if _ENTRY.fullmatch(name)
                and is_regular(Path(stage_dir) / name)
                and _is_entry(Path(stage_dir) / name)
            ]
        return out

    def info(self) -> tuple[int, int]:
        """(number of entries, their total size in bytes)."""
        entries = self._entries()
        return len(entries), sum(f.lstat().st_size for f in entries)

    # -- size --------------------------------------------------------------------------
    @property
    def max_bytes(self) -> int:
        """The size limit: ``$WHEEL_SQUEAL_CACHE_SIZE``, else the cache's own setting
        (:meth:`set_limit`), else :data:`DEFAULT_MAX_BYTES`."""
        env = os.environ.get(ENV_SIZE, "").strip()
        if env:
            try:
                return parse_size(env)
            except RequestError as exc:
                raise RequestError(f"{ENV_SIZE}={env!r}: {exc}") from None
        try:
            own = json.loads(read_small(self.root / MARKER)).get("max_bytes")
        except (OSError, ValueError, AttributeError):
            own = None
        return int(own) if isinstance(own, int | float) and own >= 1e6 else DEFAULT_MAX_BYTES

    def set_limit(self, max_bytes: int) -> None:
        """Keep ``max_bytes`` as this cache's size limit (in its marker), and evict down
        to it now."""
        if not self._ensure_root():
            raise RequestError(f"cache folder {self.root} cannot be written")
        marker = self.root / MARKER
        try:
            data = json.loads(read_small(marker))
        except (OSError, ValueError):
            data = {}
        data = {**(data if isinstance(data, dict) else {}), "tool": ENTRY_TOOL, "max_bytes": int(max_bytes)}
        try:
            write_atomic(marker, json.dumps(data) + "\n")
        except OSError as exc:
            raise RequestError(f"cache folder {self.root} cannot be written ({exc.strerror})") from None
        self.evict()

    def evict(self) -> int:
        """Remove the least recently used entries until the cache is under its limit,
        sparing those used in the last :data:`IN_USE_S` seconds; returns how many went."""
        limit = self.max_bytes
        entries = []
        for stage_dir in _stage_dirs(self.root):
            with contextlib.suppress(OSError), os.scandir(stage_dir) as it:
                for e in it:
                    if _ENTRY.fullmatch(e.name) and e.is_file(follow_symlinks=False):
                        with contextlib.suppress(OSError):
                            st = e.stat(follow_symlinks=False)
                            entries.append((st.st_mtime, st.st_size, e.path))
        total = sum(size for _, size, _ in entries)
        if total <= limit:
            return 0
        removed = 0
        now = time.time()
        for mtime, size, path in sorted(entries):
            if total <= 0.9 * limit or now - mtime < IN_USE_S:
                break  # down to 90 %: the next stores do not evict one by one
            if _is_entry(Path(path)):
                with contextlib.suppress(OSError):
                    os.unlink(path)
                    total -= size
                    removed += 1
        return removed

    def clear(self) -> int:
        """Remove every entry this tool wrote; returns how many. Refuses a folder that is
        not a cache (no marker); leaves anything else in it where it is."""
        if not self.root.exists():
            return 0
        marked = is_regular(self.root / MARKER)
        if not marked:
            self._check_root()  # refuses a folder that is not (even an unmarked) cache
        n = 0
        try:
            for f in self._entries():
                f.unlink()
                n += 1
            for stage_dir in map(Path, _stage_dirs(self.root)):
                if stage_dir.name in (LIBRARIES_FOLDER, LEGACY_COMPILED_FOLDER):
                    shutil.rmtree(stage_dir)  # the libraries' own caches: the tool made them
                    continue
                for f in stage_dir.iterdir():
                    if _TMP.fullmatch(f.name) and is_regular(f):
                        f.unlink()
                with contextlib.suppress(OSError):
                    stage_dir.rmdir()
        except OSError as exc:
            raise RequestError(
                f"cache folder {self.root} cannot be cleared ({exc.strerror or exc}); {n} entries removed"
            ) from None
        # the root goes only if this tool made it (its marker): a user's empty folder stays
        if marked and {c.name for c in self.root.iterdir()} <= {MARKER}:
            with contextlib.suppress(OSError):
                (self.root / MARKER).unlink(missing_ok=True)
                self.root.rmdir()
        return n


def _stage_dirs(root: Path) -> list[str]:
    try:
        with os.scandir(root) as it:
            return [e.path for e in it if e.is_dir(follow_symlinks=False)]
    except OSError:
        return []


def _is_entry(path: Path) -> bool:
    """True if ``path`` (named like an entry, in a stage folder) is one this tool wrote:
    its metadata says so, or it is damaged beyond reading (a corrupt entry). A readable
    array file without the metadata is somebody else's and stays."""
    try:
        arrays = read_entry(path, math.inf, only="__meta__")
        if "__meta__" not in arrays:
            return False
        meta = json.loads(str(arrays["__meta__"]))
    except (OSError, ValueError, KeyError, TypeError, zipfile.BadZipFile, EOFError):
        return True
    return isinstance(meta, dict) and "key" in meta and "checksum" in meta


T = TypeVar("T")
