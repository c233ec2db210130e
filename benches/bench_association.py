"""Association at the scale of a national maritime picture: the space-time index and the scoring
of its candidate pairs against scoring all pairs by brute force, in the same run.

    python benches/bench_association.py [--tracks 20000] [--reports 1000000] [--planar]

The synthetic picture: ships spread over a 2,000 km x 2,000 km sea area (geographic, around
50 N, 50 W, or the same area planar with --planar), straight courses at 0-12 m/s, each ship seen
by one to four sources (AIS every 10 s with 10 m noise, coastal radar every 4 s with 50 m,
patrol radar every 10 s with 150 m, HF radar every 60 s with 1.5 km), each track covering a random
part of a 3-hour window, until the requested numbers of tracks and reports are reached.

Timed: ``geofeas.associate`` (validation, candidate generation with the rstar index, alignment,
per-instant GLR, chi-square combination, the pair evidence, the posterior per component, triage,
review order and grouping), the candidate generation alone,
and the brute force baseline: the same per-pair scoring on a uniform random sample of all
``N (N - 1) / 2`` pairs, extrapolated to all pairs (scoring every pair would take hours; the
per-pair cost of the sample is the same as for all pairs). Peak resident memory is read from
``getrusage``. Timings are wall clock on a shared 2-core machine: expect noise.
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np
import pandas as pd

import geofeas
from geofeas import _core
from geofeas.association import _resolve_options

SOURCES = [  # name, report interval (s), 1-sigma noise (m)
    ("ais", 10.0, 10.0),
    ("coastal_radar", 4.0, 50.0),
    ("patrol_radar", 10.0, 150.0),
    ("hf_radar", 60.0, 1500.0),
]


def picture(n_tracks: int, n_reports: int, planar: bool, seed: int = 0) -> pd.DataFrame:
    """A synthetic national picture of about ``n_tracks`` tracks and ``n_reports`` reports."""
    rng = np.random.default_rng(seed)
    mean_per_track = n_reports / n_tracks
    n_ships = int(n_tracks / 2.2)
    start = rng.uniform(-1e6, 1e6, (n_ships, 2))
    speed = rng.uniform(0, 12, n_ships)
    course = rng.uniform(0, 2 * np.pi, n_ships)
    vel = np.stack([speed * np.sin(course), speed * np.cos(course)], 1)
    ship = rng.integers(0, n_ships, n_tracks)
    src = rng.choice(len(SOURCES), n_tracks, p=[0.35, 0.25, 0.25, 0.15])
    dt = np.array([SOURCES[s][1] for s in src])
    sigma = np.array([SOURCES[s][2] for s in src])
    count = np.maximum(2, rng.poisson(mean_per_track, n_tracks))
    t0 = rng.uniform(0, 10800 - count * dt)
    t0 = np.maximum(t0, 0)
    track = np.repeat(np.arange(n_tracks), count)
    k = np.arange(track.size) - np.repeat(np.cumsum(count) - count, count)
    t = t0[track] + k * dt[track] + rng.uniform(0, 1, track.size)
    pos = start[ship[track]] + vel[ship[track]] * t[:, None]
    pos += rng.normal(0, 1, pos.shape) * sigma[track, None]
    r = 2 * sigma[track]
    frame = pd.DataFrame(
        {
            "track_id": track,
            "source": np.array([s[0] for s in SOURCES])[src[track]],
            "time": t,
            "rx": r,
            "ry": r * rng.uniform(0.5, 1.0, track.size),
        }
    )
    phi = rng.uniform(0, np.pi, track.size)
    if planar:
        return frame.assign(x=pos[:, 0], y=pos[:, 1], phi=phi)
    # small-area equirectangular placement around 50 N, 50 W (the geometry of the test scene
    # does not need to be exact; the association itself is)
    lat = 50.0 + pos[:, 1] / 111_200.0
    lon = -50.0 + pos[:, 0] / (111_320.0 * np.cos(np.radians(lat)))
    return frame.assign(lat=lat, lon=lon, bearing=np.degrees(phi))


def peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tracks", type=int, default=20_000)
    ap.add_argument("--reports", type=int, default=1_000_000)
    ap.add_argument("--planar", action="store_true")
    ap.add_argument("--sample", type=int, default=20_000, help="brute-force sample of pairs")
    args = ap.parse_args()

    frame = picture(args.tracks, args.reports, args.planar)
    rss0 = peak_rss_mb()
    rep = geofeas.read_reports(frame)
    n = rep.n_tracks
    print(f"picture: {len(rep):,} reports, {n:,} tracks ({rep.coords}); peak RSS {rss0:.0f} MB")

    t = time.perf_counter()
    core, _ = _resolve_options(rep.sources, {}, {})  # the defaults of geofeas.associate
    a, b = _core.association_candidates(rep, options=core)
    t_cand = time.perf_counter() - t
    print(f"candidate generation (rstar): {len(a):,} candidate pairs in {t_cand:.2f} s")

    t = time.perf_counter()
    res = geofeas.associate(rep)
    t_full = time.perf_counter() - t
    rss1 = peak_rss_mb()
    counts = res.pairs["class"].value_counts()
    print(
        f"associate (candidates + scoring + posterior + triage): {t_full:.2f} s, "
        f"{len(res.pairs):,} pairs "
        f"({int(counts.get('match', 0)):,} match, {int(counts.get('borderline', 0)):,} "
        f"borderline); peak RSS {rss1:.0f} MB"
    )

    rng = np.random.default_rng(1)
    sa = rng.integers(0, n, args.sample)
    sb = rng.integers(0, n - 1, args.sample)
    sb = np.where(sb >= sa, sb + 1, sb)
    lo, hi = np.minimum(sa, sb).astype(np.uint32), np.maximum(sa, sb).astype(np.uint32)
    t = time.perf_counter()
    k = _core.association_pair_stats(rep, lo, hi, options=core).instants
    t_sample = time.perf_counter() - t
    all_pairs = n * (n - 1) / 2
    t_brute = t_sample * all_pairs / args.sample
    print(
        f"brute force: {args.sample:,} random pairs in {t_sample:.3f} s "
        f"({np.mean(k > 0):.1%} with common instants) -> all {all_pairs:,.0f} pairs "
        f"~ {t_brute:,.0f} s"
    )
    print(f"speed-up of the index over brute force: {t_brute / t_full:,.0f}x")
    print()
    print("| picture | candidates | associate | brute force (extrapolated) | speed-up | peak RSS |")
    print("|---|---|---|---|---|---|")
    print(
        f"| {n:,} tracks, {len(rep):,} reports, {rep.coords} | {len(a):,} | {t_full:.2f} s | "
        f"{t_brute:,.0f} s | {t_brute / t_full:,.0f}x | {rss1:.0f} MB |"
    )


if __name__ == "__main__":
    main()
