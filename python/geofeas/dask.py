"""Track-to-track association of a picture larger than one machine, on Dask.

Install with ``pip install "geofeas[dask]"``. :func:`associate` takes the same reports and
options as :func:`geofeas.associate` — a Dask DataFrame, a pandas DataFrame, a ``pyarrow.Table``
or a path to Parquet / CSV files — and returns the same :class:`geofeas.Association` (the same
pairs, bit-identical scores, the same classes and objects), computed on whatever Dask scheduler
is active (a ``distributed.Client`` if one exists).

How it is cut up (the argument in full is in ``docs/fusion-stacks.md``):

1. the reports are shuffled by ``track_id`` so that each partition holds whole tracks; there
   they are validated by :func:`geofeas.read_reports` (errors name the caller's row), and every
   track gets a closed space-time box (:func:`track_boxes`): the extent of its report centres
   (planar ``x, y``, or WGS84 ECEF metres for ``lat, lon``) and times, grown by a **halo** that
   bounds every box the engine's candidate index can give any chunk of the track — the largest
   2-sigma semi-axis, the Brownian-bridge term ``sqrt(q T)`` of each interpolated gap ``T``,
   the extrapolation ``|v| h + 2 sqrt(q h)`` at the ends when ``horizon = h > 0``, the geodesic
   sagitta in geographic mode — and by ``h`` in time. Two tracks can only be a candidate pair
   when their boxes intersect;
2. the picture is a grid of space-time tiles; every track is copied whole into each tile its box
   meets; each tile finds its candidate pairs with the engine's space-time index;
3. a tile keeps, and scores, only the pairs it *owns*: those whose box intersection has its
   lower corner in the tile (:mod:`geofeas._tiling`). Every candidate pair is therefore scored
   exactly once, with the very reports and options of the single-machine run;
4. the triage classes and the grouping into objects are global (one ship's tracks may cross
   tiles), so they run once, on the gathered pairs, with the engine's own grouping.

Tasks are pure functions of their inputs, so Dask's retry recomputes the work of a lost worker
and the result does not change.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import _core
from ._core import GeofeasError
from ._tiling import Grid, explode, owner
from .association import (
    DEFAULT_UPPER,
    GEOGRAPHIC,
    PLANAR,
    Association,
    Reports,
    _score_options,
    read_reports,
)

try:
    import dask.dataframe as dd
    import pandas as pd  # type: ignore[import-untyped,unused-ignore]
except ImportError as exc:  # pragma: no cover - exercised by test_missing_dask
    raise ImportError(
        f"geofeas.dask needs Dask and pandas: pip install 'geofeas[dask]' ({exc})"
    ) from exc

__all__ = ["associate", "track_boxes"]

#: WGS84 semi-major axis and flattening (the engine's geodesy constants).
_WGS84_A = 6_378_137.0
_WGS84_F = 1.0 / 298.257_223_563
#: The smallest radius of curvature of the WGS84 ellipsoid, b^2 / a (m).
_MIN_CURVATURE_RADIUS = _WGS84_A * (1.0 - _WGS84_F) ** 2
_REQUIRED = ("track_id", "source", "time")


def _columns(frame_columns: Any, coords: str) -> tuple[str, tuple[str, ...]]:
    cols = {str(c) for c in frame_columns}
    missing = [c for c in _REQUIRED if c not in cols]
    if missing:
        raise GeofeasError(f"reports: missing column(s) {', '.join(missing)}")
    if coords == "auto":
        planar, geo = set(PLANAR) <= cols, set(GEOGRAPHIC) <= cols
        if planar and geo:
            raise GeofeasError(
                "reports: both planar (x, y, rx, ry, phi) and geographic (lat, lon, rx, ry, "
                "bearing) columns are present; pass coords='planar' or coords='geographic'"
            )
        if not (planar or geo):
            raise GeofeasError(
                "reports: expected the columns x, y, rx, ry, phi (planar) or lat, lon, rx, ry, "
                f"bearing (geographic); got {', '.join(sorted(cols))}"
            )
        coords = "planar" if planar else "geographic"
    if coords not in ("planar", "geographic"):
        raise GeofeasError(f"coords: expected 'auto', 'planar' or 'geographic', got {coords!r}")
    aou = PLANAR if coords == "planar" else GEOGRAPHIC
    absent = [c for c in aou if c not in cols]
    if absent:
        raise GeofeasError(f"reports: {coords} mode needs the column(s) {', '.join(absent)}")
    return coords, _REQUIRED + aou


def _ecef(lat: NDArray[np.float64], lon: NDArray[np.float64]) -> NDArray[np.float64]:
    """WGS84 Earth-centred Earth-fixed coordinates (m) at height 0."""
    e2 = _WGS84_F * (2.0 - _WGS84_F)
    sp, cp = np.sin(np.radians(lat)), np.cos(np.radians(lat))
    sl, cl = np.sin(np.radians(lon)), np.cos(np.radians(lon))
    n = _WGS84_A / np.sqrt(1.0 - e2 * sp * sp)
    return np.column_stack([n * cp * cl, n * cp * sl, n * (1.0 - e2) * sp])


def _global_rows(exc: GeofeasError, rows: NDArray[np.int64]) -> GeofeasError:
    """The engine's error with its partition-local row numbers replaced by the caller's."""

    def sub(m: re.Match[str]) -> str:
        k = int(m.group(2))
        return f"{m.group(1)}{int(rows[k]) if 0 <= k < len(rows) else k}"

    return GeofeasError(re.sub(r"(\brow )(\d+)", sub, str(exc)))


def _read(part: pd.DataFrame, coords: str, columns: tuple[str, ...]) -> Reports:
    rows = (
        part["_row"].to_numpy(np.int64)
        if "_row" in part.columns
        else np.arange(len(part), dtype=np.int64)
    )
    try:
        return read_reports(part.loc[:, list(columns)].reset_index(drop=True), coords=coords)
    except GeofeasError as exc:
        raise _global_rows(exc, rows) from None


def _boxes(
    rep: Reports, *, max_gap: float, horizon: float, process_noise: float, halo: float
) -> dict[str, NDArray[Any]]:
    """Per track (in ``rep.track_ids`` order): span, first report and the box (module docs)."""
    n, ntr = len(rep), rep.n_tracks
    geo = rep.coords == "geographic"
    q, h, big_r = float(process_noise), float(horizon), _MIN_CURVATURE_RADIUS
    order = np.lexsort((rep.time, rep.track))
    c = rep.track[order].astype(np.int64)
    t = rep.time[order]
    aou = rep.aou[order]
    p = _ecef(aou[:, 0], aou[:, 1]) if geo else aou[:, :2]
    r = np.maximum(aou[:, 2], aou[:, 3])
    first = np.flatnonzero(np.r_[True, c[1:] != c[:-1]]) if n else np.zeros(0, np.int64)
    last = np.r_[first[1:] - 1, n - 1] if n else np.zeros(0, np.int64)

    # consecutive reports of one track (times are distinct within a track: read_reports)
    same = c[1:] == c[:-1]
    dt = t[1:] - t[:-1]
    chord = np.linalg.norm(p[1:] - p[:-1], axis=1)
    arc = chord * (1.0 + chord * chord / big_r**2) if geo else chord
    connected = same & (dt <= max_gap)
    seg = np.sqrt(q * np.maximum(dt, 0.0))
    if geo:
        seg = seg + arc * arc / (8.0 * big_r)
    seg_extra = np.zeros(ntr)
    np.maximum.at(seg_extra, c[1:][connected], seg[connected])

    # extrapolation at both ends when horizon > 0, at the speed of the end pair if connected
    end_extra = np.zeros(ntr)
    if h > 0:
        end_extra[:] = 2.0 * math.sqrt(q * h)
        if n > 1:
            multi = last > first
            for k in (np.clip(first, 0, n - 2), np.clip(last - 1, 0, n - 2)):
                moving = multi & (dt[k] <= max_gap)
                speed = np.where(moving, arc[k] / np.where(moving, dt[k], 1.0), 0.0)
                length = speed * h
                grow = length + 2.0 * math.sqrt(q * h)
                if geo:
                    grow = grow + length * length / (8.0 * big_r)
                end_extra = np.maximum(end_extra, grow)

    if n:
        rmax = np.maximum.reduceat(r, first)
        pmin = np.minimum.reduceat(p, first, axis=0)
        pmax = np.maximum.reduceat(p, first, axis=0)
    else:
        rmax, pmin, pmax = np.zeros(0), np.zeros((0, p.shape[1])), np.zeros((0, p.shape[1]))
    # the engine pads its boxes by 1e-9 |v| against rounding; 1e4 times that and 1 mm here
    scale = np.maximum(np.abs(pmin), np.abs(pmax)).max(axis=1, initial=1.0)
    grow = (rmax + seg_extra + end_extra) * (1.0 + 1e-9) + 1e-5 * scale + 1e-3
    grow = np.maximum(grow, float(halo))
    start, end = t[first], t[last]
    tpad = 1e-9 * np.maximum(np.abs(start), np.abs(end)).clip(min=1.0) + 1e-6
    out: dict[str, NDArray[Any]] = {
        "track_id": rep.track_ids,
        "source": rep.sources[rep.source[order][first]],
        "start": start,
        "end": end,
        "reports": (last - first + 1).astype(np.int64),
        "halo": grow,
    }
    for k in range(p.shape[1]):
        out[f"lo{k}"] = pmin[:, k] - grow
        out[f"hi{k}"] = pmax[:, k] + grow
    d = p.shape[1]
    out[f"lo{d}"] = start - h - tpad
    out[f"hi{d}"] = end + h + tpad
    # the first report, kept for the result's track-level Reports
    out["first_time"] = start
    for k, name in enumerate(PLANAR if rep.coords == "planar" else GEOGRAPHIC):
        out[f"first_{name}"] = aou[first, k]
    return out


def track_boxes(
    reports: Any,
    /,
    *,
    coords: str = "auto",
    max_gap: float = 300.0,
    horizon: float = 0.0,
    process_noise: float = 2.0,
    halo: float = 0.0,
) -> pd.DataFrame:
    """One row per track: its source, span and the space-time box of the distributed tiling.

    Parameters
    ----------
    reports : anything :func:`geofeas.read_reports` accepts
        Whole tracks. A column ``_row`` gives the row numbers named in errors.
    coords, max_gap, horizon, process_noise
        As for :func:`geofeas.associate`.
    halo : float
        A lower bound on the spatial halo (m).

    Returns
    -------
    pandas.DataFrame
        ``track_id, source, start, end, reports, halo`` and the box ``lo0 .. lo{d}``,
        ``hi0 .. hi{d}`` over the ``d`` spatial dimensions (``x, y``; ECEF ``X, Y, Z`` for
        geographic reports) and time (the last); every chunk box of the engine's candidate
        index for the track lies inside (see the module docs). Then the track's first report
        (``first_time``, ``first_x`` ...).
    """
    if isinstance(reports, pd.DataFrame):
        coords, columns = _columns(reports.columns, coords)
        rep = _read(reports, coords, columns)
    else:
        rep = read_reports(reports, coords=coords)
    return pd.DataFrame(
        _boxes(rep, max_gap=max_gap, horizon=horizon, process_noise=process_noise, halo=halo)
    )


def _as_dask(reports: Any, npartitions: int | None) -> dd.DataFrame:
    if isinstance(reports, dd.DataFrame):
        out = reports
    elif isinstance(reports, str) or hasattr(reports, "__fspath__"):
        path = str(reports)
        out = dd.read_csv(path) if path.lower().endswith(".csv") else dd.read_parquet(path)
    else:
        if type(reports).__module__.split(".")[0] == "pyarrow" and hasattr(reports, "to_pandas"):
            reports = reports.to_pandas()
        if isinstance(reports, Mapping):
            reports = pd.DataFrame(dict(reports))
        if not isinstance(reports, pd.DataFrame):
            raise GeofeasError(
                "reports: expected a Dask or pandas DataFrame, a pyarrow Table, a mapping of "
                f"columns or a path to Parquet / CSV files, got {type(reports).__name__}"
            )
        parts = npartitions or max(1, min(64, len(reports) // 100_000 + 1))
        return dd.from_pandas(reports.reset_index(drop=True), npartitions=parts, sort=False)
    return out if npartitions is None else out.repartition(npartitions=npartitions)


def _add_rows(
    part: pd.DataFrame, offsets: NDArray[np.int64], partition_info: Any = None
) -> pd.DataFrame:
    start = int(offsets[partition_info["number"]]) if partition_info else 0
    return part.assign(_row=np.arange(start, start + len(part), dtype=np.int64))


def _summarise(part: pd.DataFrame, coords: str, columns: tuple[str, ...], kw: dict[str, float]):
    return pd.DataFrame(_boxes(_read(part, coords, columns), **kw))


def _one_track(meta: pd.DataFrame, columns: tuple[str, ...]) -> pd.DataFrame:
    """A one-report table with the dtypes of ``meta``: the model of Dask's ``meta`` frames."""
    row: dict[str, Any] = {c: [0.0] for c in columns}
    row["rx"] = row["ry"] = [1.0]
    for c in ("track_id", "source"):
        numeric = pd.api.types.is_numeric_dtype(meta[c])
        row[c] = pd.Series([0 if numeric else "0"]).astype(meta[c].dtype)
    row["time"] = (
        pd.Series([0]).astype(meta["time"].dtype)
        if pd.api.types.is_numeric_dtype(meta["time"])
        else ["1970-01-01T00:00:00Z"]
    )
    return pd.DataFrame(row)


