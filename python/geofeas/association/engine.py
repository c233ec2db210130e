"""Track-to-track association: read reports, score every candidate track pair over its common
instants, triage the pairs and group duplicate tracks into objects.

The numerics (time alignment, geodesy, combination, the space-time index, grouping) run in the
Rust core (``geofeas._core.associate``); this module does the I/O with pandas / pyarrow,
vectorised validation with errors naming the row (or the file line), and the conversion of ids.
See ``docs/association.md`` for the model.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .. import _core
from .._atomic import atomic_path, atomic_paths
from .._core import GeofeasError

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

__all__ = [
    "Association",
    "COMBINE_RULES",
    "Reports",
    "associate",
    "combine_instants",
    "load_association",
    "read_reports",
]

#: Columns of a planar report: metres east / north, 2-sigma semi-axes (m), radians from north.
PLANAR = ("x", "y", "rx", "ry", "phi")
#: Columns of a geographic report: degrees WGS84, 2-sigma semi-axes (m), degrees from north.
GEOGRAPHIC = ("lat", "lon", "rx", "ry", "bearing")
#: Columns every report needs.
REQUIRED = ("track_id", "source", "time")
#: The options of :func:`associate`, defined once in the core (``association::schema``): dicts
#: of ``name``, ``default``, ``choices`` and ``help``, in signature order.
OPTIONS: tuple[dict[str, Any], ...] = tuple(_core.association_options())
_CHOICES = {o["name"]: tuple(o["choices"]) for o in OPTIONS}
#: Combination rules of :func:`associate` (``"chi2"`` is the calibrated default).
COMBINE_RULES: tuple[str, ...] = _CHOICES["combine"]
#: Scores of :func:`associate` (``"glr_threshold"`` is ``"glr"`` with ``threshold=True``).
SCORES: tuple[str, ...] = _CHOICES["score"]
#: The ``"chi2"`` score of a fit like one instant 2 sigma apart (a reference on the score
#: column's scale; the classes come from the posterior).
DEFAULT_UPPER: float = _core.association_default_upper()
CLASSES = np.array(["match", "borderline", "non-match"], dtype=object)

_SCORE_OPTIONS = ("threshold", "method", "vertices", "samples", "seed", "sampler")


def _pandas() -> Any:
    try:
        import pandas as pd
    except ImportError:  # pragma: no cover - depends on the environment
        raise GeofeasError(
            "geofeas association needs pandas (and pyarrow for Parquet): pip install 'geofeas[io]'"
        ) from None
    return pd


class Reports:
    """Validated reports ``(track_id, source, time, position, AOU)``, ready for
    :func:`associate`. Build them with :func:`read_reports`.

    Attributes
    ----------
    frame : pandas.DataFrame
        The table as read, every column kept (extra columns included).
    coords : str
        ``"planar"`` or ``"geographic"``.
    track_ids, sources : numpy.ndarray
        The distinct track ids and sources, sorted; ``track`` and ``source`` index them.
    track, source : numpy.ndarray of uint32
        Per report, the index of its track id and its source.
    time : numpy.ndarray of float64
        Seconds (ISO-8601 times are seconds since 1970-01-01 UTC).
    aou : numpy.ndarray of float64, shape (n, 5)
        ``x, y, rx, ry, phi`` or ``lat, lon, rx, ry, bearing``.
    """

    def __init__(
        self,
        frame: pd.DataFrame,
        *,
        coords: str,
        track_ids: NDArray[Any],
        track: NDArray[np.uint32],
        sources: NDArray[Any],
        source: NDArray[np.uint32],
        time: NDArray[np.float64],
        aou: NDArray[np.float64],
    ) -> None:
        self.frame = frame
        self.coords = coords
        self.track_ids = track_ids
        self.track = track
        self.sources = sources
        self.source = source
        self.time = time
        self.aou = aou

    def __len__(self) -> int:
        return int(self.time.shape[0])

    @property
    def n_tracks(self) -> int:
        """Number of distinct tracks."""
        return int(self.track_ids.shape[0])

    def __repr__(self) -> str:
        return (
            f"Reports({len(self)} reports, {self.n_tracks} tracks, "
            f"{len(self.sources)} sources, {self.coords})"
        )


@dataclass(frozen=True)
class _ReportColumns:
    """Report columns as the engine's bindings take them (the attributes :class:`Reports` has):
    ``track`` and ``source`` (uint32 indices), ``time``, ``aou`` (``(n, 5)``), ``n_tracks`` and
    ``coords``. For arrays that are not a table read by :func:`read_reports`."""

    track: NDArray[np.uint32]
    source: NDArray[np.uint32]
    time: NDArray[np.float64]
    aou: NDArray[np.float64]
    n_tracks: int
    coords: str


class _Where:
    """Names a row of the input in errors: a file line (header = line 1) or a table row.

    ``labels`` (optional) numbers the rows as a larger table does (``labels[row]``, or a
    callable): a part of a table read alone names the rows of the whole.
    """

    def __init__(self, path: str | None, lines: bool, labels: Any = None) -> None:
        self.path = path
        self.lines = lines
        self.labels = labels

    def label(self, row: int) -> int:
        if self.labels is None:
            return row
        return int(self.labels(row) if callable(self.labels) else self.labels[row])

    def __call__(self, row: int) -> str:
        k = self.label(row)
        where = f"line {k + 2}" if self.lines else f"row {k}"
        return f"{self.path}: {where}" if self.path else where


class _Row(int):
    """A row of the input inside the parts of an error message (see :func:`_error`)."""


def _error(where: _Where, *parts: str | _Row, field: str | None = None) -> GeofeasError:
    """A ``GeofeasError`` about rows of ``reports``: the message is ``parts`` with every
    :class:`_Row` named by ``where``; ``.row`` is the first row named, ``.field`` the column.
    The parts are kept, so :func:`_relabelled` names the rows anew without reading the text."""
    err = GeofeasError("".join(where(p) if isinstance(p, _Row) else p for p in parts))
    rows = [p for p in parts if isinstance(p, _Row)]
    err.argument = "reports"
    err.row = where.label(rows[0]) if rows else None
    err.field = field
    err._where, err._parts = where, parts
    return err


def _relabelled(err: GeofeasError, labels: Any) -> GeofeasError:
    """``err`` (from :func:`_error`) with its rows' labels ``l`` renamed ``labels(l)``."""
    where: _Where | None = getattr(err, "_where", None)
    if where is None:
        return err
    old = where.label

    def label(row: int) -> int:
        return int(labels(old(row)))

    renamed = _Where(where.path, where.lines, label)
    return _error(renamed, *err._parts, field=err.field)


