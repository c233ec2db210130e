"""geofeas measures inside Stone Soup's own associators, and the track <-> report converters.

The pictures are simulated with seeded noise drawn from the covariance each sensor reports, so
the measures see honest Gaussian tracks; the expected associations are the ground truth of the
simulation, never an output of the code under test. Values are checked against formulas written
here from seed 000's equations (eq. 71 by a linear solve on the Stone Soup covariances, the
overlap of eqs. 49-50 by the independent reference in ``reference.py``).
"""

from __future__ import annotations

import importlib
import math
import sys
from datetime import datetime, timedelta

import numpy as np
import pytest

pytest.importorskip("stonesoup")
pd = pytest.importorskip("pandas")

from stonesoup.dataassociator.tracktotrack import (  # noqa: E402
    OneToOneTrackAssociator,
    TrackToTrackCounting,
)
from stonesoup.measures import Euclidean, SquaredMahalanobis  # noqa: E402
from stonesoup.measures.multi import MeanMeasure, StateSequenceMeasure  # noqa: E402
from stonesoup.types.association import TimeRangeAssociation  # noqa: E402
from stonesoup.types.state import GaussianState, State  # noqa: E402
from stonesoup.types.track import Track  # noqa: E402

import geofeas  # noqa: E402
from geofeas.integrations.stonesoup import (  # noqa: E402
    GLRMeasure,
    OverlapMeasure,
    PosteriorTrackAssociator,
    ProbabilisticTimeRangeAssociation,
    ThresholdedGLRMeasure,
    associate,
    reports_to_tracks,
    tracks_to_reports,
)

import reference  # noqa: E402

T0 = datetime(2024, 5, 1, 12, 0, 0)
POS = (0, 2)  # [x, vx, y, vy]: Stone Soup's constant-velocity state


def cov_from_axes(sx: float, sy: float, bearing: float) -> np.ndarray:
    """Position covariance with 1-sigma ``sx`` along ``bearing`` (radians clockwise from north)."""
    u = np.array([np.sin(bearing), np.cos(bearing)])  # (east, north)
    n = np.array([-u[1], u[0]])
    return sx**2 * np.outer(u, u) + sy**2 * np.outer(n, n)


def cv_state(pos: np.ndarray, vel: np.ndarray, pcov: np.ndarray, t: datetime) -> GaussianState:
    vec = np.array([[pos[0]], [vel[0]], [pos[1]], [vel[1]]])
    cov = np.diag([0.0, 1.0, 0.0, 1.0])
    cov[np.ix_(POS, POS)] = pcov
    return GaussianState(vec, cov, timestamp=t)


def sensor_tracks(
    truth: np.ndarray,
    velocity: np.ndarray,
    covs: list[np.ndarray],
    rng: np.random.Generator,
    prefix: str,
    source: str,
    times: list[datetime],
) -> list[Track]:
    """One track per ship: truth + noise drawn from the covariance the sensor reports."""
    tracks = []
    for i, (path, pcov) in enumerate(zip(truth, covs, strict=True)):
        noise = rng.multivariate_normal(np.zeros(2), pcov, size=len(times))
        states = [cv_state(path[k] + noise[k], velocity[i], pcov, t) for k, t in enumerate(times)]
        tracks.append(Track(states, id=f"{prefix}{i}", init_metadata={"source": source}))
    return tracks


