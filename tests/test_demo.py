"""The demo pipeline: AIS loader, sensor simulator, evaluation and `geofeas demo`."""

import math

import numpy as np
import pandas as pd
import pytest
from scipy import stats

import geofeas
from geofeas.demo import bundled
from geofeas.demo.evaluate import evaluate, prf, track_table, true_pairs
from geofeas.demo.scenario import (
    CoastalRadar,
    HfDf,
    PatrolAircraft,
    Truth,
    aou_from_covariance,
    covariance_from_aou,
    metres_per_degree,
    simulate,
)
from geofeas.io.ais import read_ais

SOLENT_HEADER = "Time,MMSI,Latitude_degrees,Longitude_degrees,COG_degrees,SOG_knots\n"
MC_HEADER = (
    "BaseDateTime,LON,LAT,MMSI,SOG,COG,Heading,VesselName,IMO,CallSign,VesselType,Status,"
    "Length,Width,Draft,Cargo,TranscieverClass,ETA\n"
)


def _solent_rows(mmsi, lat0, lon0, n, dt=10.0, v=5.0, start="2016-01-12 13:00:00"):
    """A vessel sailing north at v m/s, one report every dt seconds."""
    t0 = pd.Timestamp(start)
    m_lat, _ = metres_per_degree(lat0)
    rows = []
    for k in range(n):
        t = (t0 + pd.Timedelta(seconds=k * dt)).strftime("%Y-%m-%d %H:%M:%S.%f")[:-3]
        rows.append(
            [
                t,
                str(mmsi),
                f"{lat0 + v * k * dt / m_lat:.7f}",
                f"{lon0:.7f}",
                "0.0",
                f"{v / 0.514444:.1f}",
            ]
        )
    return rows


def _write(path, header, rows):
    path.write_text(header + "".join(",".join(r) + "\n" for r in rows))
    return path


# ------------------------------------------------------------------------------------ loader


def test_solent_schema_defects(tmp_path):
    a = _solent_rows(235000001, 50.78, -1.10, 30)
    b = _solent_rows(235000002, 50.70, -1.20, 20)
    a[12][3] = "54.83"  # corrupt longitude in the middle of a track (as in the real file)
    b[0][2] = "50.90"  # corrupt first report: 22 km away 10 s before the rest of the track
    a[5][4] = "360"  # COG not available
    rows = a[:8] + [list(a[7])] + a[8:] + b  # one exact duplicate
    rows.append(list(b[-1]))  # another exact duplicate, at the end
    path = _write(tmp_path / "solent.csv", SOLENT_HEADER, rows)
    rec = read_ais(path)
    assert rec.schema == "solent"
    reasons = rec.removed["reason"]
    assert reasons.str.startswith("exact duplicate").sum() == 2
    jumps = rec.removed[reasons.str.startswith("physically impossible")]
    assert sorted(jumps["mmsi"]) == [235000001, 235000002]
    # line numbers point into the file (header is line 1; the duplicate shifts a's later rows)
    assert sorted(jumps["line"]) == [2 + 13, 2 + 31]
    t = rec.tracks
    assert len(t) == 30 + 20 + 2 - 2 - 2
    assert t["lon"].between(-1.3, -1.0).all() and t["lat"].between(50.70, 50.80).all()
    assert t["cog"].isna().sum() == 1
    assert rec.corrected["COG not available (360 or out of range), set to NaN"] == 1
    assert (t.groupby("mmsi")["time"].diff().dropna() > 0).all()
    s = rec.summary()
    assert "removed 2 row(s): exact duplicate" in s and "impossible jump" in s


