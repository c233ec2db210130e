"""Stone Soup tracks of different sensors brought to common instants (``align_tracks``), and
geographic reports read by ``reports_to_tracks``.

The expected pairs are the simulation's ground truth (the ``mmsi`` column of the demo's sensor
simulation over the bundled Solent AIS recording); the interpolation and the projection are
checked against formulas written here (linear interpolation, Karney's geodesics from the
``geographiclib`` package, which the core does not use).
"""

from __future__ import annotations

import math
from datetime import datetime, timedelta

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("stonesoup")
pd = pytest.importorskip("pandas")

from stonesoup.dataassociator.tracktotrack import TrackToTrackCounting  # noqa: E402
from stonesoup.types.state import GaussianState  # noqa: E402
from stonesoup.types.track import Track  # noqa: E402

import geofeas  # noqa: E402
from geofeas.demo import bundled  # noqa: E402
from geofeas.demo.scenario import simulate  # noqa: E402
from geofeas.integrations.stonesoup import GLRMeasure, align_tracks, reports_to_tracks  # noqa: E402
from geofeas.io.ais import read_ais  # noqa: E402

T0 = datetime(2024, 5, 1, 12, 0, 0)


def track(times_s, xy, cov, tid="t"):
    states = [
        GaussianState(
            np.reshape(p, (2, 1)), np.asarray(c, float), timestamp=T0 + timedelta(seconds=t)
        )
        for t, p, c in zip(times_s, xy, cov, strict=True)
    ]
    return Track(states, id=tid, init_metadata={"source": "s"})


# ----------------------------------------------------------------------- alignment rules


def test_alignment_interpolates_and_adds_the_bridge_term():
    c0 = np.array([[100.0, 20.0], [20.0, 50.0]])
    c1 = np.array([[300.0, -10.0], [-10.0, 80.0]])
    t = track([0.0, 40.0], [[0.0, 0.0], [400.0, -200.0]], [c0, c1])
    grid = [T0 + timedelta(seconds=s) for s in (-10.0, 10.0, 40.0)]
    (a,) = align_tracks([t], times=grid, mapping=(0, 1), process_noise=3.0)
    assert [s.timestamp for s in a.states] == grid[1:]  # -10 s is before the span
    s = a.states[0]
    w = 10.0 / 40.0
    np.testing.assert_allclose(s.state_vector[:, 0], [100.0, -50.0], rtol=1e-12)
    want = (1 - w) * c0 + w * c1 + 3.0 * 10.0 * 30.0 / 40.0 * np.eye(2)
    np.testing.assert_allclose(s.covar, want, rtol=1e-9)
    np.testing.assert_allclose(a.states[1].covar, c1, rtol=1e-9)  # a state of the track itself
    assert a.id == "t" and a.metadata == {"source": "s"}


def test_gaps_longer_than_max_gap_are_not_bridged():
    cov = [np.eye(2) * 25.0] * 4
    t = track([0.0, 30.0, 400.0, 430.0], [[0, 0], [30, 0], [400, 0], [430, 0]], cov)
    (a,) = align_tracks([t], step=10.0, mapping=(0, 1), max_gap=300.0)
    got = [(s.timestamp - T0).total_seconds() for s in a.states]
    assert got == [0.0, 10.0, 20.0, 30.0, 400.0, 410.0, 420.0, 430.0]
    (b,) = align_tracks([t], step=10.0, mapping=(0, 1), max_gap=400.0)
    assert len(b.states) == 44  # the 370 s gap is now bridged
    mid = next(s for s in b.states if s.timestamp == T0 + timedelta(seconds=200))
    assert mid.state_vector[0, 0] == pytest.approx(200.0)


def test_step_grid_is_shared_across_calls_and_takes_4d_states():
    cv = GaussianState(
        [[5.0], [1.0], [7.0], [0.0]],
        np.diag([4.0, 1.0, 9.0, 1.0]),
        timestamp=T0 + timedelta(seconds=3),
    )
    cv2 = GaussianState(
        [[25.0], [1.0], [7.0], [0.0]],
        np.diag([4.0, 1.0, 9.0, 1.0]),
        timestamp=T0 + timedelta(seconds=23),
    )
    (a,) = align_tracks([Track([cv, cv2], id="cv")], step=5.0, mapping=(0, 2))
    assert [(s.timestamp - T0).total_seconds() % 5.0 for s in a.states] == [0.0] * 4
    np.testing.assert_allclose(a.states[0].state_vector[:, 0], [5.0 + 2.0, 7.0])


