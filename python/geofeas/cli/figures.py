"""``geofeas figures``: reproduce Figs. 2-6 of seed 000 (Coates et al., "Recognized Maritime
Picture: Geofeasibility Scores") with this implementation.

Writes ``fig2.png`` ... ``fig6.png``, ``figures.csv`` (every plotted number: figure, series, x, y,
spread) and ``summary.json`` (the numbers the paper states in words, measured here) into
``--out``. The exact overlap replaces the paper's "true value" everywhere and is added as a
series where it belongs; the randomised quasi-Monte-Carlo sampler (``sampler="sobol"``) and the
uniform sampler are added beside eq. 55. Needs matplotlib (``pip install 'geofeas[plot]'``)
unless ``--csv-only`` is given.
"""

from __future__ import annotations

import argparse
import csv
import json
import time
from pathlib import Path
from typing import Any

import numpy as np

from .._atomic import atomic_open, save_figure
from .._core import GeofeasError
from ..scores import gaussian_product, glr, intersection_area, monte_carlo, overlap

#: Samples of each sampler in the accuracy figures: the paper's N = 500 for eq. 55 and for the
#: uniform sampler, 64 quasi-random points for the Sobol sampler.
SAMPLES = {"importance": 500, "uniform": 500, "sobol": 64}


def _pyplot() -> Any:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:  # pragma: no cover - depends on the environment
        raise GeofeasError(
            "geofeas figures needs matplotlib to draw the figures: pip install 'geofeas[plot]' "
            "(or pass --csv-only)"
        ) from None
    return plt


