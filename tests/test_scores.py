"""Cross-checks of the three scores against the independent NumPy reference, closed forms,
invariants and edge cases."""

import numpy as np
import pytest

import geofeas

import reference as ref

N_RANDOM = 10_000


@pytest.fixture(scope="module")
def pairs():
    return ref.random_pairs(N_RANDOM, np.random.default_rng(6))


@pytest.fixture(scope="module")
def true_overlap(pairs):
    a, b = pairs
    return ref.overlap(a, b, n=1024)


def test_glr_matches_reference(pairs):
    a, b = pairs
    np.testing.assert_allclose(geofeas.glr(a, b), ref.glr(a, b), rtol=1e-12, atol=1e-320)


def test_overlap_matches_reference_within_1e_4(pairs, true_overlap):
    a, b = pairs
    g = geofeas.overlap(a, b, method="polygon")
    err = np.abs(g - true_overlap)
    assert err.max() <= 1e-4, err.max()
    # and within the documented bound for its area ratio, pair by pair
    ratio = np.maximum(a[:, 2] * a[:, 3], b[:, 2] * b[:, 3]) / np.minimum(
        a[:, 2] * a[:, 3], b[:, 2] * b[:, 3]
    )
    bound = 8 * np.pi**2 / (3 * geofeas.DEFAULT_VERTICES**3) * (1 + ratio)
    assert np.all(err <= bound + 1e-8)


@pytest.mark.parametrize("vertices", [16, 64, 1024])
def test_polygon_error_bound_holds(pairs, true_overlap, vertices):
    a, b = pairs
    a, b, truth = a[:2000], b[:2000], true_overlap[:2000]
    g = geofeas.overlap(a, b, method="polygon", vertices=vertices)
    area_a, area_b = a[:, 2] * a[:, 3], b[:, 2] * b[:, 3]
    ratio = np.maximum(area_a, area_b) / np.minimum(area_a, area_b)
    bound = 8 * np.pi**2 / (3 * vertices**3) * (1 + ratio)
    assert np.all(np.abs(g - truth) <= bound + 1e-8)


def test_scores_in_unit_interval(pairs):
    a, b = pairs
    for g in (
        geofeas.glr(a, b),
        geofeas.glr(a, b, threshold=True),
        geofeas.overlap(a, b),
        geofeas.monte_carlo(a, b, seed=1),
    ):
        assert np.all((g >= 0) & (g <= 1))
        assert not np.any(np.isnan(g))


def test_thresholded_glr_is_zero_for_disjoint_and_one_for_nested(pairs, true_overlap):
    a, b = pairs
    gt = geofeas.glr(a, b, threshold=True)
    g = geofeas.glr(a, b)
    disjoint = true_overlap == 0.0
    nested = true_overlap == 1.0
    assert disjoint.sum() > 100 and nested.sum() > 100
    # the reference is a polygon: only trust clear-cut cases (thin margins go to the exact tests)
    clear_disjoint = disjoint & (ref.glr(a, b) < 0.2)
    assert np.all(gt[clear_disjoint] == 0.0)
    assert np.all(gt[nested] == 1.0)
    crossing = (true_overlap > 1e-6) & (true_overlap < 1 - 1e-6)
    np.testing.assert_array_equal(gt[crossing], g[crossing])


def test_symmetry(pairs):
    a, b = pairs
    np.testing.assert_array_equal(geofeas.glr(a, b), geofeas.glr(b, a))
    np.testing.assert_allclose(geofeas.overlap(a, b), geofeas.overlap(b, a), atol=1e-12)
    np.testing.assert_array_equal(
        geofeas.glr(a, b, threshold=True), geofeas.glr(b, a, threshold=True)
    )


def test_translation_invariance(pairs):
    a, b = (x[:3000].copy() for x in pairs)
    shift = np.array([631_234.5, 5_621_987.25])  # UTM-sized coordinates
    a2, b2 = a.copy(), b.copy()
    a2[:, :2] += shift
    b2[:, :2] += shift
    np.testing.assert_allclose(geofeas.glr(a2, b2), geofeas.glr(a, b), atol=1e-8)
    np.testing.assert_allclose(geofeas.overlap(a2, b2), geofeas.overlap(a, b), atol=1e-8)


