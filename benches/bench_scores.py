"""Speed of the geofeas scores against baselines measured in the same run.

    python benches/bench_scores.py [--quick]

Baselines: the independent NumPy reference of the tests (``tests/reference.py``: eq. 71 from the
matrices of eqs. 56-58 and a batched linear solve, elementwise and broadcast over all pairs), a
hand-tuned closed-form NumPy version of eq. 71 (the strongest NumPy baseline), shapely 2
(vectorised ``shapely.intersection`` + ``shapely.area`` on prebuilt 64-gons), and the paper's own
figures (Fig. 3: about 1 ms per Monte-Carlo evaluation at N = 500, 0.04 ms per GLR). Prints a
Markdown table of best-of-k wall times and ratios.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests"))
import geofeas  # noqa: E402

import reference as ref  # noqa: E402


def best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def cov3(e: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    s, c = np.sin(e[:, 4]), np.cos(e[:, 4])
    a, b = e[:, 2] ** 2 / 4, e[:, 3] ** 2 / 4
    return a * s * s + b * c * c, (a - b) * s * c, a * c * c + b * s * s


def numpy_glr(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    axx, axy, ayy = cov3(a)
    bxx, bxy, byy = cov3(b)
    sxx, sxy, syy = axx + bxx, axy + bxy, ayy + byy
    dx, dy = a[:, 0] - b[:, 0], a[:, 1] - b[:, 1]
    q = (syy * dx * dx - 2 * sxy * dx * dy + sxx * dy * dy) / (sxx * syy - sxy * sxy)
    return np.exp(-0.5 * q)


def numpy_glr_cdist(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    axx, axy, ayy = (x[:, None] for x in cov3(a))
    bxx, bxy, byy = (x[None, :] for x in cov3(b))
    sxx, sxy, syy = axx + bxx, axy + bxy, ayy + byy
    dx = a[:, 0, None] - b[None, :, 0]
    dy = a[:, 1, None] - b[None, :, 1]
    q = (syy * dx * dx - 2 * sxy * dx * dy + sxx * dy * dy) / (sxx * syy - sxy * sxy)
    return np.exp(-0.5 * q)


def reference_cdist(a: np.ndarray, b: np.ndarray, rows: int = 100) -> np.ndarray:
    """The reference's eq. 71 broadcast over all pairs, ``rows`` rows of ``a`` at a time."""
    out = np.empty((len(a), len(b)))
    for i in range(0, len(a), rows):
        blk = a[i : i + rows]
        out[i : i + rows] = ref.glr(np.repeat(blk, len(b), 0), np.tile(b, (len(blk), 1))).reshape(
            len(blk), len(b)
        )
    return out


