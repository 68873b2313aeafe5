"""Each wheel of a bogie at its own contact: the steady curving of the default two-axle
bogie (track.bogie_curving.Vehicle) with S1002 wheels (or the shipped railway wheel's own
running surface, a 1:20 cone) on UIC60 1:40 rails, 50 kN per wheel, friction 0.3, no cant,
at 40 km/h over 150-1000 m: the field guide's table.

    .venv/bin/python benchmarks/curving_table.py [--speed 40] [--cant 0] [--wheel s1002|railway_920_track]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from contact.wheel_rail import ContactGeometry  # noqa: E402
from track.bogie_curving import Vehicle, steady_curving  # noqa: E402

RADII_M = (150.0, 200.0, 300.0, 600.0, 1000.0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speed", type=float, default=40.0, help="train speed [km/h]")
    ap.add_argument("--cant", type=float, default=0.0, help="installed cant [mm]")
    ap.add_argument(
        "--wheel", default="s1002", help="s1002 or a design's name (its outline's running surface)"
    )
    args = ap.parse_args()
    if args.wheel == "s1002":
        geometry = ContactGeometry()
    else:
        import wheel_squeal as ws
        from wheel_squeal.curve import contact_geometry

        geometry = contact_geometry(ws.load_design(args.wheel))
    t0 = time.perf_counter()
    print(
        "| R [m] | wheel | shift [mm] | attack [mrad] | contact angles [deg] | flange | load [kN] "
        "| lateral [kN] | long. creep | lat. creep | adhesion used |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for radius in RADII_M:
        for w in steady_curving(
            geometry,
            Vehicle(),
            radius,
            args.speed,
            wheel_load_n=50e3,
            friction_coefficient=0.3,
            cant_mm=args.cant,
        ):
            print(
                f"| {radius:g} | {w.axle} {w.rail} | {1e3 * w.lateral_shift_m:.2f} "
                f"| {1e3 * w.angle_of_attack_rad:.2f} "
                f"| {', '.join(f'{math.degrees(c.contact_angle_rad):.1f}' for c in w.contacts)} "
                f"| {'yes' if w.flange_contact else 'no'} | {1e-3 * w.wheel_load_n:.1f} "
                f"| {1e-3 * w.lateral_force_n:.1f} | {w.main.longitudinal_creepage:.4f} "
                f"| {w.main.lateral_creepage:.4f} | {w.main.adhesion_used:.2f} |"
            )
    print(
        f"\n{len(RADII_M)} curves in {time.perf_counter() - t0:.1f} s "
        "(the contact table once, then each curve)"
    )


if __name__ == "__main__":
    main()
