"""Property-based tests (hypothesis) over the public functions: inside the documented input
domain every score is a finite number in its range, symmetric where the score is, invariant
under scaling and translation, 1 (or 0 for Hellinger) for identical ellipses; any input at all
gives a value or a GeofeasError naming the argument, never another exception or NaN. Bounded
(a few hundred examples per property) so the suite stays fast."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import geofeas
from geofeas import GeofeasError

SETTINGS = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])

SCORES = {
    "glr": geofeas.glr,
    "glr_threshold": lambda a, b: geofeas.glr(a, b, threshold=True),
    "overlap": geofeas.overlap,
    "overlap_polygon": lambda a, b: geofeas.overlap(a, b, vertices=128),
    "monte_carlo": lambda a, b: geofeas.monte_carlo(a, b, samples=64, seed=3),
    "bhattacharyya": geofeas.bhattacharyya,
    "hellinger": geofeas.hellinger,
    "gaussian_product": geofeas.gaussian_product,
}
SYMMETRIC = ("glr", "overlap", "bhattacharyya", "hellinger", "gaussian_product")


SCALE_EXPONENTS = st.integers(-40, 40)


@st.composite
def ellipses(draw, scale_exp=SCALE_EXPONENTS):
    """A valid ellipse inside the domain: semi-axes 10^(-40..40), aspect up to 1e8."""
    k = draw(scale_exp)
    scale = 10.0**k
    aspect = 10.0 ** draw(st.floats(0, 7.99))
    r = scale * draw(st.floats(0.5, 2))
    x = draw(st.floats(-1e3, 1e3)) * scale
    y = draw(st.floats(-1e3, 1e3)) * scale
    phi = draw(st.floats(-10, 10))
    return np.array([x, y, r * math.sqrt(aspect), r / math.sqrt(aspect), phi])


@st.composite
def pairs(draw):
    a = draw(ellipses())
    # the partner at a comparable scale, near enough to overlap often
    size = math.sqrt(a[2] * a[3])
    b = draw(ellipses(st.just(int(round(math.log10(size)))))).copy()
    b[:2] = a[:2] + np.array(draw(st.tuples(st.floats(-3, 3), st.floats(-3, 3)))) * max(a[2], b[2])
    return a, b


@SETTINGS
@given(pairs())
def test_scores_in_range_and_symmetric(pair):
    a, b = pair
    for name, fn in SCORES.items():
        g = fn(a, b)
        assert math.isfinite(g) and 0.0 <= g <= 1.0, (name, list(a), list(b), g)
        if name in SYMMETRIC:
            assert fn(b, a) == pytest.approx(g, rel=1e-9, abs=1e-12), name


@SETTINGS
@given(ellipses())
def test_identical_ellipses(e):
    assert geofeas.glr(e, e) == 1.0
    assert geofeas.overlap(e, e) == 1.0
    assert geofeas.overlap(e, e, vertices=256) == 1.0
    assert geofeas.bhattacharyya(e, e) == pytest.approx(1.0, abs=1e-12)
    assert geofeas.hellinger(e, e) == pytest.approx(0.0, abs=1e-6)


@SETTINGS
@given(pairs(), st.integers(-60, 60), st.floats(-1e3, 1e3))
def test_invariant_under_scale_and_translation(pair, k, shift):
    a, b = pair
    s = 2.0**k  # a power of two: the scaled inputs are exact
    sa, sb = a.copy(), b.copy()
    sa[:4] *= s
    sb[:4] *= s
    assume(all(1e-50 <= v <= 1e50 for v in (*sa[2:4], *sb[2:4])))
    assume(all(abs(v) <= 1e50 for v in (*sa[:2], *sb[:2])))
    for name in ("glr", "overlap", "bhattacharyya", "hellinger"):
        fn = SCORES[name]
        assert fn(sa, sb) == pytest.approx(fn(a, b), rel=1e-9, abs=1e-12), name
    # a translation by a multiple of the size, exact in binary
    t = math.ldexp(round(shift), int(math.floor(math.log2(max(a[2], b[2])))))
    ta, tb = a.copy(), b.copy()
    ta[0] += t
    tb[0] += t
    assume(ta[0] - tb[0] == a[0] - b[0])
    assert geofeas.overlap(ta, tb) == pytest.approx(geofeas.overlap(a, b), abs=1e-11)


ANY_FLOAT = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 5e-324, 1e-50, 1e50, 1.01e50, 1e300]),
)


@SETTINGS
@given(st.lists(ANY_FLOAT, min_size=5, max_size=5), st.lists(ANY_FLOAT, min_size=5, max_size=5))
def test_any_input_gives_a_value_or_a_named_error(a, b):
    for name, fn in SCORES.items():
        try:
            g = fn(a, b)
        except GeofeasError as exc:
            assert exc.argument in ("a", "b"), (name, str(exc))
            assert exc.row == 0 and exc.field in ("x0", "y0", "rx", "ry", "phi"), str(exc)
            continue
        assert math.isfinite(g) and 0.0 <= g <= 1.0, (name, a, b, g)


@SETTINGS
@given(
    st.lists(st.floats(0, 1), min_size=1, max_size=20),
    st.sampled_from(["chi2", "mean", "geometric", "min"]),
)
def test_combine_instants_stays_in_range(g, rule):
    try:
        v = geofeas.combine_instants(g, rule=rule)
    except GeofeasError as exc:
        assert "rule" in str(exc)
        return
    assert math.isfinite(v) and 0.0 <= v <= 1.0


IDS = st.text(alphabet="0123456789abc_-", min_size=1, max_size=4)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        st.tuples(IDS, st.sampled_from(["ais", "radar"]), st.integers(0, 5), ANY_FLOAT),
        min_size=1,
        max_size=8,
    )
)
def test_reader_keeps_ids_or_names_the_row(rows):
    frame = pd.DataFrame(
        {
            "track_id": [r[0] for r in rows],
            "source": [r[1] for r in rows],
            "time": [float(r[2]) for r in rows],
            "x": [r[3] for r in rows],
            "y": 0.0,
            "rx": 10.0,
            "ry": 5.0,
            "phi": 0.0,
        }
    )
    try:
        rep = geofeas.read_reports(frame)
    except GeofeasError as exc:
        assert exc.argument == "reports" or "track" in str(exc) or "column" in str(exc)
        return
    assert len(rep) == len(rows)
    assert set(rep.track_ids) == {r[0] for r in rows}  # as given: "007" stays "007"
