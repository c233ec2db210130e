"""The review station's web application through Starlette's test client: pages, validation,
CSRF, conflicts, the files it touches; and the per-instant distances of the pair view against an
independent geodesic computation."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from review_picture import picture

import geofeas

pytest.importorskip("starlette")
pytest.importorskip("httpx")

from starlette.testclient import TestClient  # noqa: E402

from geofeas.review.app import create_app  # noqa: E402
from geofeas.review.coast import gshhg_file  # noqa: E402
from geofeas.review.station import Station  # noqa: E402


@pytest.fixture
def station(tmp_path):
    path = tmp_path / "picture.csv"
    picture().to_csv(path, index=False)
    s = Station(path, tmp_path / "d.sqlite", operator="ann", background=False)
    yield s
    s.close()


@pytest.fixture
def client(station):
    app = create_app(station, token="tok")
    with TestClient(app) as c:
        yield c


def _post(client, url, body, token="tok"):
    headers = {"X-CSRF-Token": token} if token else {}
    return client.post(url, json=body, headers=headers)


def test_the_picture_has_borderline_pairs(station):
    q = station.snapshot.queue
    assert len(q) >= 2
    assert list(q["review_rank"]) == sorted(q["review_rank"])
    assert ((q["p_same"] > 0.01) & (q["p_same"] < 0.99)).all()


def test_queue_page_lists_the_queue_in_review_order(client, station):
    r = client.get("/")
    assert r.status_code == 200
    q = station.snapshot.queue
    for row in q.itertuples():
        assert f'data-a="{row.track_a}" data-b="{row.track_b}"' in r.text
    positions = [
        r.text.index(f'data-a="{row.track_a}" data-b="{row.track_b}"') for row in q.itertuples()
    ]
    assert positions == sorted(positions)
    assert 'name="csrf-token" content="tok"' in r.text


def test_queue_filters(client, station):
    r = client.get("/", params={"sources": "ais/radar"})
    assert r.status_code == 200 and "filter-error" not in r.text
    r = client.get("/", params={"sources": "ais/sonar"})
    assert "sources: expected two source names" in r.text
    r = client.get("/", params={"area": "51,-1,50,0"})
    assert "area:" in r.text and "smaller" in r.text
    r = client.get("/", params={"area": "1,2,3"})
    assert "area: expected four numbers" in r.text
    # an area holding nothing shows no pairs
    r = client.get("/", params={"area": "10,10,11,11"})
    assert "0 pairs shown" in r.text


def test_pair_view_draws_ellipses_coast_scale_and_chart(client, station):
    q = station.snapshot.queue
    # the couple alpha / bravo sails within the view's reach of the coast
    top = q[q["track_a"].isin(["ais-alpha", "ais-bravo"])].iloc[0]
    r = client.get("/pair", params={"a": top.track_a, "b": top.track_b})
    assert r.status_code == 200
    t = r.text
    assert 'id="now-a"' in t and 'id="now-b"' in t
    assert t.count('class="aou aou-a"') >= 10 and t.count('class="aou aou-b"') >= 10
    assert 'class="scale"' in t and 'class="north"' in t
    assert 'class="distance"' in t and "band-agree" in t and "band-disagree" in t
    assert "settles" in t
    if gshhg_file() is not None:
        assert 'class="coast"' in t
    r = client.get("/pair", params={"a": top.track_a, "b": "nope"})
    assert r.status_code == 400 and "unknown track id &#x27;nope&#x27;" in r.text


def test_decide_needs_the_csrf_token_and_valid_input(client, station, tmp_path):
    top = station.snapshot.queue.iloc[0]
    body = {
        "track_a": top.track_a,
        "track_b": top.track_b,
        "decision": "same",
        "operator": "ann",
        "seen": 0,
    }
    assert _post(client, "/api/decide", body, token=None).status_code == 403
    assert _post(client, "/api/decide", body, token="wrong").status_code == 403
    r = _post(client, "/api/decide", {**body, "decision": "maybe"})
    assert r.status_code == 400 and "decision: expected" in r.json()["error"]
    r = _post(client, "/api/decide", {**body, "track_b": "ghost"})
    assert r.status_code == 400 and "unknown track id 'ghost'" in r.json()["error"]
    r = _post(client, "/api/decide", {**body, "seen": -1})
    assert r.status_code == 400 and "seen" in r.json()["error"]
    r = _post(client, "/api/decide", {**body, "p_same": 1.5})
    assert r.status_code == 400 and "p_same" in r.json()["error"]
    r = client.post("/api/decide", content="x", headers={"X-CSRF-Token": "tok"})
    assert r.status_code == 400 and "JSON" in r.json()["error"]
    assert station.log.entries() == []
    r = _post(client, "/api/decide", body)
    assert r.status_code == 200, r.text
    (e,) = station.log.entries()
    assert (e.operator, e.action) == ("ann", "same")
    assert e.p_same == pytest.approx(float(top.p_same))
    # the probability the page showed is what the log keeps (a pair of two other tracks, which
    # the first decision cannot contradict)
    q = station.snapshot.queue
    held = {top.track_a, top.track_b}
    other = q[~q["track_a"].isin(held) & ~q["track_b"].isin(held)].iloc[-1]
    r = _post(
        client,
        "/api/decide",
        {**body, "track_a": other.track_a, "track_b": other.track_b, "p_same": 0.25},
    )
    assert r.status_code == 200, r.text
    assert station.log.entries()[-1].p_same == 0.25


def test_conflicting_decision_is_refused_with_409(client, station):
    top = station.snapshot.queue.iloc[0]
    seen = station.log.position()
    body = {"track_a": top.track_a, "track_b": top.track_b, "operator": "ann", "seen": seen}
    assert _post(client, "/api/decide", {**body, "decision": "same"}).status_code == 200
    r = _post(client, "/api/decide", {**body, "decision": "different", "operator": "bob"})
    assert r.status_code == 409 and r.json()["conflict"]
    assert "ann" in r.json()["error"]
    assert len(station.log.entries()) == 1


def test_foreign_host_and_paths_are_refused(client, tmp_path):
    assert client.get("/", headers={"host": "evil.example"}).status_code == 400
    assert client.get("/static/review.js").status_code == 200
    for bad in ("/static/..%2F..%2F__init__.py", "/static/log.py", "/static/%2Fetc%2Fpasswd"):
        assert client.get(bad).status_code == 404


def test_only_the_picture_and_the_database_are_touched(client, station, tmp_path):
    before = {p.name for p in tmp_path.iterdir()}
    q = station.snapshot.queue
    client.get("/")
    for row in q.head(3).itertuples():
        client.get("/pair", params={"a": row.track_a, "b": row.track_b})
        _post(
            client,
            "/api/decide",
            {
                "track_a": row.track_a,
                "track_b": row.track_b,
                "decision": "skip",
                "operator": "ann",
                "seen": 0,
            },
        )
    _post(client, "/api/undo", {"operator": "ann"})
    client.get("/decisions.csv")
    client.get("/api/state")
    after = {p.name for p in tmp_path.iterdir()}
    assert after - before <= {"d.sqlite-wal", "d.sqlite-shm"}


def test_reassociation_follows_the_decisions(station):
    top = station.snapshot.queue.iloc[0]
    station.log.decide("ann", top.track_a, top.track_b, "same", p_same=float(top.p_same))
    snap = station.refresh()
    ref = geofeas.associate(
        station.reports, decisions=station.log.export(station.log.path.parent / "ref.csv")
    )
    assert list(snap.queue["track_a"]) == [str(x) for x in ref.review_queue["track_a"]]
    row = station.pair_row(top.track_a, top.track_b, snap)
    assert row["p_same"] == pytest.approx(1.0, abs=1e-12) and row["class"] == "match"


def test_pair_distances_match_an_independent_geodesic_computation(station):
    """Instants where both tracks have a report at the same time: the squared distance is
    d^2 / (s_a^2 + s_b^2) for circular AOUs (2-sigma radius r: s = r / 2), d the geodesic
    distance (geographiclib), independently of the engine."""
    from geographiclib.geodesic import Geodesic

    d = station.detail("ais-alpha", "radar-1")
    frame = picture()
    a = frame[frame.track_id == "ais-alpha"].set_index("time")
    b = frame[frame.track_id == "radar-1"].set_index("time")
    both = sorted(set(a.index) & set(b.index))
    assert len(both) >= 10
    k = np.searchsorted(d.time, both)
    infl = d.inflation
    for t, kk in zip(both, k, strict=True):
        g = Geodesic.WGS84.Inverse(a.lat[t], a.lon[t], b.lat[t], b.lon[t])
        m = g["s12"] ** 2 / ((a.rx[t] / 2) ** 2 + (b.rx[t] / 2) ** 2)
        assert d.sigma[kk] == pytest.approx(math.sqrt(m / infl), rel=1e-3, abs=1e-6)
    # the ellipses drawn at those instants have the reports' 2-sigma radii
    assert d.ell_a[k, 2] == pytest.approx(15.0, rel=1e-6)
    assert d.ell_b[k, 2] == pytest.approx(250.0, rel=1e-6)


def test_cli_errors_name_the_argument(tmp_path, capsys):
    from geofeas.cli import main

    assert main(["review", "--db", str(tmp_path / "none.sqlite"), "--export", "x.csv"]) == 2
    assert "--db" in capsys.readouterr().err
    assert main(["review", "--db", str(tmp_path / "d.sqlite")]) == 2
    assert "PICTURE" in capsys.readouterr().err
    bad = tmp_path / "bad.csv"
    bad.write_text("track_id,source,time,lat,lon,rx,ry,bearing\na,ais,0,95,0,10,10,0\n")
    assert main(["review", str(bad), "--db", str(tmp_path / "d.sqlite")]) == 2
    assert "line 2: column lat" in capsys.readouterr().err
    good = tmp_path / "good.csv"
    picture().to_csv(good, index=False)
    assert main(["review", str(good), "--db", str(tmp_path / "no" / "d.sqlite")]) == 2
    assert "db:" in capsys.readouterr().err


def test_coastline_is_the_isle_of_wight():
    """GSHHG decoded from GMT's binned file runs past the Isle of Wight's headlands (St
    Catherine's Point 50.5755 N 1.2975 W, the Needles 50.6625 N 1.5880 W, Foreland 50.6796 N
    1.0706 W) within 400 m, and stays kilometres from a point in the Channel."""
    import shapely

    from geofeas.review.coast import coastline

    if gshhg_file() is None:
        pytest.skip("no GSHHG file installed (apt-get install gmt-gshhg-high)")
    c = coastline(50.50, -1.70, 50.70, -1.00)
    from geofeas.demo.scenario import metres_per_degree

    m_lat, m_lon = metres_per_degree(50.6)
    scale = np.array([m_lon, m_lat])
    shore = shapely.MultiLineString([line * scale for line in c.lines])

    def metres(lat, lon):
        return shore.distance(shapely.Point(lon * scale[0], lat * scale[1]))

    for lat, lon in ((50.5755, -1.2975), (50.6625, -1.5880), (50.6796, -1.0706)):
        assert metres(lat, lon) < 400
    assert metres(50.52, -1.30) > 4000


def test_a_coastline_clips_on_either_side_of_the_antimeridian():
    """A line across 180 degrees written east of it (179.9 to 180.1) clips the same in a box
    written west of it (-180.05 to -179.95), its longitudes brought into that box's range."""
    from geofeas.review.coast import Coastline

    c = Coastline([np.array([[179.9, -17.0], [180.1, -16.9]])], "test")
    (part,) = c.clip(-17.5, -180.05, -16.5, -179.95)
    np.testing.assert_allclose(part[:, 0], [-180.05, -179.95])
    np.testing.assert_allclose(part[:, 1], [-16.975, -16.925])
    (same,) = c.clip(-17.5, 179.95, -16.5, 180.05)
    np.testing.assert_allclose(same[:, 0], [179.95, 180.05])
    assert c.clip(-17.5, 10.0, -16.5, 11.0) == []


