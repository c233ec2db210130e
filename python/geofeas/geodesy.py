"""WGS84 geodesy of the library: the core's geodesics (Karney's algorithms, geographiclib-rs)
over broadcast NumPy arrays, and the local metres per degree.

Every module that needs a distance, a bearing or a point at a distance on the Earth (the AIS
reader's impossible-jump test, the demo's sensors, the review station's map) calls these, so the
project has one Earth model.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _core

__all__ = [
    "WGS84_A",
    "WGS84_F",
    "delta_lon",
    "direct",
    "inverse",
    "median_lon",
    "metres_per_degree",
    "wrap_lon",
]

#: WGS84 semi-major axis (m) and flattening, as the core uses them.
WGS84_A: float = _core.WGS84_A
WGS84_F: float = _core.WGS84_F
_E2 = WGS84_F * (2 - WGS84_F)


def _columns(*values: Any) -> tuple[tuple[int, ...], list[np.ndarray]]:
    """The broadcast shape of ``values`` and each as a contiguous float64 column (a view where
    the input already is one)."""
    arrays = np.broadcast_arrays(*(np.asarray(v, dtype=np.float64) for v in values))
    return arrays[0].shape, [np.ascontiguousarray(a).ravel() for a in arrays]


def inverse(lat1: Any, lon1: Any, lat2: Any, lon2: Any) -> tuple[np.ndarray, ...]:
    """Length ``s12`` (m) of the geodesics from ``(lat1, lon1)`` to ``(lat2, lon2)`` (degrees,
    broadcast) and their azimuths ``azi1`` at the start and ``azi2`` (forward) at the end, in
    degrees clockwise from north. Bad coordinates raise a ``GeofeasError`` naming the row."""
    shape, cols = _columns(lat1, lon1, lat2, lon2)
    return tuple(c.reshape(shape) for c in _core.geodesic_inverse(*cols))


def direct(lat1: Any, lon1: Any, azi1: Any, s12: Any) -> tuple[np.ndarray, ...]:
    """The ends ``(lat2, lon2)`` of the geodesics of length ``s12`` (m) leaving ``(lat1, lon1)``
    at azimuth ``azi1`` (degrees clockwise from north), broadcast, and their forward azimuths
    ``azi2`` there."""
    shape, cols = _columns(lat1, lon1, azi1, s12)
    return tuple(c.reshape(shape) for c in _core.geodesic_direct(*cols))


def metres_per_degree(lat: Any) -> tuple[np.ndarray, np.ndarray]:
    """Metres per degree of latitude and of longitude at ``lat`` on the WGS84 ellipsoid.

    The meridional radius ``M = a (1 - e^2) / W^3`` and the prime-vertical radius ``N = a / W``
    with ``W = sqrt(1 - e^2 sin^2 lat)``; a small east/north offset ``(de, dn)`` in metres is
    ``(de / (N cos lat), dn / M)`` in radians.
    """
    p = np.radians(lat)
    w = np.sqrt(1 - _E2 * np.sin(p) ** 2)
    m = WGS84_A * (1 - _E2) / w**3
    n = WGS84_A / w
    return np.radians(1.0) * m, np.radians(1.0) * n * np.cos(p)


def wrap_lon(lon: Any) -> np.ndarray:
    """Longitudes (degrees) brought into ``[-180, 180)``; those already in it are returned as
    they are, to the bit."""
    lon = np.asarray(lon, dtype=np.float64)
    inside = (lon >= -180.0) & (lon < 180.0)
    return np.where(inside, lon, (lon + 180.0) % 360.0 - 180.0)


def delta_lon(lon: Any, lon0: Any) -> np.ndarray:
    """``lon - lon0`` (degrees) the short way round, in ``[-180, 180)``: across the antimeridian
    179.9 - (-179.9) is -0.2, not 359.8."""
    return wrap_lon(np.asarray(lon, dtype=np.float64) - np.asarray(lon0, dtype=np.float64))


def median_lon(lon: Any) -> float:
    """The median of longitudes (degrees) that lie within half a turn of one another, taken
    about the first, so that points on both sides of the antimeridian have theirs on it; the
    plain median when they do not straddle it."""
    lon = np.asarray(lon, dtype=np.float64).ravel()
    if lon.size == 0:
        return float("nan")
    if lon.max() - lon.min() <= 180.0:
        return float(np.median(lon))
    return float(wrap_lon(lon[0] + np.median(delta_lon(lon, lon[0]))))
