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

from .._core import GeofeasError
from ..scores import _options, from_gaussian, glr, overlap, to_gaussian

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
        "geofeas.integrations.stonesoup needs Stone Soup and pandas: "
        f"pip install 'geofeas[stonesoup]' ({exc})"
    ) from exc

__all__ = [
    "GLRMeasure",
    "GeofeasMeasure",
    "OverlapMeasure",
    "PosteriorTrackAssociator",
    "ProbabilisticTimeRangeAssociation",
    "ThresholdedGLRMeasure",
    "align_tracks",
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


def _positions(
    states: Sequence[Any], mapping: Sequence[int] | None, what: str
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Means ``(n, 2)`` and covariances ``(n, 2, 2)`` of the position components of Gaussian
    states, gathered by one stacked array operation per side (the per-state :func:`_position`
    only when the states differ in dimension or lack a covariance, for its error message)."""
    n = len(states)
    try:
        # plain ndarrays first: Stone Soup's array types index slowly
        vectors = np.array([np.asarray(s.mean, dtype=np.float64) for s in states])
        covars = np.array([np.asarray(s.covar, dtype=np.float64) for s in states])
    except (AttributeError, ValueError, TypeError):
        vectors = covars = None  # type: ignore[assignment]
    if vectors is None or covars is None or vectors.ndim != 3 or covars.ndim != 3:
        means = np.empty((n, 2))
        covs = np.empty((n, 2, 2))
        for k, state in enumerate(states):
            means[k], covs[k] = _position(state, mapping, f"{what} {k} ({state.timestamp})")
        return means, covs
    dim = vectors.shape[1]
    index = list(range(dim)) if mapping is None else list(mapping)
    if len(index) != 2 or not all(-dim <= i < dim for i in index):
        # the per-state path words the error
        _position(states[0], mapping, f"{what} 0 ({states[0].timestamp})")
    return vectors[:, index, 0], covars[:, index][:, :, index]


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
        means, covs = _positions(states, mapping, "state")
        return from_gaussian(means, covs)

    def pair_ellipses(
        self, first: Sequence[Any], second: Sequence[Any]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The ellipses of two aligned state sequences, both sides in one core call."""
        m1, c1 = _positions(first, self.mapping, "state")
        m2, c2 = _positions(second, self.mapping2, "state")
        both = from_gaussian(np.concatenate([m1, m2]), np.concatenate([c1, c2]))
        return both[: len(first)], both[len(first) :]

    def neglog(self, first: Sequence[Any], second: Sequence[Any]) -> NDArray[np.float64]:
        """``-ln g`` of aligned state sequences, in ``[0, inf]``. Measures whose score has a
        closed-form logarithm (the GLR) override this so it never passes through ``exp``."""
        a, b = self.pair_ellipses(first, second)
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
        a, b = self.pair_ellipses(*aligned)
        if len(a) == 1:  # one instant (two states): every combination is the score itself
            return float(np.asarray(self.score(a, b), dtype=np.float64)[0])
        return _combine(np.asarray(self.score(a, b), dtype=np.float64), self.combine)

    def __call__(self, item1: Any, item2: Any) -> float | None:  # type: ignore[override]
        """Distance between two Gaussian states, or two tracks (``None``: no common time).

        ``distance="neglog"`` is computed in the log domain throughout (per instant and in the
        combination), so it is exact far beyond the point where ``g`` underflows to 0."""
        if self.distance == "neglog":
            aligned = self._aligned(item1, item2)
            if aligned is None:
                return None
            nl = self.neglog(*aligned)
            return float(nl[0]) if nl.size == 1 else _combine_neglog(nl, self.combine)
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
        ma, ca = _positions(first, self.mapping, "state")
        mb, cb = _positions(second, self.mapping2, "state")
        d = ma - mb
        s = ca + cb
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
    """Normalised overlap area of the 2-sigma AOU ellipses (seed 000, eqs. 49-50).

    Exact by default (``geofeas.overlap``'s analytic method, accurate to 1e-11); on equal-area
    polygons only when asked, by ``method="polygon"`` or a ``vertices`` resolution, with the
    same rules as :func:`geofeas.overlap`.
    """

    method: str | None = Property(
        default=None,
        doc="'exact' (the default) or 'polygon' (geofeas.overlap's method).",
    )
    vertices: int | None = Property(
        default=None,
        doc="Polygon resolution (>= 8) of method='polygon'; giving it alone selects the "
        "polygon method (default: the exact overlap).",
    )

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        # refuse a bad combination now, not at the first pair
        _options("overlap", {"method": self.method, "vertices": self.vertices})

    def score(self, a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
        out: NDArray[np.float64] = overlap(a, b, method=self.method, vertices=self.vertices)
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
        states = list(track.states)
        if states:
            mean, cov = _positions(states, mapping, f"track {track_id!r} state")
            means.append(mean)
            covs.append(cov)
        for k, state in enumerate(states):
            ids.append(track_id)
            sources.append(src)
            times.append(_seconds(state.timestamp, f"track {track_id!r} state {k}"))
    if means:
        ell = from_gaussian(np.concatenate(means), np.concatenate(covs))
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


_REQUIRED = ("track_id", "source", "time")
_PLANAR = ("x", "y", "rx", "ry", "phi")
_GEOGRAPHIC = ("lat", "lon", "rx", "ry", "bearing")
#: Columns that hold an angle of some other convention (mathematical, counter-clockwise from
#: east, or unnamed units): never read as the AOU's orientation.
_OTHER_ANGLES = ("theta", "angle", "orientation", "heading", "course", "azimuth")
_BEARING_UNITS = ("auto", "degrees")


def _row_error(message: str, *, row: int | None, field: str | None) -> GeofeasError:
    """A ``GeofeasError`` about argument ``reports`` with its row and field."""
    where = f"row {row}, " if row is not None else ""
    err = GeofeasError(f"argument 'reports': {where}field '{field}': {message}")
    err.argument = "reports"
    err.row = row
    err.field = field
    return err


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


def _numbers(df: "pd.DataFrame", columns: Sequence[str]) -> NDArray[np.float64]:
    """The named columns as an ``(n, k)`` float64 array; a non-number names its row and field."""
    out = np.empty((len(df), len(columns)))
    for k, name in enumerate(columns):
        values = pd.to_numeric(df[name], errors="coerce")
        bad = np.flatnonzero(values.isna().to_numpy() & df[name].notna().to_numpy())
        if (
            bad.size
            or pd.api.types.is_bool_dtype(df[name])
            or pd.api.types.is_complex_dtype(df[name])
        ):
            row = int(bad[0]) if bad.size else 0
            raise _row_error(f"not a number: {df[name].iloc[row]!r}", row=row, field=name)
        out[:, k] = values.to_numpy(dtype=np.float64)
    return out


def _geographic_ellipses(
    df: "pd.DataFrame", origin: tuple[float, float] | None, bearing_unit: str
) -> tuple[NDArray[np.float64], tuple[float, float]]:
    """Planar ellipses ``(n, 5)`` of geographic reports in the AEQD frame of ``origin``."""
    if "bearing" not in df.columns:
        if "phi" in df.columns:
            raise _row_error(
                "geographic reports (lat, lon) take the column 'bearing' (degrees clockwise from "
                "true north); 'phi' is the planar angle in radians and is not read with lat/lon",
                row=0 if len(df) else None,
                field="phi",
            )
        raise _row_error("geographic reports need the column 'bearing'", row=None, field="bearing")
    if "phi" in df.columns:
        raise _row_error(
            "both 'bearing' and 'phi' are given: which orientation is meant cannot be told; "
            "keep 'bearing' (degrees clockwise from north) for lat/lon reports",
            row=0 if len(df) else None,
            field="phi",
        )
    if bearing_unit not in _BEARING_UNITS:
        raise GeofeasError(
            f"argument 'bearing_unit': expected one of {_BEARING_UNITS}, got {bearing_unit!r}"
        )
    aou = _numbers(df, _GEOGRAPHIC)
    if bearing_unit == "auto" and len(aou):
        # Degrees or radians? Bearings that all lie within [-2 pi, 2 pi] (and are not all 0) on
        # non-circular AOUs would mean a picture whose every ellipse points within 6.3 degrees
        # of north: far likelier radians. Refuse rather than rotate every ellipse.
        oriented = np.flatnonzero((aou[:, 2] != aou[:, 3]) & np.isfinite(aou[:, 4]))
        b = np.abs(aou[oriented, 4])
        if b.size and np.all(b <= 2.0 * np.pi) and np.any(b > 0.0):
            row = int(oriented[np.argmax(b)])
            raise _row_error(
                f"every bearing is within [-2 pi, 2 pi] (largest {aou[row, 4]!r} here): "
                "radians or degrees cannot be told. 'bearing' is in degrees clockwise from "
                "north; convert radians with numpy.degrees, or pass bearing_unit='degrees' if "
                "these really are degrees",
                row=row,
                field="bearing",
            )
    if origin is None:
        origin = (float(aou[0, 0]), float(aou[0, 1])) if len(aou) else (0.0, 0.0)
    try:
        lat0, lon0 = (float(v) for v in origin)
    except (TypeError, ValueError):
        raise GeofeasError(
            f"argument 'origin': expected (lat, lon) in degrees, got {origin!r}"
        ) from None
    from .._core import project_aeqd

    ell = project_aeqd(np.ascontiguousarray(aou), (lat0, lon0))
    return np.asarray(ell, dtype=np.float64), (lat0, lon0)


def reports_to_tracks(
    reports: Any,
    /,
    *,
    coords: str = "auto",
    origin: tuple[float, float] | None = None,
    bearing_unit: str = "auto",
) -> set[Any]:
    """A reports table as Stone Soup tracks of 2-D position Gaussian states.

    Parameters
    ----------
    reports : pandas.DataFrame or mapping of column arrays
        Columns ``track_id, source, time`` (``time`` in seconds since the Unix epoch or
        ISO-8601) and either the planar ``x, y, rx, ry, phi`` (metres east/north, ``phi`` in
        radians clockwise from north) or the geographic ``lat, lon, rx, ry, bearing`` (degrees
        WGS84, 2-sigma semi-axes in metres, ``bearing`` of ``rx`` in degrees clockwise from
        true north). Ellipses are validated by the core.
    coords : {"auto", "planar", "geographic"}
        ``"auto"`` picks the mode from the columns present (both sets present is refused).
    origin : (lat, lon), optional
        Geographic reports only: the centre of the planar frame (default: the first report's
        position). The frame is the engine's azimuthal-equidistant projection centred on
        ``origin`` (``x`` east, ``y`` north, metres; distances and azimuths from the origin
        exact, Karney's geodesics on WGS84); each bearing is carried into the origin's frame
        along the geodesic, as the engine carries covariances when it aligns tracks. Keep the
        origin inside the picture: between two points ``r`` from it, distances are distorted
        by about ``(r / 6371 km)^2 / 6`` relative (1 part in 10^5 at 50 km).
    bearing_unit : {"auto", "degrees"}
        ``"auto"`` refuses a bearing column whose values all lie within ``[-2 pi, 2 pi]``
        (radians or degrees cannot be told); ``"degrees"`` confirms degrees.

    Returns
    -------
    set of stonesoup Track
        One track per ``track_id`` (its ``id``), of ``GaussianState`` with state vector
        ``[x, y]``, covariance from ``geofeas.to_gaussian`` (eqs. 56-59) and a naive UTC
        ``datetime`` timestamp, sorted by time; ``metadata["source"]`` holds the source, and
        for geographic reports ``metadata["origin"]`` the frame's ``(lat, lon)``. Use
        ``mapping=(0, 1)`` in the measures for these tracks.

    Raises
    ------
    GeofeasError
        With ``argument``, ``row`` and ``field``: a missing column, a non-number, an invalid
        ellipse or position, ``phi`` given with ``lat, lon`` (a planar angle in radians where a
        bearing in degrees is expected), both ``phi`` and ``bearing``, a planar ``phi`` beyond
        ``2 pi`` (degrees given as radians), a bearing column in unknown units, a track with
        several sources.
    """
    df = reports if isinstance(reports, pd.DataFrame) else pd.DataFrame(dict(reports))
    missing = [c for c in _REQUIRED if c not in df.columns]
    has_planar = all(c in df.columns for c in ("x", "y"))
    has_geo = all(c in df.columns for c in ("lat", "lon"))
    if coords == "auto":
        if has_planar and has_geo:
            raise GeofeasError(
                "argument 'reports': both planar (x, y) and geographic (lat, lon) positions are "
                "given; pass coords='planar' or coords='geographic'"
            )
        coords = "geographic" if has_geo else "planar"
    if coords not in ("planar", "geographic"):
        raise GeofeasError(
            f"argument 'coords': expected 'auto', 'planar' or 'geographic', got {coords!r}"
        )
    columns: tuple[str, ...] = _PLANAR if coords == "planar" else _GEOGRAPHIC
    if coords == "geographic" and "bearing" not in df.columns and "phi" in df.columns:
        columns = tuple(c for c in columns if c != "bearing")  # reported below, with its row
    missing += [c for c in columns if c not in df.columns]
    if missing:
        others = [c for c in _OTHER_ANGLES if c in df.columns]
        hint = (
            f" ({others[0]!r} is not read as the AOU orientation: give 'phi' (planar, radians "
            "clockwise from north) or 'bearing' (with lat/lon, degrees clockwise from north))"
            if others and ("phi" in missing or "bearing" in missing)
            else ""
        )
        raise GeofeasError(f"reports: missing column(s) {missing}{hint}")
    frame: dict[str, Any] = {}
    if coords == "geographic":
        ell, frame_origin = _geographic_ellipses(df, origin, bearing_unit)
        frame = {"origin": frame_origin}
    else:
        if origin is not None:
            raise GeofeasError("argument 'origin': only geographic (lat, lon) reports take one")
        ell = _numbers(df, _PLANAR)
        big = np.flatnonzero(np.abs(ell[:, 4]) > 2.0 * np.pi)
        if big.size:
            row = int(big[0])
            raise _row_error(
                f"{ell[row, 4]!r} is beyond 2 pi: 'phi' is in radians clockwise from north "
                "(degrees? convert with numpy.radians, or give lat, lon, bearing)",
                row=row,
                field="phi",
            )
    try:
        means, covs = to_gaussian(ell) if len(df) else (np.empty((0, 2)), np.empty((0, 2, 2)))
    except GeofeasError as exc:  # the core names the ellipse field; name the table's column
        at, field = getattr(exc, "row", None), getattr(exc, "field", None)
        if at is None or field is None:
            raise
        column = {"x0": "x", "y0": "y"}.get(field, field)
        if coords == "geographic" and column == "phi":
            column = "bearing"
        shown = df[column].iloc[at] if column in df.columns else ell[at]
        raise _row_error(f"{shown!r} is not accepted ({exc})", row=at, field=column) from None
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
                timestamp=_timestamp(float(seconds[r])),
            )
            for r in rows
        ]
        tracks.add(
            Track(states, id=str(track_id), init_metadata={"source": srcs[rows[0]], **frame})
        )
    return tracks


def _timestamp(seconds: float) -> datetime:
    """Naive UTC datetime of seconds since the Unix epoch (to the microsecond)."""
    return _EPOCH + timedelta(microseconds=round(seconds * 1e6))


def align_tracks(
    tracks: Iterable[Any],
    /,
    *,
    step: float | None = None,
    times: Iterable[Any] | None = None,
    mapping: Sequence[int] = (0, 1),
    max_gap: float = 300.0,
    horizon: float = 0.0,
    process_noise: float = 2.0,
    max_still_gap: float = 900.0,
) -> list[Any]:
    """Tracks brought to common instants by the engine's own time alignment.

    Stone Soup's track-to-track associators (``TrackToTrackCounting``, ``TrackToTruth``,
    ``OneToOneTrackAssociator`` with the measures above) compare the states two tracks have at
    *exactly* the same timestamp; tracks of different sensors almost never share one. This
    puts every track on one grid of instants with the alignment :func:`geofeas.associate` uses
    (``geofeas.association.align`` in the core): between two states at most ``max_gap`` apart
    the centre is interpolated linearly and the covariance is the blend of the two plus the
    Brownian-bridge term ``process_noise * tau (T - tau) / T``; inside a longer gap a track has
    no state (it is not bridged) unless the track stays still across it (at most
    ``max_still_gap`` seconds, the two states within the 99th percentile of the diffusion's
    spread); within
    ``horizon`` seconds before its first / after its last state it is extrapolated.

    Parameters
    ----------
    tracks : iterable of stonesoup Track
        Tracks of Gaussian states (planar positions at ``mapping``).
    step : float, optional
        Grid spacing in seconds: the instants are the multiples of ``step`` seconds since the
        Unix epoch, so tracks aligned in separate calls share instants too.
    times : iterable of datetime or seconds, optional
        The instants themselves (instead of ``step``); naive datetimes are UTC.
    mapping : sequence of 2 ints
        Indices of x (east, m) and y (north, m) in the state vectors; ``(0, 2)`` for Stone Soup's
        constant-velocity ``[x, vx, y, vy]``.
    max_gap, horizon, process_noise, max_still_gap
        The alignment options of :func:`geofeas.associate` (seconds, seconds, m^2/s, seconds).

    Returns
    -------
    list of stonesoup Track
        One per input track, in the given order, with the same ``id`` and a copy of its
        ``metadata``: ``GaussianState`` s with state vector ``[x, y]`` (use ``mapping=(0, 1)``
        and ``pos_map=[0, 1]`` downstream) at the instants of the grid where the engine gives
        the track a state (a track with none gets no states).
    """
    tracks = list(tracks)
    if (step is None) == (times is None):
        raise GeofeasError("align_tracks: give exactly one of `step` and `times`")
    for n, track in enumerate(tracks):
        if not isinstance(track, StateMutableSequence):
            raise GeofeasError(
                f"argument 'tracks': track {n}: expected a Stone Soup track, got "
                f"{type(track).__name__}"
            )
    ids = [
        str(t.id) if getattr(t, "id", None) is not None else str(n) for n, t in enumerate(tracks)
    ]
    if len(set(ids)) != len(ids):
        dup = next(i for i in ids if ids.count(i) > 1)
        raise GeofeasError(f"argument 'tracks': track id {dup!r} is used twice")
    df = tracks_to_reports(tracks, source="-", mapping=mapping)  # rows track by track, in order
    dense = np.repeat(np.arange(len(tracks), dtype=np.uint32), [len(t.states) for t in tracks])
    seconds = df["time"].to_numpy(np.float64)
    start = 0
    for n, track in enumerate(tracks):  # the engine takes one state per track and instant
        t = seconds[start : start + len(track.states)]
        _, first, count = np.unique(t, return_index=True, return_counts=True)
        if np.any(count > 1):
            k = int(first[np.argmax(count > 1)])
            again = int(np.flatnonzero(t == t[k])[1])
            raise GeofeasError(
                f"argument 'tracks': track {ids[n]!r} has states {k} and {again} at the same "
                f"time {track.states[k].timestamp}"
            )
        start += len(track.states)
    if step is not None:
        if isinstance(step, bool) or not (
            isinstance(step, (int, float)) and step > 0 and math.isfinite(step)
        ):
            raise GeofeasError(
                f"argument 'step': must be a finite number of seconds > 0, got {step!r}"
            )
        if len(seconds):
            lo = math.ceil((float(seconds.min()) - horizon) / step)
            hi = math.floor((float(seconds.max()) + horizon) / step)
            grid = np.arange(lo, hi + 1, dtype=np.float64) * step
        else:
            grid = np.empty(0)
    else:
        assert times is not None
        grid = np.asarray(
            [_seconds(t, f"argument 'times': element {k}") for k, t in enumerate(times)],
            dtype=np.float64,
        )
        bad = np.flatnonzero(~np.isfinite(grid))
        if bad.size:
            raise GeofeasError(f"argument 'times': element {bad[0]} is not finite")
        grid = np.unique(grid)
    from .._core import association_states_at
    from ..association import _alignment, _ReportColumns

    columns = _ReportColumns(
        track=dense,
        source=np.zeros(len(dense), dtype=np.uint32),
        time=np.ascontiguousarray(seconds),
        aou=np.ascontiguousarray(df[["x", "y", "rx", "ry", "phi"]].to_numpy(np.float64)),
        n_tracks=len(tracks),
        coords="planar",
    )
    out = association_states_at(
        columns,
        np.ascontiguousarray(grid),
        alignment=_alignment(
            dict(
                max_gap=max_gap,
                horizon=horizon,
                process_noise=process_noise,
                max_still_gap=max_still_gap,
            )
        ),
    )
    which = np.asarray(out.track, dtype=np.int64)
    index = np.asarray(out.index, dtype=np.int64)
    state = np.asarray(out.state, dtype=np.float64)
    bounds = np.searchsorted(which, np.arange(len(tracks) + 1))
    stamps = [_timestamp(float(t)) for t in grid]
    aligned = []
    for n, track in enumerate(tracks):
        rows = range(int(bounds[n]), int(bounds[n + 1]))
        states = [
            GaussianState(
                state[r, :2].reshape(2, 1),
                np.array([[state[r, 2], state[r, 3]], [state[r, 3], state[r, 4]]]),
                timestamp=stamps[index[r]],
            )
            for r in rows
        ]
        meta = dict(getattr(track, "metadata", {}) or {})
        aligned.append(Track(states, id=ids[n], init_metadata=meta))
    return aligned


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
    from ..association import associate as _associate

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