def test_align_errors_name_the_problem():
    t = track([0.0, 10.0], [[0, 0], [1, 1]], [np.eye(2)] * 2)
    with pytest.raises(geofeas.GeofeasError, match="exactly one of"):
        align_tracks([t])
    with pytest.raises(geofeas.GeofeasError, match="step"):
        align_tracks([t], step=0.0)
    with pytest.raises(geofeas.GeofeasError, match="max_gap"):
        align_tracks([t], step=1.0, max_gap=-1.0)
    with pytest.raises(geofeas.GeofeasError, match="used twice"):
        align_tracks([t, t], step=1.0)
    twice = track([0.0, 10.0, 0.0], [[0, 0], [1, 1], [2, 2]], [np.eye(2)] * 3, tid="twice")
    with pytest.raises(geofeas.GeofeasError, match="'twice' has states 0 and 2 at the same"):
        align_tracks([t, twice], step=1.0)
    with pytest.raises(geofeas.GeofeasError, match="not finite"):
        align_tracks([t], times=[0.0, math.nan])


# ----------------------------------------------- Stone Soup's associator on the demo's reports


@pytest.fixture(scope="module")
def solent_tracks():
    """AIS and coastal-radar tracks of the first 6 minutes of the Solent demo, as Stone Soup
    tracks in one AEQD frame, restricted to the tracks within 2 km of the median AIS position
    (so Stone Soup's pure-Python associator stays quick)."""
    sc = simulate(read_ais(bundled("solent")), seed=2, minutes=6, sensors=["ais", "radar"])
    r = sc.reports
    centre = r[r.source == "ais"].groupby("mmsi")[["lat", "lon"]].mean().median()
    origin = (float(centre["lat"]), float(centre["lon"]))
    tracks = {t.id: t for t in reports_to_tracks(r, origin=origin)}
    mmsi = r.groupby("track_id")["mmsi"].first()
    near = {
        t.id
        for t in tracks.values()
        if np.hypot(*np.mean([s.state_vector[:, 0] for s in t.states], axis=0)) < 2000.0
    }
    ais = [tracks[i] for i in sorted(near) if tracks[i].metadata["source"] == "ais"]
    radar = [tracks[i] for i in sorted(near) if tracks[i].metadata["source"] == "radar"]
    truth = {
        frozenset({a.id, b.id})
        for a in ais
        for b in radar
        if mmsi[a.id] >= 0 and mmsi[a.id] == mmsi[b.id]
    }
    return ais, radar, truth


def _found(ais, radar):
    counting = TrackToTrackCounting(
        association_threshold=1.0 - 0.01,  # g >= 0.01 at an instant
        measure=GLRMeasure(mapping=(0, 1)),
        pos_map=[0, 1],
        consec_pairs_confirm=3,
    )
    return {
        frozenset(t.id for t in a.objects)
        for a in counting.associate_tracks(ais, radar).associations
    }


def test_alignment_lets_stone_soups_counting_find_the_true_pairs(solent_tracks):
    ais, radar, truth = solent_tracks
    assert len(truth) >= 30
    by = {t.id: t for t in ais + radar}
    shared = [
        p for p in truth if set.intersection(*({s.timestamp for s in by[i].states} for i in p))
    ]
    raw = _found(ais, radar)
    al_ais, al_radar = align_tracks(ais, step=30.0), align_tracks(radar, step=30.0)
    aligned = _found(al_ais, al_radar)
    true_raw, true_aligned = len(raw & truth), len(aligned & truth)
    # without alignment the AIS and radar reports (each at its own instants) do not coincide:
    # Stone Soup's counting finds only pairs that share timestamps
    assert true_raw <= len(shared) <= 0.1 * len(truth)
    assert true_aligned >= 0.9 * len(truth)
    # the aligned states of true pairs are honest: eq. 71's g is then uniform on [0, 1]
    # (d^T (R1 + R2)^-1 d is chi-square with 2 degrees of freedom)
    m = GLRMeasure(mapping=(0, 1))
    al = {t.id: {s.timestamp: s for s in t.states} for t in al_ais + al_radar}
    g = np.array(
        [
            m.similarity(al[a][k], al[b][k])
            for a, b in (sorted(p) for p in truth)
            for k in al[a].keys() & al[b].keys()
        ]
    )
    assert g.size >= 200
    assert np.mean(g >= 0.01) >= 0.97
    u = np.sort(g)
    ks = np.max(np.abs(np.arange(1, u.size + 1) / u.size - u))
    assert ks < 0.15, ks


