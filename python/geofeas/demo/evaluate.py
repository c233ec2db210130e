"""Scoring an association against the ground truth of a simulated scenario.

A *true pair* is two tracks of one vessel (same MMSI, not a false track) from different sources
whose time spans ``[first report, last report]`` overlap, i.e. that exist at a common time. The
*predicted pairs* are the candidate pairs an association classed ``"match"``. Precision, recall
and F1 are over unordered pairs of track ids; pairs of one source are never true pairs and are
counted apart (``same_source_matches``), as are pairs implied by the grouping into objects.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from .._core import GeofeasError
from ..geodesy import delta_lon

__all__ = [
    "Metrics",
    "borderline_bound",
    "emitter_posterior",
    "evaluate",
    "labels",
    "oracle_borderline",
    "oracle_groups",
    "prf",
    "reliability",
    "simulate_operator",
    "track_table",
    "true_pairs",
]

CLASSES = ("match", "borderline", "non-match")


def track_table(reports: pd.DataFrame, seconds: Any = None) -> pd.DataFrame:
    """One row per track: ``track_id`` (index), ``source``, ``mmsi``, ``start``, ``end``.

    ``seconds`` are the report times in seconds (default: ``reports["time"]``, parsed when it
    holds ISO-8601 strings). A track whose reports disagree on the source or the MMSI is an error.
    """
    for col in ("track_id", "source", "mmsi"):
        if col not in reports:
            raise GeofeasError(f"reports: missing column {col!r}")
    if seconds is None:
        if "time" not in reports:
            raise GeofeasError("reports: missing column 'time'")
        seconds = _seconds(reports["time"])
    frame = pd.DataFrame(
        {
            "track_id": reports["track_id"].astype(str).to_numpy(),
            "source": reports["source"].astype(str).to_numpy(),
            "mmsi": pd.to_numeric(reports["mmsi"]).fillna(-1).astype(np.int64).to_numpy(),
            "t": np.asarray(seconds, dtype=np.float64),
        }
    )
    g = frame.groupby("track_id", sort=True)
    out = g.agg(
        source=("source", "first"), mmsi=("mmsi", "first"), start=("t", "min"), end=("t", "max")
    )
    bad = (g["source"].nunique() > 1) | (g["mmsi"].nunique() > 1)
    if bad.any():
        raise GeofeasError(f"track {bad[bad].index[0]!r} has reports of several sources or vessels")
    return out


def _seconds(time: pd.Series) -> np.ndarray:
    if pd.api.types.is_numeric_dtype(time):
        return time.to_numpy(np.float64)
    parsed = pd.to_datetime(time, format="ISO8601", utc=True)
    return ((parsed - pd.Timestamp("1970-01-01", tz="UTC")) / pd.Timedelta(seconds=1)).to_numpy(
        np.float64
    )


def true_pairs(tracks: pd.DataFrame) -> set[tuple[str, str]]:
    """The true duplicate-track pairs ``(a, b)`` with ``a < b`` of a :func:`track_table`."""
    out: set[tuple[str, str]] = set()
    real = tracks[tracks["mmsi"] >= 0]
    for _, grp in real.groupby("mmsi"):
        if len(grp) < 2:
            continue
        ids = grp.index.to_numpy()
        src = grp["source"].to_numpy()
        s, e = grp["start"].to_numpy(), grp["end"].to_numpy()
        i, j = np.triu_indices(len(grp), 1)
        ok = (src[i] != src[j]) & (s[i] <= e[j]) & (s[j] <= e[i])
        for a, b in zip(ids[i[ok]], ids[j[ok]], strict=True):
            out.add((a, b) if a < b else (b, a))
    return out


def prf(tp: int, n_pred: int, n_true: int) -> tuple[float, float, float]:
    """Precision, recall, F1. Precision is 1 with no prediction, recall is 1 with no true pair
    (nothing was claimed wrongly / missed), F1 their harmonic mean (0 if both are 0)."""
    p = tp / n_pred if n_pred else 1.0
    r = tp / n_true if n_true else 1.0
    f = 2 * p * r / (p + r) if p + r > 0 else 0.0
    return p, r, f


@dataclass
class Metrics:
    """Result of :func:`evaluate` (see the module doc for the definitions)."""

    true_pairs: int
    predicted: int
    tp: int
    fp: int
    fn: int
    precision: float
    recall: float
    f1: float
    classes: dict[str, int] = field(default_factory=dict)  # candidate pairs per triage class
    true_in_class: dict[str, int] = field(default_factory=dict)  # true pairs per class
    true_not_candidates: int = 0  # true pairs the association never scored
    fp_with_false_track: int = 0  # predicted pairs involving a false track
    same_source_matches: int = 0
    object_precision: float = math.nan  # pairs implied by the grouping into objects
    object_recall: float = math.nan
    object_f1: float = math.nan
    seconds: float = math.nan
    by_sources: pd.DataFrame | None = None

    def row(self) -> dict[str, Any]:
        """Flat dict (for a metrics table)."""
        d = asdict(self)
        d.pop("by_sources")
        for c in CLASSES:
            d[f"n_{c}"] = self.classes.get(c, 0)
            d[f"true_{c}"] = self.true_in_class.get(c, 0)
        d.pop("classes")
        d.pop("true_in_class")
        return d


def _key(a: Any, b: Any) -> tuple[str, str]:
    a, b = str(a), str(b)
    return (a, b) if a < b else (b, a)


def _object_pairs(objects: pd.DataFrame, tracks: pd.DataFrame) -> set[tuple[str, str]]:
    out: set[tuple[str, str]] = set()
    t = (
        objects[["track_id", "object"]]
        .assign(track_id=objects["track_id"].astype(str))
        .join(tracks, on="track_id", how="inner")
    )
    for _, grp in t.groupby("object"):
        if len(grp) < 2:
            continue
        ids = grp["track_id"].to_numpy()
        src = grp["source"].to_numpy()
        s, e = grp["start"].to_numpy(), grp["end"].to_numpy()
        i, j = np.triu_indices(len(grp), 1)
        ok = (src[i] != src[j]) & (s[i] <= e[j]) & (s[j] <= e[i])
        out.update(_key(a, b) for a, b in zip(ids[i[ok]], ids[j[ok]], strict=True))
    return out


def evaluate(
    tracks: pd.DataFrame,
    pairs: pd.DataFrame,
    /,
    *,
    objects: pd.DataFrame | None = None,
    seconds: float = math.nan,
) -> Metrics:
    """Precision, recall and F1 of the ``"match"`` pairs of an association.

    Parameters
    ----------
    tracks : pandas.DataFrame
        :func:`track_table` of the scenario's reports (the ground truth).
    pairs : pandas.DataFrame
        ``track_a, track_b, class`` (``Association.pairs``).
    objects : pandas.DataFrame, optional
        ``track_id, object`` (``Association.objects``): also scores the pairs implied by the
        grouping.
    seconds : float, optional
        Time the association took (reported as is).

    Returns
    -------
    Metrics
    """
    for col in ("track_a", "track_b", "class"):
        if col not in pairs:
            raise GeofeasError(f"pairs: missing column {col!r}")
    truth = true_pairs(tracks)
    a = pairs["track_a"].astype(str).to_numpy()
    b = pairs["track_b"].astype(str).to_numpy()
    cls = pairs["class"].astype(str).to_numpy()
    unknown = sorted(set(cls) - set(CLASSES))
    if unknown:
        raise GeofeasError(f"pairs: unknown class(es) {unknown}; expected {list(CLASSES)}")
    missing = sorted((set(a) | set(b)) - set(tracks.index))
    if missing:
        raise GeofeasError(f"pairs: track(s) not in the reports, e.g. {missing[0]!r}")
    src = tracks["source"]
    same = src.loc[a].to_numpy() == src.loc[b].to_numpy()
    keys = [_key(x, y) for x, y in zip(a, b, strict=True)]
    classes = {c: int(np.sum(cls == c)) for c in CLASSES}
    class_of: dict[tuple[str, str], str] = {}
    for k, c in zip(keys, cls, strict=True):
        class_of[k] = c
    true_in_class = {c: 0 for c in CLASSES}
    for k in truth:
        c = class_of.get(k)
        if c is not None:
            true_in_class[c] += 1
    pred = {k for k, c, s in zip(keys, cls, same, strict=True) if c == "match" and not s}
    same_matches = int(np.sum((cls == "match") & same))
    tp = len(pred & truth)
    p, r, f = prf(tp, len(pred), len(truth))
    mmsi = tracks["mmsi"]
    fp_false = sum(1 for x, y in pred - truth if mmsi[x] < 0 or mmsi[y] < 0)
    m = Metrics(
        true_pairs=len(truth),
        predicted=len(pred),
        tp=tp,
        fp=len(pred) - tp,
        fn=len(truth) - tp,
        precision=p,
        recall=r,
        f1=f,
        classes=classes,
        true_in_class=true_in_class,
        true_not_candidates=len(truth) - sum(true_in_class.values()),
        fp_with_false_track=fp_false,
        same_source_matches=same_matches,
        seconds=seconds,
        by_sources=_by_sources(tracks, truth, pred),
    )
    if objects is not None:
        for col in ("track_id", "object"):
            if col not in objects:
                raise GeofeasError(f"objects: missing column {col!r}")
        opred = _object_pairs(objects, tracks)
        m.object_precision, m.object_recall, m.object_f1 = prf(
            len(opred & truth), len(opred), len(truth)
        )
    return m


def _by_sources(
    tracks: pd.DataFrame, truth: Iterable[tuple[str, str]], pred: Iterable[tuple[str, str]]
) -> pd.DataFrame:
    src = tracks["source"]

    def pair(k: tuple[str, str]) -> str:
        return "-".join(sorted((src[k[0]], src[k[1]])))

    truth, pred = set(truth), set(pred)
    rows = []
    for name in sorted({pair(k) for k in truth | pred}):
        t = {k for k in truth if pair(k) == name}
        q = {k for k in pred if pair(k) == name}
        p, r, f = prf(len(t & q), len(q), len(t))
        rows.append(
            {
                "sources": name,
                "true_pairs": len(t),
                "predicted": len(q),
                "tp": len(t & q),
                "precision": p,
                "recall": r,
                "f1": f,
            }
        )
    return pd.DataFrame(
        rows, columns=["sources", "true_pairs", "predicted", "tp", "precision", "recall", "f1"]
    )


def labels(pairs: pd.DataFrame, tracks: pd.DataFrame) -> np.ndarray:
    """Whether each row of ``pairs`` (``track_a, track_b``) is a true duplicate-track pair."""
    truth = true_pairs(tracks)
    a = pairs["track_a"].astype(str).to_numpy()
    b = pairs["track_b"].astype(str).to_numpy()
    return np.array([_key(x, y) in truth for x, y in zip(a, b, strict=True)], dtype=bool)


def reliability(p: Any, y: Any, *, bins: int = 10) -> tuple[pd.DataFrame, float]:
    """The reliability diagram of predicted probabilities ``p`` against outcomes ``y``.

    Returns a table with one row per equal-width bin of ``p`` that holds pairs (``lo``, ``hi``,
    ``n``, ``predicted`` = mean ``p``, ``observed`` = frequency of ``y``, and the Wilson 95 %
    interval ``observed_lo``, ``observed_hi``), and the expected calibration error
    ``ECE = sum_b (n_b / N) |predicted_b - observed_b|``.
    """
    p = np.asarray(p, dtype=np.float64)
    y = np.asarray(y, dtype=bool)
    if p.shape != y.shape:
        raise GeofeasError(f"reliability: p has shape {p.shape}, y {y.shape}")
    if p.size and (np.isnan(p).any() or p.min() < 0 or p.max() > 1):
        raise GeofeasError("reliability: p must be probabilities in [0, 1]")
    edges = np.linspace(0.0, 1.0, bins + 1)
    idx = np.clip(np.searchsorted(edges, p, side="right") - 1, 0, bins - 1)
    rows = []
    ece = 0.0
    z = 1.959963984540054
    for k in range(bins):
        m = idx == k
        n = int(m.sum())
        if n == 0:
            continue
        pred, obs = float(p[m].mean()), float(y[m].mean())
        centre = (obs + z * z / (2 * n)) / (1 + z * z / n)
        half = z * math.sqrt(obs * (1 - obs) / n + z * z / (4 * n * n)) / (1 + z * z / n)
        rows.append(
            dict(
                lo=edges[k],
                hi=edges[k + 1],
                n=n,
                predicted=pred,
                observed=obs,
                # the Wilson interval holds the observed frequency; rounding must not put a
                # bound on the wrong side of it (at 0 or 1 both sides cancel exactly)
                observed_lo=min(obs, max(0.0, centre - half)),
                observed_hi=max(obs, min(1.0, centre + half)),
            )
        )
        ece += n / p.size * abs(pred - obs)
    cols = ["lo", "hi", "n", "predicted", "observed", "observed_lo", "observed_hi"]
    return pd.DataFrame(rows, columns=cols), float(ece)


def simulate_operator(
    association: Any,
    tracks: pd.DataFrame,
    /,
    *,
    checkpoints: Iterable[int] = (0, 25, 50, 100, 200),
    batch: int = 25,
) -> pd.DataFrame:
    """An operator who answers truthfully in review order, and what the association is worth
    after each number of decisions in ``checkpoints``.

    The operator takes up to ``batch`` pairs from the head of the current review queue, answers
    each from the ground truth (``same`` for a true duplicate-track pair, ``different``
    otherwise), and the association is recomputed under all the decisions so far
    (``Association.with_decisions`` of the latest result, which computes again only the
    components the new decisions change) before the next batch. A review station recomputes
    after every decision (``batch=1``); larger batches cost fewer recomputations, and answer
    the later pairs of a batch from a queue that does not know the earlier answers yet
    (Solent, seed 0: F1 0.968 after 100 decisions in batches of 25, 0.971 in batches of 5,
    ``docs/association.md``).

    Returns one row per checkpoint: ``decisions`` (made so far), ``precision``, ``recall`` and
    ``f1`` of the ``match`` pairs, ``borderline`` (pairs still to review), ``false_merges``
    and ``true_non_match`` (true pairs classed ``non-match``), and ``object_precision``,
    ``object_recall`` and ``object_f1`` of the pairs the association's objects imply (two
    tracks of one object from different sources at a common time; they include the true pairs
    that are no candidate pair, which the ``match`` pairs cannot hold).
    """
    truth = true_pairs(tracks)
    marks = sorted({int(c) for c in checkpoints})
    if not marks or marks[0] < 0:
        raise GeofeasError("checkpoints: expected non-negative decision counts")
    if batch < 1:
        raise GeofeasError(f"batch: must be >= 1, got {batch}")
    rows = []
    decided: list[dict[str, Any]] = []
    seen: set[tuple[str, str]] = set()
    current = association

    def record() -> None:
        pairs = current.pairs
        y = labels(pairs, tracks)
        cls = pairs["class"].to_numpy()
        match = cls == "match"
        tp = int((match & y).sum())
        prec, rec, f1 = prf(tp, int(match.sum()), len(truth))
        implied = _object_pairs(current.objects, tracks)
        o_prec, o_rec, o_f1 = prf(len(implied & truth), len(implied), len(truth))
        rows.append(
            dict(
                decisions=len(decided),
                precision=prec,
                recall=rec,
                f1=f1,
                borderline=int((cls == "borderline").sum()),
                false_merges=int((match & ~y).sum()),
                true_non_match=int(((cls == "non-match") & y).sum()),
                object_precision=o_prec,
                object_recall=o_rec,
                object_f1=o_f1,
            )
        )

    for mark in marks:
        while len(decided) < mark:
            queue = current.review_queue
            take = []
            for a, b in zip(queue["track_a"], queue["track_b"], strict=True):
                k = _key(a, b)
                if k in seen:
                    continue
                take.append((a, b, k))
                if len(take) >= min(batch, mark - len(decided)):
                    break
            if not take:
                break
            for a, b, k in take:
                seen.add(k)
                decided.append(
                    dict(
                        track_a=a,
                        track_b=b,
                        decision="same" if k in truth else "different",
                        operator="simulated",
                    )
                )
            current = current.with_decisions(pd.DataFrame(decided))
        if len(decided) < mark and rows and rows[-1]["decisions"] == len(decided):
            continue  # the queue ran dry: nothing new to record
        record()
    return pd.DataFrame(rows)


def emitter_posterior(scenario: Any, recording: Any, *, source: str = "hfdf") -> pd.DataFrame:
    """What an oracle knows of which vessel emitted each real track of ``source``.

    The oracle knows every vessel's true path (the recording, as :func:`~.scenario.simulate`
    reads it), that the track is real, and the exact law of its errors: each report is the
    vessel's position plus an independent draw from the Gaussian of the report's own AOU, as
    the simulated HF DF fixes are. With the uniform prior over the vessels that the simulation
    draws its emitters from, the posterior of vessel ``v`` is proportional to
    ``prod_j N(x_j - v(t_j); 0, R_j)`` over the track's reports, among the vessels whose path
    is known at every report time. It judges the track alone. Given the true paths, the other
    tracks' errors are independent of which vessel emitted it, so they add nothing, except by
    exclusion: a track of the same source at overlapping times that is known to be vessel
    ``v`` rules ``v`` out (one emitter, one track at a time). For the HF DF fixes, of a tenth
    of the vessels, that is little; for the patrol aircraft's tracks over a berth it is not,
    and there the model can leave fewer borderline pairs than this oracle
    (``docs/association.md``, "Calibration and the operator").

    Returns one row per (track, vessel) with posterior ``q > 1e-12``: ``track_id``, ``mmsi``,
    ``q``, and ``reports`` (the track's number of reports).
    """
    from .scenario import Truth, covariance_from_aou, metres_per_degree

    reports = scenario.reports
    seconds = np.asarray(scenario.seconds, dtype=np.float64)
    mask = (reports["source"] == source).to_numpy() & (reports["mmsi"].to_numpy() >= 0)
    truth = Truth.from_recording(recording)
    rows: list[dict[str, Any]] = []
    sub, sub_seconds = reports[mask], seconds[mask]
    for tid, idx in sub.groupby("track_id", sort=True).indices.items():
        g = sub.iloc[idx]
        t = sub_seconds[idx]
        lat, lon = g["lat"].to_numpy(np.float64), g["lon"].to_numpy(np.float64)
        inv = np.linalg.inv(
            covariance_from_aou(g["rx"].to_numpy(), g["ry"].to_numpy(), g["bearing"].to_numpy())
        )
        m_lat, m_lon = metres_per_degree(lat)
        ll = np.full(len(truth), -np.inf)
        for k in range(len(truth)):
            v_lat, v_lon, known = truth.vessel(k, t)
            if not known.all():
                continue
            d = np.stack([delta_lon(lon, v_lon) * m_lon, (lat - v_lat) * m_lat], axis=-1)
            ll[k] = -0.5 * np.einsum("ni,nij,nj->", d, inv, d)
        if not np.isfinite(ll).any():
            continue
        q = np.exp(ll - ll.max())
        q /= q.sum()
        for k in np.flatnonzero(q > 1e-12):
            rows.append(
                dict(track_id=tid, mmsi=int(truth.mmsi[k]), q=float(q[k]), reports=len(idx))
            )
    return pd.DataFrame(rows, columns=["track_id", "mmsi", "q", "reports"])


def borderline_bound(q: Any, n: Any, budget: float, *, p_match: float = 0.99) -> float:
    """The fewest borderline pairs a triage can leave among groups of pairs, each group true
    with probability ``q`` (the oracle's) and holding ``n`` pairs, while the expected number of
    true pairs it classes ``non-match`` stays within ``budget``.

    A group may be sent to ``non-match`` at an expected cost of ``q n`` true pairs lost, or kept
    (``borderline``, ``n`` pairs; groups with ``q >= p_match`` may be merged instead and cost
    nothing here). The bound is the fractional relaxation of that knapsack, solved exactly by
    sending the least probable groups to ``non-match`` first: if ``q`` is all there is to know,
    no triage, however it is made, can leave fewer borderline pairs in expectation.
    """
    q = np.asarray(q, dtype=np.float64)
    n = np.asarray(n, dtype=np.float64)
    if q.shape != n.shape or q.ndim != 1:
        raise GeofeasError(f"borderline_bound: q has shape {q.shape}, n {n.shape}")
    if q.size and (np.isnan(q).any() or q.min() < 0 or q.max() > 1):
        raise GeofeasError("borderline_bound: q must be probabilities in [0, 1]")
    if n.size and (np.isnan(n).any() or n.min() < 0):
        raise GeofeasError("borderline_bound: n must be non-negative counts")
    if not budget >= 0:
        raise GeofeasError(f"borderline_bound: budget must be >= 0, got {budget}")
    keep = q < p_match
    q, n = q[keep], n[keep]
    order = np.argsort(q, kind="stable")
    left = float(budget)
    kept = float(n.sum())
    for i in order:
        cost = q[i] * n[i]
        if cost <= left:
            left -= cost
            kept -= n[i]
        else:
            if q[i] > 0:
                kept -= left / q[i]
            break
    return kept


def oracle_groups(
    scenario: Any,
    recording: Any,
    pairs: pd.DataFrame,
    tracks: pd.DataFrame,
    *,
    source: str = "hfdf",
) -> pd.DataFrame:
    """The candidate pairs of each real track of ``source`` with one vessel's tracks, as groups:
    ``track_id``, ``mmsi``, ``n`` (pairs) and ``q``, the oracle's probability that the vessel
    emitted the track (:func:`emitter_posterior`; 0 where it gives none). ``tracks`` is the
    :func:`track_table` of the scenario's reports."""
    a = pairs["track_a"].astype(str).to_numpy()
    b = pairs["track_b"].astype(str).to_numpy()
    src, mmsi = tracks["source"], tracks["mmsi"]
    in_a = src.loc[a].to_numpy() == source
    in_b = src.loc[b].to_numpy() == source
    one = in_a ^ in_b
    fix = np.where(in_a, a, b)[one]
    partner = np.where(in_a, b, a)[one]
    pm = mmsi.loc[partner].to_numpy()
    real = (mmsi.loc[fix].to_numpy() >= 0) & (pm >= 0)
    groups = (
        pd.DataFrame({"track_id": fix[real], "mmsi": pm[real]})
        .groupby(["track_id", "mmsi"])
        .size()
        .rename("n")
        .reset_index()
    )
    oracle = emitter_posterior(scenario, recording, source=source)
    groups = groups.merge(oracle[["track_id", "mmsi", "q"]], how="left", on=["track_id", "mmsi"])
    groups["q"] = groups["q"].fillna(0.0)
    return groups


def oracle_borderline(
    scenario: Any,
    recording: Any,
    pairs: pd.DataFrame,
    tracks: pd.DataFrame,
    *,
    source: str = "hfdf",
    lost: float = 0.01,
) -> float:
    """The fewest borderline pairs of ``source``'s tracks that any triage of ``pairs`` can leave
    while it loses at most ``lost`` of the picture's true pairs to ``non-match`` in expectation
    (``docs/association.md``, "Calibration and the operator").

    The groups of :func:`oracle_groups` get the whole budget, the other pairs none
    (:func:`borderline_bound`). 0 when ``source`` has no real track.
    """
    groups = oracle_groups(scenario, recording, pairs, tracks, source=source)
    return borderline_bound(
        groups["q"].to_numpy(), groups["n"].to_numpy(), lost * len(true_pairs(tracks))
    )
