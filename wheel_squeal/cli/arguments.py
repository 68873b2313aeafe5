"""The command line's value types: each parses one flag's text and refuses it with a
message argparse puts after the flag's name (``argument --rpm: must be positive``)."""

from __future__ import annotations

import argparse
import math

__all__ = [
    "MAX_AXIS_POINTS",
    "angle_deg",
    "c22_value",
    "count",
    "finite",
    "friction_value",
    "grid_axis",
    "microphone",
    "non_negative",
    "positive",
]


#: Most points of one sweep axis (START:STOP:N): a typo like 0:1:1000000000 must not
#: allocate gigabytes before the budget has a say.
MAX_AXIS_POINTS = 1_000_000


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None


def positive(text: str) -> float:
    v = _number(text)
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"must be positive, got {text}")
    return v


def non_negative(text: str) -> float:
    v = _number(text)
    if not (math.isfinite(v) and v >= 0):
        raise argparse.ArgumentTypeError(f"must be zero or positive, got {text}")
    return v


def finite(text: str) -> float:
    v = _number(text)
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"must be finite, got {text}")
    return v


def friction_value(text: str) -> float:
    """A friction coefficient within what a wheel on a rail can have (``sections.FRICTION_RANGE``)."""
    from ..model_sections import FRICTION_RANGE

    v = positive(text)
    low, high = FRICTION_RANGE
    if not low <= v <= high:
        raise argparse.ArgumentTypeError(
            f"{text} is not a wheel-rail friction coefficient ({low:g} to {high:g}: 0.05-0.3 lubricated or "
            "with a friction modifier, 0.6-0.8 clean and dry)"
        )
    return v


def c22_value(text: str) -> float | str:
    return "kalker" if text.lower() == "kalker" else positive(text)


def grid_axis(text: str) -> list[float]:
    """``START:STOP:N`` (N points, inclusive) or a comma list, as a list of floats."""
    bad = argparse.ArgumentTypeError(f"expected START:STOP:N or a comma list of numbers, got {text!r}")
    try:
        if ":" in text:
            a, b, n = text.split(":")
            start, stop, count = float(a), float(b), int(n)
            if count < 1:
                raise bad
            if count > MAX_AXIS_POINTS:
                raise argparse.ArgumentTypeError(
                    f"{count:,} points is more than a sweep axis takes ({MAX_AXIS_POINTS:,})"
                )
            values = (
                [start + (stop - start) * i / (count - 1) for i in range(count)] if count > 1 else [start]
            )
        else:
            values = [float(x) for x in text.split(",")]
    except ValueError:
        raise bad from None
    if not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"values must be finite, got {text!r}")
    return values


def count(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"must be 1 or more, got {text}")
    return n


def angle_deg(text: str) -> float:
    """An angle in degrees, from -90 to 90 (``--contact-angle``)."""
    x = finite(text)
    if not -90.0 <= x <= 90.0:
        raise argparse.ArgumentTypeError(f"{x:g} is not an angle in degrees from -90 to 90")
    return x


def microphone(text: str) -> tuple[float, float, float]:
    """``R,Z,THETA`` [m, m, rad]: the microphone's radius, axial position and angle."""
    try:
        r, z, theta = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"takes R,Z,THETA (m, m, rad), got {text!r}") from None
    if not all(math.isfinite(v) for v in (r, z, theta)) or r < 0:
        raise argparse.ArgumentTypeError(f"R,Z,THETA needs finite values and R >= 0, got {text!r}")
    return (r, z, theta)
