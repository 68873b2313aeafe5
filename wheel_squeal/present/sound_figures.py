"""The PNG figures of a squeal's sound: the sound field with its far-field directivity
(sound_field.png) and the line spectra and band levels of the limit cycle (spectrum.png).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .canvas import PLOT_DPI

if TYPE_CHECKING:
    from ..simulation import Simulation
    from ..squeal_sound import SquealSound

__all__ = [
    "DIRECTIVITY_RANGE_DB",
    "NEAR_FIELD_RADII",
    "SPECTRUM_RANGE_DB",
    "write_sound_plot",
    "write_spectrum_plot",
]


#: The near-field map spans this many wheel radii around the wheel centre
NEAR_FIELD_RADII = 1.6


#: The directivity's dynamic range drawn [dB below its maximum]
DIRECTIVITY_RANGE_DB = 40.0


def write_sound_plot(path: Path, sound: SquealSound) -> Path:
    """sound_field.png: the SPL in the (r, z) plane around the wheel, framed on its near
    field (both sides of the axis, theta = 0 and pi), with the microphone; and the
    far-field directivity in the meridian plane as a polar plot (dB re its maximum, all
    harmonics), with the pattern around the axis stated."""
    from matplotlib.figure import Figure
    from matplotlib.tri import Triangulation

    from acoustics import spl_db
    from acoustics.farfield import DIRECTIVITY_ANGLES

    field, v = sound.fundamental.field, sound.fundamental.velocity_amplitude_m_s
    pts, tri = field.mesh.points, field.mesh.triangles
    inside = np.hypot(*pts[tri].mean(axis=1).T) <= field.mesh.radius
    level = spl_db(field.vertex_pressure() * max(v, 1e-300))
    top = float(np.max(level[np.unique(tri[inside])]))
    level = np.clip(np.nan_to_num(level, neginf=top - 60), top - 60, None)  # P = 0 on the axis
    fig = Figure(figsize=(11, 4.8))
    ax = fig.add_subplot(1, 2, 1)
    polar: Any = fig.add_subplot(1, 2, 2, projection="polar")  # a PolarAxes
    fig.subplots_adjust(left=0.06, right=0.95, bottom=0.1, top=0.8, wspace=0.25)
    for sign in (1, -1):
        t = Triangulation(sign * pts[:, 0], pts[:, 1], tri[inside])
        im = ax.tripcolor(t, level, shading="gouraud", cmap="magma", vmin=top - 40, vmax=top)
    r, z, _ = sound.fundamental.microphone
    ax.plot([r], [z], "c^", ms=8, label=f"microphone (r {r:g} m, z {z:g} m)")
    span = NEAR_FIELD_RADII * float(np.max(field.body.points[0]))
    ax.set(
        aspect="equal",
        xlim=(-span, span),
        ylim=(-span, span),
        xlabel="r (m)  [theta = 0 right, pi left]",
        ylabel="z (m), the wheel's axis",
        title=f"near field: SPL (dB re 20 uPa) at {field.frequency_hz:.0f} Hz,\n"
        f"n = {field.harmonic}, {v:.3g} m/s at the contact",
    )
    ax.legend(loc="lower right", fontsize=8)
    fig.colorbar(im, ax=ax, shrink=0.85, label="SPL (dB re 20 uPa)")
    total = sum((h.velocity_amplitude_m_s * h.radiation.directivity_pa_m) ** 2 for h in _harmonics(sound))
    db = 10 * np.log10(np.maximum(total / max(float(np.max(total)), 1e-300), 1e-30))
    radius = np.clip(db + DIRECTIVITY_RANGE_DB, 0.0, None)
    theta = np.concatenate([DIRECTIVITY_ANGLES, 2 * np.pi - DIRECTIVITY_ANGLES[::-1]])
    polar.plot(theta, np.concatenate([radius, radius[::-1]]), "k-")
    polar.set_theta_zero_location("N")  # the +z axis up and r > 0 to the right, as in the map
    polar.set_theta_direction(-1)
    polar.set_rticks([10, 20, 30, 40])
    polar.set_yticklabels([f"{x - DIRECTIVITY_RANGE_DB:g}" for x in (10, 20, 30, 40)], fontsize=7)
    polar.set_rlim(0, DIRECTIVITY_RANGE_DB)
    polar.set_title(
        "far-field directivity, meridian plane\n(dB re max; 0 deg: +z axis);\n"
        f"around the axis as cos({field.harmonic} phi)",
        fontsize=9,
        pad=18,
    )
    fig.savefig(path, dpi=PLOT_DPI)
    return Path(path)


def _harmonics(sound: SquealSound) -> tuple[Any, ...]:
    """The harmonics of a squeal's sound (a bare tone: itself)."""
    return getattr(sound, "harmonics", (sound,))


