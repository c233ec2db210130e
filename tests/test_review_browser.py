"""End-to-end: ``geofeas review`` served by uvicorn in a subprocess, driven by the system's
Chromium through Playwright (no browser is downloaded: the test uses ``chromium`` from PATH and
skips when there is none). Screenshots go to a temporary folder (``GEOFEAS_ARTIFACTS`` when set).
"""

from __future__ import annotations

import csv
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest
from review_picture import picture

import geofeas

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
pytestmark = [
    pytest.mark.skipif(CHROMIUM is None, reason="no system chromium (apt-get install chromium)"),
]
sync_api = pytest.importorskip("playwright.sync_api", reason="needs playwright (pip)")
pytest.importorskip("uvicorn")


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    folder = tmp_path_factory.mktemp("review")
    pic = folder / "picture.csv"
    picture().to_csv(pic, index=False)
    db = folder / "decisions.sqlite"
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "geofeas.cli",
            "review",
            str(pic),
            "--db",
            str(db),
            "--port",
            "0",
            "--operator",
            "station",
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    url = None
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        line = proc.stdout.readline()
        if not line:
            break
        if line.startswith("http://"):
            url = line.strip()
            break
    if url is None:
        proc.kill()
        out, err = proc.communicate()
        pytest.fail(f"the station did not print its address: {out} {err}")
    yield {"url": url, "db": db, "picture": pic, "folder": folder}
    proc.terminate()
    try:
        proc.wait(timeout=20)
    except subprocess.TimeoutExpired:  # pragma: no cover
        proc.kill()


@pytest.fixture(scope="module")
def browser():
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
        yield b
        b.close()


def _artifacts(served) -> Path:
    d = Path(os.environ.get("GEOFEAS_ARTIFACTS", served["folder"] / "artifacts"))
    d.mkdir(parents=True, exist_ok=True)
    return d


def _settled(page, url, version_before):
    """Wait until the station has re-associated past ``version_before``."""
    for _ in range(600):
        s = page.request.get(url + "api/state").json()
        if (
            s["version"] > version_before
            and not s["computing"]
            and s["position"] == s["log_position"]
        ):
            return s
        time.sleep(0.1)
    raise AssertionError("the station did not re-associate")


