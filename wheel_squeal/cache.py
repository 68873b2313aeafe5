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
import hashlib
import json
import os
import re
import sys
import time
import zipfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from geometry.files import atomic_file, write_atomic

from .errors import RequestError

__all__ = [
    "DEFAULT_MAX_BYTES",
    "ENV_SIZE",
    "CacheMiss",
    "ENV_VAR",
    "MARKER",
    "StageCache",
    "keep_compiled_code_in",
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


#: The cache's folder of numba's machine code for the squeal model's kernels, and the
#: environment variable numba reads it from
COMPILED_FOLDER, NUMBA_CACHE_ENV = "compiled", "NUMBA_CACHE_DIR"


def keep_compiled_code_in(folder: Path) -> None:
    """Have numba keep the kernels' machine code in ``folder`` (the stage cache's) instead
    of beside the installed package, which may be read-only and is not the tool's to
    write. Set before numba is imported (it reads the variable then); a
    ``NUMBA_CACHE_DIR`` the user set is left as it is."""
    if "numba" in sys.modules or os.environ.get(NUMBA_CACHE_ENV, "").strip():
        return
    os.environ[NUMBA_CACHE_ENV] = str(folder)


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


def _human(n: float) -> str:
    return f"{n / 1e9:.2f} GB" if n >= 1e9 else f"{n / 1e6:.1f} MB"


class CacheMiss(Exception):
    """No usable entry for the key (absent, corrupt or foreign)."""


def _checksum(arrays: dict[str, np.ndarray]) -> str:
    h = hashlib.sha256()
    for k in sorted(arrays):
        a = np.ascontiguousarray(arrays[k])
        h.update(k.encode())
        h.update(str(a.dtype).encode())
        h.update(str(a.shape).encode())
        h.update(a.reshape(-1).view(np.uint8).data if a.size else b"")  # the buffer itself, no copy
    return h.hexdigest()


def entry_bytes(arrays: dict[str, np.ndarray]) -> int:
    """The size an entry of ``arrays`` takes on disk, near enough [bytes]."""
    return sum(int(np.asarray(a).nbytes) + 256 for a in arrays.values()) + 4096


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
            keep_compiled_code_in(self.root / COMPILED_FOLDER)

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
            # numba may write the kernels' machine code before this process's first store
            # writes the marker: a concurrent run's ``compiled`` folder is ours too
            if children - _LEGACY_STAGES - {COMPILED_FOLDER}:
                raise RequestError(
                    f"cache folder {root} is not empty and not a wheel-squeal cache (no {MARKER}): "
                    f"choose an empty or new folder for the cache"
                )

    def _ensure_root(self) -> bool:
        """Create the root and its marker on the first store; False if it cannot be."""
        if (self.root / MARKER).is_file():
            return True
        try:
            self.root.mkdir(parents=True, exist_ok=True)
            (self.root / MARKER).write_text(json.dumps({"tool": ENTRY_TOOL}) + "\n")
        except OSError as exc:
            self._cannot_store(exc)
            return False
        return True

    def _cannot_store(self, exc: OSError) -> None:
        if self.writable:
            self.warn(
                f"cache folder {self.root} cannot be written ({exc.strerror or exc}); "
                "going on without storing results"
            )
        self.writable = False

    # -- entries ------------------------------------------------------------------------
    @staticmethod
    def digest(key: dict) -> str:
        return hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()

    def path(self, stage: str, key: dict) -> Path:
        return self.root / stage / f"{self.digest(key)[:32]}.npz"

    def load(self, stage: str, key: dict) -> dict[str, np.ndarray]:
        """The entry's arrays; raises :class:`CacheMiss` (after one warning if the entry
        exists but is unusable)."""
        if not self.enabled:
            raise CacheMiss
        p = self.path(stage, key)
        if not os.path.lexists(p):
            self.misses.append(stage)
            raise CacheMiss
        try:
            with np.load(p, allow_pickle=False) as z:
                arrays = {k: z[k] for k in z.files}
            meta = json.loads(str(arrays.pop("__meta__")))
            if meta.get("key") != key:
                raise ValueError("entry belongs to another key")
            if meta.get("checksum") != _checksum(arrays):
                raise ValueError("checksum mismatch")
        except (OSError, ValueError, KeyError, zipfile.BadZipFile, EOFError) as exc:
            self.warn(f"cache entry {p} is corrupt or foreign ({exc}); recomputing {stage}")
            self.misses.append(stage)
            raise CacheMiss from None
        self.hits.append(stage)
        with contextlib.suppress(OSError):
            os.utime(p)  # recently used: the last to be evicted
        return arrays

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
        meta = json.dumps({"tool": ENTRY_TOOL, "key": key, "checksum": _checksum(arrays)})
        payload: dict[str, Any] = {"__meta__": np.array(meta), **arrays}
        try:
            p.parent.mkdir(exist_ok=True)
            with atomic_file(p) as f:
                np.savez(f, **payload)
        except OSError as exc:
            self._cannot_store(exc)
            return
        self.evict()

    # -- housekeeping -------------------------------------------------------------------
    def _entries(self) -> list[Path]:
        if not (self.root / MARKER).is_file() and not self.root.is_dir():
            return []
        out = []
        for stage_dir in sorted(p for p in self.root.iterdir() if p.is_dir() and not p.is_symlink()):
            out += [
                f
                for f in sorted(stage_dir.iterdir())
                if f.is_file() and _ENTRY.fullmatch(f.name) and _is_entry(f)
            ]
        return out

    def info(self) -> tuple[int, int]:
        """(number of entries, their total size in bytes)."""
        entries = self._entries()
        return len(entries), sum(f.stat().st_size for f in entries)

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
            own = json.loads((self.root / MARKER).read_text()).get("max_bytes")
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
            data = json.loads(marker.read_text())
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
        marked = (self.root / MARKER).is_file()
        if not marked:
            self._check_root()  # refuses a folder that is not (even an unmarked) cache
        n = 0
        try:
            for f in self._entries():
                f.unlink()
                n += 1
            for stage_dir in [p for p in self.root.iterdir() if p.is_dir() and not p.is_symlink()]:
                for f in stage_dir.iterdir():
                    if f.is_file() and _TMP.fullmatch(f.name):
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
        with np.load(path, allow_pickle=False) as z:
            if "__meta__" not in z.files:
                return False
            meta = json.loads(str(z["__meta__"]))
    except (OSError, ValueError, KeyError, zipfile.BadZipFile, EOFError):
        return True
    return isinstance(meta, dict) and "key" in meta and "checksum" in meta
