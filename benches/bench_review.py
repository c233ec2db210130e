"""The review station's pair view for a pair with 2,000 common instants: the time to build the
page (aligned AOUs from the core, coastline, SVG map and distance chart, the slider's arrays) and
to serve it over HTTP, against a baseline measured in the same run: the engine associating the
same picture (``geofeas.associate``).

    python benches/bench_review.py [--instants 2000] [--rivals 0] [--repeat 5] [--browser]

The picture: two tracks of one ship in the eastern Solent (AIS every 5 s, 15 m; radar every 5 s,
250 m, offset by 2.5 s so that every report of either is an instant), and optionally more
radar tracks of the same ship (``--rivals``; with 2,000 instants the engine rules them out, so
they are not drawn as rivals). ``--browser`` also times the page in the system chromium.
Timings are wall clock on a shared machine: expect noise; the figure that matters is the page
time (interactive means well under a second).
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

import geofeas
from geofeas.review.app import create_app
from geofeas.review.render import distance_svg, map_svg, pair_payload
from geofeas.review.station import Station

LAT0, LON0, M_LAT, M_LON = 50.77, -1.09, 111_250.0, 70_400.0


def picture(instants: int, rivals: int, seed: int = 1) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    n = instants // 2 + 1
    rows = []
    for track, source, r, off, dy in [
        ("ais-1", "ais", 15.0, 0.0, 0.0),
        ("radar-1", "radar", 250.0, 2.5, 0.0),
    ] + [(f"radar-r{k}", "radar", 250.0, 2.5, 150.0 * (k + 1)) for k in range(rivals)]:
        t = off + 5.0 * np.arange(n)
        x = 3.0 * t + rng.normal(0, r / 2, n)
        y = dy + 0.8 * t + rng.normal(0, r / 2, n)
        rows.append(
            pd.DataFrame(
                {
                    "track_id": track,
                    "source": source,
                    "time": t,
                    "lat": LAT0 + y / M_LAT,
                    "lon": LON0 + x / M_LON,
                    "rx": r,
                    "ry": r,
                    "bearing": 0.0,
                }
            )
        )
    return pd.concat(rows, ignore_index=True)


def timed(fn, repeat: int) -> float:
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return statistics.median(out)


def browser_times(station: Station, repeat: int) -> tuple[float, float]:
    """Median time for chromium to load and draw the pair page served by uvicorn, and of one
    slider step (mean over all instants)."""
    import shutil
    import socket
    import threading

    import uvicorn
    from playwright.sync_api import sync_playwright

    sock = socket.socket()
    sock.bind(("127.0.0.1", 0))
    sock.listen(16)
    port = sock.getsockname()[1]
    server = uvicorn.Server(uvicorn.Config(create_app(station), log_level="warning"))
    th = threading.Thread(target=server.run, kwargs={"sockets": [sock]}, daemon=True)
    th.start()
    while not server.started:
        time.sleep(0.01)
    url = f"http://127.0.0.1:{port}/pair?a=ais-1&b=radar-1"
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=shutil.which("chromium"), args=["--no-sandbox"])
        page = b.new_page()
        page.goto(url)
        loads = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            page.goto(url, wait_until="load")
            page.wait_for_selector("#now-a")
            loads.append(time.perf_counter() - t0)
        n = int(page.locator("#slider").get_attribute("max")) + 1
        slide = page.evaluate(
            """(n) => { const s = document.getElementById('slider');
            const t0 = performance.now();
            for (let k = 0; k < n; k++) { s.value = k; s.dispatchEvent(new Event('input')); }
            document.body.getBoundingClientRect();
            return (performance.now() - t0) / n / 1000; }""",
            n,
        )
        b.close()
    server.should_exit = True
    th.join(timeout=10)
    return statistics.median(loads), float(slide)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--instants", type=int, default=2000)
    ap.add_argument("--rivals", type=int, default=0)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument(
        "--browser",
        action="store_true",
        help="also time the page in the system chromium (Playwright): load and slider move",
    )
    args = ap.parse_args()
    from starlette.testclient import TestClient

    frame = picture(args.instants, args.rivals)
    with tempfile.TemporaryDirectory() as tmp:
        pic = Path(tmp) / "picture.csv"
        frame.to_csv(pic, index=False)
        reports = geofeas.read_reports(pic)
        base = timed(lambda: geofeas.associate(reports), args.repeat)
        station = Station(pic, Path(tmp) / "d.sqlite", background=False)
        d = station.detail("ais-1", "radar-1")
        print(f"pair ais-1 / radar-1: {len(d.time)} common instants, {len(d.rivals)} rivals")
        map_svg(d)  # the coastline of the area is read once and cached
        t_detail = timed(lambda: station.detail("ais-1", "radar-1"), args.repeat)
        t_draw = timed(lambda: (map_svg(d), distance_svg(d), pair_payload(d)), args.repeat)
        client = TestClient(create_app(station, token="t"))
        page = client.get("/pair", params={"a": "ais-1", "b": "radar-1"})
        assert page.status_code == 200
        t_page = timed(
            lambda: client.get("/pair", params={"a": "ais-1", "b": "radar-1"}), args.repeat
        )
        if args.browser:
            t_load, t_slide = browser_times(station, args.repeat)
        station.close()
    if args.browser:
        print(f"{'chromium: page loaded and drawn':<40}{t_load * 1e3:>9.1f} ms")
        print(f"{'chromium: one slider step':<40}{t_slide * 1e3:>9.3f} ms")
    print(f"{'baseline: associate the picture':<40}{base * 1e3:>9.1f} ms")
    print(f"{'pair data (core alignment)':<40}{t_detail * 1e3:>9.1f} ms")
    print(f"{'SVG map + chart + slider arrays':<40}{t_draw * 1e3:>9.1f} ms")
    print(
        f"{'whole page over HTTP':<40}{t_page * 1e3:>9.1f} ms"
        f"   ({t_page / base:.2f} x the baseline; {len(page.content) / 1e6:.2f} MB)"
    )


if __name__ == "__main__":
    main()
