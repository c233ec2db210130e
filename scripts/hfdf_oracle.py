"""What geometry can decide of HF DF fixes: an oracle's bound on the operator load.

    python scripts/hfdf_oracle.py [--recording solent] [--seeds 0,1,2,3]

For every real HF DF track of a simulated picture (``geofeas.demo.scenario.simulate``), an
oracle that knows every vessel's true path and the exact law of the fixes' errors gives the
posterior of each vessel being the emitter (``geofeas.demo.evaluate.emitter_posterior``). No
method that sees only the tracks knows more. Its candidate pairs with a vessel's tracks are a
group: true with the oracle's probability ``q``. The fewest borderline pairs that any triage
can leave among the HF DF pairs while it loses at most 1 % of the picture's true pairs to
``non-match`` in expectation is the bound of ``geofeas.demo.evaluate.borderline_bound`` (the
whole 1 % budget given to HF DF, none to the other pairs; ``oracle_borderline``, which
``geofeas demo`` prints). Printed per
seed, beside what ``geofeas.associate`` (defaults) does on the same picture.
"""

from __future__ import annotations

import argparse

import pandas as pd

import geofeas
from geofeas.demo import bundled
from geofeas.demo.evaluate import borderline_bound, labels, oracle_groups, track_table, true_pairs
from geofeas.demo.scenario import simulate
from geofeas.io.ais import read_ais


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
    bound = borderline_bound(groups["q"].to_numpy(), groups["n"].to_numpy(), 0.01 * n_true)
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
        oracle_triage_expected_loss=round(
            float((groups["q"] * groups["n"])[groups["q"] < 0.01].sum()), 1
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