def test_taveuni_s_coastline_across_the_antimeridian():
    """Taveuni (Fiji), which the 180th meridian crosses: its shoreline read for a box written
    east of 180 degrees and for the same box written west of it is the same, and lies on both
    sides of the meridian."""
    import shapely

    from geofeas.review.coast import coastline

    if gshhg_file() is None:
        pytest.skip("no GSHHG file installed (apt-get install gmt-gshhg-high)")
    east = coastline(-17.2, 179.7, -16.6, 180.3)
    west = coastline(-17.2, -180.3, -16.6, -179.7)
    xs = np.concatenate([line[:, 0] for line in east.lines])
    assert (xs < 180).any() and (xs > 180).any()

    def length(lines):
        return shapely.MultiLineString(lines).length

    assert length(east.lines) > 0.5  # degrees of shoreline
    assert length(west.lines) == pytest.approx(length(east.lines), rel=1e-9)
    # clipping one with the other's box keeps it all
    clipped = east.clip(-17.2, -180.3, -16.6, -179.7)
    assert length(clipped) == pytest.approx(length(east.lines), rel=1e-9)
    assert all(((line[:, 0] >= -180.3) & (line[:, 0] <= -179.7)).all() for line in clipped)


def test_the_station_s_coastline_box_across_the_antimeridian():
    """A picture off Taveuni with reports on both sides of 180 degrees gets its coastline: the
    station's box is taken about the median longitude, not from -180 to 180."""
    import types

    import pandas as pd

    from geofeas import read_reports
    from geofeas.review.station import Station

    if gshhg_file() is None:
        pytest.skip("no GSHHG file installed (apt-get install gmt-gshhg-high)")
    pic = pd.DataFrame(
        {
            "track_id": ["a", "a", "b"],
            "source": ["ais", "ais", "radar"],
            "time": [0.0, 10.0, 5.0],
            "lat": [-16.85, -16.86, -16.9],
            "lon": [179.95, -179.98, -179.9],
            "rx": [20.0, 20.0, 100.0],
            "ry": [20.0, 20.0, 40.0],
            "bearing": [0.0, 0.0, 30.0],
        }
    )
    coast = Station._coastline(types.SimpleNamespace(reports=read_reports(pic)))
    assert coast.source is not None and coast.lines
    # the box is written about the median longitude (here west of 180): the shore on both sides
    xs = np.concatenate([line[:, 0] for line in coast.lines])
    assert xs.min() < -180.0 < xs.max() or xs.min() < 180.0 < xs.max()