def _pairs_frame(n: int = 0) -> dict[str, Any]:
    return {
        "a": np.zeros(n, np.uint32),
        "b": np.zeros(n, np.uint32),
        "score": np.zeros(n),
        "instants": np.zeros(n, np.int64),
    }


def _score_tiles(
    part: pd.DataFrame,
    grid: Grid,
    dims: int,
    coords: str,
    columns: tuple[str, ...],
    index: dict[str, Any],
    scoring: dict[str, Any],
) -> pd.DataFrame:
    """The candidate pairs each tile of a partition owns, scored by the engine.

    The engine numbers a tile's tracks by their sorted ids, as it numbers all tracks in the
    single-machine run, so every pair keeps its orientation ``a < b`` and the order of its
    floating-point operations; pairs are returned under their global dense ids ``_gid``.
    """
    lo_cols = [f"lo{k}" for k in range(dims)]
    hi_cols = [f"hi{k}" for k in range(dims)]
    geographic = coords == "geographic"
    out = [pd.DataFrame(_pairs_frame())]
    for tile, rows in part.groupby("_tile", sort=True):
        rows = rows.reset_index(drop=True)
        rep = _read(rows, coords, columns)  # parsed and validated as the engine does
        gid = np.empty(rep.n_tracks, dtype=np.uint32)
        gid[rep.track] = rows["_gid"].to_numpy(np.uint32)
        track, source, time, aou, n_local = rep._core_args()
        a, b = _core.association_candidates(
            track, source, time, aou, n_local, geographic=geographic, **index
        )
        if not len(a):
            continue
        a, b = gid[a], gid[b]
        boxes = rows.drop_duplicates("_gid").set_index("_gid")
        ba, bb = boxes.loc[a], boxes.loc[b]
        keys, meets = owner(
            ba[lo_cols].to_numpy(),
            ba[hi_cols].to_numpy(),
            bb[lo_cols].to_numpy(),
            bb[hi_cols].to_numpy(),
            grid,
        )
        if not meets.all():
            k = int(np.flatnonzero(~meets)[0])
            raise GeofeasError(
                f"internal: tracks {ba['track_id'].iloc[k]!r}, {bb['track_id'].iloc[k]!r} are a "
                "candidate pair but their boxes do not meet: the halo bound is broken"
            )
        mine = keys == tile
        a, b = a[mine], b[mine]
        local = np.searchsorted(gid, np.stack([a, b])).astype(np.uint32)  # gid is increasing
        score, instants = _core.association_score_pairs(
            track,
            source,
            time,
            aou,
            n_local,
            np.ascontiguousarray(local[0]),
            np.ascontiguousarray(local[1]),
            geographic=geographic,
            **scoring,
        )
        out.append(
            pd.DataFrame(
                {
                    "a": a,
                    "b": b,
                    "score": np.asarray(score, np.float64),
                    "instants": np.asarray(instants, np.int64),
                }
            )
        )
    return pd.concat(out, ignore_index=True)


