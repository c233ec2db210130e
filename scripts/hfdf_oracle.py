"""What geometry can decide of HF DF fixes: an oracle's bound on the operator load.

    python scripts/hfdf_oracle.py [--recording solent] [--seeds 0,1,2,3]

For every real HF DF track of a simulated picture (``geofeas.demo.scenario.simulate``), an
oracle that knows every vessel's true path and the exact law of the fixes' errors gives the
posterior of each vessel being the emitter (``geofeas.demo.evaluate.emitter_posterior``),
judging each fix track alone: what a method that sees only the tracks can know beyond it comes
from the other fix tracks at overlapping times, by exclusion, which is little here. Its
candidate pairs with a vessel's tracks are a group: true with the oracle's probability ``q``.
The fewest borderline pairs that any triage can leave among the HF DF pairs while it loses at
most 1 % of the picture's true pairs to ``non-match`` in expectation is the bound of
``geofeas.demo.evaluate.borderline_bound`` (the whole 1 % budget given to HF DF, none to the
other pairs; ``oracle_borderline``, which ``geofeas demo`` prints). Printed per
seed, beside what ``geofeas.associate`` (defaults) does on the same picture, and, to compare the
two posteriors rather than the two triage rules, the oracle's groups classed by the defaults'
thresholds (0.01 and 0.99: borderline pairs, expected true pairs lost) and where each puts its
probability: summed over the real HF DF tracks, on the true vessel (the model's ``p_same`` of a
vessel is the largest over its tracks' pairs with the fix) and, for the model, on the vessels
the oracle excludes (``q = 0``: mostly vessels whose path is unknown at one of the fix times,
which the simulation never makes emitters).
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np
import pandas as pd

import geofeas
from geofeas.demo import bundled
from geofeas.demo.evaluate import borderline_bound, labels, oracle_groups, track_table, true_pairs
from geofeas.demo.scenario import simulate
from geofeas.io.ais import read_ais


def fixes_covered(res: geofeas.Association, sc: Any, tracks: pd.DataFrame) -> tuple[int, int, int]:
    """The fixes of the real HF DF tracks (all, at which the one track of the true vessel that
    covers most of them has a state, at which any of its tracks has one), by the time cover the
    association computed (a track has a state inside a chain of its reports)."""
    rep = sc.reports
    times = pd.Series(np.asarray(sc.seconds, dtype=np.float64), index=rep.index)
    fixes = {str(k): g.to_numpy() for k, g in times.groupby(rep["track_id"].astype(str))}
    cover = res._raw.time_cover
    offsets = np.asarray(cover.cover_offsets)
    start, end = np.asarray(cover.cover_start), np.asarray(cover.cover_end)
    index = {str(t): k for k, t in enumerate(res.reports.track_ids)}

    def covered(track: str, fix: np.ndarray) -> np.ndarray:
        k = index[track]
        s, e = start[offsets[k] : offsets[k + 1]], end[offsets[k] : offsets[k + 1]]
        return ((s[None, :] <= fix[:, None]) & (fix[:, None] <= e[None, :])).any(axis=1)

    src, mm = tracks["source"], tracks["mmsi"]
    total = best = union = 0
    for d in src.index[(src == "hfdf") & (mm >= 0)]:
        mates = src.index[(src != "hfdf") & (mm == mm[d])]
        fix = fixes[d]
        total += len(fix)
        if len(mates):
            cov = np.array([covered(m, fix) for m in mates])
            best += int(cov.sum(axis=1).max())
            union += int(cov.any(axis=0).sum())
    return total, best, union


def measure(recording: str, seed: int) -> dict[str, float]:
    rec = read_ais(bundled(recording))
    sc = simulate(rec, seed=seed)
    tracks = track_table(sc.reports, sc.seconds)
    truth = true_pairs(tracks)
    res = geofeas.associate(sc.reports)
    p = res.pairs
    a, b = p["track_a"].astype(str).to_numpy(), p["track_b"].astype(str).to_numpy()
    src = tracks["source"]
    df_a = src.loc[a].to_numpy() == "hfdf"
    df_b = src.loc[b].to_numpy() == "hfdf"
    df = df_a | df_b
    cls = p["class"].to_numpy()
    y = labels(p, tracks)
    n_true = len(truth)
    groups = oracle_groups(sc, rec, p, tracks)
    q, n = groups["q"].to_numpy(), groups["n"].to_numpy()
    bound = borderline_bound(q, n, 0.01 * n_true)
    # the model's probability per (fix track, vessel): the largest p_same of the vessel's tracks
    fix = np.where(df_a, a, b)
    partner = np.where(df_a, b, a)
    one = df_a ^ df_b
    mm = tracks["mmsi"]
    model = (
        pd.DataFrame(
            {
                "track_id": fix[one],
                "mmsi": mm.loc[partner[one]].to_numpy(),
                "p": p["p_same"].to_numpy()[one],
            }
        )
        .groupby(["track_id", "mmsi"])["p"]
        .max()
        .reset_index()
    )
    both = groups.merge(model, how="left", on=["track_id", "mmsi"])
    truth_mmsi = mm.loc[both["track_id"]].to_numpy()
    true_vessel = (both["mmsi"].to_numpy() == truth_mmsi) & (truth_mmsi >= 0)
    return dict(
        recording=recording,
        seed=seed,
        true_pairs=n_true,
        oracle_groups_above_1pc=int((groups["q"] > 0.01).sum()),
        oracle_bound=round(bound),
        oracle_load=round(bound / n_true, 2),
        model_borderline_hfdf=int(((cls == "borderline") & df).sum()),
        model_borderline_other=int(((cls == "borderline") & ~df).sum()),
        model_load=round(float((cls == "borderline").sum()) / n_true, 2),
        model_lost_hfdf=int(((cls == "non-match") & df & y).sum()),
        oracle_triage_expected_loss=round(float((q * n)[q < 0.01].sum()), 1),
        oracle_borderline_at_thresholds=int(n[(q > 0.01) & (q < 0.99)].sum()),
        oracle_loss_at_thresholds=round(float((q * n)[q <= 0.01].sum()), 1),
        oracle_true_vessel=round(float(q[true_vessel].sum()), 2),
        model_true_vessel=round(float(both["p"].to_numpy()[true_vessel].sum()), 2),
        model_on_excluded=round(float(both["p"].to_numpy()[q == 0].sum()), 2),
        model_on_vessels=round(float(both["p"].sum()), 2),
        **dict(
            zip(
                ("fixes", "fixes_best_track", "fixes_any_track"),
                fixes_covered(res, sc, tracks),
                strict=True,
            )
        ),
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--recording", default="solent")
    ap.add_argument("--seeds", default="0,1,2,3")
    args = ap.parse_args()
    rows = [measure(args.recording, int(s)) for s in args.seeds.split(",")]
    print(pd.DataFrame(rows).to_string(index=False))


if __name__ == "__main__":
    main()
