"""How fast a runaway request is refused: each one in a fresh process (what a user's shell
starts), the median of ``--repeat`` runs against the bare start of the interpreter with the
tool imported, measured in the same run. The tests check that these requests are refused
(exit 2, one line); this table is where their speed is held, since a wall time asserted in a
unit test fails on a busy machine.

    .venv/bin/python benchmarks/bench_safety.py [--repeat 3]

A refusal that misses its target is marked MISSED in the table.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PIPELINE = str(ROOT / "pipeline.py")

#: (what, arguments, target [s]): a refusal's target is what a user waits for before being
#: told the request is too large.
REFUSALS: tuple[tuple[str, tuple[str, ...], float], ...] = (
    (
        "curve map of 1e12 cases",
        (
            "curve",
            "--design",
            "railway_920_track",
            "--radius",
            "100:1000000:1000000",
            "--train-speed",
            "10:120:1000000",
        ),
        2.0,
    ),
    ("a microphone inside the wheel", ("run", "--microphone", "0.2,0,0"), 5.0),
    (
        "a line of a million curves",
        ("line", "--design", "railway_920_track", "--line", "{folder}/long.csv"),
        30.0,
    ),
)


def _seconds(argv: list[str]) -> tuple[float, int]:
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, *argv], capture_output=True, check=False)
    return time.perf_counter() - t0, r.returncode


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "long.csv").write_text(
            "id,radius_m,length_m,cant_mm,train_speed_km_h\n" + "c,150,100,0,40\n" * 1_000_000
        )
        start = statistics.median(_seconds(["-c", "import wheel_squeal.cli"])[0] for _ in range(args.repeat))
        print(f"{'request':34} {'median [s]':>10} {'x import':>9} {'target [s]':>10}  exit")
        print(f"{'python -c import wheel_squeal.cli':34} {start:10.2f} {1.0:9.2f} {'':>10}")
        for what, request, target in REFUSALS:
            argv = [
                PIPELINE,
                *(a.format(folder=folder) for a in request),
                "--out",
                str(folder / "out"),
                "--quiet",
            ]
            runs = [_seconds(argv) for _ in range(args.repeat)]
            median = statistics.median(t for t, _ in runs)
            codes = sorted({c for _, c in runs})
            ok = median < target and codes == [2]
            mark = "" if ok else "  MISSED"
            print(f"{what:34} {median:10.2f} {median / start:9.2f} {target:10.1f}  {codes}{mark}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
