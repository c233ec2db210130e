"""The Monte-Carlo samplers: eq. 55 unchanged by default, and the uniform and scrambled-Sobol
samplers unbiased and more accurate, against the exact overlap."""

import numpy as np
import pytest

import geofeas

import reference as ref

A = np.array([0.0, 0.0, 1.0, 1.0, 0.0])
B = np.array([1.0, 0.0, 1.0, 1.0, 0.0])  # unit circles 1 apart: overlap 0.391 (Fig. 5)


def repeated(sampler, samples, runs=2000, seed=7):
    return geofeas.monte_carlo(
        np.tile(A, (runs, 1)), np.tile(B, (runs, 1)), samples=samples, seed=seed, sampler=sampler
    )


def test_importance_is_the_default_and_unchanged():
    a, b = ref.random_pairs(300, np.random.default_rng(4))
    np.testing.assert_array_equal(
        geofeas.monte_carlo(a, b, seed=5), geofeas.monte_carlo(a, b, seed=5, sampler="importance")
    )


@pytest.mark.parametrize("sampler", geofeas.SAMPLERS)
def test_unbiased_within_standard_error(sampler):
    truth = geofeas.overlap(A, B)
    assert abs(truth - ref.circle_lens_area(1.0, 1.0, 1.0) / np.pi) < 1e-14
    est = repeated(sampler, 64)
    se = est.std(ddof=1) / np.sqrt(len(est))
    assert abs(est.mean() - truth) < 4 * se + 1e-3 * (sampler == "importance")


def test_sobol_64_beats_eq_55_at_500():
    truth = geofeas.overlap(A, B)
    rmse_imp = np.sqrt(np.mean((repeated("importance", 500) - truth) ** 2))
    rmse_sob = np.sqrt(np.mean((repeated("sobol", 64) - truth) ** 2))
    rmse_uni = np.sqrt(np.mean((repeated("uniform", 500) - truth) ** 2))
    assert rmse_sob < rmse_imp
    # uniform sampling: the binomial standard deviation sqrt(g (1 - g) / N)
    assert rmse_uni == pytest.approx(np.sqrt(truth * (1 - truth) / 500), rel=0.1)


def test_sobol_on_random_pairs_against_exact():
    a, b = ref.random_pairs(5000, np.random.default_rng(8))
    exact = geofeas.overlap(a, b)
    imp = geofeas.monte_carlo(a, b, samples=500, seed=1)
    sob = geofeas.monte_carlo(a, b, samples=64, seed=1, sampler="sobol")
    assert np.sqrt(np.mean((sob - exact) ** 2)) < np.sqrt(np.mean((imp - exact) ** 2))
    assert abs(np.mean(sob - exact)) < 2e-3
    for g in (sob, geofeas.monte_carlo(a, b, samples=100, seed=1, sampler="uniform")):
        assert np.all((g >= 0) & (g <= 1))


def test_seeds_and_cdist_streams():
    a, b = ref.random_pairs(50, np.random.default_rng(1))
    for sampler in ("uniform", "sobol"):
        g1 = geofeas.monte_carlo(a, b, seed=3, sampler=sampler)
        np.testing.assert_array_equal(g1, geofeas.monte_carlo(a, b, seed=3, sampler=sampler))
        assert not np.array_equal(g1, geofeas.monte_carlo(a, b, seed=4, sampler=sampler))
        c = geofeas.cdist(a[:1], b, score="monte_carlo", seed=3, sampler=sampler)
        np.testing.assert_array_equal(
            c[0], geofeas.monte_carlo(np.tile(a[0], (50, 1)), b, seed=3, sampler=sampler)
        )
    with pytest.raises(geofeas.GeofeasError, match="sampler"):
        geofeas.monte_carlo(A, B, sampler="halton")
