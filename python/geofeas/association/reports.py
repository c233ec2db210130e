"""Reports: reading and validating a picture (``track_id, source, time``, position and 2-sigma
AOU) from CSV, Parquet or a table, vectorised, with errors naming the row (or the file line) and
the column; the ids become the engine's uint32 indices. :class:`Reports` is what
:func:`geofeas.associate` and the distributed path take.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .._core import GeofeasError

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

__all__ = ["GEOGRAPHIC", "PLANAR", "REQUIRED", "Reports", "read_reports"]

#: Columns of a planar report: metres east / north, 2-sigma semi-axes (m), radians from north.
PLANAR = ("x", "y", "rx", "ry", "phi")
#: Columns of a geographic report: degrees WGS84, 2-sigma semi-axes (m), degrees from north.
GEOGRAPHIC = ("lat", "lon", "rx", "ry", "bearing")
#: Columns every report needs.
REQUIRED = ("track_id", "source", "time")


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
