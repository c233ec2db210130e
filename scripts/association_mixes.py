"""The triage on other sensor mixes: what `geofeas.associate` (defaults) does when a picture is
seen by only some of the simulated sources.

    python scripts/association_mixes.py [--recording solent] [--seed 0] \
        [--mixes ais,radar ais,aircraft radar,aircraft ais,hfdf ...]

For each mix, the picture of ``geofeas.demo.scenario.simulate`` with those sensors only, and per
picture: the true duplicate-track pairs, automatic merges and the wrong ones, true pairs in
``non-match`` against the number the posterior predicts (the sum of ``p_same`` over the
``non-match`` pairs), borderline pairs per true pair (the operator load), the expected
calibration error and the log score (``sum ln p`` over the true pairs, ``ln (1 - p)`` over the
others, ``p`` clipped to ``[1e-6, 1 - 1e-6]``), and the largest standard error of the sampler.
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np
import pandas as pd

import geofeas
from geofeas.demo import bundled
from geofeas.demo.evaluate import labels, reliability, track_table, true_pairs
from geofeas.demo.scenario import simulate
from geofeas.io.ais import read_ais

MIXES = (
    "ais,radar",
    "ais,aircraft",
    "radar,aircraft",
    "ais,hfdf",
    "radar,hfdf",
    "aircraft,hfdf",
    "ais,radar,hfdf",
    "radar,aircraft,hfdf",
    "ais,radar,aircraft",
    "ais,radar,aircraft,hfdf",
)


def log_score(p: np.ndarray, y: np.ndarray) -> float:
    """``sum ln p`` over the true pairs and ``ln (1 - p)`` over the others, ``p`` clipped to
    ``[1e-6, 1 - 1e-6]``."""
    pc = np.clip(p, 1e-6, 1 - 1e-6)
    return float(np.where(y, np.log(pc), np.log(1 - pc)).sum())


def add_still_gap(ap: argparse.ArgumentParser) -> None:
    """The ``--max-still-gap`` flag of the scripts that measure the association."""
    ap.add_argument(
        "--max-still-gap",
        type=float,
        default=None,
        help="associate's max_still_gap (s; default the engine's; 0: the alignment before "
        "still tracks were bridged)",
    )


def still_gap(args: argparse.Namespace) -> dict[str, Any]:
    """The ``associate`` options of :func:`add_still_gap`'s flag (none: the engine's default)."""
    return {} if args.max_still_gap is None else {"max_still_gap": args.max_still_gap}


def mix_row(recording: str, seed: int, mix: str, **options: Any) -> dict[str, object]:
    """The measures of one mix (see the module docs); ``options`` go to ``associate``."""
    sc = simulate(read_ais(bundled(recording)), seed=seed, sensors=tuple(mix.split(",")))
    tracks = track_table(sc.reports)
    n_true = max(len(true_pairs(tracks)), 1)
    res = geofeas.associate(sc.reports, **options)
    pairs = res.pairs
    y = labels(pairs, tracks)
    cls = pairs["class"].to_numpy()
    p = pairs["p_same"].to_numpy()
    match, reject = cls == "match", cls == "non-match"
    return {
        "mix": mix,
        "true_pairs": n_true,
        "merges": int(match.sum()),
        "wrong": int((match & ~y).sum()),
        "lost": int((reject & y).sum()),
        "lost_predicted": round(float(p[reject].sum()), 1),
        "lost_pct": round(float(100.0 * (reject & y).sum() / n_true), 2),
        "load": round(float((cls == "borderline").sum()) / n_true, 2),
        "ece": round(reliability(p, y)[1], 4),
        "log_score": round(log_score(p, y), 1),
        "max_std_error": round(float(pairs["std_error"].max()), 3) if len(pairs) else 0.0,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--recording", default="solent", help="bundled recording (solent, nyharbor)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--mixes", nargs="+", default=list(MIXES), help="comma-separated sensors")
    add_still_gap(ap)
    args = ap.parse_args()
    options = still_gap(args)
    rows = []
    for mix in args.mixes:
        rows.append(mix_row(args.recording, args.seed, mix, **options))
        print(rows[-1], flush=True)
    table = pd.DataFrame(rows).astype(str)
    print(f"\n{args.recording}, seed {args.seed}\n")
    print("| " + " | ".join(table.columns) + " |")
    print("|" + "---|" * len(table.columns))
    for row in table.itertuples(index=False):
        print("| " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