def test_ellipses_match_an_eigen_decomposition(rng):
    from geofeas.review.station import _aou_cov, ellipses

    cov = []
    for _ in range(50):
        a = rng.normal(size=(2, 2)) * 100
        s = a @ a.T
        cov.append([s[0, 0], s[0, 1], s[1, 1]])
    cov = np.array(cov)
    e = ellipses(cov)
    for (xx, xy, yy), (major, minor, angle) in zip(cov, e, strict=True):
        w, v = np.linalg.eigh(np.array([[xx, xy], [xy, yy]]))
        assert major == pytest.approx(2 * math.sqrt(w[1]), rel=1e-9)
        assert minor == pytest.approx(2 * math.sqrt(max(w[0], 0)), rel=1e-6, abs=1e-9)
        u = np.array([math.cos(math.radians(angle)), math.sin(math.radians(angle))])
        assert abs(u @ v[:, 1]) == pytest.approx(1.0, abs=1e-9)
    # a report's AOU (rx along the bearing, clockwise from north) comes back as drawn
    aou = np.array([[50.0, -1.0, 300.0, 100.0, 30.0]])
    major, minor, angle = ellipses(_aou_cov(aou, geographic=True))[0]
    assert (major, minor) == (pytest.approx(300.0), pytest.approx(100.0))
    assert angle % 180 == pytest.approx(60.0)  # 30 deg from north = 60 deg from east


