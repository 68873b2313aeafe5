"""Which eigenvalues grow, by which mechanism, at what tone, as the contact moves across
the tread: the Table 1 wheel (whose 0.3 m crown reaches 2.5 deg) and the same wheel
with a 28 mm crown (27 deg), both friction laws, rotation off and on, at the Fig. 6
point; then whether a roller mode in series, or transient creep, makes the (3,0) mode
the one that squeals. Prints the tables of docs/guide/which-mode.md.

    .venv/bin/python benchmarks/contact_angle.py [--fidelity balanced]
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import wheel_squeal as ws  # noqa: E402
from wheel_squeal.mode_stability import eigenvalue_list, stability_table  # noqa: E402

ANGLES_DEG = {"table1": [0.0, 1.0, 2.0, 2.4, -2.4], "table1_crowned": [0.0, 5.0, 10.0, 15.0, 20.0, 25.0]}


def growing(design, modes, law: str, rotation: bool, rpm: float = 800.0) -> list[dict]:
    contact = ws.contact_law(design, friction_law=law)
    op = ws.operating_point(design, rpm=rpm, crabbing_velocity_m_s=0.39)
    table = stability_table(design, modes, contact, op, rotation)
    return [e for e in eigenvalue_list(table, design) if e["mechanism"] is not None]


def cell(grow: list[dict]) -> str:
    if not grow:
        return "nothing grows"
    top = grow[0]
    who = " + ".join(p["mode"] for p in top["participants"][:2])
    coupled = sum(e["mechanism"] != "falling friction" for e in grow)
    extra = f"; {coupled} by mode coupling" if coupled and top["mechanism"] == "falling friction" else ""
    return (
        f"{len(grow)} grow; fastest {who} {top['damped_frequency_hz']:.0f} Hz, "
        f"{top['growth_rate_1_s']:.3g} 1/s, {top['mechanism']}{extra}"
    )


def angle_table(fidelity: str) -> None:
    print("| design | angle [deg] | friction | rotation off | rotation on |")
    print("|---|---|---|---|---|")
    for name, angles in ANGLES_DEG.items():
        base = ws.load_design(name)
        for deg in angles:
            d = base.replace(contact_angle=math.radians(deg))
            modes = ws.compute_modes(d, fidelity)
            for law in ("falling", "constant"):
                off, on = (cell(growing(d, modes, law, rot)) for rot in (False, True))
                print(f"| {name} | {deg:g} | {law} | {off} | {on} |")


def counter_body_table(fidelity: str) -> None:
    """Roller modes in series (plausible for an 85 mm, 7 kg steel roller on its shaft):
    does the (3,0) mode become the fastest-growing?"""
    base = ws.load_design("table1_crowned").replace(contact_angle=math.radians(15.0))
    print("| roller mode | rotation off | rotation on |")
    print("|---|---|---|")
    for direction in ("normal", "lateral"):
        for f_hz in (600.0, 1100.0, 1200.0, 2500.0):
            for mass in (2.0, 7.0):
                d = base.replace(
                    **{
                        f"{direction}_frequency_hz": f_hz,
                        f"{direction}_damping_ratio": 0.01,
                        f"{direction}_modal_mass_kg": mass,
                    }
                )
                modes = ws.compute_modes(d, fidelity)
                off, on = (cell(growing(d, modes, "falling", rot)) for rot in (False, True))
                print(f"| {direction} {f_hz:g} Hz, {mass:g} kg, 1 % | {off} | {on} |")


def transient_creep_table(fidelity: str) -> None:
    """The growth rates of the Table 1 wheel's modes with the creep force's lag."""
    print("| rpm | mode | steady creep [1/s] | transient creep [1/s] |")
    print("|---|---|---|---|")
    for rpm in (400.0, 800.0):
        rates = {}
        for transient in (False, True):
            d = ws.load_design("table1").replace(transient_creep=transient)
            modes = ws.compute_modes(d, fidelity)
            op = ws.operating_point(d, rpm=rpm, crabbing_velocity_m_s=0.39)
            rows, _ = stability_table(d, modes, ws.contact_law(d), op)
            for row in rows:
                if (
                    row.mode.family == "axial"
                    and row.mode.nodal_circles == 0
                    and row.mode.nodal_diameters <= 4
                ):
                    rates.setdefault(row.mode.label(), []).append(row.stability.growth_rate_1_s)
        for label, (steady, lagged) in rates.items():
            print(f"| {rpm:g} | {label} | {steady:.3g} | {lagged:.3g} |")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--fidelity", default="balanced")
    args = p.parse_args()
    angle_table(args.fidelity)
    print()
    counter_body_table(args.fidelity)
    print()
    transient_creep_table(args.fidelity)


if __name__ == "__main__":
    main()