def test_marinecadastre_schema_defects(tmp_path):
    rows = []
    t0 = pd.Timestamp("2020-06-30T00:00:00")
    for k in range(12):
        t = (t0 + pd.Timedelta(minutes=k)).strftime("%Y-%m-%dT%H:%M:%S")
        lat = 40.60 + k * 0.002
        cog = {0: "-60.6", 1: "-49.6", 2: "360.0"}.get(k, "10.0")
        rows.append(
            [
                t,
                "-74.05",
                f"{lat:.5f}",
                "367000140",
                "7.0",
                cog,
                "511.0",
                "SAMUEL",
                "",
                "WYR",
                "60.0",
                "0.0",
                "94.0",
                "21.0",
                "",
                "69.0",
                "B",
                f"2020-06-30T{k:02d}:01:00",
            ]
        )
    dup = list(rows[4])
    dup[-1] = "2020-07-01T00:00:00"  # differs only in the untrustworthy ETA column
    rows.insert(5, dup)
    rows.append(
        [
            rows[0][0],
            "-74.05",
            "91.0",
            "366000001",
            "0",
            "0",
            "0",
            "X",
            "",
            "",
            "",
            "",
            "",
            "",
            "",
            "",
            "A",
            "",
        ]
    )  # position not available
    path = _write(tmp_path / "mc.csv", MC_HEADER, rows)
    rec = read_ais(path)
    assert rec.schema == "marinecadastre"
    t = rec.tracks
    assert len(t) == 12 and t["mmsi"].unique().tolist() == [367000140]
    assert t["cog"].iloc[0] == pytest.approx(409.6 - 60.6)
    assert np.isnan(t["cog"].iloc[1]) and np.isnan(t["cog"].iloc[2])
    assert rec.corrected["COG negative (signed 12-bit wrap), 409.6 added"] == 2
    r = rec.removed.set_index("line")["reason"]
    assert r[7].startswith("exact duplicate")
    assert r[len(rows) + 1].startswith("position not available")


def test_other_schemas(tmp_path):
    # Danish Maritime Authority export: day-first times, no SOG/COG needed
    body = "# Timestamp,Type of mobile,MMSI,Latitude,Longitude\n" + "".join(
        f"12/01/2016 13:0{k}:00,Class A,219000001,{55.70 + k * 0.001:.4f},12.6\n" for k in range(5)
    )
    (tmp_path / "dma.csv").write_text(body)
    rec = read_ais(tmp_path / "dma.csv")
    assert rec.schema == "dma" and len(rec.tracks) == 5
    assert rec.tracks["time"].iloc[0] == pd.Timestamp("2016-01-12 13:00:00", tz="UTC").timestamp()
    assert rec.tracks["sog"].isna().all()
    # snake-case names and Unix-second times
    body = "mmsi,base_date_time,latitude,longitude,sog,cog\n" + "".join(
        f"367000001,{1452603600 + 60 * k},40.6{k},-74.0,5.0,-60.6\n" for k in range(3)
    )
    (tmp_path / "snake.csv").write_text(body)
    rec = read_ais(tmp_path / "snake.csv")
    assert rec.schema == "marinecadastre"
    np.testing.assert_array_equal(rec.tracks["time"], 1452603600 + 60 * np.arange(3))
    np.testing.assert_allclose(rec.tracks["cog"], 349.0)


def test_loader_errors(tmp_path):
    with pytest.raises(geofeas.GeofeasError, match="not a recognised AIS schema"):
        read_ais(_write(tmp_path / "x.csv", "a,b\n1,2\n", []))
    rows = _solent_rows(235000001, 50.78, -1.10, 3)
    rows[1][2] = "north"
    with pytest.raises(geofeas.GeofeasError, match="line 3: column Latitude_degrees"):
        read_ais(_write(tmp_path / "y.csv", SOLENT_HEADER, rows))
    rows = _solent_rows(235000001, 50.78, -1.10, 3)
    rows[2][0] = "yesterday"
    with pytest.raises(geofeas.GeofeasError, match="line 4: column Time"):
        read_ais(_write(tmp_path / "z.csv", SOLENT_HEADER, rows))
    (tmp_path / "e.csv").write_text("")
    with pytest.raises(geofeas.GeofeasError, match="empty"):
        read_ais(tmp_path / "e.csv")


