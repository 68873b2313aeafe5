"""What the ``track`` command writes: receptance.csv (the four receptances, real and
imaginary parts) and receptance.png (magnitude and phase on log axes, the rail-on-pad
peak and the pinned-pinned frequency marked)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from track.receptances import CONVENTION, TrackReceptances

from ..output_files import columns_of
from ..outputs import write_csv

__all__ = ["track_text", "write_receptance_csv", "write_receptance_plot"]


def write_receptance_csv(path: Path, t: TrackReceptances) -> Path:
    return write_csv(path, t.rows(), columns_of("receptance.csv"))


def write_receptance_plot(path: Path, t: TrackReceptances) -> Path:
    from matplotlib.figure import Figure

    from .canvas import PLOT_DPI

    fig = Figure(figsize=(10, 6.5))
    mag, phase = fig.subplots(2, 1, sharex=True)
    fig.subplots_adjust(left=0.1, right=0.97, bottom=0.09, top=0.92, hspace=0.08)
    for name, colour, style in (
        ("vertical_support", "C0", "-"),
        ("vertical_midspan", "C0", "--"),
        ("lateral_support", "C3", "-"),
        ("lateral_midspan", "C3", "--"),
    ):
        a = getattr(t, name)
        label = name.replace("_", ", at ").replace("support", "a sleeper")
        mag.loglog(t.frequency_hz, np.abs(a), style, color=colour, label=label)
        phase.semilogx(t.frequency_hz, np.degrees(np.angle(a)), style, color=colour)
    marks = [
        ("pinned-pinned, vertical", t.pinned_pinned_hz["vertical"]),
        ("pinned-pinned, lateral", t.pinned_pinned_hz["lateral"]),
        ("rail on pads, vertical", t.pad_peak_hz()),
    ]
    shown = [
        (what, f) for what, f in marks if np.isfinite(f) and t.frequency_hz[0] <= f <= t.frequency_hz[-1]
    ]
    for _, f in shown:
        for ax in (mag, phase):
            ax.axvline(f, color="0.5", lw=0.8, ls=":")
    if shown:
        phase.text(
            0.99,
            0.04,
            "dotted: " + "; ".join(f"{what} {f:.0f} Hz" for what, f in shown),
            transform=phase.transAxes,
            ha="right",
            va="bottom",
            fontsize=8,
        )
    mag.set(
        ylabel="|receptance| (m/N)", title="the rail's point receptance (exp(+i w t): phase <= 0 passive)"
    )
    mag.legend(fontsize=8, loc="lower left")
    phase.set(xlabel="frequency (Hz)", ylabel="phase (deg)", ylim=(-185, 5))
    for ax in (mag, phase):
        ax.grid(True, which="both", alpha=0.3)
    fig.savefig(path, dpi=PLOT_DPI)
    return Path(path)


#: The receptances track_text prints, and their headings
_COLUMNS = (
    ("vertical_support", "vertical, sleeper"),
    ("vertical_midspan", "vertical, midspan"),
    ("lateral_support", "lateral, sleeper"),
    ("lateral_midspan", "lateral, midspan"),
)


def track_text(t: TrackReceptances) -> str:
    """The receptances at a few frequencies, the pinned-pinned frequencies and the fits."""
    lines = [f"{'f [Hz]':>8} " + " ".join(f"{heading:>22}" for _, heading in _COLUMNS)]
    for f in (100.0, 300.0, 500.0, 1000.0, 2000.0):
        if not t.frequency_hz[0] <= f <= t.frequency_hz[-1]:
            continue
        k = int(np.argmin(np.abs(np.log(t.frequency_hz / f))))
        cells = [getattr(t, name)[k] for name, _ in _COLUMNS]
        lines.append(
            f"{t.frequency_hz[k]:8.1f} "
            + " ".join(f"{abs(a):12.3e} {np.degrees(np.angle(a)):6.1f} deg" for a in cells)
        )
    lines.append(f"|alpha| [m/N] and phase; {CONVENTION}")
    pp = t.pinned_pinned_hz
    lines.append(f"pinned-pinned: {pp['vertical']:.0f} Hz vertical, {pp['lateral']:.0f} Hz lateral")
    for d, fit in t.fits.items():
        band = f"{fit['band_hz'][0]:g}-{fit['band_hz'][1]:g} Hz"
        lines.append(
            f"{d} fit at the contact ({fit['position']}): {fit['states']} states over {band}, "
            f"error {fit['weighted_error']:.1%} weighted towards the rail's mobility"
        )
    return "\n".join(lines)