def picture(seed: int = 7, ships: int = 4, steps: int = 20):
    """Ships 1.5 km apart seen by AIS (10 m circles) and by a radar (elongated, any bearing)."""
    rng = np.random.default_rng(seed)
    times = [T0 + timedelta(seconds=10 * k) for k in range(steps)]
    start = np.array([[1500.0 * (i % 2), 1500.0 * (i // 2)] for i in range(ships)])
    velocity = rng.uniform(-6, 6, (ships, 2))
    t = 10.0 * np.arange(steps)
    truth = start[:, None, :] + velocity[:, None, :] * t[None, :, None]
    ais = sensor_tracks(
        truth, velocity, [cov_from_axes(10, 10, 0)] * ships, rng, "ais", "ais", times
    )
    radar_cov = [cov_from_axes(75, 30, b) for b in rng.uniform(0, np.pi, ships)]
    radar = sensor_tracks(truth, velocity, radar_cov, rng, "radar", "radar", times)
    return ais, radar


def pairs_of(associations) -> set[frozenset[str]]:
    return {frozenset(t.id for t in a.objects) for a in associations.associations}


def glr_formula(s1: GaussianState, s2: GaussianState, m1=POS, m2=POS) -> float:
    d = (
        np.asarray(s1.state_vector, float)[list(m1), 0]
        - np.asarray(s2.state_vector, float)[list(m2), 0]
    )
    s = np.asarray(s1.covar)[np.ix_(m1, m1)] + np.asarray(s2.covar)[np.ix_(m2, m2)]
    return float(np.exp(-0.5 * d @ np.linalg.solve(s, d)))


def ellipse_from_cov(mean: np.ndarray, cov: np.ndarray) -> np.ndarray:
    """2-sigma ellipse by NumPy's eigh (independent of geofeas.from_gaussian)."""
    w, v = np.linalg.eigh(cov)
    major = v[:, 1]
    phi = np.arctan2(major[0], major[1])  # bearing of the major axis, clockwise from north
    return np.array([mean[0], mean[1], 2 * np.sqrt(w[1]), 2 * np.sqrt(w[0]), phi])


TRUE_PAIRS = {frozenset({f"ais{i}", f"radar{i}"}) for i in range(4)}


# --------------------------------------------------------------------------- values


def test_glr_measure_is_eq71_with_both_covariances(rng):
    for _ in range(50):
        a = cv_state(
            rng.normal(0, 100, 2),
            [1, 1],
            cov_from_axes(*rng.uniform(5, 80, 2), rng.uniform(0, 6.3)),
            T0,
        )
        b = cv_state(
            rng.normal(0, 100, 2),
            [1, 1],
            cov_from_axes(*rng.uniform(5, 80, 2), rng.uniform(0, 6.3)),
            T0,
        )
        g = glr_formula(a, b)
        assert GLRMeasure(mapping=POS)(a, b) == pytest.approx(1 - g, abs=1e-12)
        assert GLRMeasure(mapping=POS, distance="neglog")(a, b) == pytest.approx(
            -np.log(g), rel=1e-9, abs=1e-12
        )
        # symmetric, unlike Stone Soup's Mahalanobis (covariance of the first state only)
        assert GLRMeasure(mapping=POS)(b, a) == pytest.approx(1 - g, abs=1e-12)


def test_mapping2_compares_different_state_spaces():
    a = cv_state(np.array([10.0, -20.0]), [3, 4], cov_from_axes(40, 10, 0.3), T0)
    b = GaussianState([[50.0], [5.0]], cov_from_axes(20, 20, 0), timestamp=T0)  # [x, y]
    m = GLRMeasure(mapping=POS, mapping2=(0, 1))
    assert m(a, b) == pytest.approx(1 - glr_formula(a, b, POS, (0, 1)), abs=1e-12)


def test_overlap_measure_matches_reference_overlap(rng):
    for _ in range(20):
        ca = cov_from_axes(*rng.uniform(20, 60, 2), rng.uniform(0, 3.1))
        cb = cov_from_axes(*rng.uniform(20, 60, 2), rng.uniform(0, 3.1))
        pa, pb = rng.normal(0, 40, 2), rng.normal(0, 40, 2)
        a, b = cv_state(pa, [0, 0], ca, T0), cv_state(pb, [0, 0], cb, T0)
        want = reference.overlap(ellipse_from_cov(pa, ca), ellipse_from_cov(pb, cb))[0]
        assert OverlapMeasure(mapping=POS)(a, b) == pytest.approx(1 - want, abs=1e-4)


def test_overlap_measure_is_exact_by_default(rng):
    # against the 60-digit reference on the ellipses the measure sees: the polygon path (error
    # about 1e-5 at 256 vertices) cannot pass this
    exact_reference = pytest.importorskip("exact_reference")
    for _ in range(10):
        ca = cov_from_axes(*rng.uniform(20, 60, 2), rng.uniform(0, 3.1))
        cb = cov_from_axes(*rng.uniform(20, 60, 2), rng.uniform(0, 3.1))
        pa, pb = rng.normal(0, 40, 2), rng.normal(0, 40, 2)
        a, b = cv_state(pa, [0, 0], ca, T0), cv_state(pb, [0, 0], cb, T0)
        ea, eb = geofeas.from_gaussian(np.array([pa, pb]), np.array([ca, cb]))
        want = float(exact_reference.overlap(ea, eb))
        assert OverlapMeasure(mapping=POS)(a, b) == pytest.approx(1 - want, abs=1e-11)
        assert OverlapMeasure(mapping=POS, method="exact")(a, b) == pytest.approx(
            1 - want, abs=1e-11
        )
        # polygons only when asked, within their documented error
        for m in (
            OverlapMeasure(mapping=POS, vertices=64),
            OverlapMeasure(mapping=POS, method="polygon"),
        ):
            assert m(a, b) == pytest.approx(1 - want, abs=1e-3)
    with pytest.raises(geofeas.GeofeasError, match="vertices"):
        OverlapMeasure(mapping=POS, method="exact", vertices=64)
    with pytest.raises(geofeas.GeofeasError, match="method"):
        OverlapMeasure(mapping=POS, method="quadrature")


def test_thresholded_glr_is_exact_at_the_constraints():
    small = cv_state(np.array([0.0, 0.0]), [0, 0], cov_from_axes(10, 10, 0), T0)
    big = cv_state(np.array([5.0, 5.0]), [0, 0], cov_from_axes(100, 60, 0.4), T0)
    far = cv_state(np.array([5000.0, 0.0]), [0, 0], cov_from_axes(100, 60, 0.4), T0)
    m = ThresholdedGLRMeasure(mapping=POS)
    assert m(small, big) == 0.0  # nested: g = 1 exactly (eq. 48)
    assert m(small, far) == 1.0  # disjoint: g = 0 exactly (eq. 47)
    assert ThresholdedGLRMeasure(mapping=POS, distance="neglog")(small, far) == np.inf


@pytest.mark.parametrize("combine", ["geometric", "arithmetic", "harmonic", "min"])
def test_track_mode_combines_the_common_instants(combine):
    ais, radar = picture(steps=8)
    a, b = ais[0], radar[0]
    del b.states[2]  # instants only one track has are not scored
    common = {s.timestamp for s in b.states}
    g = np.array([glr_formula(s, b[s.timestamp]) for s in a.states if s.timestamp in common])
    want = {
        "geometric": np.exp(np.mean(np.log(g))),
        "arithmetic": np.mean(g),
        "harmonic": len(g) / np.sum(1 / g),
        "min": np.min(g),
    }[combine]
    assert GLRMeasure(mapping=POS, combine=combine)(a, b) == pytest.approx(1 - want, abs=1e-12)


def test_tracks_without_a_common_time_cannot_associate():
    ais, radar = picture(steps=4)
    late = Track([cv_state(np.zeros(2), [0, 0], np.eye(2), T0 + timedelta(hours=1))], id="late")
    assert GLRMeasure(mapping=POS)(ais[0], late) is None
    assoc = OneToOneTrackAssociator(measure=GLRMeasure(mapping=POS), association_threshold=0.99)
    assert pairs_of(assoc.associate_tracks({ais[0]}, {late})) == set()


def test_bad_input_raises_geofeas_error():
    good = cv_state(np.zeros(2), [0, 0], np.eye(2), T0)
    with pytest.raises(geofeas.GeofeasError, match="covariance"):
        GLRMeasure(mapping=POS)(good, State([[0], [0], [0], [0]], timestamp=T0))
    with pytest.raises(geofeas.GeofeasError, match="exactly 2"):
        GLRMeasure(mapping=(0, 1, 2))(good, good)
    with pytest.raises(geofeas.GeofeasError, match="out of range"):
        GLRMeasure(mapping=(0, 7))(good, good)
    with pytest.raises(geofeas.GeofeasError, match="distance"):
        GLRMeasure(mapping=POS, distance="euclid")
    with pytest.raises(geofeas.GeofeasError, match="combine"):
        GLRMeasure(mapping=POS, combine="median")
    nan = cv_state(np.array([np.nan, 0.0]), [0, 0], np.eye(2), T0)
    with pytest.raises(geofeas.GeofeasError):
        GLRMeasure(mapping=POS)(good, nan)
    singular = cv_state(np.zeros(2), [0, 0], np.zeros((2, 2)), T0)
    with pytest.raises(geofeas.GeofeasError):
        GLRMeasure(mapping=POS)(good, singular)
    with pytest.raises(geofeas.GeofeasError, match="not a mix"):
        GLRMeasure(mapping=POS)(Track([good]), good)


# --------------------------------------------------------------------------- associators


@pytest.mark.parametrize("measure_cls", [GLRMeasure, ThresholdedGLRMeasure, OverlapMeasure])
def test_track_to_track_counting_recovers_the_true_pairs(measure_cls):
    ais, radar = picture()
    # g >= 0.01 at an instant counts as close; three in a row confirm, two misses end
    counting = TrackToTrackCounting(
        association_threshold=0.99,
        consec_pairs_confirm=3,
        consec_misses_end=2,
        measure=measure_cls(mapping=POS),
        pos_map=list(POS),
    )
    associations = counting.associate_tracks(set(ais), set(radar))
    assert pairs_of(associations) == TRUE_PAIRS
    for a in associations.associations:
        assert T0 <= a.time_range.start_timestamp <= a.time_range.end_timestamp


@pytest.mark.parametrize("distance,threshold", [("complement", 0.99), ("neglog", np.log(100))])
def test_one_to_one_track_associator_recovers_the_true_pairs(distance, threshold):
    ais, radar = picture()
    extra = picture(seed=99, ships=1)[1][0]  # a radar track of a ship nobody else sees
    extra.states[:] = [
        cv_state(
            np.asarray(s.state_vector)[[0, 2], 0] + [0.0, 7000.0],
            [0, 0],
            np.asarray(s.covar)[np.ix_(POS, POS)],
            s.timestamp,
        )
        for s in extra.states
    ]
    extra.id = "radar-lonely"
    associator = OneToOneTrackAssociator(
        measure=GLRMeasure(mapping=POS, distance=distance), association_threshold=threshold
    )
    associations = associator.associate_tracks(set(ais), set(radar) | {extra})
    assert pairs_of(associations) == TRUE_PAIRS


def df_picture(seed: int = 3, steps: int = 10):
    """Two ships 1 km apart seen by AIS and by HF direction finding.

    The DF position comes from a bearing line: 30 m across it, 1 km (1 sigma) along it, the line
    at 60 degrees from north. Each DF track carries a persistent range error of 0.8 sigma along
    its line (a DF fix error is correlated over a track): +0.8 sigma for ship 0, -0.8 sigma for
    ship 1, each pulling the report towards the other ship. The reported covariances are honest:
    the true positions lie well inside the 2-sigma ellipses. Euclidean distance sees each DF
    report about 504 m from the wrong ship and 800 m from the right one; the GLR with R1 + R2
    sees the wrong ship 16 sigma across the line and the right one 0.8 sigma along it.
    """
    rng = np.random.default_rng(seed)
    times = [T0 + timedelta(seconds=30 * k) for k in range(steps)]
    bearing = np.radians(60.0)
    u = np.array([np.sin(bearing), np.cos(bearing)])
    n = np.array([-u[1], u[0]])
    velocity = np.array([[0.0, 5.0], [0.0, 5.0]])
    t = 30.0 * np.arange(steps)
    start = np.array([[0.0, 0.0], [1000.0, 0.0]])
    truth = start[:, None, :] + velocity[:, None, :] * t[None, :, None]
    ais = sensor_tracks(truth, velocity, [cov_from_axes(10, 10, 0)] * 2, rng, "ais", "ais", times)
    df_cov = cov_from_axes(1000.0, 30.0, bearing)
    df = []
    for i, bias in enumerate([800.0, -800.0]):
        along = bias + rng.normal(0, 50, steps)
        across = rng.normal(0, 10, steps)
        states = [
            cv_state(truth[i, k] + along[k] * u + across[k] * n, velocity[i], df_cov, times[k])
            for k in range(steps)
        ]
        df.append(Track(states, id=f"df{i}", init_metadata={"source": "df"}))
    return ais, df


DF_TRUE = {frozenset({"ais0", "df0"}), frozenset({"ais1", "df1"})}
DF_SWAPPED = {frozenset({"ais0", "df1"}), frozenset({"ais1", "df0"})}


def test_glr_beats_euclidean_on_elongated_covariances():
    ais, df = df_picture()
    euclid = OneToOneTrackAssociator(
        measure=MeanMeasure(StateSequenceMeasure(Euclidean(mapping=POS)))
    )
    assert pairs_of(euclid.associate_tracks(set(ais), set(df))) == DF_SWAPPED
    # Stone Soup's Mahalanobis uses the covariance of the first state only: with the accurate
    # AIS tracks first it is a scaled Euclidean distance and swaps the pairs too
    mahal = OneToOneTrackAssociator(
        measure=MeanMeasure(StateSequenceMeasure(SquaredMahalanobis(mapping=POS)))
    )
    assert pairs_of(mahal.associate_tracks(set(ais), set(df))) == DF_SWAPPED
    for first, second in [(ais, df), (df, ais)]:
        glr = OneToOneTrackAssociator(measure=GLRMeasure(mapping=POS), association_threshold=0.99)
        assert pairs_of(glr.associate_tracks(set(first), set(second))) == DF_TRUE


def test_counting_with_glr_beats_counting_with_euclidean():
    ais, df = df_picture()
    euclid = TrackToTrackCounting(
        association_threshold=600.0, measure=Euclidean(mapping=POS), pos_map=list(POS)
    )
    assert pairs_of(euclid.associate_tracks(set(ais), set(df))) == DF_SWAPPED
    glr = TrackToTrackCounting(
        association_threshold=0.99, measure=GLRMeasure(mapping=POS), pos_map=list(POS)
    )
    assert pairs_of(glr.associate_tracks(set(ais), set(df))) == DF_TRUE


# --------------------------------------------------------------------------- the posterior


def lonely_radar_track() -> Track:
    """A radar track of a ship nobody else sees, 7 km north of the picture."""
    extra = picture(seed=99, ships=1)[1][0]
    extra.states[:] = [
        cv_state(
            np.asarray(s.state_vector)[[0, 2], 0] + [0.0, 7000.0],
            [0, 0],
            np.asarray(s.covar)[np.ix_(POS, POS)],
            s.timestamp,
        )
        for s in extra.states
    ]
    extra.id = "radar-lonely"
    return extra


def test_posterior_of_stone_soup_tracks_recovers_the_true_pairs():
    ais, radar = picture()
    # the radar reports every 10 s but 4 s later than the AIS: no timestamp in common
    radar = [
        Track(
            [
                GaussianState(s.state_vector, s.covar, timestamp=s.timestamp + timedelta(seconds=4))
                for s in t.states
            ],
            id=t.id,
            init_metadata=dict(t.metadata),
        )
        for t in radar
    ]
    result = associate(ais + radar + [lonely_radar_track()], mapping=POS)
    assert isinstance(result, geofeas.Association)
    pairs = result.pairs.set_index(["track_a", "track_b"])
    truth = {tuple(sorted(p)) for p in TRUE_PAIRS}
    assert truth <= set(pairs.index)
    for pair in pairs.index:
        p = pairs.loc[pair, "p_same"]
        if pair in truth:
            assert p >= 0.99 and pairs.loc[pair, "class"] == "match"
        else:
            assert p <= 0.01 and pairs.loc[pair, "class"] == "non-match"
    alone = result.objects.set_index("track_id")["p_alone"]
    assert alone["radar-lonely"] == 1.0  # no candidate at all
    assert (alone[[f"ais{i}" for i in range(4)]] < 0.01).all()


def test_ships_closer_than_the_radar_can_tell_are_borderline():
    """Two ships 50 m apart under a 300 m (1-sigma) radar AOU: the radar track is one of them,
    and the geometry cannot say which."""
    rng = np.random.default_rng(5)
    times = [T0 + timedelta(seconds=10 * k) for k in range(30)]
    t = 10.0 * np.arange(30)
    velocity = np.array([[4.0, 1.0], [4.0, 1.0]])
    truth = (
        np.array([[0.0, 0.0], [50.0, 0.0]])[:, None, :] + velocity[:, None, :] * t[None, :, None]
    )
    ais = sensor_tracks(truth, velocity, [cov_from_axes(10, 10, 0)] * 2, rng, "ais", "ais", times)
    radar = sensor_tracks(
        truth[:1], velocity[:1], [cov_from_axes(300, 300, 0)], rng, "radar", "radar", times
    )
    result = associate(ais + radar, mapping=POS)
    pairs = result.pairs.set_index(["track_a", "track_b"])
    both = pairs.loc[[("ais0", "radar0"), ("ais1", "radar0")]]
    assert (both["class"] == "borderline").all()
    assert both["review_rank"].notna().all()
    # one radar track is at most one ship: the two events exclude each other
    assert both["p_same"].sum() <= 1.0 + 1e-12
    assert set(result.review_queue["track_b"]) == {"radar0"}


def test_posterior_track_associator_in_stone_soup_terms():
    ais, radar = picture()
    extra = lonely_radar_track()
    associator = PosteriorTrackAssociator(mapping=POS, sources=["ais", "radar"])
    associations = associator.associate_tracks(set(ais), set(radar) | {extra})
    assert pairs_of(associations) == TRUE_PAIRS
    tracks = {t.id: t for t in ais + radar}
    p = associator.association.pairs.set_index(["track_a", "track_b"])["p_same"]
    for a in associations.associations:
        assert isinstance(a, ProbabilisticTimeRangeAssociation)
        assert isinstance(a, TimeRangeAssociation)
        one, two = sorted(a.objects, key=lambda t: t.id)
        assert tracks[one.id] is one and tracks[two.id] is two  # Stone Soup's own objects
        assert a.probability == p[(one.id, two.id)] >= 0.99
        assert a.time_range.start_timestamp == T0
        assert a.time_range.end_timestamp == one.states[-1].timestamp
    # the same engine as a report table of the same tracks
    want = geofeas.associate(
        tracks_to_reports(
            ais + radar + [extra],
            source={
                **{t.id: "ais" for t in ais},
                **{t.id: "radar" for t in radar},
                extra.id: "radar",
            },
        )
    )
    pd.testing.assert_frame_equal(associator.association.pairs, want.pairs, check_exact=True)


def test_posterior_track_associator_takes_operator_decisions_and_options():
    ais, radar = picture()
    decided = pd.DataFrame({"track_a": ["ais0"], "track_b": ["radar0"], "decision": ["different"]})
    associator = PosteriorTrackAssociator(
        mapping=POS, decisions=decided, options=dict(p_match=0.999)
    )
    associations = associator.associate_tracks(set(ais), set(radar))
    assert pairs_of(associations) == TRUE_PAIRS - {frozenset({"ais0", "radar0"})}
    p = associator.association.pairs.set_index(["track_a", "track_b"])["p_same"]
    assert p[("ais0", "radar0")] == 0.0
    assert associator.association.options["p_match"] == 0.999


def test_posterior_track_associator_errors_name_the_problem():
    ais, radar = picture(steps=5)
    with pytest.raises(geofeas.GeofeasError, match="2 names for 1 tracks sets"):
        PosteriorTrackAssociator(mapping=POS, sources=["a", "b"]).associate_tracks(set(ais))
    with pytest.raises(geofeas.GeofeasError, match="used twice"):
        PosteriorTrackAssociator(mapping=POS).associate_tracks(set(ais), set(ais))
    with pytest.raises(geofeas.GeofeasError, match="expected a Stone Soup track"):
        PosteriorTrackAssociator(mapping=POS).associate_tracks({1, 2})
    with pytest.raises(TypeError, match="lower"):
        PosteriorTrackAssociator(mapping=POS, options=dict(lower=0.5)).associate_tracks(
            set(ais), set(radar)
        )


# --------------------------------------------------------------------------- converters


def test_tracks_to_reports_and_back_round_trip():
    ais, radar = picture(steps=5)
    df = tracks_to_reports(ais + radar)
    assert list(df.columns) == ["track_id", "source", "time", "x", "y", "rx", "ry", "phi"]
    assert len(df) == 8 * 5
    assert set(df["source"]) == {"ais", "radar"}
    # the ellipses are the 2-sigma AOU of the position covariance
    s = radar[1].states[3]
    row = df[(df.track_id == "radar1")].iloc[3]
    want = ellipse_from_cov(
        np.asarray(s.state_vector)[list(POS), 0], np.asarray(s.covar)[np.ix_(POS, POS)]
    )
    got = row[["x", "y", "rx", "ry"]].to_numpy(float)
    np.testing.assert_allclose(got, want[:4], rtol=1e-12)
    assert np.isclose(np.cos(2 * (row["phi"] - want[4])), 1.0)  # axis direction mod pi
    assert row["time"] == (s.timestamp - datetime(1970, 1, 1)).total_seconds()

    back = {t.id: t for t in reports_to_tracks(df)}
    assert set(back) == {t.id for t in ais + radar}
    for original in ais + radar:
        copy = back[original.id]
        assert copy.metadata["source"] == original.metadata["source"]
        assert [s.timestamp for s in copy.states] == [s.timestamp for s in original.states]
        for s0, s1 in zip(original.states, copy.states, strict=True):
            np.testing.assert_allclose(
                np.asarray(s1.state_vector)[:, 0], np.asarray(s0.state_vector)[list(POS), 0]
            )
            np.testing.assert_allclose(
                np.asarray(s1.covar),
                np.asarray(s0.covar)[np.ix_(POS, POS)],
                rtol=1e-9,
                atol=1e-9,
            )
    # the measure gives the same distance on the converted 2-D tracks
    m4, m2 = GLRMeasure(mapping=POS), GLRMeasure(mapping=(0, 1))
    assert m2(back["ais2"], back["radar2"]) == pytest.approx(m4(ais[2], radar[2]), abs=1e-9)


def test_reports_scored_by_geofeas_match_the_measure():
    ais, radar = picture(steps=3)
    df = tracks_to_reports([ais[0], radar[0]])
    a = df[df.track_id == "ais0"][["x", "y", "rx", "ry", "phi"]].to_numpy()
    b = df[df.track_id == "radar0"][["x", "y", "rx", "ry", "phi"]].to_numpy()
    g = geofeas.glr(a, b)
    want = [glr_formula(s, r) for s, r in zip(ais[0].states, radar[0].states, strict=True)]
    np.testing.assert_allclose(g, want, rtol=1e-10)


def test_converters_accept_iso_times_and_source_overrides():
    ais, _ = picture(ships=1, steps=3)
    df = tracks_to_reports(ais, source={"ais0": "shore-ais"})
    assert set(df["source"]) == {"shore-ais"}
    iso = df.assign(time=pd.to_datetime(df["time"], unit="s").dt.strftime("%Y-%m-%dT%H:%M:%S"))
    (track,) = reports_to_tracks(iso)
    assert [s.timestamp for s in track.states] == [s.timestamp for s in ais[0].states]


def test_converter_errors_name_the_problem():
    ais, _ = picture(ships=1, steps=3)
    with pytest.raises(geofeas.GeofeasError, match="no source"):
        tracks_to_reports([Track(ais[0].states, id="x")])
    with pytest.raises(geofeas.GeofeasError, match="no source given"):
        tracks_to_reports(ais, source={"other": "s"})
    with pytest.raises(geofeas.GeofeasError, match="Stone Soup track"):
        tracks_to_reports([object()], source="s")
    df = tracks_to_reports(ais)
    with pytest.raises(geofeas.GeofeasError, match=r"missing column\(s\) \['phi'\]"):
        reports_to_tracks(df.drop(columns="phi"))
    with pytest.raises(geofeas.GeofeasError, match="lat/lon"):
        reports_to_tracks(df.drop(columns=["x", "y"]).assign(lat=0.0, lon=0.0))
    bad = df.copy()
    bad.loc[1, "ry"] = -1.0
    with pytest.raises(geofeas.GeofeasError, match="row 1"):
        reports_to_tracks(bad)
    mixed = df.copy()
    mixed.loc[2, "source"] = "radar"
    with pytest.raises(geofeas.GeofeasError, match="several sources"):
        reports_to_tracks(mixed)
    with pytest.raises(geofeas.GeofeasError, match="time"):
        reports_to_tracks(df.assign(time=["noon", "later", "never"]))


def test_missing_stonesoup_gives_an_install_hint(monkeypatch):
    for name in [m for m in sys.modules if m == "stonesoup" or m.startswith("stonesoup.")]:
        monkeypatch.setitem(sys.modules, name, None)
    monkeypatch.delitem(sys.modules, "geofeas.integrations.stonesoup")
    with pytest.raises(ImportError, match=r"geofeas\[stonesoup\]"):
        importlib.import_module("geofeas.integrations.stonesoup")
    monkeypatch.undo()
    importlib.import_module("geofeas.integrations.stonesoup")


def test_neglog_stays_in_the_log_domain():
    # 100 sigma apart (S = R1 + R2 = 2 I): g underflows to 0, -ln g = 0.5 d^T S^-1 d = 5000
    a = GaussianState([[0.0], [0.0]], np.eye(2), timestamp=T0)
    b = GaussianState([[0.0], [100.0 * math.sqrt(2.0)]], np.eye(2), timestamp=T0)
    measure = GLRMeasure(distance="neglog", mapping=(0, 1))
    assert measure(a, b) == pytest.approx(5000.0, rel=1e-12)
    # a true pair with 100 good instants and one wild one stays associable (finite)
    times = [T0 + timedelta(seconds=k) for k in range(101)]
    good = [GaussianState([[0.0], [0.0]], np.eye(2), timestamp=t) for t in times]
    other = [GaussianState([[0.0], [0.1]], np.eye(2), timestamp=t) for t in times[:100]]
    other.append(GaussianState([[0.0], [200.0]], np.eye(2), timestamp=times[100]))
    d = measure(Track(good), Track(other))
    expected = (100 * 0.25 * 0.1**2 + 0.25 * 200.0**2) / 101  # geometric: mean of -ln g
    assert math.isfinite(d) and d == pytest.approx(expected, rel=1e-12)
