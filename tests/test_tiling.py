"""Tiles with per-track halos: every pair of intersecting boxes is owned by exactly one tile."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from geofeas import GeofeasError
from geofeas.integrations._tiling import Grid, explode, owner


def random_boxes(rng: np.random.Generator, n: int, dims: int):
    lo = rng.uniform(-1000, 1000, (n, dims))
    hi = lo + rng.exponential(150, (n, dims))
    # some degenerate boxes (a point, or flat along one axis)
    hi[: n // 10] = lo[: n // 10]
    return lo, hi


@pytest.mark.parametrize("dims", [3, 4])
@pytest.mark.parametrize("size", [37.0, 250.0, 5000.0])
def test_every_intersecting_pair_is_owned_by_exactly_one_shared_tile(rng, dims, size):
    lo, hi = random_boxes(rng, 120, dims)
    grid = Grid.covering(lo, hi, np.full(dims, size))
    rows, keys = explode(lo, hi, grid)
    members: dict[int, list[int]] = {}
    for r, k in zip(rows.tolist(), keys.tolist(), strict=True):
        members.setdefault(k, []).append(r)
    found: list[tuple[int, int]] = []
    for key, tracks in members.items():
        tracks = sorted(tracks)
        pairs = np.array(list(itertools.combinations(tracks, 2)), dtype=np.int64).reshape(-1, 2)
        if not len(pairs):
            continue
        keys_, meets = owner(
            lo[pairs[:, 0]], hi[pairs[:, 0]], lo[pairs[:, 1]], hi[pairs[:, 1]], grid
        )
        found += [tuple(p) for p in pairs[meets & (keys_ == key)].tolist()]
    # brute force: all pairs of closed boxes that intersect
    want = {
        (i, j)
        for i, j in itertools.combinations(range(len(lo)), 2)
        if np.all(lo[i] <= hi[j]) and np.all(lo[j] <= hi[i])
    }
    assert len(found) == len(set(found))  # none counted twice
    assert set(found) == want  # none lost
    assert want  # the picture has intersecting pairs at all


def test_explode_lists_exactly_the_cells_a_box_meets():
    grid = Grid((0.0, 0.0), (10.0, 10.0), (5, 5))
    lo = np.array([[0.0, 0.0], [9.9, 19.9], [10.0, 10.0]])
    hi = np.array([[0.0, 0.0], [10.1, 20.1], [29.9, 10.0]])
    rows, keys = explode(lo, hi, grid)
    got = {(int(r), divmod(int(k), 5)) for r, k in zip(rows, keys, strict=True)}
    assert got == {
        (0, (0, 0)),
        (1, (0, 1)),
        (1, (0, 2)),
        (1, (1, 1)),
        (1, (1, 2)),
        (2, (1, 1)),
        (2, (2, 1)),
    }


def test_bad_tiles_are_refused():
    lo, hi = np.zeros((2, 3)), np.ones((2, 3))
    for size in ([0.0, 1.0, 1.0], [1.0, np.nan, 1.0], [1.0, 1.0]):
        with pytest.raises(GeofeasError, match="tile sizes"):
            Grid.covering(lo, hi, np.array(size))
    with pytest.raises(GeofeasError, match="too small"):
        Grid.covering(np.zeros((2, 3)), np.full((2, 3), 1e18), np.full(3, 1e-3))
