"""A railway line as its curve sections: a CSV of one row per curve (``id``, ``radius_m``,
``length_m``, ``cant_mm``, ``train_speed_km_h``; optionally where it lies, ``x0``, ``y0``,
``x1``, ``y1`` in a projected coordinate system, or a ``wkt`` LINESTRING), read with one-line
errors (:class:`LineFileError`) naming the file, the row and the value."""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path

from geometry.files import read_text

__all__ = ["LINE_COLUMNS", "LINE_OPTIONAL_COLUMNS", "LineCurve", "LineFileError", "count_rows", "read_line"]

#: The columns a line's CSV must have, and those it may
LINE_COLUMNS = ("id", "radius_m", "length_m", "cant_mm", "train_speed_km_h")
LINE_OPTIONAL_COLUMNS = ("x0", "y0", "x1", "y1", "wkt")


class LineFileError(ValueError):
    """A line's CSV that cannot be read as curves (one line: the file, the row, why)."""


@dataclass(frozen=True)
class LineCurve:
    """One curve section of a line: its id, radius [m], length [m], cant [mm], train speed
    [km/h], and where it lies (a polyline in the line's coordinates; empty: not given)."""

    id: str
    radius_m: float
    length_m: float
    cant_mm: float
    train_speed_km_h: float
    coordinates: tuple[tuple[float, float], ...] = ()


def count_rows(path: Path) -> int:
    """How many curves a line's CSV holds, counted without parsing it (a line too long to
    run is refused before it is read)."""
    with open(path, "rb") as f:
        rows = sum(chunk.count(b"\n") for chunk in iter(lambda: f.read(1 << 20), b""))
    return max(rows - 1, 0)


def _number(row: dict[str, str], key: str, where: str) -> float:
    try:
        value = float(row[key])
    except (TypeError, ValueError):
        raise LineFileError(f"{where}: {key} = {row.get(key)!r} is not a number") from None
    if not math.isfinite(value):
        raise LineFileError(f"{where}: {key} must be finite")
    return value


def _wkt(text: str, where: str) -> tuple[tuple[float, float], ...]:
    body = text.strip()
    if not body.upper().startswith("LINESTRING") or "(" not in body:
        raise LineFileError(f"{where}: wkt must be a LINESTRING (x y, x y, ...)")
    try:
        pairs = body[body.index("(") + 1 : body.rindex(")")].split(",")
        return tuple((float(p.split()[0]), float(p.split()[1])) for p in pairs)
    except (ValueError, IndexError):
        raise LineFileError(f"{where}: wkt {body[:40]!r}... is not a LINESTRING of x y pairs") from None


def _coordinates(row: dict[str, str], where: str) -> tuple[tuple[float, float], ...]:
    if (row.get("wkt") or "").strip():
        return _wkt(row["wkt"], where)
    if all((row.get(k) or "").strip() for k in ("x0", "y0", "x1", "y1")):
        x0, y0, x1, y1 = (_number(row, k, where) for k in ("x0", "y0", "x1", "y1"))
        return ((x0, y0), (x1, y1))
    return ()


def read_line(path: Path) -> list[LineCurve]:
    """The curves of a line's CSV (module docstring), each checked."""
    text = read_text(path, "line", LineFileError)
    reader = csv.DictReader(io.StringIO(text))
    columns = reader.fieldnames or []
    missing = [c for c in LINE_COLUMNS if c not in columns]
    if missing:
        raise LineFileError(
            f"{path}: the line needs the columns {', '.join(LINE_COLUMNS)}; missing {', '.join(missing)}"
        )
    known = LINE_COLUMNS + LINE_OPTIONAL_COLUMNS
    extra = [c for c in columns if c not in known]
    if extra:
        raise LineFileError(f"{path}: column {extra[0]!r} is not one a line has ({', '.join(known)})")
    curves, ids = [], set()
    for i, row in enumerate(reader, start=2):
        where = f"{path}:{i}"
        cid = (row.get("id") or "").strip()
        if not cid or cid in ids:
            raise LineFileError(f"{where}: id {cid!r} is empty or not unique")
        ids.add(cid)
        radius, length, cant, speed = (_number(row, k, where) for k in LINE_COLUMNS[1:])
        if radius <= 0 or length <= 0 or speed <= 0:
            raise LineFileError(f"{where}: radius, length and train speed must be positive")
        curves.append(LineCurve(cid, radius, length, cant, speed, _coordinates(row, where)))
    if not curves:
        raise LineFileError(f"{path}: the line has no curve")
    return curves
