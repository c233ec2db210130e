"""Stone Soup measures backed by geofeasibility scores, and converters to and from reports.

Install with ``pip install "geofeas[stonesoup]"``. The measures are ordinary Stone Soup
:class:`~stonesoup.measures.Measure` objects, so Stone Soup's own associators
(``TrackToTrackCounting``, ``OneToOneTrackAssociator``, ``TrackToTruth``, the hypothesisers)
can use geofeasibility directly:

* :class:`GLRMeasure` — the generalized likelihood ratio of seed 000, eq. 71,
  ``g = exp(-0.5 d^T (R1 + R2)^-1 d)``, with the position covariances of *both* states
  (Stone Soup's ``Mahalanobis`` measure uses the covariance of the first state only);
* :class:`ThresholdedGLRMeasure` — the same with constraints 46-48 (exactly 0 when the 2-sigma
  ellipses do not touch, exactly 1 when one lies inside the other);
* :class:`OverlapMeasure` — the normalised overlap area of the 2-sigma AOU ellipses, eqs. 49-50.

**Distance convention.** Stone Soup's associators treat a measure as a *distance*: a pair is
"close" when the measure is at most (``TrackToTrackCounting``) or below (``OneToOneAssociator``)
``association_threshold``, and ``OneToOneAssociator`` minimises the sum. A geofeasibility score
``g`` is a similarity in ``[0, 1]``, so every measure returns a decreasing function of ``g``,
chosen by ``distance``:

* ``"complement"`` (default): ``1 - g`` in ``[0, 1]``; the paper's threshold ``g >= 0.5`` is
  ``association_threshold=0.5``;
* ``"neglog"``: ``-ln g`` in ``[0, inf]``; for the GLR this is half the squared Mahalanobis
  distance with ``R1 + R2``, so it adds over independent instants (``inf`` when ``g == 0``).

Either way ``g >= t`` is exactly ``distance <= 1 - t`` (or ``<= -ln t``).

**States and tracks.** Called with two states, a measure scores their positions, selected by
``mapping`` (and ``mapping2`` for the second state, as for every Stone Soup measure); positions
are planar metres (x east, y north), as in the rest of geofeas. Called with two tracks
(any :class:`~stonesoup.types.state.StateMutableSequence`), it scores the states at the
timestamps both tracks have, in one vectorised call, and combines the per-instant scores with
``combine`` (``"geometric"``, ``"arithmetic"``, ``"harmonic"`` or ``"min"``) before mapping the
result to a distance; tracks with no common timestamp give ``None``, which Stone Soup's
``OneToOneAssociator`` treats as "cannot associate". So one measure object serves both
``TrackToTrackCounting`` (state by state) and ``OneToOneTrackAssociator`` (track by track).

**The posterior.** The measures score pairs one at a time. :func:`associate` runs the whole
:func:`geofeas.associate` on Stone Soup tracks of several sources — time alignment of tracks
that share no timestamp, the joint model of every connected component of candidate pairs — and
returns the :class:`geofeas.Association` with ``p_same`` (the posterior probability that two
tracks are one object), the triage, the review queue and the objects, keyed by the tracks'
``id``. :class:`PosteriorTrackAssociator` is the same as a Stone Soup ``TrackToTrackAssociator``:
each tracks set is one source, and the pairs the engine merges come back as
:class:`ProbabilisticTimeRangeAssociation` objects holding the two ``Track`` objects, their
common time range and ``probability`` = ``p_same``.
"""

import math
from collections.abc import Iterable, Mapping, Sequence
from datetime import datetime, timedelta, timezone
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._core import GeofeasError
from .scores import DEFAULT_VERTICES, from_gaussian, glr, overlap, to_gaussian

try:
    import pandas as pd  # type: ignore[import-untyped,unused-ignore]
    from stonesoup.base import Property  # type: ignore[import-untyped]
    from stonesoup.dataassociator.base import (  # type: ignore[import-untyped]
        TrackToTrackAssociator,
    )
    from stonesoup.measures import Measure  # type: ignore[import-untyped]
    from stonesoup.measures.base import TrackMeasure  # type: ignore[import-untyped]
    from stonesoup.types.association import (  # type: ignore[import-untyped]
        AssociationSet,
        TimeRangeAssociation,
    )
    from stonesoup.types.state import GaussianState, StateMutableSequence  # type: ignore[import-untyped]
    from stonesoup.types.time import TimeRange  # type: ignore[import-untyped]
    from stonesoup.types.track import Track  # type: ignore[import-untyped]
