"""Fuzzing campaign over the public Python functions of geofeas (the README's "Reliability").

For every function: ``--calls`` evaluations (pairs or rows), half inside the documented input
domain at its extremes (semi-axes 1e-50 .. 1e50, aspect up to 1e8, centres up to 1e50, tangent,
identical and near-identical pairs) scored in batches, half raw adversarial doubles (NaN,
infinities, zeros, signed zeros, subnormals, 1e308, values just outside the domain) called one
row at a time. A call must give a ``GeofeasError`` or a finite value in the function's range;
anything else (another exception, NaN, out of range, a crash of the process) is a finding.

    python scripts/fuzz_python.py [--calls N] [--seed S]

Prints one line per function: calls, errors raised (expected refusals), findings; exits 1 on
any finding.
"""

from __future__ import annotations

import argparse
import math
import sys
import time

import numpy as np

import geofeas
from geofeas import GeofeasError

SPECIAL = np.array(
    [
        0.0,
        -0.0,
        np.nan,
        np.inf,
        -np.inf,
        5e-324,
        2.2e-308,
        1e-300,
        1e-51,
        1e-50,
        1.0,
        1e50,
        1.01e50,
        1e300,
        1.7976931348623157e308,
        -1.0,
        -1e300,
    ]
)


def domain_pairs(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    """``n`` valid pairs at the extremes of the domain, of every hard kind."""
    scale = 10 ** rng.uniform(-45, 45, n)
    aspect_a = 10 ** rng.uniform(0, 8, n)
    aspect_b = 10 ** rng.uniform(0, 8, n)
    a = np.empty((n, 5))
    b = np.empty((n, 5))
    a[:, 2] = scale * np.sqrt(aspect_a)
    a[:, 3] = scale / np.sqrt(aspect_a)
    a[:, 4] = rng.uniform(-10, 10, n)
    centre = rng.choice([0.0, 1.0, 1e6, 1e15], n) * scale * rng.uniform(-1, 1, n)
    a[:, 0] = centre
    a[:, 1] = -centre
    kind = rng.integers(0, 4, n)
    # 0: random partner at a comparable scale
    other = scale * 10 ** rng.uniform(-3, 3, n)
    b[:, 2] = other * np.sqrt(aspect_b)
    b[:, 3] = other / np.sqrt(aspect_b)
    b[:, 4] = rng.uniform(-10, 10, n)
    b[:, 0] = a[:, 0] + rng.standard_normal(n) * np.maximum(a[:, 2], b[:, 2])
    b[:, 1] = a[:, 1] + rng.standard_normal(n) * np.maximum(a[:, 2], b[:, 2])
    # 1: identical; 2: near-identical; 3: same centre, rotated (crossed needles)
    same = kind == 1
    b[same] = a[same]
    near = kind == 2
    rel = 10.0 ** rng.integers(-16, -3, near.sum())[:, None]
    b[near] = a[near] * (1 + rel * rng.standard_normal((near.sum(), 5)))
    crossed = kind == 3
    b[crossed] = a[crossed]
    b[crossed, 4] += rng.uniform(0, np.pi, crossed.sum())
    # keep every row inside the domain
    for e in (a, b):
        big = np.maximum(e[:, 2], e[:, 3])
        small = np.minimum(e[:, 2], e[:, 3])
        ok = (small >= 1e-50) & (big <= 1e50) & (big <= 1e8 * small)
        ok &= (np.abs(e[:, 0]) <= 1e50) & (np.abs(e[:, 1]) <= 1e50)
        e[~ok] = [0.0, 0.0, 2.0, 1.0, 0.3]
    return a, b


def raw_rows(rng: np.random.Generator, n: int) -> np.ndarray:
    """Rows of adversarial doubles: specials, random magnitudes, random bit patterns."""
    out = SPECIAL[rng.integers(0, len(SPECIAL), (n, 5))]
    with np.errstate(over="ignore"):
        mag = rng.standard_normal((n, 5)) * 10.0 ** rng.uniform(-320, 308, (n, 5))
    pick = rng.random((n, 5)) < 0.5
    out[pick] = mag[pick]
    bits = rng.random((n, 5)) < 0.1
    out[bits] = rng.integers(0, 2**63, bits.sum(), dtype=np.int64).view(np.float64)
    return out


def in_unit(v: np.ndarray) -> bool:
    return bool(np.all(np.isfinite(v)) and np.all(v >= 0.0) and np.all(v <= 1.0))


def check_scores(rng, name, fn, calls, batch=1000):
    findings = []
    errors = 0
    half = calls // 2
    done = 0
    while done < half:
        a, b = domain_pairs(rng, batch)
        try:
            g = np.asarray(fn(a, b))
        except GeofeasError as exc:
            findings.append(f"domain batch refused: {exc}")
            break
        if not in_unit(g):
            bad = int(np.flatnonzero(~((g >= 0) & (g <= 1)))[0])
            findings.append(f"{list(a[bad])} {list(b[bad])} -> {g[bad]}")
        done += batch
    rows_a, rows_b = raw_rows(rng, half), raw_rows(rng, half)
    for k in range(half):
        try:
            g = fn(rows_a[k], rows_b[k])
        except GeofeasError:
            errors += 1
            continue
        except Exception as exc:  # noqa: BLE001 - a finding
            findings.append(f"{list(rows_a[k])} {list(rows_b[k])}: {type(exc).__name__}: {exc}")
            continue
        if not (math.isfinite(g) and 0.0 <= g <= 1.0):
            findings.append(f"{list(rows_a[k])} {list(rows_b[k])} -> {g}")
    return done + half, errors, findings


def check_area(rng, calls, batch=1000):
    findings = []
    errors = 0
    half = calls // 2
    done = 0
    while done < half:
        a, b = domain_pairs(rng, batch)
        area = geofeas.intersection_area(a, b)
        small = np.pi * np.minimum(a[:, 2] * a[:, 3], b[:, 2] * b[:, 3])
        bad = ~(np.isfinite(area) & (area >= 0) & (area <= small * (1 + 1e-12)))
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            findings.append(f"{list(a[k])} {list(b[k])} -> {area[k]}")
        done += batch
    for _ in range(half):
        a, b = raw_rows(rng, 1)[0], raw_rows(rng, 1)[0]
        try:
            v = geofeas.intersection_area(a, b)
        except GeofeasError:
            errors += 1
            continue
        if not (math.isfinite(v) and v >= 0):
            findings.append(f"{list(a)} {list(b)} -> {v}")
    return done + half, errors, findings


def check_gaussian(rng, calls, batch=1000):
    findings = []
    errors = 0
    done = 0
    while done < calls // 2:
        a, _ = domain_pairs(rng, batch)
        mean, cov = geofeas.to_gaussian(a)
        if not (np.all(np.isfinite(mean)) and np.all(np.isfinite(cov))):
            findings.append("to_gaussian: non-finite output")
        # aspect 1e8 means covariance eigenvalues 1e16 apart: the stored matrix may be
        # singular to rounding, which from_gaussian refuses (a refusal, not a finding)
        for k in range(0, batch, 100):
            try:
                back = geofeas.from_gaussian(mean[k : k + 100], cov[k : k + 100])
            except GeofeasError:
                errors += 1
                continue
            if not np.all(np.isfinite(back)):
                findings.append("from_gaussian: non-finite output")
        done += batch
    for _ in range(calls // 2):
        row = raw_rows(rng, 1)[0]
        try:
            mean, cov = geofeas.to_gaussian(row)
        except GeofeasError:
            errors += 1
            continue
        if not (np.all(np.isfinite(mean)) and np.all(np.isfinite(cov))):
            findings.append(f"to_gaussian({list(row)}) non-finite")
    return done + calls // 2, errors, findings


def check_combine(rng, calls):
    findings = []
    errors = 0
    n = 0
    while n < calls:
        k = int(rng.integers(0, 6))
        g = SPECIAL[rng.integers(0, len(SPECIAL), k)] if rng.random() < 0.5 else rng.random(k)
        try:
            v = geofeas.combine_instants(g)
        except GeofeasError:
            errors += 1
        except Exception as exc:  # noqa: BLE001 - a finding
            findings.append(f"{list(g)}: {type(exc).__name__}: {exc}")
        else:
            if not (math.isfinite(v) and 0.0 <= v <= 1.0):
                findings.append(f"{list(g)} -> {v}")
        n += 1
    return n, errors, findings


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--calls", type=int, default=100_000)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    functions = {
        "glr": geofeas.glr,
        "glr(threshold)": lambda a, b: geofeas.glr(a, b, threshold=True),
        "overlap": geofeas.overlap,
        "overlap(polygon)": lambda a, b: geofeas.overlap(a, b, vertices=64),
        "monte_carlo": lambda a, b: geofeas.monte_carlo(a, b, samples=16, seed=1),
        "bhattacharyya": geofeas.bhattacharyya,
        "hellinger": geofeas.hellinger,
        "gaussian_product": geofeas.gaussian_product,
        "cdist(overlap)": lambda a, b: geofeas.cdist(
            np.atleast_2d(a)[:40], np.atleast_2d(b)[:25], score="overlap"
        ).ravel(),
    }
    total_findings = 0
    for name, fn in functions.items():
        t0 = time.perf_counter()
        calls, errors, findings = check_scores(rng, name, fn, args.calls)
        total_findings += len(findings)
        print(
            f"{name:<18} {calls:>8} calls  {errors:>7} refused  {len(findings)} findings  "
            f"({time.perf_counter() - t0:.1f} s)"
        )
        for f in findings[:5]:
            print("   ", f)
    for name, check in (
        ("intersection_area", check_area),
        ("to/from_gaussian", check_gaussian),
        ("combine_instants", check_combine),
    ):
        t0 = time.perf_counter()
        calls, errors, findings = check(rng, args.calls)
        total_findings += len(findings)
        print(
            f"{name:<18} {calls:>8} calls  {errors:>7} refused  {len(findings)} findings  "
            f"({time.perf_counter() - t0:.1f} s)"
        )
        for f in findings[:5]:
            print("   ", f)
    return 1 if total_findings else 0


if __name__ == "__main__":
    sys.exit(main())
