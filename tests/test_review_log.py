"""The review station's decision log against a real SQLite file: append-only, undo as a
reversal, contradictions refused with the rows named (cross-checked against the engine),
conflicts between operators, concurrent writers, export read back by the engine."""

from __future__ import annotations

import csv
import itertools
import sqlite3
import threading

import numpy as np
import pandas as pd
import pytest
from review_picture import picture

import geofeas
from geofeas import GeofeasError
from geofeas.review.log import (
    Conflict,
    Contradiction,
    DecisionLog,
    TrackSpan,
    contradiction,
    spans_of,
)

SPANS = {
    "a1": TrackSpan("ais", 0, 100),
    "a2": TrackSpan("ais", 50, 150),  # overlaps a1: never one object with it
    "a3": TrackSpan("ais", 200, 300),
    "r1": TrackSpan("radar", 0, 300),
    "r2": TrackSpan("radar", 0, 300),
    "h1": TrackSpan("hfdf", 0, 300),
}


@pytest.fixture
def log(tmp_path):
    return DecisionLog(tmp_path / "d.sqlite", spans=SPANS)


def test_rows_are_never_updated_or_deleted(log):
    log.decide("ann", "a1", "r1", "same", p_same=0.6)
    con = sqlite3.connect(log.path)
    with pytest.raises(sqlite3.DatabaseError, match="append-only"):
        con.execute("UPDATE decisions SET action = 'different'")
    with pytest.raises(sqlite3.DatabaseError, match="append-only"):
        con.execute("DELETE FROM decisions")
    con.close()
    assert [e.action for e in log.entries()] == ["same"]


def test_each_row_keeps_operator_time_pair_decision_and_p_same(log):
    e = log.decide("ann", "r1", "a1", "same", p_same=0.625)
    (row,) = log.entries()
    assert row == e
    assert (row.operator, row.track_a, row.track_b, row.action, row.p_same) == (
        "ann",
        "a1",
        "r1",
        "same",
        0.625,
    )
    assert row.time.endswith("Z") and row.time[:4].isdigit()


def test_undo_appends_a_reversal(log):
    first = log.decide("ann", "a1", "r1", "same", p_same=0.6)
    log.decide("bob", "a3", "r2", "different", p_same=0.4)
    u = log.undo("ann")
    assert u.action == "undo" and u.reverses == first.seq and u.operator == "ann"
    assert [e.action for e in log.entries()] == ["same", "different", "undo"]
    assert [(e.track_a, e.track_b, e.action) for e in log.decisions()] == [
        ("a3", "r2", "different")
    ]
    # undone once: nothing of ann's left to undo, and the row cannot be undone twice
    with pytest.raises(GeofeasError, match="no decision to undo"):
        log.undo("ann")
    with pytest.raises(GeofeasError, match="not an active decision"):
        log.undo("bob", seq=first.seq)
    # after the undo the pair can be decided again
    log.decide("ann", "a1", "r1", "different", p_same=0.6)
    assert len(log.entries()) == 4


def test_contradictions_are_refused_with_the_rows_named(log):
    s1 = log.decide("ann", "a1", "r1", "same")
    s2 = log.decide("ann", "r1", "h1", "same")
    with pytest.raises(Contradiction) as info:
        log.decide("bob", "a1", "h1", "different")
    msg = str(info.value)
    assert f"#{s1.seq}" in msg and f"#{s2.seq}" in msg and "one object" in msg
    assert {e.seq for e in info.value.entries} == {s1.seq, s2.seq}
    # two AIS tracks at overlapping times joined through r1
    with pytest.raises(Contradiction, match="overlapping times"):
        log.decide("bob", "a2", "r1", "same")
    # a3 does not overlap a1: allowed
    log.decide("bob", "a3", "r1", "same")
    # a pair already decided must be undone first
    with pytest.raises(Contradiction, match="already decided"):
        log.decide("bob", "a1", "r1", "different")
    assert len(log.entries()) == 3


def test_a_decision_newer_than_the_page_is_a_conflict(log):
    seen = log.position()
    e = log.decide("ann", "a1", "r1", "same", seen=seen)
    with pytest.raises(Conflict) as info:
        log.decide("bob", "r1", "a1", "different", seen=seen)
    assert info.value.entry == e and "ann" in str(info.value)
    with pytest.raises(Conflict):
        log.decide("bob", "a1", "r1", "skip", seen=seen)
    with pytest.raises(Conflict):
        log.undo("bob", seq=e.seq, seen=seen)
    # decisions on other pairs are not conflicts
    log.decide("bob", "a3", "r2", "different", seen=seen)
    assert [x.operator for x in log.entries()] == ["ann", "bob"]


def test_bad_input_names_the_field(log):
    with pytest.raises(GeofeasError, match="track_b: unknown track id 'zz'"):
        log.decide("ann", "a1", "zz", "same")
    with pytest.raises(GeofeasError, match="decision: expected"):
        log.decide("ann", "a1", "r1", "maybe")
    with pytest.raises(GeofeasError, match="operator"):
        log.decide("", "a1", "r1", "same")
    with pytest.raises(GeofeasError, match="itself"):
        log.decide("ann", "a1", "a1", "same")
    with pytest.raises(GeofeasError, match="p_same"):
        log.decide("ann", "a1", "r1", "same", p_same=1.5)
    assert log.entries() == []


