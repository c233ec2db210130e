"""``geofeas mht-study``: the Monte-Carlo reproduction of Tables 1 and 2 of seed 004.

Writes ``DIR/tables.csv`` (columns ``targets, sensors, tracker, false_alarms, t_pd, t_far,
pos_err, vel_err``), ``DIR/comparison.md`` (the three-sensor MHT rows beside the paper's
Tables 1 and 2), ``DIR/trends.png`` (the metrics against the false-alarm rate) and, for one
two-target run with two false alarms per sensor per scan, figures like the paper's Figs. 4-7
for the MHT and the single-hypothesis baseline (``DIR/fig_mht_*.png``, ``DIR/fig_single_*.png``).
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
import time
from pathlib import Path
from typing import Any

from ._atomic import atomic_open, save_figure, write_text
from .tracking import PAPER_TABLE_1, PAPER_TABLE_2, STUDY_COLUMNS, plot_run, simulate_run, study


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        return "nan" if math.isnan(v) else f"{v:.4g}"
    return str(v)


def write_tables(rows: list[dict[str, Any]], path: Path) -> None:
    with atomic_open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(STUDY_COLUMNS)
        for r in rows:
            w.writerow([_fmt(r[c]) for c in STUDY_COLUMNS])


def comparison_markdown(rows: list[dict[str, Any]], runs: int, seed: int, note: str = "") -> str:
    def cell(v: float, digits: int) -> str:
        return "-" if math.isnan(v) else f"{v:.{digits}f}"

    out = [f"Reproduction with {runs} runs per column (seed {seed}{note}); paper / geofeas.\n"]
    for targets, paper, title in ((1, PAPER_TABLE_1, "Table 1"), (2, PAPER_TABLE_2, "Table 2")):
        for sensors in (3, 2):
            out.append(f"\n### {title}: {targets} target(s), {sensors} sensors\n")
            sel = {
                (r["tracker"], r["false_alarms"]): r
                for r in rows
                if r["targets"] == targets and r["sensors"] == sensors
            }
            fas = sorted({fa for (_, fa) in sel})
            out.append("| metric | " + " | ".join(f"{fa} FA" for fa in fas) + " |")
            out.append("|---|" + "---|" * len(fas))
            for k, (name, digits) in enumerate(
                [("T_PD", 2), ("T_FAR [1/s]", 2), ("pos err [m]", 2), ("vel err [m/s]", 2)]
            ):
                key = STUDY_COLUMNS[4 + k]
                for tracker in ("mht", "single"):
                    vals = []
                    for fa in fas:
                        ours = cell(float(sel[(tracker, fa)][key]), digits)
                        if tracker == "mht" and sensors == 3 and fa in paper:
                            vals.append(f"{paper[fa][k]:g} / {ours}")
                        else:
                            vals.append(ours)
                    label = f"{name} ({'MHT' if tracker == 'mht' else 'single'})"
                    out.append(f"| {label} | " + " | ".join(vals) + " |")
    return "\n".join(out) + "\n"


def plot_trends(rows: list[dict[str, Any]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    keys = [
        ("t_pd", "T_PD"),
        ("t_far", "T_FAR [tracks/s]"),
        ("pos_err", "pos err [m]"),
        ("vel_err", "vel err [m/s]"),
    ]
    fig, axes = plt.subplots(2, 4, figsize=(16, 7))
    for row, targets in enumerate((1, 2)):
        paper = PAPER_TABLE_1 if targets == 1 else PAPER_TABLE_2
        for col, (key, label) in enumerate(keys):
            ax = axes[row, col]
            for tracker, sensors, style in (
                ("mht", 3, "o-"),
                ("mht", 2, "s-"),
                ("single", 3, "o--"),
                ("single", 2, "s--"),
            ):
                sel = sorted(
                    (r["false_alarms"], r[key])
                    for r in rows
                    if r["targets"] == targets
                    and r["sensors"] == sensors
                    and r["tracker"] == tracker
                )
                ax.plot(
                    [a for a, _ in sel],
                    [b for _, b in sel],
                    style,
                    label=f"{tracker}, {sensors} sensors",
                )
            fas = sorted(paper)
            ax.plot(fas, [paper[f][col] for f in fas], "k^:", label="paper (MHT, 3 sensors)")
            ax.set_title(f"{targets} target(s): {label}")
            ax.set_xlabel("false alarms per sensor per scan")
            if key == "t_far":
                ax.set_yscale("symlog", linthresh=0.1)
            elif key in ("pos_err", "vel_err"):
                ax.set_yscale("log")
    axes[0, 0].legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, path, dpi=100)
    plt.close(fig)


def run(args: argparse.Namespace) -> int:
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    res = study(
        runs=args.runs,
        seed=args.seed,
        max_hypotheses=args.max_hypotheses,
        ekf_iterations=args.ekf_iterations,
        new_target_rate=args.new_target_rate,
        detection_probability=args.detection_probability,
    )
    elapsed = time.perf_counter() - t0
    rows = [{c: res[c][i] for c in STUDY_COLUMNS} for i in range(len(res["tracker"]))]
    for r in rows:
        for c in ("targets", "sensors", "false_alarms"):
            r[c] = int(r[c])
        for c in ("t_pd", "t_far", "pos_err", "vel_err"):
            r[c] = float(r[c])
    write_tables(rows, out / "tables.csv")
    note = (
        f", {args.max_hypotheses} hypotheses, {args.ekf_iterations} EKF relinearisations, "
        f"new-target rate {args.new_target_rate:g}, detection probability "
        f"{args.detection_probability:g}"
    )
    write_text(out / "comparison.md", comparison_markdown(rows, args.runs, args.seed, note))
    print(
        f"study: {len(rows)} columns x {args.runs} runs in {elapsed:.1f} s -> {out / 'tables.csv'}",
        file=sys.stderr,
    )
    if not args.no_figures:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            print(
                "geofeas mht-study: error: the figures need matplotlib "
                "(pip install 'geofeas[plot]'); the tables are written, use --no-figures to skip",
                file=sys.stderr,
            )
            return 2
        plot_trends(rows, out / "trends.png")
        for tracker in ("mht", "single"):
            r = simulate_run(
                targets=2,
                sensors=3,
                false_alarms=2,
                tracker=tracker,
                run=0,
                seed=args.seed,
                max_hypotheses=args.max_hypotheses,
                ekf_iterations=args.ekf_iterations,
                detection_probability=args.detection_probability,
            )
            plot_run(r, out, prefix=f"fig_{tracker}")
        print(f"figures -> {out}", file=sys.stderr)
    return 0


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "mht-study",
        help="reproduce Tables 1 and 2 of the MHT trilateration paper (seed 004)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--out", required=True, help="output directory")
    p.add_argument("--runs", type=int, default=100, help="Monte-Carlo runs per column (100)")
    p.add_argument("--seed", type=int, default=0, help="seed of the random streams (0)")
    p.add_argument("--max-hypotheses", type=int, default=50, help="MHT hypotheses kept (50)")
    p.add_argument(
        "--ekf-iterations",
        type=int,
        default=2,
        help="relinearisations of the Cartesian EKF update (2; 0: the paper's EKF)",
    )
    p.add_argument(
        "--new-target-rate",
        type=float,
        default=0.02,
        help="expected new targets per scan in a sensor window (0.02)",
    )
    p.add_argument(
        "--detection-probability",
        type=float,
        default=1.0,
        help="detection probability of the simulated sensors (1, as in the paper)",
    )
    p.add_argument("--no-figures", action="store_true", help="write the CSV and markdown only")
    p.set_defaults(func=run)