def circle_pair(d: float, r: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Two circles of 2-sigma radius ``r`` whose centres are ``d`` apart (the paper's Fig. 2
    scenario)."""
    return np.array([0.0, 0.0, r, r, 0.0]), np.array([d, 0.0, r, r, 0.0])


def distance_for_overlap(g: float, r: float = 1.0) -> float:
    """Centre distance of two equal circles whose normalised overlap is ``g`` (bisection on the
    exact overlap, which decreases with the distance)."""
    lo, hi = 0.0, 2.0 * r
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        a, b = circle_pair(mid, r)
        if overlap(a, b) > g:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def trials(
    a: np.ndarray, b: np.ndarray, n: int, samples: int, sampler: str, seed: int
) -> np.ndarray:
    """``n`` independent Monte-Carlo estimates of one pair (pair ``k`` of a call uses stream
    ``k``, so one call gives ``n`` independent trials)."""
    return np.asarray(
        monte_carlo(
            np.tile(a, (n, 1)), np.tile(b, (n, 1)), samples=samples, seed=seed, sampler=sampler
        )
    )


def random_pairs(n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Random pairs for Fig. 6: sizes, aspect ratios, orientations and centre distances varying
    from nested to disjoint."""
    a = np.empty((n, 5))
    b = np.empty((n, 5))
    for e in (a, b):
        e[:, 2] = rng.uniform(0.5, 3.0, n)
        e[:, 3] = e[:, 2] * rng.uniform(0.2, 1.0, n)
        e[:, 4] = rng.uniform(-np.pi, np.pi, n)
    a[:, :2] = rng.uniform(-1, 1, (n, 2))
    dist = rng.uniform(0, 1.2, n) * (a[:, 2] + b[:, 2])
    ang = rng.uniform(0, 2 * np.pi, n)
    b[:, 0] = a[:, 0] + dist * np.cos(ang)
    b[:, 1] = a[:, 1] + dist * np.sin(ang)
    return a, b


def _time(fn: Any, repeat: int = 3) -> float:
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return float(best)


def compute(
    n_trials: int, n_pairs: int, n_timing: int, seed: int, quick: bool = False
) -> tuple[list, dict]:
    """All plotted numbers as rows ``(figure, series, x, y, spread)`` and the summary; ``quick``
    shortens the N ranges of Figs. 3 and 5."""
    rows: list[tuple[int, str, float, float, float]] = []
    summary: dict[str, Any] = {
        "trials": n_trials,
        "pairs": n_pairs,
        "timing_evaluations": n_timing,
        "seed": seed,
    }

    # Fig. 2: estimate vs exact overlap of two circles, mean and sd over n_trials.
    for k, d in enumerate(np.linspace(0.0, 2.0, 21)):
        a, b = circle_pair(float(d))
        g = float(overlap(a, b))
        rows.append((2, "exact", g, g, 0.0))
        for sampler, n in SAMPLES.items():
            est = trials(a, b, n_trials, n, sampler, seed + k)
            rows.append((2, f"{sampler}_{n}", g, float(est.mean()), float(est.std(ddof=1))))

    # Fig. 4: relative MSE vs overlap.
    for k, g in enumerate(np.linspace(0.05, 0.95, 19)):
        a, b = circle_pair(distance_for_overlap(float(g)))
        truth = float(overlap(a, b))
        for sampler, n in SAMPLES.items():
            est = trials(a, b, n_trials, n, sampler, seed + 100 + k)
            mse = float(np.mean((est - truth) ** 2))
            rows.append((4, f"{sampler}_{n}", truth, mse / truth**2, mse))

    # Fig. 5: MSE (dB) vs N at overlap 0.391.
    a, b = circle_pair(distance_for_overlap(0.391))
    truth = float(overlap(a, b))
    summary["fig5_overlap"] = truth
    ns = [2**k for k in range(4, 11 if quick else 13)]
    slopes = {}
    for sampler in SAMPLES:
        mses = []
        for k, n in enumerate(ns):
            est = trials(a, b, n_trials, n, sampler, seed + 200 + k)
            mse = float(np.mean((est - truth) ** 2))
            mses.append(mse)
            rows.append((5, sampler, float(n), 10 * np.log10(mse), mse))
        # least-squares slope in dB per doubling of N
        slope = np.polyfit(np.log2(ns), 10 * np.log10(mses), 1)[0]
        slopes[sampler] = float(slope)
    summary["fig5_db_per_doubling"] = slopes
    imp500 = float(np.mean((trials(a, b, n_trials, 500, "importance", seed + 300) - truth) ** 2))
    sob64 = float(np.mean((trials(a, b, n_trials, 64, "sobol", seed + 301) - truth) ** 2))
    summary["fig5_rmse_importance_500"] = imp500**0.5
    summary["fig5_rmse_sobol_64"] = sob64**0.5

    # Fig. 3: time for n_timing evaluations vs N; GLR and exact for reference.
    rng = np.random.default_rng(seed)
    ta, tb = random_pairs(n_timing, rng)
    scale = 100_000 / n_timing
    repeat = 1 if quick else 3
    sweep = (100, 500, 1000) if quick else (100, 200, 300, 400, 500, 600, 700, 800, 900, 1000)
    for sampler in SAMPLES:
        for n in sweep:
            t = _time(
                lambda n=n, s=sampler: monte_carlo(ta, tb, samples=n, seed=1, sampler=s), repeat
            )
            rows.append((3, sampler, float(n), t * scale, 0.0))
    t_glr = _time(lambda: glr(ta, tb)) * scale
    t_exact = _time(lambda: overlap(ta, tb)) * scale
    t_poly = _time(lambda: overlap(ta, tb, method="polygon")) * scale
    t_mc500 = _time(lambda: monte_carlo(ta, tb, samples=500, seed=1)) * scale
    t_sob64 = _time(lambda: monte_carlo(ta, tb, samples=64, seed=1, sampler="sobol")) * scale
    for name, t in (("glr", t_glr), ("exact", t_exact), ("polygon_256", t_poly)):
        rows.append((3, name, 0.0, t, 0.0))
    summary["fig3_seconds_per_100k"] = {
        "importance_500": t_mc500,
        "sobol_64": t_sob64,
        "glr": t_glr,
        "exact": t_exact,
        "polygon_256": t_poly,
    }

    # Fig. 6: n_pairs random pairs sorted by the Monte-Carlo estimate (N = 1000).
    a6, b6 = random_pairs(n_pairs, np.random.default_rng(seed + 6))
    mc = np.asarray(monte_carlo(a6, b6, samples=1000, seed=seed + 7))
    ex = np.asarray(overlap(a6, b6))
    gl = np.asarray(glr(a6, b6))
    pr = np.asarray(gaussian_product(a6, b6))
    sob = np.asarray(monte_carlo(a6, b6, samples=64, seed=seed + 8, sampler="sobol"))
    order = np.lexsort((ex, mc))
    for rank, i in enumerate(order):
        for name, v in (
            ("monte_carlo_1000", mc),
            ("exact", ex),
            ("glr", gl),
            ("gaussian_product", pr),
            ("sobol_64", sob),
        ):
            rows.append((6, name, float(rank), float(v[i]), 0.0))
    low = (ex > 0) & (ex < 0.7)
    high = ex >= 0.7
    summary["fig6"] = {
        "glr_above_exact_in_0_0.7": float(np.mean(gl[low] > ex[low])),
        "glr_below_exact_in_0.7_1": float(np.mean(gl[high] < ex[high])),
        "glr_min_in_0.7_1": float(gl[high].min()) if high.any() else None,
        "glr_above_0.5_in_0.7_1": float(np.mean(gl[high] > 0.5)) if high.any() else None,
        "glr_max_where_disjoint": float(gl[ex == 0].max()) if (ex == 0).any() else None,
        "glr_min_where_nested": float(gl[ex == 1].min()) if (ex == 1).any() else None,
        "mean_abs_glr_minus_exact": float(np.mean(np.abs(gl - ex))),
        "mean_abs_product_minus_exact": float(np.mean(np.abs(pr - ex))),
        "mc1000_rmse_vs_exact": float(np.sqrt(np.mean((mc - ex) ** 2))),
        "sobol64_rmse_vs_exact": float(np.sqrt(np.mean((sob - ex) ** 2))),
        "pairs_disjoint": int(np.sum(ex == 0)),
        "pairs_nested": int(np.sum(ex == 1)),
    }
    # a check the CSV carries: the exact areas of the Fig. 2 circles are the circle lens
    summary["fig2_max_abs_exact_minus_lens"] = float(
        max(
            abs(
                float(intersection_area(*circle_pair(d)))
                - (2 * np.arccos(d / 2) - d / 2 * np.sqrt(4 - d * d))
            )
            for d in np.linspace(0.0, 2.0, 21)
        )
    )
    return rows, summary


def plot(rows: list, out: Path) -> list[Path]:
    plt = _pyplot()
    arr: dict[tuple[int, str], np.ndarray] = {}
    for fig, series, x, y, spread in rows:
        arr.setdefault((fig, series), []).append((x, y, spread))  # type: ignore[attr-defined]
    data = {k: np.array(v) for k, v in arr.items()}
    paths = []
    colours = {"importance": "C0", "uniform": "C2", "sobol": "C3"}

    fig, ax = plt.subplots(figsize=(6, 5))
    ex = data[(2, "exact")]
    ax.plot(ex[:, 0], ex[:, 1], "k-", label="exact (true value)")
    for j, (sampler, n) in enumerate(SAMPLES.items()):
        d = data[(2, f"{sampler}_{n}")]
        ax.errorbar(
            d[:, 0] + 0.006 * (j - 1),
            d[:, 1],
            yerr=d[:, 2],
            fmt="o",
            ms=3,
            capsize=2,
            color=colours[sampler],
            label=f"{sampler}, N = {n} (mean +- sd)",
        )
    ax.set(
        xlabel="exact relative overlap",
        ylabel="estimated relative overlap",
        title="Fig. 2: Monte-Carlo vs exact, two circles",
    )
    ax.legend(fontsize=8)
    paths.append(_save(fig, out / "fig2.png", plt))

    fig, ax = plt.subplots(figsize=(6, 5))
    for sampler in SAMPLES:
        d = data[(3, sampler)]
        ax.plot(d[:, 0], d[:, 1], "o-", color=colours[sampler], label=f"Monte-Carlo, {sampler}")
    for name, style in (("glr", "k--"), ("exact", "m-."), ("polygon_256", "y:")):
        t = data[(3, name)][0, 1]
        ax.axhline(t, linestyle=style[1:], color=style[0], label=f"{name} ({t:.3g} s)")
    ax.set(
        xlabel="number of samples N",
        ylabel="seconds for 100,000 evaluations",
        title="Fig. 3: computing time",
        yscale="log",
    )
    ax.legend(fontsize=8)
    paths.append(_save(fig, out / "fig3.png", plt))

    fig, ax = plt.subplots(figsize=(6, 5))
    for sampler, n in SAMPLES.items():
        d = data[(4, f"{sampler}_{n}")]
        ax.plot(d[:, 0], d[:, 1], "o-", color=colours[sampler], label=f"{sampler}, N = {n}")
    ax.set(
        xlabel="exact relative overlap",
        ylabel="relative MSE",
        yscale="log",
        title="Fig. 4: relative MSE vs overlap",
    )
    ax.legend(fontsize=8)
    paths.append(_save(fig, out / "fig4.png", plt))

    fig, ax = plt.subplots(figsize=(6, 5))
    for sampler in SAMPLES:
        d = data[(5, sampler)]
        ax.semilogx(d[:, 0], d[:, 1], "o-", color=colours[sampler], base=2, label=sampler)
    ax.set(
        xlabel="number of samples N",
        ylabel="MSE (dB)",
        title="Fig. 5: MSE vs N at relative overlap 0.391",
    )
    ax.legend(fontsize=8)
    paths.append(_save(fig, out / "fig5.png", plt))

    fig, ax = plt.subplots(figsize=(9, 5))
    for name, style, lw in (
        ("monte_carlo_1000", "C0", 2.5),
        ("exact", "k", 0.8),
        ("glr", "0.3", 0.6),
        ("gaussian_product", "r", 0.6),
    ):
        d = data[(6, name)]
        ax.plot(d[:, 0], d[:, 1], color=style, lw=lw, label=name)
    ax.axhline(0.5, color="g", lw=1.5, label="threshold 0.5")
    ax.set(
        xlabel="trial (sorted by the Monte-Carlo estimate)",
        ylabel="score",
        title="Fig. 6: scores of random ellipse pairs",
    )
    ax.legend(fontsize=8)
    paths.append(_save(fig, out / "fig6.png", plt))
    return paths


def _save(fig: Any, path: Path, plt: Any) -> Path:
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)
    return path


