"""Result folders and files: written whole or not at all, never at the cost of anything else.

A result folder is this tool's when it holds the marker file :data:`MARKER` (written with
every result). ``--out DIR`` may name a new folder, an empty one, or an earlier result;
any other folder is refused, so no command ever deletes a user's files.

How a result folder is written (:class:`ResultFolder`):

1. Before any computation: refuse an ``out`` that is the current folder or one of its
   parents, a file, or a non-empty folder without the marker; put back a previous result
   that a killed run left aside (only on file systems without an atomic exchange, see
   below); remove the hidden staging folders of dead runs of this host; create the
   staging folder ``.NAME.tmp-HOST-PID-TOKEN`` beside ``out`` (mode from the user's
   umask). Creating it proves the place is writable before the work starts.
2. The command writes plain files into the staging folder.
3. Publish: write the marker, then put the staging folder in place in one atomic step:
   a rename where ``out`` does not exist, an exchange (Linux ``renameat2`` with
   ``RENAME_EXCHANGE``: the two names swap at once) where it does. The old result, now
   under the staging name, is removed last. A kill at any point leaves either the old or
   the new result under ``out``, complete, and at most a hidden folder that the next run
   removes. Two runs writing the same ``out`` both succeed; the last one's result stays.
   Without ``renameat2`` (other systems, some network file systems) the old result is
   renamed to ``.NAME.old-HOST-PID-TOKEN`` first; a kill between the two renames leaves
   it there, and step 1 of the next run puts it back.
4. On any error the staging folder is removed and ``out`` is untouched.
"""

from __future__ import annotations

import contextlib
import csv
import ctypes
import ctypes.util
import errno
import json
import math
import os
import secrets
import shutil
import socket
import time
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any, ClassVar

from geometry.files import umask

from .errors import RequestError

__all__ = ["MARKER", "ResultFolder", "result_folder", "write_csv", "write_json"]

#: The file that marks a folder as a result of this tool.
MARKER = ".wheel-squeal-result"

_HOST = "".join(c if c.isalnum() else "_" for c in socket.gethostname())[:32] or "host"


# --------------------------------------------------------------------------------------
# atomic renames
# --------------------------------------------------------------------------------------
_AT_FDCWD = -100
_RENAME_NOREPLACE = 1
_RENAME_EXCHANGE = 2


def _libc_renameat2() -> Any:
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or None, use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return None
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    fn.restype = ctypes.c_int
    return fn


_RENAMEAT2 = _libc_renameat2()


def _renameat2(src: Path, dst: Path, flags: int) -> None:
    if _RENAMEAT2 is None:
        raise OSError(errno.ENOSYS, "renameat2 is not available")
    if _RENAMEAT2(_AT_FDCWD, os.fsencode(src), _AT_FDCWD, os.fsencode(dst), flags) != 0:
        e = ctypes.get_errno()
        raise OSError(e, os.strerror(e), str(dst))


def _exchange(a: Path, b: Path) -> None:
    """Swap the names of ``a`` and ``b`` atomically (both must exist)."""
    _renameat2(a, b, _RENAME_EXCHANGE)


def _rename_new(src: Path, dst: Path) -> None:
    """Rename ``src`` to ``dst``, failing with EEXIST / ENOTEMPTY if ``dst`` exists."""
    try:
        _renameat2(src, dst, _RENAME_NOREPLACE)
    except OSError as exc:
        if exc.errno not in (errno.ENOSYS, errno.EINVAL):
            raise
        # rename(2) of a folder onto an empty folder would succeed: check first (a
        # race with another writer then ends in ENOTEMPTY on the loser's next try)
        if os.path.lexists(dst):
            raise OSError(errno.EEXIST, "exists", str(dst)) from None
        os.rename(src, dst)


def _remove(path: Path) -> None:
    if path.is_symlink() or not path.is_dir():
        with contextlib.suppress(FileNotFoundError):
            path.unlink()
    else:
        shutil.rmtree(path, ignore_errors=True)


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


