"""Calibration of the combination rules for simulated true track pairs (docs/association.md).

    python scripts/association_calibration.py [--out docs/img/association/calibration.png]

For k = 1..100 instants, 4000 simulated true pairs with consistent covariances: per instant the
squared Mahalanobis distance is chi-square with 2 degrees of freedom and the GLR is
``exp(-m / 2)``. Each panel shows the 5/25/50/75/95 % quantiles of one rule's track score against
k: the raw means drift (the geometric mean to 1/e, the minimum and harmonic mean to 0), the
chi-square p-value stays uniform and the default ``chi2`` score stays put with 0.5 at its
1.1 % quantile. The last two panels repeat the p-value with errors correlated in time (AR(1),
correlation time 20 s, an instant per second), without and with the effective number of
instants.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from geofeas import _core
from geofeas.association import DEFAULT_UPPER

RULES = ["geometric", "harmonic", "arithmetic", "min", "pvalue", "chi2"]
QUANTILES = [0.05, 0.25, 0.5, 0.75, 0.95]


def simulate(rng, k, n, tau=0.0):
    if tau <= 0:
        m = rng.chisquare(2, size=(n, k))
    else:
        a = math.exp(-1.0 / tau)
        e = np.empty((n, k, 2))
        e[:, 0] = rng.normal(size=(n, 2))
        for j in range(1, k):
            e[:, j] = a * e[:, j - 1] + math.sqrt(1 - a * a) * rng.normal(size=(n, 2))
        m = (e**2).sum(-1)
    g = np.exp(-0.5 * m).ravel()
    t = np.tile(np.arange(k, dtype=np.float64), n)
    off = np.arange(0, n * k + 1, k, dtype=np.uint64)
    return g, m.ravel(), t, off


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="docs/img/association/calibration.png")
    ap.add_argument("--pairs", type=int, default=4000)
    args = ap.parse_args()
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:  # pragma: no cover
        raise SystemExit("this script needs matplotlib: pip install matplotlib") from None
    rng = np.random.default_rng(0)
    ks = np.unique(np.round(np.logspace(0, 2, 16)).astype(int))
    q = {r: np.empty((len(ks), len(QUANTILES))) for r in RULES}
    qc = {name: np.empty((len(ks), len(QUANTILES))) for name in ("naive", "effective")}
    for i, k in enumerate(ks):
        g, m, t, off = simulate(rng, int(k), args.pairs)
        for r in RULES:
            q[r][i] = np.quantile(_core.combine_instants(g, m, t, off, r), QUANTILES)
        g, m, t, off = simulate(rng, int(k), args.pairs, tau=20.0)
        for name, tau in (("naive", 0.0), ("effective", 20.0)):
            s = _core.combine_instants(g, m, t, off, "pvalue", correlation_time=tau)
            qc[name][i] = np.quantile(s, QUANTILES)

    fig, axes = plt.subplots(2, 4, figsize=(15, 7), sharex=True, sharey=True)
    panels = [(r, q[r], f"{r}" + (" (default)" if r == "chi2" else "")) for r in RULES]
    panels += [
        ("naive", qc["naive"], "pvalue, correlated errors,\ninstants taken as independent"),
        ("effective", qc["effective"], "pvalue, correlated errors,\neffective instants (tau=20 s)"),
    ]
    for ax, (_, qq, title) in zip(axes.ravel(), panels, strict=True):
        ax.fill_between(ks, qq[:, 0], qq[:, 4], color="C0", alpha=0.2, label="5-95 %")
        ax.fill_between(ks, qq[:, 1], qq[:, 3], color="C0", alpha=0.4, label="25-75 %")
        ax.plot(ks, qq[:, 2], color="C0", lw=2, label="median")
        ax.axhline(0.5, color="C2", ls="--", lw=1, label="0.5 borderline")
        ax.axhline(math.exp(-1), color="C3", ls=":", lw=1, label="1/e")
        ax.axhline(DEFAULT_UPPER, color="C1", ls="-.", lw=1, label="match threshold")
        ax.set_xscale("log")
        ax.set_ylim(0, 1)
        ax.set_title(title, fontsize=10)
    for ax in axes[1]:
        ax.set_xlabel("instants k")
    for ax in axes[:, 0]:
        ax.set_ylabel("track-pair score, true pairs")
    axes[0, 0].legend(fontsize=8, loc="upper right")
    fig.suptitle(
        "Combination rules on simulated true pairs (consistent covariances): raw means drift "
        "with k, the chi-square rules do not",
        fontsize=11,
    )
    fig.tight_layout()
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