def run(args: argparse.Namespace) -> int:
    n_trials = 100 if args.quick else args.trials
    n_pairs = 1000 if args.quick else args.pairs
    n_timing = 10_000 if args.quick else args.timing
    for name, v in (("trials", n_trials), ("pairs", n_pairs), ("timing", n_timing)):
        if v < 2:
            raise GeofeasError(f"--{name} must be >= 2, got {v}")
    if not args.csv_only:
        _pyplot()  # fail before the work if matplotlib is missing
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    rows, summary = compute(n_trials, n_pairs, n_timing, args.seed, args.quick)
    with atomic_open(out / "figures.csv", "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(["figure", "series", "x", "y", "spread"])
        for fig, series, x, y, spread in rows:
            w.writerow([fig, series, repr(float(x)), repr(float(y)), repr(float(spread))])
    summary["seconds"] = time.perf_counter() - start
    with atomic_open(out / "summary.json", "w", encoding="utf-8") as fh:
        json.dump(summary, fh, indent=2)
    paths = [] if args.csv_only else plot(rows, out)
    print(
        f"wrote {out / 'figures.csv'}, {out / 'summary.json'}"
        + "".join(f", {p.name}" for p in paths)
        + f" in {summary['seconds']:.1f} s"
    )
    print(json.dumps(summary, indent=2))
    return 0


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "figures",
        help="reproduce Figs. 2-6 of the paper (PNG + figures.csv)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--out", "-o", required=True, help="output directory")
    p.add_argument(
        "--trials",
        type=int,
        default=1000,
        help="Monte-Carlo trials per point of Figs. 2, 4, 5 (default 1000)",
    )
    p.add_argument(
        "--pairs", type=int, default=10_000, help="random pairs of Fig. 6 (default 10000)"
    )
    p.add_argument(
        "--timing",
        type=int,
        default=100_000,
        help="evaluations timed per point of Fig. 3 (default 100000)",
    )
    p.add_argument("--seed", type=int, default=0, help="seed of every random choice")
    p.add_argument(
        "--quick",
        action="store_true",
        help="100 trials, 1000 pairs, 10000 timed evaluations, shorter N ranges (a smoke run)",
    )
    p.add_argument("--csv-only", action="store_true", help="write the CSV only, no PNGs")
    p.set_defaults(func=run)
