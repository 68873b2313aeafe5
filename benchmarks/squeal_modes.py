"""Which mode squeals, and what the wheel's rotation does: the tables of the README's
"Which mode squeals" section, printed from the tool's own API.

    .venv/bin/python benchmarks/squeal_modes.py [--fidelity balanced]

1. Every design in designs/ at the Fig. 6 point (800 RPM, Vc = 0.39 m/s): the mode
   ``--mode auto`` picks with rotation off and on (ignoring a design's named mode),
   its growth rate, and the (3,0) mode's; the damping ratio each other mode needs for
   (3,0) to be the only unstable one.
2. Table 1's single mode (m 3.1 kg, k 1.6e8 N/m, c 42 N s/m, 3 nodal diameters) and the
   FE (3,0) mode of designs/table1.toml at 400, 600 and 800 RPM (Vc = 0.39 m/s),
   rotation off and on: linear growth rate, saturation time, amplitude, tone.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import wheel_squeal as ws  # noqa: E402
from reduced import ModalDOF  # noqa: E402
from wheel_squeal.mode_stability import stability_table, wheel_speed_rad_s  # noqa: E402
from wheel_squeal.presets import designs_folder  # noqa: E402

TABLE1_MODE = ModalDOF(3.1, 1.6e8, 42.0, nodal_diameters=3)
RPMS = (400.0, 600.0, 800.0)


def which_mode(fidelity: str) -> None:
    print(
        "| design | auto picks (rotation off) | sigma [1/s] | auto picks (rotation on) | sigma [1/s] "
        "| (3,0) sigma off / on [1/s] | zeta other modes need for (3,0) alone |"
    )
    print("|---|---|---|---|---|---|---|")
    for path in sorted(designs_folder().glob("*.toml")):
        design = ws.load_design(path)
        ms = ws.compute_modes(design, fidelity)
        contact, op = ws.contact_law(design), ws.operating_point(design)
        cells = []
        s30 = []
        for rotation in (False, True):
            table = stability_table(design, ms, contact, op, rotation)
            rows = table.rows
            w = rows[table.fastest]
            cells += [
                f"{w.mode.index} {w.mode.label()} {w.mode.frequency_hz:.0f} Hz",
                f"{w.stability.growth_rate_1_s:.2f}",
            ]
            r30 = [
                r
                for r in rows
                if (r.mode.nodal_diameters, r.mode.nodal_circles, r.mode.family) == (3, 0, "axial")
            ]
            s30.append(f"{r30[0].stability.growth_rate_1_s:.2f}" if r30 else "-")
            if not rotation:
                need = ", ".join(
                    f"{r.mode.label().split()[0]} {r.stability.critical_damping_ratio:.2g}"
                    for r in rows
                    if r.stability.unstable and r not in r30
                )
        print("| " + " | ".join([design.name, *cells, " / ".join(s30), need]) + " |")


def _row(name: str, dof, design, rpm: float, rotation: bool) -> str:
    from reduced import linear_stability

    contact = ws.contact_law(design)
    op = ws.operating_point(design, rpm=rpm)
    omega = wheel_speed_rad_s(design, op, rotation)
    sigma = linear_stability(dof, contact, op, omega).growth_rate_1_s
    sim = ws.simulate(dof, contact, op, None, omega)
    lc = sim.limit_cycle
    if lc.squeal:
        tsat = f"{lc.time_to_saturation_s:.2f}" if lc.saturated else "not yet"
        out = f"{tsat} | {lc.velocity_amplitude_m_s:.3f} | {lc.frequency_hz:.1f}"
    else:
        out = "- | no squeal | -"
    tone = dof.frequency_hz - dof.nodal_diameters * omega / (2 * math.pi)
    return f"| {name} | {rpm:.0f} | {'on' if rotation else 'off'} | {sigma:.2f} | {out} | {tone:.1f} |"


def rotation_table(fidelity: str) -> None:
    design = ws.load_design()
    ms = ws.compute_modes(design, fidelity)
    fe = ws.modal_dof(ws.pick_mode(ms, "n=3,c=0")[0], design)
    print(
        "| mode | RPM | rotation | linear sigma [1/s] | saturates at [s] | amplitude [m/s] | tone [Hz] "
        "| f0 - n Omega/2pi [Hz] |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for name, dof in (("Table 1", TABLE1_MODE), (f"FE (3,0), {fidelity}", fe)):
        for rpm in RPMS:
            for rotation in (False, True):
                print(_row(name, dof, design, rpm, rotation), flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fidelity", default="balanced")
    args = ap.parse_args()
    which_mode(args.fidelity)
    print()
    rotation_table(args.fidelity)


if __name__ == "__main__":
    main()