def test_rotation_invariance(pairs):
    a, b = (x[:3000] for x in pairs)
    for alpha in (0.3, np.pi / 2, 2.0):
        ra, rb = ref.rotate(a, alpha), ref.rotate(b, alpha)
        np.testing.assert_allclose(geofeas.glr(ra, rb), geofeas.glr(a, b), atol=1e-12)
        # polygon vertices rotate with the ellipse, so this is invariant to rounding
        np.testing.assert_allclose(geofeas.overlap(ra, rb), geofeas.overlap(a, b), atol=1e-9)


def test_swapped_axes_describe_the_same_ellipse(pairs):
    a, b = (x[:3000] for x in pairs)
    a2 = a.copy()
    a2[:, 2], a2[:, 3], a2[:, 4] = a[:, 3], a[:, 2], a[:, 4] + np.pi / 2
    np.testing.assert_allclose(geofeas.glr(a2, b), geofeas.glr(a, b), rtol=1e-12)
    np.testing.assert_allclose(geofeas.overlap(a2, b), geofeas.overlap(a, b), atol=1e-5)
    np.testing.assert_array_equal(
        geofeas.glr(a2, b, threshold=True) == 0, geofeas.glr(a, b, threshold=True) == 0
    )


@pytest.mark.parametrize("d", [0.0, 0.3, 1.0, 1.7, 2.5, 2.99])
@pytest.mark.parametrize("r2", [1.0, 0.5])
def test_circle_lens_closed_form(d, r2):
    a = np.array([0.0, 0.0, 1.5, 1.5, 0.0])
    b = np.array([d, 0.0, r2, r2, 0.7])
    truth = ref.circle_lens_area(1.5, r2, d) / (np.pi * r2 * r2)
    assert abs(geofeas.overlap(a, b, method="polygon") - truth) <= 1e-5
    assert abs(geofeas.overlap(a, b) - truth) <= 1e-14
    assert abs(geofeas.overlap(a, b, method="polygon", vertices=4096) - truth) <= 1e-8


@pytest.mark.parametrize("ab", [(3.0, 1.0), (2.0, 1.9), (10.0, 0.5)])
def test_crossed_ellipses_closed_form(ab):
    a, b = ab
    e1 = np.array([5.0, -3.0, a, b, 0.4])
    e2 = np.array([5.0, -3.0, a, b, 0.4 + np.pi / 2])
    truth = 4 * a * b * np.arctan(b / a) / (np.pi * a * b)
    assert abs(geofeas.overlap(e1, e2, method="polygon", vertices=4096) - truth) <= 1e-7
    assert abs(geofeas.overlap(e1, e2, method="polygon") - truth) <= 2e-4
    assert abs(geofeas.overlap(e1, e2) - truth) <= 1e-13


def test_edge_cases_exact_values():
    e = np.array([10.0, 20.0, 3.0, 1.0, 0.3])
    far = np.array([100.0, 20.0, 3.0, 1.0, 0.3])
    inner = np.array([10.2, 20.1, 0.5, 0.2, 1.0])
    assert geofeas.overlap(e, e) == 1.0
    assert geofeas.glr(e, e) == 1.0
    assert geofeas.glr(e, e, threshold=True) == 1.0
    assert geofeas.monte_carlo(e, e, seed=3) == 1.0
    assert geofeas.overlap(e, far) == 0.0
    assert geofeas.glr(e, far, threshold=True) == 0.0
    assert geofeas.monte_carlo(e, far, seed=3) == 0.0
    assert geofeas.overlap(e, inner) == 1.0
    assert geofeas.overlap(inner, e) == 1.0
    assert geofeas.glr(inner, e, threshold=True) == 1.0
    assert geofeas.monte_carlo(inner, e, seed=3) == 1.0


def test_tangent_circles():
    a = np.array([0.0, 0.0, 1.0, 1.0, 0.0])
    outside = np.array([2.0, 0.0, 1.0, 1.0, 0.0])
    # touching is not disjoint: the polygon answer is within its documented bound of 0
    bound = 8 * np.pi**2 / (3 * geofeas.DEFAULT_VERTICES**3) * 2
    assert 0.0 <= geofeas.overlap(a, outside, method="polygon") <= bound
    assert 0.0 <= geofeas.overlap(a, outside) <= 1e-20
    assert geofeas.overlap(a, outside + [1e-9, 0, 0, 0, 0]) == 0.0
    inside = np.array([0.5, 0.0, 0.5, 0.5, 0.0])  # internally tangent
    assert geofeas.overlap(a, inside) == 1.0
    assert geofeas.glr(a, inside, threshold=True) == 1.0