# ------------------------------------------------------------------- geographic reports


def _planar_equivalent(lat0, lon0, lat, lon, bearing):
    """The planar report equivalent to a geographic one, from geographiclib (independent)."""
    from geographiclib.geodesic import Geodesic

    g = Geodesic.WGS84.Inverse(lat0, lon0, lat, lon)
    s, a1, a2 = g["s12"], math.radians(g["azi1"]), math.radians(g["azi2"])
    phi = math.radians(bearing) + a1 - a2
    return s * math.sin(a1), s * math.cos(a1), (phi + math.pi) % (2 * math.pi) - math.pi


@pytest.mark.parametrize(
    "lat0, lon0, lat, lon",
    [
        (50.8, -1.3, 50.8, -1.3),
        (50.8, -1.3, 50.85, -1.2),
        (-33.9, 151.2, -34.2, 151.9),
        (10.0, 179.9, 10.1, -179.8),
    ],
)
def test_geographic_report_gives_the_ellipse_of_its_planar_equivalent(lat0, lon0, lat, lon):
    rx, ry, bearing = 300.0, 40.0, 63.0
    geo = pd.DataFrame(
        {
            "track_id": ["a"],
            "source": ["s"],
            "time": [0.0],
            "lat": [lat],
            "lon": [lon],
            "rx": [rx],
            "ry": [ry],
            "bearing": [bearing],
        }
    )
    x, y, phi = _planar_equivalent(lat0, lon0, lat, lon, bearing)
    planar = pd.DataFrame(
        {
            "track_id": ["a"],
            "source": ["s"],
            "time": [0.0],
            "x": [x],
            "y": [y],
            "rx": [rx],
            "ry": [ry],
            "phi": [phi],
        }
    )
    (g,) = reports_to_tracks(geo, origin=(lat0, lon0))
    (p,) = reports_to_tracks(planar)
    assert g.metadata["origin"] == (lat0, lon0)
    np.testing.assert_allclose(
        g.states[0].state_vector, p.states[0].state_vector, rtol=0, atol=1e-6
    )
    np.testing.assert_allclose(g.states[0].covar, p.states[0].covar, rtol=1e-9, atol=1e-9)
    # a 2-sigma semi-axis of 300 m at 63 degrees from north: the covariance's major axis
    w, v = np.linalg.eigh(np.asarray(g.states[0].covar, float))
    assert w[1] == pytest.approx((rx / 2) ** 2, rel=1e-9)
    if (lat, lon) == (lat0, lon0):
        assert math.degrees(math.atan2(v[0, 1], v[1, 1])) % 180.0 == pytest.approx(63.0)


def _geo_frame(**over):
    df = pd.DataFrame(
        {
            "track_id": ["a", "a", "b"],
            "source": ["s", "s", "t"],
            "time": [0.0, 10.0, 0.0],
            "lat": [50.8, 50.81, 50.82],
            "lon": [-1.3, -1.3, -1.31],
            "rx": [300.0, 200.0, 50.0],
            "ry": [40.0, 40.0, 50.0],
            "bearing": [63.0, 120.0, 0.0],
        }
    )
    return df.assign(**over)


