"""Independent vectorised NumPy implementation of seed 003's particle filter (Ohlmeyer and
Menon), written from the paper's equations, not from the Rust code.

Used by ``tests/test_pf.py`` to check the Rust Method-2 weights on small cases and by
``benches/bench_pf.py`` as the same-run baseline of the full filter. Conventions: frame
``z[j, i]`` is row ``j`` (y) and column ``i`` (x) with cell centres at integer coordinates.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def render(
    positions: NDArray[np.float64],
    width: int,
    height: int,
    amplitude: float,
    blur: float,
    sigma: float,
    rng: np.random.Generator,
) -> NDArray[np.float64]:
    """Section II: Gaussian point spreads of amplitude ``A`` and blur ``Sigma`` plus white noise."""
    jj, ii = np.mgrid[0:height, 0:width].astype(np.float64)
    z = np.zeros((height, width))
    for x, y in positions:
        z += amplitude * np.exp(-((ii - x) ** 2 + (jj - y) ** 2) / (2.0 * blur**2))
    return z + sigma * rng.standard_normal((height, width))


def log_likelihood_ratio(
    z: NDArray[np.float64],
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    amplitude: float,
    blur: float,
    sigma: float,
    half_box: int,
) -> NDArray[np.float64]:
    """Section V: ``log prod_{(i, j) in C} exp(-h (h - 2 z) / (2 sigma^2))`` per particle, ``C``
    the cells within ``+-D`` of the particle's nearest cell (clipped to the frame), ``h`` the
    point spread ``A exp(-((i - x)^2 + (j - y)^2) / (2 Sigma^2))``, all cells at once."""
    height, width = z.shape
    d = np.arange(-half_box, half_box + 1)
    # the particle's cell is the nearest one, ties upwards: floor(x + 1/2)
    ci = np.floor(x + 0.5)[:, None, None] + d[None, None, :]  # (N, 1, L) columns
    cj = np.floor(y + 0.5)[:, None, None] + d[None, :, None]  # (N, L, 1) rows
    ci, cj = np.broadcast_arrays(ci, cj)
    inside = (ci >= 0) & (ci < width) & (cj >= 0) & (cj < height)
    zi = z[np.clip(cj, 0, height - 1).astype(np.intp), np.clip(ci, 0, width - 1).astype(np.intp)]
    r2 = (ci - x[:, None, None]) ** 2 + (cj - y[:, None, None]) ** 2
    h = amplitude * np.exp(-r2 / (2.0 * blur**2))
    terms = np.where(inside, -h * (h - 2.0 * zi) / (2.0 * sigma**2), 0.0)
    out: NDArray[np.float64] = terms.sum(axis=(1, 2))
    return out


def systematic_resample(w: NDArray[np.float64], rng: np.random.Generator) -> NDArray[np.intp]:
    n = len(w)
    points = (np.arange(n) + rng.random()) / n
    cum = np.cumsum(w)
    cum[-1] = 1.0
    out: NDArray[np.intp] = np.searchsorted(cum, points, side="right")
    return out


def track_method2(
    frames: NDArray[np.float64],
    init: NDArray[np.float64],
    *,
    sigma_z: float,
    particles: int,
    rng: np.random.Generator,
    amplitude: float = 1.0,
    blur: float = 2.0,
    dt: float = 0.1,
    sigma_w: float = 0.5,
    xmax: float = 3.0,
    vmax: float = 0.5,
    factors: tuple[float, float, float] = (0.8, 1.5, 1.5),
    half_box: int = 10,
) -> dict[str, NDArray[np.float64]]:
    """The bank of Method-2 particle filters (Figs. 4 and section V, Table 1), with the
    weighted-nearest-neighbour distances of section III to the four strongest pixels of each
    frame recorded as in the Rust tracker; returns the posterior means ``(F, n, 4)`` and
    covariances ``(F, n, 4, 4)``."""
    n_frames = frames.shape[0]
    targets = init.shape[0]
    a_f, s_f, sig_f = factors[0] * amplitude, factors[1] * blur, factors[2] * sigma_z
    lo = init[:, None, :] - np.array([xmax, xmax, vmax, vmax])
    hi = init[:, None, :] + np.array([xmax, xmax, vmax, vmax])
    p = rng.uniform(lo, hi, size=(targets, particles, 4))
    w = np.full((targets, particles), 1.0 / particles)
    means = np.empty((n_frames, targets, 4))
    covs = np.empty((n_frames, targets, 4, 4))
    phi = np.array([[1, 0, dt, 0], [0, 1, 0, dt], [0, 0, 1, 0], [0, 0, 0, 1]], dtype=float)
    gam = np.array([[dt**2 / 2, 0], [0, dt**2 / 2], [dt, 0], [0, dt]])
    for k in range(n_frames):
        z = frames[k]
        if k > 0:
            noise = sigma_w * rng.standard_normal((targets, particles, 2))
            p = p @ phi.T + noise @ gam.T
        flat = np.argsort(z, axis=None)[-4:]
        peaks = np.stack([flat % z.shape[1], flat // z.shape[1]], axis=1).astype(float)
        dist = np.hypot(
            p[:, :, None, 0] - peaks[None, None, :, 0], p[:, :, None, 1] - peaks[None, None, :, 1]
        )
        _ = (w[:, :, None] * dist).sum(axis=1).argmin(axis=1)  # section III association
        for i in range(targets):
            lw = np.log(w[i]) + log_likelihood_ratio(
                z, p[i, :, 0], p[i, :, 1], a_f, s_f, sig_f, half_box
            )
            lw -= lw.max()
            wi = np.exp(lw)
            wi /= wi.sum()
            m = wi @ p[i]
            d = p[i] - m
            means[k, i] = m
            covs[k, i] = (wi[:, None] * d).T @ d
            idx = systematic_resample(wi, rng)
            p[i] = p[i, idx]
            w[i] = 1.0 / particles
    return {"estimates": means, "covariances": covs}
