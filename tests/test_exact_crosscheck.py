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


def shallow_pair(rng, aspect, tilt):
    """A thin ellipse lying along the boundary of a larger one and crossing it twice at a
    shallow angle: centred just inside the boundary point with normal ``n``, its long axis along
    the tangent turned by ``tilt``. The crossings are ill-conditioned (``|g'|`` down to 1e-6), so
    one rounding of the frames moves the area by more than 1e-11."""
    b = np.array([0.0, 0.0, *_shape(rng, 2)])
    p, n = _boundary(b, rng.uniform(0, 2 * math.pi))
    length = 10 ** rng.uniform(-2.5, -1) * math.sqrt(b[2] * b[3])
    tangent = np.array([-n[1], n[0]])
    axis = math.cos(tilt) * tangent + math.sin(tilt) * n
    centre = p - 0.5 * length * abs(math.sin(tilt)) * n
    # bearing of the rx axis: (sin phi, cos phi) = axis
    phi = math.atan2(axis[0], axis[1])
    return np.array([centre[0], centre[1], length, length / aspect, phi]), b


CASES = cases()

# A thin ellipse crossing a larger one at a very shallow angle (found by fuzzing; each was off
# by 2e-11 to 3e-11 when its crossings were refined in doubles only), and generated pairs of
# the same class.
SHALLOW = [
    (
        [
            2.4445362158345643,
            -6.838384499123773,
            0.02344338863362363,
            1.930177086930869e-5,
            -0.38631939816910593,
        ],
        [0, 0, 7.611223842986369, 0.09354348924548375, 2.794422513907926],
    ),
    (
        [
            12.190369172649886,
            -8.471524944210286,
            0.0720433878694075,
            1.6312592174523283e-5,
            -1.2291512879642885,
        ],
        [0, 0, 30.231512331752178, 3.4240014352315886, 1.974482218256914],
    ),
]
_rng = np.random.default_rng(20261203)
SHALLOW += [
    shallow_pair(_rng, 10 ** _rng.uniform(2, 4), _rng.choice([-1, 1]) * 10 ** _rng.uniform(-5, -2))
    for _ in range(20)
]


@pytest.mark.parametrize("a, b", SHALLOW, ids=[f"shallow-{i}" for i in range(len(SHALLOW))])
def test_shallow_crossings_match_the_reference(a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    truth = exact_reference.overlap(a, b)
    area = float(exact_reference.area(a, b))
    for p, q in ((a, b), (b, a)):
        g = geofeas.overlap(p, q)
        assert 0.0 <= g <= 1.0
        assert abs(g - float(truth)) <= TOL, (list(p), list(q), g, float(truth))
        assert abs(geofeas.intersection_area(p, q) - area) <= TOL * area


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