def _read_table(source: Any) -> tuple[pd.DataFrame, _Where]:
    pd = _pandas()
    if isinstance(source, (str, os.PathLike)):
        path = Path(source)
        suffix = path.suffix.lower()
        try:
            if suffix == ".csv":
                _check_csv_header(path)
                # ids are names: read as text, so "007" stays "007"
                frame = pd.read_csv(
                    path,
                    skip_blank_lines=False,
                    skipinitialspace=True,
                    dtype={"track_id": str, "source": str},
                )
                return frame, _Where(str(path), lines=True)
            if suffix in (".parquet", ".pq"):
                return pd.read_parquet(path), _Where(str(path), lines=False)
        except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
            raise GeofeasError(f"{path}: {exc}") from None
        except ImportError as exc:  # pragma: no cover - pyarrow missing
            raise GeofeasError(f"{path}: reading Parquet needs pyarrow ({exc})") from None
        raise GeofeasError(f"{path}: unknown file type {suffix!r} (expected .csv or .parquet)")
    if isinstance(source, pd.DataFrame):
        return source.reset_index(drop=True), _Where(None, lines=False)
    if isinstance(source, np.ndarray) and source.dtype.names:
        return pd.DataFrame.from_records(source), _Where(None, lines=False)
    if isinstance(source, Mapping):
        try:
            return pd.DataFrame(dict(source)), _Where(None, lines=False)
        except ValueError as exc:
            raise GeofeasError(f"reports: cannot build a table from the columns ({exc})") from None
    raise GeofeasError(
        "reports: expected a path to a .csv / .parquet file, a pandas DataFrame, a dict of "
        f"column arrays or a Reports; got {type(source).__name__}"
    )


