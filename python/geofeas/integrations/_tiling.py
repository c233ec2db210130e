"""Space-time tiles with per-track halos: every intersecting pair of boxes owned by one tile.

The distributed association (:mod:`geofeas.integrations.dask`) cuts the picture into a regular
grid of space-time tiles. Each track has a closed box ``[lo, hi]`` (its reports' space-time extent
grown by its halo, see :func:`track_boxes`) and is copied, whole, into every tile its box meets
(:func:`explode`). A pair of tracks whose boxes intersect is *owned* by the tile holding the
lower corner ``c = max(lo_a, lo_b)`` of the intersection (:func:`owner`). Because ``c`` lies in
both boxes and the tile index ``floor((v - origin) / size)`` is monotone in ``v``, the owner is
one of the tiles both tracks were copied into: keeping, in every tile, only the pairs it owns
yields every intersecting pair exactly once, whatever the tile size.

Everything here is vectorised NumPy over one row per track (or per track and tile).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .._core import GeofeasError

__all__ = ["Grid", "explode", "owner"]

#: Refuse grids with more cells than this (the key is an int64 linear index).
MAX_CELLS = 1 << 62


@dataclass(frozen=True)
class Grid:
    """A regular grid: ``origin`` and cell ``size`` per dimension, ``shape`` cells."""

    origin: tuple[float, ...]
    size: tuple[float, ...]
    shape: tuple[int, ...]

    @classmethod
    def covering(cls, lo: NDArray[np.float64], hi: NDArray[np.float64], size: NDArray[np.float64]):
        """The grid of cells ``size`` whose origin is the smallest ``lo``, covering every box."""
        size = np.asarray(size, dtype=np.float64)
        if size.shape != (lo.shape[1],) or not np.all(np.isfinite(size)) or np.any(size <= 0):
            raise GeofeasError(f"tile sizes must be {lo.shape[1]} finite values > 0, got {size}")
        origin = lo.min(axis=0) if len(lo) else np.zeros(lo.shape[1])
        top = hi.max(axis=0) if len(hi) else origin
        cells = np.floor((top - origin) / size) + 1.0
        if not np.all(np.isfinite(cells)) or float(np.prod(cells)) >= MAX_CELLS:
            raise GeofeasError(
                f"tiles too small: a grid of {cells.tolist()} cells; use larger tiles"
            )
        shape = cells.astype(np.int64)
        return cls(tuple(map(float, origin)), tuple(map(float, size)), tuple(map(int, shape)))

    def cell(self, v: NDArray[np.float64]) -> NDArray[np.int64]:
        """Integer cell index ``(n, d)`` of points ``(n, d)``, clamped into the grid."""
        idx = np.floor((v - np.asarray(self.origin)) / np.asarray(self.size)).astype(np.int64)
        return np.clip(idx, 0, np.asarray(self.shape) - 1)

    def key(self, idx: NDArray[np.int64]) -> NDArray[np.int64]:
        """Linear int64 key of cell indices ``(n, d)``."""
        out = np.zeros(len(idx), dtype=np.int64)
        for d, n in enumerate(self.shape):
            out = out * n + idx[:, d]
        return out


def explode(
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    grid: Grid,
    *,
    max_copies: int | None = None,
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Every (box, cell) with the closed box meeting the cell.

    ``max_copies`` refuses (before allocating) grids so fine that the entries would exceed it.

    Returns
    -------
    rows : ndarray of int64
        Index of the box of each (box, cell) entry.
    keys : ndarray of int64
        Linear key of the cell.
    """
    a = grid.cell(lo)
    b = grid.cell(hi)
    n = b - a + 1
    count = np.prod(n, axis=1)
    total = float(np.sum(count.astype(np.float64)))
    if max_copies is not None and total > max_copies:
        raise GeofeasError(
            f"tiles too small: the {len(lo)} tracks would be copied into {int(total)} tiles "
            f"(more than {max_copies}); use larger tiles (the mean box is "
            f"{np.round(np.mean(hi - lo, axis=0), 1).tolist()}, the tile {list(grid.size)})"
        )
    rows = np.repeat(np.arange(len(lo), dtype=np.int64), count)
    first = np.concatenate([[0], np.cumsum(count)[:-1]]).astype(np.int64)
    j = np.arange(int(count.sum()), dtype=np.int64) - np.repeat(first, count)
    idx = np.empty((len(rows), lo.shape[1]), dtype=np.int64)
    for d in range(lo.shape[1] - 1, -1, -1):
        nd = n[rows, d]
        idx[:, d] = a[rows, d] + j % nd
        j //= nd
    return rows, grid.key(idx)


def owner(
    lo_a: NDArray[np.float64],
    hi_a: NDArray[np.float64],
    lo_b: NDArray[np.float64],
    hi_b: NDArray[np.float64],
    grid: Grid,
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """Owner cell key of each pair of boxes, and whether the two boxes intersect."""
    corner = np.maximum(lo_a, lo_b)
    meets = np.all(corner <= np.minimum(hi_a, hi_b), axis=1)
    return grid.key(grid.cell(corner)), meets
