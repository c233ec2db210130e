"""Speed of the Stone Soup measures: one call per track pair (all common instants batched)
against one call per state pair (the unbatched path, as ``TrackToTrackCounting`` calls a
measure), measured in the same run, with ``geofeas.glr`` on prebuilt ellipse arrays as the floor.

    python benches/bench_stonesoup.py [--quick]

Prints a Markdown table of best-of-k wall times per state pair and the ratios.
"""

from __future__ import annotations

import argparse
import time
from datetime import datetime, timedelta

import numpy as np
from stonesoup.types.state import GaussianState
from stonesoup.types.track import Track

import geofeas
from geofeas.integrations.stonesoup import GLRMeasure


def best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def tracks(n: int, rng: np.random.Generator) -> tuple[Track, Track]:
    t0 = datetime(2024, 1, 1)
    out = []
    for _ in range(2):
        states = []
        for k in range(n):
            a = rng.normal(size=(2, 2)) * 30.0
            cov = np.diag([1.0, 1.0, 1.0, 1.0])
            cov[np.ix_([0, 2], [0, 2])] = a @ a.T + 25.0 * np.eye(2)
            vec = np.array([[10.0 * k], [1.0], [5.0 * k], [0.5]]) + rng.normal(size=(4, 1)) * 20
            states.append(GaussianState(vec, cov, timestamp=t0 + timedelta(seconds=k)))
        out.append(Track(states))
    return out[0], out[1]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    n = 100 if args.quick else 400
    repeat = 3 if args.quick else 7
    rng = np.random.default_rng(0)
    t1, t2 = tracks(n, rng)
    print(f"{n} common instants per track pair; best of {repeat}; time per state pair\n")
    print("| path | distance | per state pair | ratio to the unbatched path |")
    print("|---|---|---|---|")
    for distance in ("complement", "neglog"):
        m = GLRMeasure(mapping=(0, 2), distance=distance)
        pairs = list(zip(t1.states, t2.states, strict=True))
        unbatched = best(lambda m=m, pairs=pairs: [m(a, b) for a, b in pairs], repeat) / n
        batched = best(lambda m=m: m(t1, t2), repeat) / n
        print(
            f"| one call per state pair (unbatched) | {distance} | {unbatched * 1e6:.1f} µs | 1 |"
        )
        print(
            f"| one call per track pair (batched) | {distance} | {batched * 1e6:.2f} µs "
            f"| {unbatched / batched:.0f}x faster |"
        )
    ea = GLRMeasure(mapping=(0, 2)).ellipses(t1.states)
    eb = GLRMeasure(mapping=(0, 2)).ellipses(t2.states)
    single = best(lambda: [geofeas.glr(ea[k], eb[k]) for k in range(n)], repeat) / n
    arrays = best(lambda: geofeas.glr(ea, eb), repeat) / n
    print(
        f"| `geofeas.glr` on one prebuilt ellipse pair per call | - | {single * 1e6:.1f} µs | - |"
    )
    print(f"| `geofeas.glr` on prebuilt `(n, 5)` arrays | - | {arrays * 1e6:.3f} µs | - |")


if __name__ == "__main__":
    main()
