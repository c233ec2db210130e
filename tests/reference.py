"""Independent NumPy reference of the geofeasibility scores, written from seed 000's equations.

Nothing here calls geofeas: the Gaussian of an AOU is built from eqs. 56-59 as matrices, the GLR of
eq. 71 by a linear solve, the Monte-Carlo estimator of eq. 55 with NumPy's own generator, and the
normalised overlap area of eqs. 49-50 by GEOS (shapely) on inscribed polygons at two resolutions
with Richardson extrapolation (the inscribed-polygon error is a smooth ``c / n^2`` series), and to
full double precision by adaptive quadrature (Gauss-Legendre) of the length of the vertical chord
the two ellipses share, between the kinks of that length (found by bracketing on a grid). The
Gaussian overlap scores come from the covariance matrices of eqs. 56-58 by NumPy linear algebra.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "bhattacharyya",
    "chords",
    "circle_lens_area",
    "gaussian_product",
    "intersection_area",
    "lens_near_tangent",
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


def _quadratic_form(e: np.ndarray) -> np.ndarray:
    """``A`` with the ellipse ``{x : (x - c)^T A (x - c) <= 1}``: ``A = (4 R)^-1``."""
    return np.linalg.inv(4.0 * covariance(e)[0])


def chords(e: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper ends of the vertical chords of ellipse ``e`` at abscissae ``x`` (NaN
    outside the ellipse's x-range)."""
    a = _quadratic_form(e)
    dx = x - e[0]
    disc = a[1, 1] - np.linalg.det(a) * dx * dx
    with np.errstate(invalid="ignore"):
        root = np.sqrt(disc)
    mid = e[1] - a[0, 1] * dx / a[1, 1]
    return mid - root / a[1, 1], mid + root / a[1, 1]


def _x_range(e: np.ndarray) -> tuple[float, float]:
    a = _quadratic_form(e)
    half = np.sqrt(a[1, 1] / np.linalg.det(a))
    return e[0] - half, e[0] + half


_GL = (np.polynomial.legendre.leggauss(48), np.polynomial.legendre.leggauss(96))


def _gauss_legendre(f, lo: float, hi: float, depth: int = 0, floor: float = 0.0) -> float:
    """Adaptive Gauss-Legendre: 48 against 96 nodes, halving the interval until they agree to
    rounding (relative to the size of the integrand on the interval), or to ``floor`` times the
    interval's length (the rounding of an integrand computed as a difference)."""
    (x1, w1), (x2, w2) = _GL
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    v2 = f(mid + half * x2)
    coarse = half * float(np.dot(w1, f(mid + half * x1)))
    fine = half * float(np.dot(w2, v2))
    scale = 2.0 * half * float(np.max(np.abs(v2)))
    if abs(fine - coarse) <= max(1e-14 * scale, floor * 2.0 * half) or depth >= 14:
        return fine
    return _gauss_legendre(f, lo, mid, depth + 1, floor) + _gauss_legendre(
        f, mid, hi, depth + 1, floor
    )


def intersection_area(a: np.ndarray, b: np.ndarray, grid: int = 20001) -> float:
    """Area of the intersection of two ellipses ``(5,)`` by adaptive quadrature of the length of
    their common vertical chord, in a frame centred on ``a``.

    The chord length is smooth except at the x-range ends (square-root behaviour, removed by the
    substitution ``x = p + (q - p)(1 - cos u) / 2``) and at the kinks where the chord's ends
    switch ellipse; those are bracketed on a grid of ``grid`` abscissae and located by Brent's
    method. Between knots the integrand is analytic in ``u`` and adaptive Gauss-Legendre
    quadrature converges to rounding. Accurate to about 1e-15 relative for pairs whose kinks are
    not closer than the grid.
    """
    from scipy.optimize import brentq

    a = np.array(a, dtype=float)
    b = np.array(b, dtype=float)
    b[:2] -= a[:2]
    a[:2] = 0.0
    la, ra = _x_range(a)
    lb, rb = _x_range(b)
    lo, hi = max(la, lb), min(ra, rb)
    if lo >= hi:
        return 0.0

    def ends(x):
        x = np.atleast_1d(np.asarray(x, dtype=float))
        a0, a1 = chords(a, x)
        b0, b1 = chords(b, x)
        return np.stack([a1 - b1, a0 - b0, a1 - b0, b1 - a0])

    def length(x):
        a0, a1 = chords(a, x)
        b0, b1 = chords(b, x)
        return np.nan_to_num(np.maximum(0.0, np.minimum(a1, b1) - np.maximum(a0, b0)))

    xs = np.linspace(lo, hi, grid)[1:-1]
    diffs = ends(xs)
    points = {lo, hi}
    for k in range(4):
        v = diffs[k]
        for i in np.nonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0)[0]:
            root = brentq(lambda x, k=k: float(ends(x)[k, 0]), xs[i], xs[i + 1], xtol=1e-16)
            points.add(root)
        for i in np.nonzero(v == 0.0)[0]:
            points.add(float(xs[i]))
    knots = sorted(points)
    total = 0.0
    for p, q in zip(knots[:-1], knots[1:], strict=True):
        if q <= p:
            continue
        half = 0.5 * (q - p)

        def integrand(u, p=p, half=half):
            return length(p + half * (1.0 - np.cos(u))) * half * np.sin(u)

        total += _gauss_legendre(integrand, 0.0, np.pi)
    return total