def test_bundled_recordings():
    sol = read_ais(bundled("solent"))
    assert sol.tracks["mmsi"].nunique() == 91
    assert len(sol.removed) == 4  # 3 duplicates, 1 corrupt longitude
    bad = sol.removed[sol.removed["reason"].str.startswith("physically")]
    assert bad["mmsi"].tolist() == [245188000]
    ny = read_ais(bundled("nyharbor"))
    assert ny.tracks["mmsi"].nunique() == 295 and len(ny.removed) == 2


# ------------------------------------------------------------------------------------ geometry


def test_aou_covariance_round_trip(rng):
    rx = rng.uniform(1, 100, 200)
    ry = rng.uniform(1, 100, 200)
    b = rng.uniform(0, 360, 200)
    cov = covariance_from_aou(rx, ry, b)
    rx2, ry2, b2 = aou_from_covariance(cov)
    np.testing.assert_allclose(rx2, np.maximum(rx, ry), rtol=1e-9)
    np.testing.assert_allclose(ry2, np.minimum(rx, ry), rtol=1e-9)
    np.testing.assert_allclose(covariance_from_aou(rx2, ry2, b2), cov, rtol=1e-9, atol=1e-9)
    # bearing 0 puts rx along north: var(north) = (rx/2)^2
    c = covariance_from_aou(np.array([20.0]), np.array([10.0]), np.array([0.0]))[0]
    np.testing.assert_allclose(c, [[25.0, 0.0], [0.0, 100.0]], atol=1e-12)


def test_metres_per_degree_closed_form():
    # WGS84 at the equator: 110574.3 m per degree of latitude, 111319.5 m of longitude
    m_lat, m_lon = metres_per_degree(0.0)
    assert m_lat == pytest.approx(110574.27, abs=0.05)
    assert m_lon == pytest.approx(111319.49, abs=0.05)
    m_lat, m_lon = metres_per_degree(45.0)
    assert m_lat == pytest.approx(111131.75, abs=0.05)


# ------------------------------------------------------------------------------------ simulator


@pytest.fixture(scope="module")
def solent():
    return read_ais(bundled("solent"))


@pytest.fixture(scope="module")
def scenario(solent):
    return simulate(solent, seed=3, minutes=30)


def _mahalanobis(scenario, recording, source):
    r = scenario.reports
    sel = (r["source"] == source).to_numpy() & (r["mmsi"] >= 0).to_numpy()
    truth = Truth.from_recording(recording)
    index = {m: k for k, m in enumerate(truth.mmsi)}
    rep = r[sel]
    t = scenario.seconds[sel]
    tl = np.empty(len(rep))
    to = np.empty(len(rep))
    for m, idx in rep.groupby("mmsi").indices.items():
        la, lo, ok = truth.vessel(index[m], t[idx])
        assert ok.all()
        tl[idx], to[idx] = la, lo
    m_lat, m_lon = metres_per_degree(tl)
    e = np.stack([(rep["lon"].to_numpy() - to) * m_lon, (rep["lat"].to_numpy() - tl) * m_lat], -1)
    cov = covariance_from_aou(rep["rx"].to_numpy(), rep["ry"].to_numpy(), rep["bearing"].to_numpy())
    return np.einsum("ni,nij,nj->n", e, np.linalg.inv(cov), e)


@pytest.fixture(scope="module")
def dense_hfdf(solent):
    sensors = ["ais", "radar", "aircraft", HfDf(emitter_fraction=1.0, transmission_interval=60.0)]
    return simulate(solent, seed=4, minutes=30, sensors=sensors)


@pytest.mark.parametrize("source", ["ais", "radar", "aircraft", "hfdf"])
def test_noise_consistent_with_aou(dense_hfdf, solent, source):
    d2 = _mahalanobis(dense_hfdf, solent, source)
    assert len(d2) > 30
    # the squared Mahalanobis distance of a 2-D Gaussian error is chi2(2)
    assert stats.kstest(d2, stats.chi2(2).cdf).pvalue > 1e-3
    # and the test has power: AOUs 30% too large (or too small) are rejected when n is large
    if len(d2) > 2000:
        assert stats.kstest(d2 * 1.3**2, stats.chi2(2).cdf).pvalue < 1e-6
        assert stats.kstest(d2 / 1.3**2, stats.chi2(2).cdf).pvalue < 1e-6


