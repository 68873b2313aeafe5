"""The steady curving of a run of curves: each solved cold (the usual starts) against each
started from its wider neighbour's equilibrium (what a curve map and a line do), on the
shipped railway wheel, 60 radii from 3000 m down to 100 m at three speeds and frictions,
the contact table made once; the time per curve of each and the largest difference of the
wheels' lateral shifts and angles of attack between the two.

    .venv/bin/python benchmarks/bench_curving_starts.py
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import wheel_squeal as ws  # noqa: E402
from track.bogie_curving import contact_table, solve_curving  # noqa: E402
from wheel_squeal.curve_contacts import contact_geometry  # noqa: E402


def main() -> None:
    design = ws.load_design("railway_920_track")
    geometry, vehicle = contact_geometry(design), design.vehicle.vehicle()
    table = contact_table(geometry, design.wheel.youngs_modulus, design.wheel.poissons_ratio)
    radii = np.exp(np.linspace(np.log(3000.0), np.log(100.0), 60))
    load = design.contact.normal_load
    print(
        "| V [km/h] | mu | cold [ms a curve] | started from the neighbour [ms a curve] "
        "| max dy [m] | max dpsi [rad] |"
    )
    print("|---|---|---|---|---|---|")
    for speed, mu in ((40.0, 0.3), (60.0, 0.5), (30.0, 0.2)):
        t0 = time.perf_counter()
        cold = [
            solve_curving(
                geometry, vehicle, r, speed, wheel_load_n=load, friction_coefficient=mu, table=table
            )
            for r in radii
        ]
        t_cold = (time.perf_counter() - t0) / len(radii)
        t0, last, warm = time.perf_counter(), None, []
        for r in radii:
            last = solve_curving(
                geometry,
                vehicle,
                r,
                speed,
                wheel_load_n=load,
                friction_coefficient=mu,
                table=table,
                start=last,
            )
            warm.append(last)
        t_warm = (time.perf_counter() - t0) / len(radii)
        pairs = [(a, b) for x, y in zip(cold, warm) for a, b in zip(x.wheels, y.wheels)]
        dy = max(abs(a.lateral_shift_m - b.lateral_shift_m) for a, b in pairs)
        dpsi = max(abs(a.angle_of_attack_rad - b.angle_of_attack_rad) for a, b in pairs)
        print(f"| {speed:g} | {mu:g} | {1e3 * t_cold:.0f} | {1e3 * t_warm:.0f} | {dy:.1e} | {dpsi:.1e} |")


if __name__ == "__main__":
    main()
