"""The exact overlap and intersection area against published vectors, the independent quadrature
reference, generated tangent pairs, and the Gaussian overlap scores against NumPy."""

import numpy as np
import pytest

import geofeas

import reference as ref

TOL = 1e-11


def lit(cx, cy, a, b, theta):
    """``(cx, cy, a, b, theta)`` with theta counter-clockwise from +x (the literature's
    convention) as a geofeas ellipse: ``phi = pi/2 - theta``."""
    return np.array([cx, cy, a, b, np.pi / 2 - theta])


def small_area(a, b):
    return np.pi * np.minimum(a[..., 2] * a[..., 3], b[..., 2] * b[..., 3])


VECTORS = [
    (lit(0, 0, 3, 2, 0), lit(1, -0.5, 3, 1, np.pi / 4), 7.5131405589426367),
    (
        lit(1e6, 1e6, 3, 2, 0),
        lit(1e6 + 1, 1e6 - 0.5, 3, 1, np.pi / 4),
        7.5131405589426367,
    ),
    (lit(0, 0, 2, 1, 0), lit(1, 0, 1, 2, 0), 3.0550146972417223),  # tangent + 2
    (lit(0, 0, 3, 1, 0.1), lit(0.2, -0.1, 2.5, 1.6, 1.3), 6.1437831527223838),  # 4 crossings
    (  # EEOver issue 1
        lit(41.94107253, 39.78655647, 43.28271488, 22.83392139, 3.120439222),
        lit(53.92619514, 45.62883047, 32.64211672, 27.84469155, 3.093992268),
        2227.3519086285505,
    ),
    (lit(100, 100, 100, 100, 0), lit(75, 100, 125, 50, 0), 16598.17337245166),  # GTE 42
    (lit(500, 0, 200, 200, 0), lit(0, 0, 500, 500, 0), 57476.906924020905),  # GTE 105
    (  # GTE 55
        lit(0, 0, 2, 1, 1e-8),
        lit(0, 0, 2, 1, 1e-8 + np.pi / 2),
        8 * np.arctan(0.5),
    ),
    (lit(0, 0, 100, 0.01, 0.3), lit(20, 5, 10, 10, 0), 0.38821113655868701),  # needle
]


@pytest.mark.parametrize("a, b, truth", VECTORS)
def test_published_vectors_both_orders(a, b, truth):
    small = small_area(a, b)
    for p, q in ((a, b), (b, a)):
        assert abs(geofeas.intersection_area(p, q) - truth) / small <= TOL
        assert abs(geofeas.overlap(p, q) - min(1.0, truth / small)) <= TOL
        assert abs(geofeas.overlap(p, q, method="exact") - min(1.0, truth / small)) <= TOL
    assert geofeas.overlap(a, b) == geofeas.overlap(b, a)


def test_reference_reproduces_the_published_vectors():
    # the quadrature reference is itself checked (the needle is left out: its vertical chords
    # are 1e-4 thick, beyond the reference's grid of kinks)
    for a, b, truth in VECTORS[:-1]:
        assert abs(ref.intersection_area(a, b) - truth) / small_area(a, b) <= 1e-13


@pytest.fixture(scope="module")
def quad_pairs():
    a, b = ref.random_pairs(240, np.random.default_rng(17))
    return a, b, ref.overlap_quad(a, b)


def test_random_pairs_match_the_quadrature_reference(quad_pairs):
    a, b, truth = quad_pairs
    assert np.abs(geofeas.overlap(a, b) - truth).max() <= TOL
    assert np.abs(geofeas.overlap(b, a) - truth).max() <= TOL
    area = geofeas.intersection_area(a, b)
    assert np.all(np.abs(area / small_area(a, b) - truth) <= TOL)
    # the polygon method at its default resolution is within its documented bound
    poly = geofeas.overlap(a, b, method="polygon")
    assert np.abs(poly - truth).max() <= 1e-4


def _normal(e, t):
    """Outward unit normal (x, y) of ellipse ``e`` at parameter ``t``."""
    s, c = np.sin(e[4]), np.cos(e[4])
    e1, e2 = np.array([s, c]), np.array([c, -s])
    n = np.cos(t) / e[2] * e1 + np.sin(t) / e[3] * e2
    return n / np.linalg.norm(n)