except ImportError as exc:  # pragma: no cover - exercised by test_missing_stonesoup
    raise ImportError(
        f"geofeas.stonesoup needs Stone Soup and pandas: pip install 'geofeas[stonesoup]' ({exc})"
    ) from exc

__all__ = [
    "GLRMeasure",
    "GeofeasMeasure",
    "OverlapMeasure",
    "PosteriorTrackAssociator",
    "ProbabilisticTimeRangeAssociation",
    "ThresholdedGLRMeasure",
    "associate",
    "reports_to_tracks",
    "tracks_to_reports",
]

_DISTANCES = ("complement", "neglog")
_COMBINES = ("geometric", "arithmetic", "harmonic", "min")
_EPOCH = datetime(1970, 1, 1)


def _to_distance(g: float, kind: str) -> float:
    if kind == "complement":
        return 1.0 - g
    return math.inf if g <= 0.0 else -math.log(g)


def _combine_neglog(nl: NDArray[np.float64], how: str) -> float:
    """``-ln`` of :func:`_combine` of ``g = exp(-nl)``, computed in the log domain so that
    instants far beyond the range of ``exp`` (``-ln g`` above about 745) keep their value."""
    if how == "geometric":
        return float(np.mean(nl))
    if how == "min":
        return float(np.max(nl))
    n = nl.size
    if how == "arithmetic":
        # -ln(mean(exp(-nl))) = min(nl) - ln(mean(exp(min(nl) - nl)))
        lo = float(np.min(nl))
        if math.isinf(lo):
            return math.inf
        return lo - math.log(float(np.sum(np.exp(lo - nl))) / n)
    # harmonic: -ln(n / sum(exp(nl))) = max(nl) + ln(sum(exp(nl - max(nl))) / n)
    hi = float(np.max(nl))
    if math.isinf(hi):
        return math.inf
    return hi + math.log(float(np.sum(np.exp(nl - hi))) / n)


def _combine(g: NDArray[np.float64], how: str) -> float:
    if how == "arithmetic":
        return float(np.mean(g))
    if how == "min":
        return float(np.min(g))
    if np.any(g <= 0.0):
        return 0.0
    if how == "geometric":
        return float(np.exp(np.mean(np.log(g))))
    return float(g.size / np.sum(1.0 / g))  # harmonic