def write_spectrum_plot(path: Path, simulation: Simulation, sound: SquealSound) -> Path:
    """spectrum.png: the line spectra of the contact velocity, the lateral contact force
    and the microphone pressure over whole periods of the limit cycle, and the
    microphone's one-third-octave band levels with their A-weighted sum."""
    from matplotlib.figure import Figure

    from acoustics.signal import line_spectrum, periodic_samples

    h, signal = simulation.history, sound.signal
    assert signal is not None  # a squeal's sound keeps its record
    start, end, count = signal.window
    n = len(signal.cycle_pa)
    rows = [
        ("contact velocity", h.v, "dB re 1 m/s", 1.0, 20.0),
        ("lateral contact force", h.Q, "dB re 1 N", 1.0, 20.0),
    ]
    fig = Figure(figsize=(11, 6.4))
    axes = fig.subplots(2, 2)
    fig.subplots_adjust(left=0.08, right=0.98, bottom=0.09, top=0.92, hspace=0.45, wspace=0.25)
    f0 = count / (end - start)
    for ax, (name, x, unit, ref, scale) in zip(axes.flat, rows):
        k, amp = line_spectrum(periodic_samples(h.t, x, start, end, n), count)
        _lines(ax, k * f0, scale * np.log10(np.maximum(amp / ref, 1e-30)))
        ax.set(title=f"{name}: amplitude per harmonic", xlabel="frequency (Hz)", ylabel=unit)
    ax = axes.flat[2]
    spl = [x["spl_db"] for x in sound.summary()["harmonics"]]  # computed once, before the plot
    _lines(ax, sound.frequencies_hz, np.array(spl, float))
    ax.set(
        title=f"microphone: SPL of the {len(spl)} harmonic(s) radiated",
        xlabel="frequency (Hz)",
        ylabel="dB re 20 uPa",
        xlim=axes.flat[0].get_xlim(),
    )
    s = sound.summary()
    bands = s["third_octave_bands"]
    ax = axes.flat[3]
    labels = [b["label_hz"] for b in bands]
    values = [b["spl_db"] if b["spl_db"] is not None else np.nan for b in bands]
    ax.bar(range(len(labels)), values, color="0.4")
    ax.set_xticks(range(len(labels)), [f"{x:g}" for x in labels], rotation=90, fontsize=6)
    ax.set(
        title="one-third-octave bands: "
        + (f"{s['spl_db']:.1f} dB, {s['spl_dba']:.1f} dB(A)" if s["spl_db"] is not None else "silent"),
        xlabel="band centre (Hz)",
        ylabel="dB re 20 uPa",
    )
    finite = [x for x in values if np.isfinite(x)]
    if finite:
        ax.set_ylim(max(finite) - 80, max(finite) + 5)
    ax.grid(alpha=0.3, axis="y")
    fig.suptitle(f"the limit cycle over {count} periods ({start:.3f}-{end:.3f} s), tone {f0:.1f} Hz")
    fig.savefig(path, dpi=PLOT_DPI)
    return Path(path)


#: The line spectra are drawn down to this many dB below their largest line
SPECTRUM_RANGE_DB = 100.0


def _lines(ax: Any, f: np.ndarray, level: np.ndarray) -> None:
    """A line spectrum: a line from the floor up to each level, the floor
    :data:`SPECTRUM_RANGE_DB` below the largest."""
    finite = level[np.isfinite(level)]
    if not len(finite):
        ax.text(0.5, 0.5, "silent", transform=ax.transAxes, ha="center", va="center")
        return
    top = float(finite.max())
    floor = top - SPECTRUM_RANGE_DB
    keep = level > floor
    ax.vlines(f[keep], floor, level[keep], color="C0")
    ax.plot(f[keep], level[keep], "o", color="C0", ms=4)
    ax.set_ylim(floor, top + 5)
    ax.grid(alpha=0.3)
