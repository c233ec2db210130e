"""Speed of the particle-filter focal-plane tracker (seed 003) against a vectorised NumPy
implementation of the same filter, measured in the same run.

    python benches/bench_pf.py [--frames F] [--particles N] [--repeat K]

Rows (best of ``--repeat`` wall times):

- the full 10 s scenario of the paper (101 frames, 4 filters x N particles, Method 2, 6 dB)
  simulated and tracked by :func:`geofeas.tracking.pf_simulate_run`;
- the same bank of Method-2 filters on the same ``F`` frames (``pf_track``), against
  ``tests/pf_reference.py::track_method2`` (NumPy, the paper's cell-by-cell likelihood ratio
  over the +-10 box, vectorised over particles): the ratio is NumPy / Rust;
- the Method-2 weights of N particles on one frame (``pf_log_weights``) against the NumPy
  reference.

By default the NumPy filter runs on the first 20 frames (about 15 s at N = 10,000); ``--frames
101`` runs the full scenario in both.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from geofeas.tracking import pf_log_weights, pf_simulate_run, pf_track

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from pf_reference import log_likelihood_ratio, track_method2  # noqa: E402


def best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--frames", type=int, default=20, help="frames for the NumPy filter (20)")
    parser.add_argument("--particles", type=int, default=10_000, help="particles per filter")
    parser.add_argument("--repeat", type=int, default=3, help="repeats of the Rust timings")
    args = parser.parse_args()
    n, f = args.particles, args.frames
    snr = 6.0
    sigma = 10 ** (-snr / 20)

    t_full = best(lambda: pf_simulate_run(snr_db=snr, method=2, particles=n), args.repeat)
    sim = pf_simulate_run(snr_db=snr, method=2, particles=10, keep_frames=list(range(f)))
    frames = sim["frames"]
    init = sim["truth"][0, :, :4]

    t_rust = best(lambda: pf_track(frames, init, sigma_z=sigma, particles=n), args.repeat)
    t0 = time.perf_counter()
    track_method2(frames, init, sigma_z=sigma, particles=n, rng=np.random.default_rng(0))
    t_numpy = time.perf_counter() - t0

    rng = np.random.default_rng(1)
    xy = init[0, :2] + rng.uniform(-3, 3, (n, 2))
    z = frames[0]
    t_w = best(lambda: pf_log_weights(z, xy, amplitude=0.8, blur=3.0, sigma=1.5 * sigma), 10)
    t0 = time.perf_counter()
    log_likelihood_ratio(z, xy[:, 0], xy[:, 1], 0.8, 3.0, 1.5 * sigma, 10)
    t_wn = time.perf_counter() - t0

    print("| what | time | ratio |")
    print("|---|---|---|")
    print(
        f"| full 10 s scenario, 4 x {n} particles, Method 2, simulated + tracked (Rust) | "
        f"{t_full:.2f} s | {10.0 / t_full:.1f}x real time |"
    )
    print(
        f"| Method-2 bank on {f} frames, 4 x {n} particles: Rust `pf_track` | "
        f"{t_rust * 1e3:.0f} ms | 1 |"
    )
    print(
        f"| same, NumPy reference (vectorised, cell by cell) | {t_numpy:.2f} s | "
        f"{t_numpy / t_rust:.0f}x slower |"
    )
    print(f"| Method-2 weights of {n} particles, one frame (Rust) | {t_w * 1e3:.2f} ms | 1 |")
    print(f"| same, NumPy reference | {t_wn * 1e3:.1f} ms | {t_wn / t_w:.0f}x slower |")


if __name__ == "__main__":
    main()