def shapely_polygons(e: np.ndarray, n: int):
    import shapely

    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    s, c = np.sin(e[:, 4:5]), np.cos(e[:, 4:5])
    u, v = e[:, 2:3] * np.cos(t), e[:, 3:4] * np.sin(t)
    x = e[:, 0:1] + u * s + v * c
    y = e[:, 1:2] + u * c - v * s
    return shapely.polygons(np.stack([x, y], -1))


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--quick", action="store_true", help="smaller sizes (a smoke run)")
    args = p.parse_args()
    q = args.quick
    rows = []
    rng = np.random.default_rng(0)

    n = 100_000 if q else 1_000_000
    a, b = ref.random_pairs(n, rng)
    np.testing.assert_allclose(geofeas.glr(a, b), numpy_glr(a, b), rtol=1e-12, atol=1e-320)
    t_ref = best(lambda: ref.glr(a, b), 3)
    t_np = best(lambda: numpy_glr(a, b), 3)
    t_gf = best(lambda: geofeas.glr(a, b), 5)
    rows.append((f"glr elementwise, {n:,} pairs", "NumPy reference", n, t_ref, t_gf))
    rows.append((f"glr elementwise, {n:,} pairs", "NumPy closed form (tuned)", n, t_np, t_gf))

    m = 1000 if q else 3000
    ca, cb = ref.random_pairs(m, rng)
    np.testing.assert_allclose(
        geofeas.cdist(ca, cb), numpy_glr_cdist(ca, cb), rtol=1e-12, atol=1e-320
    )
    t_ref = best(lambda: reference_cdist(ca, cb), 1)
    t_np = best(lambda: numpy_glr_cdist(ca, cb), 3)
    t_gf = best(lambda: geofeas.cdist(ca, cb), 5)
    case = f"cdist glr, {m:,} x {m:,}"
    rows.append((case, "NumPy reference, broadcast", m * m, t_ref, t_gf))
    rows.append((case, "NumPy closed form, broadcast (tuned)", m * m, t_np, t_gf))

    import shapely

    k = 20_000
    pa, pb = ref.random_pairs(k, rng)
    sa, sb = shapely_polygons(pa, 64), shapely_polygons(pb, 64)
    t_sh = best(lambda: shapely.area(shapely.intersection(sa, sb)), 3)
    t_gf = best(lambda: geofeas.overlap(pa, pb, method="polygon", vertices=64), 5)
    rows.append((f"overlap, 64 vertices, {k:,} pairs", "shapely 2 vectorised", k, t_sh, t_gf))
    t_poly = best(lambda: geofeas.overlap(pa, pb, method="polygon"), 5)
    rows.append(
        (
            f"overlap, polygon {geofeas.DEFAULT_VERTICES} vertices, {k:,} pairs",
            "shapely 2 at 64 vertices",
            k,
            t_sh,
            t_poly,
        )
    )
    t_ex = best(lambda: geofeas.overlap(pa, pb), 5)
    rows.append(
        (f"overlap, exact (default), {k:,} pairs", "shapely 2 at 64 vertices", k, t_sh, t_ex)
    )
    rows.append(
        (
            f"overlap, exact (default), {k:,} pairs",
            f"geofeas polygon {geofeas.DEFAULT_VERTICES} vertices",
            k,
            t_poly,
            t_ex,
        )
    )
    kq = 20
    t_ref = best(lambda: ref.overlap_quad(pa[:kq], pb[:kq]), 1) * (k / kq)
    rows.append(
        (
            f"overlap, exact (default), {k:,} pairs",
            "NumPy/SciPy quadrature reference",
            k,
            t_ref,
            t_ex,
        )
    )
    k = 1_000_000 if not q else 200_000
    xa, xb = ref.random_pairs(k, rng)
    t_ex = best(lambda: geofeas.overlap(xa, xb), 3)
    t_glr = best(lambda: geofeas.glr(xa, xb), 3)
    rows.append(
        (f"overlap, exact (default), {k:,} pairs", "geofeas glr (same pairs)", k, t_glr, t_ex)
    )

    k = 50_000 if q else 200_000
    ma, mb = ref.random_pairs(k, rng)
    t_gf = best(lambda: geofeas.monte_carlo(ma, mb, samples=500, seed=1), 3)
    rows.append((f"monte_carlo N=500, {k:,} pairs", "paper Fig. 3 (1 ms/pair)", k, k * 1e-3, t_gf))
    t_sob = best(lambda: geofeas.monte_carlo(ma, mb, samples=64, seed=1, sampler="sobol"), 3)
    rows.append(
        (f"monte_carlo sobol N=64, {k:,} pairs", "geofeas importance N=500", k, t_gf, t_sob)
    )

    print(f"threads: {os.cpu_count()} cpus; numpy {np.__version__}; shapely {shapely.__version__}")
    print()
    print("| case | baseline | baseline s | geofeas s | speed-up | geofeas pairs/s |")
    print("|---|---|---|---|---|---|")
    for case, base, pairs, tb, tg in rows:
        print(f"| {case} | {base} | {tb:.4f} | {tg:.4f} | {tb / tg:.1f}x | {pairs / tg:,.0f} |")


if __name__ == "__main__":
    main()
