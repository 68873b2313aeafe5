"""What the rail changes: each wheel on its roller, on the test track, and on a rigid rail
with the track's contact (the rail's dynamics alone), at one operating point: the modes
that grow, the fastest eigenvalue and the verdict's mode and tone (the linear verdict).

    .venv/bin/python benchmarks/track_effect.py
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import wheel_squeal as ws  # noqa: E402
from track.design_sections import Track  # noqa: E402

#: (design, operating point): the rig wheel at the paper's Fig. 6 point, the railway
#: wheel at 11.1 m/s and 10 mrad
CASES = (
    ("table1", {"rpm": 800.0, "crabbing_velocity_m_s": 0.39}),
    ("railway_920", {"rolling_speed_m_s": 11.1, "crabbing_velocity_m_s": 0.111}),
)


def main() -> None:
    head = (
        f"{'design':<12} {'rolls on':<10} {'grow':>5} {'fastest [1/s]':>14} {'verdict':<16} {'tone [Hz]':>9}"
    )
    print(head + " rail effect")
    for name, at in CASES:
        base = ws.load_design(name).replace(squeal_mode="")
        for label, design in (("roller", base), ("track", base.replace(counter_body=Track()))):
            a = ws.analyse(design, stop_after="stability", remedy=False, **at)
            v = a.verdict
            fastest = float(a.table.result.eigenvalues.real.max())
            grow = len(a.table.growing)
            effect = v.counter_body_effect_1_s
            words = "" if effect is None else f"{effect:+.3g} 1/s against a rigid rail"
            print(
                f"{name:<12} {label:<10} {grow:>5} {fastest:14.3g} {v.get('mode') or 'none':<16} "
                f"{v.get('tone_hz') or 0:9.1f} {words}"
            )


if __name__ == "__main__":
    main()
