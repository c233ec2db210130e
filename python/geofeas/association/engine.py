"""Track-to-track association: score every candidate track pair of the reports over its common
instants, triage the pairs and group duplicate tracks into objects.

The numerics (time alignment, geodesy, combination, the space-time index, the posterior) run in
the Rust core (``geofeas._core.associate``); this module calls it on validated
:class:`~.reports.Reports` with the resolved :mod:`.options` and turns its columns into the
:class:`Association` (pandas tables, saving and reloading, the recomputation under operator
decisions). See ``docs/association.md`` for the model.
"""

from __future__ import annotations

import os
import types
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _core
from .._atomic import atomic_path, atomic_paths
from .._core import GeofeasError
from .options import ASSOCIATION_DEFAULTS, _resolve_options
from .reports import Reports, _arg_error, _first, _pandas, read_reports

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

__all__ = [
    "Association",
    "associate",
    "combine_instants",
    "load_association",
    "write_table",
    "write_tables",
]

CLASSES = np.array(["match", "borderline", "non-match"], dtype=object)


class Association:
    """The result of :func:`associate`.

    Attributes
    ----------
    pairs : pandas.DataFrame
        One row per candidate pair with at least one common instant, sorted by
        ``(track_a, track_b)``: ``track_a``, ``track_b`` (the user's ids, ``track_a <
        track_b``), ``score`` (the combined per-instant score of seed 000, for continuity),
        ``instants``, ``class`` (``"match"``, ``"borderline"`` or ``"non-match"``, from
        ``p_same``), ``p_same`` (the posterior probability that the two tracks are one object),
        ``review_rank`` (1 = review first; missing for pairs that are not borderline), and the
        model's details: ``llr`` (the pair's log-likelihood ratio), ``std_error`` (of
        ``p_same``; 0 where computed exactly), ``review_gain`` (expected probability mass a
        decision settles), ``settles_same`` / ``settles_different`` (how many other pairs of
        the component each answer takes out of the borderline band) and ``component``.
    objects : pandas.DataFrame
        ``track_id``, ``object`` (one id per ship: the confident pairs joined), ``source`` and
        ``p_alone`` (the posterior probability that the track has no partner), one row per
        track.
    components : pandas.DataFrame
        Per connected component of the candidate graph: ``tracks``, ``method`` (``"exact"``
        or ``"sampled"``), ``partitions`` (enumerated; 0 when sampled), ``max_std_error`` and
        ``reused`` (taken unchanged from the association :meth:`with_decisions` was called on,
        not computed again).
    coverage : dict
        ``{source: P_s}``: the share of the picture's objects each source is estimated to hold.
    track_breaks : dict
        ``{source: g_s}``: the odds, estimated from the picture, that an object a source sees
        gets a further track of that source (a track break, another pass of an aircraft); an
        object holding several tracks of one source weighs them (``docs/association.md``).
    false_overlap : dict
        ``{source: rho_s}``: the share of a source's reports that fall in the cells of the
        most complete source, from how much wider its AOUs are; its false tracks are taken to
        be spread as its reports are, so where the objects are their density is ``rho_s``
        times the source's picture-wide rate (``docs/association.md``).
    reports : Reports
        The input.
    candidates : int
        Number of candidate pairs the space-time index returned (before dropping those without
        a common instant).
    inflation : dict
        ``{(source_a, source_b): c}``: the covariance inflation used for each pair of sources.
    options : dict
        The options used.
    """

    def __init__(
        self, reports: Reports, raw: _core.AssociationOutput, options: dict[str, Any]
    ) -> None:
        pd = _pandas()
        self.reports = reports
        self.options = options
        self._raw = raw
        #: The operator decisions the association was computed under (``Decisions``), if any.
        self.decisions: Any = None
        self.candidates = int(raw.candidates)
        a = np.asarray(raw.a, dtype=np.intp)
        b = np.asarray(raw.b, dtype=np.intp)
        self._a, self._b = a, b
        self._score = np.asarray(raw.score)
        ids = reports.track_ids
        rank = np.asarray(raw.review_rank, dtype=np.int64)
        component = np.asarray(raw.component, dtype=np.int64)
        self.pairs = pd.DataFrame(
            {
                "track_a": ids[a],
                "track_b": ids[b],
                "score": self._score,
                "instants": np.asarray(raw.instants, dtype=np.int64),
                "class": CLASSES[np.asarray(raw.pair_class, dtype=np.intp)],
                "p_same": np.asarray(raw.p_same, dtype=np.float64),
                "review_rank": pd.array(np.where(rank > 0, rank, 0), dtype="Int64"),
                "llr": np.asarray(raw.llr, dtype=np.float64),
                "std_error": np.asarray(raw.std_error, dtype=np.float64),
                "review_gain": np.asarray(raw.review_gain, dtype=np.float64),
                "settles_same": np.asarray(raw.settles_same, dtype=np.int64),
                "settles_different": np.asarray(raw.settles_different, dtype=np.int64),
                "component": pd.array(np.where(component < 2**32 - 1, component, 0), dtype="Int64"),
            }
        )
        self.pairs.loc[rank == 0, "review_rank"] = pd.NA
        self.pairs.loc[component >= 2**32 - 1, "component"] = pd.NA
        srcs = reports.sources
        self.inflation = {
            (srcs[int(a)], srcs[int(b)]): float(c)
            for a, b, c in zip(raw.inflation_a, raw.inflation_b, raw.inflation, strict=True)
        }
        self.coverage = {
            srcs[k]: float(p) for k, p in enumerate(np.asarray(raw.coverage)) if k < len(srcs)
        }
        self.track_breaks = {
            srcs[k]: float(g) for k, g in enumerate(np.asarray(raw.track_breaks)) if k < len(srcs)
        }
        self.false_overlap = {
            srcs[k]: float(x) for k, x in enumerate(np.asarray(raw.false_overlap)) if k < len(srcs)
        }
        obj = np.asarray(raw.object, dtype=np.int64)
        per_track_source = np.empty(reports.n_tracks, dtype=np.intp)
        per_track_source[reports.track] = reports.source
        self.objects = pd.DataFrame(
            {
                "track_id": ids,
                "object": obj,
                "source": reports.sources[per_track_source] if reports.n_tracks else [],
                "p_alone": np.asarray(raw.p_alone, dtype=np.float64),
            }
        )
        methods = np.array(["exact", "sampled"], dtype=object)
        self.components = pd.DataFrame(
            {
                "tracks": np.asarray(raw.component_tracks, dtype=np.int64),
                "method": methods[np.asarray(raw.component_method, dtype=np.intp)],
                "partitions": np.asarray(raw.component_partitions, dtype=np.int64),
                "max_std_error": np.asarray(raw.component_std_error, dtype=np.float64),
                "reused": np.asarray(raw.component_reused, dtype=bool),
            }
        )

    def __repr__(self) -> str:
        counts = self.pairs["class"].value_counts()
        parts = ", ".join(f"{int(counts.get(c, 0))} {c}" for c in CLASSES)
        objects = self.objects["object"].nunique()
        return f"Association({len(self.pairs)} pairs: {parts}; {objects} objects)"

    @property
    def matches(self) -> pd.DataFrame:
        """The pairs classed ``"match"``."""
        return self.pairs[self.pairs["class"] == "match"].reset_index(drop=True)

    @property
    def review_queue(self) -> pd.DataFrame:
        """The ``"borderline"`` pairs in review order (the pair whose decision is expected to
        settle the most probability mass first)."""
        q = self.pairs[self.pairs["class"] == "borderline"]
        return q.sort_values("review_rank").reset_index(drop=True)

    def with_decisions(self, decisions: Any) -> Association:
        """The association recomputed under operator ``decisions`` (a path, a DataFrame or a
        ``Decisions``; see :func:`geofeas.read_decisions`) without scoring the pairs again:
        the posterior, classes, review order and objects of every component follow the
        decisions, as :func:`associate` with ``decisions=`` would give them. The decisions
        replace this association's own (they are the whole set); only the components they
        change are computed, the others are taken from this association as they are (the
        ``reused`` column of :attr:`components`), so a review station calls it on its latest
        result and pays for the component of the new decision alone."""
        from .decisions import Decisions, read_decisions

        dec = (
            decisions
            if isinstance(decisions, Decisions)
            else read_decisions(decisions, self.reports)
        )
        raw = self._raw
        core, _ = _resolve_options(
            self.reports.sources,
            {k: v for k, v in self.options.items() if k in ASSOCIATION_DEFAULTS},
            {k: v for k, v in self.options.items() if k not in ASSOCIATION_DEFAULTS},
        )
        with dec.naming_rows():
            out = _core.association_finish(
                {
                    "source": raw.track_source,
                    "spread": raw.track_spread,
                    **_fields(raw.time_cover),
                },
                {"a": raw.a, "b": raw.b, "candidates": self.candidates, **_fields(raw.stats)},
                [_fields(raw.counts)],
                dec,
                geographic=self.reports.coords == "geographic",
                options=core,
                memo=raw.memo,
            )
        result = Association(self.reports, out, dict(self.options))
        result.decisions = dec
        return result

    def assignment(
        self, source_a: Any, source_b: Any, *, min_p: float | None = None
    ) -> pd.DataFrame:
        """One-to-one assignment between the tracks of two sources maximising the total
        posterior probability (Hungarian algorithm per connected component of the sparse
        candidate graph, in Rust).

        Parameters
        ----------
        source_a, source_b : source names
        min_p : float, optional
            Pairs with ``p_same`` below are not used (default: the ``p_reject`` option).

        Returns
        -------
        pandas.DataFrame
            The chosen rows of :attr:`pairs`.
        """
        srcs = list(self.reports.sources)
        for s in (source_a, source_b):
            if s not in srcs:
                raise GeofeasError(f"assignment: unknown source {s!r} (have {srcs})")
        ia, ib = srcs.index(source_a), srcs.index(source_b)
        track_source = np.empty(self.reports.n_tracks, dtype=np.intp)
        track_source[self.reports.track] = self.reports.source
        sa, sb = track_source[self._a], track_source[self._b]
        fwd = (sa == ia) & (sb == ib)
        rev = (sa == ib) & (sb == ia)
        rows = np.flatnonzero(fwd | rev)
        left = np.where(fwd[rows], self._a[rows], self._b[rows]).astype(np.uint32)
        right = np.where(fwd[rows], self._b[rows], self._a[rows]).astype(np.uint32)
        thr = self.options["p_reject"] if min_p is None else float(min_p)
        chosen = _core.assign_one_to_one(
            np.ascontiguousarray(left),
            np.ascontiguousarray(right),
            np.ascontiguousarray(self.pairs["p_same"].to_numpy()[rows], dtype=np.float64),
            min_score=thr,
        )
        return self.pairs.iloc[rows[np.asarray(chosen, dtype=np.intp)]].reset_index(drop=True)

    def save(self, directory: str | os.PathLike[str]) -> Path:
        """Save the result into ``directory`` (created if absent) so that it can be reviewed or
        reloaded: ``reports.parquet`` (the picture as read), ``pairs.parquet``,
        ``objects.parquet`` and ``options.json`` (the options it was computed with), written
        as one transaction. :func:`load_association` reads it back; ``geofeas review DIRECTORY``
        reviews it."""
        import json

        out = Path(directory)
        out.mkdir(parents=True, exist_ok=True)
        try:
            text = json.dumps(self.options, indent=1, sort_keys=True)
        except TypeError as exc:
            raise GeofeasError(f"save: the options cannot be written as JSON ({exc})") from None
        with atomic_paths(
            out / "reports.parquet",
            out / "pairs.parquet",
            out / "objects.parquet",
            out / "options.json",
        ) as (rep, pairs, objects, options):
            frame = self.reports.frame.copy()
            for col in ("track_id", "source"):
                frame[col] = frame[col].astype(str)
            frame.to_parquet(rep, index=False)
            self.pairs.to_parquet(pairs, index=False)
            self.objects.to_parquet(objects, index=False)
            options.write_text(text, encoding="utf-8")
        return out

    def to_file(self, path: str | os.PathLike[str]) -> None:
        """Write :attr:`pairs` to a ``.csv`` or ``.parquet`` file (by extension)."""
        write_table(self.pairs, path)


