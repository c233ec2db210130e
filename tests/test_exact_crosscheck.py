"""The exact overlap against an independent 60-digit reference (``exact_reference.py``, mpmath)
on the hard classes: thin ellipses (aspect up to 1e6), tangent pairs (internal and external, at
offsets down to 0, crossing elsewhere or not), near-identical pairs and pairs far from the
origin, in both argument orders; and the polygon method against it on the same pairs."""

from __future__ import annotations

import math

import numpy as np
import pytest

import geofeas

exact_reference = pytest.importorskip("exact_reference")

TOL = 1e-11


def _normal_point(shape, normal):
    """The boundary point (relative to the centre) of ellipse ``shape = (rx, ry, phi)`` whose
    outward normal is ``normal`` (unit, world frame)."""
    rx, ry, phi = shape
    e1 = np.array([math.sin(phi), math.cos(phi)])
    e2 = np.array([math.cos(phi), -math.sin(phi)])
    n1, n2 = normal @ e1, normal @ e2
    k = math.sqrt((rx * n1) ** 2 + (ry * n2) ** 2)
    return (rx * rx * n1 * e1 + ry * ry * n2 * e2) / k


def _boundary(e, t):
    x0, y0, rx, ry, phi = e
    e1 = np.array([math.sin(phi), math.cos(phi)])
    e2 = np.array([math.cos(phi), -math.sin(phi)])
    p = np.array([x0, y0]) + rx * math.cos(t) * e1 + ry * math.sin(t) * e2
    # outward normal: gradient of the quadratic form
    n = math.cos(t) / rx * e1 + math.sin(t) / ry * e2
    return p, n / np.linalg.norm(n)


def _shape(rng, max_log_aspect):
    r = 10 ** rng.uniform(-0.5, 0.5)
    aspect = 10 ** rng.uniform(0, max_log_aspect)
    return r * math.sqrt(aspect), r / math.sqrt(aspect), rng.uniform(0, 2 * math.pi)


def tangent_pair(rng, internal, offset, max_log_aspect=6):
    """Ellipses tangent at one point (externally or internally: the second on the inside of
    the first there), the second then moved by ``offset`` (relative to its size) along the
    normal."""
    a = np.array([0.0, 0.0, *_shape(rng, max_log_aspect)])
    p, n = _boundary(a, rng.uniform(0, 2 * math.pi))
    shape = _shape(rng, max_log_aspect)
    q = _normal_point(shape, n if internal else -n)
    centre = p - q + offset * math.sqrt(shape[0] * shape[1]) * n
    return a, np.array([centre[0], centre[1], *shape])


def cases():
    rng = np.random.default_rng(20261202)
    out = []
    for _ in range(40):  # thin, random crossings
        a = np.array([0.0, 0.0, *_shape(rng, 6)])
        b = np.array([*rng.uniform(-1, 1, 2) * a[2] * 0.5, *_shape(rng, 6)])
        out.append(("thin", a, b))
    for internal in (False, True):  # tangent, at offsets down to 0
        for offset in (0.0, 1e-15, -1e-15, 1e-12, -1e-12, 1e-9, -1e-9, 1e-6, -1e-6, 1e-3):
            for _ in range(6):
                a, b = tangent_pair(rng, internal, offset, max_log_aspect=rng.choice([1, 3, 6]))
                out.append(("internal" if internal else "external", a, b))
    for rel in (0.0, 1e-16, 1e-13, 1e-10, 1e-7, 1e-4):  # near-identical
        for _ in range(5):
            a = np.array([*rng.uniform(-10, 10, 2), *_shape(rng, 2)])
            b = a * (1 + rel * rng.standard_normal(5))
            out.append(("near-identical", a, b))
    for far in (1e6, 1e9):  # far from the origin (the reference gets the same doubles)
        for _ in range(10):
            a, b = tangent_pair(rng, bool(rng.integers(2)), rng.choice([0.0, 1e-9, -0.1]), 2)
            shift = far * rng.uniform(-1, 1, 2)
            a[:2] += shift
            b[:2] += shift
            out.append(("far", a, b))
    return out


CASES = cases()


@pytest.mark.parametrize("kind, a, b", CASES, ids=[f"{c[0]}-{i}" for i, c in enumerate(CASES)])
def test_exact_overlap_matches_the_reference(kind, a, b):
    truth = float(exact_reference.overlap(a, b))
    for p, q in ((a, b), (b, a)):
        g = geofeas.overlap(p, q)
        assert 0.0 <= g <= 1.0
        assert abs(g - truth) <= TOL, (kind, list(p), list(q), g, truth)


POLYGON_CASES = CASES[::4]


@pytest.mark.parametrize(
    "kind, a, b", POLYGON_CASES, ids=[f"{c[0]}-{i}" for i, c in enumerate(POLYGON_CASES)]
)
def test_polygon_overlap_within_its_bound(kind, a, b):
    truth = float(exact_reference.overlap(a, b))
    vertices = 1024
    ratio = max(a[2] * a[3], b[2] * b[3]) / min(a[2] * a[3], b[2] * b[3])
    bound = 26 * (1 + ratio) / vertices**3
    for p, q in ((a, b), (b, a)):
        g = geofeas.overlap(p, q, method="polygon", vertices=vertices)
        assert 0.0 <= g <= 1.0
        # thin ellipses: the polygon of a needle is itself a needle, the bound still holds;
        # rounding of the clipper adds at most 1e-9
        assert abs(g - truth) <= bound + 1e-9, (kind, list(p), list(q), g, truth)