def _tile_size(
    lo: NDArray[np.float64], hi: NDArray[np.float64], target: int
) -> NDArray[np.float64]:
    """Default tile: about ``target`` tiles, each at least 4x the 90th percentile track box."""
    dims = lo.shape[1]
    spatial = dims - 1
    extent = np.maximum(hi.max(axis=0) - lo.min(axis=0), 1e-9)
    side = np.quantile(hi - lo, 0.9, axis=0)
    # spread the target over two horizontal axes (ECEF boxes are thin along the third)
    per_axis = max(1, math.ceil(math.sqrt(target)))
    size = np.empty(dims)
    size[:spatial] = max(
        float(np.sort(extent[:spatial])[-2:].min()) / per_axis,
        4.0 * float(side[:spatial].max()),
        1.0,
    )
    size[spatial] = max(float(extent[spatial]), 1.0)  # time: one slab unless asked
    return size


class DistributedAssociation(Association):
    """:class:`geofeas.Association` computed on Dask.

    ``pairs``, ``objects``, ``candidates`` and ``options`` are those the single-machine
    :func:`geofeas.associate` gives. The reports themselves stay where they were: ``reports``
    holds the first report of every track (enough for :meth:`assignment`), ``tracks`` the
    per-track summary with the space-time boxes and ``tiles`` the number of tiles used.
    """

    def __init__(
        self,
        reports: Reports,
        raw: Mapping[str, Any],
        options: dict[str, Any],
        tracks: pd.DataFrame,
        tiles: int,
    ) -> None:
        super().__init__(reports, raw, options)
        self.tracks = tracks
        self.tiles = tiles


