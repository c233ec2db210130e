"""Distributed association on a real ``distributed.LocalCluster`` equals the single-machine one.

Every comparison is exact: the same pairs, bit-identical scores and posteriors (``p_same``,
``p_alone``), the same numbers of instants, classes, review order, components and objects as
``geofeas.associate`` on the whole picture, with and without operator decisions, with and
without a worker process killed in the middle of the run. The cluster listens on the loopback
interface only.
"""

from __future__ import annotations

import os
import re
import sys

import numpy as np
import pytest

pytest.importorskip("dask")
distributed = pytest.importorskip("distributed")
pd = pytest.importorskip("pandas")

import cloudpickle  # noqa: E402
import dask.dataframe as dd  # noqa: E402
from distributed import WorkerPlugin  # noqa: E402

import geofeas  # noqa: E402
import geofeas.integrations.dask as gd  # noqa: E402
from geofeas import GeofeasError  # noqa: E402

# the worker plugin below travels to the worker processes by value
cloudpickle.register_pickle_by_value(sys.modules[__name__])


def aou_cov(rx: np.ndarray, ry: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Eqs. 56-58: R = U diag(rx^2/4, ry^2/4) U^T, U = [[sin, cos], [cos, -sin]]."""
    s, c = np.sin(phi), np.cos(phi)
    u = np.stack([np.stack([s, c], -1), np.stack([c, -s], -1)], -2)
    lam = np.zeros((len(rx), 2, 2))
    lam[:, 0, 0], lam[:, 1, 1] = rx**2 / 4, ry**2 / 4
    return u @ lam @ np.swapaxes(u, -1, -2)


def picture(
    seed: int = 1,
    ships: int = 60,
    area: float = 30_000.0,
    hours: float = 1.0,
    noise: float = 1.0,
    apart: tuple[float, float] = (150.0, 400.0),
    convoy: bool = False,
):
    """Ships seen by AIS (every 60 s, 10 m) and radar (every 20 s, elongated, track breaks).

    A third of the ships sail in pairs ``apart`` metres apart, so that near-duplicates, rival
    pairs and grouping conflicts occur; times are seconds. The radar's errors are ``noise``
    times what its AOUs claim. With ``convoy``, the paired ships also share their speed.
    """
    rng = np.random.default_rng(seed)
    pos0 = rng.uniform(0, area, (ships, 2))
    pos0[1 : ships // 3 : 2] = pos0[0 : ships // 3 - 1 : 2] + rng.uniform(*apart, (1, 2))
    heading = rng.uniform(0, 2 * np.pi, ships)
    heading[1 : ships // 3 : 2] = heading[0 : ships // 3 - 1 : 2]
    speed = rng.uniform(3, 10, ships)
    if convoy:
        speed[1 : ships // 3 : 2] = speed[0 : ships // 3 - 1 : 2]
    vel = np.column_stack([np.sin(heading), np.cos(heading)]) * speed[:, None]
    frames = []
    duration = hours * 3600
    for source, step, rx, ry in (("ais", 60.0, 20.0, 20.0), ("radar", 20.0, 150.0, 60.0)):
        for i in range(ships):
            t = np.arange(rng.uniform(0, step), duration, step)
            t = t + rng.uniform(-1, 1, t.size)
            n = t.size
            phi = np.full(n, rng.uniform(0, np.pi)) if source == "radar" else np.zeros(n)
            rxs, rys = np.full(n, rx), np.full(n, ry)
            cov = aou_cov(rxs, rys, phi)
            err = np.einsum("nij,nj->ni", np.linalg.cholesky(cov), rng.normal(size=(n, 2)))
            xy = pos0[i] + vel[i] * t[:, None] + err * (noise if source == "radar" else 1.0)
            ids = np.full(n, f"{source}-{i}", dtype=object)
            if source == "radar":  # the radar tracker drops the track and starts a new one
                cut = rng.integers(n // 4, 3 * n // 4)
                ids[cut:] = f"{source}-{i}b"
                keep = np.ones(n, bool)
                keep[cut : cut + 15] = False  # five minutes unseen
                t, xy, rxs, rys, phi, ids = (
                    t[keep],
                    xy[keep],
                    rxs[keep],
                    rys[keep],
                    phi[keep],
                    ids[keep],
                )
            frames.append(
                pd.DataFrame(
                    {
                        "track_id": ids,
                        "source": source,
                        "time": t,
                        "x": xy[:, 0],
                        "y": xy[:, 1],
                        "rx": rxs,
                        "ry": rys,
                        "phi": phi,
                    }
                )
            )
    df = pd.concat(frames, ignore_index=True)
    return df.sample(frac=1.0, random_state=seed).reset_index(drop=True)  # any row order


def geographic(df: pd.DataFrame, lat0: float = 51.0, lon0: float = 179.8) -> pd.DataFrame:
    """The planar picture across the antimeridian in lat/lon (a local equirectangular map)."""
    lat = lat0 + df["y"] / 111_320.0
    lon = lon0 + df["x"] / (111_320.0 * np.cos(np.radians(lat0)))
    lon = (lon + 180.0) % 360.0 - 180.0
    return pd.DataFrame(
        {
            "track_id": df["track_id"],
            "source": df["source"],
            "time": df["time"],
            "lat": lat,
            "lon": lon,
            "rx": df["rx"],
            "ry": df["ry"],
            "bearing": np.degrees(df["phi"]),
        }
    )


def assert_same(got, want) -> None:
    """Exactly the single-machine result: pairs, bit-identical scores and posteriors, classes,
    review order, components, objects."""
    assert len(want.pairs) > 0
    assert (want.pairs["class"] == "match").any() and (want.pairs["class"] != "match").any()
    pd.testing.assert_frame_equal(got.pairs, want.pairs, check_exact=True)
    for col in ("score", "p_same", "llr"):
        np.testing.assert_array_equal(got.pairs[col].to_numpy(), want.pairs[col].to_numpy())
    pd.testing.assert_frame_equal(got.objects, want.objects, check_exact=True)
    pd.testing.assert_frame_equal(got.components, want.components, check_exact=True)
    assert got.candidates == want.candidates
    assert got.inflation == want.inflation
    assert got.coverage == want.coverage
    assert got.track_breaks == want.track_breaks
    assert got.false_overlap == want.false_overlap


def components_across_tiles(got, tile) -> int:
    """How many components of the candidate graph have pairs owned by different tiles."""
    from geofeas.integrations._tiling import Grid, owner

    tr = got.tracks
    dims = sum(1 for c in tr.columns if c.startswith("lo"))
    lo = tr[[f"lo{k}" for k in range(dims)]].to_numpy(np.float64)
    hi = tr[[f"hi{k}" for k in range(dims)]].to_numpy(np.float64)
    grid = Grid.covering(lo, hi, np.r_[np.full(dims - 1, tile[0]), tile[1]])
    index = {t: k for k, t in enumerate(tr["track_id"])}
    a = got.pairs["track_a"].map(index).to_numpy()
    b = got.pairs["track_b"].map(index).to_numpy()
    keys, meets = owner(lo[a], hi[a], lo[b], hi[b], grid)
    assert meets.all()
    tiles_per_component = (
        pd.DataFrame({"component": got.pairs["component"], "tile": keys})
        .dropna()
        .groupby("component")["tile"]
        .nunique()
    )
    return int((tiles_per_component > 1).sum())


@pytest.fixture(scope="module")
def client():
    with (
        distributed.LocalCluster(
            n_workers=2,
            processes=True,
            threads_per_worker=1,
            host="127.0.0.1",
            dashboard_address=":0",
        ) as cluster,
        distributed.Client(cluster) as c,
    ):
        yield c


@pytest.fixture(scope="module")
def planar():
    return picture()


@pytest.fixture(scope="module")
def twins():
    """Pairs of ships 10-30 m apart, closer than the radar can tell: borderline pairs, a review
    order, components of rivals."""
    return picture(seed=2, apart=(10.0, 30.0), convoy=True)


# --------------------------------------------------------------------------- on the cluster


@pytest.mark.parametrize("tile", [(4000.0, 1800.0), (8000.0, 1e9), None])
def test_cluster_result_equals_single_machine(client, planar, tile):
    want = geofeas.associate(planar)
    got = gd.associate(dd.from_pandas(planar, npartitions=4), tile=tile)
    assert_same(got, want)
    if tile is not None:
        assert got.tiles > 10  # the picture really was cut, and tracks cross tile edges
        assert len(got.tracks) == planar["track_id"].nunique()
        # components whose pairs were scored in different tiles: gathered whole
        assert components_across_tiles(got, tile) > 0


@pytest.mark.parametrize("tile", [(3000.0, 1800.0), None])
def test_cluster_posterior_and_review_order_of_rivals(client, twins, tile):
    want = geofeas.associate(twins)
    assert (want.pairs["class"] == "borderline").sum() > 5  # a review order to compare
    assert (want.components["tracks"] > 2).any()
    got = gd.associate(dd.from_pandas(twins, npartitions=4), tile=tile)
    assert_same(got, want)
    pd.testing.assert_frame_equal(got.review_queue, want.review_queue, check_exact=True)
    if tile is not None:
        assert got.tiles > 10
        # components whose pairs were scored in different tiles: gathered whole
        assert components_across_tiles(got, tile) > 0


def test_cluster_geographic_across_the_antimeridian_with_extrapolation(client, planar):
    geo = geographic(planar)
    assert (geo["lon"] > 179).any() and (geo["lon"] < -179).any()
    options = dict(horizon=120.0, max_gap=240.0)
    want = geofeas.associate(geo, **options)
    got = gd.associate(geo, tile=(6000.0, 1800.0), npartitions=3, **options)
    assert got.tiles > 10
    assert_same(got, want)


def test_cluster_estimated_inflation_of_understated_aous(client):
    reports = picture(seed=4, noise=1.5)  # the radar understates its errors
    want = geofeas.associate(reports)
    (factor,) = want.inflation.values()
    assert factor > 1.5  # the engine's global estimate really is at work
    got = gd.associate(reports, tile=(6000.0, 1800.0), npartitions=4)
    assert got.tiles > 10
    assert_same(got, want)


@pytest.mark.parametrize(
    "options",
    [
        dict(inflation=1.3),
        dict(score="overlap", combine="geometric"),
        dict(score="glr_threshold", combine="harmonic", p_match=0.95, p_reject=0.05),
        dict(completeness=0.8, false_tracks={"radar": 0.2}, density_cell=5000.0),
        # every component sampled (seeded chains), not enumerated
        dict(exact_limit=1, chains=2, sweeps=50, posterior_seed=3),
        dict(same_source=True, combine="pvalue", correlation_time=0.0),
        # seeded: a tile draws each pair's stream from the picture's track ids
        dict(score="monte_carlo", combine="arithmetic", samples=64, seed=5),
        dict(score="monte_carlo", combine="arithmetic", samples=32, sampler="sobol", seed=2),
    ],
)
def test_cluster_other_scores_and_options(client, planar, options):
    want = geofeas.associate(planar, **options)
    got = gd.associate(planar, tile=(6000.0, 1e9), npartitions=3, **options)
    assert_same(got, want)
    assert got.options == want.options


class KillOnce(WorkerPlugin):
    """Kills the worker process the first time any worker starts a task named ``prefix``."""

    name = "kill-once"

    def __init__(self, marker: str, prefix: str) -> None:
        self.marker, self.prefix = marker, prefix

    def transition(self, key, start, finish, **kwargs):
        if finish == "executing" and self.prefix in str(key):
            try:
                os.remove(self.marker)  # one kill in the whole cluster: the first to claim it
            except FileNotFoundError:
                return
            os._exit(1)


@pytest.mark.parametrize("stage", ["_partition_partials", "shuffle-transfer", "_score_tiles"])
def test_a_worker_killed_mid_run_changes_nothing(planar, tmp_path, stage):
    want = geofeas.associate(planar)
    marker = tmp_path / "kill"
    marker.touch()
    with (
        distributed.LocalCluster(
            n_workers=2,
            processes=True,
            threads_per_worker=1,
            host="127.0.0.1",
            dashboard_address=":0",
        ) as cluster,
        distributed.Client(cluster) as c,
    ):
        c.register_plugin(KillOnce(str(marker), stage))
        before = set(c.run(os.getpid).values())
        got = gd.associate(planar, tile=(6000.0, 1e9), npartitions=4)
        assert not marker.exists()  # a worker process really was killed while working
        c.wait_for_workers(2)
        after = set(c.run(os.getpid).values())
    assert before - after  # the killed process is gone; the nanny started a new one
    assert_same(got, want)


# --------------------------------------------------------------------------- inputs, errors


def test_local_scheduler_and_every_input_kind(planar, tmp_path):
    want = geofeas.associate(planar)
    assert_same(gd.associate(planar, tile=(6000.0, 1e9)), want)
    path = tmp_path / "reports"
    dd.from_pandas(planar, npartitions=3).to_parquet(str(path))
    assert_same(gd.associate(str(path), tile=(6000.0, 1e9)), want)
    pa = pytest.importorskip("pyarrow")
    assert_same(gd.associate(pa.Table.from_pandas(planar), tile=(6000.0, 1e9)), want)
    csv = tmp_path / "reports.csv"
    planar.to_csv(csv, index=False)
    assert_same(gd.associate(str(csv), tile=(6000.0, 1e9)), geofeas.associate(str(csv)))


def test_operator_decisions_give_the_single_machine_posterior(twins, tmp_path):
    base = geofeas.associate(twins)
    q = base.review_queue
    assert len(q) >= 2
    decided = pd.DataFrame(
        {
            "track_a": [q["track_a"][0], q["track_a"][1]],
            "track_b": [q["track_b"][0], q["track_b"][1]],
            "decision": ["same", "different"],
            "operator": ["op1", "op2"],
        }
    )
    path = tmp_path / "decisions.csv"
    decided.to_csv(path, index=False)
    want = geofeas.associate(twins, decisions=path)
    got = gd.associate(twins, decisions=path, tile=(6000.0, 1e9), npartitions=3)
    assert_same(got, want)
    assert_same(gd.associate(twins, decisions=decided, tile=(4000.0, 1800.0)), want)
    # the decisions were at work: the decided pairs are settled and their components changed
    p = got.pairs.set_index(["track_a", "track_b"])["p_same"]
    assert p[(q["track_a"][0], q["track_b"][0])] > 1.0 - 1e-12
    assert p[(q["track_a"][1], q["track_b"][1])] < 1e-12
    assert not np.array_equal(got.pairs["p_same"], base.pairs["p_same"])
    pd.testing.assert_frame_equal(got.decisions.frame, want.decisions.frame)


def test_contradictory_decisions_are_refused_as_on_one_machine(planar):
    want = geofeas.associate(planar)
    m = want.matches
    a, b = m["track_a"][0], m["track_b"][0]
    c = sorted(set(want.objects["track_id"]) - {a, b})[0]
    bad = pd.DataFrame(
        {"track_a": [a, b, a], "track_b": [b, c, c], "decision": ["same", "same", "different"]}
    )
    with pytest.raises(GeofeasError) as one:
        geofeas.associate(planar, decisions=bad)
    with pytest.raises(GeofeasError) as many:
        gd.associate(planar, decisions=bad, tile=(6000.0, 1e9))
    assert str(many.value) == str(one.value)


def test_the_reports_read_reports_returns(planar):
    rep = geofeas.read_reports(planar)
    want = geofeas.associate(rep)
    assert_same(gd.associate(rep, tile=(6000.0, 1e9), npartitions=3), want)
    geo = geofeas.read_reports(geographic(planar))
    got = gd.associate(geo, tile=(6000.0, 1800.0), npartitions=2)
    assert got.reports.coords == "geographic"
    assert_same(got, geofeas.associate(geo))


def test_iso_times_and_numeric_ids(planar):
    iso = planar.assign(
        time=pd.to_datetime(planar["time"] + 1.7e9, unit="s", utc=True).dt.strftime(
            "%Y-%m-%dT%H:%M:%S.%fZ"
        ),
        track_id=pd.factorize(planar["track_id"])[0] * 7 + 3,
    )
    want = geofeas.associate(iso)
    assert_same(gd.associate(iso, tile=(6000.0, 1e9), npartitions=3), want)


def test_the_assignment_of_the_result_is_the_single_machine_one(planar):
    want = geofeas.associate(planar)
    got = gd.associate(planar, tile=(6000.0, 1e9), npartitions=3)
    pd.testing.assert_frame_equal(got.assignment("ais", "radar"), want.assignment("ais", "radar"))


def test_halo_boxes_hold_every_report_aou(planar):
    boxes = gd.track_boxes(planar).set_index("track_id")
    own = boxes.loc[planar["track_id"]]
    r = np.maximum(planar["rx"], planar["ry"]).to_numpy()
    for k, col in enumerate(["x", "y", "time"]):
        v = planar[col].to_numpy()
        pad = r if col != "time" else 0.0
        assert np.all(own[f"lo{k}"].to_numpy() <= v - pad)
        assert np.all(v + pad <= own[f"hi{k}"].to_numpy())


def test_errors_name_the_row_of_the_whole_table(planar):
    bad = planar.copy()
    bad.loc[1234, "ry"] = -1.0
    with pytest.raises(GeofeasError, match=r"row 1234: column ry") as info:
        gd.associate(bad, npartitions=4)
    assert (info.value.argument, info.value.row, info.value.field) == ("reports", 1234, "ry")
    bad = planar.copy()
    bad.loc[777, "x"] = np.nan
    with pytest.raises(GeofeasError, match=r"row 777: column x"):
        gd.associate(bad, npartitions=4)
    dup = pd.concat([planar, planar.iloc[[10]]], ignore_index=True)
    # found in a tile (the two rows are in different partitions): the caller's rows and id
    name = re.escape(repr(str(planar["track_id"].iloc[10])))
    with pytest.raises(
        GeofeasError, match=rf"^row {len(planar)}: track {name} already has a report .*\(row 10\)"
    ) as info:
        gd.associate(dup, npartitions=4)
    assert (info.value.row, info.value.field) == (len(planar), "time")
    with pytest.raises(GeofeasError, match="missing column"):
        gd.associate(planar.drop(columns="source"))
    with pytest.raises(GeofeasError, match="p_match"):
        gd.associate(planar, p_match=0.1)
    with pytest.raises(GeofeasError, match="false_tracks"):
        gd.associate(planar, false_tracks={"sonar": 0.1})
    with pytest.raises(TypeError, match="lower"):  # the options of geofeas.associate only
        gd.associate(planar, lower=0.5)
    with pytest.raises(GeofeasError, match="too small"):
        gd.associate(planar, tile=(50.0, 60.0))
    with pytest.raises(GeofeasError, match="halo"):
        gd.associate(planar, halo=-1.0)
    with pytest.raises(GeofeasError, match="unknown track id"):
        gd.associate(
            planar,
            decisions=pd.DataFrame(
                {"track_a": ["ais-0"], "track_b": ["no-such"], "decision": ["same"]}
            ),
        )


def test_the_time_cover_of_the_home_tiles_in_global_order():
    """Each home tile's chains (their times and report counts, which weigh a track's time in
    the posterior) come back in the picture's track order, as the engine gives them for the
    whole picture: tracks 2 and 0 from one tile, 1 from another."""
    pieces = [
        {
            "track": np.array([2, 0]),
            "cover_offsets": np.array([0, 2, 3], np.uint32),
            "cover_start": np.array([0.0, 900.0, 10.0]),
            "cover_end": np.array([100.0, 900.0, 50.0]),
            "cover_reports": np.array([6, 1, 3], np.uint32),
        },
        {
            "track": np.array([1]),
            "cover_offsets": np.array([0, 3], np.uint32),
            "cover_start": np.array([0.0, 500.0, 1000.0]),
            "cover_end": np.array([20.0, 500.0, 1060.0]),
            "cover_reports": np.array([2, 1, 4], np.uint32),
        },
    ]
    got = gd._time_cover(pieces, 3)
    np.testing.assert_array_equal(got["cover_offsets"], [0, 1, 4, 6])
    np.testing.assert_array_equal(got["cover_start"], [10.0, 0.0, 500.0, 1000.0, 0.0, 900.0])
    np.testing.assert_array_equal(got["cover_end"], [50.0, 20.0, 500.0, 1060.0, 100.0, 900.0])
    np.testing.assert_array_equal(got["cover_reports"], [3, 2, 1, 4, 6, 1])


def test_missing_dask_gives_an_install_hint(monkeypatch):
    import importlib
    import sys

    for name in [m for m in sys.modules if m == "dask" or m.startswith("dask.")]:
        monkeypatch.setitem(sys.modules, name, None)
    monkeypatch.delitem(sys.modules, "geofeas.integrations.dask")
    with pytest.raises(ImportError, match=r"geofeas\[dask\]"):
        importlib.import_module("geofeas.integrations.dask")
    monkeypatch.undo()
    importlib.import_module("geofeas.integrations.dask")
