"""Simulated multi-source maritime picture over a real AIS recording.

The trajectories are real (an :class:`~geofeas.io.ais.AisRecording`, linearly interpolated between
reports); the sources observing them are simulated, each with its own track numbering, detection
probability, track breaks after missed updates and false tracks:

``ais``
    the vessels' self-reports at the recorded instants, GPS error sigma 10 m (2-sigma AOU circle
    of 20 m), one track per MMSI.
``radar``
    a coastal surveillance radar at a fixed shore site, range sigma 20 m and bearing sigma 0.5 deg,
    so the AOU is elongated across the line of sight and grows with range; a scan every 3 s (each
    vessel is seen when the beam sweeps it), instrumented range 24 km, detection probability 0.9,
    a track is dropped after 3 missed scans and a new number is given at re-detection.
``aircraft``
    a maritime patrol aircraft orbiting over the traffic for the middle half of the recording; its
    surface-search radar has range sigma 50 m, bearing sigma 1 deg and a navigation / registration
    error of 100 m, i.e. AOUs of hundreds of metres; an update every 10 s, detection probability
    0.8.
``hfdf``
    an HF direction-finding net of two distant stations (100 and 150 km away, 20 deg apart as seen
    from the area) with bearing sigma 2 deg: fixes whose AOUs are kilometres long and very
    elongated; only a third of the vessels emit on HF, a few times an hour.

Every non-AIS position is the truth plus a draw from the Gaussian of its own AOU (2-sigma semi-axes
``rx, ry``, bearing of ``rx`` clockwise from north), so the reported AOUs are statistically
consistent with the errors. Randomness comes from ``numpy.random.default_rng([seed, k])`` with
one fixed ``k`` per source, so a source's reports do not change when another is switched off.

The parameters and their justification are documented in ``docs/demo.md``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from .. import geodesy
from .._core import GeofeasError
from ..geodesy import delta_lon, median_lon, metres_per_degree, wrap_lon
from ..io.ais import AisRecording
from ..scores import from_gaussian, to_gaussian

__all__ = [
    "AisSensor",
    "CoastalRadar",
    "HfDf",
    "PatrolAircraft",
    "SENSORS",
    "Scenario",
    "aou_from_covariance",
    "covariance_from_aou",
    "metres_per_degree",
    "simulate",
]

REPORT_COLUMNS = ("track_id", "source", "time", "lat", "lon", "rx", "ry", "bearing", "mmsi")

# ----------------------------------------------------------------------------------- geometry


def _direct(lat: Any, lon: Any, azi: Any, dist: Any) -> tuple[np.ndarray, np.ndarray]:
    """The ends of the WGS84 geodesics of ``dist`` metres leaving ``(lat, lon)`` at azimuth
    ``azi`` (degrees clockwise from north), broadcast."""
    la, lo, _ = geodesy.direct(lat, lon, azi, dist)
    return la, lo


def _offset(lat: np.ndarray, lon: np.ndarray, de: np.ndarray, dn: np.ndarray) -> tuple[Any, Any]:
    """``(lat, lon)`` moved by ``de`` metres east and ``dn`` metres north: along the geodesic of
    length ``hypot(de, dn)`` and azimuth ``atan2(de, dn)``."""
    de, dn = np.asarray(de, dtype=np.float64), np.asarray(dn, dtype=np.float64)
    return _direct(lat, lon, np.degrees(np.arctan2(de, dn)), np.hypot(de, dn))


def _destination(lat: float, lon: float, bearing_deg: float, dist: float) -> tuple[float, float]:
    """Point ``dist`` metres from ``(lat, lon)`` along the geodesic of initial bearing."""
    la, lo = _direct(lat, lon, bearing_deg, dist)
    return float(la), float(lo)


def _range_bearing(lat1: Any, lon1: Any, lat2: Any, lon2: Any) -> tuple[np.ndarray, np.ndarray]:
    """Geodesic range (m) from point 1 to point 2 and the bearing of the line of sight *at
    point 2* (degrees in ``[0, 360)`` clockwise from north, pointing away from point 1): the
    WGS84 geodesic's length and forward azimuth at point 2 (the core's ``geodesic_inverse``)."""
    s12, _, azi2 = geodesy.inverse(lat1, lon1, lat2, lon2)
    return s12, azi2 % 360.0


def covariance_from_aou(rx: Any, ry: Any, bearing_deg: Any) -> np.ndarray:
    """East/north covariance ``(..., 2, 2)`` of 2-sigma AOUs (seed 000, eqs. 56-58): the core's
    :func:`geofeas.to_gaussian` of the ellipses ``(0, 0, rx, ry, bearing)``."""
    rx, ry, b = np.broadcast_arrays(
        np.asarray(rx, dtype=np.float64),
        np.asarray(ry, dtype=np.float64),
        np.radians(np.asarray(bearing_deg, dtype=np.float64)),
    )
    zero = np.zeros(rx.size)
    ellipses = np.column_stack([zero, zero, rx.ravel(), ry.ravel(), b.ravel()])
    _, cov = to_gaussian(ellipses)
    return cov.reshape(rx.shape + (2, 2))


def aou_from_covariance(cov: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """2-sigma semi-axes ``rx >= ry`` and the bearing (degrees in ``[0, 180)``) of the ``rx``
    axis of east/north covariances ``(..., 2, 2)`` (positive definite): the core's
    :func:`geofeas.from_gaussian` (eqs. 56-59), the inverse of :func:`covariance_from_aou`."""
    cov = np.asarray(cov, dtype=np.float64)
    shape = cov.shape[:-2]
    flat = cov.reshape(-1, 2, 2)
    e = from_gaussian(np.zeros((len(flat), 2)), flat)
    bearing = np.degrees(e[:, 4]) % 180.0
    return e[:, 2].reshape(shape), e[:, 3].reshape(shape), bearing.reshape(shape)


def _draw(rng: np.random.Generator, rx: np.ndarray, ry: np.ndarray, bearing: np.ndarray) -> Any:
    """East/north errors drawn from the Gaussian of each AOU."""
    b = np.radians(bearing)
    z1, z2 = rng.standard_normal(len(rx)), rng.standard_normal(len(rx))
    a1, a2 = rx / 2 * z1, ry / 2 * z2
    return a1 * np.sin(b) + a2 * np.cos(b), a1 * np.cos(b) - a2 * np.sin(b)


# ----------------------------------------------------------------------------------- truth


@dataclass(frozen=True)
class Truth:
    """Interpolated vessel positions: the trajectories of the recording.

    Between two reports of a vessel its position is interpolated linearly when the reports are
    at most ``max_gap`` seconds apart, or (a vessel at anchor or moored, which reports only every
    3 min) at most ``max_still_gap`` apart and less than ``still_distance`` metres apart. Elsewhere
    the truth is unknown and no sensor sees the vessel. Longitudes are interpolated along each
    vessel's path continued across the antimeridian (``_path_lon``, computed once) and wrapped.
    """

    mmsi: np.ndarray
    offsets: np.ndarray
    time: np.ndarray
    lat: np.ndarray
    lon: np.ndarray
    max_gap: float = 180.0
    max_still_gap: float = 900.0
    still_distance: float = 100.0
    #: each vessel's longitudes made continuous (no jump of 360 degrees between two reports)
    _path_lon: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        # a whole turn added after each crossing of the antimeridian (a step of more than half a
        # turn between two reports), counted from each vessel's first report: a path that never
        # crosses keeps its longitudes to the bit
        lon = np.asarray(self.lon, dtype=np.float64)
        step = np.diff(lon)
        turn = np.where(step > 180.0, -1, np.where(step < -180.0, 1, 0))
        turns = np.concatenate([[0], np.cumsum(turn)])[: len(lon)]
        starts = np.asarray(self.offsets[:-1], dtype=np.int64)
        turns -= np.repeat(turns[starts], np.diff(self.offsets))
        object.__setattr__(self, "_path_lon", lon + 360.0 * turns)

    @classmethod
    def from_recording(cls, rec: AisRecording, **options: float) -> Truth:
        t = rec.tracks
        mmsi = t["mmsi"].to_numpy()
        starts = np.concatenate([[0], np.flatnonzero(np.diff(mmsi)) + 1, [len(mmsi)]])
        return cls(
            mmsi[starts[:-1]],
            starts,
            t["time"].to_numpy(np.float64),
            t["lat"].to_numpy(np.float64),
            t["lon"].to_numpy(np.float64),
            **options,
        )

    def __len__(self) -> int:
        return len(self.mmsi)

    def vessel(self, k: int, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``lat, lon, known`` of vessel ``k`` at times ``q`` (any shape)."""
        q = np.asarray(q, dtype=np.float64)
        lat = np.full(q.shape, np.nan)
        lon = np.full(q.shape, np.nan)
        a, b = self.offsets[k], self.offsets[k + 1]
        tv, la, lo = self.time[a:b], self.lat[a:b], self._path_lon[a:b]
        inside = (q >= tv[0]) & (q <= tv[-1])
        if len(tv) == 1 or not inside.any():
            lat[inside], lon[inside] = la[0], self.lon[a]
            return lat, lon, inside
        j = np.clip(np.searchsorted(tv, q, side="right"), 1, len(tv) - 1)
        gap = tv[j] - tv[j - 1]
        m_lat, m_lon = metres_per_degree(la[j])
        step = np.hypot((la[j] - la[j - 1]) * m_lat, (lo[j] - lo[j - 1]) * m_lon)
        good = inside & (
            (gap <= self.max_gap)
            | ((gap <= self.max_still_gap) & (step <= self.still_distance))
            | (q == tv[j - 1])
            | (q == tv[j])
        )
        lat[good] = np.interp(q[good], tv, la)
        lon[good] = wrap_lon(np.interp(q[good], tv, lo))
        return lat, lon, good

    def at(self, times: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Positions of every vessel at ``times`` of shape ``(V, S)`` (or ``(S,)``, shared).

        Returns ``lat, lon`` of shape ``(V, S)`` and the mask where the truth is known.
        """
        v = len(self)
        times = np.broadcast_to(np.asarray(times, dtype=np.float64), (v, np.shape(times)[-1]))
        lat = np.full(times.shape, np.nan)
        lon = np.full(times.shape, np.nan)
        ok = np.zeros(times.shape, dtype=bool)
        for k in range(v):
            lat[k], lon[k], ok[k] = self.vessel(k, times[k])
        return lat, lon, ok


# ----------------------------------------------------------------------------------- sensors


@dataclass(frozen=True)
class AisSensor:
    """AIS self-reports at the recorded instants.

    ``sigma``: GPS horizontal error (1-sigma, metres, per axis); the AOU is the 2-sigma circle.
    ``loss_probability``: extra message loss at the fusion centre (0: the recording is what was
    received).
    """

    sigma: float = 10.0
    loss_probability: float = 0.0
    name: str = "ais"
    stream: int = 1


@dataclass(frozen=True)
class _Tracked:
    """Track management shared by the simulated trackers."""

    detection_probability: float = 0.9
    coast: int = 3  # missed updates tolerated before the track is dropped (then renumbered)
    confirm: int = 2  # detections needed before a track is reported
    false_tracks_per_hour: float = 20.0
    false_track_life: float = 90.0  # mean life of a false track, s
    false_track_speed: float = 4.0  # max speed of a false track, m/s


@dataclass(frozen=True)
class CoastalRadar(_Tracked):
    """A coastal surveillance radar at a fixed site.

    ``site``: ``(lat, lon)``; ``None`` chooses a point off the traffic (land or shore) nearest to
    the densest traffic (:func:`choose_radar_site`).
    """

    site: tuple[float, float] | None = None
    range_sigma: float = 20.0
    bearing_sigma: float = 0.5  # degrees
    max_range: float = 24_000.0
    min_range: float = 100.0
    scan_period: float = 3.0
    name: str = "radar"
    stream: int = 2


@dataclass(frozen=True)
class PatrolAircraft(_Tracked):
    """A maritime patrol aircraft orbiting over the traffic for part of the recording."""

    speed: float = 100.0  # m/s (about 195 kn, a patrol speed at low level)
    orbit_radius: float | None = None  # None: half the spread of the traffic, 3-15 km
    on_station: tuple[float, float] = (0.25, 0.75)  # fractions of the recording
    range_sigma: float = 50.0
    bearing_sigma: float = 1.0  # degrees
    navigation_sigma: float = 100.0  # platform position / registration error, per axis
    max_range: float = 40_000.0
    update_period: float = 10.0
    detection_probability: float = 0.8
    coast: int = 2
    false_tracks_per_hour: float = 15.0
    false_track_life: float = 120.0
    name: str = "aircraft"
    stream: int = 3


@dataclass(frozen=True)
class HfDf:
    """An HF direction-finding net of two distant stations giving cross-bearing fixes.

    ``stations``: ``((range_m, bearing_deg), ...)`` from the traffic centre to each station.
    """

    stations: tuple[tuple[float, float], ...] = ((100_000.0, 205.0), (150_000.0, 225.0))
    bearing_sigma: float = 2.0  # degrees, per station
    emitter_fraction: float = 0.1
    transmission_interval: float = 600.0  # mean time between transmissions of an emitter, s
    session_gap: float = 1800.0  # silence after which the DF track is renumbered, s
    false_tracks_per_hour: float = 2.0
    name: str = "hfdf"
    stream: int = 4


#: The sources by name, with their default parameters.
SENSORS: dict[str, Any] = {
    "ais": AisSensor(),
    "radar": CoastalRadar(),
    "aircraft": PatrolAircraft(),
    "hfdf": HfDf(),
}


# ----------------------------------------------------------------------------------- scenario


@dataclass
class Scenario:
    """Simulated reports of all sources with their ground truth.

    Attributes
    ----------
    reports : pandas.DataFrame
        ``track_id, source, time, lat, lon, rx, ry, bearing, mmsi``: ``time`` is ISO-8601 UTC,
        ``rx, ry`` 2-sigma semi-axes in metres, ``bearing`` of ``rx`` in degrees clockwise from
        true north; ``mmsi`` is the truth (-1 for a false track). Sorted by time.
    seconds : numpy.ndarray
        ``time`` as seconds since the Unix epoch (same order as ``reports``).
    geometry : dict
        Sensor sites, aircraft path and HF DF station positions (for maps and docs).
    """

    reports: pd.DataFrame
    seconds: np.ndarray
    geometry: dict[str, Any] = field(default_factory=dict)

    def counts(self) -> pd.DataFrame:
        """Reports, tracks and false tracks per source."""
        r = self.reports
        g = r.groupby("source", sort=False)
        return pd.DataFrame(
            {
                "reports": g.size(),
                "tracks": g["track_id"].nunique(),
                "false_tracks": r[r["mmsi"] < 0]
                .groupby("source", sort=False)["track_id"]
                .nunique()
                .reindex(g.size().index, fill_value=0),
                "vessels": r[r["mmsi"] >= 0]
                .groupby("source", sort=False)["mmsi"]
                .nunique()
                .reindex(g.size().index, fill_value=0),
            }
        )


def _traffic_centre(rec: AisRecording) -> tuple[float, float]:
    t = rec.tracks
    return float(np.median(t["lat"])), median_lon(t["lon"])


def choose_radar_site(
    rec: AisRecording, *, cell: float = 250.0, clearance: int = 2
) -> tuple[float, float]:
    """A coastal radar site: the point off the traffic nearest to the densest traffic.

    Vessel-minutes are counted on a 1 km grid to find the densest area; on a ``cell``-metre grid
    the cells within ``clearance`` cells of any AIS position are water (or traffic lanes); the
    site is the centre of the non-water cell nearest to the densest area, i.e. usually a point of
    the shore overlooking the busiest water. No coastline database is needed.
    """
    t = rec.tracks
    lat0, lon0 = _traffic_centre(rec)
    m_lat, m_lon = metres_per_degree(lat0)
    x = delta_lon(t["lon"].to_numpy(), lon0) * m_lon
    y = (t["lat"].to_numpy() - lat0) * m_lat
    lo_x, hi_x = np.quantile(x, [0.02, 0.98])
    lo_y, hi_y = np.quantile(y, [0.02, 0.98])
    minute = ((t["time"].to_numpy() - rec.start) // 60).astype(np.int64)
    # densest 1 km cell by distinct vessel-minutes
    cx, cy = np.floor(x / 1000).astype(np.int64), np.floor(y / 1000).astype(np.int64)
    keys = pd.DataFrame({"cx": cx, "cy": cy, "m": t["mmsi"].to_numpy(), "mi": minute})
    dens = keys.drop_duplicates().groupby(["cx", "cy"]).size()
    bx, by = dens.idxmax()
    dense = ((bx + 0.5) * 1000.0, (by + 0.5) * 1000.0)
    # occupancy grid
    x0, y0 = lo_x - 2000, lo_y - 2000
    nx = int((hi_x + 2000 - x0) // cell) + 1
    ny = int((hi_y + 2000 - y0) // cell) + 1
    occ = np.zeros((nx, ny), dtype=bool)
    ix = np.clip(((x - x0) // cell).astype(np.int64), 0, nx - 1)
    iy = np.clip(((y - y0) // cell).astype(np.int64), 0, ny - 1)
    occ[ix, iy] = True
    water = occ.copy()
    for dx in range(-clearance, clearance + 1):
        for dy in range(-clearance, clearance + 1):
            water |= np.roll(np.roll(occ, dx, axis=0), dy, axis=1)
    free = np.argwhere(~water)
    if len(free) == 0:
        sx, sy = dense
    else:
        px = x0 + (free[:, 0] + 0.5) * cell
        py = y0 + (free[:, 1] + 0.5) * cell
        k = int(np.argmin(np.hypot(px - dense[0], py - dense[1])))
        sx, sy = px[k], py[k]
    return lat0 + sy / m_lat, float(wrap_lon(lon0 + sx / m_lon))


def _iso(seconds: np.ndarray) -> np.ndarray:
    ms = np.round(np.asarray(seconds) * 1000).astype("int64").astype("datetime64[ms]")
    return np.datetime_as_string(ms, unit="ms")


def _frame(
    source: str,
    track: np.ndarray,
    t: np.ndarray,
    lat: np.ndarray,
    lon: np.ndarray,
    rx: np.ndarray,
    ry: np.ndarray,
    bearing: np.ndarray,
    mmsi: np.ndarray,
) -> pd.DataFrame:
    return pd.DataFrame(
        {
            "track_id": track,
            "source": source,
            "t": t,
            "lat": lat,
            "lon": lon,
            "rx": rx,
            "ry": ry,
            "bearing": bearing % 360.0,
            "mmsi": mmsi.astype(np.int64),
        }
    )


def _simulate_ais(sensor: AisSensor, truth: Truth, rng: np.random.Generator) -> pd.DataFrame:
    n = len(truth.time)
    keep = rng.random(n) >= sensor.loss_probability
    mmsi = np.repeat(truth.mmsi, np.diff(truth.offsets))[keep]
    lat, lon = truth.lat[keep], truth.lon[keep]
    r = np.full(len(lat), 2 * sensor.sigma)
    b = np.zeros(len(lat))
    de, dn = _draw(rng, r, r, b)
    la, lo = _offset(lat, lon, de, dn)
    ids = np.char.add(f"{sensor.name}-", mmsi.astype(str))
    return _frame(sensor.name, ids, truth.time[keep], la, lo, r, r, b, mmsi)


#: Update times simulated per block: memory stays O(vessels x _BLOCK + reports).
_BLOCK = 512

Observe = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]
Coverage = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]


def _track_numbers(
    rows: np.ndarray, cols: np.ndarray, coast: int, confirm: int
) -> tuple[np.ndarray, np.ndarray]:
    """Track management over detections ``(rows, cols)`` sorted by row then column.

    A track is reported from its ``confirm``-th detection on and dropped after more than
    ``coast`` consecutive missed updates; the next detection starts a new track. Returns the
    mask of the reported detections and, for them, a track number (numbered in order of the
    track's first report).
    """
    n = len(rows)
    if n == 0:
        return np.zeros(0, dtype=bool), np.zeros(0, dtype=np.int64)
    new = np.ones(n, dtype=bool)
    new[1:] = (rows[1:] != rows[:-1]) | (cols[1:] - cols[:-1] > coast + 1)
    seg = np.cumsum(new) - 1
    first = np.flatnonzero(new)
    keep = np.arange(n) - first[seg] >= confirm - 1
    seg = seg[keep]
    uniq, inv = np.unique(seg, return_inverse=True)
    start_col = np.full(len(uniq), np.iinfo(np.int64).max)
    np.minimum.at(start_col, inv, cols[keep])
    order = np.lexsort((uniq, start_col))
    number = np.empty(len(uniq), dtype=np.int64)
    number[order] = np.arange(len(uniq))
    return keep, number[inv]


def _vessel_detections(
    n_updates: int, observe: Observe, probability: float, rng: np.random.Generator
) -> tuple[np.ndarray, ...]:
    """Detections of the real vessels: ``observe(cols) -> lat, lon, visible, time`` (each
    ``(V, len(cols))``) block by block, each visible vessel detected with ``probability``."""
    parts: list[tuple[np.ndarray, ...]] = []
    for c0 in range(0, n_updates, _BLOCK):
        cols = np.arange(c0, min(c0 + _BLOCK, n_updates))
        la, lo, ok, t = observe(cols)
        det = ok & (rng.random(ok.shape) < probability)
        r, c = np.nonzero(det)
        parts.append((r, cols[c], la[r, c], lo[r, c], t[r, c]))
    if not parts:
        return tuple(np.zeros(0) for _ in range(5))
    return tuple(np.concatenate(p) for p in zip(*parts, strict=True))


def _false_detections(
    sensor: Any,
    rng: np.random.Generator,
    times: np.ndarray,
    anchors: tuple[np.ndarray, np.ndarray],
    coverage: Coverage,
) -> tuple[np.ndarray, ...]:
    """Detections of false tracks: born at a uniform time 200-2000 m from a random detected
    vessel position (sea clutter and wakes are on the water), moving at a constant random
    velocity for an exponential life; returns ``(track, cols, lat, lon, time)``."""
    duration = float(times[-1] - times[0]) if len(times) > 1 else 0.0
    n = int(rng.poisson(sensor.false_tracks_per_hour * duration / 3600.0))
    if n == 0 or len(anchors[0]) == 0:
        return tuple(np.zeros(0) for _ in range(5))
    birth = rng.uniform(times[0], times[-1], n)
    life = rng.exponential(sensor.false_track_life, n)
    pick = rng.integers(0, len(anchors[0]), n)
    dist = rng.uniform(200.0, 2000.0, n)
    ang = rng.uniform(0, 2 * np.pi, n)
    speed = rng.uniform(0, sensor.false_track_speed, n)
    head = rng.uniform(0, 2 * np.pi, n)
    la0, lo0 = _offset(anchors[0][pick], anchors[1][pick], dist * np.sin(ang), dist * np.cos(ang))
    c0 = np.searchsorted(times, birth, side="left")
    c1 = np.searchsorted(times, birth + life, side="right")
    count = np.maximum(c1 - c0, 0)
    track = np.repeat(np.arange(n), count)
    cols = np.repeat(c0, count) + (
        np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    )
    t = times[cols]
    dt = t - birth[track]
    la, lo = _offset(
        la0[track],
        lo0[track],
        (speed * np.sin(head))[track] * dt,
        (speed * np.cos(head))[track] * dt,
    )
    det = coverage(la, lo, cols) & (rng.random(len(cols)) < sensor.detection_probability)
    return track[det], cols[det], la[det], lo[det], t[det]


def _tracker_reports(
    sensor: Any,
    rng: np.random.Generator,
    times: np.ndarray,
    mmsi: np.ndarray,
    observe: Observe,
    coverage: Coverage,
    covariance: Callable[[np.ndarray, np.ndarray, np.ndarray], tuple[Any, Any, Any]],
) -> pd.DataFrame:
    """Detections, track numbers and noisy reports of a tracking sensor at update ``times``.

    ``observe(cols)`` gives the vessels' truth, visibility and observation time at those
    updates; ``coverage(lat, lon, cols)`` the visibility of a false track;
    ``covariance(cols, lat, lon) -> (rx, ry, bearing)`` the AOU of each report.
    """
    v = len(mmsi)
    rows, cols, la, lo, t = _vessel_detections(
        len(times), observe, sensor.detection_probability, rng
    )
    f_track, f_cols, f_la, f_lo, f_t = _false_detections(sensor, rng, times, (la, lo), coverage)
    rows = np.concatenate([rows, v + f_track]).astype(np.int64)
    cols = np.concatenate([cols, f_cols]).astype(np.int64)
    la, lo, t = np.concatenate([la, f_la]), np.concatenate([lo, f_lo]), np.concatenate([t, f_t])
    truth = np.concatenate([mmsi, np.full(int(f_track.max()) + 1 if len(f_track) else 0, -1)])
    order = np.lexsort((cols, rows))
    rows, cols, la, lo, t = rows[order], cols[order], la[order], lo[order], t[order]
    # a vessel crossing the sweep's start (north) is seen at the end of one scan and again at
    # the start of the next, milliseconds later: the plot extractor keeps one plot per scan
    period = float(np.median(np.diff(times))) if len(times) > 1 else 1.0
    twin = np.zeros(len(rows), dtype=bool)
    twin[1:] = (rows[1:] == rows[:-1]) & (t[1:] - t[:-1] < 0.5 * period)
    rows, cols, la, lo, t = rows[~twin], cols[~twin], la[~twin], lo[~twin], t[~twin]
    keep, number = _track_numbers(rows, cols, sensor.coast, sensor.confirm)
    rows, cols, la, lo, t = rows[keep], cols[keep], la[keep], lo[keep], t[keep]
    rx, ry, b = covariance(cols, la, lo)
    de, dn = _draw(rng, rx, ry, b)
    pla, plo = _offset(la, lo, de, dn)
    ids = np.char.add(f"{sensor.name}-", np.char.zfill(number.astype(str), 4))
    return _frame(sensor.name, ids, t, pla, plo, rx, ry, b, truth[rows])


def _simulate_radar(
    sensor: CoastalRadar, truth: Truth, rec: AisRecording, rng: np.random.Generator, geo: dict
) -> pd.DataFrame:
    site = sensor.site if sensor.site is not None else choose_radar_site(rec)
    geo["radar_site"] = site
    scans = np.arange(rec.start, rec.end, sensor.scan_period)

    def visible(la: np.ndarray, lo: np.ndarray) -> np.ndarray:
        r, _ = _range_bearing(site[0], site[1], la, lo)
        return (r >= sensor.min_range) & (r <= sensor.max_range)

    def observe(cols: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        # the beam sweeps clockwise from north: a vessel at bearing b is seen b/360 of a scan late
        lat, lon, _ = truth.at(scans[cols])
        _, los = _range_bearing(
            site[0], site[1], np.nan_to_num(lat, nan=site[0]), np.nan_to_num(lon, nan=site[1])
        )
        seen = scans[cols][None, :] + sensor.scan_period * los / 360.0
        lat, lon, ok = truth.at(seen)
        ok &= visible(np.nan_to_num(lat, nan=site[0]), np.nan_to_num(lon, nan=site[1]))
        return lat, lon, ok, seen

    def cov(cols: np.ndarray, la: np.ndarray, lo: np.ndarray) -> Any:
        r, los = _range_bearing(site[0], site[1], la, lo)
        across = 2 * r * np.radians(sensor.bearing_sigma)
        return across, np.full(len(r), 2 * sensor.range_sigma), los + 90.0

    return _tracker_reports(
        sensor, rng, scans, truth.mmsi, observe, lambda la, lo, _c: visible(la, lo), cov
    )


def _aircraft_path(
    sensor: PatrolAircraft, rec: AisRecording, times: np.ndarray, geo: dict
) -> tuple[np.ndarray, np.ndarray]:
    lat0, lon0 = _traffic_centre(rec)
    t = rec.tracks
    m_lat, m_lon = metres_per_degree(lat0)
    spread = np.median(np.hypot((t["lat"] - lat0) * m_lat, delta_lon(t["lon"], lon0) * m_lon))
    radius = sensor.orbit_radius or float(np.clip(spread, 3000.0, 15000.0))
    omega = sensor.speed / radius
    ang = omega * (times - times[0]) if len(times) else times
    la, lo = _offset(
        np.full(len(times), lat0),
        np.full(len(times), lon0),
        radius * np.sin(ang),
        radius * np.cos(ang),
    )
    geo["aircraft_orbit"] = {"centre": (lat0, lon0), "radius": radius}
    return la, lo


def _simulate_aircraft(
    sensor: PatrolAircraft, truth: Truth, rec: AisRecording, rng: np.random.Generator, geo: dict
) -> pd.DataFrame:
    f0, f1 = sensor.on_station
    t0 = rec.start + f0 * (rec.end - rec.start)
    t1 = rec.start + f1 * (rec.end - rec.start)
    times = np.arange(t0, t1, sensor.update_period)
    if len(times) == 0:
        e = np.zeros(0)
        return _frame(sensor.name, e.astype(str), e, e, e, e, e, e, e)
    alat, alon = _aircraft_path(sensor, rec, times, geo)
    geo["aircraft_path"] = (alat, alon)

    def visible(la: np.ndarray, lo: np.ndarray, cols: np.ndarray) -> np.ndarray:
        r, _ = _range_bearing(alat[cols], alon[cols], la, lo)
        return r <= sensor.max_range

    def observe(cols: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        lat, lon, ok = truth.at(times[cols])
        ok &= visible(
            np.nan_to_num(lat, nan=alat[0]), np.nan_to_num(lon, nan=alon[0]), cols[None, :]
        )
        return lat, lon, ok, np.broadcast_to(times[cols], lat.shape)

    def cov(cols: np.ndarray, la: np.ndarray, lo: np.ndarray) -> Any:
        r, los = _range_bearing(alat[cols], alon[cols], la, lo)
        across = np.hypot(r * np.radians(sensor.bearing_sigma), sensor.navigation_sigma)
        along = np.hypot(sensor.range_sigma, sensor.navigation_sigma)
        return 2 * across, np.full(len(r), 2 * along), los + 90.0

    return _tracker_reports(sensor, rng, times, truth.mmsi, observe, visible, cov)


def _simulate_hfdf(
    sensor: HfDf, truth: Truth, rec: AisRecording, rng: np.random.Generator, geo: dict
) -> pd.DataFrame:
    lat0, lon0 = _traffic_centre(rec)
    stations = [_destination(lat0, lon0, b, r) for r, b in sensor.stations]
    geo["hfdf_stations"] = stations
    v = len(truth)
    emitters = np.flatnonzero(rng.random(v) < sensor.emitter_fraction)
    duration = rec.end - rec.start
    t_list, v_list = [], []
    for k in emitters:
        n = int(rng.poisson(duration / sensor.transmission_interval))
        t_list.append(np.sort(rng.uniform(rec.start, rec.end, n)))
        v_list.append(np.full(n, k))
    t = np.concatenate(t_list) if t_list else np.zeros(0)
    vv = np.concatenate(v_list).astype(np.int64) if v_list else np.zeros(0, np.int64)
    lat = np.full(len(t), np.nan)
    lon = np.full(len(t), np.nan)
    ok = np.zeros(len(t), dtype=bool)
    for k in np.unique(vv):
        sel = vv == k
        lat[sel], lon[sel], ok[sel] = truth.vessel(int(k), t[sel])
    t, vv, lat, lon = t[ok], vv[ok], lat[ok], lon[ok]
    mmsi = truth.mmsi[vv]
    # false fixes: emitters ashore or unrelated, near the traffic, 1-3 fixes each
    nf = int(rng.poisson(sensor.false_tracks_per_hour * duration / 3600.0))
    if nf and len(rec.tracks):
        pick = rng.integers(0, len(rec.tracks), nf)
        base_la = rec.tracks["lat"].to_numpy()[pick]
        base_lo = rec.tracks["lon"].to_numpy()[pick]
        d, a = rng.uniform(500, 5000, nf), rng.uniform(0, 2 * np.pi, nf)
        fla, flo = _offset(base_la, base_lo, d * np.sin(a), d * np.cos(a))
        reps = rng.integers(1, 4, nf)
        ft = [np.sort(rng.uniform(rec.start, rec.end, r)) for r in reps]
        t = np.concatenate([t, *ft])
        lat = np.concatenate([lat, np.repeat(fla, reps)])
        lon = np.concatenate([lon, np.repeat(flo, reps)])
        vv = np.concatenate([vv, v + np.repeat(np.arange(nf), reps)])
        mmsi = np.concatenate([mmsi, np.full(int(reps.sum()), -1)])
    # DF tracks: one per emitter, renumbered after a long silence
    order = np.lexsort((t, vv))
    t, vv, lat, lon, mmsi = t[order], vv[order], lat[order], lon[order], mmsi[order]
    new = np.ones(len(t), dtype=bool)
    new[1:] = (vv[1:] != vv[:-1]) | (np.diff(t) > sensor.session_gap)
    seg = np.cumsum(new) - 1
    first_t = t[new]
    number = np.empty(len(first_t), dtype=np.int64)
    number[np.argsort(first_t, kind="stable")] = np.arange(len(first_t))
    ids = np.char.add(f"{sensor.name}-", np.char.zfill(number[seg].astype(str), 4))
    # cross-bearing fix covariance: J = sum n n^T / (r sigma)^2, n normal to each line of sight
    sig = np.radians(sensor.bearing_sigma)
    info = np.zeros((len(t), 2, 2))
    for s_lat, s_lon in stations:
        r, los = _range_bearing(s_lat, s_lon, lat, lon)
        b = np.radians(los)
        nrm = np.stack([np.cos(b), -np.sin(b)], axis=-1)
        info += nrm[:, :, None] * nrm[:, None, :] / ((r * sig) ** 2)[:, None, None]
    cov = np.linalg.inv(info) if len(t) else info
    rx, ry, bearing = aou_from_covariance(cov)
    de, dn = _draw(rng, rx, ry, bearing)
    pla, plo = _offset(lat, lon, de, dn)
    return _frame(sensor.name, ids, t, pla, plo, rx, ry, bearing, mmsi)


def simulate(
    recording: AisRecording,
    /,
    *,
    sensors: Sequence[str | Any] = ("ais", "radar", "aircraft", "hfdf"),
    seed: int = 0,
    minutes: float | None = None,
) -> Scenario:
    """Simulate the sources observing the vessels of an AIS recording.

    Parameters
    ----------
    recording : AisRecording
        From :func:`geofeas.io.ais.read_ais`.
    sensors : sequence of str or sensor objects, optional
        Names from :data:`SENSORS` (default parameters) or configured :class:`AisSensor`,
        :class:`CoastalRadar`, :class:`PatrolAircraft`, :class:`HfDf` objects.
    seed : int, optional
        Seed; each source draws from ``numpy.random.default_rng([seed, k])``.
    minutes : float, optional
        Use only the first ``minutes`` of the recording.

    Returns
    -------
    Scenario
    """
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise GeofeasError(f"seed must be a non-negative integer, got {seed!r}")
    rec = recording
    if minutes is not None:
        if not minutes > 0:
            raise GeofeasError(f"minutes must be > 0, got {minutes}")
        keep = rec.tracks["time"] <= rec.start + 60.0 * minutes
        rec = AisRecording(
            rec.tracks[keep].reset_index(drop=True),
            rec.removed,
            rec.corrected,
            rec.schema,
            rec.source,
        )
    truth = Truth.from_recording(rec)
    geo: dict[str, Any] = {"centre": _traffic_centre(rec)}
    frames = []
    seen_names = set()
    for spec in sensors:
        if isinstance(spec, str):
            if spec not in SENSORS:
                raise GeofeasError(f"unknown sensor {spec!r}; expected one of {sorted(SENSORS)}")
            spec = SENSORS[spec]
        if spec.name in seen_names:
            raise GeofeasError(f"sensor {spec.name!r} given twice")
        seen_names.add(spec.name)
        rng = np.random.default_rng([int(seed), spec.stream])
        if isinstance(spec, AisSensor):
            frames.append(_simulate_ais(spec, truth, rng))
        elif isinstance(spec, CoastalRadar):
            frames.append(_simulate_radar(spec, truth, rec, rng, geo))
        elif isinstance(spec, PatrolAircraft):
            frames.append(_simulate_aircraft(spec, truth, rec, rng, geo))
        elif isinstance(spec, HfDf):
            frames.append(_simulate_hfdf(spec, truth, rec, rng, geo))
        else:
            raise GeofeasError(f"not a sensor: {spec!r}")
    if not frames:
        raise GeofeasError("no sensor given")
    out = pd.concat(frames, ignore_index=True)
    out["t"] = np.round(out["t"].to_numpy(np.float64), 3)  # times are written to the millisecond
    out = out.sort_values(["t", "source", "track_id"], kind="stable")
    # two reports of one track at one millisecond (two HF DF fixes drawn at the same instant)
    same = out.duplicated(["track_id", "t"], keep="first").to_numpy()
    geo["same_time_reports_dropped"] = int(same.sum())
    out = out[~same].reset_index(drop=True)
    seconds = out.pop("t").to_numpy(np.float64)
    out.insert(2, "time", _iso(seconds))
    return Scenario(out[list(REPORT_COLUMNS)], seconds, geo)