def _point(e, t):
    s, c = np.sin(e[4]), np.cos(e[4])
    return e[:2] + e[2] * np.cos(t) * np.array([s, c]) + e[3] * np.sin(t) * np.array([c, -s])


def _touching(b_shape, p, m):
    """Ellipse of shape ``(rx, ry, phi)`` whose boundary passes through ``p`` with outward
    normal ``m`` there."""
    rx, ry, phi = b_shape
    s, c = np.sin(phi), np.cos(phi)
    e1, e2 = np.array([s, c]), np.array([c, -s])
    t = np.arctan2(ry * (m @ e2), rx * (m @ e1))
    offset = rx * np.cos(t) * e1 + ry * np.sin(t) * e2
    return np.array([*(p - offset), rx, ry, phi])


def tangent_cases(rng, n):
    """Random ellipses ``a`` with a second ellipse touching from outside, or a circle touching
    from inside, each nudged by +-delta along the common normal."""
    for k in range(n):
        rx = rng.uniform(0.5, 3.0)
        a = np.array(
            [
                rng.uniform(-1, 1),
                rng.uniform(-1, 1),
                rx,
                rx * rng.uniform(0.2, 1.0),
                rng.uniform(-np.pi, np.pi),
            ]
        )
        t = rng.uniform(0, 2 * np.pi)
        p, m = _point(a, t), _normal(a, t)
        delta = 10.0 ** rng.uniform(-15, -5) * rng.choice([-1.0, 1.0])
        if k % 2 == 0:
            rbx = rng.uniform(0.3, 3.0)
            b = _touching((rbx, rbx * rng.uniform(0.2, 1.0), rng.uniform(-np.pi, np.pi)), p, -m)
            b[:2] -= delta * m  # delta > 0: b moves into a
            yield a, b, delta, True, np.arctan2(m[1], m[0])
        else:
            r = 0.9 * a[3] ** 2 / a[2] * rng.uniform(0.1, 1.0)  # inside the smallest curvature
            b = _touching((r, r, 0.0), p, m)
            b[:2] += delta * m  # delta > 0: b pokes out of a
            yield a, b, delta, False, np.arctan2(m[1], m[0])


def test_tangent_pairs_perturbed_both_orders():
    rng = np.random.default_rng(5)
    checked = 0
    for a, b, delta, outside, normal in tangent_cases(rng, 160):
        area_b = np.pi * b[2] * b[3]
        if outside:
            truth_area = ref.lens_near_tangent(a, b, normal, True) if delta > 0 else 0.0
        else:
            bite = ref.lens_near_tangent(a, b, normal, False) if delta > 0 else 0.0
            truth_area = area_b - bite
        truth = truth_area / small_area(a, b)
        for p, q in ((a, b), (b, a)):
            g = geofeas.overlap(p, q)
            assert 0.0 <= g <= 1.0
            assert abs(g - truth) <= TOL, (p, q, delta, g, truth)
        if outside and delta > 1e-10:
            # thin lenses keep relative accuracy too (their crossings are 1e-5 apart or more)
            lens = geofeas.intersection_area(a, b)
            assert abs(lens - truth_area) <= 1e-5 * truth_area
        checked += 1
    assert checked == 160


def test_range_no_nan_and_cdist(quad_pairs):
    a, b = ref.random_pairs(20_000, np.random.default_rng(2))
    g = geofeas.overlap(a, b)
    assert np.all((g >= 0) & (g <= 1)) and not np.any(np.isnan(g))
    c = geofeas.cdist(a[:40], b[:30], score="overlap")
    np.testing.assert_array_equal(c[3], geofeas.overlap(np.tile(a[3], (30, 1)), b[:30]))
    c2 = geofeas.cdist(a[:40], b[:30], score="overlap", method="polygon", vertices=64)
    assert np.abs(c2 - c).max() < 1e-2