def associate(
    reports: Any,
    /,
    *,
    tile: tuple[float, float] | None = None,
    halo: float = 0.0,
    npartitions: int | None = None,
    coords: str = "auto",
    score: str = "glr",
    combine: str = "chi2",
    lower: float = 0.5,
    upper: float = DEFAULT_UPPER,
    max_gap: float = 300.0,
    horizon: float = 0.0,
    process_noise: float = 2.0,
    same_source: bool = False,
    correlation_time: float = 60.0,
    window: float = 300.0,
    **score_options: Any,
) -> DistributedAssociation:
    """:func:`geofeas.associate` on Dask: the same pairs, scores, classes and objects.

    Parameters
    ----------
    reports : dask or pandas DataFrame, pyarrow.Table, mapping of columns, or path
        The columns of :func:`geofeas.read_reports`. A path ending in ``.csv`` is read with
        ``dask.dataframe.read_csv``, any other (Parquet files or a directory of them) with
        ``dask.dataframe.read_parquet``. Errors name the row of the whole table (0-based).
    tile : (float, float), optional
        Tile size ``(metres, seconds)``. Default: about four tiles per partition, each at least
        four times the 90th percentile of the tracks' box sizes, one slab in time. The tile
        size changes the cost only, never the result.
    halo : float
        A lower bound (m) on every track's spatial halo. The halo is chosen from the data and
        is always sufficient; a larger value only copies more tracks.
    npartitions : int, optional
        Partitions of the reports (default: the input's, or one per 100,000 rows).
    coords, score, combine, lower, upper, max_gap, horizon, process_noise, same_source, \
correlation_time, window, **score_options
        As for :func:`geofeas.associate`.

    Returns
    -------
    DistributedAssociation
        A :class:`geofeas.Association` with ``tracks`` (the per-track boxes) and ``tiles``.
    """
    ddf = _as_dask(reports, npartitions)
    coords, columns = _columns(ddf.columns, coords)
    if not (isinstance(halo, (int, float)) and math.isfinite(halo) and halo >= 0):
        raise GeofeasError(f"halo: must be a finite number >= 0, got {halo!r}")
    name, opts = _score_options(score, score_options)
    options = dict(
        score=score,
        combine=combine,
        lower=float(lower),
        upper=float(upper),
        max_gap=float(max_gap),
        horizon=float(horizon),
        process_noise=float(process_noise),
        same_source=bool(same_source),
        correlation_time=float(correlation_time),
        window=float(window),
        **score_options,
    )
    index = dict(
        max_gap=float(max_gap),
        horizon=float(horizon),
        process_noise=float(process_noise),
        same_source=bool(same_source),
        window=float(window),
    )
    scoring = dict(
        score=name,
        combine=combine,
        max_gap=float(max_gap),
        horizon=float(horizon),
        process_noise=float(process_noise),
        correlation_time=float(correlation_time),
        **opts,
    )
    # every option checked by the engine before any work is distributed
    empty = {c: np.zeros(0) for c in columns}
    _core.associate(
        *read_reports(empty, coords=coords)._core_args(),
        geographic=coords == "geographic",
        lower=float(lower),
        upper=float(upper),
        same_source=bool(same_source),
        window=float(window),
        **scoring,
    )

    ddf = ddf[list(columns)]
    lengths = ddf.map_partitions(len).compute()
    offsets = np.concatenate([[0], np.cumsum(np.asarray(lengths, dtype=np.int64))])
    ddf = ddf.map_partitions(_add_rows, offsets, meta=ddf._meta.assign(_row=np.int64(0)))
    nparts = ddf.npartitions
    ddf = ddf.shuffle("track_id", npartitions=nparts).persist()

    kw = dict(
        max_gap=float(max_gap),
        horizon=float(horizon),
        process_noise=float(process_noise),
        halo=float(halo),
    )
    meta = _summarise(_one_track(ddf._meta, columns), coords, columns, kw).iloc[:0]
    tracks = ddf.map_partitions(_summarise, coords, columns, kw, meta=meta).compute()
    track_ids, inverse = np.unique(tracks["track_id"].to_numpy(), return_inverse=True)
    if len(track_ids) != len(tracks):  # pragma: no cover - the shuffle keeps tracks whole
        raise GeofeasError("internal: a track was split across partitions")
    tracks = tracks.iloc[np.argsort(inverse, kind="stable")].reset_index(drop=True)
    dims = sum(1 for c in tracks.columns if c.startswith("lo"))
    lo = tracks[[f"lo{k}" for k in range(dims)]].to_numpy()
    hi = tracks[[f"hi{k}" for k in range(dims)]].to_numpy()
    if tile is None:
        size = _tile_size(lo, hi, 4 * nparts) if len(tracks) else np.ones(dims)
    else:
        if len(tile) != 2:
            raise GeofeasError(f"tile: expected (metres, seconds), got {tile!r}")
        size = np.r_[np.full(dims - 1, float(tile[0])), float(tile[1])]
    grid = Grid.covering(lo, hi, size)
    per_track = np.prod(grid.cell(hi) - grid.cell(lo) + 1, axis=1).astype(np.float64)
    n_reports = tracks["reports"].to_numpy(np.float64)
    copied = float(per_track @ n_reports)
    if copied > max(1e6, 16.0 * n_reports.sum()):
        raise GeofeasError(
            f"tile: {tuple(size.tolist())} is too small for these tracks: the tiles would hold "
            f"{copied / max(n_reports.sum(), 1):.0f} copies of every report on average; use "
            "larger tiles (or the default)"
        )
    rows, keys = explode(lo, hi, grid)
    copies = pd.DataFrame(
        {
            "track_id": tracks["track_id"].to_numpy()[rows],
            "_tile": keys,
            "_gid": rows.astype(np.uint32),
        }
    )
    for k in range(dims):
        copies[f"lo{k}"] = lo[rows, k]
        copies[f"hi{k}"] = hi[rows, k]
    n_tiles = int(np.unique(keys).size)

    rep = ddf.merge(copies, on="track_id", how="inner")
    rep = rep.shuffle("_tile", npartitions=max(1, min(n_tiles, 4 * nparts)))
    scored = rep.map_partitions(
        _score_tiles,
        grid,
        dims,
        coords,
        columns,
        index,
        scoring,
        meta=pd.DataFrame(_pairs_frame()),
    )
    pairs = scored.compute()
    return _gather(pairs, tracks, track_ids, coords, options, n_tiles)