def _position(
    state: Any, mapping: Sequence[int] | None, what: str
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Mean (2,) and covariance (2, 2) of the position components of a Gaussian state."""
    covar = getattr(state, "covar", None)
    if covar is None:
        raise GeofeasError(
            f"{what}: a geofeas measure needs a Gaussian state with a covariance, got "
            f"{type(state).__name__}"
        )
    vector = np.asarray(getattr(state, "mean", state.state_vector), dtype=np.float64)
    covar = np.asarray(covar, dtype=np.float64)
    index = list(range(vector.shape[0])) if mapping is None else list(mapping)
    if len(index) != 2:
        raise GeofeasError(
            f"{what}: the mapping must select exactly 2 position components (x east, y north), "
            f"got {len(index)}: {index}"
        )
    try:
        mean = vector[index, 0]
        cov = covar[np.ix_(index, index)]
    except IndexError:
        raise GeofeasError(
            f"{what}: mapping {index} is out of range for a state of dimension {vector.shape[0]}"
        ) from None
    return mean, cov


class GeofeasMeasure(Measure, TrackMeasure):
    """Base of the geofeas measures: a geofeasibility score turned into a Stone Soup distance.

    Subclasses implement :meth:`score`, the score of aligned arrays of 2-sigma ellipses.
    """

    distance: str = Property(
        default="complement",
        doc="How the score g in [0, 1] becomes a distance: 'complement' (1 - g) or 'neglog' "
        "(-ln g).",
    )
    combine: str = Property(
        default="geometric",
        doc="How the per-instant scores of two tracks are combined: 'geometric', 'arithmetic', "
        "'harmonic' or 'min'.",
    )

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        if self.distance not in _DISTANCES:
            raise GeofeasError(f"distance must be one of {_DISTANCES}, got {self.distance!r}")
        if self.combine not in _COMBINES:
            raise GeofeasError(f"combine must be one of {_COMBINES}, got {self.combine!r}")

    def score(self, a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
        """Scores of aligned ellipse arrays ``(n, 5)`` x ``(n, 5)`` -> ``(n,)``."""
        raise NotImplementedError

    def ellipses(self, states: Sequence[Any], *, second: bool = False) -> NDArray[np.float64]:
        """The 2-sigma position ellipses ``(n, 5)`` of Gaussian states (``from_gaussian``)."""
        mapping = self.mapping2 if second else self.mapping
        means = np.empty((len(states), 2))
        covs = np.empty((len(states), 2, 2))
        for k, state in enumerate(states):
            means[k], covs[k] = _position(state, mapping, f"state {k} ({state.timestamp})")
        return from_gaussian(means, covs)

    def neglog(self, first: Sequence[Any], second: Sequence[Any]) -> NDArray[np.float64]:
        """``-ln g`` of aligned state sequences, in ``[0, inf]``. Measures whose score has a
        closed-form logarithm (the GLR) override this so it never passes through ``exp``."""
        a = self.ellipses(first)
        b = self.ellipses(second, second=True)
        g = np.asarray(self.score(a, b), dtype=np.float64)
        with np.errstate(divide="ignore"):
            out: NDArray[np.float64] = -np.log(g)
        return out

    def _aligned(self, item1: Any, item2: Any) -> tuple[list[Any], list[Any]] | None:
        """The states of two tracks at their common timestamps (``None``: none), or the two
        states."""
        if isinstance(item1, StateMutableSequence) and isinstance(item2, StateMutableSequence):
            first = {s.timestamp: s for s in item1.states}
            second = {s.timestamp: s for s in item2.states}
            times = sorted(first.keys() & second.keys())
            if not times:
                return None
            return [first[t] for t in times], [second[t] for t in times]
        if isinstance(item1, StateMutableSequence) or isinstance(item2, StateMutableSequence):
            raise GeofeasError("a geofeas measure compares two states or two tracks, not a mix")
        return [item1], [item2]

    def similarity(self, item1: Any, item2: Any) -> float | None:
        """The score ``g`` itself (a similarity in ``[0, 1]``); ``None`` for disjoint tracks."""
        aligned = self._aligned(item1, item2)
        if aligned is None:
            return None
        a = self.ellipses(aligned[0])
        b = self.ellipses(aligned[1], second=True)
        return _combine(np.asarray(self.score(a, b), dtype=np.float64), self.combine)

    def __call__(self, item1: Any, item2: Any) -> float | None:  # type: ignore[override]
        """Distance between two Gaussian states, or two tracks (``None``: no common time).

        ``distance="neglog"`` is computed in the log domain throughout (per instant and in the
        combination), so it is exact far beyond the point where ``g`` underflows to 0."""
        if self.distance == "neglog":
            aligned = self._aligned(item1, item2)
            if aligned is None:
                return None
            return _combine_neglog(self.neglog(*aligned), self.combine)
        g = self.similarity(item1, item2)
        return None if g is None else _to_distance(g, self.distance)


class GLRMeasure(GeofeasMeasure):
    """Generalized likelihood ratio of seed 000, eq. 71, as a Stone Soup distance.

    ``g = exp(-0.5 d^T (R1 + R2)^-1 d)`` with ``d`` the difference of the mapped positions and
    ``R1``, ``R2`` their covariances. With ``distance="neglog"`` the measure is
    ``0.5 d^T (R1 + R2)^-1 d``.
    """

    def score(self, a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
        out: NDArray[np.float64] = glr(a, b)
        return out

    def neglog(self, first: Sequence[Any], second: Sequence[Any]) -> NDArray[np.float64]:
        """``0.5 d^T (R1 + R2)^-1 d`` per instant, straight from the states' means and
        covariances (no ``exp``: no saturation at large distances)."""
        n = len(first)
        d = np.empty((n, 2))
        s = np.empty((n, 2, 2))
        for k, (x, y) in enumerate(zip(first, second, strict=True)):
            ma, ca = _position(x, self.mapping, f"state {k} ({x.timestamp})")
            mb, cb = _position(y, self.mapping2, f"state {k} ({y.timestamp})")
            d[k] = ma - mb
            s[k] = ca + cb
        # the covariances are validated as the score would validate them
        from_gaussian(np.zeros((n, 2)), s / 2)
        # 2x2 solve in closed form, scaled per instant so no product overflows
        scale = np.maximum(np.abs(s).max(axis=(1, 2)), np.finfo(float).tiny)
        sx, sy = s[:, 0, 0] / scale, s[:, 1, 1] / scale
        sxy = 0.5 * (s[:, 0, 1] + s[:, 1, 0]) / scale
        det = sx * sy - sxy * sxy
        dx, dy = d[:, 0] / np.sqrt(scale), d[:, 1] / np.sqrt(scale)
        q = (sy * dx * dx - 2.0 * sxy * dx * dy + sx * dy * dy) / det
        out: NDArray[np.float64] = 0.5 * np.maximum(q, 0.0)
        return out


class ThresholdedGLRMeasure(GeofeasMeasure):
    """The GLR with constraints 46-48: 0 when the 2-sigma ellipses do not touch, 1 when nested."""

    def score(self, a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
        out: NDArray[np.float64] = glr(a, b, threshold=True)
        return out


class OverlapMeasure(GeofeasMeasure):
    """Normalised overlap area of the 2-sigma AOU ellipses (seed 000, eqs. 49-50)."""

    vertices: int = Property(
        default=DEFAULT_VERTICES, doc="Polygon resolution of geofeas.overlap (>= 8)."
    )

    def score(self, a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
        out: NDArray[np.float64] = overlap(a, b, vertices=self.vertices)
        return out


def _seconds(timestamp: Any, what: str) -> float:
    if isinstance(timestamp, datetime):
        if timestamp.tzinfo is not None:
            timestamp = timestamp.astimezone(timezone.utc).replace(tzinfo=None)
        return (timestamp - _EPOCH).total_seconds()
    if isinstance(timestamp, (int, float, np.integer, np.floating)) and not isinstance(
        timestamp, bool
    ):
        return float(timestamp)
    raise GeofeasError(f"{what}: timestamp must be a datetime or seconds, got {timestamp!r}")


def tracks_to_reports(
    tracks: Iterable[Any],
    /,
    *,
    source: str | Mapping[str, str] | None = None,
    mapping: Sequence[int] = (0, 2),
) -> "pd.DataFrame":
    """Stone Soup tracks of Gaussian states as a reports table (planar contract columns).

    Parameters
    ----------
    tracks : iterable of stonesoup Track
        Tracks whose states have covariances (``GaussianState``, ``GaussianStateUpdate``, ...).
    source : str or mapping of track id to str, optional
        The source of every track, or per track id. Default: each track's
        ``metadata["source"]`` (as written by :func:`reports_to_tracks`).
    mapping : sequence of 2 ints
        Indices of x (east, metres) and y (north, metres) in the state vector; ``(0, 2)`` for
        Stone Soup's constant-velocity ``[x, vx, y, vy]``.

    Returns
    -------
    pandas.DataFrame
        Columns ``track_id, source, time, x, y, rx, ry, phi``: ``time`` in seconds since the
        Unix epoch (naive datetimes are taken as UTC), ``rx, ry`` the 2-sigma semi-axes and
        ``phi`` the bearing of ``rx`` in radians clockwise from north (``geofeas.from_gaussian``).
        One row per state, tracks in the given order.
    """
    ids: list[str] = []
    sources: list[str] = []
    times: list[float] = []
    means: list[NDArray[np.float64]] = []
    covs: list[NDArray[np.float64]] = []
    for n, track in enumerate(tracks):
        if not isinstance(track, StateMutableSequence):
            raise GeofeasError(
                f"track {n}: expected a Stone Soup track, got {type(track).__name__}"
            )
        track_id = str(track.id) if getattr(track, "id", None) is not None else str(n)
        if isinstance(source, str):
            src = source
        elif source is not None:
            if track_id not in source:
                raise GeofeasError(f"track {track_id!r}: no source given for it in `source`")
            src = str(source[track_id])
        else:
            meta = getattr(track, "metadata", {}) or {}
            if "source" not in meta:
                raise GeofeasError(
                    f"track {track_id!r}: no source; pass source=... or set "
                    "metadata['source'] on the track"
                )
            src = str(meta["source"])
        for k, state in enumerate(track.states):
            what = f"track {track_id!r} state {k}"
            mean, cov = _position(state, mapping, what)
            ids.append(track_id)
            sources.append(src)
            times.append(_seconds(state.timestamp, what))
            means.append(mean)
            covs.append(cov)
    if means:
        ell = from_gaussian(np.stack(means), np.stack(covs))
    else:
        ell = np.empty((0, 5))
    return pd.DataFrame(
        {
            "track_id": pd.Series(ids, dtype=object),
            "source": pd.Series(sources, dtype=object),
            "time": np.asarray(times, dtype=np.float64),
            "x": ell[:, 0],
            "y": ell[:, 1],
            "rx": ell[:, 2],
            "ry": ell[:, 3],
            "phi": ell[:, 4],
        }
    )


_REQUIRED = ("track_id", "source", "time", "x", "y", "rx", "ry", "phi")


def _times(column: "pd.Series") -> NDArray[np.float64]:
    """Seconds since the Unix epoch of a time column (numbers, ISO-8601 strings, datetimes)."""
    if pd.api.types.is_numeric_dtype(column) and not pd.api.types.is_bool_dtype(column):
        return column.to_numpy(dtype=np.float64)
    try:
        parsed = pd.to_datetime(column, utc=True, format="ISO8601")
    except (ValueError, TypeError) as exc:
        raise GeofeasError(f"column 'time': cannot be read as ISO-8601 times ({exc})") from None
    bad = np.flatnonzero(parsed.isna().to_numpy())
    if bad.size:
        raise GeofeasError(f"row {bad[0]}: column 'time' is missing or not a time")
    epoch = pd.Timestamp(0, tz="UTC")
    return ((parsed - epoch) / pd.Timedelta(seconds=1)).to_numpy(dtype=np.float64)


def reports_to_tracks(reports: Any, /) -> set[Any]:
    """A reports table as Stone Soup tracks of 2-D position Gaussian states.

    Parameters
    ----------
    reports : pandas.DataFrame or mapping of column arrays
        Planar contract columns ``track_id, source, time, x, y, rx, ry, phi`` (``time`` in
        seconds since the Unix epoch or ISO-8601). Ellipses are validated by the core.

    Returns
    -------
    set of stonesoup Track
        One track per ``track_id`` (its ``id``), of ``GaussianState`` with state vector
        ``[x, y]``, covariance from ``geofeas.to_gaussian`` (eqs. 56-59) and a naive UTC
        ``datetime`` timestamp, sorted by time; ``metadata["source"]`` holds the source. Use
        ``mapping=(0, 1)`` in the measures for these tracks.
    """
    df = reports if isinstance(reports, pd.DataFrame) else pd.DataFrame(dict(reports))
    missing = [c for c in _REQUIRED if c not in df.columns]
    if missing:
        hint = " (project lat/lon reports to planar metres first)" if "lat" in df.columns else ""
        raise GeofeasError(f"reports: missing column(s) {missing}{hint}")
    ell = np.column_stack([df[c].to_numpy(dtype=np.float64) for c in ("x", "y", "rx", "ry", "phi")])
    means, covs = to_gaussian(ell) if len(df) else (np.empty((0, 2)), np.empty((0, 2, 2)))
    seconds = _times(df["time"])
    bad = np.flatnonzero(~np.isfinite(seconds))
    if bad.size:
        raise GeofeasError(f"row {bad[0]}: column 'time' must be finite, got {seconds[bad[0]]}")
    ids = df["track_id"].astype(str).to_numpy()
    srcs = df["source"].astype(str).to_numpy()
    tracks: set[Any] = set()
    for track_id, rows in pd.Series(ids).groupby(ids, sort=True).indices.items():
        rows = rows[np.argsort(seconds[rows], kind="stable")]
        track_sources = set(srcs[rows])
        if len(track_sources) > 1:
            raise GeofeasError(
                f"row {rows[0]}: track {track_id!r} has several sources {sorted(track_sources)}"
            )
        states = [
            GaussianState(
                means[r].reshape(2, 1),
                covs[r],
                timestamp=_EPOCH + timedelta(microseconds=round(float(seconds[r]) * 1e6)),
            )
            for r in rows
        ]
        tracks.add(Track(states, id=str(track_id), init_metadata={"source": srcs[rows[0]]}))
    return tracks


def associate(
    tracks: Iterable[Any],
    /,
    *,
    source: str | Mapping[str, str] | None = None,
    mapping: Sequence[int] = (0, 2),
    decisions: Any = None,
    **options: Any,
) -> Any:
    """:func:`geofeas.associate` of Stone Soup tracks of several sources: the posterior
    probability that each candidate pair of tracks is one object.

    Parameters
    ----------
    tracks : iterable of stonesoup Track
        Tracks of Gaussian states of every source, with distinct ``id`` s. Tracks of different
        sources need not share timestamps (the engine interpolates, see ``max_gap``).
    source, mapping
        As for :func:`tracks_to_reports` (default source: each track's
        ``metadata["source"]``).
    decisions : path, pandas.DataFrame or None
        Operator decisions on pairs of track ids (``track_a, track_b, decision``).
    **options
        Every option of :func:`geofeas.associate` (``p_match``, ``p_reject``, ``max_gap`` ...).

    Returns
    -------
    geofeas.Association
        ``pairs`` (``track_a``, ``track_b`` are the tracks' ids; ``p_same``, ``class``,
        ``review_rank`` ...), ``objects`` (``p_alone`` per track), ``review_queue``.
    """
    from .association import associate as _associate

    reports = tracks_to_reports(tracks, source=source, mapping=mapping)
    return _associate(reports, decisions=decisions, **options)


class ProbabilisticTimeRangeAssociation(TimeRangeAssociation):  # type: ignore[misc]
    """A Stone Soup ``TimeRangeAssociation`` of two tracks with the posterior probability that
    they are one object."""

    probability: float = Property(
        default=None, doc="P(same object) of the two tracks (geofeas ``p_same``)."
    )


class PosteriorTrackAssociator(TrackToTrackAssociator):  # type: ignore[misc]
    """A Stone Soup track-to-track associator from the joint posterior of
    :func:`geofeas.associate`.

    ``associate_tracks(*tracks_sets)`` takes one set of tracks per source and returns an
    ``AssociationSet`` of :class:`ProbabilisticTimeRangeAssociation`: one per pair the engine
    merges (class ``"match"``: ``p_same >= p_match`` within a feasible grouping), holding the
    two ``Track`` objects, the time range both cover and ``probability = p_same``. The whole
    :class:`geofeas.Association` of the last call (the borderline pairs in review order, the
    objects) is kept in :attr:`association`.
    """

    mapping: Sequence[int] = Property(
        default=(0, 2), doc="Indices of x (east, m) and y (north, m) in the state vectors."
    )
    sources: Sequence[str] = Property(
        default=None, doc="A name per tracks set (default: '0', '1', ...)."
    )
    options: Mapping[str, Any] = Property(
        default=None, doc="Options of geofeas.associate (p_match, p_reject, max_gap ...)."
    )
    decisions: Any = Property(
        default=None, doc="Operator decisions on pairs of track ids (path or DataFrame)."
    )

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        #: The :class:`geofeas.Association` of the last :meth:`associate_tracks` call.
        self.association: Any = None

    def associate_tracks(self, *tracks_sets: Any) -> Any:
        """Associate the tracks of several sources (one set per source)."""
        names = (
            [str(k) for k in range(len(tracks_sets))]
            if self.sources is None
            else [str(s) for s in self.sources]
        )
        if len(names) != len(tracks_sets):
            raise GeofeasError(f"sources: {len(names)} names for {len(tracks_sets)} tracks sets")
        by_id: dict[str, Any] = {}
        source: dict[str, str] = {}
        for name, tracks in zip(names, tracks_sets, strict=True):
            for n, track in enumerate(tracks):
                if not isinstance(track, StateMutableSequence):
                    raise GeofeasError(
                        f"tracks set {name!r}, track {n}: expected a Stone Soup track, got "
                        f"{type(track).__name__}"
                    )
                track_id = str(track.id)
                if track_id in by_id:
                    raise GeofeasError(
                        f"tracks set {name!r}: track id {track_id!r} is used twice (ids name "
                        "tracks across all sets)"
                    )
                by_id[track_id] = track
                source[track_id] = name
        self.association = associate(
            list(by_id.values()),
            source=source,
            mapping=self.mapping,
            decisions=self.decisions,
            **dict(self.options or {}),
        )
        out = set()
        for row in self.association.matches.itertuples(index=False):
            t1, t2 = by_id[str(row.track_a)], by_id[str(row.track_b)]
            start = max(t1.states[0].timestamp, t2.states[0].timestamp)
            end = min(t1.states[-1].timestamp, t2.states[-1].timestamp)
            out.add(
                ProbabilisticTimeRangeAssociation(
                    {t1, t2},
                    time_range=TimeRange(min(start, end), max(start, end)),
                    probability=float(row.p_same),
                )
            )
        return AssociationSet(out)
