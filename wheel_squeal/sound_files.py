"""The sound's files: the SPL map around the wheel and on a circle (PNG), the pressure
field (VTU, for ParaView), and the sweep's SPL against crabbing velocity (the paper's
Fig. 5 counterpart, CSV and PNG)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from reduced.report import PLOT_DPI

__all__ = ["sound_text", "write_pressure_vtu", "write_sound_plot"]


def write_sound_plot(path: Path, sound) -> Path:
    """sound_field.png: SPL in the (r, z) plane around the wheel (both sides of the
    axis, theta = 0 and pi), and the SPL on the circle of 0.9 R, with the microphone."""
    from matplotlib.figure import Figure
    from matplotlib.tri import Triangulation

    from acoustics import spl_db

    from .sound import ring_points

    field, v = sound.field, sound.velocity_amplitude_m_s
    pts, tri = field.mesh.points, field.mesh.triangles
    inside = np.hypot(*pts[tri].mean(axis=1).T) <= field.mesh.radius
    level = spl_db(field.vertex_pressure() * max(v, 1e-300))
    top = float(np.max(level[np.unique(tri[inside])]))
    level = np.clip(np.nan_to_num(level, neginf=top - 60), top - 60, None)  # P = 0 on the axis
    fig = Figure(figsize=(11, 4.8))
    ax, ax2 = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.4, 1]})
    fig.subplots_adjust(left=0.06, right=0.97, bottom=0.12, top=0.9, wspace=0.3)
    for sign in (1, -1):
        t = Triangulation(sign * pts[:, 0], pts[:, 1], tri[inside])
        im = ax.tripcolor(t, level, shading="gouraud", cmap="magma", vmin=top - 40, vmax=top)
    r, z, _ = sound.microphone
    ax.plot([r], [z], "c^", ms=8, label=f"microphone (r {r:g} m, z {z:g} m)")
    ax.set(
        aspect="equal",
        xlabel="r (m)  [theta = 0 right, pi left]",
        ylabel="z (m)",
        title=f"SPL (dB re 20 uPa), {field.frequency_hz:.0f} Hz, n = {field.harmonic}, "
        f"{v:.3g} m/s at the contact",
    )
    ax.legend(loc="lower right", fontsize=8)
    fig.colorbar(im, ax=ax, shrink=0.85)
    ring = ring_points(field.mesh.radius)
    rc = float(np.hypot(*ring[0]))
    ring_level = spl_db(sound.radiation.ring_pressure_pa * max(v, 1e-300))
    ax2.plot(np.degrees(np.arctan2(ring[:, 0], ring[:, 1])), ring_level, "k-")
    ax2.set_ylim(float(np.max(ring_level)) - 50, float(np.max(ring_level)) + 5)
    ax2.set(
        xlabel="angle from the +z axis (deg)",
        ylabel="SPL (dB re 20 uPa)",
        title=f"on the circle rho = {rc:.3f} m, theta = 0",
    )
    ax2.grid(alpha=0.3)
    fig.savefig(path, dpi=PLOT_DPI)
    return Path(path)


def write_pressure_vtu(path: Path, sound) -> Path:
    """pressure.vtu: the pressure field on the (r, z) plane (x = r, y = z) for ParaView:
    real and imaginary parts, amplitude [Pa] and SPL [dB]."""
    import meshio

    from acoustics import spl_db

    field = sound.field
    p = field.vertex_pressure() * sound.velocity_amplitude_m_s
    pts = np.column_stack([field.mesh.points, np.zeros(len(field.mesh.points))])
    mesh = meshio.Mesh(
        pts,
        [("triangle", field.mesh.triangles)],
        point_data={
            "pressure_real_pa": p.real,
            "pressure_imag_pa": p.imag,
            "pressure_amplitude_pa": np.abs(p),
            "spl_db": np.nan_to_num(spl_db(p), neginf=-100.0),
        },
    )
    mesh.write(path)
    return Path(path)


def sound_text(summary: dict) -> str:
    """One line: the levels, at which contact velocity and where they were taken."""
    r, z, theta = summary["microphone_m"]
    where = f"at the microphone (r {r:g} m, z {z:g} m, theta {theta:g})"
    v = summary["velocity_amplitude_m_s"]
    if summary["sound_power_level_db"] is None:
        return f"sound: none (contact velocity amplitude {v:g} m/s)"
    spl = (
        f"SPL {summary['spl_db']:.1f} dB re 20 uPa {where}"
        if summary["spl_db"] is not None
        else f"no pressure {where}: a pressure node of this mode (on the axis, or theta on a nodal diameter)"
    )
    return (
        f"sound: sound power level {summary['sound_power_level_db']:.1f} dB re 1 pW, {spl}, "
        f"radiation efficiency {summary['radiation_efficiency']:.3g}, {summary['frequency_hz']:.1f} Hz, "
        f"contact velocity {v:.4g} m/s (wheel alone, free field)"
    )