def _gather(
    pairs: pd.DataFrame,
    tracks: pd.DataFrame,
    track_ids: NDArray[Any],
    coords: str,
    options: dict[str, Any],
    tiles: int,
) -> DistributedAssociation:
    """The global steps: candidates in the engine's order, triage and grouping once."""
    candidates = len(pairs)
    a = pairs["a"].to_numpy(np.uint32)
    b = pairs["b"].to_numpy(np.uint32)
    score = pairs["score"].to_numpy(np.float64)
    instants = pairs["instants"].to_numpy(np.int64)
    order = np.lexsort((b, a))
    keep = order[instants[order] > 0]
    if len(order) > 1:
        key = a[order].astype(np.int64) * len(track_ids) + b[order]
        if (np.diff(key) == 0).any():  # pragma: no cover - ownership makes this impossible
            raise GeofeasError("internal: a candidate pair was scored in two tiles")
    a, b, score, instants = a[keep], b[keep], score[keep], instants[keep]
    sources, inverse = np.unique(tracks["source"].to_numpy(), return_inverse=True)
    source: NDArray[np.uint32] = np.ascontiguousarray(inverse.reshape(-1), dtype=np.uint32)
    start = tracks["start"].to_numpy(np.float64)
    end = tracks["end"].to_numpy(np.float64)
    klass, obj = _core.association_group(
        np.ascontiguousarray(source),
        np.ascontiguousarray(start),
        np.ascontiguousarray(end),
        np.ascontiguousarray(a),
        np.ascontiguousarray(b),
        np.ascontiguousarray(score),
        lower=options["lower"],
        upper=options["upper"],
    )
    names = PLANAR if coords == "planar" else GEOGRAPHIC
    first = tracks[["track_id", "source", "first_time"] + [f"first_{n}" for n in names]]
    first.columns = ["track_id", "source", "time", *names]
    track_reports = Reports(
        first,
        coords=coords,
        track_ids=track_ids,
        track=np.arange(len(track_ids), dtype=np.uint32),
        sources=sources,
        source=source,
        time=np.ascontiguousarray(tracks["first_time"].to_numpy(np.float64)),
        aou=np.ascontiguousarray(first[list(names)].to_numpy(np.float64)),
    )
    raw = {
        "a": a,
        "b": b,
        "score": score,
        "instants": instants.astype(np.uint32),
        "class": klass,
        "object": obj,
        "candidates": candidates,
    }
    return DistributedAssociation(track_reports, raw, options, tracks, tiles)
