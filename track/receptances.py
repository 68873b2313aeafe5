"""A track's point receptances at a sleeper and at midspan, vertical and lateral
(:func:`track.beam.receptance`), the fits the squeal model takes (:mod:`track.fit`) and its
resonances, on a frequency grid (:func:`track_receptances`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .beam import pinned_pinned_frequency_hz, receptance
from .design_sections import Track

__all__ = ["CONVENTION", "TrackReceptances", "track_receptances"]

#: The receptances' sign convention, said in every file that holds them
CONVENTION = "alpha = u / F [m/N] for u, F ~ exp(+i omega t): Im(alpha) <= 0 at a passive point"


@dataclass(frozen=True)
class TrackReceptances:
    """A track's point receptances [m/N] on a frequency grid, and what the squeal model
    takes from them.

    Attributes
    ----------
    frequency_hz : numpy.ndarray
    vertical_support, vertical_midspan, lateral_support, lateral_midspan : numpy.ndarray
        Complex receptances at a sleeper and at midspan.
    pinned_pinned_hz : dict
        The simply supported span's first bending frequency, vertical and lateral [Hz].
    fits : dict
        Per direction at the contact's position: the rational fit's states, its band, its
        error in the weights' norm and its largest relative error (``track.fit``).
    """

    frequency_hz: np.ndarray
    vertical_support: np.ndarray
    vertical_midspan: np.ndarray
    lateral_support: np.ndarray
    lateral_midspan: np.ndarray
    pinned_pinned_hz: dict[str, float]
    fits: dict[str, dict[str, Any]]

    def rows(self) -> list[dict[str, float]]:
        """receptance.csv's rows."""
        out = []
        for k, f in enumerate(self.frequency_hz):
            row = {"frequency_hz": float(f)}
            for name in ("vertical_support", "vertical_midspan", "lateral_support", "lateral_midspan"):
                a = getattr(self, name)[k]
                row[f"{name}_re"], row[f"{name}_im"] = float(a.real), float(a.imag)
            out.append(row)
        return out

    def pad_peak_hz(self) -> float:
        """The vertical receptance's peak at a sleeper between 150 Hz and the pinned-pinned
        frequency: the rail bouncing on its pads [Hz] (NaN outside the grid)."""
        f = self.frequency_hz
        sel = (f > 150.0) & (f < 0.8 * self.pinned_pinned_hz["vertical"])
        if not sel.any():
            return float("nan")
        return float(f[sel][np.argmax(np.abs(self.vertical_support[sel]))])

    def summary(self) -> dict[str, Any]:
        return {
            "convention": CONVENTION,
            "frequency_range_hz": [float(self.frequency_hz[0]), float(self.frequency_hz[-1])],
            "pinned_pinned_vertical_hz": self.pinned_pinned_hz["vertical"],
            "pinned_pinned_lateral_hz": self.pinned_pinned_hz["lateral"],
            **{f"fit_{d}": fit for d, fit in self.fits.items()},
        }


def track_receptances(
    body: Track, fmin_hz: float = 20.0, fmax_hz: float = 5000.0, points: int = 300
) -> TrackReceptances:
    """The receptances of the track ``body`` at ``points`` frequencies spaced
    logarithmically from ``fmin_hz`` to ``fmax_hz`` [Hz]; ValueError for another grid.

    Examples
    --------
    >>> from track.design_sections import Track
    >>> t = track_receptances(Track(), 100.0, 1000.0, 5)
    >>> round(t.pinned_pinned_hz["vertical"])
    1068
    """
    if not (0.0 < fmin_hz < fmax_hz <= 20000.0) or not 2 <= points <= 20000:
        raise ValueError("the grid: 0 < fmin < fmax <= 20000 Hz and 2 to 20000 points")
    f = np.geomspace(fmin_hz, fmax_hz, int(points))
    (bv, bl), (sv, sl) = body.beams(), body.supports()
    vertical_fit, lateral_fit = body.fits()
    fits = {
        name: {
            "states": fit.order,
            "band_hz": list(fit.band_hz),
            "weighted_error": fit.weighted_error,
            "max_relative_error": fit.max_relative_error,
            "position": body.position,
        }
        for name, fit in (("vertical", vertical_fit), ("lateral", lateral_fit))
    }
    return TrackReceptances(
        f,
        receptance(bv, sv, f, 0.0),
        receptance(bv, sv, f, 0.5),
        receptance(bl, sl, f, 0.0),
        receptance(bl, sl, f, 0.5),
        {
            "vertical": pinned_pinned_frequency_hz(bv, body.sleeper_spacing),
            "lateral": pinned_pinned_frequency_hz(bl, body.sleeper_spacing),
        },
        fits,
    )
