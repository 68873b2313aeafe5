"""The curve's speed/accuracy trade: the harmonic balance (the default) against the time
domain on the shipped railway wheel's map, 150-400 m x 30-60 km/h, the modes cached:
for each wheel that squeals, whether both methods say so, the contact velocity
amplitude, the mode and tone, the bogie's L_pAmax, and each map's time. The modal band
is 8 kHz by default: at 5 kHz the time domain settles on modes near the band's top that
a wider band shows to be the truncation's (``--fmax 5000`` shows it).

    .venv/bin/python benchmarks/bench_curve_methods.py [--radius 150,200,300,400] [--speed 30,40,60]
        [--fmax 8000]

Prints a markdown table (the field guide's) and the totals.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import wheel_squeal as ws  # noqa: E402


def _floats(text: str) -> list[float]:
    return [float(x) for x in text.split(",")]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--radius", type=_floats, default=[150.0, 200.0, 300.0, 400.0])
    ap.add_argument("--speed", type=_floats, default=[30.0, 40.0, 60.0])
    ap.add_argument("--fmax", type=float, default=8000.0, help="the modal band [Hz] (default 8000)")
    args = ap.parse_args()
    design = ws.load_design("railway_920_track")
    ctx = ws.RunContext.of("balanced", fmax_hz=args.fmax)
    ws.curve(design, args.radius[:1], args.speed[:1], context=ctx)  # warm: modes, fits
    maps, seconds = {}, {}
    for method in ("harmonic balance", "time domain"):
        t0 = time.perf_counter()
        maps[method] = ws.curve(design, args.radius, args.speed, method=method, context=ctx)  # type: ignore[arg-type]
        seconds[method] = time.perf_counter() - t0
    print(
        "| R [m] | V [km/h] | wheel | squeals (HB / TD) | mode (HB / TD) | tone [Hz] (HB / TD) "
        "| amplitude [m/s] (HB / TD) | bogie L_pAmax [dB(A)] (HB / TD) | difference [dB] |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    agree, within, both = 0, 0, 0
    for hb, td in zip(maps["harmonic balance"], maps["time domain"]):
        a, b = hb.to_record(), td.to_record()
        if not (a["squeals"] or b["squeals"]):
            agree += 1
            continue
        agree += a["squeals"] == b["squeals"]
        diff = None
        if a["bogie_lpamax_dba"] is not None and b["bogie_lpamax_dba"] is not None:
            diff = a["bogie_lpamax_dba"] - b["bogie_lpamax_dba"]
            both += 1
            within += abs(diff) <= 1.0

        def cell(key: str, fmt: str, rec_a: dict = a, rec_b: dict = b) -> str:
            x, y = rec_a[key], rec_b[key]
            return " / ".join("-" if v is None or v == "" else format(v, fmt) for v in (x, y))

        print(
            f"| {a['radius_m']:g} | {a['train_speed_km_h']:g} | {a['axle']} {a['rail']} "
            f"| {cell('squeals', '')} | {cell('verdict_mode', '')} | {cell('tone_hz', '.0f')} "
            f"| {cell('amplitude_m_s', '.3f')} | {cell('bogie_lpamax_dba', '.1f')} "
            f"| {'-' if diff is None else format(diff, '+.1f')} |"
        )
    n = len(maps["harmonic balance"])
    print(
        f"\n{n} wheel cases: the methods agree on {agree} whether the wheel squeals; where both give a "
        f"level ({both} cases) the bogie L_pAmax is within 1 dB(A) in {within}. "
        f"Harmonic balance {seconds['harmonic balance']:.1f} s, time domain {seconds['time domain']:.1f} s "
        f"({seconds['time domain'] / max(seconds['harmonic balance'], 1e-9):.0f}x)."
    )


if __name__ == "__main__":
    main()
