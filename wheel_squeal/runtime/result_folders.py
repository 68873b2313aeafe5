"""Result folders and files: written whole or not at all, never at the cost of anything else.

A result folder is this tool's when it holds the marker file :data:`MARKER` (written with
every result). ``--out DIR`` may name a new folder, an empty one, or an earlier result;
any other folder is refused, so no command ever deletes a user's files.

How a result folder is written (:class:`ResultFolder`):

1. Before any computation: refuse an ``out`` that is the current folder or one of its
   parents, a file, or a non-empty folder without the marker (a symbolic link to a
   result: its target is replaced, the link stays); put back a previous result
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
   removes. From the exchange on a stop signal ends nothing (``interrupts.committing``):
   the old result is removed whole and the command ends as it would have. Two runs
   writing the same ``out`` both succeed; the last one's result stays.
   Without ``renameat2`` (other systems, some network file systems) the old result is
   renamed to ``.NAME.old-HOST-PID-TOKEN`` first; a kill between the two renames leaves
   it there, and step 1 of the next run puts it back.
4. On any error the staging folder is removed and ``out`` is untouched.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import errno
import json
import os
import secrets
import shutil
import socket
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any, ClassVar

from geometry.files import umask

from .interrupts import committing
from .request_errors import RequestError

__all__ = ["MARKER", "ResultFolder", "is_result", "result_folder"]

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
    :class:`~wheel_squeal.runtime.request_errors.RequestError` with the reason if it cannot); write
    into ``.staging``; then ``publish(command)`` or ``discard()``.
    """

    #: The staging folders this process has open (a command killed past its grace
    #: period removes them before it ends: :meth:`discard_all`).
    live: ClassVar[set[Path]] = set()
    #: Earlier results this process has replaced and is removing (likewise).
    retired: ClassVar[set[Path]] = set()

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
        were) and every earlier result it replaced: the last thing a command ended by a
        signal does."""
        for path in [*cls.live, *cls.retired]:
            _remove(path)
        cls.live.clear()
        cls.retired.clear()

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
        """Check ``out``, tidy what dead runs left beside it and create the staging folder.
        An ``out`` that is a symbolic link to an earlier result keeps the link: the result
        replaces the link's target."""
        self.check()
        if self.out.is_symlink():
            self.out = self.out.resolve()
        parent, name = self.out.parent, self.out.name
        # staged in the nearest folder that exists: the folders ``out`` needs are made only
        # when the result is put in place, so that a refused or failed run leaves none
        while not parent.exists() and parent != parent.parent:
            parent = parent.parent
        try:
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
        """Mark the staged result and put it in place of ``out`` atomically; from then on
        a stop signal ends nothing (``interrupts.committing``): the request completes."""
        if self.staging is None:
            raise RuntimeError("publish() before open()")
        with committing():
            return self._publish(command)

    def _publish(self, command: str) -> Path:
        staging = self.staging
        assert staging is not None
        marker = {"tool": "wheel-squeal", "command": command, "written": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
        (staging / MARKER).write_text(json.dumps(marker) + "\n")
        out = self.out
        out.parent.mkdir(parents=True, exist_ok=True)  # the folders it needs, now (:meth:`open`)
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
            self._retire(staging)  # now the old result
            return out
        raise RuntimeError(f"could not put the result in place of {out}")

    @classmethod
    def _retire(cls, old: Path) -> None:
        """Remove an earlier result that has been replaced (the stop watcher finishes it
        if the process is stopped meanwhile)."""
        cls.retired.add(old)
        _remove(old)
        cls.retired.discard(old)

    def _replace_in_two_steps(self, staging: Path, out: Path) -> None:
        old = out.with_name(f".{out.name}.old-{_HOST}-{os.getpid()}-{secrets.token_hex(4)}")
        os.rename(out, old)
        _rename_new(staging, out)
        self.staging = None
        self._retire(old)

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
