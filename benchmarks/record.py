"""Run one benchmark script and write what it prints into its section of RESULTS.md.

    .venv/bin/python benchmarks/record.py bench_line.py [ARGS...]

The section is the one whose heading names ``benchmarks/SCRIPT``; its tables are replaced
by the script's output (one fenced block) and its ``Run:`` line by the command run. A
script that fails leaves RESULTS.md as it was. RESULTS.md holds nothing else: what a
change did to a figure is in git's history of this file.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "RESULTS.md"


def replaced_section(text: str, script: str, command: str, output: str) -> str:
    """``text`` with the section of ``script`` holding ``output`` (ValueError: no such
    section)."""
    lines = text.split("\n")
    start = next(
        (i for i, ln in enumerate(lines) if ln.startswith("## ") and f"`benchmarks/{script}`" in ln), None
    )
    if start is None:
        raise ValueError(f"RESULTS.md has no section naming `benchmarks/{script}`")
    end, fenced = len(lines), False
    for i in range(start + 1, len(lines)):  # the next heading outside a fenced block
        if lines[i].startswith("```"):
            fenced = not fenced
        elif not fenced and re.match(r"^## ", lines[i]):
            end = i
            break
    body = ["", f"Run: `{command}`", "", "```", output.rstrip("\n"), "```", ""]
    return "\n".join(lines[: start + 1] + body + lines[end:])


def main(argv: list[str]) -> int:
    if not argv:
        print(__doc__, file=sys.stderr)
        return 2
    script, args = argv[0], argv[1:]
    if not (HERE / script).is_file():
        print(f"error: no benchmark script benchmarks/{script}", file=sys.stderr)
        return 2
    run = subprocess.run([sys.executable, str(HERE / script), *args], capture_output=True, text=True)
    if run.returncode != 0:
        sys.stderr.write(run.stderr[-4000:])
        print(
            f"error: benchmarks/{script} ended with status {run.returncode}; RESULTS.md unchanged",
            file=sys.stderr,
        )
        return 1
    command = " ".join([".venv/bin/python", f"benchmarks/{script}", *args])
    RESULTS.write_text(replaced_section(RESULTS.read_text(), script, command, run.stdout))
    print(f"{RESULTS}: the section of benchmarks/{script} written")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
