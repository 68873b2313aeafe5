"""The figures' common ground: their resolution, a figure on the Agg canvas (matplotlib's
object API: no pyplot, no display, no global state) and a long line decimated to what its
pixels can show (the same picture from a few thousand points instead of millions)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["DECIMATE_COLUMNS", "PLOT_DPI", "decimate", "figure", "save"]

#: resolution of every figure the tool writes [dots per inch]
PLOT_DPI = 110


def figure(width_in: float, height_in: float, rows: int = 1, cols: int = 1, **kwargs: Any) -> Any:
    """A new Agg figure and its axes (object API: nothing global), with fixed margins
    for tick labels, axis labels and a title (tight_layout would draw every figure twice)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width_in, height_in))
    axes = fig.subplots(rows, cols, **kwargs)
    fig.subplots_adjust(
        left=0.85 / width_in,
        right=1 - 0.2 / width_in,
        bottom=0.55 / height_in,
        top=1 - 0.4 / height_in,
        hspace=0.3 if rows > 1 else None,
    )
    return fig, axes


#: Columns a decimated line keeps: more than the pixels of a 110-dpi, 7-inch axis.
DECIMATE_COLUMNS = 2000


def decimate(x: np.ndarray, y: np.ndarray, columns: int = DECIMATE_COLUMNS) -> tuple[np.ndarray, np.ndarray]:
    """The points of a line that a plot ``columns`` pixels wide can show: per column
    of samples its minimum and maximum, in time order (every sample if there are few)."""
    n = len(x)
    if n <= 4 * columns:
        return x, y
    per = n // columns
    m = per * columns
    xb, yb = x[:m].reshape(columns, per), y[:m].reshape(columns, per)
    lo, hi = yb.argmin(axis=1), yb.argmax(axis=1)
    first, second = np.minimum(lo, hi), np.maximum(lo, hi)
    rows = np.arange(columns)
    xs = np.column_stack([xb[rows, first], xb[rows, second]]).ravel()
    ys = np.column_stack([yb[rows, first], yb[rows, second]]).ravel()
    return np.concatenate([xs, x[m:]]), np.concatenate([ys, y[m:]])


def save(fig: Any, path: Path) -> Path:
    fig.savefig(path, dpi=PLOT_DPI)
    return path