# --------------------------------------------------------------------------------------
# the result folder
# --------------------------------------------------------------------------------------
class ResultFolder:
    """One result folder being written (see the module docstring for the protocol).

    ``ResultFolder(out).open()`` checks ``out`` and creates the staging folder (raising
    :class:`~wheel_squeal.errors.RequestError` with the reason if it cannot); write
    into ``.staging``; then ``publish(command)`` or ``discard()``.
    """

    #: The staging folders this process has open (a command killed past its grace
    #: period removes them before it ends: :meth:`discard_all`).
    live: ClassVar[set[Path]] = set()

    def __init__(self, out: str | os.PathLike):
        self.out = Path(out)
        self._staging: Path | None = None

    @property
    def staging(self) -> Path | None:
        """The staging folder while the result is being written (None before
        :meth:`open` and after :meth:`publish` or :meth:`discard`)."""
        return self._staging

    @staging.setter
    def staging(self, path: Path | None) -> None:
        if self._staging is not None:
            ResultFolder.live.discard(self._staging)
        if path is not None:
            ResultFolder.live.add(path)
        self._staging = path

    @classmethod
    def discard_all(cls) -> None:
        """Remove every staging folder this process has open (its results stay as they
        were): the last thing a command ended by a signal does."""
        for path in list(cls.live):
            _remove(path)
        cls.live.clear()

    # -- checks ---------------------------------------------------------------------
    def check(self) -> None:
        """Refuse an ``out`` that cannot hold a result or holds something that is not one."""
        out = self.out
        try:
            resolved = out.resolve()
            cwd = Path.cwd().resolve()
        except OSError as exc:
            raise RequestError(f"result folder {out}: {exc.strerror}") from None
        if resolved == cwd or resolved in cwd.parents:
            raise RequestError(
                f"result folder {out} is the current folder or one of its parents: "
                "name a folder for the results"
            )
        if out.is_symlink() and not out.exists():
            raise RequestError(f"result folder {out} is a broken symbolic link")
        for parent in resolved.parents:
            if (parent / MARKER).is_file():
                raise RequestError(
                    f"result folder {out} lies inside another result, {parent}: results are never nested "
                    "(a run that replaces the outer one would delete it); choose a folder outside it"
                )
        if out.exists():
            if not out.is_dir():
                raise RequestError(f"result folder {out} exists and is not a folder")
            if not is_result(out):
                raise RequestError(
                    f"result folder {out} is a folder with other files in it, not a result of this tool "
                    f"(no {MARKER}): choose a new or empty folder (nothing was written)"
                )
            inner = next((p.parent for p in out.glob(f"*/**/{MARKER}")), None)
            if inner is not None:
                raise RequestError(
                    f"result folder {out} holds another result ({inner}) that replacing it would delete; "
                    "choose another folder (nothing was written)"
                )

    def open(self) -> Path:
        """Check ``out``, tidy what dead runs left beside it and create the staging folder."""
        self.check()
        parent, name = self.out.parent, self.out.name
        try:
            parent.mkdir(parents=True, exist_ok=True)
            self._recover(parent, name)
            mode = 0o777 & ~umask()
            while True:
                staging = parent / f".{name}.tmp-{_HOST}-{os.getpid()}-{secrets.token_hex(4)}"
                try:
                    os.mkdir(staging, 0o777)
                    break
                except FileExistsError:
                    continue
            os.chmod(staging, mode)  # mkdir's mode is also masked by the umask; be explicit
        except OSError as exc:
            where = exc.filename or parent
            raise RequestError(
                f"result folder {self.out} cannot be written ({where}: {exc.strerror})"
            ) from None
        self.staging = staging
        return staging

    @staticmethod
    def _recover(parent: Path, name: str) -> None:
        """Put back a result a killed run left aside; remove dead runs' staging folders."""
        prefix_tmp, prefix_old = f".{name}.tmp-{_HOST}-", f".{name}.old-{_HOST}-"
        try:
            entries = list(os.scandir(parent))
        except OSError:
            return
        for entry in entries:
            for prefix in (prefix_tmp, prefix_old):
                if not entry.name.startswith(prefix):
                    continue
                pid_text = entry.name[len(prefix) :].split("-", 1)[0]
                if not pid_text.isdigit() or _pid_alive(int(pid_text)):
                    continue
                path = Path(entry.path)
                if prefix == prefix_old and not os.path.lexists(parent / name):
                    # the only copy of the previous result: put it back, never delete it
                    with contextlib.suppress(OSError):
                        _rename_new(path, parent / name)
                    continue
                _remove(path)

    # -- finishing --------------------------------------------------------------------
    def publish(self, command: str) -> Path:
        """Mark the staged result and put it in place of ``out`` atomically."""
        if self.staging is None:
            raise RuntimeError("publish() before open()")
        staging = self.staging
        marker = {"tool": "wheel-squeal", "command": command, "written": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
        (staging / MARKER).write_text(json.dumps(marker) + "\n")
        out = self.out
        for _ in range(100):  # only another writer racing for the same name repeats this
            try:
                _rename_new(staging, out)
                self.staging = None
                return out
            except OSError as exc:
                if exc.errno not in (errno.EEXIST, errno.ENOTEMPTY):
                    raise
            if out.is_dir() and not is_result(out):
                raise RequestError(
                    f"result folder {out} was filled with other files during the run; "
                    f"the result is left in {staging}"
                )
            try:
                _exchange(staging, out)
            except OSError as exc:
                if exc.errno == errno.ENOENT:
                    continue  # the other writer's result vanished: rename again
                if exc.errno not in (errno.ENOSYS, errno.EINVAL):
                    raise
                self._replace_in_two_steps(staging, out)
                return out
            self.staging = None
            _remove(staging)  # now the old result
            return out
        raise RuntimeError(f"could not put the result in place of {out}")

    def _replace_in_two_steps(self, staging: Path, out: Path) -> None:
        old = out.with_name(f".{out.name}.old-{_HOST}-{os.getpid()}-{secrets.token_hex(4)}")
        os.rename(out, old)
        _rename_new(staging, out)
        self.staging = None
        _remove(old)

    def discard(self) -> None:
        """Remove the staging folder (``out`` stays as it was)."""
        if self.staging is not None:
            _remove(self.staging)
            self.staging = None


def is_result(folder: Path) -> bool:
    """True for a folder this tool wrote (it holds :data:`MARKER`) or an empty one."""
    try:
        return (folder / MARKER).is_file() or not any(os.scandir(folder))
    except OSError:
        return False


@contextlib.contextmanager
def result_folder(out: str | os.PathLike, command: str) -> Iterator[Path]:
    """``with result_folder(out, "run") as tmp:`` write into ``tmp``; on success it
    becomes ``out`` (atomically, see the module docstring), on any error it is removed.
    Call :meth:`ResultFolder.open` yourself (``ResultFolder``) to check ``out`` before
    a long computation."""
    folder = out if isinstance(out, ResultFolder) else ResultFolder(out)
    staging = folder.staging or folder.open()
    try:
        yield staging
    except BaseException:
        folder.discard()
        raise
    folder.publish(command)


# --------------------------------------------------------------------------------------
# files
# --------------------------------------------------------------------------------------
#: The one word in text for a value that does not exist (a mode the contact cannot
#: excite has no modal mass there, no critical damping or slope; a bound no value
#: reaches): null in JSON, an empty CSV cell, NaN in a VTU's fields
NONE = "none"

#: A bound past this size is the root finder's round-off, not a requirement
MAX_BOUND = 1e20
#: A damping ratio needed below this is round-off: no damping is needed
MIN_NEEDED_DAMPING_RATIO = 1e-8


def bound_or_none(x: Any) -> float | None:
    """A critical value (damping ratio, friction slope) as it is reported: None where it
    is not finite or past :data:`MAX_BOUND` (round-off)."""
    v = finite_or_none(x)
    return None if v is None or abs(float(v)) > MAX_BOUND else float(v)


def needed_or_none(x: Any) -> float | None:
    """A damping ratio a remedy needs: None where it is none (below
    :data:`MIN_NEEDED_DAMPING_RATIO`, round-off, or not a finite number)."""
    v = bound_or_none(x)
    return None if v is None or v < MIN_NEEDED_DAMPING_RATIO else v


def finite_or_none(x: Any) -> Any:
    """A number as a plain Python value, None for NaN and infinities (no value: JSON's
    null, an empty CSV cell); anything else unchanged. The one rule for missing values in
    every file the tool writes."""
    if x is None:
        return None
    if hasattr(x, "item") and callable(x.item) and getattr(x, "ndim", 1) == 0:
        x = x.item()  # numpy scalars
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


def json_ready(x: Any) -> Any:
    """``x`` with every container made of JSON types (:func:`finite_or_none`; paths as
    text)."""
    if isinstance(x, dict):
        return {str(k): json_ready(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [json_ready(v) for v in x]
    if isinstance(x, os.PathLike):
        return os.fspath(x)
    return finite_or_none(x)


def write_json(path: Path, data: dict) -> Path:
    """JSON with NaN and infinities as null (JSON has no NaN)."""
    path.write_text(json.dumps(json_ready(data), indent=2, allow_nan=False) + "\n")
    return path


def csv_cell(x: Any) -> Any:
    """A CSV cell: empty for no value (:func:`finite_or_none`), floats in full."""
    x = finite_or_none(x)
    return "" if x is None else repr(x) if isinstance(x, float) else x


def write_csv(path: Path, rows: list[dict], columns: Sequence[str] | None = None) -> Path:
    """One row per dict under the header ``columns`` (default: the keys of the first
    row). Every row must have exactly those keys: a file's columns are documented
    (:mod:`wheel_squeal.fields`), and a row that differs is a bug, not an empty cell."""
    keys = list(columns) if columns is not None else list(rows[0]) if rows else []
    for r in rows:
        if set(r) != set(keys):
            raise ValueError(f"{path.name}: row fields {sorted(set(r) ^ set(keys))} differ from its columns")
    with open(path, "w", newline="") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(keys)
        for r in rows:
            writer.writerow([csv_cell(r[k]) for k in keys])
    return path
