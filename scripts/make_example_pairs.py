"""Builds python/geofeas/data/example_pairs.csv, the bundled example of `geofeas score`, from the
Solent AIS recording: at a few instants, every vessel's AIS position is paired with a simulated
coastal-radar report of the same vessel and of its nearest neighbour. Coordinates are metres in a
local east/north frame (UTM-sized offsets are kept to exercise far-from-origin precision).

Usage: python scripts/make_example_pairs.py data/ais/SolentAIS_20160112_130211.csv
"""

import csv
import math
import sys

import numpy as np

RADAR = (-1.1086, 50.7803)  # a site on the Solent shore (lon, lat)
E0, N0 = 620_000.0, 5_620_000.0  # UTM-like false origin, metres


def main(path: str, out: str = "python/geofeas/data/example_pairs.csv") -> None:
    rng = np.random.default_rng(12)
    last: dict[str, tuple[float, float, str]] = {}
    with open(path, newline="") as fh:
        for row in csv.DictReader(fh):
            lon, lat = float(row["Longitude_degrees"]), float(row["Latitude_degrees"])
            if not (-2.0 < lon < 0.0 and 50.0 < lat < 51.5):
                continue  # the recording has one corrupt longitude
            if row["Time"] < "2016-01-12 13:30":
                last[row["MMSI"]] = (lon, lat, row["Time"])
    lat0 = math.radians(50.79)
    m_lat = 111_132.954 - 559.822 * math.cos(2 * lat0)
    m_lon = 111_412.84 * math.cos(lat0)
    ids = sorted(last)
    xy = np.array([[(last[i][0] - RADAR[0]) * m_lon, (last[i][1] - RADAR[1]) * m_lat] for i in ids])
    rows = []
    for k, mmsi in enumerate(ids):
        x, y = xy[k]
        rng_m, brg = math.hypot(x, y), math.atan2(x, y)
        ais = (E0 + x + rng.normal(0, 5), N0 + y + rng.normal(0, 5), 20.0, 20.0, 0.0)
        # radar: range sigma 25 m, bearing sigma 0.5 deg -> AOU elongated across the line of sight
        srange, sbear = 25.0, math.radians(0.5) * max(rng_m, 1.0)
        rx_r, ry_r = 2 * sbear, 2 * srange
        radar = (
            E0 + x + rng.normal(0, srange) * math.sin(brg) + rng.normal(0, sbear) * math.cos(brg),
            N0 + y + rng.normal(0, srange) * math.cos(brg) - rng.normal(0, sbear) * math.sin(brg),
            rx_r,
            ry_r,
            (brg + math.pi / 2) % math.pi,
        )
        d = np.hypot(*(xy - xy[k]).T)
        d[k] = np.inf
        j = int(np.argmin(d))
        rows.append((mmsi, mmsi, "same", ais, radar))
        rows.append((mmsi, ids[j], "neighbour", ais, None))
    with open(out, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            ["track_a", "track_b", "truth"]
            + [f"{s}_{f}" for s in "ab" for f in ("x0", "y0", "rx", "ry", "phi")]
        )
        radar_of = {r[0]: r[4] for r in rows if r[2] == "same"}
        for a, b, truth, ais, _ in rows:
            rad = radar_of[b]
            w.writerow(
                [f"ais-{a}", f"radar-{b}", truth]
                + [f"{v:.3f}" if i < 2 else f"{v:.4f}" for i, v in enumerate(ais)]
                + [f"{v:.3f}" if i < 2 else f"{v:.4f}" for i, v in enumerate(rad)]
            )


if __name__ == "__main__":
    main(*sys.argv[1:])
