"""Track-to-track association of a picture larger than one machine, on Dask.

Install with ``pip install "geofeas[dask]"``. :func:`associate` takes the same reports, options
and operator decisions as :func:`geofeas.associate` — a Dask DataFrame, a pandas DataFrame, a
``pyarrow.Table``, the :class:`geofeas.Reports` that :func:`geofeas.read_reports` returns or a
path to Parquet / CSV files — and returns the same :class:`geofeas.Association` (the same pairs,
bit-identical scores and posteriors, the same classes, review order and objects), computed on
whatever Dask scheduler is active (a ``distributed.Client`` if one exists).

How it is cut up (the argument in full is in ``docs/fusion-stacks.md``):

1. every partition is read by :func:`geofeas.read_reports` (errors name the caller's row) and
   reduced by the engine to per-track partials (``association_track_partials``: count, time
   span, extent of the report centres in the index space — planar ``x, y``, WGS84 ECEF metres
   for ``lat, lon`` —, largest 2-sigma semi-axis, first and last two reports), which merge over
   any split of a track's reports, so the reports are not shuffled for this. The engine merges
   them and gives each track a closed space-time box (``association_track_boxes``,
   :func:`track_boxes`): that extent grown by a **halo** bounding every box its candidate index
   can give any chunk of the track, with the very growth functions of the index (the property
   test ``merged_partials_of_any_split_hold_every_chunk_box``) — and by ``h`` in time. Two
   tracks can only be a candidate pair when their boxes intersect;
2. the picture is a grid of space-time tiles; every report is copied into each tile its track's
   box meets (ids and sources replaced by their indices among the sorted ids, times by seconds:
   numbers only), in one shuffle; each tile then holds whole tracks and finds its candidate
   pairs with the engine's space-time index;
3. a tile keeps, and summarises with the engine (``association_pair_stats``: the score and the
   Gaussian evidence of the common instants), only the pairs it *owns*: those whose box
   intersection has its lower corner in the tile (:mod:`geofeas.integrations._tiling`). Every
   candidate pair is therefore scored exactly once, with the very reports, options and track
   order of the single-machine run. A tile also takes the engine's picture counts (track-time
   per source and per density cell, in whole microseconds) of the tracks whose *home* it is —
   the first tile a track is copied into — so every track is counted once and the integer
   counts of all tiles add up to the whole picture's exactly;
4. everything global runs once, on the gathered pairs and the merged counts, in the engine's
   own ``finish`` (the function the single-machine pipeline ends with): the covariance
   inflation, the picture's object density and coverage, each pair's evidence, the posterior
   of every connected component of the candidate graph (a component may span many tiles: it is
   never cut, as its pairs are all gathered), the operator decisions, triage, review order and
   objects.

Tasks are pure functions of their inputs, so Dask's retry recomputes the work of a lost worker
and the result does not change.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import _core
from .._core import GeofeasError
from ..association import (
    ASSOCIATION_DEFAULTS,
    GEOGRAPHIC,
    PLANAR,
    Association,
    Reports,
    _alignment,
    _read_reports,
    _relabelled,
    _ReportColumns,
    _resolve_options,
    read_reports,
)
from ..association.decisions import Decisions, read_decisions
from ..association.engine import _fields
from ._tiling import Grid, explode, owner

try:
    import dask.dataframe as dd
    import pandas as pd  # type: ignore[import-untyped,unused-ignore]
except ImportError as exc:  # pragma: no cover - exercised by test_missing_dask
    raise ImportError(
        f"geofeas.integrations.dask needs Dask and pandas: pip install 'geofeas[dask]' ({exc})"
    ) from exc

__all__ = ["associate", "track_boxes"]

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


def _partials(rep: Reports) -> tuple[NDArray[Any], NDArray[Any], NDArray[np.float64]]:
    """The engine's mergeable partial of every track of some of the reports
    (``association_track_partials``), with the tracks' ids and sources: merged over any split
    of the reports by :func:`_combine`, so the tracks' boxes need no shuffle of the reports."""
    source = np.zeros(rep.n_tracks, np.uint32)
    source[rep.track] = rep.source  # read_reports checked: one source per track
    return rep.track_ids, rep.sources[source], _core.association_track_partials(rep)