def overlap_quad(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Eqs. 49-50 from :func:`intersection_area` for arrays of pairs ``(n, 5)``."""
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    out = np.empty(len(a))
    for k in range(len(a)):
        small = np.pi * min(a[k, 2] * a[k, 3], b[k, 2] * b[k, 3])
        out[k] = min(1.0, intersection_area(a[k], b[k]) / small)
    return out


def lens_near_tangent(a: np.ndarray, b: np.ndarray, normal: float, outside: bool) -> float:
    """Area of the small lens (``outside=True``: ``b`` outside ``a``, touching) or of the small
    bite (``b`` inside ``a``, pushed out) near a point where the two boundaries nearly touch
    with common normal at angle ``normal`` (counter-clockwise from +x).

    The pair is rotated so the normal points up; near the contact both boundaries are graphs
    over x, the gap between them is integrated between its two zeros (found by Brent's method
    outward from the contact), with the rounding of one chord end (1e-16) as the only error.
    """
    from scipy.optimize import brentq

    alpha = normal - np.pi / 2  # clockwise rotation taking the normal to +y
    ra, rb = rotate(np.array([a]), alpha)[0], rotate(np.array([b]), alpha)[0]
    rb[:2] -= ra[:2]
    ra[:2] = 0.0
    # contact abscissa: top of a
    x0 = float(_top_x(ra))

    def gap(x):
        x = np.atleast_1d(x)
        a0, a1 = chords(ra, x)
        b0, b1 = chords(rb, x)
        return float((a1 - b0)[0] if outside else (b1 - a1)[0])

    if not gap(x0) > 0.0:
        return 0.0
    width = 1e-9
    while gap(x0 - width) > 0.0 or gap(x0 + width) > 0.0:
        width *= 2.0
    left = brentq(gap, x0 - width, x0, xtol=1e-18)
    right = brentq(gap, x0, x0 + width, xtol=1e-18)
    size = 1.0 + float(np.max(np.abs(np.concatenate([ra[:4], rb[:4]]))))
    return _gauss_legendre(np.vectorize(gap), left, right, floor=1e-15 * size)


def _top_x(e: np.ndarray) -> float:
    """Abscissa of the highest point of an ellipse."""
    a = _quadratic_form(e)
    # maximise y on (x, y)^T A (x, y) = 1: x = -A12 / A11 y
    return float(e[0] - a[0, 1] / a[0, 0] * (1.0 / np.sqrt(a[1, 1] - a[0, 1] ** 2 / a[0, 0])))


def bhattacharyya(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``integral sqrt(p1 p2)`` of two Gaussians from their covariance matrices."""
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    r1, r2 = covariance(a), covariance(b)
    s = 0.5 * (r1 + r2)
    d = a[:, :2] - b[:, :2]
    q = np.einsum("ni,ni->n", d, np.linalg.solve(s, d[..., None])[..., 0])
    ratio = np.sqrt(np.sqrt(np.linalg.det(r1) * np.linalg.det(r2)) / np.linalg.det(s))
    return ratio * np.exp(-q / 8.0)


def gaussian_product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``integral p1 p2 / sqrt(integral p1^2 integral p2^2)`` of two Gaussians."""
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    r1, r2 = covariance(a), covariance(b)
    s = r1 + r2
    d = a[:, :2] - b[:, :2]
    q = np.einsum("ni,ni->n", d, np.linalg.solve(s, d[..., None])[..., 0])
    cross = np.exp(-0.5 * q) / (2 * np.pi * np.sqrt(np.linalg.det(s)))
    self1 = 1.0 / (4 * np.pi * np.sqrt(np.linalg.det(r1)))
    self2 = 1.0 / (4 * np.pi * np.sqrt(np.linalg.det(r2)))
    return cross / np.sqrt(self1 * self2)