def _check_csv_header(path: Path) -> None:
    """Refuses a CSV file whose header names a column twice (pandas would rename one)."""
    import csv

    with open(path, newline="", encoding="utf-8") as fh:
        header = next(csv.reader(fh), None)
    if not header:
        raise GeofeasError(f"{path}: empty file (expected a header line)")
    names = [h.strip() for h in header]
    seen: set[str] = set()
    for name in names:
        if name in seen:
            err = GeofeasError(f"{path}: line 1: column {name!r} appears more than once")
            err.argument, err.row, err.field = "reports", None, name
            raise err
        seen.add(name)


def _arg_error(argument: str, row: int | None, message: str) -> GeofeasError:
    """A ``GeofeasError`` about ``argument`` (element ``row``), with the attributes set."""
    err = GeofeasError(f"argument '{argument}': {message}")
    err.argument, err.row = argument, row
    return err


def _first(mask: NDArray[np.bool_]) -> int:
    return int(np.flatnonzero(mask)[0])


def _ids(frame: pd.DataFrame, column: str, where: _Where) -> tuple[NDArray[Any], NDArray[Any]]:
    """Sorted distinct ids of ``column`` (as strings) and the index of each row's id.

    Ids are names, kept as given: a file's ``007`` and ``7`` are two tracks. Integer columns of
    an in-memory table become their decimal text; floats, booleans, dates and mixed columns are
    refused (a float id such as ``7.0`` has no single spelling)."""
    pd = _pandas()
    col = frame[column]
    missing = col.isna().to_numpy()
    if missing.any():
        raise _field_error(where, _first(missing), column, "missing value")
    kind = pd.api.types.infer_dtype(col, skipna=False)
    if len(col) == 0:
        return np.zeros(0, dtype=object), np.zeros(0, dtype=np.uint32)
    if kind == "integer":
        values = np.asarray([str(int(v)) for v in col.to_numpy()], dtype=object)
    elif kind == "string":
        values = col.to_numpy(dtype=object)
    else:
        types = col.map(type).to_numpy()
        ok = np.asarray([issubclass(t, str) for t in types])
        row = _first(~ok) if (~ok).any() else 0
        raise _field_error(
            where,
            row,
            column,
            f"ids are names: strings (or integers in an in-memory table); found {kind} "
            f"values, e.g. {col.iloc[row]!r}",
        )
    uniq, inverse = np.unique(values.astype(str), return_inverse=True)
    return uniq.astype(object), inverse.reshape(-1).astype(np.uint32)


def _field_error(where: _Where, row: int, column: str, message: str) -> GeofeasError:
    """A ``GeofeasError`` naming the row (file line) and column, with the attributes set."""
    return _error(where, _Row(row), f": column {column}: {message}", field=column)