def write_table(frame: pd.DataFrame, path: str | os.PathLike[str]) -> None:
    """Write a table to ``.csv`` or ``.parquet`` by extension, atomically (a temporary file in
    the destination folder renamed over it: a failed write leaves any previous file intact)."""
    with atomic_path(_table_path(path)) as tmp:
        _write_table_to(frame, tmp)


def write_tables(tables: Sequence[tuple[pd.DataFrame, str | os.PathLike[str]]]) -> None:
    """Write several tables as one transaction: no destination is replaced unless all of them
    were written."""
    dests = [_table_path(p) for _, p in tables]
    with atomic_paths(*dests) as temps:
        for (frame, _), tmp in zip(tables, temps, strict=True):
            _write_table_to(frame, tmp)


def _table_path(path: str | os.PathLike[str]) -> Path:
    p = Path(path)
    if p.suffix.lower() not in (".csv", ".parquet", ".pq"):
        raise GeofeasError(
            f"{p}: unknown file type {p.suffix.lower()!r} (expected .csv or .parquet)"
        )
    return p


def _write_table_to(frame: pd.DataFrame, p: Path) -> None:
    if p.suffix.lower() == ".csv":
        frame.to_csv(p, index=False)
    else:
        try:
            frame.to_parquet(p, index=False)
        except ImportError as exc:  # pragma: no cover
            raise GeofeasError(f"{p}: writing Parquet needs pyarrow ({exc})") from None


