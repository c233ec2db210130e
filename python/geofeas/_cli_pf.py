"""``geofeas pf-study``: the Monte-Carlo reproduction of seed 003 (Ohlmeyer and Menon, particle
filters for image-plane tracking of multiple objects).

Writes to DIR:

- ``pca_vs_snr.csv`` (``method, snr_db, pca``): probability of correct association of Methods
  1 and 2 at 0, 1, ..., 20 dB (Fig. 19);
- ``errors.csv`` (``method, snr_db, filter, rmse_px``): position RMSE of each filter at 2, 6 and
  15 dB;
- ``summary.csv``: every study row with PCA, hit rate, RMSE, 2-sigma coverage and held-track
  fraction, each with its 95 % percentile-bootstrap interval over runs (``_lo``, ``_hi``);
- ``ic_sensitivity.csv`` (``xmax, vmax, rmse_px, held, pca``): Method 2 at 2 dB against the
  initialisation half-widths (Fig. 20);
- ``comparison.md``: the numbers beside the paper's statements;
- figures: ``fig19_pca_vs_snr.png``, ``fig20_ic_sensitivity.png``, ``rmse_vs_snr.png``,
  ``fig02_frames.png`` and, for run 0, tracks / errors / association / residual figures of
  Method 1 at 15 dB and Method 2 at 15, 6 and 2 dB (``m<method>_<snr>db_*.png``, Figs. 6-18).
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

import numpy as np

from ._atomic import save_figure, write_text
from .tracking import PAPER_IC, PAPER_PCA, pf_simulate_run, pf_study, plot_pf_run

#: SNRs of the error table.
ERROR_SNRS = (2.0, 6.0, 15.0)


def _fmt(v: float) -> str:
    return "nan" if math.isnan(v) else f"{v:.4g}"


def _csv(path: Path, header: list[str], rows: list[list[Any]]) -> None:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    w.writerows(rows)
    write_text(path, buf.getvalue())


#: Metrics of a study row; each has a 95 % percentile-bootstrap interval over runs
#: (``<name>_lo``, ``<name>_hi``).
METRICS = ("pca", "hit", "rmse_px", "coverage", "held")

#: Multi-target measures of the bank (point estimates): GOSPA (cut-off 5 px, order 2), its
#: localisation part and missed / false counts per frame, identity switches and fragmentations
#: per run.
BANK_METRICS = (
    "gospa",
    "gospa_loc",
    "gospa_missed",
    "gospa_false",
    "id_switches",
    "fragmentations",
)


def _with_ci(res: dict[str, Any], k: int, names: tuple[str, ...]) -> list[str]:
    return [_fmt(float(res[f"{c}{s}"][k])) for c in names for s in ("", "_lo", "_hi")]


def _ci_header(names: tuple[str, ...]) -> list[str]:
    return [f"{c}{s}" for c in names for s in ("", "_lo", "_hi")]


def write_csvs(res: dict[str, Any], out: Path) -> None:
    n = len(res["method"])
    n_ic = res["_n_ic"]
    snr_rows = list(range(n - n_ic))
    _csv(
        out / "pca_vs_snr.csv",
        ["method", "snr_db"] + _ci_header(("pca",)),
        [
            [int(res["method"][k]), f"{res['snr_db'][k]:g}"] + _with_ci(res, k, ("pca",))
            for k in snr_rows
        ],
    )
    _csv(
        out / "errors.csv",
        ["method", "snr_db", "filter", "rmse_px"],
        [
            [int(res["method"][k]), f"{res['snr_db'][k]:g}", i + 1, _fmt(v)]
            for k in snr_rows
            if float(res["snr_db"][k]) in ERROR_SNRS
            for i, v in enumerate(res["filter_rmse_px"][k])
        ],
    )
    _csv(
        out / "summary.csv",
        ["method", "snr_db", "xmax", "vmax", "runs"] + _ci_header(METRICS) + list(BANK_METRICS),
        [
            [int(res["method"][k])]
            + [f"{res[c][k]:g}" for c in ("snr_db", "xmax", "vmax")]
            + [int(res["_runs"])]
            + _with_ci(res, k, METRICS)
            + [_fmt(float(res[c][k])) for c in BANK_METRICS]
            for k in range(n)
        ],
    )
    _csv(
        out / "ic_sensitivity.csv",
        ["xmax", "vmax"] + _ci_header(("rmse_px", "held", "pca")),
        [
            [f"{res['xmax'][k]:g}", f"{res['vmax'][k]:g}"]
            + _with_ci(res, k, ("rmse_px", "held", "pca"))
            for k in range(n - n_ic, n)
        ],
    )


def _row(res: dict[str, Any], method: int, snr: float) -> int:
    for k in range(len(res["method"]) - res["_n_ic"]):
        if res["method"][k] == method and res["snr_db"][k] == snr:
            return k
    raise KeyError((method, snr))


def _interval(res: dict[str, Any], k: int, key: str) -> str:
    v, lo, hi = (float(res[f"{key}{s}"][k]) for s in ("", "_lo", "_hi"))
    if lo == hi:
        return _fmt(v)
    return f"{_fmt(v)} [{_fmt(lo)}, {_fmt(hi)}]"


def comparison_markdown(res: dict[str, Any], note: str) -> str:
    def cell(method: int, snr: float, key: str) -> str:
        try:
            return _interval(res, _row(res, method, snr), key)
        except KeyError:
            return "-"

    lines = [
        f"Reproduction: {note}. Value [95 % percentile-bootstrap interval over runs].\n",
        "| SNR [dB] | paper (Method 2) | PCA M2 | PCA M1 | hit M2 | hit M1 | RMSE M2 [px] "
        "| RMSE M1 [px] | held M2 | held M1 |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for snr in (0.0, 2.0, 6.0, 9.0, 12.0, 15.0, 20.0):
        paper = PAPER_PCA.get(snr)
        lines.append(
            f"| {snr:g} | {'PCA %.0f%%' % (100 * paper) if paper is not None else '-'} | "
            f"{cell(2, snr, 'pca')} | {cell(1, snr, 'pca')} | {cell(2, snr, 'hit')} | "
            f"{cell(1, snr, 'hit')} | {cell(2, snr, 'rmse_px')} | "
            f"{cell(1, snr, 'rmse_px')} | {cell(2, snr, 'held')} | {cell(1, snr, 'held')} |"
        )
    lines += [
        "",
        "GOSPA (cut-off 5 px, order 2) between the true positions and the four filters' "
        "estimates, mean per frame, with the missed / false targets per frame, and identity "
        "switches and fragmentations per run:",
        "",
        "| SNR [dB] | GOSPA M2 [px] | GOSPA M1 [px] | missed M2 | missed M1 | ID switches M2 "
        "| ID switches M1 | fragmentations M2 | fragmentations M1 |",
        "|---|---|---|---|---|---|---|---|---|",
    ]

    def plain(method: int, snr: float, key: str) -> str:
        try:
            return _fmt(float(res[key][_row(res, method, snr)]))
        except KeyError:
            return "-"

    for snr in (0.0, 2.0, 6.0, 9.0, 12.0, 15.0, 20.0):
        cells = [
            plain(m, snr, key)
            for key in ("gospa", "gospa_missed", "id_switches", "fragmentations")
            for m in (2, 1)
        ]
        lines.append(f"| {snr:g} | " + " | ".join(cells) + " |")
    n = len(res["method"])
    lines += [
        "",
        "Method 2 at the initial-condition SNR against the initialisation half-widths:",
        "",
        "| Xmax [px] | Vmax [px/s] | RMSE [px] | held | PCA |",
        "|---|---|---|---|---|",
    ]
    for k in range(n - res["_n_ic"], n):
        lines.append(
            f"| {res['xmax'][k]:g} | {res['vmax'][k]:g} | {_interval(res, k, 'rmse_px')} | "
            f"{_interval(res, k, 'held')} | {_interval(res, k, 'pca')} |"
        )
    return "\n".join(lines) + "\n"


def plot_study(res: dict[str, Any], out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(res["method"])
    m = n - res["_n_ic"]
    method = np.asarray(res["method"][:m])
    snr = np.asarray(res["snr_db"][:m])
    fig, ax = plt.subplots(figsize=(6, 4))
    for k, style in ((1, "s--"), (2, "o-")):
        sel = method == k
        ax.plot(snr[sel], 100 * np.asarray(res["pca"][:m])[sel], style, label=f"Method {k}")
        ax.plot(
            snr[sel],
            100 * np.asarray(res["hit"][:m])[sel],
            style[0] + ":",
            color=ax.lines[-1].get_color(),
            alpha=0.6,
            label=f"Method {k}, hit (peak within 3 px)",
        )
    ax.plot(list(PAPER_PCA), [100 * v for v in PAPER_PCA.values()], "k^", label="paper, Method 2")
    ax.set_xlabel("SNR [dB]")
    ax.set_ylabel("PCA [%]")
    ax.set_ylim(0, 105)
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title("Probability of correct association vs SNR (Fig. 19)")
    fig.tight_layout()
    save_figure(fig, out / "fig19_pca_vs_snr.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6, 4))
    for k, style in ((1, "s--"), (2, "o-")):
        sel = method == k
        ax.semilogy(snr[sel], np.asarray(res["rmse_px"][:m])[sel], style, label=f"Method {k}")
    ax.set_xlabel("SNR [dB]")
    ax.set_ylabel("position RMSE [px]")
    ax.grid(alpha=0.3, which="both")
    ax.legend()
    ax.set_title("Position RMSE over 10 s and four targets")
    fig.tight_layout()
    save_figure(fig, out / "rmse_vs_snr.png", dpi=110)
    plt.close(fig)

    xs = np.asarray(res["xmax"][m:])
    vs = np.asarray(res["vmax"][m:])
    fig, ax1 = plt.subplots(figsize=(6, 4))
    labels = [f"{x:g} / {v:g}" for x, v in zip(xs, vs, strict=True)]
    pos = np.arange(len(labels))
    ax1.bar(pos - 0.2, np.asarray(res["rmse_px"][m:]), 0.4, label="RMSE [px]")
    ax1.set_ylabel("RMSE [px]")
    ax2 = ax1.twinx()
    ax2.bar(pos + 0.2, 100 * np.asarray(res["held"][m:]), 0.4, color="C1", label="held [%]")
    ax2.set_ylabel("tracks held [%]")
    ax2.set_ylim(0, 105)
    ax1.set_xticks(pos, labels)
    ax1.set_xlabel("Xmax [px] / Vmax [px/s]")
    ax1.set_title("Method 2 initial-condition sensitivity (Fig. 20)")
    fig.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    save_figure(fig, out / "fig20_ic_sensitivity.png", dpi=110)
    plt.close(fig)


def plot_frames(seed: int, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    keep = [0, 30, 60, 100]
    r = pf_simulate_run(snr_db=15.0, method=2, seed=seed, particles=100, keep_frames=keep)
    fig, axes = plt.subplots(1, 4, figsize=(14, 3.8))
    for ax, k, img in zip(axes, keep, r["frames"], strict=True):
        ax.imshow(img, cmap="gray", origin="lower")
        ax.plot(r["truth"][k, :, 0], r["truth"][k, :, 1], "r+", ms=10)
        ax.set_title(f"t = {k * 0.1:.0f} s" if k % 10 == 0 else f"t = {k * 0.1:.1f} s")
    fig.suptitle("Frames at 15 dB with the true positions (Fig. 2)")
    fig.tight_layout()
    save_figure(fig, out / "fig02_frames.png", dpi=90)
    plt.close(fig)


def run(args: argparse.Namespace) -> int:
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    common = {
        "seed": args.seed,
        "truth": args.truth,
        "particles": args.particles,
        "association": args.association,
        "smoothing": args.smoothing,
    }
    t0 = time.perf_counter()
    res = pf_study(runs=args.runs, ic=PAPER_IC, ic_snr=args.ic_snr, **common)
    res["_n_ic"] = len(PAPER_IC)
    res["_runs"] = args.runs
    elapsed = time.perf_counter() - t0
    write_csvs(res, out)
    note = (
        f"{args.runs} runs per row, seed {args.seed}, {args.particles} particles per filter, "
        f"truth '{args.truth}', association '{args.association}', peak smoothing "
        f"{args.smoothing:g}, initial-condition rows at {args.ic_snr:g} dB"
    )
    write_text(out / "comparison.md", comparison_markdown(res, note))
    print(
        f"pf-study: {len(res['method'])} rows x {args.runs} runs in {elapsed:.1f} s -> {out}",
        file=sys.stderr,
    )
    if not args.no_figures:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            print(
                "geofeas pf-study: error: the figures need matplotlib "
                "(pip install 'geofeas[plot]'); the CSVs are written, use --no-figures to skip",
                file=sys.stderr,
            )
            return 2
        plot_study(res, out)
        plot_frames(args.seed, out)
        for method, snr in ((1, 15.0), (2, 15.0), (2, 6.0), (2, 2.0)):
            r = pf_simulate_run(
                snr_db=snr,
                method=method,
                snapshot_frames=[0, 25, 50, 75, 100],
                keep_frames=[100],
                **common,
            )
            plot_pf_run(r, out, prefix=f"m{method}_{snr:g}db")
        print(f"figures -> {out}", file=sys.stderr)
    return 0


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "pf-study",
        help="reproduce the particle-filter focal-plane tracking study (seed 003)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--out", required=True, help="output directory")
    p.add_argument("--runs", type=int, default=16, help="Monte-Carlo runs per row (16)")
    p.add_argument("--seed", type=int, default=0, help="seed of the random streams (0)")
    p.add_argument(
        "--particles", type=int, default=10_000, help="particles per filter (10000, the paper's)"
    )
    p.add_argument(
        "--association",
        choices=["nearest", "one-to-one"],
        default="nearest",
        help="peak-to-filter association (nearest: the paper's)",
    )
    p.add_argument(
        "--truth",
        choices=["white", "jerk", "gauss-markov", "ncv"],
        default="white",
        help="reading of the Fig. 3 truth model (white)",
    )
    p.add_argument(
        "--smoothing",
        type=float,
        default=0.0,
        help="Gaussian smoothing of the frame before peak extraction, px (0: the paper's raw)",
    )
    p.add_argument("--ic-snr", type=float, default=2.0, help="SNR of the Fig. 20 rows (2 dB)")
    p.add_argument("--no-figures", action="store_true", help="write the CSVs and markdown only")
    p.set_defaults(func=run)