def test_radar_aou_geometry(scenario):
    from geofeas.demo.scenario import _range_bearing

    radar = CoastalRadar()
    site = scenario.geometry["radar_site"]
    r = scenario.reports[scenario.reports["source"] == "radar"]
    rng_m, los = _range_bearing(site[0], site[1], r["lat"].to_numpy(), r["lon"].to_numpy())
    assert rng_m.max() < radar.max_range + 500
    # across the line of sight, 2 r sigma_bearing (r from the noisy position: within 5 sigma_r)
    r_true = r["rx"].to_numpy() / (2 * math.radians(radar.bearing_sigma))
    assert np.abs(r_true - rng_m).max() < 5 * radar.range_sigma
    np.testing.assert_allclose(r["ry"], 2 * radar.range_sigma)
    diff = (r["bearing"].to_numpy() - los) % 180.0
    # the line of sight seen from the noisy position is off by the bearing error (sigma 0.5 deg)
    assert np.abs(diff - 90.0).max() < 5 * radar.bearing_sigma
    assert abs(np.mean(diff) - 90.0) < 0.05


def test_tracks_breaks_and_false_tracks(scenario):
    r = scenario.reports
    t = scenario.seconds
    for source, period, coast in (("radar", 3.0, 3), ("aircraft", 10.0, 2)):
        sel = (r["source"] == source).to_numpy()
        rep = r[sel].assign(t=t[sel])
        # one vessel per track; within a track no gap longer than the coasting allows
        assert (rep.groupby("track_id")["mmsi"].nunique() == 1).all()
        gaps = rep.groupby("track_id")["t"].diff().dropna()
        assert gaps.max() <= (coast + 1) * period + period + 1e-6
        assert (rep["mmsi"] < 0).any()  # false tracks
        # breaks: some vessels have several tracks of this source
        assert (rep[rep["mmsi"] >= 0].groupby("mmsi")["track_id"].nunique() > 1).any()
    ais = r[r["source"] == "ais"]
    assert (ais["track_id"] == "ais-" + ais["mmsi"].astype(str)).all()
    assert set(r.columns) == {
        "track_id",
        "source",
        "time",
        "lat",
        "lon",
        "rx",
        "ry",
        "bearing",
        "mmsi",
    }


def test_one_report_per_track_and_instant():
    # a vessel crossing the radar's sweep start (north) is seen twice within milliseconds
    # unless the twin plot is dropped; the New York scenario has such crossings
    sc = simulate(read_ais(bundled("nyharbor")), seed=0)
    r = sc.reports.assign(t=sc.seconds)
    assert not r.duplicated(["track_id", "t"]).any()
    gaps = r.sort_values("t").groupby("track_id")["t"].diff().dropna()
    radar = r.loc[gaps.index, "source"] == "radar"
    assert gaps[radar.to_numpy()].min() >= 1.5  # half a scan


def test_seeded_and_sources_independent(solent):
    a = simulate(solent, seed=5, minutes=5, sensors=["radar", "aircraft"]).reports
    b = simulate(solent, seed=5, minutes=5, sensors=["aircraft", "radar", "hfdf"]).reports
    c = simulate(solent, seed=6, minutes=5, sensors=["radar"]).reports
    ra, rb = (x[x["source"] == "radar"].reset_index(drop=True) for x in (a, b))
    pd.testing.assert_frame_equal(ra, rb)
    assert not np.allclose(ra["lat"].to_numpy()[:50], c["lat"].to_numpy()[:50])


def test_hfdf_elongated_and_sparse(scenario):
    r = scenario.reports
    h = r[r["source"] == "hfdf"]
    assert (h["rx"] / h["ry"] > 3).all() and (h["ry"] > 1000).all()
    assert len(h) < 0.01 * len(r)
    assert h["mmsi"][h["mmsi"] >= 0].nunique() <= 0.3 * r["mmsi"][r["mmsi"] >= 0].nunique()


