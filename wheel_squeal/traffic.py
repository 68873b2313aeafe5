"""A line's traffic and the friction its rail head has over the year: the ``[line]`` table
of a traffic file (``line --traffic``), read and checked whole (:class:`LineSpec`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from acoustics.emission import PERIODS
from geometry.files import read_toml

from .runtime.request_errors import RequestError

__all__ = [
    "DEFAULT_TRAINS_PER_HOUR",
    "GRID_ORIGIN_M",
    "LINE_KEYS",
    "TIGHTEST_GRID_RADIUS_M",
    "LineSpec",
    "load_line_spec",
    "read_line_spec",
]

#: The default traffic: trains per hour in each period (an illustrative regional service)
DEFAULT_TRAINS_PER_HOUR = {"day": 6.0, "evening": 4.0, "night": 1.0}
#: The keys a [line] table takes
LINE_KEYS = (
    "trains_per_hour",
    "bogies_per_train",
    "friction_coefficients",
    "friction_weights",
    "modifier_share",
    "radius_step",
)
#: The radius the grid of ``radius_step`` passes through [m]
GRID_ORIGIN_M = 100.0


#: The tightest radius a shared grid map is run at [m]: a bogie of 2.5 m wheelbase runs
#: curves of 50 m and more (``track.curving.check_curve``); a curve whose grid radius is
#: tighter keeps its own
TIGHTEST_GRID_RADIUS_M = 50.0


@dataclass(frozen=True)
class LineSpec:
    """A line's traffic and friction (the ``[line]`` table).

    Attributes
    ----------
    trains_per_hour : dict
        Trains per hour in each period of :data:`PERIODS`. Default: 6 by day, 4 in the
        evening, 1 at night, an illustrative regional service (not a timetable).
    bogies_per_train : float
        Default 8: a four-car unit.
    friction_coefficients, friction_weights : tuple of float
        The rail head's friction over the year and each value's share of the time. Default:
        0.2, 0.3, 0.4, 0.5 equally: the range of the creep curve's peak measured over
        relative humidity on a twin-disc rig (Liu & Meehan, Wear 2014: about 0.2 humid to
        0.6 dry), taken as uniform for want of a site's record.
    modifier_share : float
        The share of the time a top-of-rail friction modifier keeps the creep curve flat
        beyond saturation (default 0: none).
    radius_step : float
        0 (default): each curve's map at its own radius. A relative step (0.05 to 0.5): each
        curve's at the nearest radius of a geometric grid of that step through 100 m, so
        that the curves of a long line share maps (``benchmarks/bench_line.py`` measures
        what it changes).
    """

    trains_per_hour: dict[str, float] = field(default_factory=lambda: dict(DEFAULT_TRAINS_PER_HOUR))
    bogies_per_train: float = 8.0
    friction_coefficients: tuple[float, ...] = (0.2, 0.3, 0.4, 0.5)
    friction_weights: tuple[float, ...] = (0.25, 0.25, 0.25, 0.25)
    modifier_share: float = 0.0
    radius_step: float = 0.0

    def __post_init__(self) -> None:
        if set(self.trains_per_hour) != {p for p, _ in PERIODS}:
            raise RequestError(f"[line] trains_per_hour needs {', '.join(p for p, _ in PERIODS)}")
        if any(not (math.isfinite(v) and v >= 0) for v in self.trains_per_hour.values()):
            raise RequestError("[line] trains_per_hour: numbers of trains, 0 or more")
        if not (math.isfinite(self.bogies_per_train) and 1 <= self.bogies_per_train <= 100):
            raise RequestError(f"[line] bogies_per_train = {self.bogies_per_train!r}: 1 to 100")
        mus, ws = self.friction_coefficients, self.friction_weights
        if not mus or len(mus) != len(ws):
            raise RequestError(
                "[line] friction_coefficients and friction_weights: as many of each, at least one"
            )
        # a weight of 1e308 is finite, but two of them sum to inf, and every share to 0
        total = sum(ws) if all(math.isfinite(w) and w >= 0 for w in ws) else math.nan  # inf on overflow
        if any(not (0.001 <= m <= 1.0) for m in mus) or not (math.isfinite(total) and total > 0):
            raise RequestError(
                "[line] friction coefficients 0.001 to 1; weights finite, 0 or more, "
                "with a finite sum above 0"
            )
        if not 0.0 <= self.modifier_share <= 1.0:
            raise RequestError(
                f"[line] modifier_share = {self.modifier_share!r}: a share of the time, 0 to 1"
            )

        if self.radius_step != 0.0 and not 0.01 <= self.radius_step <= 0.5:
            raise RequestError(
                f"[line] radius_step = {self.radius_step!r}: 0, or a relative step of 0.01 to 0.5"
            )

    def grid_radius_m(self, radius_m: float) -> float:
        """The radius a curve's map is run at (``radius_step``): its own, or the nearest of
        the geometric grid 100 (1 + step)^k m."""
        if self.radius_step == 0.0:
            return radius_m
        ratio = math.log1p(self.radius_step)
        grid = round(GRID_ORIGIN_M * math.exp(ratio * round(math.log(radius_m / GRID_ORIGIN_M) / ratio)), 3)
        # a grid radius tighter than a bogie runs (the grid rounds 52 m down to 44.4 m) is
        # no curve: such a curve's map is run at its own radius
        return grid if grid >= radius_m or grid >= TIGHTEST_GRID_RADIUS_M else radius_m

    def states(self) -> list[tuple[float, str, float]]:
        """The friction states: (friction coefficient, friction law, share of the time)."""
        total = float(sum(self.friction_weights))
        out = []
        for mu, w in zip(self.friction_coefficients, self.friction_weights):
            share = w / total
            if self.modifier_share < 1.0:
                out.append((float(mu), "falling", share * (1.0 - self.modifier_share)))
            if self.modifier_share > 0.0:
                out.append((float(mu), "constant", share * self.modifier_share))
        return [s for s in out if s[2] > 0.0]

    def bogies_per_hour(self, period: str) -> float:
        return self.trains_per_hour[period] * self.bogies_per_train


def load_line_spec(data: dict[str, Any] | None, source: str) -> LineSpec:
    """A :class:`LineSpec` from a ``[line]`` table (None: the defaults)."""
    if data is None:
        return LineSpec()
    if not isinstance(data, dict):
        raise RequestError(f"{source}: line = {str(data)[:40]!r}: [line] is a table ({', '.join(LINE_KEYS)})")
    unknown = sorted(set(data) - set(LINE_KEYS))
    if unknown:
        raise RequestError(f"{source}: [line] {unknown[0]!r} is not a key; allowed: {', '.join(LINE_KEYS)}")
    d = LineSpec()
    try:
        return LineSpec(
            trains_per_hour={k: float(v) for k, v in data.get("trains_per_hour", d.trains_per_hour).items()},
            bogies_per_train=float(data.get("bogies_per_train", d.bogies_per_train)),
            friction_coefficients=tuple(
                float(x) for x in data.get("friction_coefficients", d.friction_coefficients)
            ),
            friction_weights=tuple(float(x) for x in data.get("friction_weights", d.friction_weights)),
            modifier_share=float(data.get("modifier_share", d.modifier_share)),
            radius_step=float(data.get("radius_step", d.radius_step)),
        )
    except RequestError as exc:  # LineSpec's own, which names the key
        raise RequestError(f"{source}: {exc}") from None
    except (TypeError, ValueError, AttributeError) as exc:
        raise RequestError(f"{source}: [line]: {exc}") from None


def read_line_spec(path: Path | None) -> LineSpec:
    """The ``[line]`` table of a TOML file (``--traffic``), or the defaults."""
    if path is None:
        return LineSpec()
    _, data = read_toml(path, "traffic file", RequestError)
    return load_line_spec(data.get("line"), str(path))
