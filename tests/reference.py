"""Independent NumPy reference of the geofeasibility scores, written from seed 000's equations.

Nothing here calls geofeas: the Gaussian of an AOU is built from eqs. 56-59 as matrices, the GLR of
eq. 71 by a linear solve, the Monte-Carlo estimator of eq. 55 with NumPy's own generator, and the
normalised overlap area of eqs. 49-50 by GEOS (shapely) on inscribed polygons at two resolutions
with Richardson extrapolation (the inscribed-polygon error is a smooth ``c / n^2`` series).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "circle_lens_area",
    "covariance",
    "glr",
    "monte_carlo",
    "overlap",
    "random_pairs",
    "rotate",
]


def covariance(e: np.ndarray) -> np.ndarray:
    """``R = U Lambda U^T`` (eqs. 56-58) for ellipses ``(n, 5)``; returns ``(n, 2, 2)``."""
    e = np.atleast_2d(e)
    s, c = np.sin(e[:, 4]), np.cos(e[:, 4])
    u = np.stack([np.stack([s, c], -1), np.stack([c, -s], -1)], -2)  # rows of U
    lam = np.zeros((len(e), 2, 2))
    lam[:, 0, 0] = e[:, 2] ** 2 / 4
    lam[:, 1, 1] = e[:, 3] ** 2 / 4
    return u @ lam @ np.swapaxes(u, -1, -2)


def glr(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Eq. 71: ``exp(-0.5 d^T (R1 + R2)^-1 d)``."""
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    d = a[:, :2] - b[:, :2]
    s = covariance(a) + covariance(b)
    q = np.einsum("ni,ni->n", d, np.linalg.solve(s, d[..., None])[..., 0])
    return np.exp(-0.5 * q)


def _polygon(e: np.ndarray, n: int):
    import shapely

    t = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    s, c = np.sin(e[4]), np.cos(e[4])
    u, v = e[2] * np.cos(t), e[3] * np.sin(t)
    # rx axis (sin phi, cos phi), ry axis (cos phi, -sin phi)
    return shapely.Polygon(np.stack([u * s + v * c, u * c - v * s], -1))


def _overlap_at(a: np.ndarray, b: np.ndarray, n: int) -> np.ndarray:
    import shapely

    out = np.empty(len(a))
    for k in range(len(a)):
        # centre the pair on a, scaled to the smaller ellipse, as a careful user would
        small = a[k] if a[k, 2] * a[k, 3] <= b[k, 2] * b[k, 3] else b[k]
        scale = np.sqrt(small[2] * small[3])
        ea = a[k].copy()
        eb = b[k].copy()
        eb[:2] -= ea[:2]
        ea[:2] = 0
        ea[:4] /= scale
        eb[:4] /= scale
        pa = _polygon(ea, n)
        pb = shapely.affinity.translate(_polygon(eb, n), eb[0], eb[1])
        inter = shapely.intersection(pa, pb).area
        out[k] = inter / min(pa.area, pb.area)
    return out


def overlap(a: np.ndarray, b: np.ndarray, n: int = 2048) -> np.ndarray:
    """Eqs. 49-50 by inscribed polygons of ``n`` and ``2n`` vertices, Richardson-extrapolated.

    Accurate to about 1e-8 for pairs of comparable size; clipped to [0, 1].
    """
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    g1 = _overlap_at(a, b, n)
    g2 = _overlap_at(a, b, 2 * n)
    return np.clip((4 * g2 - g1) / 3, 0.0, 1.0)


def monte_carlo(a: np.ndarray, b: np.ndarray, samples: int, rng: np.random.Generator) -> np.ndarray:
    """Eq. 55 with samples from the Gaussian of the smaller ellipse and weights ``1/p``."""
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    out = np.empty(len(a))
    for k in range(len(a)):
        small, other = (a[k], b[k]) if a[k, 2] * a[k, 3] <= b[k, 2] * b[k, 3] else (b[k], a[k])
        r = covariance(small)[0]
        x = rng.multivariate_normal(small[:2], r, size=samples)
        d = x - small[:2]
        p = np.exp(-0.5 * np.einsum("ni,ij,nj->n", d, np.linalg.inv(r), d))
        p /= 2 * np.pi * np.sqrt(np.linalg.det(r))
        in_small = _inside(small, x)
        in_both = in_small & _inside(other, x)
        den = np.sum(in_small / p)
        out[k] = np.sum(in_both / p) / den if den > 0 else 0.0
    return out


def _inside(e: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Points inside the 2-sigma ellipse: Mahalanobis distance <= 2."""
    d = x - e[:2]
    q = np.einsum("ni,ij,nj->n", d, np.linalg.inv(covariance(e)[0]), d)
    return q <= 4.0


def circle_lens_area(r1: float, r2: float, d: float) -> float:
    """Area of the intersection of two circles of radii ``r1, r2`` at distance ``d``."""
    if d >= r1 + r2:
        return 0.0
    if d <= abs(r1 - r2):
        return np.pi * min(r1, r2) ** 2
    a1 = r1**2 * np.arccos((d * d + r1 * r1 - r2 * r2) / (2 * d * r1))
    a2 = r2**2 * np.arccos((d * d + r2 * r2 - r1 * r1) / (2 * d * r2))
    k = 0.5 * np.sqrt((-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2))
    return float(a1 + a2 - k)


def random_pairs(
    n: int, rng: np.random.Generator, spread: float = 1.0
) -> tuple[np.ndarray, np.ndarray]:
    """Random ellipse pairs as in Fig. 6: varying size, orientation, aspect and overlap."""
    a = np.empty((n, 5))
    b = np.empty((n, 5))
    for e in (a, b):
        e[:, 2] = rng.uniform(0.5, 3.0, n)
        e[:, 3] = e[:, 2] * rng.uniform(0.2, 1.0, n)
        e[:, 4] = rng.uniform(-np.pi, np.pi, n)
    a[:, :2] = rng.uniform(-1, 1, (n, 2))
    # centre distance spans disjoint .. nested
    dist = rng.uniform(0, 1.2, n) * (a[:, 2] + b[:, 2]) * spread
    ang = rng.uniform(0, 2 * np.pi, n)
    b[:, 0] = a[:, 0] + dist * np.cos(ang)
    b[:, 1] = a[:, 1] + dist * np.sin(ang)
    return a, b


def rotate(e: np.ndarray, alpha: float) -> np.ndarray:
    """Ellipses rotated clockwise by ``alpha`` about the origin (bearings grow by ``alpha``)."""
    e = np.array(e, dtype=float, copy=True)
    x, y = e[:, 0].copy(), e[:, 1].copy()
    e[:, 0] = x * np.cos(alpha) + y * np.sin(alpha)
    e[:, 1] = -x * np.sin(alpha) + y * np.cos(alpha)
    e[:, 4] = e[:, 4] + alpha
    return e
