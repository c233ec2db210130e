"""Track-to-track association: reading and validating reports, time alignment against the NumPy
reference, the combination rules and their calibration, the candidate index against brute force,
geographic against planar mode, triage and grouping, and the ``geofeas associate`` CLI."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from reference_association import effective_instants, pair_distances
from scenes import pair_scores as _scores
from scenes import straight_track, track_arrays
from scipy import stats
from scipy.optimize import linear_sum_assignment
from scipy.special import gammaincc

import geofeas
from geofeas import _core
from geofeas.association import ASSOCIATION_DEFAULTS, DEFAULT_UPPER
from geofeas.cli import main

# ---------------------------------------------------------------------------------------------
# scenes


# ---------------------------------------------------------------------------------------------
# reading and validation


def test_read_reports_planar_with_extra_columns(tmp_path, rng):
    df = straight_track(rng, "A", "ais", (0, 0), (5, 0), 10, 10).assign(mmsi=123)
    path = tmp_path / "r.csv"
    df.to_csv(path, index=False)
    rep = geofeas.read_reports(path)
    assert rep.coords == "planar" and len(rep) == len(df) and rep.n_tracks == 1
    assert "mmsi" in rep.frame.columns
    np.testing.assert_allclose(rep.aou[:, 0], df.x.to_numpy())
    df.to_parquet(tmp_path / "r.parquet")
    rep2 = geofeas.read_reports(tmp_path / "r.parquet")
    np.testing.assert_array_equal(rep2.aou, rep.aou)
    rep3 = geofeas.read_reports({c: df[c].to_numpy() for c in df.columns})
    np.testing.assert_array_equal(rep3.time, rep.time)
    rep4 = geofeas.read_reports(df.to_records(index=False))
    np.testing.assert_array_equal(rep4.aou, rep.aou)


def test_iso_times_and_geographic_columns():
    df = pd.DataFrame(
        {
            "track_id": [1, 1, 2],
            "source": ["ais", "ais", "radar"],
            "time": ["2016-01-12T13:02:11Z", "2016-01-12 13:02:21.5", "2016-01-12T14:02:11+01:00"],
            "lat": [50.8, 50.801, 50.8],
            "lon": [-1.1, -1.1, -1.1001],
            "rx": [20.0, 20.0, 100.0],
            "ry": [10.0, 10.0, 50.0],
            "bearing": [0.0, 30.0, 90.0],
        }
    )
    rep = geofeas.read_reports(df)
    assert rep.coords == "geographic"
    t0 = pd.Timestamp("2016-01-12T13:02:11Z").timestamp()
    np.testing.assert_allclose(rep.time, [t0, t0 + 10.5, t0], rtol=0, atol=1e-6)


def test_ids_keep_their_type_and_order():
    base = dict(
        source=["a", "b", "c"], time=[0.0, 0.0, 0.0], x=0.0, y=0.0, rx=10.0, ry=10.0, phi=0.0
    )
    res = geofeas.associate(pd.DataFrame(dict(base, track_id=["9", "10", "x"])))
    # string order: "10" < "9" < "x"
    assert list(res.pairs.track_a) == ["10", "10", "9"]
    assert list(res.pairs.track_b) == ["9", "x", "x"]
    # ids are names: integers of an in-memory table become their decimal text, in text order
    res = geofeas.associate(pd.DataFrame(dict(base, track_id=[9, 10, 11])))
    assert list(zip(res.pairs.track_a, res.pairs.track_b, strict=True)) == [
        ("10", "11"),
        ("10", "9"),
        ("11", "9"),
    ]
    assert (res.pairs.track_a < res.pairs.track_b).all()
    # and never collapse: "007" and "7" are two tracks
    res = geofeas.associate(pd.DataFrame(dict(base, track_id=["007", "7", "x"])))
    assert sorted(set(res.pairs.track_a) | set(res.pairs.track_b)) == ["007", "7", "x"]


CSV_HEADER = "track_id,source,time,x,y,rx,ry,phi\n"


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ("A,s,0,0,0,10,10,0\nA,s,1,zero,0,10,10,0\n", "line 3: column x: 'zero' is not a number"),
        ("A,s,0,0,0,10,10,0\nA,s,1,0,0,10,-1,0\n", "line 3: column ry"),
        ("A,s,0,0,0,10,10,0\nA,s,1,0,0,,10,0\n", "line 3: column rx: missing value"),
        ("A,s,0,0,0,10,10,0\nA,s,1,0,0,inf,10,0\n", "line 3: column rx"),
        ("A,s,0,0,0,10,10,0\nA,s,yesterday,0,0,10,10,0\n", "line 3: column time"),
        ("A,s,0,0,0,10,10,0\nA,s,0,5,0,10,10,0\n", "line 3: track 'A' already has a report"),
        ("A,s,0,0,0,10,10,0\nA,t,1,5,0,10,10,0\n", "line 3: track 'A' has source 't'"),
        ("A,s,0,0,0,10,10,0\nA,s,1,5,0,10,10,0,9\n", "line 3"),
        ("A,s,0,0,0,10,10,0\n\nA,s,1,5,0,10,10,0\n", "line 3: column track_id: missing value"),
    ],
)
def test_malformed_files_name_the_line(tmp_path, body, message):
    path = tmp_path / "bad.csv"
    path.write_text(CSV_HEADER + body)
    with pytest.raises(geofeas.GeofeasError, match=message.replace("(", r"\(")):
        geofeas.read_reports(path)
    assert main(["associate", str(path), "--out", str(tmp_path / "o.csv")]) == 2


def test_table_errors_name_the_row():
    df = pd.DataFrame(
        dict(
            track_id=["a", "b", "c"],
            source="s",
            time=[0.0, 1.0, 2.0],
            lat=[0.0, 91.0, 0.0],
            lon=0.0,
            rx=1.0,
            ry=1.0,
            bearing=0.0,
        )
    )
    with pytest.raises(geofeas.GeofeasError, match=r"row 1: column lat"):
        geofeas.read_reports(df)
    with pytest.raises(geofeas.GeofeasError, match="missing column"):
        geofeas.read_reports(df.drop(columns="source"))
    with pytest.raises(geofeas.GeofeasError, match="both planar"):
        geofeas.read_reports(df.assign(x=0.0, y=0.0, phi=0.0))
    with pytest.raises(geofeas.GeofeasError, match="row 1: column track_id"):
        geofeas.read_reports(df.assign(track_id=pd.Series(["a", 2, "c"], dtype=object)))
    with pytest.raises(geofeas.GeofeasError, match="unknown file type"):
        geofeas.read_reports("reports.txt")
    with pytest.raises(geofeas.GeofeasError, match="combine"):
        geofeas.associate(df.assign(lat=0.0), combine="median")
    with pytest.raises(geofeas.GeofeasError, match="p_match"):
        geofeas.associate(df.assign(lat=0.0), p_match=0.3)
    with pytest.raises(TypeError, match="unexpected"):
        geofeas.associate(df.assign(lat=0.0), sample=3)


# ---------------------------------------------------------------------------------------------
# alignment and scores against the NumPy reference


def test_interpolation_exact_for_linear_motion(rng):
    # noise-free reports of one straight-line ship at unrelated times: every interpolated
    # centre is exact, so every distance is 0 and every rule gives 1
    a = straight_track(rng, "A", "ais", (100, -50), (4.0, 3.0), 10.0, 1.0)
    b = straight_track(rng, "B", "radar", (100, -50), (4.0, 3.0), 3.7, 1.0)
    for df in (a, b):
        df["x"] = 100 + 4.0 * df.time
        df["y"] = -50 + 3.0 * df.time
    frame = pd.concat([a, b])
    for rule in ("geometric", "pvalue", "chi2", "min"):
        s, k = _scores(frame, "A", "B", combine=rule, process_noise=0.0)
        assert k > 200
        assert s == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("horizon", [0.0, 20.0])
def test_distances_match_the_numpy_reference(rng, horizon):
    a = straight_track(rng, "A", "ais", (0, 0), (6, 1), 10.0, 15.0, duration=900)
    b = straight_track(rng, "B", "radar", (30, 0), (6, 1.2), 4.0, 40.0, duration=500, t0=200)
    # a long gap in A (not interpolated) and elongated, rotated AOUs
    a = a[(a.time < 400) | (a.time > 750)].copy()
    a["ry"] = a.rx * 0.4
    a["phi"] = rng.uniform(0, np.pi, len(a))
    frame = pd.concat([a, b])
    ta, ra = track_arrays(frame, "A")
    tb, rb = track_arrays(frame, "B")
    q = 3.0
    times, m = pair_distances(ta, ra, tb, rb, max_gap=300.0, horizon=horizon, q=q)
    kw = dict(process_noise=q, horizon=horizon, max_gap=300.0)
    g, k = _scores(frame, "A", "B", combine="geometric", **kw)
    assert k == len(m) > 50
    assert -2 * math.log(g) * k == pytest.approx(m.sum(), rel=1e-9)
    p, _ = _scores(frame, "A", "B", combine="pvalue", correlation_time=0.0, **kw)
    assert p == pytest.approx(stats.chi2.sf(m.sum(), 2 * k), rel=1e-8, abs=1e-300)
    tau = 45.0
    keff = effective_instants(times, tau)
    p, _ = _scores(frame, "A", "B", combine="pvalue", correlation_time=tau, **kw)
    assert p == pytest.approx(gammaincc(keff, 0.5 * m.sum() * keff / k), rel=1e-8)
    mn, _ = _scores(frame, "A", "B", combine="min", **kw)
    assert mn == pytest.approx(np.exp(-0.5 * m.max()), rel=1e-9)


# ---------------------------------------------------------------------------------------------
# combination rules


def test_combination_rules_hand_computed():
    g = [0.5, 0.25, 1.0]
    # geometric (1/8)^(1/3) = 1/2; harmonic 3 / (2 + 4 + 1); arithmetic 1.75 / 3; min 1/4
    assert geofeas.combine_instants(g, rule="geometric") == pytest.approx(0.5, rel=1e-15)
    assert geofeas.combine_instants(g, rule="harmonic") == pytest.approx(3 / 7, rel=1e-15)
    assert geofeas.combine_instants(g, rule="arithmetic") == pytest.approx(1.75 / 3, rel=1e-15)
    assert geofeas.combine_instants(g, rule="min") == 0.25
    # sum of m = 6 ln 2 on 6 degrees of freedom: e^-x (1 + x + x^2 / 2), x = 3 ln 2
    x = 3 * math.log(2)
    p = math.exp(-x) * (1 + x + x * x / 2)
    assert geofeas.combine_instants(g, rule="pvalue") == pytest.approx(p, rel=1e-13)
    # the operator scale: 2^(-m_eq / 9) with m_eq = -2 ln p
    assert geofeas.combine_instants(g, rule="chi2") == pytest.approx(
        2 ** (2 * math.log(p) / 9), rel=1e-13
    )
    # one instant: the p-value is the GLR, and 3 sigma (m = 9) is the 0.5 borderline
    assert geofeas.combine_instants([math.exp(-4.5)], rule="pvalue") == pytest.approx(
        math.exp(-4.5), rel=1e-13
    )
    assert geofeas.combine_instants([math.exp(-4.5)], rule="chi2") == pytest.approx(0.5)
    assert DEFAULT_UPPER == pytest.approx(2 ** (-4 / 9))
    # a zero instant zeroes the product-like rules but not the arithmetic mean
    assert geofeas.combine_instants([0.0, 1.0], rule="chi2") == 0.0
    assert geofeas.combine_instants([0.0, 1.0], rule="harmonic") == 0.0
    assert geofeas.combine_instants([0.0, 1.0], rule="arithmetic") == 0.5


def _simulated_true_pairs(rng, k, n):
    """``n`` true pairs of ``k`` independent instants: per-instant m ~ chi2_2."""
    m = rng.chisquare(2, size=(n, k))
    g = np.exp(-0.5 * m)
    offsets = np.arange(0, n * k + 1, k, dtype=np.uint64)
    t = np.tile(np.arange(k, dtype=np.float64), n)
    return g.ravel(), m.ravel(), t, offsets


@pytest.mark.parametrize("k", [1, 2, 5, 20, 100])
def test_calibrated_default_is_stable_in_the_number_of_instants(rng, k):
    n = 4000
    g, m, t, off = _simulated_true_pairs(rng, k, n)
    p = _core.combine_instants(g, m, t, off, "pvalue")
    assert stats.kstest(p, "uniform").pvalue > 1e-3
    s = _core.combine_instants(g, m, t, off, "chi2")
    # P(score < x) = x^(4.5 / ln 2) for every k
    assert stats.kstest(s ** (4.5 / math.log(2)), "uniform").pvalue > 1e-3
    assert np.mean(s < 0.5) == pytest.approx(math.exp(-4.5), abs=0.006)
    geo = _core.combine_instants(g, m, t, off, "geometric")
    if k >= 20:
        # the raw geometric mean of a true pair drifts to 1/e: far from uniform
        assert abs(np.median(geo) - math.exp(-1)) < 0.05
        assert stats.kstest(geo, "uniform").pvalue < 1e-10


def test_effective_instants_correct_for_correlated_errors(rng):
    # AR(1) errors with correlation exp(-dt / tau) at 1 s steps: the sum of the distances is
    # over-dispersed, and the effective number of instants restores the calibration
    tau, k, n = 20.0, 100, 3000
    a = math.exp(-1 / tau)
    e = np.empty((n, k, 2))
    e[:, 0] = rng.normal(size=(n, 2))
    for j in range(1, k):
        e[:, j] = a * e[:, j - 1] + math.sqrt(1 - a * a) * rng.normal(size=(n, 2))
    m = (e**2).sum(-1).ravel()
    g = np.exp(-0.5 * m)
    t = np.tile(np.arange(k, dtype=np.float64), n)
    off = np.arange(0, n * k + 1, k, dtype=np.uint64)
    naive = _core.combine_instants(g, m, t, off, "pvalue", correlation_time=0.0)
    fixed = _core.combine_instants(g, m, t, off, "pvalue", correlation_time=tau)
    assert np.mean(naive < 0.05) > 0.15  # far too many true pairs rejected
    assert np.mean(fixed < 0.05) == pytest.approx(0.05, abs=0.02)
    assert np.mean(fixed < 0.5) == pytest.approx(0.5, abs=0.05)


# ---------------------------------------------------------------------------------------------
# known answers on scenes


def test_one_ship_two_sources_beats_two_ships_passing(rng):
    wins = 0
    for _ in range(10):
        frame = pd.concat(
            [
                straight_track(rng, "ais-1", "ais", (0, 0), (6, 0), 10, 15),
                straight_track(rng, "radar-1", "radar", (0, 0), (6, 0), 3, 50),
                # another ship passing head-on 400 m abeam
                straight_track(rng, "radar-2", "radar", (3600, 400), (-6, 0), 3, 50),
            ]
        )
        res = geofeas.associate(frame)
        p = res.pairs.set_index(["track_a", "track_b"])
        same = p.loc[("ais-1", "radar-1"), "score"]
        other = p.loc[("ais-1", "radar-2"), "score"] if ("ais-1", "radar-2") in p.index else 0.0
        assert same > other
        wins += p.loc[("ais-1", "radar-1"), "class"] == "match" and other < 0.5
    assert wins >= 6  # 13.5 % of consistent true pairs fall below the match threshold


@pytest.mark.parametrize(
    ("score", "options"),
    [
        ("overlap", {}),
        ("overlap", {"vertices": 64}),
        ("monte_carlo", {"samples": 64, "sampler": "sobol", "seed": 3}),
        ("bhattacharyya", {}),
        ("gaussian_product", {}),
    ],
)
def test_every_per_instant_score_ranks_the_true_pair_first(rng, score, options):
    frame = pd.concat(
        [
            straight_track(rng, "ais-1", "ais", (0, 0), (6, 0), 10, 15),
            straight_track(rng, "radar-1", "radar", (0, 0), (6, 0), 3, 50),
            straight_track(rng, "radar-2", "radar", (3600, 150), (-6, 0), 3, 50),
        ]
    )
    p = geofeas.associate(frame, score=score, combine="arithmetic", **options).pairs
    p = p.set_index(["track_a", "track_b"])["score"]
    other = p.get(("ais-1", "radar-2"), 0.0)
    assert p[("ais-1", "radar-1")] > other


def test_a_vague_track_does_not_chain_two_ships():
    # Two ships 400 m apart, each seen by AIS and a radar, and a direction-finding track with a
    # 10 km AOU, halfway between them, consistent with both: merged by score alone its pairs
    # would merge first and chain the ships, refusing a precise AIS-radar pair (it does for this
    # seed when the merges go by score alone).
    rng = np.random.default_rng(16)
    frame = pd.concat(
        [
            straight_track(rng, "ais-A", "ais", (0, 0), (6, 0), 10, 10),
            straight_track(rng, "radar-A", "radar", (0, 0), (6, 0), 3, 25),
            straight_track(rng, "ais-B", "ais", (0, 400), (6, 0), 10, 10),
            straight_track(rng, "radar-B", "radar", (0, 400), (6, 0), 3, 25),
            straight_track(rng, "hfdf-A", "hfdf", (0, 200), (6, 0), 60, 5000),
        ]
    )
    res = geofeas.associate(frame)
    p = res.pairs.set_index(["track_a", "track_b"])
    # the vague pairs score at least as high as the precise ones
    assert p.loc[("ais-B", "hfdf-A"), "score"] > p.loc[("ais-A", "radar-A"), "score"]
    assert p.loc[("ais-A", "radar-A"), "class"] == "match"
    assert p.loc[("ais-B", "radar-B"), "class"] == "match"
    obj = res.objects.set_index("track_id")["object"]
    assert obj["ais-A"] == obj["radar-A"] != obj["ais-B"] == obj["radar-B"]
    # the vague track joins at most one ship
    assert sum(obj["hfdf-A"] == obj[t] for t in ("ais-A", "ais-B")) <= 1


def test_renumbered_tracks_form_one_object_and_overlaps_are_refused(rng):
    frame = pd.concat(
        [
            straight_track(rng, "ais", "ais", (0, 0), (5, 0), 10, 10, duration=1200),
            # the radar drops the ship at 500 s and picks it up again as a new track
            straight_track(rng, "r1", "radar", (0, 0), (5, 0), 3, 30, duration=500),
            straight_track(rng, "r2", "radar", (3000, 0), (5, 0), 3, 30, duration=600, t0=600),
        ]
    )
    # a second radar track on the same ship at the same time (a split track): the object may not
    # hold it together with r1
    dup = straight_track(rng, "r3", "radar", (500, 0), (5, 0), 3, 30, duration=300, t0=100)
    res = geofeas.associate(pd.concat([frame, dup]))
    obj = res.objects.set_index("track_id")["object"]
    # the renumbered track joins the ship
    assert obj["ais"] == obj["r2"]
    assert obj["r1"] != obj["r3"]
    cls = res.pairs.set_index(["track_a", "track_b"])["class"]
    p = res.pairs.set_index(["track_a", "track_b"])["p_same"]
    # r1 and r3 exclude each other: their probabilities of being the AIS ship's add up to at
    # most one, and at most one of them is merged
    assert p[("ais", "r1")] + p[("ais", "r3")] <= 1.0 + 1e-9
    assert [cls[q] for q in (("ais", "r1"), ("ais", "r3"))].count("match") <= 1


def test_one_to_one_assignment_matches_scipy(rng):
    for _ in range(20):
        na, nb = rng.integers(2, 7, size=2)
        dense = rng.uniform(0, 1, size=(na, nb)) * (rng.uniform(size=(na, nb)) < 0.6)
        ia, ib = np.nonzero(dense)
        chosen = _core.assign_one_to_one(
            ia.astype(np.uint32), (100 + ib).astype(np.uint32), dense[ia, ib], min_score=0.0
        )
        total = dense[ia[chosen], ib[chosen]].sum()
        r, c = linear_sum_assignment(dense, maximize=True)
        assert total == pytest.approx(dense[r, c].sum(), rel=1e-12)
        assert len(set(ia[chosen])) == len(chosen) == len(set(ib[chosen]))


def _random_scene(rng, n_tracks, size, geographic=False):
    rows = []
    for t in range(n_tracks):
        n = int(rng.integers(1, 12))
        times = rng.uniform(0, 1500) + np.cumsum(rng.uniform(1, 200, n))
        p = rng.uniform(0, size, 2) + np.cumsum(rng.normal(0, 300, (n, 2)), axis=0)
        r = rng.uniform(10, 400, n)
        rows.append(
            pd.DataFrame(
                dict(
                    track_id=t,
                    source=int(rng.integers(0, 3)),
                    time=times,
                    x=p[:, 0],
                    y=p[:, 1],
                    rx=r,
                    ry=r * rng.uniform(0.1, 1, n),
                    phi=rng.uniform(0, 6.3, n),
                )
            )
        )
    return pd.concat(rows)


@pytest.mark.parametrize("same_source", [False, True])
def test_index_returns_exactly_the_brute_force_pairs(rng, same_source):
    found = 0
    for _ in range(10):
        rep = geofeas.read_reports(_random_scene(rng, int(rng.integers(5, 80)), 20_000))
        kw = dict(max_gap=300.0, process_noise=2.0, same_source=same_source, horizon=30.0)
        kw["max_still_gap"] = 900.0
        kw["window"] = 120.0
        fast = _core.association_candidates(rep, options=kw)
        slow = _core.association_candidates(rep, options=kw, brute_force=True)
        np.testing.assert_array_equal(fast[0], slow[0])
        np.testing.assert_array_equal(fast[1], slow[1])
        found += len(fast[0])
    assert found > 20


# ---------------------------------------------------------------------------------------------
# geographic mode


@pytest.mark.parametrize("centre", [(0.0, 179.99), (80.0, 10.0), (-80.0, -179.995), (50.8, -1.1)])
def test_geographic_agrees_with_planar_after_an_exact_projection(rng, centre):
    from geographiclib.geodesic import Geodesic

    geod = Geodesic.WGS84
    frame = pd.concat(
        [
            straight_track(rng, "a", "ais", (-1500, -200), (5, 0.5), 10, 15),
            straight_track(rng, "b", "radar", (-1500, -200), (5, 0.5), 4, 40),
            straight_track(rng, "c", "radar", (1500, 300), (-4, 0), 5, 200),
        ]
    ).reset_index(drop=True)
    frame["ry"] = frame.rx * 0.6
    frame["phi"] = rng.uniform(0, np.pi, len(frame))
    # the exact azimuthal-equidistant projection centred on `centre`, inverted point by point:
    # the geodesic of azimuth atan2(x, y) and length |(x, y)|; bearings turn by the meridian
    # convergence azi2 - azi1 along it
    lat, lon, bearing = [], [], []
    for x, y, phi in zip(frame.x, frame.y, frame.phi, strict=True):
        azi1 = math.degrees(math.atan2(x, y))
        g = geod.Direct(centre[0], centre[1], azi1, math.hypot(x, y))
        lat.append(g["lat2"])
        lon.append(g["lon2"])
        bearing.append(math.degrees(phi) + g["azi2"] - azi1)
    geo = frame.drop(columns=["x", "y", "phi"]).assign(lat=lat, lon=lon, bearing=bearing)
    kw = dict(combine="pvalue", correlation_time=0.0, process_noise=0.0)
    planar = geofeas.associate(frame, **kw).pairs
    spherical = geofeas.associate(geo, **kw).pairs
    assert len(planar) == len(spherical) >= 2
    np.testing.assert_array_equal(planar.track_a, spherical.track_a)
    np.testing.assert_array_equal(planar.track_b, spherical.track_b)
    np.testing.assert_array_equal(planar.instants, spherical.instants)
    # the pair of one ship has p-values of order 0.1-1; the other pairs tiny ones: compare the
    # summed distances, -2 log of the geometric mean
    kw["combine"] = "geometric"
    gp = geofeas.associate(frame, **kw).pairs.score.to_numpy()
    gs = geofeas.associate(geo, **kw).pairs.score.to_numpy()
    np.testing.assert_allclose(np.log(gs), np.log(gp), rtol=1e-6)
    np.testing.assert_allclose(spherical.score, planar.score, rtol=1e-5, atol=1e-12)


# ---------------------------------------------------------------------------------------------
# CLI and file contract


def test_cli_associate_csv_and_parquet(tmp_path, rng):
    frame = pd.concat(
        [
            straight_track(rng, "A1", "ais", (0, 0), (6, 0), 10, 15),
            straight_track(rng, "R1", "radar", (0, 0), (6, 0), 3, 50),
            straight_track(rng, "R2", "radar", (0, 300), (6, 0), 3, 50),
        ]
    ).assign(comment="extra")
    frame["time"] = pd.Timestamp("2024-05-01T10:00:00Z") + pd.to_timedelta(frame.time, unit="s")
    frame["time"] = frame.time.dt.strftime("%Y-%m-%dT%H:%M:%S.%fZ")
    src = tmp_path / "reports.csv"
    frame.to_csv(src, index=False)
    out = tmp_path / "pairs.csv"
    assert (
        main(["associate", str(src), "--out", str(out), "--objects", str(tmp_path / "o.csv"), "-q"])
        == 0
    )
    pairs = pd.read_csv(out)
    assert list(pairs.columns) == [
        "track_a",
        "track_b",
        "score",
        "instants",
        "class",
        "p_same",
        "review_rank",
    ]
    assert set(pairs["class"]) <= {"match", "borderline", "non-match"}
    assert (pairs.track_a < pairs.track_b).all()
    api = geofeas.associate(src).pairs
    np.testing.assert_allclose(pairs.score, api.score, rtol=1e-12)
    frame.to_parquet(tmp_path / "reports.parquet")
    out2 = tmp_path / "pairs.parquet"
    assert (
        main(
            [
                "associate",
                str(tmp_path / "reports.parquet"),
                "--out",
                str(out2),
                "--score",
                "glr_threshold",
                "--combine",
                "geometric",
                "-q",
            ]
        )
        == 0
    )
    p2 = pd.read_parquet(out2)
    assert list(p2.columns) == list(pairs.columns) and len(p2) == len(pairs)
    assert (
        main(
            [
                "associate",
                str(src),
                "--out",
                str(tmp_path / "x.csv"),
                "--score",
                "overlap",
                "--vertices",
                "32",
                "-q",
            ]
        )
        == 0
    )


@pytest.mark.parametrize(
    ("a", "b"),
    [
        ((10.0, 179.5), (10.9, -179.6)),
        ((80.0, 10.0), (80.8, 16.0)),
        ((-79.5, -179.8), (-80.4, 178.9)),
    ],
)
def test_large_geographic_aous_match_the_geodesic_frame(a, b):
    # two 100 km AOUs some 100-150 km apart, across the antimeridian or near 80 degrees: the
    # single-instant GLR is that of the planar pair built from the geodesic between the centres
    # (Python geographiclib): B at s12 (sin azi1, cos azi1), its bearing turned by azi1 - azi2
    from geographiclib.geodesic import Geodesic

    import reference

    inv = Geodesic.WGS84.Inverse(a[0], a[1], b[0], b[1])
    s12, azi1, azi2 = inv["s12"], inv["azi1"], inv["azi2"]
    assert 50e3 < s12 < 200e3
    ea = np.array([0.0, 0.0, 100e3, 60e3, math.radians(30.0)])
    eb = np.array(
        [
            s12 * math.sin(math.radians(azi1)),
            s12 * math.cos(math.radians(azi1)),
            80e3,
            50e3,
            math.radians(110.0 + azi1 - azi2),
        ]
    )
    want = reference.glr(ea, eb)[0]
    frame = pd.DataFrame(
        dict(
            track_id=["a", "b"],
            source=["s1", "s2"],
            time=[0.0, 0.0],
            lat=[a[0], b[0]],
            lon=[a[1], b[1]],
            rx=[100e3, 80e3],
            ry=[60e3, 50e3],
            bearing=[30.0, 110.0],
        )
    )
    got = geofeas.associate(frame, combine="pvalue").pairs
    assert got.instants[0] == 1
    assert got.score[0] == pytest.approx(want, rel=1e-9)
    # the same pair seen from the other end (ids swapped) gives the same score
    swapped = frame.assign(track_id=["b", "a"])
    assert geofeas.associate(swapped, combine="pvalue").pairs.score[0] == pytest.approx(
        want, rel=1e-12
    )


def test_auto_inflation_recovers_true_pairs_with_optimistic_aous(rng):
    # 12 ships on parallel lanes 2 km apart, AIS (10 m) and radar (40 m) each, but the radar
    # states an AOU for 20 m: the summed distances of true pairs are about (10^2 + 40^2) /
    # (10^2 + 20^2) = 3.4 times too large for the stated covariances
    parts = []
    for s in range(12):
        parts.append(straight_track(rng, f"a{s:02d}", "ais", (0, 2000 * s), (5, 0), 10, 10))
        radar = straight_track(rng, f"r{s:02d}", "radar", (0, 2000 * s), (5, 0), 4, 40)
        parts.append(radar.assign(rx=40.0, ry=40.0))
    frame = pd.concat(parts)
    strict = geofeas.associate(frame, inflation=1.0)
    auto = geofeas.associate(frame)
    truth = lambda p: p.track_a.str[1:] == p.track_b.str[1:]  # noqa: E731
    assert (strict.pairs["class"][truth(strict.pairs)] == "match").sum() <= 2
    true_auto = auto.pairs[truth(auto.pairs)]
    assert (true_auto["class"] == "match").sum() >= 10
    c = auto.inflation[("ais", "radar")]
    # AIS interpolated at radar times has a smaller actual error than stated, so the measured
    # factor is somewhat below 3.4
    assert 2.3 < c < 3.6
    assert strict.inflation == {("ais", "radar"): 1.0}
    # the inflation serves the posterior whatever rule makes the score column
    assert geofeas.associate(frame, combine="geometric").inflation == auto.inflation


def test_assignment_is_one_to_one_between_two_sources(rng):
    frame = pd.concat(
        [
            straight_track(rng, "ais", "ais", (0, 0), (5, 0), 10, 10, duration=1200),
            straight_track(rng, "r1", "radar", (0, 0), (5, 0), 3, 30, duration=500),
            straight_track(rng, "r2", "radar", (3000, 0), (5, 0), 3, 30, duration=600, t0=600),
            straight_track(rng, "other", "ais", (0, 150), (5, 0), 10, 10, duration=1200),
        ]
    )
    res = geofeas.associate(frame)
    one = res.assignment("ais", "radar")
    tracks = list(one.track_a) + list(one.track_b)
    assert len(tracks) == len(set(tracks))  # nobody twice
    total = one.p_same.sum()
    # brute force over all one-to-one choices of the candidate pairs between the two sources
    p = res.pairs[res.pairs.p_same >= 0.01]
    best = 0.0
    rows = list(p.itertuples())
    for mask in range(1 << len(rows)):
        chosen = [r for i, r in enumerate(rows) if mask >> i & 1]
        ends = [r.track_a for r in chosen] + [r.track_b for r in chosen]
        if len(ends) == len(set(ends)):
            best = max(best, sum(r.p_same for r in chosen))
    assert total == pytest.approx(best, rel=1e-12)
    with pytest.raises(geofeas.GeofeasError, match="unknown source"):
        res.assignment("ais", "sonar")


def test_empty_reports_give_empty_results():
    empty = pd.DataFrame(
        {c: np.array([], dtype=float) for c in ("time", "x", "y", "rx", "ry", "phi")}
    ).assign(track_id=np.array([], dtype=np.int64), source=np.array([], dtype=np.int64))
    res = geofeas.associate(empty)
    assert len(res.pairs) == 0 and len(res.objects) == 0
    assert list(res.pairs.columns)[:7] == [
        "track_a",
        "track_b",
        "score",
        "instants",
        "class",
        "p_same",
        "review_rank",
    ]


def test_false_overlap_is_the_share_of_a_source_s_reports_where_the_objects_are(rng):
    """``Association.false_overlap`` against a direct computation: the most complete source's
    track-time per ``density_cell`` square (every report stands for the time to its track's
    next report, at most ``max_gap``; a last report for the gap before it, a lone one for
    ``min(max_gap, 60)``), each square's time displaced by a Gaussian of the source's typical
    1-sigma reach beyond the reference's (the mean over its reports of ``sqrt(rx ry) / 2``)
    and summed over the squares it lands in, against every pair of occupied squares; at least
    0.05."""
    rows = []
    for t in range(40):
        source = ["ais", "ais", "radar", "hfdf"][t % 4]
        n = 1 if source == "hfdf" else int(rng.integers(2, 30))
        times = rng.uniform(0, 900) + np.cumsum(rng.uniform(1, 400, n))
        p = rng.normal(0, 3_000.0, 2) + np.cumsum(rng.normal(0, 200, (n, 2)), axis=0)
        r = {"ais": 20.0, "radar": 300.0, "hfdf": 30_000.0}[source]
        rows.append(
            pd.DataFrame(
                dict(track_id=f"{source}-{t}", source=source, time=times, x=p[:, 0], y=p[:, 1])
            ).assign(rx=r * rng.uniform(0.5, 1.5, n), ry=r / 5, phi=0.3)
        )
    frame = pd.concat(rows, ignore_index=True)
    res = geofeas.associate(frame)
    max_gap = ASSOCIATION_DEFAULTS["max_gap"]
    cell = ASSOCIATION_DEFAULTS["density_cell"]
    seconds: dict[str, dict[tuple[int, int], float]] = {}
    for (_, source), g in frame.sort_values("time").groupby(["track_id", "source"]):
        t = g["time"].to_numpy()
        gaps = np.diff(t)
        if len(t) == 1:
            dt = np.array([min(max_gap, 60.0)])
        else:
            dt = np.minimum(np.append(gaps, gaps[-1]), max_gap)
        for x, y, d in zip(g["x"], g["y"], dt, strict=True):
            key = (math.floor(x / cell), math.floor(y / cell))
            per = seconds.setdefault(source, {})
            per[key] = per.get(key, 0.0) + d
    reference = max(seconds, key=lambda s: sum(seconds[s].values()))
    assert reference == "ais"
    sigma = {s: np.round(np.sqrt(g["rx"] * g["ry"])).mean() / 2 for s, g in frame.groupby("source")}
    keys = np.array(list(seconds[reference]), dtype=float)
    w = np.array(list(seconds[reference].values()))
    for source in seconds:
        extra = math.sqrt(max(0.0, sigma[source] ** 2 - sigma[reference] ** 2)) / cell
        if extra == 0.0:
            want = 1.0
        else:
            d = keys[None, :, :] - keys[:, None, :]  # from square i to square j, in squares
            mass = stats.norm.cdf((d + 0.5) / extra) - stats.norm.cdf((d - 0.5) / extra)
            want = float((w[:, None] * mass.prod(axis=2)).sum() / w.sum())
        want = min(1.0, max(0.05, want))
        assert res.false_overlap[source] == pytest.approx(want, rel=1e-7, abs=1e-12), source
    # the fixes mostly fall outside the ships' squares, the radar reports (a few hundred
    # metres) among them
    assert res.false_overlap["hfdf"] < 0.5 and res.false_overlap["radar"] > 0.99
    assert res.false_overlap["ais"] == 1.0


def _moored_pair_under_a_radar(rng):
    """Two ships 30 m apart, each with an AIS track, and a radar track (2-sigma 300 m) of the
    first; and a third ship far away with a precise radar track."""
    return [
        straight_track(rng, "ais-1", "ais", (0, 0), (5, 0), 10, 5),
        straight_track(rng, "ais-2", "ais", (0, 30), (5, 0), 10, 5),
        straight_track(rng, "radar", "radar", (0, 0), (5, 0), 4, 150),
        straight_track(rng, "ais-3", "ais", (0, 5000), (5, 0), 10, 5),
        straight_track(rng, "radar-3", "radar", (0, 5000), (5, 0), 4, 20),
    ]


def test_ships_geometry_cannot_separate_are_left_to_the_operator(rng):
    # geography cannot tell which of the two ships the radar sees, so neither pair may be a
    # confident merge; the third ship's pair is unambiguous
    frame = pd.concat(_moored_pair_under_a_radar(rng))
    res = geofeas.associate(frame)
    pairs = res.pairs.set_index(["track_a", "track_b"])
    assert pairs.loc[("ais-1", "radar"), "class"] == "borderline"
    assert pairs.loc[("ais-2", "radar"), "class"] == "borderline"
    # the two explanations share the radar track: their probabilities add up to about one
    both = pairs.loc[("ais-1", "radar"), "p_same"] + pairs.loc[("ais-2", "radar"), "p_same"]
    assert 0.95 < both <= 1.0 + 1e-9
    assert pairs.loc[("ais-3", "radar-3"), "class"] == "match"
    assert pairs.loc[("ais-3", "radar-3"), "p_same"] > 0.999
    # both borderline pairs are in the review queue; an operator who confirms the first settles
    # the second
    queue = res.review_queue
    assert set(zip(queue.track_a, queue.track_b, strict=True)) == {
        ("ais-1", "radar"),
        ("ais-2", "radar"),
    }
    assert list(queue.review_rank) == [1, 2]
    decided = res.with_decisions(
        pd.DataFrame({"track_a": ["radar"], "track_b": ["ais-1"], "decision": ["same"]})
    )
    after = decided.pairs.set_index(["track_a", "track_b"])
    assert after.loc[("ais-1", "radar"), "p_same"] == 1.0
    assert after.loc[("ais-1", "radar"), "class"] == "match"
    assert after.loc[("ais-2", "radar"), "p_same"] == 0.0
    assert after.loc[("ais-2", "radar"), "class"] == "non-match"
    assert decided.review_queue.empty
    # the same through associate(decisions=...)
    confirm = pd.DataFrame({"track_a": ["ais-1"], "track_b": ["radar"], "decision": ["same"]})
    again = geofeas.associate(frame, decisions=confirm)
    np.testing.assert_array_equal(again.pairs.p_same, decided.pairs.p_same)


def test_decisions_recompute_only_the_components_they_change(rng):
    # three pictures in one: two ships 30 m apart under a vague radar track, a third ship with
    # its radar track, and two more ships 40 m apart under a vague aircraft track
    frame = pd.concat(
        [
            *_moored_pair_under_a_radar(rng),
            straight_track(rng, "ais-4", "ais", (0, 20000), (5, 0), 10, 5),
            straight_track(rng, "ais-5", "ais", (0, 20040), (5, 0), 10, 5),
            straight_track(rng, "air", "aircraft", (0, 20000), (5, 0), 6, 200),
        ]
    )

    def decisions(*rows):
        return pd.DataFrame(rows, columns=["track_a", "track_b", "decision"])

    def component_of(res, a, b):
        pairs = res.pairs.set_index(["track_a", "track_b"])
        return int(pairs.loc[(a, b), "component"])

    def assert_same_result(got, want):
        pd.testing.assert_frame_equal(got.pairs, want.pairs, check_exact=True)
        pd.testing.assert_frame_equal(got.objects, want.objects, check_exact=True)
        cols = ["tracks", "method", "partitions", "max_std_error"]
        pd.testing.assert_frame_equal(got.components[cols], want.components[cols])

    base = geofeas.associate(frame)
    assert not base.components.reused.any()
    first = decisions(("radar", "ais-1", "same"))
    both = decisions(("radar", "ais-1", "same"), ("air", "ais-4", "different"))
    prior = base.pairs.set_index(["track_a", "track_b"]).p_same
    one = base.with_decisions(first)
    two = one.with_decisions(both)
    # computed again: the component of the new decision; the radar's component keeps its
    # decision and is taken from `one`, the third ship's from `base` through `one`
    changed = component_of(two, "air", "ais-4")
    assert list(two.components.reused) == [c != changed for c in range(len(two.components))]
    assert_same_result(two, geofeas.associate(frame, decisions=both))
    pairs = two.pairs.set_index(["track_a", "track_b"])
    # the rival drops to its conditional value (the component is enumerated exactly)
    assert pairs.loc[("air", "ais-4"), "p_same"] == 0.0
    want = prior[("air", "ais-5")] / (1.0 - prior[("air", "ais-4")])
    assert pairs.loc[("air", "ais-5"), "p_same"] == pytest.approx(want, rel=1e-9)
    # a decision taken back: its component is computed again, as without it
    back = two.with_decisions(decisions(("air", "ais-4", "different")))
    undone = component_of(back, "ais-1", "radar")
    assert list(back.components.reused) == [c != undone for c in range(len(back.components))]
    assert_same_result(back, geofeas.associate(frame, decisions=decisions(both.iloc[1])))
    assert back.pairs.set_index(["track_a", "track_b"]).loc[("ais-1", "radar"), "class"] == (
        "borderline"
    )


def test_decisions_files_are_read_and_contradictions_refused(tmp_path, rng):
    frame = pd.concat(
        [
            straight_track(rng, "s007", "ais", (0, 0), (5, 0), 10, 5),
            straight_track(rng, "s7", "radar", (0, 0), (5, 0), 4, 50),
            straight_track(rng, "x", "aircraft", (0, 0), (5, 0), 10, 200),
        ]
    )
    path = tmp_path / "decisions.csv"
    path.write_text(
        "track_a,track_b,decision,operator,time\n"
        "s007,s7,same,ana,2026-01-01T10:00:00Z\n"
        "s7,x,same,ana,2026-01-01T10:01:00Z\n"
        "s007,x,different,bo,2026-01-01T10:02:00Z\n"
    )
    before = path.read_bytes()
    # named as written: the file's lines with their tracks, the chain "same" then the "different"
    with pytest.raises(geofeas.GeofeasError) as err:
        geofeas.associate(frame, decisions=path)
    assert str(err.value) == (
        f"{path}: line 2 (s007 same s7), line 3 (s7 same x), line 4 (s007 different x): "
        "the last declares two tracks different that the others make one object"
    )
    assert err.value.rows == [0, 1, 2]
    assert path.read_bytes() == before  # never written
    # a DataFrame's rows; only the decisions that make the contradiction are named
    table = pd.DataFrame(
        {
            "track_a": ["s007", "s7", "s007", "s7"],
            "track_b": ["x", "s007", "s7", "x"],
            "decision": ["same", "different", "same", "same"],
        }
    )
    with pytest.raises(geofeas.GeofeasError) as err:
        geofeas.associate(frame, decisions=table)
    assert str(err.value) == (
        "decisions: row 2 (s007 same s7), row 1 (s7 different s007): "
        "the last declares two tracks different that the others make one object"
    )
    # two tracks of one source at overlapping times made one object through two others
    twin = straight_track(rng, "s008", "ais", (0, 0), (5, 0), 10, 5)
    table = pd.DataFrame(
        {"track_a": ["s007", "s7", "x"], "track_b": ["x", "s008", "s7"], "decision": "same"}
    )
    with pytest.raises(geofeas.GeofeasError) as err:
        geofeas.associate(pd.concat([frame, twin]), decisions=table)
    assert sorted(err.value.rows) == [0, 1, 2]
    for named in ("row 0 (s007 same x)", "row 1 (s7 same s008)", "row 2 (x same s7)"):
        assert named in str(err.value)
    assert str(err.value).endswith("one source at overlapping times")

    path.write_text("track_a,track_b,decision\ns007,s7,maybe\n")
    with pytest.raises(geofeas.GeofeasError, match=r"line 2: column decision"):
        geofeas.associate(frame, decisions=path)
    path.write_text("track_a,track_b,decision\ns007,s8,same\n")
    with pytest.raises(geofeas.GeofeasError, match=r"line 2: column track_b: unknown track id"):
        geofeas.associate(frame, decisions=path)
    path.write_text("track_a,track_b,decision\ns007,s7,same\n")
    res = geofeas.associate(frame, decisions=path)
    p = res.pairs.set_index(["track_a", "track_b"])["p_same"]
    assert p[("s007", "s7")] == 1.0
    assert res.decisions.frame.shape == (1, 3)
