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
import io
import math
import sys
import time
from pathlib import Path
from typing import Any

from .._atomic import save_figure, write_text
from ..tracking import (
    PAPER_TABLE_1,
    PAPER_TABLE_2,
    STUDY_COLUMNS,
    TRACKERS,
    mht_simulate_run,
    mht_study,
    plot_mht_run,
)
from ..tracking._mht import OPTIONS


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        return "nan" if math.isnan(v) else f"{v:.4g}"
    return str(v)


def write_tables(rows: list[dict[str, Any]], path: Path) -> None:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(STUDY_COLUMNS)
    for r in rows:
        w.writerow([_fmt(r[c]) for c in STUDY_COLUMNS])
    write_text(path, buf.getvalue())


#: Rows of the comparison tables: metric, label, digits, index in the paper's tables (or None).
_TABLE_ROWS = (
    ("t_pd", "T_PD", 2, 0),
    ("t_far", "T_FAR [1/s]", 2, 1),
    ("pos_err", "pos err [m]", 2, 2),
    ("vel_err", "vel err [m/s]", 2, 3),
    ("speed_err", "speed err [m/s]", 2, None),
    ("gospa", "GOSPA [m]", 2, None),
    ("gospa_missed", "GOSPA missed / output", 2, None),
    ("gospa_false", "GOSPA false / output", 2, None),
    ("id_switches", "ID switches / run", 2, None),
    ("fragmentations", "fragmentations / run", 2, None),
)


def comparison_markdown(rows: list[dict[str, Any]], runs: int, seed: int, note: str = "") -> str:
    def cell(r: dict[str, Any], key: str, digits: int) -> str:
        v, lo, hi = (float(r[key]), float(r[f"{key}_lo"]), float(r[f"{key}_hi"]))
        if math.isnan(v):
            return "-"
        if math.isnan(lo) or math.isnan(hi):
            return f"{v:.{digits}f}"
        return f"{v:.{digits}f} [{lo:.{digits}f}, {hi:.{digits}f}]"

    trackers = [t for t in TRACKERS if any(r["tracker"] == t for r in rows)]
    out = [
        f"{runs} runs per column (seed {seed}{note}); value [95% percentile-bootstrap interval "
        "over runs]. The paper's rows are its Tables 1 and 2 (MHT, three sensors).\n"
    ]
    for targets, paper, title in ((1, PAPER_TABLE_1, "Table 1"), (2, PAPER_TABLE_2, "Table 2")):
        for sensors in (3, 2):
            sel = {
                (r["tracker"], r["false_alarms"]): r
                for r in rows
                if r["targets"] == targets and r["sensors"] == sensors
            }
            if not sel:
                continue
            out.append(f"\n### {title}: {targets} target(s), {sensors} sensors\n")
            fas = sorted({fa for (_, fa) in sel})
            out.append("| metric | tracker | " + " | ".join(f"{fa} FA" for fa in fas) + " |")
            out.append("|---|---|" + "---|" * len(fas))
            for key, name, digits, k in _TABLE_ROWS:
                if k is not None and sensors == 3:
                    vals = [f"{paper[fa][k]:g}" if fa in paper else "" for fa in fas]
                    out.append(f"| {name} | paper | " + " | ".join(vals) + " |")
                for tracker in trackers:
                    vals = [
                        cell(sel[(tracker, fa)], key, digits) if (tracker, fa) in sel else ""
                        for fa in fas
                    ]
                    out.append(f"| {name} | {tracker} | " + " | ".join(vals) + " |")
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
                ("mht-paper", 3, "o-."),
                ("mht-paper", 2, "s-."),
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
                if not sel:
                    continue
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


#: The study options as declared in the core: name -> (kind, default, doc, choices).
_STUDY = {o[0]: o[1:] for o in OPTIONS["study"]}

#: Flags whose default is the command's own, not the library's: more runs than
#: :func:`geofeas.tracking.mht_study`'s quick default.
CLI_DEFAULTS = {"runs": 100}


