"""Files: reading a user's text file (a design, an outline CSV, a study spec) and
writing any file atomically.

A text file is read from regular files only, of a bounded size, in UTF-8, each
failure one line naming the file.
A FIFO or a device would block or never end (``/dev/zero``), a huge file would fill the
memory, and an editor or spreadsheet may save text in another encoding; none of these is
a traceback or a hang.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
import tomllib
from pathlib import Path

__all__ = ["MAX_TEXT_BYTES", "read_text", "read_toml", "umask", "write_atomic"]

#: The largest input file read [bytes]: a 100,000-point outline CSV is about 4 MB.
MAX_TEXT_BYTES = 64 * 2**20


def read_text(path: str | Path, what: str, error: type[Exception] = ValueError) -> str:
    """The text of the regular file ``path``; ``error(message)`` (one line naming
    ``what`` and the file) when it is missing, not a regular file, larger than
    :data:`MAX_TEXT_BYTES` or not UTF-8."""
    path = Path(path)
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise error(f"{what} not found: {path}") from None
    except OSError as exc:
        raise error(f"cannot read {what} {path}: {exc.strerror}") from None
    if not stat.S_ISREG(info.st_mode):
        kind = "a folder" if stat.S_ISDIR(info.st_mode) else "not a regular file (a pipe or a device)"
        raise error(f"{what} {path} is {kind}: give a file")
    if info.st_size > MAX_TEXT_BYTES:
        raise error(
            f"{what} {path} is {info.st_size / 2**20:.0f} MiB, more than the {MAX_TEXT_BYTES >> 20} MiB read"
        )
    try:
        with open(path, "rb") as f:
            data = f.read(MAX_TEXT_BYTES + 1)
    except OSError as exc:
        raise error(f"cannot read {what} {path}: {exc.strerror}") from None
    if len(data) > MAX_TEXT_BYTES:
        raise error(f"{what} {path} is more than the {MAX_TEXT_BYTES >> 20} MiB read")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise error(
            f"{what} {path}, line {line}: not UTF-8 text (byte 0x{data[exc.start]:02x}); save it as UTF-8"
        ) from None


def read_toml(path: str | Path, what: str, error: type[Exception] = ValueError) -> tuple[str, dict]:
    """The text of a TOML file and its tables (:func:`read_text`, then the parse; an
    invalid file is ``error(message)`` naming it)."""
    text = read_text(path, what, error)
    try:
        return text, tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML ({exc})") from None


def umask() -> int:
    """The process's file-creation mask (read without changing it for long)."""
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_atomic(path: str | Path, data: bytes | str) -> Path:
    """Write ``data`` to ``path`` through a temporary file beside it and a rename: a
    reader (or a run killed meanwhile) sees the old file or the new one, never half of
    one. The file gets the usual permissions (``mkstemp`` would leave it 0600)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data.encode() if isinstance(data, str) else data)
        os.chmod(tmp, 0o666 & ~umask())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    return path