def _combine(
    parts: list[tuple[NDArray[Any], NDArray[Any], NDArray[np.float64]]],
    coords: str,
    *,
    alignment: dict[str, float],
    halo: float,
) -> pd.DataFrame:
    """The track table, sorted by track id as the engine numbers tracks: the partials merged
    and the halo boxes computed by the engine (``association_track_boxes``) under the
    ``alignment`` options."""
    ids = np.concatenate([p[0] for p in parts]) if parts else np.zeros(0, object)
    try:
        track_ids, inverse = np.unique(ids, return_inverse=True)
    except TypeError:
        raise GeofeasError(
            "column track_id: ids must be all strings or all numbers (partitions differ)"
        ) from None
    inverse = inverse.reshape(-1)
    src = np.concatenate([p[1] for p in parts]) if parts else np.zeros(0, object)
    # a track's source as one partition gives it (the tiles, holding whole tracks, refuse a
    # track given two)
    source = np.empty(len(track_ids), dtype=object)
    source[inverse] = src
    geo = coords == "geographic"
    raw = _core.association_track_boxes(
        np.concatenate([p[2] for p in parts]) if parts else np.zeros((0, 1)),
        inverse.astype(np.uint32),
        len(track_ids),
        geographic=geo,
        alignment=alignment,
        halo=halo,
    )
    out: dict[str, Any] = {
        "track_id": track_ids,
        "source": source,
        "start": raw.start,
        "end": raw.end,
        "reports": raw.reports.astype(np.int64),
        "halo": raw.halo,
        "spread": raw.spread,
    }
    dims = [0, 1, 2, 3] if geo else [0, 1, 3]  # planar boxes have no z
    for j, k in enumerate(dims):
        out[f"lo{j}"] = raw.lo[:, k]
        out[f"hi{j}"] = raw.hi[:, k]
    out["first_time"] = raw.first_time
    for k, name in enumerate(PLANAR if coords == "planar" else GEOGRAPHIC):
        out[f"first_{name}"] = raw.first_aou[:, k]
    return pd.DataFrame(out)


def track_boxes(
    reports: Any,
    /,
    *,
    coords: str = "auto",
    max_gap: float = 300.0,
    horizon: float = 0.0,
    process_noise: float = 2.0,
    max_still_gap: float = 900.0,
    halo: float = 0.0,
) -> pd.DataFrame:
    """One row per track: its source, span and the space-time box of the distributed tiling.

    Parameters
    ----------
    reports : anything :func:`geofeas.read_reports` accepts
    coords, max_gap, horizon, process_noise, max_still_gap
        As for :func:`geofeas.associate`.
    halo : float
        A lower bound on the spatial halo (m).

    Returns
    -------
    pandas.DataFrame
        Sorted by ``track_id``: ``track_id, source, start, end, reports, halo, spread`` (the
        track's AOU size as the posterior orders tracks) and the box
        ``lo0 .. lo{d}``, ``hi0 .. hi{d}`` over the ``d`` spatial dimensions (``x, y``; ECEF
        ``X, Y, Z`` for geographic reports) and time (the last); every chunk box of the
        engine's candidate index for the track lies inside (see the module docs). Then the
        track's first report (``first_time``, ``first_x`` ...).
    """
    rep = read_reports(reports, coords=coords)
    return _combine(
        [_partials(rep)],
        rep.coords,
        alignment=_alignment(
            dict(
                max_gap=max_gap,
                horizon=horizon,
                process_noise=process_noise,
                max_still_gap=max_still_gap,
            )
        ),
        halo=halo,
    )


def _frame_of(rep: Reports) -> pd.DataFrame:
    """The reports that :func:`geofeas.read_reports` returned, as a table of parsed values
    (ids and sources as given, times in seconds)."""
    names = PLANAR if rep.coords == "planar" else GEOGRAPHIC
    cols: dict[str, Any] = {
        "track_id": rep.track_ids[rep.track],
        "source": rep.sources[rep.source],
        "time": rep.time,
    }
    for k, name in enumerate(names):
        cols[name] = rep.aou[:, k]
    return pd.DataFrame(cols)