def _option(p: argparse.ArgumentParser, name: str, **kw: Any) -> None:
    """Adds ``--name`` for the study option ``name``: its type, its default (unless the command
    has its own, :data:`CLI_DEFAULTS`) and its doc with the default."""
    kind, default, doc, _choices = _STUDY[name]
    default = CLI_DEFAULTS.get(name, default)
    if kind in ("int", "float"):
        kw.setdefault("type", {"int": int, "float": float}[kind])
    if isinstance(default, tuple):
        shown = ",".join(str(v) for v in default)
    else:
        shown = f"{default:.4g}" if isinstance(default, float) else str(default)
    p.add_argument(f"--{name.replace('_', '-')}", default=default, help=f"{doc} ({shown})", **kw)


def _ints(text: str) -> list[int]:
    try:
        return [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected comma-separated integers, got {text!r}"
        ) from None


def _trackers(text: str) -> list[str]:
    names = [v.strip() for v in text.split(",") if v.strip()]
    bad = [n for n in names if n not in TRACKERS]
    if bad or not names:
        raise argparse.ArgumentTypeError(
            f"expected trackers among {', '.join(TRACKERS)}, got {text!r}"
        )
    return names


def run(args: argparse.Namespace) -> int:
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    res = mht_study(
        runs=args.runs,
        seed=args.seed,
        max_hypotheses=args.max_hypotheses,
        ekf_iterations=args.ekf_iterations,
        new_target_rate=args.new_target_rate,
        detection_probability=args.detection_probability,
        confirm_probability=args.confirm_probability,
        accel_sigma=args.accel_sigma,
        paper_ekf_iterations=args.paper_ekf_iterations,
        paper_new_target_rate=args.paper_new_target_rate,
        paper_confirm_probability=args.paper_confirm_probability,
        paper_accel_sigma=args.paper_accel_sigma,
        trackers=args.trackers,
        one_target=args.one_target,
        two_targets=args.two_targets,
        resamples=args.resamples,
    )
    elapsed = time.perf_counter() - t0
    rows = [{c: res[c][i] for c in STUDY_COLUMNS} for i in range(len(res["tracker"]))]
    for r in rows:
        for c in STUDY_COLUMNS:
            if c in ("targets", "sensors", "false_alarms", "runs"):
                r[c] = int(r[c])
            elif c != "tracker":
                r[c] = float(r[c])
    write_tables(rows, out / "tables.csv")
    note = (
        f"; mht: {args.ekf_iterations} EKF relinearisations, new-target rate "
        f"{args.new_target_rate:g}, confirmation {args.confirm_probability:g}; mht-paper: "
        f"{args.paper_ekf_iterations} relinearisations, new-target rate "
        f"{args.paper_new_target_rate:g}, confirmation {args.paper_confirm_probability:g}, "
        f"process noise {args.paper_accel_sigma:.3g} m/s^2; "
        f"{args.max_hypotheses} hypotheses, process noise of mht and single "
        f"{args.accel_sigma:.3g} m/s^2, "
        f"detection probability {args.detection_probability:g}"
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
            r = mht_simulate_run(
                targets=2,
                sensors=3,
                false_alarms=2,
                tracker=tracker,
                run=0,
                seed=args.seed,
                max_hypotheses=args.max_hypotheses,
                ekf_iterations=args.ekf_iterations,
                detection_probability=args.detection_probability,
                new_target_rate=args.new_target_rate,
                confirm_probability=args.confirm_probability,
                accel_sigma=args.accel_sigma,
            )
            plot_mht_run(r, out, prefix=f"fig_{tracker}")
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
    _option(p, "runs")
    _option(p, "seed")
    _option(p, "trackers", type=_trackers)
    _option(p, "one_target", type=_ints)
    _option(p, "two_targets", type=_ints)
    for name in (
        "max_hypotheses",
        "ekf_iterations",
        "new_target_rate",
        "confirm_probability",
        "paper_ekf_iterations",
        "paper_new_target_rate",
        "paper_confirm_probability",
        "paper_accel_sigma",
        "accel_sigma",
        "detection_probability",
        "resamples",
    ):
        _option(p, name)
    p.add_argument("--no-figures", action="store_true", help="write the CSV and markdown only")
    p.set_defaults(func=run)
