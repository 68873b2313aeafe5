"""The cost of the acoustician's outputs: the warm ``pipeline.py run`` of the default wheel
now (with the harmonics, the far-field levels, the bands, squeal.wav, spectrum.png,
growth.png and report.html) against the same command of an earlier commit, checked out
beside this one and run with this machine's Python, interleaved, medians.

    .venv/bin/python benchmarks/bench_report.py [--baseline REV] [--repeat 7]
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
from wheel_squeal.runtime.provenance import CODE_PACKAGES  # noqa: E402

#: The last commit before the acoustician's outputs
BASELINE = "6bd0612"


def seconds(command: list[str], cwd: Path) -> float:
    t0 = time.perf_counter()
    subprocess.run(command, cwd=cwd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", default=BASELINE)
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    tmp = Path(tempfile.mkdtemp(prefix="bench-report-"))
    base = tmp / "baseline"
    git = ["git", "-C", str(ROOT), "worktree"]
    try:
        subprocess.run([*git, "add", "-q", "--detach", str(base), args.baseline], check=True)
        trees = {"now": ROOT, "baseline": base}
        for tree in trees.values():  # bytecode compiled, as an install would
            packages = [str(tree / p) for p in CODE_PACKAGES]
            subprocess.run([sys.executable, "-m", "compileall", "-q", *packages], check=True)
        times: dict[str, list[float]] = {k: [] for k in trees}

        def run(k: str, out: str) -> list[str]:
            return [
                sys.executable,
                str(trees[k] / "pipeline.py"),
                "run",
                "--quiet",
                "--cache-dir",
                str(tmp / f"cache-{k}"),
                "--out",
                str(tmp / out),
            ]

        for k, tree in trees.items():  # fill each cache once
            seconds(run(k, f"first-{k}"), tree)
        for i in range(args.repeat):
            for k, tree in trees.items():
                times[k].append(seconds(run(k, f"{k}-{i}"), tree))
        now, before = statistics.median(times["now"]), statistics.median(times["baseline"])
        files = sorted(p.name for p in (tmp / "now-0").iterdir() if not p.name.startswith("."))
        print(f"warm run now: {now:.2f} s (median of {args.repeat}; {', '.join(files)})")
        print(f"warm run at {args.baseline}: {before:.2f} s (median of {args.repeat})")
        print(f"ratio {now / before:.2f} (target <= 1.3)")
    finally:
        subprocess.run([*git, "remove", "--force", str(base)], check=False)
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
