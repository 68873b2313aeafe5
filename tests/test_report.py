"""report.html opened in a real headless browser (the distribution's Chromium, driven by
Playwright): every image loads, the audio element has a playable source, the console
has no error, nothing is fetched from the network, the verdict is visible; a screenshot
is saved. The pages of run, compare and study are each checked."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from conftest import ROOT, run_cli

#: The distribution's Chromium (Debian's package `chromium`; .ci/run installs it)
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
#: The flags of a headless browser on a machine without a network or a display
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(
        CHROMIUM is None,
        reason="no Chromium on this machine: .ci/run installs the distribution's package "
        "(apt-get install chromium)",
    ),
]


def open_report(path: Path, screenshot: Path | None = None) -> dict:
    """Open ``path`` in headless Chromium; what a reader would see: the images (alt,
    loaded, width), the audio element (source prefix, ready state, duration [s]), the
    console errors, the requests that left the file, the verdict's text (if visible)."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 1200, "height": 900})
        errors: list[str] = []
        requests: list[str] = []
        page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.on(
            "request", lambda r: requests.append(r.url) if not r.url.startswith(("file:", "data:")) else None
        )
        page.goto(path.as_uri())
        page.wait_for_load_state("load")
        images = page.evaluate("Array.from(document.images).map(i => [i.alt, i.complete, i.naturalWidth])")
        audio = page.evaluate(
            """(async () => {
                const a = document.querySelector('audio');
                if (!a) return null;
                if (a.readyState < 1)
                    await new Promise(r => { a.onloadedmetadata = r; setTimeout(r, 5000); });
                return [a.src.slice(0, 22), a.readyState, a.duration];
            })()"""
        )
        verdict = page.locator(".verdict").first
        shown = verdict.inner_text() if verdict.count() and verdict.is_visible() else None
        if screenshot is not None:
            page.screenshot(path=str(screenshot))
        browser.close()
    return {"images": images, "audio": audio, "errors": errors, "requests": requests, "verdict": shown}


def _check_page(seen: dict, images: int) -> None:
    assert seen["errors"] == []
    assert seen["requests"] == []  # self-contained: opens from a mail attachment
    assert len(seen["images"]) >= images
    for alt, complete, width in seen["images"]:
        assert complete and width > 0, alt


def test_the_run_report_opens_whole_in_a_browser(tmp_path):
    out = tmp_path / "run"
    r = run_cli("run", "--fidelity", "fast", "--quiet", "--out", out)
    assert r.returncode == 0, r.stderr
    seen = open_report(out / "report.html", tmp_path / "report.png")
    _check_page(seen, images=5)  # growth, history, spectrum, sound field, the mode
    source, ready, duration = seen["audio"]
    assert source == "data:audio/wav;base64," and ready >= 1 and duration > 0.5
    assert seen["verdict"] and seen["verdict"].startswith("VERDICT: squeals in (3,0) axial")
    assert (tmp_path / "report.png").stat().st_size > 10_000


def test_the_compare_and_study_reports_open_whole_in_a_browser(tmp_path):
    r = run_cli("compare", "table1", "thin_web", "--fidelity", "fast", "--quiet", "--out", tmp_path / "c")
    assert r.returncode == 0, r.stderr
    seen = open_report(tmp_path / "c" / "report.html")
    _check_page(seen, images=1)
    assert seen["verdict"] and "VERDICT" in seen["verdict"]
    r = run_cli("study", ROOT / "studies" / "smoke.toml", "--quiet", "--out", tmp_path / "s")
    assert r.returncode == 0, r.stderr
    _check_page(open_report(tmp_path / "s" / "report.html"), images=1)
