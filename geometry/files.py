"""Files: reading a user's text file (a design, an outline CSV, a study spec), writing
any file atomically, the one rule for a name that becomes a file or folder name, and the
checks of a record read back from stored arrays (:func:`stored_array`).

A text file is read from regular files only, of a bounded size, in UTF-8, each
failure one line naming the file.
A FIFO or a device would block or never end (``/dev/zero``), a huge file would fill the
memory, and an editor or spreadsheet may save text in another encoding; none of these is
a traceback or a hang.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import stat
import tempfile
import tomllib
from collections.abc import Iterator
from pathlib import Path
from typing import Any, BinaryIO

import numpy as np

__all__ = [
    "LABEL_PATTERN",
    "LABEL_RULE",
    "MAX_TEXT_BYTES",
    "atomic_file",
    "check_text_file",
    "check_label",
    "read_text",
    "printable",
    "quoted",
    "read_toml",
    "stored_array",
    "stored_json",
    "umask",
    "write_atomic",
]

#: A label: the name of a design, a study, a curve... anything that becomes the name of a
#: file or a result folder. One path component, never empty, "." or "..", no separator,
#: no leading dot (hidden) or dash (an option), printable ASCII only (no terminal control
#: characters), short enough for every file system.
LABEL_PATTERN = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.+-]{0,63}")
LABEL_RULE = "letters, digits, '_', '.', '+', '-'; a letter or digit first; at most 64"

#: The largest input file read [bytes]: a 100,000-point outline CSV is about 4 MB.
MAX_TEXT_BYTES = 64 * 2**20


def read_text(path: str | Path, what: str, error: type[Exception] = ValueError) -> str:
    """The text of the regular file ``path``; ``error(message)`` (one line naming
    ``what`` and the file) when it is missing, not a regular file, larger than
    :data:`MAX_TEXT_BYTES` or not UTF-8."""
    path = Path(path)
    check_text_file(path, what, error)
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


def check_text_file(path: Path, what: str, error: type[Exception] = ValueError) -> None:
    """``error(message)`` unless ``path`` is a regular file within :data:`MAX_TEXT_BYTES`,
    judged from its ``stat`` alone (a pipe is never opened, a huge file never read)."""
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
            f"{what} {path} is {info.st_size / 2**20:,.0f} MiB, more than the {MAX_TEXT_BYTES >> 20} MiB read"
        )


def quoted(text: str) -> str:
    """``text`` quoted for a message, its control and bidirectional characters escaped."""
    return repr(text) if printable(text) else ascii(text)


def read_toml(path: str | Path, what: str, error: type[Exception] = ValueError) -> tuple[str, dict]:
    """The text of a TOML file and its tables (:func:`read_text`, then the parse; an
    invalid file is ``error(message)`` naming it)."""
    text = read_text(path, what, error)
    try:
        return text, tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML ({exc})") from None


#: The characters that reorder text on a terminal (Unicode's bidirectional controls): a
#: printable string holding one can show other text than it holds.
BIDI_CONTROLS = re.compile("[\u061c\u200e\u200f\u202a-\u202e\u2066-\u2069]")


def printable(text: str) -> bool:
    """Whether ``text`` shows on a terminal as what it is: no control characters (escape
    sequences, newlines, bells) and no bidirectional controls."""
    return text.isprintable() and not BIDI_CONTROLS.search(text)


def check_label(name: object, what: str, error: type[Exception] = ValueError) -> str:
    """``name`` if it is a label (:data:`LABEL_PATTERN`), else ``error(message)`` naming
    ``what`` and the rule: a name that becomes a folder is never a path."""
    if not isinstance(name, str) or not LABEL_PATTERN.fullmatch(name):
        shown = name if isinstance(name, str) and name.isprintable() else ascii(name)
        raise error(f"{what} {shown!r} is not a usable name ({LABEL_RULE})")
    return name


def umask() -> int:
    """The process's file-creation mask (read without changing it for long)."""
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_file(path: str | Path) -> Iterator[BinaryIO]:
    """``with atomic_file(path) as f:`` write ``f`` (binary); on leaving the block it
    becomes ``path`` in one rename, so a reader (or a run killed meanwhile) sees the old
    file or the new one, never half of one; on an error it is removed. The file gets the
    usual permissions (``mkstemp`` would leave it 0600)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            yield f
        os.chmod(tmp, 0o666 & ~umask())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def write_atomic(path: str | Path, data: bytes | str) -> Path:
    """Write ``data`` to ``path`` atomically (:func:`atomic_file`)."""
    with atomic_file(path) as f:
        f.write(data.encode() if isinstance(data, str) else data)
    return Path(path)


def stored_array(
    arrays: dict[str, np.ndarray],
    name: str,
    kinds: str = "f",
    ndim: int | tuple[int, ...] | None = None,
    columns: int | tuple[int, ...] | None = None,
    index_below: int | None = None,
) -> np.ndarray:
    """``arrays[name]`` checked to be what a record stored there, before any use: stored
    arrays are read back from a cache that anyone who can write it could have made.

    ``kinds``: the allowed numpy kinds ("f" float, "c" complex, "i"/"u" integer, "b"
    bool, "U" text); ``ndim`` / ``columns``: the allowed number of dimensions and of
    columns (the last axis of a 2-D array); ``index_below``: an array of indices into
    something of that length (each in ``[0, index_below)``). Numbers are finite. Raises
    ``ValueError`` naming the array (a ``KeyError`` where it is missing).
    """
    a = arrays[name]
    if not isinstance(a, np.ndarray) or a.dtype.kind not in kinds:
        raise ValueError(f"stored array {name!r} is not of kind {kinds!r}")
    if ndim is not None and a.ndim not in (ndim if isinstance(ndim, tuple) else (ndim,)):
        raise ValueError(f"stored array {name!r} has {a.ndim} dimensions")
    if columns is not None and (
        a.ndim != 2 or a.shape[1] not in (columns if isinstance(columns, tuple) else (columns,))
    ):
        raise ValueError(f"stored array {name!r} has shape {a.shape}")
    if a.dtype.kind in "fc" and not np.isfinite(a).all():
        raise ValueError(f"stored array {name!r} holds a number that is not finite")
    if index_below is not None and a.size and not (a.min() >= 0 and a.max() < index_below):
        raise ValueError(f"stored array {name!r} indexes beyond its {index_below} items")
    return a


def stored_json(arrays: dict[str, np.ndarray], name: str) -> Any:
    """The JSON text stored as the 0-d text array ``arrays[name]``, parsed; every number in
    it finite (``ValueError`` otherwise)."""
    text = stored_array(arrays, name, "U", ndim=0)

    def refuse(constant: str) -> float:
        raise ValueError(f"stored {name!r} holds {constant}")

    return json.loads(str(text), parse_constant=refuse)