def test_closed_forms():
    # circle lens
    for d in (0.0, 0.3, 1.0, 1.7, 2.4999):
        a = np.array([0.0, 0.0, 1.5, 1.5, 0.0])
        b = np.array([d, 0.0, 1.0, 1.0, 0.7])
        truth = ref.circle_lens_area(1.5, 1.0, d) / np.pi
        assert abs(geofeas.overlap(a, b) - truth) <= 1e-14
    # centred a x b and its 90-degree rotation: 4 a b atan(b / a)
    for ra, rb in ((3.0, 1.0), (10.0, 0.5), (2.0, 1.9)):
        e1 = np.array([5.0, -3.0, ra, rb, 0.4])
        e2 = np.array([5.0, -3.0, ra, rb, 0.4 + np.pi / 2])
        assert abs(geofeas.intersection_area(e1, e2) - 4 * ra * rb * np.arctan(rb / ra)) <= 1e-13
    # touching circles: 0 outside, 1 inside
    unit = np.array([0.0, 0.0, 1.0, 1.0, 0.0])
    assert geofeas.overlap(unit, np.array([2.0, 0.0, 1.0, 1.0, 0.0])) <= 1e-20
    assert geofeas.overlap(unit, np.array([0.5, 0.0, 0.5, 0.5, 0.0])) == 1.0
    # near-identical: centre moved by 1e-9
    e = np.array([0.0, 0.0, 3.0, 2.0, 0.3])
    moved = e + [1e-9, 0, 0, 0, 0]
    s, c = np.sin(0.3), np.cos(0.3)
    width = 2 * np.hypot(3.0 * c, 2.0 * s)  # width of e across an eastward shift
    assert abs(geofeas.overlap(e, moved) - (1 - 1e-9 * width / (6 * np.pi))) <= 1e-15


def test_polygon_method_still_available():
    a = np.array([0.0, 0.0, 2.0, 1.0, 0.3])
    b = np.array([0.8, 0.2, 1.5, 1.2, 1.2])
    exact = geofeas.overlap(a, b)
    for n in (64, 256, 4096):
        poly = geofeas.overlap(a, b, method="polygon", vertices=n)
        assert abs(poly - exact) <= geofeas._core.polygon_error_bound(n, 2.0 / 1.8)
    with pytest.raises(geofeas.GeofeasError, match="method"):
        geofeas.overlap(a, b, method="analytic")


def test_gaussian_scores_match_numpy():
    a, b = ref.random_pairs(3000, np.random.default_rng(9))
    bc = geofeas.bhattacharyya(a, b)
    np.testing.assert_allclose(bc, ref.bhattacharyya(a, b), rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(
        geofeas.hellinger(a, b), np.sqrt(1 - ref.bhattacharyya(a, b)), rtol=1e-9, atol=1e-8
    )
    np.testing.assert_allclose(
        geofeas.gaussian_product(a, b), ref.gaussian_product(a, b), rtol=1e-12, atol=1e-300
    )
    assert np.all((bc > 0) & (bc <= 1))
    e = np.array([1.0, 2.0, 3.0, 1.0, 0.2])
    assert geofeas.bhattacharyya(e, e) == 1.0 and geofeas.hellinger(e, e) == 0.0
    assert geofeas.gaussian_product(e, e) == 1.0
    # the product is the GLR times the shape factor sqrt(4 sqrt(det R1 det R2) / det(R1 + R2))
    np.testing.assert_allclose(
        geofeas.gaussian_product(a, b) / geofeas.glr(a, b),
        (bc / np.sqrt(geofeas.glr(a, b))),
        rtol=1e-10,
    )
    c = geofeas.cdist(a[:5], b[:7], score="hellinger")
    np.testing.assert_array_equal(c[2], geofeas.hellinger(np.tile(a[2], (7, 1)), b[:7]))


def test_hellinger_keeps_its_digits_near_identity():
    a = np.array([0.0, 0.0, 2.0, 2.0, 0.0])
    for k in (1 + 1e-9, 1 + 1e-5):
        b = np.array([0.0, 0.0, 2.0 * k, 2.0 * k, 0.0])
        truth = np.sqrt((k - 1) ** 2 / (1 + k * k))
        assert geofeas.hellinger(a, b) == pytest.approx(truth, rel=1e-6)
