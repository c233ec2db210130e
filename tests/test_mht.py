"""Boundary and cross-checks of the MHT trilateration tracker (seed 004).

The NumPy references here are written from the paper's equations (eqs. 1-8 for sensors on the x
axis), not from the Rust code.
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

import geofeas
from geofeas import GeofeasError
from geofeas.cli import main
from geofeas.tracking import (
    ESTIMATE_COLUMNS,
    METRICS,
    PAPER_TABLE_1,
    STUDY_COLUMNS,
    TRACKERS,
    MhtTracker,
    mht_ellipses,
    mht_simulate_run,
    mht_study,
    mht_track,
    mht_track_scans,
    mht_trilaterate,
    paper_sensors,
)

R = np.diag([0.05**2, 0.02**2])


def paper_trilateration(s1: float, s2: float, z: np.ndarray) -> np.ndarray:
    """Eqs. 4-7 of the paper: ``z = (z1, z2, z1', z2')`` -> ``(x, y, x', y')``; the derivatives of
    eqs. 6-7 by central differences of eqs. 4-5."""

    def pos(z1: float, z2: float) -> tuple[float, float]:
        x = (s1**2 - s2**2 - z1**2 + z2**2) / (2 * (s1 - s2))
        y = math.sqrt(0.5 * (z1**2 + z2**2 - (x - s1) ** 2 - (x - s2) ** 2))
        return x, y

    z1, z2, d1, d2 = z
    x, y = pos(z1, z2)
    h = 1e-6
    dx1 = (np.array(pos(z1 + h, z2)) - np.array(pos(z1 - h, z2))) / (2 * h)
    dx2 = (np.array(pos(z1, z2 + h)) - np.array(pos(z1, z2 - h))) / (2 * h)
    v = dx1 * d1 + dx2 * d2
    return np.array([x, y, v[0], v[1]])


def measure(sensor_x: float, state: np.ndarray) -> np.ndarray:
    dx, dy = state[0] - sensor_x, state[1]
    r = math.hypot(dx, dy)
    return np.array([r, (dx * state[2] + dy * state[3]) / r])


def test_trilateration_matches_the_paper_equations(rng: np.random.Generator) -> None:
    for _ in range(200):
        s1, s2 = -10.0, 10.0
        truth = np.array([rng.uniform(-40, 40), rng.uniform(5, 80), *rng.uniform(-10, 10, 2)])
        za, zb = measure(s1, truth), measure(s2, truth)
        state, cov = mht_trilaterate([s1, 0], za, R, [s2, 0], zb, R)
        ref = paper_trilateration(s1, s2, np.array([za[0], zb[0], za[1], zb[1]]))
        np.testing.assert_allclose(state, ref, rtol=1e-6, atol=1e-6)
        np.testing.assert_allclose(state, truth, rtol=1e-8, atol=1e-8)
        assert cov.shape == (4, 4)
        np.testing.assert_allclose(cov, cov.T, atol=1e-15)
        assert np.all(np.linalg.eigvalsh(cov) > 0)


def test_trilateration_covariance_matches_monte_carlo(rng: np.random.Generator) -> None:
    s1, s2 = -10.0, 10.0
    truth = np.array([3.0, 25.0, 5.0, -4.0])
    za, zb = measure(s1, truth), measure(s2, truth)
    _, cov = mht_trilaterate([s1, 0], za, R, [s2, 0], zb, R)
    n = 20_000
    noise = rng.standard_normal((n, 4)) * np.array([0.05, 0.05, 0.02, 0.02])
    samples = np.array(
        [
            paper_trilateration(
                s1, s2, np.array([za[0] + e[0], zb[0] + e[1], za[1] + e[2], zb[1] + e[3]])
            )
            for e in noise
        ]
    )
    mc = np.cov(samples.T)
    # Variances to 5% (standard error 1% at n = 20000), correlations to 0.03.
    np.testing.assert_allclose(np.diag(mc), np.diag(cov), rtol=0.05)
    corr = lambda c: c / np.sqrt(np.outer(np.diag(c), np.diag(c)))  # noqa: E731
    np.testing.assert_allclose(corr(mc), corr(cov), atol=0.03)


def test_trilateration_rejects_bad_input() -> None:
    with pytest.raises(GeofeasError, match="do not intersect"):
        mht_trilaterate([-10, 0], [3, 0], R, [10, 0], [3, 0], R)
    with pytest.raises(GeofeasError, match="z_a"):
        mht_trilaterate([-10, 0], [np.nan, 0], R, [10, 0], [20, 0], R)
    with pytest.raises(GeofeasError, match="cov_b"):
        mht_trilaterate([-10, 0], [20, 0], R, [10, 0], [20, 0], np.eye(3))
    with pytest.raises(GeofeasError, match="pos_a"):
        mht_trilaterate([-10, 0, 1], [20, 0], R, [10, 0], [20, 0], R)
    with pytest.raises(ValueError):
        mht_trilaterate([-10, 0], ["a", 0], R, [10, 0], [20, 0], R)


def simulate_line(
    rng: np.random.Generator,
    sensors: np.ndarray,
    periods: list[float],
    start: np.ndarray,
    velocity: np.ndarray,
    duration: float,
    false_alarms: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """An independent simulator: a straight-line target, noisy (r, r') per scan, uniform false
    alarms. Rows ``[time, sensor, range, range_rate]`` sorted by time, and the target labels."""
    rows, labels = [], []
    for s, period in enumerate(periods):
        for t in np.arange(0.0, duration + 1e-9, period):
            p = start + velocity * t
            d = p - sensors[s, :2]
            r = np.hypot(*d)
            rows.append(
                [
                    t,
                    s,
                    r + 0.05 * rng.standard_normal(),
                    d @ velocity / r + 0.02 * rng.standard_normal(),
                ]
            )
            labels.append(0)
            for _ in range(false_alarms):
                rows.append([t, s, rng.uniform(0, 100), rng.uniform(-15, 15)])
                labels.append(-1)
    order = np.lexsort((np.array(rows)[:, 1], np.array(rows)[:, 0]))
    return np.array(rows)[order], np.array(labels)[order]


@pytest.mark.parametrize("false_alarms", [0, 2])
def test_track_finds_a_straight_line_target_with_any_layout(
    rng: np.random.Generator, false_alarms: int
) -> None:
    # Three sensors not on a line, looking +y.
    sensors = paper_sensors(3)
    sensors[:, 1] = [0.0, 3.0, -2.0]
    start, velocity = np.array([-20.0, 40.0]), np.array([6.0, -2.0])
    det, labels = simulate_line(rng, sensors, [0.5, 0.6, 0.7], start, velocity, 8.0, false_alarms)
    # A straight line: a gentle motion model (1 m/s^2) instead of the paper's 4 g.
    res = mht_track(det, sensors, accel_sigma=1.0)
    tracks = res["tracks"]
    assert tracks.shape[1] == 6 and len(tracks) > 0
    # The longest track follows the target; its last estimate is within 0.5 m and 0.5 m/s.
    ids, counts = np.unique(tracks[:, 0], return_counts=True)
    best = tracks[tracks[:, 0] == ids[np.argmax(counts)]]
    t, x, y, vx, vy = best[-1, 1:]
    assert np.hypot(x - (start[0] + velocity[0] * t), y - (start[1] + velocity[1] * t)) < 0.5
    assert np.hypot(vx - velocity[0], vy - velocity[1]) < 0.5
    # Its detections are the target's.
    owner = res["track_of_detection"]
    mine = labels[owner == ids[np.argmax(counts)]]
    assert (mine == 0).mean() > 0.95
    assert 0.0 < res["probability"] <= 1.0


def test_track_rejects_bad_input() -> None:
    sensors = paper_sensors(3)
    good = np.array([[0.0, 0, 20.0, 1.0], [0.0, 1, 21.0, 1.0]])
    with pytest.raises(GeofeasError, match=r"detections: expected shape \(n, 4\)"):
        mht_track(good[:, :3], sensors)
    with pytest.raises(GeofeasError, match=r"sensors: expected shape \(s, 6\)"):
        mht_track(good, sensors[:, :5])
    bad = good.copy()
    bad[1, 2] = np.nan
    with pytest.raises(GeofeasError, match="row 1.*range"):
        mht_track(bad, sensors)
    bad = good.copy()
    bad[1, 1] = 7
    with pytest.raises(GeofeasError, match="row 1: sensor 7"):
        mht_track(bad, sensors)
    bad = good.copy()
    bad[0, 0] = 1.0
    with pytest.raises(GeofeasError, match="sort detections by time"):
        mht_track(bad, sensors)
    bad_sensors = sensors.copy()
    bad_sensors[2, 4] = -1
    with pytest.raises(GeofeasError, match="sensor row 2.*max_range"):
        mht_track(good, bad_sensors)
    with pytest.raises(GeofeasError, match="pd"):
        mht_track(good, sensors, pd=1.0)
    with pytest.raises(GeofeasError, match="max_hypotheses"):
        mht_track(good, sensors, max_hypotheses=0)
    # Non-contiguous and integer input is accepted.
    res = mht_track(np.asfortranarray(good), sensors.astype(np.float32))
    assert res["tracks"].shape[1] == 6


def test_simulate_run_is_seeded_and_consistent() -> None:
    a = mht_simulate_run(targets=2, sensors=3, false_alarms=2, seed=4)
    b = mht_simulate_run(targets=2, sensors=3, false_alarms=2, seed=4)
    c = mht_simulate_run(targets=2, sensors=3, false_alarms=2, seed=5)
    np.testing.assert_array_equal(a["detections"], b["detections"])
    assert not np.array_equal(a["detections"][:, 2], c["detections"][:, 2])
    det = a["detections"]
    # 41 + 34 + 29 scans, 2 targets + 2 false alarms each.
    assert det.shape == ((41 + 34 + 29) * 4, 6)
    assert set(np.unique(det[:, 4])) == {-1.0, 0.0, 1.0}
    m = a["metrics"]
    assert list(m) == list(METRICS)
    assert 0.0 <= m["t_pd"] <= 1.0
    truth = a["truth"]
    speeds = np.hypot(truth[:, 4], truth[:, 5])
    np.testing.assert_allclose(speeds, 10.0)
    with pytest.raises(GeofeasError, match="tracker"):
        mht_simulate_run(tracker="jpda")
    with pytest.raises(GeofeasError, match="targets"):
        mht_simulate_run(targets=3)


def test_track_ellipses_feed_the_geofeasibility_scores(rng: np.random.Generator) -> None:
    """Two radar networks see the same two targets; their track AOUs associate by GLR."""
    net_a = paper_sensors(3)
    net_b = paper_sensors(2)
    net_b[:, 0] += 5.0
    targets = [
        (np.array([-20.0, 30.0]), np.array([5.0, 1.0])),
        (np.array([15.0, 60.0]), np.array([-4.0, -2.0])),
    ]
    ell = []
    for net, periods in ((net_a, [0.5, 0.6, 0.7]), (net_b, [0.4, 0.45])):
        rows = np.vstack([simulate_line(rng, net, periods, p0, v, 6.0)[0] for p0, v in targets])
        rows = rows[np.lexsort((rows[:, 1], rows[:, 0]))]
        res = mht_track(rows, net)
        ids, e = mht_ellipses(res)
        assert e.shape == (len(ids), 5) and len(ids) >= 2
        ell.append(e)
    g = geofeas.cdist(ell[0], ell[1], score="glr")
    # Each track of network A is best matched by the track of B at the same place.
    for i, e in enumerate(ell[0]):
        j = int(np.argmax(g[i]))
        assert np.hypot(*(ell[1][j, :2] - e[:2])) < 1.0
        assert g[i, j] > 0.1
    with pytest.raises(GeofeasError):
        mht_ellipses({"tracks": []})


def test_study_columns_and_reproducibility() -> None:
    kw = dict(runs=2, seed=3, max_hypotheses=10, one_target=(0, 2), two_targets=(1,), resamples=50)
    a = mht_study(**kw)
    b = mht_study(**kw)
    assert tuple(a) == STUDY_COLUMNS
    assert set(METRICS) <= set(STUDY_COLUMNS) and "gospa" in METRICS and "id_switches" in METRICS
    # 3 trackers x 2 layouts x 3 false-alarm columns.
    assert len(a["tracker"]) == 18
    for k in STUDY_COLUMNS:
        np.testing.assert_array_equal(np.asarray(a[k]), np.asarray(b[k]))
    assert set(a["tracker"]) == set(TRACKERS) == {"mht", "mht-paper", "single"}
    # Every interval brackets its estimate.
    for m in ("t_pd", "t_far", "gospa"):
        v, lo, hi = (np.asarray(a[k], dtype=float) for k in (m, f"{m}_lo", f"{m}_hi"))
        ok = ~np.isnan(v)
        assert np.all(lo[ok] <= v[ok] + 1e-12) and np.all(v[ok] <= hi[ok] + 1e-12)
    with pytest.raises(GeofeasError, match="runs"):
        mht_study(runs=0)
    with pytest.raises(GeofeasError, match="tracker"):
        mht_study(runs=1, trackers=("mht", "jpda"))


def test_mht_study_command_writes_the_contract(tmp_path) -> None:
    out = tmp_path / "study"
    args = ["mht-study", "--out", str(out), "--runs", "2", "--seed", "1", "--resamples", "20"]
    assert main(args + ["--one-target", "0,1,2,4,6", "--two-targets", "1"]) == 0
    with open(out / "tables.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == list(STUDY_COLUMNS)
    assert len(rows) == 3 * 2 * 6
    assert {r["tracker"] for r in rows} == {"mht", "mht-paper", "single"}
    assert {r["sensors"] for r in rows} == {"2", "3"}
    one = sorted(
        int(r["false_alarms"])
        for r in rows
        if r["targets"] == "1" and r["tracker"] == "mht" and r["sensors"] == "3"
    )
    assert one == sorted(PAPER_TABLE_1)
    for name in [
        "trends.png",
        "fig_mht_tracks.png",
        "fig_mht_sensor1.png",
        "fig_single_sensor3.png",
        "comparison.md",
    ]:
        assert (out / name).stat().st_size > 0
    # No temporary files are left beside the outputs.
    assert not [p for p in out.iterdir() if p.name.startswith(".")]
    assert main(["mht-study", "--out", str(out), "--runs", "0"]) == 2


def test_scan_stream_charges_empty_scans_with_reid_s_probabilities() -> None:
    # Reid's hypothesis probabilities written out by hand: after one detection, "new track" vs
    # "false alarm" weigh beta_NT : beta_FA; an empty scan of a sensor that could see the track
    # multiplies the track hypothesis by 1 - P_D.
    fa, nt, pd = 1e-3, 4e-4, 0.8
    mht = MhtTracker(paper_sensors(2), pd=pd, false_alarm_density=fa, new_target_density=nt)
    assert mht.process_scan(0.0, 0, np.array([[25.0, 1.0]])) == 0
    (p0, _, ids0), (p1, _, ids1) = mht.hypotheses(top=2)
    assert ids0 == [] and ids1 == [0]
    assert p1 / p0 == pytest.approx(nt / fa, rel=1e-12)
    assert mht.process_scan(0.5, 1, np.empty((0, 2))) == 1
    (q0, _, _), (q1, _, _) = mht.hypotheses(top=2)
    assert q1 / q0 == pytest.approx(nt / fa * (1 - pd), rel=1e-12)
    assert mht.scans == 2
    # An empty list of detections is an empty scan too.
    mht.process_scan(1.0, 1, [])
    (r0, _, _), (r1, _, _) = mht.hypotheses(top=2)
    assert r1 / r0 == pytest.approx(nt / fa * (1 - pd) ** 2, rel=1e-12)
    with pytest.raises(GeofeasError, match="time order"):
        mht.process_scan(0.2, 0, np.empty((0, 2)))
    with pytest.raises(GeofeasError, match="detections"):
        mht.process_scan(2.0, 0, np.zeros((3, 3)))
    with pytest.raises(GeofeasError, match="sensor"):
        mht.process_scan(2.0, 5, np.zeros((0, 2)))
    with pytest.raises(GeofeasError, match="rank"):
        mht.estimates(rank=99)
    with pytest.raises(GeofeasError, match="bogus"):
        MhtTracker(paper_sensors(2), bogus=1)


def _scans_of(run: dict) -> list[tuple[float, int, np.ndarray]]:
    """The scans of a simulated run, empty ones included, from its detection rows."""
    det = run["detections"]
    periods = (0.5, 0.6, 0.7) if len(run["sensors"]) == 3 else (0.5, 0.7)
    scans = []
    for s, period in enumerate(periods):
        for k in range(int(20.0 / period + 1e-9) + 1):
            scans.append((k * period, s))
    scans.sort()
    out = []
    for t, s in scans:
        rows = det[(np.abs(det[:, 0] - t) < 1e-9) & (det[:, 1] == s)][:, 2:4]
        out.append((t, s, rows))
    return out


def test_track_scans_agrees_with_batch_tracking_and_reports_top_hypotheses() -> None:
    run = mht_simulate_run(targets=2, sensors=3, false_alarms=1, seed=4)
    scans = _scans_of(run)
    assert sum(len(r) for _, _, r in scans) == len(run["detections"])
    res = mht_track_scans(scans, paper_sensors(3), top=3)
    assert res["estimates"].shape[1] == 1 + len(ESTIMATE_COLUMNS)
    # Same data, same tracker: the final assignment of detections equals the batch run's.
    np.testing.assert_array_equal(
        res["track_of_detection"], run["detections"][:, 5].astype(np.int64)
    )
    top = res["top"]
    assert top.shape[1] == 3 and set(np.unique(top[:, 1])) <= {0.0, 1.0, 2.0}
    for scan in np.unique(top[:, 0]):
        p = top[top[:, 0] == scan, 2]
        assert np.all(np.diff(p) <= 0) and p.sum() <= 1 + 1e-12
    probs = [p for p, _, _ in res["hypotheses"]]
    assert len(probs) == 3 and probs == sorted(probs, reverse=True)
    # Per-scan estimates of the best hypothesis end near the two targets.
    last = res["estimates"][res["estimates"][:, 0] == len(scans) - 1]
    truth = run["truth"][np.isclose(run["truth"][:, 1], 20.0)]
    for target in truth:
        d = np.hypot(last[:, 3] - target[2], last[:, 4] - target[3]).min()
        assert d < 1.5, d
    # With a false alarm per scan no scan is empty; empty scans are the next test's.
    assert all(len(r) for _, _, r in scans)


def test_empty_scans_matter_on_user_data() -> None:
    run = mht_simulate_run(targets=1, sensors=3, false_alarms=0, seed=5, detection_probability=0.6)
    scans = _scans_of(run)
    empty = sum(1 for _, _, r in scans if len(r) == 0)
    assert empty > 5
    with_empty = mht_track_scans(scans, paper_sensors(3), top=2)
    without = mht_track_scans([s for s in scans if len(s[2])], paper_sensors(3), top=2)
    # The missed-detection charges change the hypothesis probabilities.
    assert with_empty["hypotheses"][0][0] != pytest.approx(without["hypotheses"][0][0])
    assert len(with_empty["top"]) > len(without["top"])


def test_process_noise_default_is_2_g_in_every_entry_point() -> None:
    """The trackers' process noise is 2 g (experiment E1 of docs/mht-study.md) wherever a
    default applies: the Python signatures, the CLI and the Rust bindings called without it."""
    import argparse
    import inspect

    from geofeas import _core
    from geofeas.cli.mht import add_parser

    two_g, four_g = 2.0 * 9.80665, 4.0 * 9.80665
    for f in (mht_track, mht_simulate_run, mht_study):
        assert inspect.signature(f).parameters["accel_sigma"].default == two_g, f.__name__
    parser = argparse.ArgumentParser()
    add_parser(parser.add_subparsers())
    assert parser.parse_args(["mht-study", "--out", "x"]).accel_sigma == two_g

    # The bindings' own defaults: the same run as with 2 g given, another with 4 g.
    def run(**kw: float) -> np.ndarray:
        r = _core.mht_simulate_run(targets=2, sensors=3, false_alarms=2, seed=1, **kw)
        return np.asarray(r.tracks)

    assert np.array_equal(run(), run(accel_sigma=two_g))
    assert not np.array_equal(run(), run(accel_sigma=four_g))
    scans = _scans_of(mht_simulate_run(targets=2, sensors=3, false_alarms=2, seed=1))

    def fed(**kw: float) -> np.ndarray:
        mht = _core.MhtTracker(paper_sensors(3), **kw)
        for t, sensor, rows in scans:
            mht.process_scan(t, sensor, np.ascontiguousarray(rows, dtype=np.float64))
        return np.asarray(mht.estimates(0))

    assert np.array_equal(fed(), fed(accel_sigma=two_g))
    assert not np.array_equal(fed(), fed(accel_sigma=four_g))


@pytest.mark.parametrize("targets", [1, 2])
def test_without_false_alarms_the_true_tracks_are_found(targets: int) -> None:
    r = mht_simulate_run(targets=targets, sensors=3, false_alarms=0, seed=2)
    m = r["metrics"]
    assert m["t_pd"] > 0.9 and m["t_far"] == 0.0 and m["pos_err"] < 1.5, m
    det = r["detections"]
    tracked = det[det[:, 5] >= 0]
    # Every detection is in a track, and every track holds one target's detections only.
    assert len(tracked) > 0.9 * len(det)
    for tid in np.unique(tracked[:, 5]):
        assert len(np.unique(tracked[tracked[:, 5] == tid, 4])) == 1
    # The single-hypothesis baseline also succeeds without false alarms.
    s = mht_simulate_run(targets=targets, sensors=3, false_alarms=0, seed=2, tracker="single")
    assert s["metrics"]["t_pd"] > 0.9


def test_detection_probability_is_configurable() -> None:
    full = mht_simulate_run(targets=2, false_alarms=0, seed=3)["detections"]
    some = mht_simulate_run(targets=2, false_alarms=0, seed=3, detection_probability=0.7)
    det = some["detections"]
    # Binomial(208, 0.7): 145.6 expected, standard deviation 6.6.
    assert len(full) == 208 and 120 < len(det) < 172
    assert 0.0 <= some["metrics"]["t_pd"] <= 1.0
    with pytest.raises(GeofeasError, match="pd"):
        mht_simulate_run(detection_probability=1.5)


def test_stonesoup_adapter_tracks_stone_soup_detections() -> None:
    pytest.importorskip("stonesoup")
    from datetime import datetime, timedelta

    from stonesoup.types.detection import Clutter, TrueDetection
    from stonesoup.types.groundtruth import GroundTruthPath, GroundTruthState
    from stonesoup.types.track import Track

    from geofeas.tracking.stonesoup import MhtStoneSoupTracker

    run = mht_simulate_run(targets=2, sensors=3, false_alarms=2, seed=6)
    epoch = datetime(2026, 1, 1)
    paths = {k: GroundTruthPath(id=f"target-{k}") for k in (0, 1)}
    for row in run["truth"]:
        paths[int(row[0])].append(
            GroundTruthState(
                [row[2], row[4], row[3], row[5]], timestamp=epoch + timedelta(seconds=row[1])
            )
        )
    # Stone Soup detections: TrueDetection for targets, Clutter for false alarms, one set per time.
    by_time: dict[float, set] = {}
    for t, s, r, rr, target, _ in run["detections"]:
        when = epoch + timedelta(seconds=float(t))
        meta = {"sensor": int(s)}
        if target >= 0:
            det = TrueDetection(
                [[r], [rr]], timestamp=when, metadata=meta, groundtruth_path=paths[int(target)]
            )
        else:
            det = Clutter([[r], [rr]], timestamp=when, metadata=meta)
        by_time.setdefault(float(t), set()).add(det)
    detector = [(epoch + timedelta(seconds=t), by_time[t]) for t in sorted(by_time)]
    tracker = MhtStoneSoupTracker(detector, paper_sensors(3))
    seen: dict[str, Track] = {}
    for time, tracks in tracker:
        for tr in tracks:
            assert isinstance(tr, Track) and tr.id.startswith("mht-")
            assert tr.timestamp == time
            seen.setdefault(tr.id, tr)
            assert seen[tr.id] is tr  # the same Track object grows
    final = tracker.tracks
    assert len(final) >= 2
    # Each target has a final track within 1.5 m, with a symmetric positive definite covariance
    # in Stone Soup's [x, vx, y, vy] order.
    for path in paths.values():
        gt = path[-1]
        best = min(
            final,
            key=lambda tr: np.hypot(
                tr.state_vector[0] - gt.state_vector[0], tr.state_vector[2] - gt.state_vector[2]
            ),
        )
        sv = np.asarray(best.state_vector, dtype=float).ravel()
        assert np.hypot(sv[0] - gt.state_vector[0], sv[2] - gt.state_vector[2]) < 1.5
        cov = np.asarray(best.state.covar, dtype=float)
        assert np.allclose(cov, cov.T) and np.all(np.linalg.eigvalsh(cov) > 0)
    # The adapter's tracks are the core tracker's best-hypothesis estimates, reordered.
    est = tracker.tracker.estimates()
    for row in est:
        tr = next(t for t in final if t.id == f"mht-{int(row[0])}")
        np.testing.assert_allclose(
            np.asarray(tr.state_vector, dtype=float).ravel(), [row[2], row[4], row[3], row[5]]
        )
    bad = [(epoch, {Clutter([[1.0], [0.0]], timestamp=epoch, metadata={})})]
    with pytest.raises(GeofeasError, match="sensor"):
        list(MhtStoneSoupTracker(bad, paper_sensors(3)))


def test_former_mht_names_warn_and_are_the_new_functions():
    import importlib

    import geofeas.tracking as tracking

    for old, new in tracking.DEPRECATED_NAMES.items():
        with pytest.warns(DeprecationWarning, match=f"tracking.{old} is deprecated.*{new}"):
            f = getattr(tracking, old)
        assert f is getattr(tracking, new)
        assert old not in tracking.__all__ and new in tracking.__all__
    with pytest.warns(DeprecationWarning, match="tracking.track is deprecated"):
        exec("from geofeas.tracking import track as _t", {})
    with pytest.raises(AttributeError, match="no attribute 'tracks'"):
        tracking.tracks  # noqa: B018
    importlib.reload(tracking)
