"""The static flexibility at the contact, in the normal direction, of the modes above
fmax, against the Hertz spring's: the modes between fmax and a cut-off summed
(phi_n^2 / omega^2 over their members), and what it changes in the linear stability
when put in series with the Hertz spring. Prints the table of docs/theory.md
(truncation).

    .venv/bin/python benchmarks/residual_flexibility.py
"""

from __future__ import annotations

import dataclasses
import math
import sys
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import wheel_squeal as ws  # noqa: E402
from wheel_squeal.mode_stability import stability_table  # noqa: E402
from wheel_squeal.presets import DEFAULT_FMAX_HZ  # noqa: E402

CASES = (("table1", 0.0), ("table1", 2.0), ("table1_crowned", 15.0))
CUTOFFS_HZ = (10_000.0, 20_000.0, 40_000.0)


def residual(modes, f_lo: float, f_hi: float) -> float:
    """sum phi_n^2 / omega^2 [m/N] over the members of the modes in (f_lo, f_hi]."""
    return sum(
        sum(x * x for x in m.contact_normal) / m.omega**2 for m in modes if f_lo < m.frequency_hz <= f_hi
    )


def main() -> None:
    warnings.simplefilter("ignore")
    print(
        "| design | angle | 1/k_H [m/N] | "
        + " | ".join(f"to {f / 1e3:g} kHz" for f in CUTOFFS_HZ)
        + " | growth rates change | tones change | fastest, mechanism |"
    )
    print("|---" * (6 + len(CUTOFFS_HZ)) + "|")
    for name, deg in CASES:
        d = ws.load_design(name).replace(contact_angle=math.radians(deg))
        law = ws.contact_law(d)
        k_h = law.normal_stiffness_n_m
        wide = ws.compute_modes(d, "balanced", fmax_hz=max(CUTOFFS_HZ)).modes
        shares = [residual(wide, DEFAULT_FMAX_HZ, f) * k_h for f in CUTOFFS_HZ]
        # in series with the Hertz spring, the residual up to 20 kHz
        k_eff = 1.0 / (1.0 / k_h + residual(wide, DEFAULT_FMAX_HZ, 20_000.0))
        softer = dataclasses.replace(law, hertz_approach_m=1.5 * law.normal_load_n / k_eff)
        modes, op = ws.compute_modes(d, "balanced"), ws.operating_point(d)
        a, _ = stability_table(d, modes, law, op)
        b, _ = stability_table(d, modes, softer, op)
        grow = [
            (x.stability, y.stability) for x, y in zip(a, b) if x.stability.unstable or y.stability.unstable
        ]
        dg = max(abs(x.growth_rate_1_s - y.growth_rate_1_s) for x, y in grow)
        df = max(abs(x.damped_frequency_hz - y.damped_frequency_hz) / x.damped_frequency_hz for x, y in grow)
        fa = max(a, key=lambda row: row.stability.growth_rate_1_s)
        fb = max(b, key=lambda row: row.stability.growth_rate_1_s)
        same = (
            "same"
            if (fa.mode.index, fa.stability.mechanism) == (fb.mode.index, fb.stability.mechanism)
            else "CHANGED"
        )
        print(
            f"| {name} | {deg:g} deg | {1 / k_h:.3g} | "
            + " | ".join(f"{s:.1%}" for s in shares)
            + f" | <= {dg:.2g} 1/s | <= {df:.2%} | {same} ({fa.mode.label()}, {fa.stability.mechanism}) |"
        )


if __name__ == "__main__":
    main()
