"""Speed of the MHT trilateration tracker (seed 004) against baselines measured in the same run.

    python benches/bench_mht.py [--quick]

Rows: one 20 s two-target scenario of the paper with 3 sensors and 4 false alarms per sensor per
scan, simulated and tracked through the Python API, by the MHT with 50 hypotheses and by the
single-hypothesis baseline (the ratio is MHT / single); the paper's real time (20 s of data); and
the full Tables 1-2 study (three trackers, up to 8 false alarms per sensor per scan). Prints a
Markdown table of best-of-k wall times.
"""

from __future__ import annotations

import argparse
import time

from geofeas.tracking import mht_simulate_run, mht_study


def best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="fewer repeats and study runs")
    args = parser.parse_args()
    repeat = 3 if args.quick else 10
    runs = 5 if args.quick else 100

    def scenario(tracker: str) -> None:
        mht_simulate_run(targets=2, sensors=3, false_alarms=4, tracker=tracker, seed=1)

    t_mht = best(lambda: scenario("mht"), repeat)
    t_single = best(lambda: scenario("single"), repeat)
    cells: list[int] = []
    t_study = best(lambda: cells.append(len(mht_study(runs=runs)["tracker"])), 1)
    print("| what | time | ratio |")
    print("|---|---|---|")
    print(
        f"| 20 s, 2 targets, 3 sensors, 4 FA: MHT (50 hypotheses) | {t_mht * 1e3:.1f} ms | "
        f"{t_mht / t_single:.2f}x single, {20.0 / t_mht:.0f}x real time |"
    )
    print(f"| same, single-hypothesis baseline | {t_single * 1e3:.1f} ms | 1 |")
    print(
        f"| Tables 1-2 study (mht, mht-paper, single; up to 8 FA), {cells[0]} columns x {runs} "
        f"runs | {t_study:.1f} s | |"
    )


if __name__ == "__main__":
    main()