def associate(
    reports: Any,
    /,
    *,
    decisions: Any = None,
    score: str = "glr",
    combine: str = "chi2",
    p_match: float = 0.99,
    p_reject: float = 0.01,
    max_gap: float = 300.0,
    horizon: float = 0.0,
    process_noise: float = 2.0,
    max_still_gap: float = 900.0,
    same_source: bool = False,
    correlation_time: float = 60.0,
    window: float = 300.0,
    inflation: float | str = "auto",
    completeness: float = 0.95,
    false_tracks: float | Mapping[Any, float] = 0.05,
    density_cell: float = 2000.0,
    exact_limit: int = 20_000,
    chains: int = 4,
    sweeps: int = 400,
    posterior_seed: int = 0,
    **score_options: Any,
) -> Association:
    """Associate the tracks of a picture: the posterior probability that each candidate pair is
    one object, the operator triage, the review order and the objects.

    The model (``docs/association.md``): per connected component of the candidate graph, the
    hypotheses are the feasible partitions of its tracks into objects (no object holds two
    tracks of one source whose time spans overlap); a partition's likelihood comes from the
    aligned per-instant Gaussian densities of its tracks (normalisers included), discounted for
    correlated instants, the picture's object density and each source's coverage and false
    tracks. Marginals are exact by enumeration for small components and sampled (Markov chain
    Monte-Carlo, with a standard error) beyond.

    Parameters
    ----------
    reports : Reports or anything :func:`read_reports` accepts
    decisions : path, pandas.DataFrame or None
        Operator decisions (``track_a, track_b, decision`` with ``same`` / ``different``,
        optionally ``operator, time``; see :func:`geofeas.read_decisions`): hard constraints.
        Contradictory decisions are refused with an error naming them (file lines or rows,
        with their tracks).
    score : one of :data:`SCORES`
        Per-instant geofeasibility score of the ``score`` column (seed 000).
    combine : {"chi2", "pvalue", "geometric", "harmonic", "arithmetic", "min"}
        How the per-instant scores become the ``score`` column (``"chi2"``: 0.5 means "fits
        like one instant 3 sigma apart").
    p_match, p_reject : float
        ``"match"`` when ``p_same >= p_match`` (default 0.99: at most 1 % of automatic merges
        wrong, if the model holds), ``"non-match"`` when ``p_same <= p_reject`` (default 0.01),
        ``"borderline"`` between.
    max_gap : float
        Longest gap between two reports of a track that is interpolated (s).
    horizon : float
        How far a track is extrapolated beyond its first / last report (s).
    process_noise : float
        Diffusion ``q`` (m^2/s) of the position around straight-line motion.
    max_still_gap : float
        Longest gap (s) interpolated across when the track stays still over it: its two
        reports at most ``sqrt(chi2_2(0.99) q T)`` apart for a gap of ``T`` seconds (a ship at
        anchor or moored, whose AIS reports come every 3 minutes or more); gaps longer than
        ``max_gap`` are otherwise not interpolated.
    same_source : bool
        Whether pairs of tracks from the same source are compared (default: not).
    correlation_time : float
        Error correlation time (s): ``k`` instants count as ``k_eff`` independent ones.
    window : float
        Longest time span of one chunk of the space-time index (s); affects speed only.
    inflation : "auto" or float
        Covariance inflation: ``"auto"`` estimates one factor per pair of sources from the
        pairs that are each other's best partner (at least 1); a number multiplies every
        covariance by it.
    completeness : float
        Share of the picture's objects the most complete source holds a track of (0.95).
    false_tracks : float or dict
        Share of each source's tracks that are false (0.05), or ``{source: share}``.
    density_cell : float
        Cell side (m) of the picture's object-density grid.
    exact_limit : int
        Components with at most this many feasible partitions are enumerated exactly.
    chains, sweeps, posterior_seed : int
        The sampler of larger components: independent chains, sweeps per chain, seed.
    **score_options
        ``threshold`` (glr), ``method`` and ``vertices`` (overlap), ``samples``, ``seed`` and
        ``sampler`` (monte_carlo).

    Returns
    -------
    Association
    """
    from .decisions import Decisions, read_decisions

    rep = read_reports(reports)
    core, recorded = _resolve_options(
        rep.sources,
        dict(
            score=score,
            combine=combine,
            p_match=p_match,
            p_reject=p_reject,
            max_gap=max_gap,
            horizon=horizon,
            process_noise=process_noise,
            max_still_gap=max_still_gap,
            same_source=same_source,
            correlation_time=correlation_time,
            window=window,
            inflation=inflation,
            completeness=completeness,
            false_tracks=false_tracks,
            density_cell=density_cell,
            exact_limit=exact_limit,
            chains=chains,
            sweeps=sweeps,
            posterior_seed=posterior_seed,
        ),
        score_options,
    )
    dec = Decisions.empty() if decisions is None else read_decisions(decisions, rep)
    with dec.naming_rows():
        raw = _core.associate(rep, dec, options=core)
    result = Association(rep, raw, recorded)
    result.decisions = dec
    return result


