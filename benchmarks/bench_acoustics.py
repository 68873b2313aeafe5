"""Convergence of the radiation solver: error against elements per wavelength (the
sphere, against the exact solution) and the wheel's (3,0) mode per 1 m/s against mesh,
layer and FE preset, with DOFs and times.

    .venv/bin/python benchmarks/bench_acoustics.py
"""

from __future__ import annotations

import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import acoustics as ac  # noqa: E402
import wheel_squeal as ws  # noqa: E402
from wheel_squeal.listener import default_microphone  # noqa: E402
from wheel_squeal.sound import mode_surface  # noqa: E402

EPW = (4.0, 6.0, 8.0, 12.0, 16.0)


def _timed(fn, n: int = 3):
    times, out = [], None
    for _ in range(n):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out


def _sphere_row(l_, m, ka, settings, segments, label, a=0.1) -> None:
    k = ka / a
    f = k * ac.AIR.sound_speed_m_s / (2 * math.pi)
    t = np.linspace(0.25, math.pi - 0.25, 6)
    far = (1 + settings.margin) * a * 0.95
    pts = np.concatenate([np.stack([rho * np.sin(t), rho * np.cos(t)], axis=1) for rho in (a, 1.2 * a, far)])
    exact = ac.sphere_pressure(l_, m, a, k, pts)
    s, field = _timed(
        lambda: ac.radiate(ac.sphere_surface(l_, m, a, segments=segments), f, settings=settings)
    )
    ratio = field.pressure_at(pts) / exact
    print(
        f"| {l_}, {m} | {ka:g} | {label} | {len(field.pressure)} | "
        f"{np.max(np.abs(20 * np.log10(np.abs(ratio)))):.3f} | "
        f"{np.max(np.abs(np.angle(ratio, deg=True))):.2f} | "
        f"{100 * (field.sound_power_w / ac.sphere_sound_power(l_, m, a, k) - 1):+.2f} | {s:.2f} |",
        flush=True,
    )


def sphere_table() -> None:
    print("sphere a = 0.1 m: max error on the surface, at 1.2 a and near R (6 angles each); power error")
    print("| l, m | ka | mesh | DOFs | pressure error [dB] | phase [deg] | power error [%] | time [s] |")
    print("|---|---|---|---|---|---|---|---|")
    for (l_, m), ka in (((0, 0), 5.0), ((1, 0), 1.0), ((3, 3), 0.2), ((3, 3), 5.0)):
        _sphere_row(l_, m, ka, ac.RadiationSettings(), 120, "default (8/wavelength, 120 segments)")
    # a domain of 3 radii, where the wavelength sets the element size
    for epw in EPW:
        settings = ac.RadiationSettings(elements_per_wavelength=epw, margin=2.0)
        _sphere_row(3, 3, 5.0, settings, 120, f"R = 3a, {epw:g}/wavelength")
    for segments in (15, 30, 60, 120, 240):
        _sphere_row(3, 3, 5.0, ac.RadiationSettings(), segments, f"{segments} segments on the sphere")


def wheel_table() -> None:
    design = ws.load_design()
    mic = default_microphone(design)
    print()
    print("designs/table1.toml, per 1 m/s contact velocity, microphone 0.05 m off the rim face at R1")
    print(
        "| FE preset | mode | f [Hz] | settings | DOFs | L_W [dB re 1 pW] | SPL [dB re 20 uPa] "
        "| efficiency | time [s] |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    directivity_fields = []
    variants = [(f"{epw:g} el/wavelength", ac.RadiationSettings(elements_per_wavelength=epw)) for epw in EPW]
    variants += [
        ("layer 2x thicker", ac.RadiationSettings(pml_wavelengths=0.5, pml_min_fraction=1.0)),
        ("layer farther (margin 0.6)", ac.RadiationSettings(margin=0.6)),
        ("attenuation 20 Np", ac.RadiationSettings(pml_attenuation=20.0)),
    ]
    for fid in ("fast", "balanced", "accurate"):
        ms = ws.compute_modes(design, fid)
        for label in ("n=3,c=0", "n=6,c=0"):
            mode, _ = ws.pick_mode(ms, label)
            surface = mode_surface(ms, mode, mode.frequency_hz)
            rows = variants if fid == "balanced" else variants[2:3]
            for name, settings in rows:
                s, field = _timed(
                    lambda settings=settings, surface=surface, f=mode.frequency_hz: ac.radiate(
                        surface, f, settings=settings
                    )
                )
                spl = float(ac.spl_db(field.pressure_at(np.array([mic[:2]]))[0]))
                lw = float(ac.sound_power_level_db(field.sound_power_w))
                print(
                    f"| {fid} | {mode.label()} | {mode.frequency_hz:.1f} | {name} | {len(field.pressure)} | "
                    f"{lw:.2f} | {spl:.2f} | {field.radiation_efficiency:.4f} | {s:.2f} |",
                    flush=True,
                )
                if fid == "balanced" and name == variants[2][0]:
                    directivity_fields.append((mode.label(), field))
    directivity_table(directivity_fields)


def _far_field_with_jvp(traces, n: int, k: float, cos_theta: np.ndarray) -> np.ndarray:
    """The baseline: ``acoustics.helmholtz.far_field`` with SciPy's jvp for J_n' (three
    Bessel evaluations)."""
    from scipy.special import jv, jvp

    x, (nr, nz), p, dp, ds = traces
    r, z = x
    st, ct = np.sqrt(1.0 - cos_theta**2)[:, None], cos_theta[:, None]
    kappa = k * r[None, :] * st
    jn, jnp_ = jv(n, kappa), jvp(n, kappa)
    phase = np.exp(1j * k * z[None, :] * ct)
    ring_cos = 2 * np.pi * (1j**n) * jn
    ring_cos1 = 2 * np.pi * (1j ** (n - 1)) * jnp_
    dG = 1j * k * p[None, :] * (st * nr[None, :] * ring_cos1 + ct * nz[None, :] * ring_cos)
    integrand = phase * (dG - dp[None, :] * ring_cos) * (r * ds)[None, :]
    return integrand.sum(axis=1) / (4 * np.pi)


def directivity_table(fields) -> None:
    """The far-field directivity the pass-by reads (``acoustics.farfield.DIRECTIVITY_ANGLES``)
    against the same integral with SciPy's jvp, in the same run: time and difference."""
    from acoustics.farfield import DIRECTIVITY_ANGLES
    from acoustics.helmholtz import far_field

    print()
    print("far-field directivity, balanced preset, 8 el/wavelength, medians of 5")
    print("| mode | angles | time [s] | with jvp [s] | ratio | largest difference (relative) |")
    print("|---|---|---|---|---|---|")
    for label, field in fields:
        args = (field.body.as_tuple(), field.harmonic, field.wavenumber, np.cos(DIRECTIVITY_ANGLES))
        s, d = _timed(lambda args=args: far_field(*args), 5)
        b, ref = _timed(lambda args=args: _far_field_with_jvp(*args), 5)
        diff = float(np.max(np.abs(d - ref)) / np.max(np.abs(ref)))
        print(f"| {label} | {len(DIRECTIVITY_ANGLES)} | {s:.3f} | {b:.3f} | {s / b:.2f} | {diff:.1e} |")


if __name__ == "__main__":
    sphere_table()
    wheel_table()