def test_not_a_decision_log(tmp_path):
    p = tmp_path / "x.sqlite"
    con = sqlite3.connect(p)
    con.execute("CREATE TABLE decisions (x INTEGER)")
    con.commit()
    con.close()
    with pytest.raises(GeofeasError, match="not a decision log.*track_a"):
        DecisionLog(p)
    q = tmp_path / "y.sqlite"
    q.write_bytes(b"not a database at all" * 100)
    with pytest.raises(GeofeasError, match="not a decision log"):
        DecisionLog(q)


def test_concurrent_writers_lose_nothing(tmp_path):
    path = tmp_path / "d.sqlite"
    spans = {f"t{k}": TrackSpan(f"s{k}", 0, 1) for k in range(40)}
    logs = [DecisionLog(path, spans=spans), DecisionLog(path, spans=spans)]
    pairs = [(f"t{i}", f"t{j}") for i, j in itertools.combinations(range(40), 2)][:120]
    barrier = threading.Barrier(2)
    errors: list[BaseException] = []

    def work(k: int) -> None:
        barrier.wait()
        try:
            for a, b in pairs[k::2]:
                logs[k].decide(f"op{k}", a, b, "skip")
        except BaseException as exc:  # pragma: no cover - reported below
            errors.append(exc)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    rows = logs[0].entries()
    assert len(rows) == len(pairs)
    assert sorted((e.track_a, e.track_b) for e in rows) == sorted(tuple(sorted(p)) for p in pairs)
    assert len({e.seq for e in rows}) == len(rows)


def test_two_operators_racing_on_one_pair(tmp_path):
    """Both saw the same page; both decide at once: one wins, the other gets a conflict."""
    path = tmp_path / "d.sqlite"
    for _ in range(10):
        if path.exists():
            path.unlink()
        logs = [DecisionLog(path, spans=SPANS), DecisionLog(path, spans=SPANS)]
        seen = logs[0].position()
        barrier = threading.Barrier(2)
        out: list[object] = [None, None]

        def work(k: int, logs=logs, seen=seen, barrier=barrier, out=out) -> None:
            barrier.wait()
            try:
                out[k] = logs[k].decide(f"op{k}", "a1", "r1", ("same", "different")[k], seen=seen)
            except Conflict as exc:
                out[k] = exc

        threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        kinds = sorted(type(x).__name__ for x in out)
        assert kinds == ["Conflict", "Entry"]
        assert len(logs[0].entries()) == 1


def test_export_is_what_the_engine_reads(tmp_path):
    frame = picture()
    reports = geofeas.read_reports(frame)
    log = DecisionLog(tmp_path / "d.sqlite", spans=spans_of(reports))
    log.decide("ann", "ais-alpha", "radar-1", "same", p_same=0.5)
    log.decide("ann", "ais-bravo", "radar-1", "different", p_same=0.5)
    log.decide("bob", "ais-charlie", "radar-2", "skip")
    log.decide("bob", "ais-bravo", "radar-2", "same")
    log.undo("bob")
    out = log.export(tmp_path / "decisions.csv")
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")] == []
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [(r["track_a"], r["track_b"], r["decision"], r["operator"]) for r in rows] == [
        ("ais-alpha", "radar-1", "same", "ann"),
        ("ais-bravo", "radar-1", "different", "ann"),
    ]
    dec = geofeas.read_decisions(out, reports)
    assert len(dec) == 2
    res = geofeas.associate(reports, decisions=out)
    p = res.pairs.set_index(["track_a", "track_b"])["p_same"]
    assert p[("ais-alpha", "radar-1")] == pytest.approx(1.0, abs=1e-12)
    assert p[("ais-bravo", "radar-1")] == pytest.approx(0.0, abs=1e-12)
    with pytest.raises(GeofeasError, match="csv"):
        log.export(tmp_path / "decisions.parquet")


def test_contradiction_rules_agree_with_the_engine(tmp_path):
    """Random sets of decisions on the test picture: the log refuses exactly the sets the
    engine refuses."""
    frame = picture()
    reports = geofeas.read_reports(frame)
    spans = spans_of(reports)
    ids = [str(t) for t in reports.track_ids]
    rng = np.random.default_rng(3)
    refused = accepted = 0
    for _ in range(60):
        n = int(rng.integers(1, 5))
        chosen = set()
        rows = []
        for _ in range(n):
            a, b = rng.choice(len(ids), 2, replace=False)
            key = tuple(sorted((ids[a], ids[b])))
            if key in chosen:
                continue
            chosen.add(key)
            rows.append((key[0], key[1], str(rng.choice(["same", "different"], p=[0.7, 0.3]))))
        entries = [
            geofeas.review.Entry(k + 1, "t", "x", a, b, d, None, None)
            for k, (a, b, d) in enumerate(rows)
        ]
        ours = contradiction(entries, spans)
        table = pd.DataFrame(rows, columns=["track_a", "track_b", "decision"])
        try:
            geofeas.associate(reports, decisions=table)
            engine_ok = True
        except GeofeasError:
            engine_ok = False
        assert (ours is None) == engine_ok, (rows, ours)
        refused += ours is not None
        accepted += ours is None
    assert refused >= 5 and accepted >= 5
