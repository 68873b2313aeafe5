"""The error of a design file: one type for every mistake in one, whichever section."""

from __future__ import annotations

__all__ = ["DesignError"]


class DesignError(ValueError):
    """An invalid design. The message is one line that names the value and its range."""