def _times(frame: pd.DataFrame, where: _Where) -> NDArray[np.float64]:
    pd = _pandas()
    col = frame["time"]
    missing = col.isna().to_numpy()
    if missing.any():
        raise _field_error(where, _first(missing), "time", "missing value")
    if pd.api.types.is_datetime64_any_dtype(col):
        dt = pd.to_datetime(col, utc=True)
    elif pd.api.types.is_numeric_dtype(col) and not pd.api.types.is_bool_dtype(col):
        t = col.to_numpy(dtype=np.float64)
        bad = ~np.isfinite(t)
        if bad.any():
            raise _field_error(where, _first(bad), "time", f"{t[bad][0]} is not finite")
        return np.ascontiguousarray(t)
    else:
        text = col.astype(str)
        numeric = pd.to_numeric(text, errors="coerce")
        if len(text) and not np.isnan(numeric.iloc[0]):
            # the first value is a number: the column is seconds
            bad = numeric.isna().to_numpy()
            if bad.any():
                row = _first(bad)
                raise _field_error(
                    where,
                    row,
                    "time",
                    f"{text.iloc[row]!r} is not a number of seconds "
                    "(the column is read as seconds, as its first value is)",
                )
            return _times(frame.assign(time=numeric), where)
        try:
            dt = pd.to_datetime(text, utc=True, errors="coerce", format="ISO8601")
        except (ValueError, TypeError):  # pragma: no cover - pandas < 2
            dt = pd.to_datetime(text, utc=True, errors="coerce")
        bad = dt.isna().to_numpy()
        if bad.any():
            row = _first(bad)
            raise _field_error(
                where,
                row,
                "time",
                f"{text.iloc[row]!r} is not an ISO-8601 time "
                "(the column is read as ISO-8601, as its first value is)",
            )
    epoch = pd.Timestamp("1970-01-01", tz="UTC")
    return np.ascontiguousarray(((dt - epoch) / pd.Timedelta(seconds=1)).to_numpy(np.float64))


def _numbers(frame: pd.DataFrame, columns: tuple[str, ...], where: _Where) -> NDArray[np.float64]:
    pd = _pandas()
    out = np.empty((len(frame), len(columns)), dtype=np.float64)
    for k, name in enumerate(columns):
        col = frame[name]
        missing = col.isna().to_numpy()
        if missing.any():
            raise _field_error(where, _first(missing), name, "missing value")
        if pd.api.types.is_bool_dtype(col):
            raise _field_error(where, 0, name, "booleans are not numbers")
        values = pd.to_numeric(col, errors="coerce")
        bad = values.isna().to_numpy()
        if bad.any():
            row = _first(bad)
            raise _field_error(where, row, name, f"{col.iloc[row]!r} is not a number")
        v = values.to_numpy(dtype=np.float64)
        bad = ~np.isfinite(v)
        if bad.any():
            raise _field_error(where, _first(bad), name, f"{v[bad][0]} is not finite")
        out[:, k] = v
    for k in (2, 3):
        bad = out[:, k] <= 0
        if bad.any():
            row = _first(bad)
            raise _field_error(
                where, row, columns[k], f"{out[row, k]} must be > 0 (2-sigma semi-axis in metres)"
            )
    if columns == GEOGRAPHIC:
        bad = np.abs(out[:, 0]) > 90
        if bad.any():
            row = _first(bad)
            raise _field_error(where, row, "lat", f"{out[row, 0]} is outside [-90, 90]")
        bad = np.abs(out[:, 1]) > 180
        if bad.any():
            row = _first(bad)
            raise _field_error(
                where, row, "lon", f"{out[row, 1]} is outside [-180, 180] (not wrapped)"
            )
    return out


def read_reports(source: Any, /, *, coords: str = "auto") -> Reports:
    """Read and validate reports.

    Parameters
    ----------
    source : path, pandas.DataFrame, dict of arrays, NumPy structured array or Reports
        A ``.csv`` or ``.parquet`` file, or a table, with the columns ``track_id``, ``source``,
        ``time`` (seconds, or ISO-8601 strings read as UTC) and either ``x, y, rx, ry, phi``
        (planar: metres, ``phi`` in radians clockwise from north) or ``lat, lon, rx, ry,
        bearing`` (geographic: degrees WGS84, 2-sigma semi-axes in metres, ``bearing`` of the
        ``rx`` axis in degrees clockwise from true north). Extra columns are kept in
        :attr:`Reports.frame` and otherwise ignored.
    coords : {"auto", "planar", "geographic"}
        ``"auto"`` picks the mode from the columns present.

    Returns
    -------
    Reports

    Raises
    ------
    GeofeasError
        Naming the row (table) or line (CSV file) of the first bad value: a missing column or
        value, a non-number, NaN or infinity, a non-positive semi-axis, a latitude outside
        ``[-90, 90]``, ids mixing strings and numbers, a track reported by two sources, or
        two reports of one track at the same time. Nothing is dropped silently.
    """
    return _read_reports(source, coords=coords)


