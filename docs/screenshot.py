"""Regenerate docs/report.png, the screenshot of the default run's report.html that the
README and the sound guide show: run the default job, open its report in the
distribution's headless Chromium (Playwright) and take the top of the page.

    .venv/bin/python docs/screenshot.py
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main() -> None:
    from playwright.sync_api import sync_playwright

    chromium = shutil.which("chromium")
    if chromium is None:
        sys.exit("no chromium: apt-get install chromium")
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "run"
        command = [sys.executable, str(HERE.parent / "pipeline.py"), "run", "--quiet", "--out", str(out)]
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=chromium, args=["--no-sandbox", "--disable-gpu"])
            page = browser.new_page(viewport={"width": 1150, "height": 1500})
            page.goto((out / "report.html").as_uri())
            page.wait_for_load_state("load")
            page.screenshot(path=str(HERE / "report.png"))
            browser.close()
    print(HERE / "report.png")


if __name__ == "__main__":
    main()