def test_configured_sensors(solent):
    sc = simulate(
        solent,
        seed=1,
        minutes=10,
        sensors=[
            CoastalRadar(site=(50.7955, -1.1077), false_tracks_per_hour=0.0),
            PatrolAircraft(on_station=(0.0, 1.0)),
            HfDf(emitter_fraction=1.0),
        ],
    )
    r = sc.reports
    assert sc.geometry["radar_site"] == (50.7955, -1.1077)
    assert (r[r["source"] == "radar"]["mmsi"] >= 0).all()
    with pytest.raises(geofeas.GeofeasError, match="unknown sensor"):
        simulate(solent, sensors=["sonar"])
    with pytest.raises(geofeas.GeofeasError, match="seed"):
        simulate(solent, seed=-1)


# ------------------------------------------------------------------------------------ evaluation


def _tracks(rows):
    return track_table(pd.DataFrame(rows, columns=["track_id", "source", "time", "mmsi"]))


def test_true_pairs_need_overlap_and_different_sources():
    tracks = _tracks(
        [
            ("ais-1", "ais", 0.0, 1),
            ("ais-1", "ais", 100.0, 1),
            ("r-1", "radar", 10.0, 1),
            ("r-1", "radar", 50.0, 1),
            ("r-2", "radar", 60.0, 1),
            ("r-2", "radar", 200.0, 1),  # break: same source
            ("a-1", "aircraft", 150.0, 1),
            ("a-1", "aircraft", 160.0, 1),  # overlaps r-2 only
            ("r-3", "radar", 0.0, -1),
            ("r-3", "radar", 100.0, -1),  # false track
            ("ais-2", "ais", 0.0, 2),
            ("ais-2", "ais", 100.0, 2),
            ("a-2", "aircraft", 100.0, 2),  # touches ais-2 at t = 100: a common time
        ]
    )
    assert true_pairs(tracks) == {
        ("ais-1", "r-1"),
        ("ais-1", "r-2"),
        ("a-1", "r-2"),
        ("a-2", "ais-2"),
    }


def test_evaluate_counts():
    tracks = _tracks(
        [
            ("ais-1", "ais", 0.0, 1),
            ("r-1", "radar", 0.0, 1),
            ("a-1", "aircraft", 0.0, 1),
            ("ais-2", "ais", 0.0, 2),
            ("r-2", "radar", 0.0, 2),
            ("r-9", "radar", 0.0, -1),
            ("r-8", "radar", 0.0, 1),
        ]
    )
    pairs = pd.DataFrame(
        [
            ("r-1", "ais-1", 0.9, 3, "match"),  # tp (order does not matter)
            ("ais-1", "a-1", 0.6, 3, "borderline"),  # fn, borderline
            ("ais-2", "r-9", 0.8, 3, "match"),  # fp with a false track
            ("ais-2", "a-1", 0.7, 3, "match"),  # fp
            ("r-1", "r-8", 0.9, 3, "match"),  # same source: counted apart
            ("ais-2", "r-2", 0.1, 3, "non-match"),  # fn
        ],
        columns=["track_a", "track_b", "score", "instants", "class"],
    )
    m = evaluate(tracks, pairs, seconds=1.5)
    # true pairs: ais-1/r-1, ais-1/a-1, r-1/a-1, ais-2/r-2, ais-1/r-8, a-1/r-8
    assert m.true_pairs == 6
    assert (m.tp, m.fp, m.fn, m.predicted) == (1, 2, 5, 3)
    assert m.precision == pytest.approx(1 / 3) and m.recall == pytest.approx(1 / 6)
    assert m.f1 == pytest.approx(2 / 9)
    assert m.classes == {"match": 4, "borderline": 1, "non-match": 1}
    assert m.true_in_class == {"match": 1, "borderline": 1, "non-match": 1}
    assert m.true_not_candidates == 3
    assert m.fp_with_false_track == 1 and m.same_source_matches == 1
    bs = m.by_sources.set_index("sources")
    assert bs.loc["ais-radar", "true_pairs"] == 3 and bs.loc["ais-radar", "tp"] == 1
    objects = pd.DataFrame(
        {
            "track_id": ["ais-1", "r-1", "a-1", "r-8", "ais-2", "r-2", "r-9"],
            "object": [0, 0, 0, 0, 1, 1, 2],
        }
    )
    m = evaluate(tracks, pairs, objects=objects)
    assert (m.object_precision, m.object_recall, m.object_f1) == (1.0, 1.0, 1.0)
    with pytest.raises(geofeas.GeofeasError, match="not in the reports"):
        evaluate(tracks, pairs.assign(track_a="zz"))
    with pytest.raises(geofeas.GeofeasError, match="unknown class"):
        evaluate(tracks, pairs.assign(**{"class": "maybe"}))