def test_review_demo_needs_the_demo_reports(tmp_path):
    from geofeas.cli.review import review_demo

    with pytest.raises(geofeas.GeofeasError, match="reports.csv"):
        review_demo(tmp_path)


def test_a_restart_loses_nothing_and_two_stations_share_the_log(tmp_path):
    import time

    path = tmp_path / "picture.csv"
    picture().to_csv(path, index=False)
    db = tmp_path / "d.sqlite"
    one = Station(path, db, background=False)
    top = one.snapshot.queue.iloc[0]
    two = Station(path, db, background=True, poll=0.05)
    before = two.snapshot.version
    one.log.decide("ann", top.track_a, top.track_b, "same", p_same=float(top.p_same))
    # the second station sees the row appended by the first and re-associates (bounded wait)
    for _ in range(600):
        snap = two.snapshot
        if snap.version > before and snap.position == two.log.position():
            break
        time.sleep(0.05)
    assert snap.position == 1
    assert two.pair_row(top.track_a, top.track_b, snap)["class"] == "match"
    two.close()
    one.close()
    # a new station on the same files starts from the decisions made
    three = Station(path, db, background=False)
    assert [(e.operator, e.action) for e in three.log.decisions()] == [("ann", "same")]
    assert three.pair_row(top.track_a, top.track_b)["class"] == "match"
    assert three.progress()["decided"] == 1


def test_a_saved_association_is_reviewed_as_it_was_computed(tmp_path):
    path = tmp_path / "picture.csv"
    picture().to_csv(path, index=False)
    sources = sorted(set(pd.read_csv(path)["source"].astype(str)))
    shares = {src: 0.02 for src in sources}
    original = geofeas.associate(path, p_match=0.995, sweeps=200, false_tracks=shares)
    saved = original.save(tmp_path / "saved")
    assert {p.name for p in saved.iterdir()} == {
        "reports.parquet",
        "pairs.parquet",
        "objects.parquet",
        "options.json",
    }
    again = geofeas.load_association(saved)
    assert again.options["false_tracks"] == shares  # every option kept, none dropped
    np.testing.assert_array_equal(again.pairs["p_same"], original.pairs["p_same"])
    assert list(again.pairs["class"]) == list(original.pairs["class"])
    s = Station(saved, tmp_path / "d.sqlite", operator="ann", background=False)
    try:
        assert s.options["p_match"] == 0.995
        queue = s.snapshot.queue
        assert list(queue["review_rank"]) == list(original.review_queue["review_rank"])
    finally:
        s.close()
    with pytest.raises(geofeas.GeofeasError, match="not a saved association"):
        geofeas.load_association(tmp_path)
    (tmp_path / "empty").mkdir()
    with pytest.raises(geofeas.GeofeasError, match="not a saved association"):
        Station(tmp_path / "empty", tmp_path / "e.sqlite", background=False)