def _fields(result: Any) -> dict[str, Any]:
    """The fields of a core result class (``PairStats``, ``TimeCover``, ``PictureCounts``), in
    their order, as the mapping of columns ``association_finish`` takes; read from the class, so
    a field added in the core comes along."""
    kinds = (types.MemberDescriptorType, types.GetSetDescriptorType)
    return {
        name: getattr(result, name)
        for name, attr in vars(type(result)).items()
        if not name.startswith("_") and isinstance(attr, kinds)
    }


def load_association(directory: str | os.PathLike[str], /) -> Association:
    """The association saved by :meth:`Association.save` in ``directory``, recomputed from its
    reports and options (the engine is deterministic for given options and seeds)."""
    import json

    d = Path(directory)
    for name in ("reports.parquet", "options.json"):
        if not (d / name).is_file():
            raise GeofeasError(f"{d}: not a saved association ({name} is missing)")
    try:
        options = json.loads((d / "options.json").read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise GeofeasError(f"{d / 'options.json'}: cannot read the options ({exc})") from None
    if not isinstance(options, dict):
        raise GeofeasError(f"{d / 'options.json'}: expected an object of options")
    return associate(read_reports(d / "reports.parquet"), **options)


def combine_instants(
    g: Any,
    m: Any | None = None,
    time: Any | None = None,
    /,
    *,
    rule: str = "chi2",
    correlation_time: float = 0.0,
) -> float:
    """Combine the per-instant scores ``g`` of one track pair by ``rule`` (as
    :func:`associate` does). ``m`` are the squared Mahalanobis distances (default
    ``-2 ln g``, exact for the GLR), ``time`` the instants' times (default ``0, 1, ...``).

    Domain: at least one instant; ``g`` in ``[0, 1]``; ``m`` in ``[0, inf]`` (``inf`` where
    ``g`` is 0); ``time`` finite and strictly increasing; ``correlation_time`` finite and
    ``>= 0``. Anything else raises ``GeofeasError`` naming the argument and the element."""
    from .._arrays import as_float_array

    gg = as_float_array(g, "g").reshape(-1)
    if gg.size == 0:
        raise _arg_error("g", None, "no instants to combine (an empty array)")
    bad = ~((gg >= 0.0) & (gg <= 1.0))
    if bad.any():
        i = _first(bad)
        raise _arg_error("g", i, f"element {i} = {gg[i]} is outside [0, 1]")
    if m is None:
        with np.errstate(divide="ignore"):
            mm = -2.0 * np.log(gg)
    else:
        mm = as_float_array(m, "m").reshape(-1)
        if mm.shape != gg.shape:
            raise _arg_error("m", None, f"{mm.size} values for {gg.size} instants of g")
        bad = ~(mm >= 0.0)
        if bad.any():
            i = _first(bad)
            raise _arg_error("m", i, f"element {i} = {mm[i]} is not in [0, inf]")
    if time is None:
        tt = np.arange(len(gg), dtype=np.float64)
    else:
        tt = as_float_array(time, "time").reshape(-1)
        if tt.shape != gg.shape:
            raise _arg_error("time", None, f"{tt.size} values for {gg.size} instants of g")
        bad = ~np.isfinite(tt)
        if bad.any():
            i = _first(bad)
            raise _arg_error("time", i, f"element {i} = {tt[i]} is not finite")
        bad = ~(np.diff(tt) > 0)
        if bad.any():
            i = _first(bad) + 1
            raise _arg_error("time", i, f"element {i} = {tt[i]} does not increase")
    if not (np.isfinite(correlation_time) and correlation_time >= 0):
        raise _arg_error(
            "correlation_time", None, f"must be finite and >= 0, got {correlation_time}"
        )
    out = _core.combine_instants(
        np.ascontiguousarray(gg),
        np.ascontiguousarray(mm),
        np.ascontiguousarray(tt.reshape(-1)),
        np.array([0, len(gg)], dtype=np.uint64),
        rule,
        correlation_time=float(correlation_time),
    )
    return float(out[0])
