"""The demo pipeline on ten minutes of the Solent: its output files, and the calibrated
combination rule against the plain mean on the score column. In a file of its own (one
module-scoped run of the pipeline) so that a parallel test run balances it against the rest."""

import numpy as np
import pandas as pd
import pytest

import geofeas


@pytest.fixture(scope="module")
def short_demo():
    from geofeas.demo import run

    return run(
        "solent",
        minutes=10,
        scores=["glr", "overlap"],
        combines=["chi2", "geometric"],
        operator=(0, 10, 20),
        progress=False,
    )


def test_pipeline_outputs(short_demo, tmp_path):
    from geofeas.demo import write_outputs

    res = short_demo
    table = res.metrics_table()
    # the default (the engine's defaults) once, then each further score with the default rule,
    # each further rule with the default score
    assert list(zip(table["score"], table["combine"], strict=True)) == [
        ("glr", "chi2"),
        ("overlap", "chi2"),
        ("glr", "geometric"),
    ]
    written = write_outputs(res, tmp_path / "out")
    assert {p.name for p in written} >= {
        "reports.csv",
        "pairs.csv",
        "metrics.csv",
        "map.png",
        "calibration.csv",
        "calibration.png",
        "operator.csv",
        "operator.png",
    }
    cal = pd.read_csv(tmp_path / "out" / "calibration.csv")
    assert cal["n"].sum() == len(res.default.pairs)
    # the expected calibration error recomputed from the table
    ece = (cal["n"] * (cal["predicted"] - cal["observed"]).abs()).sum() / cal["n"].sum()
    assert ece == pytest.approx(res.ece, abs=1e-4)
    op = pd.read_csv(tmp_path / "out" / "operator.csv")
    # every checkpoint is recorded, in order, from no decision at all (the 10-minute picture has
    # more than 20 borderline pairs to answer)
    assert list(op["decisions"]) == [0, 10, 20]
    assert op["f1"].iloc[0] == pytest.approx(res.default.metrics.f1, abs=1e-4)
    # a truthful operator never makes the association worse
    assert (op["f1"].diff().fillna(0) >= -1e-9).all()
    assert (op["false_merges"].diff().fillna(0) <= 0).all()
    # the objects imply every match pair and the true pairs that are no candidate pair too
    assert op["object_f1"].iloc[0] == pytest.approx(res.default.metrics.object_f1, abs=1e-4)
    assert (op["object_recall"] >= op["recall"] - 1e-12).all()
    pairs = pd.read_csv(tmp_path / "out" / "pairs.csv")
    m = res.default.metrics
    assert int((pairs["true_pair"] & (pairs["class"] == "match")).sum()) == m.tp
    assert int(pairs["true_pair"].sum()) == m.true_pairs - m.true_not_candidates
    assert (tmp_path / "out" / "map.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # reports.csv is what `geofeas associate` reads, and it is the picture the demo associated,
    # to the bit: the same pairs, posteriors and classes (the sampler follows the same paths)
    again = geofeas.associate(geofeas.read_reports(tmp_path / "out" / "reports.csv"))
    key = ["track_a", "track_b"]
    mine = res.default.pairs.sort_values(key, ignore_index=True)
    theirs = again.pairs.sort_values(key, ignore_index=True)
    assert mine[key].astype(str).equals(theirs[key].astype(str))
    assert np.array_equal(mine["p_same"].to_numpy(), theirs["p_same"].to_numpy())
    assert list(mine["class"]) == list(theirs["class"])


def test_calibrated_rule_beats_the_plain_mean(short_demo):
    # the geometric mean of a long true pair drifts to 1/e, below the 0.5 borderline: on the
    # score column, true pairs rank above false ones far better with the calibrated rule
    from geofeas.demo.evaluate import labels

    def separation(run):
        y = labels(run.pairs, short_demo.tracks)
        s = run.pairs["score"].to_numpy()
        return float((s[y] >= 0.5).mean())

    runs = {(r.score, r.combine): r for r in short_demo.runs}
    assert separation(short_demo.default) > separation(runs[("glr", "geometric")]) + 0.3


@pytest.mark.parametrize("batch, recomputations", [(1, 12), (5, 3), (25, 1)])
def test_the_operator_recomputes_after_each_batch(short_demo, monkeypatch, batch, recomputations):
    """The simulated operator answers ``batch`` pairs from the head of the queue between two
    recomputations, and no more than the checkpoint needs: 12 decisions in batches of 5 are
    three recomputations (5, 5, 2)."""
    from geofeas.association import Association
    from geofeas.demo.evaluate import simulate_operator, track_table

    calls: list[int] = []
    real = Association.with_decisions

    def counted(self, decisions, *args, **kwargs):
        calls.append(len(decisions))
        return real(self, decisions, *args, **kwargs)

    monkeypatch.setattr(Association, "with_decisions", counted)
    sc = short_demo.scenario
    op = simulate_operator(
        short_demo.default.association,
        track_table(sc.reports, sc.seconds),
        checkpoints=(0, 12),
        batch=batch,
    )
    assert list(op["decisions"]) == [0, 12]
    assert len(calls) == recomputations
    assert calls[-1] == 12
    steps = np.diff([0, *calls])
    assert (steps[:-1] == batch).all() and 1 <= steps[-1] <= batch


def test_no_map_leaves_the_other_figures(short_demo, tmp_path):
    """``--no-map`` leaves out map.png alone: the reliability diagram and the operator's curve
    are still drawn; ``--no-figures`` draws none and writes the same tables."""
    from geofeas.demo import write_outputs

    no_map = {p.name for p in write_outputs(short_demo, tmp_path / "a", map_png=False)}
    assert {"calibration.png", "operator.png"} <= no_map and "map.png" not in no_map
    assert (tmp_path / "a" / "calibration.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    none = {p.name for p in write_outputs(short_demo, tmp_path / "b", figures=False)}
    assert not {n for n in none if n.endswith(".png")}
    assert none == {n for n in no_map if not n.endswith(".png")}
    assert not list((tmp_path / "b").glob("*.png"))