def test_review_station_in_a_real_browser(served, browser):
    url, db = served["url"], served["db"]
    reports = geofeas.read_reports(pd.read_csv(served["picture"]))
    expected = geofeas.associate(reports).review_queue
    ctx1 = browser.new_context(viewport={"width": 1200, "height": 1300})
    page = ctx1.new_page()

    # the queue, in the engine's review order
    page.goto(url)
    rows = page.locator("#queue tbody tr")
    assert rows.count() == len(expected)
    shown = [
        (rows.nth(k).get_attribute("data-a"), rows.nth(k).get_attribute("data-b"))
        for k in range(rows.count())
    ]
    assert shown == [
        (str(a), str(b)) for a, b in zip(expected.track_a, expected.track_b, strict=True)
    ]

    # a pair: the ellipses are rendered SVG elements with a size on screen
    first, second = shown[0], shown[1]
    rows.nth(0).locator("a").click()
    page.wait_for_selector("svg#map")
    assert page.locator("svg#map ellipse.aou-a").count() > 5
    assert page.locator("svg#map ellipse.aou-b").count() > 5
    box = page.locator("#now-b").bounding_box()
    assert box is not None and box["width"] > 2 and box["height"] > 2
    assert page.locator("svg#chart polyline.distance").count() == 1
    # the slider moves the instant drawn
    before = page.locator("#now-a").get_attribute("cx")
    page.locator("#slider").fill("0")
    page.locator("#slider").dispatch_event("input")
    assert page.locator("#now-a").get_attribute("cx") != before
    shot = _artifacts(served) / "pair.png"
    page.screenshot(path=str(shot), full_page=True)
    assert shot.stat().st_size > 10_000

    # decide with the keyboard as operator "ann"
    page.fill("#operator", "ann")
    page.locator("#operator").dispatch_event("change")
    page.evaluate("document.activeElement.blur()")
    version = page.request.get(url + "api/state").json()["version"]
    pair_url = page.url
    page.keyboard.press("s")
    page.wait_for_selector("#message.ok")
    assert "same" in page.locator("#message").inner_text()
    page.wait_for_url(lambda u: u != pair_url)

    # reload: the decision is kept
    page.goto(pair_url)
    assert "same" in page.locator("#decided-by").inner_text()
    assert "ann" in page.locator("#decided-by").inner_text()

    # a second browser context sees it
    ctx2 = browser.new_context()
    other = ctx2.new_page()
    other.goto(pair_url)
    assert "ann" in other.locator("#decided-by").inner_text()

    # re-association: the queue becomes the engine's under the decision
    _settled(page, url, version)
    ref_csv = served["folder"] / "ref.csv"
    from geofeas.review.log import DecisionLog

    DecisionLog(db).export(ref_csv)
    after = geofeas.associate(reports, decisions=ref_csv).review_queue
    page.goto(url)
    rows = page.locator("#queue tbody tr")
    shown_after = [
        (rows.nth(k).get_attribute("data-a"), rows.nth(k).get_attribute("data-b"))
        for k in range(rows.count())
    ]
    assert shown_after == [
        (str(a), str(b)) for a, b in zip(after.track_a, after.track_b, strict=True)
    ]
    assert first not in shown_after
    assert shown_after != shown

    # conflict: bob's page was drawn before ann decides the pair; his decision is refused
    target = shown_after[0] if shown_after else second
    bob = ctx2.new_page()
    bob.goto(f"{url}pair?a={target[0]}&b={target[1]}")
    bob.fill("#operator", "bob")
    bob.locator("#operator").dispatch_event("change")
    page.goto(f"{url}pair?a={target[0]}&b={target[1]}")
    page.evaluate("document.activeElement.blur()")
    # the saved decision's message, then the page moves on to the next pair by itself (after
    # 600 ms): wait for that navigation, or it can abort the test's own next one
    with page.expect_navigation():
        page.keyboard.press("d")
        page.wait_for_selector("#message.ok")
    bob.evaluate("document.activeElement.blur()")
    bob.keyboard.press("s")
    bob.wait_for_selector("#message.conflict")
    assert "changed since this page was drawn" in bob.locator("#message").inner_text()
    bob.screenshot(path=str(_artifacts(served) / "conflict.png"))

    # the log holds exactly the two decisions; the export equals the database
    log = DecisionLog(db)
    assert [(e.operator, e.action) for e in log.decisions()] == [
        ("ann", "same"),
        ("ann", "different"),
    ]
    out = served["folder"] / "export.csv"
    r = subprocess.run(
        [sys.executable, "-m", "geofeas.cli", "review", "--db", str(db), "--export", str(out)],
        capture_output=True,
        text=True,
        check=True,
    )
    assert "wrote" in r.stdout
    with open(out, newline="") as fh:
        exported = list(csv.DictReader(fh))
    assert exported == log.decisions_table()
    served_csv = page.request.get(url + "decisions.csv").text()
    assert list(csv.DictReader(served_csv.splitlines())) == exported

    # undo with the keyboard appends a reversal, then the page reloads the pair
    target_url = f"{url}pair?a={target[0]}&b={target[1]}"
    page.goto(target_url)
    page.evaluate("document.activeElement.blur()")
    with page.expect_navigation():
        page.keyboard.press("u")
    assert [e.action for e in log.entries()][-1] == "undo"
    assert len(log.decisions()) == 1

    # skip with the keyboard: logged, decides nothing, moves on to another pair
    page.evaluate("document.activeElement.blur()")
    with page.expect_navigation():
        page.keyboard.press("k")
    assert page.url != target_url
    assert [(e.operator, e.action) for e in log.entries()][-1] == ("ann", "skip")
    assert len(log.decisions()) == 1
    ctx1.close()
    ctx2.close()
