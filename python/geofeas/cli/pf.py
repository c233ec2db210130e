"""``geofeas pf-study``: the Monte-Carlo reproduction of seed 003 (Ohlmeyer and Menon, particle
filters for image-plane tracking of multiple objects).

Runs the paper-faithful configuration, the project's recommended one or both (``--config``;
``geofeas.tracking.PF_CONFIGS``) on the same seeded runs and writes to DIR, every CSV row
starting with its ``config``:

- ``pca_vs_snr.csv`` (``method, snr_db, pca``): probability of correct association of Methods
  1 and 2 at 0, 1, ..., 20 dB (Fig. 19);
- ``errors.csv`` (``method, snr_db, filter, rmse_px``): position RMSE of each filter at 2, 6 and
  15 dB;
- ``summary.csv``: every study row with PCA, hit rate, RMSE, 2-sigma coverage and held-track
  fraction, each with its 95 % percentile-bootstrap interval over runs (``_lo``, ``_hi``);
- ``ic_sensitivity.csv`` (``xmax, vmax, rmse_px, held, pca``): Method 2 at 2 dB against the
  initialisation half-widths (Fig. 20);
- ``comparison.md``: the numbers beside the paper's statements, the two configurations side by
  side;
- figures: ``fig19_pca_vs_snr.png``, ``rmse_vs_snr.png`` (every configuration),
  ``fig20_ic_sensitivity.png``, ``fig02_frames.png`` and, for run 0, tracks / errors /
  association / residual figures of Method 1 at 15 dB and Method 2 at 15, 6 and 2 dB
  (``m<method>_<snr>db_*.png``, Figs. 6-18) of the first configuration (``paper`` with ``both``).
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import sys
import time
from pathlib import Path
from typing import Any, Literal

import numpy as np

from .._atomic import save_figure, write_text
from ..tracking import PAPER_IC, PAPER_PCA, PF_CONFIGS, pf_simulate_run, pf_study, plot_pf_run
from ..tracking._pf import OPTIONS

#: The study options as declared in the core: name -> (kind, default, doc, choices).
_STUDY = {o[0]: o[1:] for o in OPTIONS["study"]}

#: Flags whose default is the command's own, not the library's: more runs than
#: :func:`geofeas.tracking.pf_study`'s quick default, and the two options set by ``--config``.
CLI_DEFAULTS = {"runs": 16, "association": None, "smoothing": None}


def _option(p: argparse.ArgumentParser, name: str, **kw: Any) -> None:
    """Adds ``--name`` for the study option ``name``: its choices, its default (unless the
    command has its own, :data:`CLI_DEFAULTS`) and its doc with the default."""
    kind, default, doc, choices = _STUDY[name]
    default = CLI_DEFAULTS.get(name, default)
    if choices:
        kw.setdefault("choices", list(choices))
    else:
        kw.setdefault("type", {"int": int, "float": float}.get(kind, str))
    shown = "" if default is None else f" ({default})"
    p.add_argument(
        f"--{name.replace('_', '-')}", default=default, help=kw.pop("help", doc + shown), **kw
    )


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


def write_csvs(results: list[tuple[str, dict[str, Any]]], out: Path) -> None:
    """Writes the four CSVs; ``results`` is ``[(config, pf_study result), ...]``."""
    pca: list[list[Any]] = []
    errors: list[list[Any]] = []
    summary: list[list[Any]] = []
    ic: list[list[Any]] = []
    for cfg, res in results:
        n = len(res["method"])
        n_ic = res["_n_ic"]
        snr_rows = list(range(n - n_ic))
        pca += [
            [cfg, int(res["method"][k]), f"{res['snr_db'][k]:g}"] + _with_ci(res, k, ("pca",))
            for k in snr_rows
        ]
        errors += [
            [cfg, int(res["method"][k]), f"{res['snr_db'][k]:g}", i + 1, _fmt(v)]
            for k in snr_rows
            if float(res["snr_db"][k]) in ERROR_SNRS
            for i, v in enumerate(res["filter_rmse_px"][k])
        ]
        summary += [
            [cfg, int(res["method"][k])]
            + [f"{res[c][k]:g}" for c in ("snr_db", "xmax", "vmax")]
            + [int(res["_runs"])]
            + _with_ci(res, k, METRICS)
            + [_fmt(float(res[c][k])) for c in BANK_METRICS]
            for k in range(n)
        ]
        ic += [
            [cfg, f"{res['xmax'][k]:g}", f"{res['vmax'][k]:g}"]
            + _with_ci(res, k, ("rmse_px", "held", "pca"))
            for k in range(n - n_ic, n)
        ]
    _csv(out / "pca_vs_snr.csv", ["config", "method", "snr_db"] + _ci_header(("pca",)), pca)
    _csv(out / "errors.csv", ["config", "method", "snr_db", "filter", "rmse_px"], errors)
    _csv(
        out / "summary.csv",
        ["config", "method", "snr_db", "xmax", "vmax", "runs"]
        + _ci_header(METRICS)
        + list(BANK_METRICS),
        summary,
    )
    _csv(
        out / "ic_sensitivity.csv",
        ["config", "xmax", "vmax"] + _ci_header(("rmse_px", "held", "pca")),
        ic,
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
    for snr in TABLE_SNRS:
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

    for snr in TABLE_SNRS:
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


#: Metrics of the side-by-side table: (key, method, label).
SIDE_BY_SIDE = (
    ("pca", 2, "PCA, Method 2"),
    ("pca", 1, "PCA, Method 1"),
    ("hit", 2, "hit, Method 2"),
    ("hit", 1, "hit, Method 1"),
    ("rmse_px", 2, "RMSE [px], Method 2"),
    ("rmse_px", 1, "RMSE [px], Method 1"),
    ("held", 1, "held, Method 1"),
)

#: SNRs of the tables, dB.
TABLE_SNRS = (0.0, 2.0, 6.0, 9.0, 12.0, 15.0, 20.0)


def side_by_side_markdown(results: list[tuple[str, dict[str, Any]]]) -> str:
    """The paper's figures beside the first two configurations of ``results``, with whether
    their 95 % intervals are disjoint (``apart``)."""
    (name_a, a), (name_b, b) = results[0], results[1]
    lines = [
        f"Configurations side by side ({name_a} / {name_b}; value [95 % percentile-bootstrap "
        "interval over runs]; *apart*: the two intervals are disjoint):\n",
        f"| metric | SNR [dB] | the paper | `{name_a}` | `{name_b}` | apart |",
        "|---|---|---|---|---|---|",
    ]
    for key, method, label in SIDE_BY_SIDE:
        for snr in TABLE_SNRS:
            try:
                ka, kb = _row(a, method, snr), _row(b, method, snr)
            except KeyError:
                continue
            paper = PAPER_PCA.get(snr) if (key, method) == ("pca", 2) else None
            lo_a, hi_a = float(a[f"{key}_lo"][ka]), float(a[f"{key}_hi"][ka])
            lo_b, hi_b = float(b[f"{key}_lo"][kb]), float(b[f"{key}_hi"][kb])
            apart = "yes" if hi_a < lo_b or hi_b < lo_a else "no"
            lines.append(
                f"| {label} | {snr:g} | {'%.0f%%' % (100 * paper) if paper is not None else '-'} "
                f"| {_interval(a, ka, key)} | {_interval(b, kb, key)} | {apart} |"
            )
    return "\n".join(lines) + "\n"


def plot_study(results: list[tuple[str, dict[str, Any]]], out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, ax_hit) = plt.subplots(1, 2, figsize=(11, 4), sharey=True)
    fig_rmse, ax_rmse = plt.subplots(figsize=(6, 4))
    for c, (cfg, res) in enumerate(results):
        m = len(res["method"]) - res["_n_ic"]
        method = np.asarray(res["method"][:m])
        snr = np.asarray(res["snr_db"][:m])
        for k, marker in ((1, "s"), (2, "o")):
            sel = method == k
            style = marker + ("-" if c == 0 else "--")
            color = f"C{2 * c + k - 1}"
            label = f"Method {k}, {cfg}"
            for a, key in ((ax, "pca"), (ax_hit, "hit")):
                v = 100 * np.asarray(res[key][:m])[sel]
                lo = 100 * np.asarray(res[f"{key}_lo"][:m])[sel]
                hi = 100 * np.asarray(res[f"{key}_hi"][:m])[sel]
                a.plot(snr[sel], v, style, color=color, ms=4, label=label)
                a.fill_between(snr[sel], lo, hi, color=color, alpha=0.2)
            ax_rmse.semilogy(
                snr[sel], np.asarray(res["rmse_px"][:m])[sel], style, color=color, label=label
            )
    ax.plot(list(PAPER_PCA), [100 * v for v in PAPER_PCA.values()], "k^", label="paper, Method 2")
    ax.set_title("PCA: nearest target labels the peak (Fig. 19)")
    ax_hit.set_title("hit: the peak is also within 3 px of the target")
    for a in (ax, ax_hit):
        a.set_xlabel("SNR [dB]")
        a.set_ylim(0, 105)
        a.grid(alpha=0.3)
    ax.set_ylabel("probability of correct association [%]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, out / "fig19_pca_vs_snr.png", dpi=110)
    plt.close(fig)

    ax_rmse.set_xlabel("SNR [dB]")
    ax_rmse.set_ylabel("position RMSE [px]")
    ax_rmse.grid(alpha=0.3, which="both")
    ax_rmse.legend(fontsize=8)
    ax_rmse.set_title("Position RMSE over 10 s and four targets")
    fig_rmse.tight_layout()
    save_figure(fig_rmse, out / "rmse_vs_snr.png", dpi=110)
    plt.close(fig_rmse)

    cfg, res = results[0]
    m = len(res["method"]) - res["_n_ic"]
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
    ax1.set_title(f"Method 2 initial-condition sensitivity (Fig. 20), {cfg}")
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


def _snr_list(text: str) -> list[float]:
    try:
        out = [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected numbers separated by commas, got {text!r}"
        ) from None
    if not out or not all(math.isfinite(v) for v in out):
        raise argparse.ArgumentTypeError(f"expected finite numbers, got {text!r}")
    return out


def _configs(args: argparse.Namespace) -> list[tuple[str, dict[str, Any]]]:
    """``[(label, {association, smoothing}), ...]`` of the configurations to run; an explicit
    ``--association`` / ``--smoothing`` that departs from the named configuration labels it
    ``custom``."""
    names = ["paper", "recommended"] if args.config == "both" else [args.config]
    overrides = {
        k: v
        for k, v in (("association", args.association), ("smoothing", args.smoothing))
        if v is not None
    }
    if overrides and len(names) > 1:
        raise ValueError(
            "--association / --smoothing change one configuration: "
            "give --config paper or --config recommended with them"
        )
    out = []
    for name in names:
        settings = {**PF_CONFIGS[name], **overrides}
        out.append((name if settings == PF_CONFIGS[name] else "custom", settings))
    return out


def run(args: argparse.Namespace) -> int:
    try:
        configs = _configs(args)
    except ValueError as exc:
        print(f"geofeas pf-study: error: {exc}", file=sys.stderr)
        return 2
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    common = {"seed": args.seed, "truth": args.truth, "particles": args.particles}
    results: list[tuple[str, dict[str, Any]]] = []
    sections: list[str] = []
    for label, settings in configs:
        t0, c0 = time.perf_counter(), time.process_time()
        res = pf_study(
            runs=args.runs,
            ic=PAPER_IC,
            ic_snr=args.ic_snr,
            snrs=args.snrs,
            **common,
            **settings,
        )
        res["_n_ic"] = len(PAPER_IC)
        res["_runs"] = args.runs
        elapsed, cpu = time.perf_counter() - t0, time.process_time() - c0
        results.append((label, res))
        note = (
            f"{args.runs} runs per row, seed {args.seed}, {args.particles} particles per "
            f"filter, truth '{args.truth}', association '{settings['association']}', peak "
            f"smoothing {settings['smoothing']:g}, initial-condition rows at {args.ic_snr:g} dB"
        )
        sections.append(f"## Configuration `{label}`\n\n" + comparison_markdown(res, note))
        print(
            f"pf-study [{label}]: {len(res['method'])} rows x {args.runs} runs in "
            f"{elapsed:.1f} s ({cpu:.1f} s CPU)",
            file=sys.stderr,
        )
    write_csvs(results, out)
    if len(results) > 1:
        sections.insert(0, "## Side by side\n\n" + side_by_side_markdown(results))
    write_text(out / "comparison.md", "\n".join(sections))
    print(f"pf-study -> {out}", file=sys.stderr)
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
        plot_study(results, out)
        plot_frames(args.seed, out)
        first = {**common, **configs[0][1]}
        runs: tuple[tuple[Literal[1, 2], float], ...] = ((1, 15.0), (2, 15.0), (2, 6.0), (2, 2.0))
        for method, snr in runs:
            r = pf_simulate_run(
                snr_db=snr,
                method=method,
                snapshot_frames=[0, 25, 50, 75, 100],
                keep_frames=[100],
                **first,
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
    _option(p, "runs")
    _option(p, "seed")
    _option(p, "particles")
    p.add_argument(
        "--config",
        choices=["paper", "recommended", "both"],
        default="both",
        help="paper: the paper's filters, nearest association, raw-intensity peaks; "
        "recommended: the same with peaks after smoothing by the point spread (Sigma = 2 px); "
        "both (default): the two on the same runs, side by side",
    )
    _option(
        p,
        "association",
        help="peak-to-filter association, overriding the configuration's (nearest in both)",
    )
    _option(p, "truth")
    _option(
        p,
        "smoothing",
        help="Gaussian smoothing of the frame before peak extraction, px, overriding the "
        "configuration's (paper: 0, the raw frame; recommended: 2, the point spread's Sigma)",
    )
    _option(
        p,
        "snrs",
        type=_snr_list,
        help="comma-separated SNRs of the Method 1 / 2 rows, dB (0,1,...,20)",
    )
    _option(p, "ic_snr")
    p.add_argument("--no-figures", action="store_true", help="write the CSVs and markdown only")
    p.set_defaults(func=run)
