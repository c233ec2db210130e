"""The Python boundary: shapes, dtypes, broadcasting, cdist, conversions, errors, threads."""

import os
import signal
import subprocess
import sys
import threading

import numpy as np
import pytest

import geofeas
from geofeas import GeofeasError

import reference as ref

A = np.array([0.0, 0.0, 2.0, 1.0, 0.3])
B = np.array([1.0, 0.5, 1.5, 1.5, 1.0])


@pytest.mark.parametrize("fn", [geofeas.glr, geofeas.overlap, geofeas.monte_carlo])
def test_shapes_of_call(fn):
    single = fn(A, B)
    assert isinstance(single, float)
    arr = np.stack([A, B, A])
    assert fn(arr, arr).shape == (3,)
    broadcast = fn(A, arr)
    assert broadcast.shape == (3,)
    if fn is not geofeas.monte_carlo:
        assert broadcast[1] == pytest.approx(single)
        assert fn(arr, B)[0] == pytest.approx(single)
    assert fn(np.empty((0, 5)), np.empty((0, 5))).shape == (0,)


@pytest.mark.parametrize("score", ["glr", "overlap", "monte_carlo"])
def test_cdist_matches_elementwise(score):
    a, b = ref.random_pairs(40, np.random.default_rng(2))
    opts = {"seed": 9} if score == "monte_carlo" else {}
    d = geofeas.cdist(a, b[:30], score=score, **opts)
    assert d.shape == (40, 30)
    if score != "monte_carlo":
        fn = getattr(geofeas, score)
        for i in (0, 17, 39):
            np.testing.assert_allclose(d[i], fn(a[i], b[:30]), atol=1e-13)
    assert geofeas.cdist(A, B[None], score=score, **opts).shape == (1, 1)


def test_cdist_threshold_option():
    a, b = ref.random_pairs(30, np.random.default_rng(3))
    d = geofeas.cdist(a, b, score="glr", threshold=True)
    np.testing.assert_array_equal(np.diag(d), geofeas.glr(a, b, threshold=True))


def test_giant_cdist_refused_before_allocating():
    big = np.tile(A, (200_000, 1))
    with pytest.raises(GeofeasError, match="exceeds"):
        geofeas.cdist(big, big)
    with pytest.raises(GeofeasError, match="exceeds"):
        geofeas.cdist(A, B, max_bytes=4)


def test_non_contiguous_and_int_input():
    a, b = ref.random_pairs(20, np.random.default_rng(4))
    wide = np.zeros((20, 10))
    wide[:, ::2] = a
    strided = wide[:, ::2]
    assert not strided.flags.c_contiguous
    np.testing.assert_array_equal(geofeas.glr(strided, b), geofeas.glr(a, b))
    np.testing.assert_array_equal(geofeas.glr(np.asfortranarray(a), b), geofeas.glr(a, b))
    ints = np.array([[0, 0, 2, 1, 0], [1, 1, 3, 2, 1]])
    np.testing.assert_array_equal(
        geofeas.glr(ints, ints[::-1]), geofeas.glr(ints.astype(float), ints[::-1].astype(float))
    )
    assert geofeas.glr([0, 0, 1, 1, 0], (0.5, 0, 1, 1, 0)) == pytest.approx(
        np.exp(-0.25 * 0.5 * 4 / 2 * 0.5 * 2)
    )
    f32 = a.astype(np.float32)
    assert geofeas.glr(f32, b).dtype == np.float64


@pytest.mark.parametrize(
    "row, field, value",
    [(2, "x0", np.nan), (0, "y0", np.inf), (1, "rx", 0.0), (3, "ry", -1.0), (2, "phi", -np.inf)],
)
@pytest.mark.parametrize("fn", [geofeas.glr, geofeas.overlap, geofeas.monte_carlo])
def test_bad_values_name_row_and_field(fn, row, field, value):
    a, b = ref.random_pairs(5, np.random.default_rng(5))
    a[row, ["x0", "y0", "rx", "ry", "phi"].index(field)] = value
    with pytest.raises(ValueError, match=rf"row {row}: field '{field}'"):
        fn(a, b)
    with pytest.raises(ValueError, match=rf"row {row}: field '{field}'"):
        fn(b, a)
    with pytest.raises(ValueError, match=rf"row {row}"):
        geofeas.cdist(b, a, score="glr")


def test_bad_shapes_and_dtypes():
    with pytest.raises(ValueError, match=r"shape \(5,\) or an array of shape \(n, 5\)"):
        geofeas.glr(np.zeros((3, 4)), np.zeros((3, 4)))
    with pytest.raises(ValueError, match="length mismatch"):
        geofeas.glr(np.tile(A, (3, 1)), np.tile(B, (2, 1)))
    with pytest.raises(ValueError, match="not a real number type"):
        geofeas.glr(np.array([["a"] * 5]), A)
    with pytest.raises(ValueError, match="complex"):
        geofeas.glr(A.astype(complex), B)
    with pytest.raises(ValueError, match="cannot be read"):
        geofeas.glr([[1, 2, 3, 4, 5], [1, 2]], A)
    with pytest.raises(ValueError, match="vertices"):
        geofeas.overlap(A, B, vertices=3)
    with pytest.raises(ValueError, match="samples"):
        geofeas.monte_carlo(A, B, samples=0)
    with pytest.raises(ValueError, match="seed"):
        geofeas.monte_carlo(A, B, seed=-1)
    with pytest.raises(ValueError, match="do not apply"):
        geofeas.cdist(A, B, score="glr", samples=10)
    with pytest.raises(ValueError, match="unknown score"):
        geofeas.cdist(A, B, score="nope")
    with pytest.raises(ValueError, match="method"):
        geofeas.overlap(A, B, method="magic")