def test_ambiguous_angle_units_are_refused_with_row_and_field():
    with pytest.raises(geofeas.GeofeasError) as e:
        reports_to_tracks(_geo_frame().rename(columns={"bearing": "phi"}))
    assert (e.value.argument, e.value.row, e.value.field) == ("reports", 0, "phi")
    with pytest.raises(geofeas.GeofeasError) as e:
        reports_to_tracks(_geo_frame(phi=[1.1, 2.1, 0.0]))
    assert e.value.field == "phi"
    # radians where degrees are expected: every bearing within 2 pi
    with pytest.raises(geofeas.GeofeasError) as e:
        reports_to_tracks(_geo_frame(bearing=[1.1, 2.1, 0.3]))
    assert (e.value.argument, e.value.row, e.value.field) == ("reports", 1, "bearing")
    assert "radians or degrees" in str(e.value)
    # ... unless confirmed; a circle's bearing (row 2) does not matter
    tracks = reports_to_tracks(_geo_frame(bearing=[1.1, 2.1, 300.0]), bearing_unit="degrees")
    assert len(tracks) == 2
    reports_to_tracks(_geo_frame(bearing=[63.0, 120.0, 1.0]))
    # degrees where radians are expected (planar phi beyond 2 pi)
    planar = _geo_frame().rename(columns={"lat": "x", "lon": "y", "bearing": "phi"})
    with pytest.raises(geofeas.GeofeasError) as e:
        reports_to_tracks(planar)
    assert (e.value.argument, e.value.row, e.value.field) == ("reports", 0, "phi")
    # a mathematical angle column is never read as a bearing
    with pytest.raises(geofeas.GeofeasError, match="'theta' is not read"):
        reports_to_tracks(_geo_frame().drop(columns="bearing").assign(theta=0.5))
    with pytest.raises(geofeas.GeofeasError, match="both planar"):
        reports_to_tracks(_geo_frame(x=0.0, y=0.0, phi=0.0))
    with pytest.raises(geofeas.GeofeasError) as e:
        reports_to_tracks(_geo_frame(lat=[50.8, 95.0, 50.0]))
    assert (e.value.row, e.value.field) == (1, "lat")
    with pytest.raises(geofeas.GeofeasError) as e:
        reports_to_tracks(_geo_frame(rx=[300.0, 200.0, "wide"]))
    assert (e.value.row, e.value.field) == (2, "rx")
    planar = _geo_frame().rename(columns={"lat": "x", "lon": "y"})
    planar["phi"] = [0.1, 0.2, 0.3]
    planar = planar.drop(columns="bearing")
    for column, value in (("x", math.nan), ("ry", -1.0), ("rx", math.inf)):
        bad = planar.copy()
        bad.loc[1, column] = value
        with pytest.raises(geofeas.GeofeasError) as e:
            reports_to_tracks(bad)
        assert (e.value.argument, e.value.row, e.value.field) == ("reports", 1, column)


@settings(max_examples=60, deadline=None)
@given(
    lat0=st.floats(-75.0, 75.0),
    lon0=st.floats(-180.0, 180.0),
    azimuth=st.floats(-180.0, 180.0),
    distance=st.floats(0.0, 50_000.0),
    bearing=st.floats(0.0, 359.99),
    rx=st.floats(1.0, 5_000.0),
    ratio=st.floats(1e-3, 1.0),
)
def test_geographic_and_planar_reports_agree_anywhere(
    lat0, lon0, azimuth, distance, bearing, rx, ratio
):
    from geographiclib.geodesic import Geodesic

    p = Geodesic.WGS84.Direct(lat0, lon0, azimuth, distance)
    lat, lon = p["lat2"], (p["lon2"] + 180.0) % 360.0 - 180.0
    x, y, phi = _planar_equivalent(lat0, lon0, lat, lon, bearing)
    common = {"track_id": ["a"], "source": ["s"], "time": [0.0], "rx": [rx], "ry": [rx * ratio]}
    geo = pd.DataFrame({**common, "lat": [lat], "lon": [lon], "bearing": [bearing]})
    planar = pd.DataFrame({**common, "x": [x], "y": [y], "phi": [phi]})
    (g,) = reports_to_tracks(geo, origin=(lat0, lon0), bearing_unit="degrees")
    (q,) = reports_to_tracks(planar)
    np.testing.assert_allclose(g.states[0].state_vector, q.states[0].state_vector, atol=1e-6)
    scale = (rx / 2) ** 2
    np.testing.assert_allclose(g.states[0].covar, q.states[0].covar, atol=1e-9 * scale)