def _as_dask(reports: Any, npartitions: int | None) -> dd.DataFrame:
    if isinstance(reports, Reports):
        reports = _frame_of(reports)
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
                "columns, geofeas Reports or a path to Parquet / CSV files, got "
                f"{type(reports).__name__}"
            )
        parts = npartitions or max(1, min(64, len(reports) // 100_000 + 1))
        return dd.from_pandas(reports.reset_index(drop=True), npartitions=parts, sort=False)
    return out if npartitions is None else out.repartition(npartitions=npartitions)


_ROW_BITS = 40  # a row is named (partition << 40) + row-in-partition until an error needs it


def _reports_of(part: pd.DataFrame, pidx: int, coords: str, columns: tuple[str, ...]) -> Reports:
    """``read_reports`` of one partition; errors name ``(pidx << 40) + row``."""
    rows = (np.int64(pidx) << _ROW_BITS) + np.arange(len(part), dtype=np.int64)
    frame = part.loc[:, list(columns)].reset_index(drop=True)
    for c in ("track_id", "source"):  # categorical columns (from Parquet) as their values
        if isinstance(frame[c].dtype, pd.CategoricalDtype):
            frame[c] = frame[c].astype(frame[c].cat.categories.dtype)
    return _read_reports(frame, coords=coords, labels=rows)


def _partition_partials(
    part: pd.DataFrame, pidx: int, coords: str, columns: tuple[str, ...]
) -> tuple[tuple[NDArray[Any], ...], tuple[NDArray[Any], NDArray[Any], NDArray[np.float64]]]:
    """A partition parsed once: its reports as arrays, and its tracks' partials."""
    rep = _reports_of(part, pidx, coords, columns)
    return (rep.track, rep.source, rep.time, rep.aou, rep.track_ids, rep.sources), _partials(rep)


def _to_tiles(
    parsed: tuple[NDArray[Any], ...],
    pidx: int,
    coords: str,
    shared: tuple[NDArray[Any], ...],
) -> pd.DataFrame:
    """The reports of a partition, numbered and copied into their tracks' tiles.

    Ids become the track's index among all sorted track ids (``track_id``) and the source's
    among all sorted sources (``source``), times are seconds: every column is numeric, and
    the engine, which numbers a tile's tracks by their sorted ids, numbers them in the same
    order as the whole picture.
    """
    track, source, time, aou, local_ids, local_sources = parsed
    track_ids, sources, first_copy, copies, keys = shared
    gid = np.searchsorted(track_ids, local_ids).astype(np.int64)[track]
    src = np.searchsorted(sources, local_sources).astype(np.int64)[source]
    count = copies[gid]
    row = np.repeat(np.arange(len(time), dtype=np.int64), count)
    start = np.repeat(first_copy[gid] - np.cumsum(count) + count, count)
    tile = keys[start + np.arange(row.size, dtype=np.int64)]
    names = PLANAR if coords == "planar" else GEOGRAPHIC
    out: dict[str, Any] = {
        "track_id": gid[row],
        "source": src[row],
        "time": time[row],
    }
    for k, name in enumerate(names):
        out[name] = aou[row, k]
    out["_row"] = (np.int64(pidx) << _ROW_BITS) + row
    out["_tile"] = tile
    return pd.DataFrame(out)


def _tiles_meta(coords: str) -> pd.DataFrame:
    names = PLANAR if coords == "planar" else GEOGRAPHIC
    cols: dict[str, Any] = {"track_id": np.zeros(0, np.int64), "source": np.zeros(0, np.int64)}
    cols["time"] = np.zeros(0)
    for name in names:
        cols[name] = np.zeros(0)
    cols["_row"] = np.zeros(0, np.int64)
    cols["_tile"] = np.zeros(0, np.int64)
    return pd.DataFrame(cols)


#: The per-pair summaries a tile returns (``association_pair_stats``), after ``a`` and ``b``.
_STATS = (
    ("score", np.float64),
    ("instants", np.uint32),
    ("sum_m", np.float64),
    ("k_eff", np.float64),
    ("mean_mg", np.float64),
    ("mean_ln_det", np.float64),
    ("mean_trace_over_det", np.float64),
    ("mean_inv_det", np.float64),
    ("evidence_k_eff", np.float64),
    ("pos_0", np.float64),
    ("pos_1", np.float64),
)


def _pairs_frame(n: int = 0) -> dict[str, Any]:
    out: dict[str, Any] = {"a": np.zeros(n, np.uint32), "b": np.zeros(n, np.uint32)}
    for name, dtype in _STATS:
        out[name] = np.zeros(n, dtype)
    return out


def _home_counts(
    rep: Reports,
    home: NDArray[np.bool_],
    gid: NDArray[np.int64],
    sources: NDArray[Any],
    geographic: bool,
    options: dict[str, Any],
) -> tuple[dict[str, Any], dict[str, Any]] | None:
    """The engine's picture counts of the tracks of ``rep`` whose home tile this is (each track
    has exactly one, so the counts of all tiles add up to the whole picture's), with sources
    as their indices among all the picture's sources; and the engine's time cover of those
    tracks (``association_track_summary``) with their global indices (``track``)."""
    keep = home[rep.track]
    if not keep.any():
        return None
    tracks, track = np.unique(rep.track[keep], return_inverse=True)
    home_reports = _ReportColumns(
        track=np.ascontiguousarray(track.reshape(-1), dtype=np.uint32),
        source=np.ascontiguousarray(rep.source[keep]),
        time=np.ascontiguousarray(rep.time[keep]),
        aou=np.ascontiguousarray(rep.aou[keep]),
        n_tracks=len(tracks),
        coords=rep.coords,
    )
    summary = _core.association_track_summary(home_reports, options=options)
    counts, cover = _fields(summary[0]), _fields(summary[1])
    cover["track"] = gid[tracks]
    # the tile numbers sources among those it holds; map them to the picture's indices
    glob = np.searchsorted(sources, rep.sources).astype(np.int64)
    for name in ("micros", "reach", "reports"):
        per_source = np.asarray(counts[name], dtype=np.uint64)
        whole = np.zeros(int(glob.max()) + 1, dtype=np.uint64)
        whole[glob[: len(per_source)]] = per_source
        counts[name] = whole
    counts["cell_source"] = glob[np.asarray(counts["cell_source"], np.intp)].astype(np.uint32)
    return dict(counts), cover


def _time_cover(pieces: list[dict[str, Any]], n_tracks: int) -> dict[str, NDArray[Any]]:
    """The time cover of every track (global order) from the pieces of the home tiles."""
    track = np.concatenate([np.asarray(p["track"], np.int64) for p in pieces] or [np.zeros(0)])
    if len(track) != n_tracks or (np.sort(track) != np.arange(n_tracks)).any():
        raise GeofeasError("internal: the home tiles do not hold every track once")
    lengths = np.concatenate([np.diff(np.asarray(p["cover_offsets"], np.int64)) for p in pieces])
    start = np.concatenate([np.asarray(p["cover_start"], np.float64) for p in pieces])
    end = np.concatenate([np.asarray(p["cover_end"], np.float64) for p in pieces])
    reports = np.concatenate([np.asarray(p["cover_reports"], np.uint32) for p in pieces])
    first = np.cumsum(lengths) - lengths
    order = np.argsort(track, kind="stable")
    # the chains of the tracks in global order: each track's run of rows, one after another
    n = lengths[order]
    offsets = np.r_[0, np.cumsum(n)]
    rows = (np.repeat(first[order] - offsets[:-1], n) + np.arange(offsets[-1])).astype(np.intp)
    offsets = offsets.astype(np.uint32)
    return {
        "cover_offsets": offsets,
        "cover_start": start[rows],
        "cover_end": end[rows],
        "cover_reports": reports[rows],
    }


def _score_tiles(
    part: pd.DataFrame,
    coords: str,
    columns: tuple[str, ...],
    shared: tuple[Any, ...],
    options: dict[str, Any],
) -> tuple[pd.DataFrame, list[dict[str, Any]], list[dict[str, Any]]]:
    """The candidate pairs each tile of a partition owns, with the engine's summaries, and the
    picture counts of the tracks whose home the tile is.

    Tracks arrive under their global indices (``track_id``) and are read under their ids, so
    the engine numbers a tile's tracks in the order of the whole picture: every pair keeps its
    orientation ``a < b`` and the order of its floating-point operations.
    """
    grid, lo, hi, track_ids, sources, home_tile = shared
    geographic = coords == "geographic"
    out = [pd.DataFrame(_pairs_frame())]
    counts: list[dict[str, Any]] = []
    covers: list[dict[str, Any]] = []
    for tile, rows in part.groupby("_tile", sort=True):
        rows = rows.sort_values("_row", kind="stable")  # the caller's order
        # whole tracks here: the cross-report checks (one source, distinct times) bite, naming
        # the caller's ids, sources and rows; the engine numbers the tile's tracks by their
        # sorted ids, i.e. in the order of the whole picture
        table = rows.loc[:, list(columns)].reset_index(drop=True)
        table["track_id"] = track_ids[table["track_id"].to_numpy(np.int64)]
        table["source"] = sources[table["source"].to_numpy(np.int64)]
        rep = _read_reports(table, coords=coords, labels=rows["_row"].to_numpy(np.int64))
        gid = np.searchsorted(track_ids, rep.track_ids).astype(np.int64)
        c = _home_counts(rep, home_tile[gid] == tile, gid, sources, geographic, options)
        if c is not None:
            counts.append(c[0])
            covers.append(c[1])
        a, b = _core.association_candidates(rep, options=options)
        if not len(a):
            continue
        ga, gb = gid[a], gid[b]
        keys, meets = owner(lo[ga], hi[ga], lo[gb], hi[gb], grid)
        if not meets.all():
            k = int(np.flatnonzero(~meets)[0])
            raise GeofeasError(
                f"internal: tracks {ga[k]} and {gb[k]} are a candidate pair but their boxes do "
                "not meet: the halo bound is broken"
            )
        mine = keys == tile
        stats = _fields(
            _core.association_pair_stats(
                rep,
                np.ascontiguousarray(a[mine]),
                np.ascontiguousarray(b[mine]),
                options=options,
                stream_ids=np.ascontiguousarray(gid, dtype=np.uint32),
            )
        )
        frame: dict[str, Any] = {
            "a": ga[mine].astype(np.uint32),
            "b": gb[mine].astype(np.uint32),
        }
        for name_, dtype in _STATS:
            frame[name_] = np.asarray(stats[name_], dtype)
        out.append(pd.DataFrame(frame))
    return pd.concat(out, ignore_index=True), counts, covers


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

    ``pairs``, ``objects``, ``components``, ``coverage``, ``track_breaks``,
    ``false_overlap``, ``inflation``, ``candidates`` and ``options`` are those the
    single-machine :func:`geofeas.associate` gives. The reports themselves stay where they
    were: ``reports`` holds the first report of every track (enough for :meth:`assignment`),
    ``tracks`` the per-track summary with the space-time boxes and ``tiles`` the number of
    tiles used.
    """

    def __init__(
        self,
        reports: Reports,
        raw: _core.AssociationOutput,
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
    decisions: Any = None,
    tile: tuple[float, float] | None = None,
    halo: float = 0.0,
    npartitions: int | None = None,
    coords: str = "auto",
    **options: Any,
) -> DistributedAssociation:
    """:func:`geofeas.associate` on Dask: the same pairs, scores, posteriors, classes, review
    order and objects.

    Parameters
    ----------
    reports : dask or pandas DataFrame, pyarrow.Table, mapping of columns, Reports, or path
        The columns of :func:`geofeas.read_reports` (or what it returned). A path ending in
        ``.csv`` is read with ``dask.dataframe.read_csv``, any other (Parquet files or a
        directory of them) with ``dask.dataframe.read_parquet``. Errors name the row of the
        whole table (0-based).
    decisions : path, pandas.DataFrame or None
        Operator decisions, as for :func:`geofeas.associate`.
    tile : (float, float), optional
        Tile size ``(metres, seconds)``. Default: about four tiles per partition, each at least
        four times the 90th percentile of the tracks' box sizes, one slab in time. The tile
        size changes the cost only, never the result.
    halo : float
        A lower bound (m) on every track's spatial halo. The halo is chosen from the data and
        is always sufficient; a larger value only copies more tracks.
    npartitions : int, optional
        Partitions of the reports (default: the input's, or one per 100,000 rows).
    coords : {"auto", "planar", "geographic"}
        As for :func:`geofeas.read_reports`.
    **options
        Every option of :func:`geofeas.associate` (``score``, ``combine``, ``p_match``,
        ``p_reject``, ``max_gap`` ... and the score's own), with the same defaults.

    Returns
    -------
    DistributedAssociation
        A :class:`geofeas.Association` with ``tracks`` (the per-track boxes) and ``tiles``.
    """
    if isinstance(reports, Reports):
        coords = reports.coords if coords == "auto" else coords
    ddf = _as_dask(reports, npartitions)
    coords, columns = _columns(ddf.columns, coords)
    if not (isinstance(halo, (int, float)) and math.isfinite(halo) and halo >= 0):
        raise GeofeasError(f"halo: must be a finite number >= 0, got {halo!r}")
    general = {k: v for k, v in options.items() if k in ASSOCIATION_DEFAULTS}
    score_options = {k: v for k, v in options.items() if k not in ASSOCIATION_DEFAULTS}
    # every option checked by the engine before any work is distributed (the sources are not
    # known yet: those a false_tracks mapping names stand in for them)
    ft = general.get("false_tracks")
    named = np.array(sorted(ft, key=str) if isinstance(ft, Mapping) else [], dtype=object)
    core, _ = _resolve_options(named, general, score_options)
    empty = read_reports({c: np.zeros(0) for c in columns}, coords=coords)
    _core.associate(empty, Decisions.empty(), options=core)

    ddf = ddf[list(columns)]
    try:
        return _run(ddf, coords, columns, tile, halo, general, score_options, decisions)
    except GeofeasError as exc:
        raise _name_rows(exc, ddf) from None


def _name_rows(exc: GeofeasError, ddf: dd.DataFrame) -> GeofeasError:
    """The error with its rows, numbered ``(partition << 40) + row`` by the tasks, renamed as
    rows of the whole table (the partitions' lengths are counted only now, on the error
    path); the message is built anew from its parts (see ``association._error``)."""
    if getattr(exc, "row", None) is None or getattr(exc, "_where", None) is None:
        return exc  # not about a row of the reports
    offsets = np.concatenate([[0], np.cumsum(np.asarray(ddf.map_partitions(len).compute()))])
    mask = (1 << _ROW_BITS) - 1

    def whole(label: int) -> int:
        p = label >> _ROW_BITS
        return int(offsets[p]) + (label & mask) if p < len(offsets) - 1 else label

    return _relabelled(exc, whole)


def _run(
    ddf: dd.DataFrame,
    coords: str,
    columns: tuple[str, ...],
    tile: tuple[float, float] | None,
    halo: float,
    general: dict[str, Any],
    score_options: dict[str, Any],
    decisions: Any,
) -> DistributedAssociation:
    import dask

    nparts = ddf.npartitions
    # 1. per-track boxes from per-partition partial aggregates (no shuffle of the reports)
    # (each partition is parsed once; the parsed arrays stay on the workers for step 3)
    partial = dask.delayed(_partition_partials, pure=True, nout=2)
    stage = dask.persist(*[partial(p, i, coords, columns) for i, p in enumerate(ddf.to_delayed())])
    (parts,) = dask.compute([s[1] for s in stage])
    o = {**ASSOCIATION_DEFAULTS, **general}
    tracks = _combine(
        list(parts),
        coords,
        alignment=_alignment(o),
        halo=halo,
    )
    track_ids = tracks["track_id"].to_numpy()
    sources = np.unique(tracks["source"].to_numpy())
    # the options as the single machine resolves them, against the picture's sources
    options, recorded = _resolve_options(sources, general, score_options)
    track_reports = _track_reports(tracks, track_ids, sources, coords)
    dec = Decisions.empty() if decisions is None else read_decisions(decisions, track_reports)
    dims = sum(1 for c in tracks.columns if c.startswith("lo"))
    lo = np.ascontiguousarray(tracks[[f"lo{k}" for k in range(dims)]].to_numpy(np.float64))
    hi = np.ascontiguousarray(tracks[[f"hi{k}" for k in range(dims)]].to_numpy(np.float64))

    # 2. the grid, and the tiles of every track
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
    rows, keys = explode(lo, hi, grid)  # rows are sorted: the tiles of track 0, then 1, ...
    copies = np.bincount(rows, minlength=len(tracks)).astype(np.int64)
    first_copy = np.cumsum(copies) - copies
    # every track's home: the first tile it is copied into (its picture counts are taken there)
    home_tile = keys[first_copy] if len(tracks) else np.zeros(0, np.int64)
    n_tiles = int(np.unique(keys).size)

    # 3. reports, as numbers, copied into tiles; one shuffle; each tile scores the pairs it owns
    shared = dask.delayed((track_ids, sources, first_copy, copies, keys), pure=True)
    to_tiles = dask.delayed(_to_tiles, pure=True)
    tiled = dd.from_delayed(
        [to_tiles(s[0], i, coords, shared) for i, s in enumerate(stage)],
        meta=_tiles_meta(coords),
        verify_meta=False,
    )
    tiled = tiled.shuffle("_tile", npartitions=max(1, min(n_tiles, 4 * nparts)))
    lookup = dask.delayed((grid, lo, hi, track_ids, sources, home_tile), pure=True)
    score = dask.delayed(_score_tiles, pure=True)
    done = dask.compute(*[score(p, coords, columns, lookup, options) for p in tiled.to_delayed()])
    pairs = pd.concat([d[0] for d in done], ignore_index=True)
    counts = [c for d in done for c in d[1]]
    cover = _time_cover([c for d in done for c in d[2]], len(tracks))
    return _gather(
        pairs, counts, cover, tracks, track_reports, dec, coords, options, recorded, n_tiles
    )


def _track_reports(
    tracks: pd.DataFrame, track_ids: NDArray[Any], sources: NDArray[Any], coords: str
) -> Reports:
    """The first report of every track: the :class:`Reports` of the distributed result."""
    names = PLANAR if coords == "planar" else GEOGRAPHIC
    _, inverse = np.unique(tracks["source"].to_numpy(), return_inverse=True)
    source = np.ascontiguousarray(inverse.reshape(-1), dtype=np.uint32)
    first = tracks[["track_id", "source", "first_time"] + [f"first_{n}" for n in names]]
    first.columns = ["track_id", "source", "time", *names]
    return Reports(
        first,
        coords=coords,
        track_ids=track_ids,
        track=np.arange(len(track_ids), dtype=np.uint32),
        sources=sources,
        source=source,
        time=np.ascontiguousarray(tracks["first_time"].to_numpy(np.float64)),
        aou=np.ascontiguousarray(first[list(names)].to_numpy(np.float64)),
    )


def _gather(
    pairs: pd.DataFrame,
    counts: list[dict[str, Any]],
    cover: dict[str, NDArray[Any]],
    tracks: pd.DataFrame,
    track_reports: Reports,
    decisions: Decisions,
    coords: str,
    options: dict[str, Any],
    recorded: dict[str, Any],
    tiles: int,
) -> DistributedAssociation:
    """The global step, once, with the engine's own ``finish``: covariance inflation, the
    posterior of every component (whole: components are never cut by tiles), triage, review
    order and objects, on the gathered pairs in the engine's order and the merged picture."""
    candidates = len(pairs)
    a = pairs["a"].to_numpy(np.uint32)
    b = pairs["b"].to_numpy(np.uint32)
    instants = pairs["instants"].to_numpy(np.int64)
    order = np.lexsort((b, a))
    keep = order[instants[order] > 0]
    if len(order) > 1:
        key = a[order].astype(np.int64) * len(track_reports.track_ids) + b[order]
        if (np.diff(key) == 0).any():  # pragma: no cover - ownership makes this impossible
            raise GeofeasError("internal: a candidate pair was scored in two tiles")
    stats = {
        name: np.ascontiguousarray(pairs[name].to_numpy(dtype)[keep]) for name, dtype in _STATS
    }
    spread = tracks["spread"].to_numpy(np.float64)
    with decisions.naming_rows():
        raw = _core.association_finish(
            {"source": track_reports.source, "spread": np.ascontiguousarray(spread), **cover},
            {
                "a": np.ascontiguousarray(a[keep]),
                "b": np.ascontiguousarray(b[keep]),
                "candidates": candidates,
                **stats,
            },
            counts,
            decisions,
            geographic=coords == "geographic",
            options=options,
        )
    result = DistributedAssociation(track_reports, raw, recorded, tracks, tiles)
    result.decisions = decisions
    return result
