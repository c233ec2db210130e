"""Coastlines for the review map from GSHHG (Wessel and Smith, "A global, self-consistent,
hierarchical, high-resolution shoreline database", JGR 1996), as GMT ships it: the binned netCDF
files of Debian's ``gmt-gshhg-full`` / ``gmt-gshhg-high`` packages, read offline with h5py and
clipped with shapely. Nothing is ever downloaded.

GMT's binned format: the globe is cut into square bins (``Bin_size_in_minutes``), numbered row by
row from the north-west; each bin holds the pieces ("segments") of the shoreline polygons that
cross it, as points in 1/65535 of the bin side relative to its south-west corner. A segment's
packed word holds its point count (bits 9 and up) and its level (bits 6-8: 1 land, 2 lake,
3 island in a lake, 4 pond). The segments are drawn as polylines.
"""

from __future__ import annotations

import functools
import math
import os
from pathlib import Path

import numpy as np

__all__ = ["Coastline", "coastline", "gshhg_file"]

#: Folders searched for ``binned_GSHHS_<res>.nc`` (``GEOFEAS_GSHHG`` first, when set).
SEARCH = ("/usr/share/gmt-gshhg", "/usr/share/gmt/coast", "/usr/share/gshhg-gmt-nc4")
#: Resolutions, finest first (full, high, intermediate, low, crude).
RESOLUTIONS = ("f", "h", "i", "l", "c")


def gshhg_file() -> Path | None:
    """The finest installed GSHHG binned shoreline file, or ``None``."""
    folders = [os.environ["GEOFEAS_GSHHG"]] if os.environ.get("GEOFEAS_GSHHG") else []
    folders += list(SEARCH)
    for res in RESOLUTIONS:
        for folder in folders:
            p = Path(folder) / f"binned_GSHHS_{res}.nc"
            if p.is_file():
                return p
    return None


class Coastline:
    """Shoreline polylines of a lat/lon box: ``lines`` is a list of ``(n, 2)`` arrays of
    ``(lon, lat)`` degrees; ``source`` names the file (``None`` when no data is installed)."""

    def __init__(self, lines: list[np.ndarray], source: str | None) -> None:
        self.lines = lines
        self.source = source
        self._geometry: object = None

    def clip(self, south: float, west: float, north: float, east: float) -> list[np.ndarray]:
        """The polylines inside a smaller box (in memory: no file is read), with longitudes in
        the box's range. Near the antimeridian the box and the lines may be written on either
        side of it (179.9 or -180.1): each turn of 360 degrees is tried."""
        import shapely

        if not self.lines:
            return []
        if self._geometry is None:
            self._geometry = shapely.MultiLineString(self.lines)
        out: list[np.ndarray] = []
        lo, _, hi, _ = self._geometry.bounds  # type: ignore[attr-defined]
        for turn in (-360.0, 0.0, 360.0):
            if west + turn > hi or east + turn < lo:
                continue
            clipped = shapely.clip_by_rect(self._geometry, west + turn, south, east + turn, north)
            for g in getattr(clipped, "geoms", [clipped]):
                if not g.is_empty and g.geom_type == "LineString":
                    xy = np.asarray(g.coords, dtype=np.float64)
                    xy[:, 0] -= turn
                    out.append(xy)
        return out


@functools.lru_cache(maxsize=32)
def _read_box(path: str, south: float, west: float, north: float, east: float) -> Coastline:
    import h5py
    import shapely

    with h5py.File(path, "r") as f:
        side = float(f["Bin_size_in_minutes"][0]) / 60.0
        nx = int(f["N_bins_in_360_longitude_range"][0])
        ny = int(f["N_bins_in_180_degree_latitude_range"][0])
        first = f["Id_of_first_segment_in_a_bin"]
        nseg = f["N_segments_in_a_bin"]
        info = f["Embedded_npts_levels_exit_entry_for_a_segment"]
        start = f["Id_of_first_point_in_a_segment"]
        dlon = f["Relative_longitude_from_SW_corner_of_bin"]
        dlat = f["Relative_latitude_from_SW_corner_of_bin"]
        rows = range(max(0, int((90.0 - north) // side)), min(ny, int((90.0 - south) // side) + 1))
        w = west % 360.0
        e = w + (east - west)
        cols = [c % nx for c in range(int(w // side), int(e // side) + 1)]
        box = shapely.box(west, south, east, north)
        lines: list[np.ndarray] = []
        for row in rows:
            lat_sw = 90.0 - (row + 1) * side
            for col in cols:
                b = row * nx + col
                n_seg = int(nseg[b])
                if n_seg == 0:
                    continue
                s0 = int(first[b])
                lon_sw = col * side
                # keep the longitudes on the side of the box (west may be negative)
                shift = lon_sw - 360.0 if lon_sw > east else lon_sw
                for s in range(s0, s0 + n_seg):
                    word = int(info[s])
                    n = word >> 9
                    p = int(start[s])
                    x = shift + dlon[p : p + n].astype(np.uint16) / 65535.0 * side
                    y = lat_sw + dlat[p : p + n].astype(np.uint16) / 65535.0 * side
                    if n < 2:
                        continue
                    clipped = shapely.clip_by_rect(shapely.linestrings(np.c_[x, y]), *box.bounds)
                    for part in getattr(clipped, "geoms", [clipped]):
                        if not part.is_empty and part.geom_type == "LineString":
                            lines.append(np.asarray(part.coords, dtype=np.float64))
    return Coastline(lines, path)


def coastline(south: float, west: float, north: float, east: float) -> Coastline:
    """The shoreline inside a lat/lon box (degrees; ``west < east``, at most 10 degrees wide).
    Returns an empty :class:`Coastline` with ``source=None`` when no GSHHG file is installed."""
    if not (south < north and west < east) or east - west > 10 or north - south > 10:
        return Coastline([], None)
    path = gshhg_file()
    if path is None:
        return Coastline([], None)
    # round the box outwards to 0.01 degree so nearby views share the cache
    q = 100.0
    return _read_box(
        str(path),
        math.floor(south * q) / q,
        math.floor(west * q) / q,
        math.ceil(north * q) / q,
        math.ceil(east * q) / q,
    )
