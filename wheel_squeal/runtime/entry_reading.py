"""Reading a stage cache's files as untrusted input: a cache may be shared, and anyone who
can write it can put any file there, under any name, of any size and type.

Only regular files are opened (never a link, a pipe or a device: opened without following
a link and without blocking, then checked), each within a size limit; an entry's archive
is checked member by member (uncompressed ``.npy`` arrays of plain types whose headers
account exactly for their sizes) before its data is read; the files a result keeps are
plain names within the result (:func:`kept_files`). Each failure is a ``ValueError`` or an
``OSError``, which the cache reports as a corrupt entry and computes again."""

from __future__ import annotations

import hashlib
import io
import math
import os
import stat
import typing
import zipfile
from pathlib import Path
from typing import BinaryIO

import numpy as np

from geometry.files import printable, quoted

__all__ = [
    "ENTRY_KINDS",
    "MARKER_BYTES",
    "checksum",
    "entry_bytes",
    "is_plain_file_name",
    "is_regular",
    "kept_files",
    "open_regular",
    "read_entry",
    "read_small",
]


def checksum(arrays: dict[str, np.ndarray]) -> str:
    """The SHA-256 of an entry's arrays: their names, types, shapes and bytes."""
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


#: The largest marker file read [bytes] (a few settings)
MARKER_BYTES = 4096
#: The array types an entry may hold: booleans, integers, floats, complex numbers, text
ENTRY_KINDS = frozenset("biufcUS")


def is_regular(path: Path) -> bool:
    """Whether ``path`` itself (not a link's target) is a regular file."""
    try:
        return stat.S_ISREG(os.lstat(path).st_mode)
    except OSError:
        return False


def open_regular(path: Path, limit: float) -> BinaryIO:
    """``path`` opened for reading if it is a regular file (not a link, a pipe or a
    device: opened without following a link and without blocking, then checked) of at
    most ``limit`` bytes; ``ValueError`` or ``OSError`` otherwise."""
    fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC)
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise ValueError("not a regular file")
        if info.st_size > limit:
            raise ValueError(f"{info.st_size:,} bytes, more than the cache's limit")
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def read_small(path: Path) -> str:
    """The text of a small regular file of the cache's own (its marker)."""
    with open_regular(path, MARKER_BYTES) as f:
        return f.read(MARKER_BYTES).decode()


def read_entry(path: Path, limit: float, only: str | None = None) -> dict[str, np.ndarray]:
    """The arrays of the entry file ``path`` (only the one named ``only``, if given),
    every structural fact checked before its data is read (:meth:`StageCache.load`):
    members stored uncompressed, each a ``.npy`` array of a plain type whose header's
    shape and type account exactly for its size, together within ``limit`` bytes."""
    with open_regular(path, limit) as f, zipfile.ZipFile(f) as archive:
        infos = archive.infolist()
        names = [i.filename for i in infos]
        if len(set(names)) != len(names):
            raise ValueError("an array is stored twice")
        if sum(i.file_size for i in infos) > limit:
            raise ValueError("its arrays are larger than the cache's limit")
        arrays: dict[str, np.ndarray] = {}
        for info in infos:
            name = info.filename.removesuffix(".npy")
            if info.compress_type != zipfile.ZIP_STORED or not info.filename.endswith(".npy"):
                raise ValueError(f"member {info.filename[:64]!r} is not a stored array")
            if only is not None and name != only:
                continue
            with archive.open(info) as member:
                version = np.lib.format.read_magic(member)
                if version == (1, 0):
                    shape, fortran, dtype = np.lib.format.read_array_header_1_0(member)
                elif version == (2, 0):
                    shape, fortran, dtype = np.lib.format.read_array_header_2_0(member)
                else:
                    raise ValueError(f"array {name[:64]!r} has an unknown format {version}")
                if dtype.kind not in ENTRY_KINDS or dtype.fields is not None or dtype.subdtype is not None:
                    raise ValueError(f"array {name[:64]!r} is of type {dtype}, not a plain one")
                count = math.prod(shape)
                header = member.tell()
                if count * dtype.itemsize != info.file_size - header:
                    raise ValueError(f"array {name[:64]!r}: its header does not account for its size")
                data = bytearray(count * dtype.itemsize)  # the member's size, checked above
                # a zip member is a buffered reader (ZipExtFile): it reads into the buffer
                if typing.cast(io.BufferedIOBase, member).readinto(data) != len(data):
                    raise EOFError(f"array {name[:64]!r} is cut short")
            array = np.frombuffer(data, dtype=dtype)  # the buffer's own memory, writable
            arrays[name] = array.reshape(shape, order="F" if fortran else "C")
        return arrays


def kept_files(arrays: dict[str, np.ndarray], text: str | None = None) -> dict[str, bytes]:
    """Files kept as byte arrays in an entry (a result's, the mode views'), read as
    untrusted: each name a plain file name (no folder, no separator, no ``..``, not
    hidden, printable), each array bytes. ``text``: the name of an entry that is printed
    text instead (UTF-8, printable lines). ``ValueError`` where one is not."""
    files: dict[str, bytes] = {}
    for name, data in arrays.items():
        if not (isinstance(data, np.ndarray) and data.dtype == np.uint8 and data.ndim == 1):
            raise ValueError(f"kept file {quoted(name[:64])} is not bytes")
        if name != text and not is_plain_file_name(name):
            raise ValueError(f"kept file name {quoted(name[:64])} is not a plain file name")
        files[name] = data.tobytes()
    if text is not None:
        lines = files[text].decode("utf-8").split("\n")  # UnicodeDecodeError is a ValueError
        if not all(printable(line) for line in lines):
            raise ValueError("the kept printed text holds control characters")
    return files


def is_plain_file_name(name: str) -> bool:
    """Whether ``name`` names a file in the folder it is written to, and nothing else."""
    return (
        bool(name)
        and name not in (".", "..")
        and not name.startswith(".")
        and not any(c in name for c in "/\\\0")
        and printable(name)
        and len(name.encode()) <= 255
    )
