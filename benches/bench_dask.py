"""Distributed association on Dask against the single-process engine, in the same run.

A synthetic picture of about 1,000,000 reports (ships seen by AIS and by coastal radar over a
2,000 km square, radar tracks broken and renumbered) is associated

1. by ``geofeas.associate`` in this process (rayon on every core): the baseline;
2. by ``geofeas.integrations.dask.associate`` on a ``distributed.LocalCluster`` of 1 worker
   process and of 2 worker processes (one thread each, ``RAYON_NUM_THREADS=1`` per worker),
   loopback only.

Every distributed result is checked equal to the baseline before its time is reported. Times
are wall-clock medians of ``--repeat`` runs; the figures are ratios against the baseline (and
1 worker against 2). On a shared 2-core machine the timings are noisy.

    python benches/bench_dask.py                 # 1,000,000 reports
    python benches/bench_dask.py --reports 200000 --repeat 1
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

import numpy as np
import pandas as pd


def aou_cov(rx: np.ndarray, ry: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Eqs. 56-58 of seed 000 as a stacked 2x2 covariance."""
    s, c = np.sin(phi), np.cos(phi)
    u = np.stack([np.stack([s, c], -1), np.stack([c, -s], -1)], -2)
    lam = np.zeros((len(rx), 2, 2))
    lam[:, 0, 0], lam[:, 1, 1] = rx**2 / 4, ry**2 / 4
    return u @ lam @ np.swapaxes(u, -1, -2)


def synthetic_picture(reports: int, seed: int = 0, area: float = 2_000_000.0) -> pd.DataFrame:
    """About ``reports`` reports: per ship 4 h of AIS every 60 s and radar every 30 s."""
    rng = np.random.default_rng(seed)
    duration = 4 * 3600.0
    per_ship = duration / 60.0 + duration / 30.0
    ships = max(2, int(round(reports / per_ship)))
    pos0 = rng.uniform(0, area, (ships, 2))
    heading = rng.uniform(0, 2 * np.pi, ships)
    vel = np.column_stack([np.sin(heading), np.cos(heading)]) * rng.uniform(3, 10, (ships, 1))
    frames = []
    for source, step, rx, ry in (("ais", 60.0, 20.0, 20.0), ("radar", 30.0, 150.0, 60.0)):
        k = int(duration // step)
        t = rng.uniform(0, step, (ships, 1)) + step * np.arange(k)[None, :]
        ship = np.repeat(np.arange(ships), k)
        t = t.ravel()
        n = t.size
        phi = np.repeat(rng.uniform(0, np.pi, ships), k) if source == "radar" else np.zeros(n)
        rxs, rys = np.full(n, rx), np.full(n, ry)
        chol = np.linalg.cholesky(aou_cov(rxs, rys, phi))
        noise = np.einsum("nij,nj->ni", chol, rng.normal(size=(n, 2)))
        xy = pos0[ship] + vel[ship] * t[:, None] + noise
        if source == "radar":  # the tracker renumbers each ship's track once, at a random time
            cut = np.repeat(rng.uniform(0, duration, ships), k)
            segment = (t > cut).astype(np.int64)
            ids = np.char.add(
                np.char.add(f"{source}-", ship.astype(str)), np.where(segment, "b", "")
            )
        else:
            ids = np.char.add(f"{source}-", ship.astype(str))
        frames.append(
            pd.DataFrame(
                {
                    "track_id": ids.astype(object),
                    "source": source,
                    "time": t,
                    "x": xy[:, 0],
                    "y": xy[:, 1],
                    "rx": rxs,
                    "ry": rys,
                    "phi": phi,
                }
            )
        )
    return pd.concat(frames, ignore_index=True)


def canonical(assoc) -> tuple[pd.DataFrame, pd.DataFrame]:
    pairs = assoc.pairs.sort_values(["track_a", "track_b"]).reset_index(drop=True)
    objects = assoc.objects.sort_values("track_id").reset_index(drop=True)
    return pairs, objects


def same(a, b) -> bool:
    (pa, oa), (pb, ob) = canonical(a), canonical(b)
    return pa.equals(pb) and oa.equals(ob)


def timed(fn, repeat: int, cpu=time.process_time):
    """Median wall time, median CPU time (``cpu()`` deltas: all threads, all processes)."""
    walls, cpus, out = [], [], None
    for _ in range(repeat):
        c0, t0 = cpu(), time.perf_counter()
        out = fn()
        walls.append(time.perf_counter() - t0)
        cpus.append(cpu() - c0)
    return statistics.median(walls), statistics.median(cpus), out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reports", type=int, default=1_000_000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--partitions", type=int, default=8)
    parser.add_argument("--score", default="glr", help="per-instant score (glr, overlap, ...)")
    args = parser.parse_args(argv)

    import dask.dataframe as dd
    from distributed import Client, LocalCluster, wait

    import geofeas
    import geofeas.integrations.dask as gd

    df = synthetic_picture(args.reports)
    options = {"score": args.score}
    print(f"picture: {len(df):,} reports, {df['track_id'].nunique():,} tracks; {options}")
    print(f"load average before: {os.getloadavg()}", flush=True)
    t_single, c_single, base = timed(lambda: geofeas.associate(df, **options), args.repeat)
    print(
        f"single process (geofeas.associate, {os.cpu_count()} rayon threads): {t_single:.2f} s "
        f"wall, {c_single:.2f} s CPU; {len(base.pairs):,} pairs",
        flush=True,
    )
    rows = []
    for workers in (1, 2):
        with (
            LocalCluster(
                n_workers=workers,
                threads_per_worker=1,
                processes=True,
                host="127.0.0.1",
                dashboard_address=None,
                env={"RAYON_NUM_THREADS": "1"},
            ) as cluster,
            Client(cluster) as client,
        ):
            ddf = client.persist(dd.from_pandas(df, npartitions=args.partitions))
            wait(ddf)

            def cpu(client=client):
                # this process (client and scheduler) and every worker process
                return time.process_time() + sum(client.run(time.process_time).values())

            t, c, got = timed(lambda ddf=ddf: gd.associate(ddf, **options), args.repeat, cpu)
            if not same(got, base):
                print(f"{workers} worker(s): result differs from the single-process one")
                return 1
            rows.append((workers, t, c))
            print(
                f"dask, {workers} worker process(es): {t:.2f} s wall ({t / t_single:.2f}x the "
                f"single process), {c:.2f} s CPU ({c / c_single:.2f}x), {got.tiles} tiles",
                flush=True,
            )
    (_, t1, c1), (_, t2, c2) = rows
    print(f"load average after: {os.getloadavg()}")
    print()
    print("| run | wall (s) | vs single process | CPU (s) | vs single process | 1 -> 2 workers |")
    print("|---|---|---|---|---|---|")
    print(f"| geofeas.associate, one process | {t_single:.2f} | 1.00 | {c_single:.2f} | 1.00 | |")
    print(
        f"| geofeas.integrations.dask, 1 worker | {t1:.2f} | {t1 / t_single:.2f} | {c1:.2f} | "
        f"{c1 / c_single:.2f} | |"
    )
    print(
        f"| geofeas.integrations.dask, 2 workers | {t2:.2f} | {t2 / t_single:.2f} | {c2:.2f} | "
        f"{c2 / c_single:.2f} | {t1 / t2:.2f}x faster |"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
