"""A railway line as its curve sections: a CSV of one row per curve (``id``, ``radius_m``,
``length_m``, ``cant_mm``, ``train_speed_km_h``; optionally where it lies, ``x0``, ``y0``,
``x1``, ``y1`` in a projected coordinate system, or a ``wkt`` LINESTRING), read with one-line
errors (:class:`LineFileError`) naming the file, the row and the value."""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from geometry.files import MAX_TEXT_BYTES, check_text_file, printable, quoted, read_text

__all__ = [
    "LINE_COLUMNS",
    "LINE_OPTIONAL_COLUMNS",
    "MAX_ID_CHARACTERS",
    "MAX_LINE_POSITIONS",
    "LineCurve",
    "LineFileError",
    "count_rows",
    "read_line",
]

#: The columns a line's CSV must have, and those it may
LINE_COLUMNS = ("id", "radius_m", "length_m", "cant_mm", "train_speed_km_h")
LINE_OPTIONAL_COLUMNS = ("x0", "y0", "x1", "y1", "wkt")
#: The longest curve id [characters]: a track section's name or number, not a text
MAX_ID_CHARACTERS = 100
#: The most positions a line's curves hold together: a network's curves drawn every few
#: metres. At most 54 bytes each in line.geojson (two 24-character numbers), they keep it
#: within the largest file a command writes (200 MB) and their parse within a few hundred MB
MAX_LINE_POSITIONS = 2_000_000


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
    run is refused before it is read): its line breaks, ``\\n``, ``\\r\\n`` or ``\\r``. The
    file is checked first (a regular file within :data:`MAX_TEXT_BYTES`), so that the
    count takes a time bounded whatever the size of the file named."""
    check_text_file(path, "line", LineFileError)
    with open(path, "rb") as f:
        data = f.read(MAX_TEXT_BYTES + 1)
    rows = data.count(b"\n") + data.count(b"\r") - data.count(b"\r\n")
    if data and not data.endswith((b"\n", b"\r")):
        rows += 1  # a last row without its line break
    return max(rows - 1, 0)


def _number(row: dict[str, str], key: str, where: str) -> float:
    try:
        value = float(row[key])
    except (TypeError, ValueError):
        raise LineFileError(f"{where}: {key} = {quoted(row.get(key) or '')} is not a number") from None
    if not math.isfinite(value):
        raise LineFileError(f"{where}: {key} must be finite")
    return value


def _wkt(text: str, where: str) -> tuple[tuple[float, float], ...]:
    body = text.strip()
    if not body.upper().startswith("LINESTRING") or "(" not in body or not body.endswith(")"):
        raise LineFileError(f"{where}: wkt must be a LINESTRING (x y, x y, ...)")
    try:
        pairs = [p.split() for p in body[body.index("(") + 1 : -1].split(",")]
        if any(len(p) != 2 for p in pairs):
            raise ValueError
        points = tuple((float(x), float(y)) for x, y in pairs)
    except ValueError:
        raise LineFileError(f"{where}: wkt {quoted(body[:40])}... is not a LINESTRING of x y pairs") from None
    if not all(math.isfinite(x) and math.isfinite(y) for x, y in points):
        raise LineFileError(f"{where}: wkt holds a coordinate that is not a finite number")
    if len(points) < 2:  # RFC 7946: a LineString has two or more positions
        raise LineFileError(f"{where}: wkt LINESTRING has {len(points)} position; a line needs two or more")
    return points


def _coordinates(row: dict[str, str], where: str) -> tuple[tuple[float, float], ...]:
    if (row.get("wkt") or "").strip():
        return _wkt(row["wkt"], where)
    given = [k for k in ("x0", "y0", "x1", "y1") if (row.get(k) or "").strip()]
    if len(given) == 4:
        x0, y0, x1, y1 = (_number(row, k, where) for k in ("x0", "y0", "x1", "y1"))
        return ((x0, y0), (x1, y1))
    if given:
        raise LineFileError(f"{where}: x0, y0, x1, y1 go together; this row gives only {', '.join(given)}")
    return ()


def _rows(text: str, path: Path) -> Iterator[tuple[int, list[str]]]:
    """The CSV's rows with their line numbers; any newline (``\\n``, ``\\r\\n``, ``\\r``)
    ends a row, and a cell beyond the csv module's limit is one line."""
    reader = csv.reader(io.StringIO(text.removeprefix("\ufeff"), newline=None))
    try:
        start = 1
        for row in reader:
            if row:  # (a blank line)
                yield start, row
            start = reader.line_num + 1  # a quoted cell may span lines: a row is where it starts
    except csv.Error as exc:
        limit = csv.field_size_limit()
        why = f"a cell longer than {limit:,} characters" if "field limit" in str(exc) else str(exc)
        raise LineFileError(f"{path}:{reader.line_num}: {why}") from None


def read_line(path: Path) -> list[LineCurve]:
    """The curves of a line's CSV (module docstring), each checked, the file as a whole:
    a byte-order mark is read as none, a column named twice, a row with more or fewer
    cells than the header and an id that is not printable text are refused with the row."""
    check_text_file(path, "line", LineFileError)
    text = read_text(path, "line", LineFileError)
    rows = _rows(text, path)
    _, columns = next(rows, (1, []))
    columns = [c.strip() for c in columns]
    missing = [c for c in LINE_COLUMNS if c not in columns]
    if missing:
        raise LineFileError(
            f"{path}: the line needs the columns {', '.join(LINE_COLUMNS)}; missing {', '.join(missing)}"
        )
    known = LINE_COLUMNS + LINE_OPTIONAL_COLUMNS
    extra = [c for c in columns if c not in known]
    if extra:
        raise LineFileError(f"{path}: column {quoted(extra[0])} is not one a line has ({', '.join(known)})")
    twice = sorted({c for c in columns if columns.count(c) > 1})
    if twice:
        raise LineFileError(f"{path}: column {twice[0]!r} is named twice")
    curves, ids, positions = [], set(), 0
    for i, cells in rows:
        where = f"{path}:{i}"
        if len(cells) != len(columns):
            raise LineFileError(f"{where}: {len(cells)} cells for the header's {len(columns)} columns")
        row = dict(zip(columns, cells))
        cid = row["id"].strip()
        if not cid or cid in ids:
            raise LineFileError(f"{where}: id {quoted(cid)} is empty or not unique")
        if not printable(cid) or len(cid) > MAX_ID_CHARACTERS:
            raise LineFileError(
                f"{where}: id {quoted(cid[:40])}: printable text of at most {MAX_ID_CHARACTERS} characters "
                "(no control or bidirectional characters)"
            )
        ids.add(cid)
        radius, length, cant, speed = (_number(row, k, where) for k in LINE_COLUMNS[1:])
        if radius <= 0 or length <= 0 or speed <= 0:
            raise LineFileError(f"{where}: radius, length and train speed must be positive")
        positions += row.get("wkt", "").count(",") + 1  # counted before any is parsed
        if positions > MAX_LINE_POSITIONS:
            raise LineFileError(
                f"{where}: the line's curves hold more than {MAX_LINE_POSITIONS:,} positions: "
                "split the line, or draw its curves with fewer"
            )
        curves.append(LineCurve(cid, radius, length, cant, speed, _coordinates(row, where)))
    if not curves:
        raise LineFileError(f"{path}: the line has no curve")
    return curves