def test_aspect_ratio_1000():
    needle = np.array([0.0, 0.0, 1000.0, 1.0, 0.0])  # along north
    crossing = np.array([0.0, 0.0, 1000.0, 1.0, np.pi / 2])
    truth = 4 * 1000.0 * np.arctan(1 / 1000.0) / (np.pi * 1000.0)
    g = geofeas.overlap(needle, crossing, method="polygon", vertices=8192)
    assert abs(g - truth) <= 1e-4
    assert 0 < geofeas.glr(needle, crossing) <= 1
    off = np.array([5.0, 0.0, 1000.0, 1.0, 0.0])  # parallel needle 5 m east: disjoint
    assert geofeas.overlap(needle, off) == 0.0
    assert geofeas.glr(needle, off, threshold=True) == 0.0


def test_tiny_ellipses_far_from_origin():
    base = np.array([[0.0, 0.0, 0.02, 0.01, 0.3]])
    other = np.array([[0.012, 0.004, 0.015, 0.012, 1.1]])
    truth = ref.overlap(base, other)[0]
    for shift in (0.0, 6.5e5, 5.6e6):
        a, b = base.copy(), other.copy()
        a[:, :2] += shift
        b[:, :2] += shift
        assert abs(geofeas.overlap(a, b)[0] - truth) <= 1e-4
        assert geofeas.glr(a, b)[0] == pytest.approx(ref.glr(base, other)[0], rel=1e-6)


def test_monte_carlo_unbiased_within_standard_error():
    # Eq. 55 is a ratio estimator: its bias is O(1/N); with N = 500 it is far below the
    # standard error of the mean over 4000 seeds, which is what this test resolves.
    a = np.array([0.0, 0.0, 2.0, 2.0, 0.0])
    b = np.array([2.0, 0.0, 2.0, 2.0, 0.0])
    truth = ref.circle_lens_area(2.0, 2.0, 2.0) / (4 * np.pi)
    runs = 4000
    aa = np.tile(a, (runs, 1))
    bb = np.tile(b, (runs, 1))
    est = geofeas.monte_carlo(aa, bb, samples=500, seed=11)  # pair k uses stream k
    se = est.std(ddof=1) / np.sqrt(runs)
    assert abs(est.mean() - truth) < 4 * se
    # the NumPy reference of eq. 55 has the same spread (independent generator)
    r = ref.monte_carlo(aa[:400], bb[:400], 500, np.random.default_rng(5))
    assert abs(r.mean() - truth) < 4 * r.std(ddof=1) / np.sqrt(400)
    assert 0.5 < est.std() / r.std() < 2.0


def test_monte_carlo_mean_over_seeds_within_standard_error():
    a = np.array([0.0, 0.0, 3.0, 1.0, 0.4])
    b = np.array([1.0, 0.5, 2.0, 1.5, 1.2])
    truth = ref.overlap(a[None], b[None])[0]
    est = np.array([geofeas.monte_carlo(a, b, samples=500, seed=s) for s in range(1500)])
    se = est.std(ddof=1) / np.sqrt(len(est))
    assert abs(est.mean() - truth) < 4 * se


def test_monte_carlo_close_to_exact_on_random_pairs(pairs, true_overlap):
    a, b = (x[:3000] for x in pairs)
    g = geofeas.monte_carlo(a, b, samples=500, seed=2)
    err = g - true_overlap[:3000]
    # eq. 55's absolute error is roughly constant (Fig. 2): sd about 0.02 at N = 500
    assert abs(err.mean()) < 3e-3
    assert err.std() < 0.03


def test_monte_carlo_seeds():
    a, b = ref.random_pairs(500, np.random.default_rng(1))
    g1 = geofeas.monte_carlo(a, b, seed=123)
    np.testing.assert_array_equal(g1, geofeas.monte_carlo(a, b, seed=123))
    assert not np.array_equal(g1, geofeas.monte_carlo(a, b, seed=124))
    # elementwise pair k and cdist pair (i, j) draw from stream k = i * m + j
    c = geofeas.cdist(a[:1], b[:50], score="monte_carlo", seed=123)
    np.testing.assert_array_equal(
        c[0], geofeas.monte_carlo(np.tile(a[0], (50, 1)), b[:50], seed=123)
    )
