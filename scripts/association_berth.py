"""A berth of moored ships, built from scratch: where the triage's tail is and is not calibrated.

    python scripts/association_berth.py [--ships 10] [--spacing 10] [--ais-period 360] \
        [--repeats 20] [--no-radar]

Planar and noise-controlled: ``--ships`` still ships on a line, ``--spacing`` metres apart, for
30 minutes. Each ship has

- an AIS track reporting its exact position every ``--ais-period`` seconds with the 20 m AOU of
  the demo's AIS (a moored ship reports every three minutes or less often; above ``max_gap``,
  300 s, its reports are lone instants that the alignment does not interpolate);
- a radar track, a scan every 3 s detected with probability 0.9, errors of 16 m across and 20 m
  along (the AOU 32 x 40 m) drawn independently for each scan;
- the patrol aircraft's track from minute 5 to minute 25, an update every 10 s detected with
  probability 0.8, errors of 112 m per axis (AOU 224 m), broken into three tracks.

Every error is drawn from the AOU the report states, independently, so the model's only
approximations are its own. Per source pair, over ``--repeats`` pictures: the true pairs, the
automatic merges that are wrong (and the number the posterior predicts, the sum of ``1 -
p_same`` over them), the true pairs in ``non-match`` (and the number predicted, the sum of
``p_same`` over ``non-match``), and the log score.
"""

from __future__ import annotations

import argparse
from collections import defaultdict
from typing import Any

import numpy as np
import pandas as pd

# scripts/ is on the path of `python scripts/...`
from association_mixes import add_still_gap, log_score, still_gap

import geofeas


def berth(
    rng: np.random.Generator, ships: int, spacing: float, ais_period: float, radar: bool = True
) -> pd.DataFrame:
    """One picture of the berth (see the module docs); ``radar=False`` leaves the radar out
    (its errors are still drawn, so the other tracks do not change)."""
    frames = []
    duration = 1800.0

    def track(name: str, source: str, t: np.ndarray, x: Any, y: Any, aou: tuple) -> None:
        frames.append(
            pd.DataFrame(
                {
                    "track_id": name,
                    "source": source,
                    "time": t,
                    "x": x,
                    "y": y,
                    "rx": aou[0],
                    "ry": aou[1],
                    "phi": aou[2],
                }
            )
        )

    for k in range(ships):
        x0, y0 = 0.0, k * spacing
        t = np.arange(rng.uniform(0, ais_period), duration, ais_period)
        track(f"ais-{k}", "ais", t, x0, y0, (20.0, 20.0, 0.0))
        t = np.arange(0.0, duration, 3.0)
        t = t[rng.random(len(t)) < 0.9]
        ex, ey = rng.normal(0, 16, len(t)), rng.normal(0, 20, len(t))
        if radar:
            track(f"radar-{k}", "radar", t, x0 + ex, y0 + ey, (32.0, 40.0, np.pi / 2))
        t = np.arange(300.0 + rng.uniform(0, 10), 1500.0, 10.0)
        t = t[rng.random(len(t)) < 0.8]
        for j, ts in enumerate(np.array_split(t, 3)):
            ex, ey = rng.normal(0, 112, len(ts)), rng.normal(0, 112, len(ts))
            track(f"aircraft-{k}-{j}", "aircraft", ts, x0 + ex, y0 + ey, (224.0, 224.0, 0.0))
    return pd.concat(frames, ignore_index=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ships", type=int, default=10)
    ap.add_argument("--spacing", type=float, default=10.0, help="metres between ships")
    ap.add_argument("--ais-period", type=float, default=360.0, help="seconds between AIS reports")
    ap.add_argument("--repeats", type=int, default=20)
    ap.add_argument("--no-radar", action="store_true", help="AIS and the aircraft only")
    add_still_gap(ap)
    args = ap.parse_args()
    tally: dict[str, dict[str, float]] = defaultdict(lambda: defaultdict(float))
    for rep in range(args.repeats):
        rng = np.random.default_rng(rep)
        pairs = geofeas.associate(
            berth(rng, args.ships, args.spacing, args.ais_period, radar=not args.no_radar),
            **still_gap(args),
        ).pairs
        names = [
            (a.split("-"), b.split("-")) for a, b in zip(pairs.track_a, pairs.track_b, strict=True)
        ]
        y = np.array([a[1] == b[1] for a, b in names])
        kind = np.array([f"{a[0]}-{b[0]}" for a, b in names])
        cls = pairs["class"].to_numpy()
        p = pairs["p_same"].to_numpy()
        for kd in np.unique(kind):
            s = kind == kd
            t = tally[kd]
            t["true pairs"] += (y & s).sum()
            t["wrong merges"] += (~y & s & (cls == "match")).sum()
            t["predicted wrong"] += (1 - p[s & (cls == "match")]).sum()
            t["lost"] += (y & s & (cls == "non-match")).sum()
            t["predicted lost"] += p[s & (cls == "non-match")].sum()
            t["log score"] += log_score(p[s], y[s])
    table = pd.DataFrame(tally).T.round(2)
    print(
        f"{args.ships} ships {args.spacing:g} m apart, AIS every {args.ais_period:g} s, "
        f"{args.repeats} pictures"
    )
    print(table.to_string())


if __name__ == "__main__":
    main()
