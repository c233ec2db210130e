"""The review station's pair view of the first pair in the queue, drawn by the system Chromium:
the README's screenshot, and the time the station takes to serve and draw its whole queue.

    geofeas demo --out demo
    python scripts/review_screenshot.py demo/reports.csv [--out docs/img/review/pair.png]

Serves ``geofeas review PICTURE`` on a free local port with a new decisions database in a
temporary folder (nothing is decided), loads the queue page in Chromium (``chromium`` on PATH,
through Playwright; nothing is downloaded) and prints the queue's length and the time from the
request to the page's ``load`` event, then opens the first pair and writes a full-page
screenshot (atomically: a temporary file renamed over ``--out``).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("picture", type=Path, help="a reports file, as `geofeas review` reads it")
    ap.add_argument("--out", type=Path, default=Path("docs/img/review/pair.png"))
    ap.add_argument("--operator", default="ann")
    args = ap.parse_args()
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium is None:
        sys.exit("no system chromium on PATH (apt-get install chromium)")
    from playwright.sync_api import sync_playwright

    with tempfile.TemporaryDirectory() as tmp:
        cmd = [sys.executable, "-m", "geofeas.cli", "review", str(args.picture)]
        cmd += ["--db", str(Path(tmp) / "decisions.sqlite"), "--port", "0"]
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True)
        try:
            url = ""
            assert proc.stdout is not None
            for line in proc.stdout:
                if line.startswith("http://"):
                    url = line.strip()
                    break
            if not url:
                sys.exit("the station did not print its address")
            took = time.perf_counter() - t0
            print(f"station listening after {took:.1f} s (association included)")
            with sync_playwright() as p:
                browser = p.chromium.launch(executable_path=chromium, args=["--no-sandbox"])
                page = browser.new_page(viewport={"width": 1100, "height": 900})
                t1 = time.perf_counter()
                page.goto(url, wait_until="load")
                rows = page.locator("#queue tbody tr").count()
                print(f"queue page: {rows} pairs, drawn in {time.perf_counter() - t1:.2f} s")
                page.fill("#operator", args.operator)
                page.locator("#operator").dispatch_event("change")
                page.locator("#queue tbody tr").nth(0).locator("a").click()
                page.wait_for_selector("svg#map")
                # the header's progress comes from the station's first poll of /api/state
                page.wait_for_function(
                    "document.getElementById('status').textContent.includes('remaining')"
                )
                args.out.parent.mkdir(parents=True, exist_ok=True)
                part = args.out.with_name(f".{args.out.name}.{os.getpid()}.png")
                page.screenshot(path=str(part), full_page=True)
                os.replace(part, args.out)
                print(f"wrote {args.out} ({page.locator('h1, h2').first.inner_text()})")
                browser.close()
        finally:
            proc.terminate()
            proc.wait(timeout=30)


if __name__ == "__main__":
    main()