def test_prf_edge_cases():
    assert prf(0, 0, 0) == (1.0, 1.0, 1.0)
    assert prf(0, 0, 5) == (1.0, 0.0, 0.0)
    assert prf(0, 3, 0) == (0.0, 1.0, 0.0)
    assert prf(3, 4, 6) == pytest.approx((0.75, 0.5, 0.6))


# ------------------------------------------------------------------------------------ pipeline


# ------------------------------------------------------------------------------------ pipeline


def test_cli_names_match_the_modules():
    from geofeas import demo
    from geofeas.cli import demo as _cli_demo
    from geofeas.demo import scenario

    assert list(_cli_demo.SENSORS) == list(scenario.SENSORS)
    assert list(_cli_demo.SCORES) == list(demo.SCORES)
    assert list(_cli_demo.RECORDINGS) == list(demo.RECORDINGS)


def test_cli_rejects_unknown_sensor(capsys):
    from geofeas.cli import main

    with pytest.raises(SystemExit):
        main(["demo", "--sensors", "ais,sonar"])
    assert "unknown sensor(s) sonar" in capsys.readouterr().err


@pytest.mark.parametrize("value", ["0", "-3", "2.5"])
def test_cli_rejects_an_operator_batch_that_is_no_count(capsys, value):
    from geofeas.cli import main

    with pytest.raises(SystemExit):
        main(["demo", "--operator-batch", value])
    assert "--operator-batch" in capsys.readouterr().err


def test_reliability_table_and_ece_by_hand():
    from geofeas.demo.evaluate import reliability

    p = np.array([0.05, 0.05, 0.95, 0.95, 0.55, 0.55])
    y = np.array([0, 0, 1, 0, 1, 1], dtype=bool)
    table, ece = reliability(p, y, bins=10)
    assert list(table["n"]) == [2, 2, 2]
    # |0.05 - 0| * 2 + |0.55 - 1| * 2 + |0.95 - 0.5| * 2, over 6
    assert ece == pytest.approx((0.1 + 0.9 + 0.9) / 6)
    with pytest.raises(geofeas.GeofeasError, match="probabilities"):
        reliability([1.5], [True])


@pytest.mark.parametrize("n", [1, 3, 7, 300, 1001])
def test_wilson_interval_holds_the_observed_frequency(n):
    from geofeas.demo.evaluate import reliability

    # bins where nothing or everything is a true pair: the interval's edge is the frequency itself
    # (0 or 1) and must not be rounded past it; the error bars drawn from it are then >= 0
    p = np.r_[np.full(n, 0.03), np.full(n, 0.45), np.full(n, 0.97)]
    y = np.r_[np.zeros(n, bool), np.zeros(n, bool), np.ones(n, bool)]
    table, _ = reliability(p, y, bins=10)
    assert (table["observed_lo"] <= table["observed"]).all()
    assert (table["observed"] <= table["observed_hi"]).all()
    assert list(table["observed_lo"][table["observed"] == 0]) == [0.0, 0.0]
    assert list(table["observed_hi"][table["observed"] == 1]) == [1.0]
    # the Wilson bound of an empty bin is (0, z^2 / (n + z^2))
    z2 = 1.959963984540054**2
    assert table["observed_hi"].iloc[0] == pytest.approx(z2 / (n + z2))


