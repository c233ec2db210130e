"""A small geographic picture for the review station's tests: five ships in the eastern
Solent seen by AIS (tight AOUs) and a radar (wide AOUs); two couples of them sail side by side,
50-60 m apart, close enough that the radar cannot tell which is which (borderline pairs); one
ship is alone, and a lone radar track lies far away. Deterministic (seeded)."""

from __future__ import annotations

import numpy as np
import pandas as pd

LAT0, LON0 = 50.770, -1.090
M_LAT, M_LON = 111_250.0, 70_400.0


def picture(seed: int = 7, minutes: float = 8.0, step: float = 10.0) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, minutes * 60.0, step)
    ships = {
        # name: (x0, y0, vx, vy) metres, m/s
        "alpha": (0.0, 0.0, 4.0, 1.0),
        "bravo": (0.0, 60.0, 4.0, 1.0),
        "charlie": (-2500.0, -1500.0, 0.5, 5.0),
        "delta": (1500.0, -1200.0, -3.0, 2.0),
        "echo": (1500.0, -1150.0, -3.0, 2.0),
    }
    rows = []
    for k, (name, (x0, y0, vx, vy)) in enumerate(ships.items()):
        x, y = x0 + vx * t, y0 + vy * t
        for source, track, r, every in (
            ("ais", f"ais-{name}", 15.0, 1),
            ("radar", f"radar-{k + 1}", 250.0, 3),
        ):
            sel = slice(k % every, None, every)
            n = len(t[sel])
            ex = rng.normal(0, r / 2, n)
            ey = rng.normal(0, r / 2, n)
            for tt, xx, yy in zip(t[sel], x[sel] + ex, y[sel] + ey, strict=True):
                rows.append((track, source, tt, LAT0 + yy / M_LAT, LON0 + xx / M_LON, r, r, 0.0))
    # a radar track far from every ship
    for tt in t[::3]:
        rows.append(("radar-9", "radar", tt, LAT0 + 0.05, LON0 - 0.1, 250.0, 250.0, 0.0))
    return pd.DataFrame(
        rows, columns=["track_id", "source", "time", "lat", "lon", "rx", "ry", "bearing"]
    )