def test_gaussian_round_trip_and_formula():
    e = np.array([[1.0, 2.0, 4.0, 2.0, 0.0], [0.0, 0.0, 3.0, 1.0, 0.7], [5, 5, 2, 2, 0]])
    mean, cov = geofeas.to_gaussian(e)
    np.testing.assert_array_equal(mean, e[:, :2])
    np.testing.assert_allclose(cov, ref.covariance(e), rtol=1e-14, atol=1e-15)
    back = geofeas.from_gaussian(mean, cov)
    np.testing.assert_allclose(ref.covariance(back), cov, rtol=1e-12, atol=1e-14)
    assert np.all(back[:, 2] >= back[:, 3])
    assert np.all((back[:, 4] >= 0) & (back[:, 4] < np.pi))
    m1, c1 = geofeas.to_gaussian(e[1])
    assert m1.shape == (2,) and c1.shape == (2, 2)
    assert geofeas.from_gaussian(m1, c1).shape == (5,)


def test_from_gaussian_nearly_singular_and_circles():
    cov = np.array([[[1.0, 0.0], [0.0, 1.0]], [[1e6, 1e6 - 1e-3], [1e6 - 1e-3, 1e6]]])
    e = geofeas.from_gaussian(np.zeros((2, 2)), cov)
    assert e[0, 4] == 0.0 and e[0, 2] == e[0, 3] == 2.0
    # eigenvalues 2e6 - 1e-3 and 1e-3: the small axis keeps its digits
    assert e[1, 3] == pytest.approx(2 * np.sqrt(1e-3), rel=1e-6)
    assert e[1, 4] == pytest.approx(np.pi / 4, abs=1e-12)


def test_from_gaussian_rejects_bad_covariances():
    with pytest.raises(ValueError, match="row 1.*positive definite"):
        geofeas.from_gaussian(np.zeros((2, 2)), np.array([np.eye(2), [[1, 2], [2, 1]]]))
    with pytest.raises(ValueError, match="row 0.*symmetric"):
        geofeas.from_gaussian(np.zeros((1, 2)), np.array([[[1, 0.5], [0.1, 1]]]))
    with pytest.raises(ValueError, match="row 0: field 'cov_yy' is not finite"):
        geofeas.from_gaussian(np.zeros((1, 2)), np.array([[[1, 0], [0, np.nan]]]))
    with pytest.raises(ValueError, match=r"\(n, 2\) and \(n, 2, 2\)"):
        geofeas.from_gaussian(np.zeros((1, 3)), np.eye(2)[None])


def test_monte_carlo_bit_identical_across_thread_counts():
    code = (
        "import numpy as np, geofeas, sys;"
        "rng = np.random.default_rng(0);"
        "a = rng.uniform(1, 2, (3000, 5));"
        "b = a + rng.uniform(-1, 1, (3000, 5)) * [1, 1, 0.2, 0.2, 1];"
        "sys.stdout.write(geofeas.monte_carlo(a, b, seed=77).tobytes().hex())"
    )
    outs = []
    for threads in ("1", "2", "3"):
        env = dict(os.environ, RAYON_NUM_THREADS=threads)
        outs.append(
            subprocess.run(
                [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
            ).stdout
        )
    assert outs[0] == outs[1] == outs[2]


def test_ctrl_c_interrupts_a_long_call():
    big = np.tile(A, (3000, 1))
    # a runner may start the tests with SIGINT ignored; Python's own handler must be in place for
    # the signal to become KeyboardInterrupt (otherwise this would run for minutes, not fail)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            geofeas.cdist(big, big, score="monte_carlo", samples=5000, seed=1)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)


def test_gil_is_released_during_work():
    a = np.tile(A, (2_000_000, 1))
    ticks = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(1)
            stop.wait(0.001)

    t = threading.Thread(target=ticker)
    t.start()
    before = len(ticks)
    geofeas.monte_carlo(a[:200_000], a[:200_000], samples=200, seed=1)
    during = len(ticks) - before
    stop.set()
    t.join()
    assert during > 5


def test_vertices_alone_selects_the_polygon_method() -> None:
    rng = np.random.default_rng(5)
    a, b = ref.random_pairs(200, rng)
    poly = geofeas.overlap(a, b, method="polygon", vertices=64)
    np.testing.assert_array_equal(geofeas.overlap(a, b, vertices=64), poly)
    np.testing.assert_array_equal(
        geofeas.cdist(a[:5], b[:7], score="overlap", vertices=64),
        geofeas.cdist(a[:5], b[:7], score="overlap", method="polygon", vertices=64),
    )
    # 64 vertices differ from the exact value by more than rounding, so the method really changed
    assert np.max(np.abs(poly - geofeas.overlap(a, b))) > 1e-9
    with pytest.raises(ValueError, match="vertices"):
        geofeas.overlap(a, b, method="exact", vertices=64)