def test_old_module_paths_warn_and_are_the_moved_modules():
    import importlib
    import sys

    from geofeas.demo import scenario as moved_scenario

    # the module: `from geofeas.demo import evaluate` is the function of that name
    moved_evaluate = importlib.import_module("geofeas.demo.evaluate")
    assert moved_evaluate.evaluate is geofeas.demo.evaluate

    for old, moved in (("geofeas.scenario", moved_scenario), ("geofeas.evaluate", moved_evaluate)):
        sys.modules.pop(old, None)
        with pytest.warns(DeprecationWarning, match="moved to geofeas.demo"):
            module = importlib.import_module(old)
        assert module is moved


# ------------------------------------------------------------------- the HF DF oracle's bound


def test_emitter_posterior_by_hand():
    from types import SimpleNamespace

    from geofeas.demo.evaluate import emitter_posterior
    from geofeas.demo.scenario import Scenario

    lat0, lon0 = 50.8, -1.3
    m_lat, m_lon = metres_per_degree(np.array([lat0]))
    east = 1000.0 / m_lon[0]  # vessel B is 1 km east of vessel A
    tracks = pd.DataFrame(
        {
            "mmsi": [1, 1, 2, 2, 3],
            "time": [0.0, 100.0, 0.0, 100.0, 500.0],  # vessel 3 is unknown at the fix
            "lat": [lat0, lat0, lat0, lat0, lat0],
            "lon": [lon0, lon0, lon0 + east, lon0 + east, lon0],
        }
    )
    # one fix at t = 50, 300 m east of A, 2-sigma circle of 1 km (sigma 500 m), and a false one
    fix_lon = lon0 + 300.0 / m_lon[0]
    reports = pd.DataFrame(
        {
            "track_id": ["hfdf-0000", "hfdf-0001"],
            "source": ["hfdf", "hfdf"],
            "time": ["", ""],
            "lat": [lat0, lat0],
            "lon": [fix_lon, fix_lon],
            "rx": [1000.0, 1000.0],
            "ry": [1000.0, 1000.0],
            "bearing": [0.0, 0.0],
            "mmsi": [2, -1],
        }
    )
    got = emitter_posterior(
        Scenario(reports, np.array([50.0, 50.0])), SimpleNamespace(tracks=tracks)
    )
    # m_A = (300 / 500)^2, m_B = (700 / 500)^2: q_A = 1 / (1 + exp(-(1.96 - 0.36) / 2))
    want_a = 1.0 / (1.0 + math.exp(-0.8))
    assert list(got["track_id"]) == ["hfdf-0000", "hfdf-0000"]
    assert list(got["mmsi"]) == [1, 2]
    assert got["q"].to_numpy() == pytest.approx([want_a, 1.0 - want_a], rel=1e-3)


def test_borderline_bound_by_hand_and_against_brute_force(rng):
    from itertools import product

    from geofeas.demo.evaluate import borderline_bound

    # send the 0.001 group (cost 0.01); 0.05 left buys 2.5 of the 0.02 group's 5 pairs; the
    # 0.995 group is a merge, not borderline
    got = borderline_bound([0.001, 0.02, 0.5, 0.995], [10, 5, 2, 4], 0.06)
    assert got == pytest.approx(17 - 10 - 2.5)
    for _ in range(200):
        k = int(rng.integers(1, 8))
        q = rng.choice([0.0, 0.001, 0.01, 0.05, 0.2, 0.7, 0.999], size=k)
        n = rng.integers(0, 6, size=k).astype(float)
        budget = float(rng.uniform(0, 2))
        best = math.inf
        for send in product([False, True], repeat=k):
            s = np.array(send)
            if (q * n)[s].sum() <= budget + 1e-12:
                best = min(best, n[~s & (q < 0.99)].sum())
        bound = borderline_bound(q, n, budget)
        # a relaxation: never above the best whole choice, and short of it by less than one group
        assert bound <= best + 1e-9
        assert bound > best - n.max() - 1e-9
    with pytest.raises(geofeas.GeofeasError, match="budget"):
        borderline_bound([0.1], [1], -1.0)
    with pytest.raises(geofeas.GeofeasError, match="probabilities"):
        borderline_bound([1.1], [1], 1.0)
