"""Values and files as every result writes them: the one word for a value that does not
exist (``none``: null in JSON, an empty CSV cell, NaN in a VTU), the rule for what counts
as a value (:func:`finite_or_none`), and the JSON and CSV writers (result folders
themselves: :mod:`wheel_squeal.runtime.result_folders`)."""

from __future__ import annotations

import csv
import json
import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

__all__ = [
    "NONE",
    "bound_or_none",
    "csv_cell",
    "finite_or_none",
    "json_ready",
    "needed_or_none",
    "write_csv",
    "write_json",
]


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


#: The first characters a spreadsheet reads as a formula (OWASP's CSV injection list)
FORMULA_STARTS = ("=", "+", "-", "@", "\t", "\r")


def csv_cell(x: Any) -> Any:
    """A CSV cell: empty for no value (:func:`finite_or_none`), floats in full, and text
    that a spreadsheet would run as a formula (a curve id ``=HYPERLINK(...)``) behind a
    leading apostrophe, the OWASP rule, which shows it as the text it is.

    >>> csv_cell("=1+2"), csv_cell("-12.5"), csv_cell("R150"), csv_cell(float("nan"))
    ("'=1+2", '-12.5', 'R150', '')
    """
    x = finite_or_none(x)
    if x is None:
        return ""
    if isinstance(x, float):
        return repr(x)
    if isinstance(x, str) and x.startswith(FORMULA_STARTS) and not _is_number(x):
        return "'" + x
    return x


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


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
