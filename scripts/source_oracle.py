"""One source's tracks judged alone by an oracle, against the association's triage of them.

    python scripts/source_oracle.py [--recording nyharbor] [--seed 1] [--source aircraft] \
        [--sensors ais,radar,aircraft,hfdf]

For every real track of ``--source`` in a simulated picture, the oracle of
``geofeas.demo.evaluate.emitter_posterior`` knows every vessel's true path and the exact law of
the track's errors (each report the vessel's position plus an independent draw from its AOU,
as the simulation draws the radar's, the aircraft's and the HF DF net's), and gives the
posterior of each vessel being the one the track follows. It judges each track alone: the
exclusion between tracks of one source at overlapping times, which the association's model
uses, is left out, so for a source whose tracks overlap over the same vessels (the patrol
aircraft over a berth) it is no lower bound. It shows the scale of what the geometry of one
track leaves open. Printed, over the candidate pairs of the source's tracks whose partner is
not an HF DF track: the pairs and true pairs, ``associate``'s classes of them (defaults), the
oracle's groups (a track with one vessel's tracks) classed by the same thresholds (borderline
pairs, expected true pairs lost) and the fewest borderline pairs a triage of the oracle's
groups leaves while it loses at most 1 % of the picture's true pairs
(``geofeas.demo.evaluate.borderline_bound``).
"""

from __future__ import annotations

import argparse

import geofeas
from geofeas.demo import bundled
from geofeas.demo.evaluate import (
    borderline_bound,
    labels,
    oracle_groups,
    track_table,
    true_pairs,
)
from geofeas.demo.scenario import simulate
from geofeas.io.ais import read_ais


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--recording", default="nyharbor")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--source", default="aircraft")
    ap.add_argument("--sensors", default="ais,radar,aircraft,hfdf")
    args = ap.parse_args()
    rec = read_ais(bundled(args.recording))
    sc = simulate(rec, seed=args.seed, sensors=tuple(args.sensors.split(",")))
    tracks = track_table(sc.reports, sc.seconds)
    n_true = len(true_pairs(tracks))
    pairs = geofeas.associate(sc.reports).pairs
    src = tracks["source"]
    sa = src.loc[pairs["track_a"].astype(str)].to_numpy()
    sb = src.loc[pairs["track_b"].astype(str)].to_numpy()
    keep = ((sa == args.source) ^ (sb == args.source)) & (sa != "hfdf") & (sb != "hfdf")
    sub = pairs[keep]
    y = labels(sub, tracks)
    cls = sub["class"].to_numpy()
    groups = oracle_groups(sc, rec, sub, tracks, source=args.source)
    q, n = groups["q"].to_numpy(), groups["n"].to_numpy()
    open_ = (q > 0.01) & (q < 0.99)
    best = groups.groupby("track_id")["q"].max()
    print(
        f"{args.recording} seed {args.seed} ({args.sensors}), {args.source} pairs whose partner "
        f"is not HF DF: {len(sub)} pairs, {int(y.sum())} true; the picture's true pairs {n_true}"
    )
    print(
        f"  associate: {(cls == 'match').sum()} match, {(cls == 'borderline').sum()} borderline "
        f"({int(((cls == 'borderline') & y).sum())} true), {(cls == 'non-match').sum()} "
        f"non-match ({int(((cls == 'non-match') & y).sum())} true)"
    )
    bound = borderline_bound(q, n, 0.01 * n_true)
    print(
        f"  oracle at 0.01 / 0.99: {int(n[open_].sum())} borderline pairs "
        f"({n[open_].sum() / n_true:.2f} per true pair), expected true pairs lost "
        f"{float((q * n)[q <= 0.01].sum()):.1f}; its 1 % bound {bound:.0f}"
    )
    print(
        f"  {args.source} tracks whose likeliest vessel the oracle gives less than 0.99: "
        f"{int((best < 0.99).sum())} of {len(best)}"
    )


if __name__ == "__main__":
    main()