def _read_reports(source: Any, /, *, coords: str = "auto", labels: Any = None) -> Reports:
    """:func:`read_reports`, with errors naming row ``labels[row]`` (see :class:`_Where`)."""
    if isinstance(source, Reports):
        return source
    frame, where = _read_table(source)
    where.labels = labels
    frame.columns = [str(c).strip() for c in frame.columns]
    dup = frame.columns[frame.columns.duplicated()]
    if len(dup):
        raise GeofeasError(f"reports: column {dup[0]!r} appears more than once")
    missing = [c for c in REQUIRED if c not in frame.columns]
    if missing:
        raise GeofeasError(f"reports: missing column(s) {', '.join(missing)}")
    has_planar = all(c in frame.columns for c in PLANAR)
    has_geo = all(c in frame.columns for c in GEOGRAPHIC)
    if coords == "auto":
        if has_planar and has_geo:
            raise GeofeasError(
                "reports: both planar (x, y, rx, ry, phi) and geographic (lat, lon, rx, ry, "
                "bearing) columns are present; pass coords='planar' or coords='geographic'"
            )
        if not (has_planar or has_geo):
            raise GeofeasError(
                "reports: expected the columns x, y, rx, ry, phi (planar) or lat, lon, rx, ry, "
                f"bearing (geographic); got {', '.join(map(str, frame.columns))}"
            )
        coords = "planar" if has_planar else "geographic"
    if coords not in ("planar", "geographic"):
        raise GeofeasError(f"coords: expected 'auto', 'planar' or 'geographic', got {coords!r}")
    columns = PLANAR if coords == "planar" else GEOGRAPHIC
    absent = [c for c in columns if c not in frame.columns]
    if absent:
        raise GeofeasError(f"reports: {coords} mode needs the column(s) {', '.join(absent)}")
    track_ids, track = _ids(frame, "track_id", where)
    sources, src = _ids(frame, "source", where)
    time = _times(frame, where)
    aou = _numbers(frame, columns, where)
    n = len(frame)
    if n:
        # one source per track
        order = np.lexsort((np.arange(n), track))
        same_track = track[order][1:] == track[order][:-1]
        other_source = src[order][1:] != src[order][:-1]
        bad = same_track & other_source
        if bad.any():
            k = _first(bad)
            a, b = sorted((int(order[k]), int(order[k + 1])))
            raise _error(
                where,
                _Row(b),
                f": track {track_ids[track[b]]!r} has source {sources[src[b]]!r} but ",
                _Row(a),
                f" gives it source {sources[src[a]]!r}",
                field="source",
            )
        # distinct times within a track
        order = np.lexsort((np.arange(n), time, track))
        dup = (track[order][1:] == track[order][:-1]) & (time[order][1:] == time[order][:-1])
        if dup.any():
            k = _first(dup)
            a, b = sorted((int(order[k]), int(order[k + 1])))
            raise _error(
                where,
                _Row(b),
                f": track {track_ids[track[b]]!r} already has a report at this time (",
                _Row(a),
                "); remove or merge duplicate reports",
                field="time",
            )
    return Reports(
        frame,
        coords=coords,
        track_ids=track_ids,
        track=np.ascontiguousarray(track, dtype=np.uint32),
        sources=sources,
        source=np.ascontiguousarray(src, dtype=np.uint32),
        time=time,
        aou=np.ascontiguousarray(aou),
    )


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
        or ``"sampled"``), ``partitions`` (enumerated; 0 when sampled) and ``max_std_error``.
    coverage : dict
        ``{source: P_s}``: the share of the picture's objects each source is estimated to hold.
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

    def __init__(self, reports: Reports, raw: Mapping[str, Any], options: dict[str, Any]) -> None:
        pd = _pandas()
        self.reports = reports
        self.options = options
        self._raw = raw
        #: The operator decisions the association was computed under (``Decisions``), if any.
        self.decisions: Any = None
        self.candidates = int(raw["candidates"])
        a = np.asarray(raw["a"], dtype=np.intp)
        b = np.asarray(raw["b"], dtype=np.intp)
        self._a, self._b = a, b
        self._score = np.asarray(raw["score"])
        ids = reports.track_ids
        rank = np.asarray(raw["review_rank"], dtype=np.int64)
        component = np.asarray(raw["component"], dtype=np.int64)
        self.pairs = pd.DataFrame(
            {
                "track_a": ids[a],
                "track_b": ids[b],
                "score": self._score,
                "instants": np.asarray(raw["instants"], dtype=np.int64),
                "class": CLASSES[np.asarray(raw["class"], dtype=np.intp)],
                "p_same": np.asarray(raw["p_same"], dtype=np.float64),
                "review_rank": pd.array(np.where(rank > 0, rank, 0), dtype="Int64"),
                "llr": np.asarray(raw["llr"], dtype=np.float64),
                "std_error": np.asarray(raw["std_error"], dtype=np.float64),
                "review_gain": np.asarray(raw["review_gain"], dtype=np.float64),
                "settles_same": np.asarray(raw["settles_same"], dtype=np.int64),
                "settles_different": np.asarray(raw["settles_different"], dtype=np.int64),
                "component": pd.array(np.where(component < 2**32 - 1, component, 0), dtype="Int64"),
            }
        )
        self.pairs.loc[rank == 0, "review_rank"] = pd.NA
        self.pairs.loc[component >= 2**32 - 1, "component"] = pd.NA
        srcs = reports.sources
        self.inflation = {
            (srcs[int(a)], srcs[int(b)]): float(c)
            for a, b, c in zip(
                raw["inflation_a"], raw["inflation_b"], raw["inflation"], strict=True
            )
        }
        self.coverage = {
            srcs[k]: float(p) for k, p in enumerate(np.asarray(raw["coverage"])) if k < len(srcs)
        }
        obj = np.asarray(raw["object"], dtype=np.int64)
        per_track_source = np.empty(reports.n_tracks, dtype=np.intp)
        per_track_source[reports.track] = reports.source
        self.objects = pd.DataFrame(
            {
                "track_id": ids,
                "object": obj,
                "source": reports.sources[per_track_source] if reports.n_tracks else [],
                "p_alone": np.asarray(raw["p_alone"], dtype=np.float64),
            }
        )
        methods = np.array(["exact", "sampled"], dtype=object)
        self.components = pd.DataFrame(
            {
                "tracks": np.asarray(raw["component_tracks"], dtype=np.int64),
                "method": methods[np.asarray(raw["component_method"], dtype=np.intp)],
                "partitions": np.asarray(raw["component_partitions"], dtype=np.int64),
                "max_std_error": np.asarray(raw["component_std_error"], dtype=np.float64),
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
        decisions, as :func:`associate` with ``decisions=`` would give them."""
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
        out = _core.association_finish(
            {"source": raw["track_source"], "spread": raw["track_spread"], **raw["time_cover"]},
            {
                "a": np.ascontiguousarray(raw["a"], dtype=np.uint32),
                "b": np.ascontiguousarray(raw["b"], dtype=np.uint32),
                "candidates": self.candidates,
                **raw["stats"],
            },
            [raw["counts"]],
            dec,
            geographic=self.reports.coords == "geographic",
            options=core,
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


def _score_options(score: str, options: dict[str, Any]) -> tuple[str, dict[str, Any]]:
    unknown = sorted(set(options) - set(_SCORE_OPTIONS))
    if unknown:
        raise TypeError(f"associate() got unexpected option(s) {', '.join(unknown)}")
    opts = dict(options)
    if score == "glr_threshold":
        score = "glr"
        opts["threshold"] = True
    if score not in SCORES:
        raise GeofeasError(f"score: unknown score {score!r} (expected one of {SCORES})")
    if opts.get("seed") is None:
        opts.pop("seed", None)
    from ..scores import _OPTIONS

    misplaced = sorted(set(opts) - _OPTIONS[score])
    if misplaced:
        err = GeofeasError(
            f"option(s) {misplaced} do not apply to score {score!r}; "
            f"it takes {sorted(_OPTIONS[score])}"
        )
        err.argument = misplaced[0]
        raise err
    if score == "overlap" and "vertices" in opts:
        # a resolution alone asks for the polygon method, as in geofeas.overlap
        opts.setdefault("method", "polygon")
    return score, opts


#: The defaults of :func:`associate`'s options (besides the score's own), from :data:`OPTIONS`.
ASSOCIATION_DEFAULTS: dict[str, Any] = {o["name"]: o["default"] for o in OPTIONS}


def _options_markdown() -> str:
    """The options table of ``docs/association.md``, rendered from :data:`OPTIONS`
    (``python scripts/options_doc.py`` writes it; a test checks the page)."""
    rows = ["| option | default | `geofeas associate` | meaning |", "|---|---|---|---|"]
    for o in OPTIONS:
        flag = "--" + o["name"].replace("_", "-")
        choices = f" (one of {', '.join(o['choices'])})" if o["choices"] else ""
        rows.append(f"| `{o['name']}` | `{o['default']!r}` | `{flag}` | {o['help']}{choices} |")
    return "\n".join(rows) + "\n"


_SCORE_DEFAULTS: dict[str, Any] = dict(
    threshold=False, method="exact", vertices=256, samples=500, seed=0, sampler="importance"
)


def _resolve_options(
    sources: NDArray[Any], options: Mapping[str, Any], score_options: dict[str, Any]
) -> tuple[dict[str, Any], dict[str, Any]]:
    """The engine's options (a dict for ``_core``) and the options as recorded on the result,
    from :func:`associate`'s keyword arguments (shared with ``geofeas.dask``)."""
    unknown = sorted(set(options) - set(ASSOCIATION_DEFAULTS))
    if unknown:
        raise TypeError(f"associate() got unexpected option(s) {', '.join(unknown)}")
    o = {**ASSOCIATION_DEFAULTS, **options}
    name, opts = _score_options(str(o["score"]), score_options)
    inflation = o["inflation"]
    if isinstance(inflation, str):
        if inflation != "auto":
            raise GeofeasError(f"inflation: expected 'auto' or a number, got {inflation!r}")
        infl: float | None = None
    else:
        infl = float(inflation)
    ft = o["false_tracks"]
    if isinstance(ft, Mapping):
        unknown_src = [k for k in ft if k not in set(sources.tolist())]
        if unknown_src:
            raise GeofeasError(
                f"false_tracks: unknown source(s) {unknown_src} (have {list(sources)})"
            )
        false_tracks = [float(ft.get(s, 0.05)) for s in sources]
    else:
        false_tracks = [float(ft)] * len(sources)
    core = dict(
        score=name,
        combine=str(o["combine"]),
        p_match=float(o["p_match"]),
        p_reject=float(o["p_reject"]),
        max_gap=float(o["max_gap"]),
        horizon=float(o["horizon"]),
        process_noise=float(o["process_noise"]),
        same_source=bool(o["same_source"]),
        correlation_time=float(o["correlation_time"]),
        window=float(o["window"]),
        inflation=infl,
        completeness=float(o["completeness"]),
        false_tracks=false_tracks,
        density_cell=float(o["density_cell"]),
        exact_limit=int(o["exact_limit"]),
        chains=int(o["chains"]),
        sweeps=int(o["sweeps"]),
        posterior_seed=int(o["posterior_seed"]),
        **{**_SCORE_DEFAULTS, **opts},
    )
    recorded = {**o, **score_options}
    return core, recorded


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
        Contradictory decisions are refused with an error naming their rows.
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
    raw = _core.associate(rep, dec, options=core)
    result = Association(rep, raw, recorded)
    result.decisions = dec
    return result


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
