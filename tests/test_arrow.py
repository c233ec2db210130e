"""Arrow tables and Parquet files in and out, equal to the pandas path."""

from __future__ import annotations

import numpy as np
import pytest

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")
pd = pytest.importorskip("pandas")

import geofeas  # noqa: E402
import geofeas.io.arrow as ga  # noqa: E402


def reports(seed: int = 5, ships: int = 12, twin: float | None = None) -> pd.DataFrame:
    """AIS and radar tracks of ``ships`` ships; with ``twin``, ship 1 sails ``twin`` metres
    beside ship 0, closer than the radar can tell apart."""
    rng = np.random.default_rng(seed)
    rows = []
    first = None
    for i in range(ships):
        p0, v = rng.uniform(0, 5000, 2), rng.uniform(-5, 5, 2)
        if i == 0:
            first = p0, v
        elif i == 1 and twin is not None:
            p0, v = first[0] + [twin, 0.0], first[1]
        for source, step, r in (("ais", 30.0, 20.0), ("radar", 10.0, 90.0)):
            t = np.arange(0, 900, step) + rng.uniform(0, step)
            xy = p0 + v * t[:, None] + rng.normal(0, r / 2, (t.size, 2))
            rows.append(
                pd.DataFrame(
                    {
                        "track_id": f"{source}{i}",
                        "source": source,
                        "time": t,
                        "x": xy[:, 0],
                        "y": xy[:, 1],
                        "rx": r,
                        "ry": r,
                        "phi": 0.0,
                    }
                )
            )
    return pd.concat(rows, ignore_index=True)


def test_arrow_table_in_gives_the_pandas_result():
    df = reports()
    want = geofeas.associate(df)
    got = ga.associate(pa.Table.from_pandas(df))
    pd.testing.assert_frame_equal(got.pairs, want.pairs)
    pd.testing.assert_frame_equal(got.objects, want.objects)
    batch = pa.Table.from_pandas(df, preserve_index=False).combine_chunks().to_batches()[0]
    pd.testing.assert_frame_equal(ga.associate(batch).pairs, want.pairs)


def test_dictionary_columns_and_timestamps_read_as_values(tmp_path):
    df = reports()
    table = pa.Table.from_pandas(df, preserve_index=False)
    # ids dictionary-encoded (what Parquet writers do for repeated strings), times as timestamps
    table = table.set_column(0, "track_id", table.column("track_id").dictionary_encode())
    table = table.set_column(1, "source", table.column("source").dictionary_encode())
    stamps = pa.array((df["time"].to_numpy() * 1e6).astype("int64"), pa.timestamp("us", "UTC"))
    table = table.set_column(2, "time", stamps)
    path = tmp_path / "reports.parquet"
    pq.write_table(table, path)
    # the pandas path on the same values: ids as strings, times as a datetime64 column
    want = geofeas.associate(df.assign(time=pd.to_datetime(stamps.to_numpy(), utc=True)))
    for source in (table, path):
        rep = ga.read_reports(source)
        np.testing.assert_allclose(rep.time, df["time"].to_numpy(), rtol=0, atol=1e-6)
        got = ga.associate(source)
        pd.testing.assert_frame_equal(got.pairs, want.pairs, check_exact=True)
        pd.testing.assert_frame_equal(got.objects, want.objects)


def test_results_out_as_arrow_and_parquet(tmp_path):
    df = reports(twin=20.0)
    result = geofeas.associate(df)
    classes = set(result.pairs["class"])
    assert {"match", "non-match", "borderline"} <= classes
    pairs = ga.pairs_table(result)
    assert pairs.column_names == list(result.pairs.columns)
    # the file contract first, then the posterior and the model's details
    assert pairs.column_names[:7] == [
        "track_a",
        "track_b",
        "score",
        "instants",
        "class",
        "p_same",
        "review_rank",
    ]
    for name in ("llr", "std_error", "review_gain", "settles_same", "settles_different"):
        assert name in pairs.column_names
    assert pairs.num_rows == len(result.pairs)
    for name in ("score", "p_same", "llr", "std_error", "review_gain"):
        assert pairs.schema.field(name).type == pa.float64()
        np.testing.assert_array_equal(pairs.column(name).to_numpy(), result.pairs[name])
    for name in ("review_rank", "component", "settles_same", "settles_different", "instants"):
        assert pa.types.is_integer(pairs.schema.field(name).type), name
    # review_rank: null exactly for the pairs that are not borderline, never 0 or NaN
    rank = pairs.column("review_rank")
    borderline = (result.pairs["class"] == "borderline").to_numpy()
    assert rank.null_count == int((~borderline).sum()) > 0
    got = np.array(rank.to_pylist(), dtype=object)
    assert sorted(got[borderline].tolist()) == list(range(1, int(borderline.sum()) + 1))
    objects = ga.objects_table(result)
    assert objects.column_names == ["track_id", "object", "source", "p_alone"]
    np.testing.assert_array_equal(objects.column("p_alone").to_numpy(), result.objects["p_alone"])

    ga.write_parquet(result, tmp_path / "out")
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [
        "objects.parquet",
        "pairs.parquet",
    ]  # no temporary file left behind
    raw = pq.read_table(tmp_path / "out" / "pairs.parquet")
    assert raw.schema.field("review_rank").type == pairs.schema.field("review_rank").type
    assert raw.column("review_rank").null_count == rank.null_count
    back = raw.to_pandas()
    pd.testing.assert_frame_equal(back, result.pairs, check_exact=True)
    objects = pq.read_table(tmp_path / "out" / "objects.parquet").to_pandas()
    pd.testing.assert_frame_equal(objects, result.objects, check_exact=True)


def test_decisions_as_an_arrow_table():
    df = reports()
    base = geofeas.associate(df)
    m = base.matches
    decided = pd.DataFrame(
        {"track_a": [m["track_a"][0]], "track_b": [m["track_b"][0]], "decision": ["different"]}
    )
    want = geofeas.associate(df, decisions=decided)
    got = ga.associate(pa.Table.from_pandas(df), decisions=pa.Table.from_pandas(decided))
    pd.testing.assert_frame_equal(got.pairs, want.pairs, check_exact=True)
    p = got.pairs.set_index(["track_a", "track_b"])["p_same"]
    assert p[(m["track_a"][0], m["track_b"][0])] == 0.0


def test_bad_arrow_input_raises_geofeas_error(tmp_path):
    with pytest.raises(geofeas.GeofeasError, match="pyarrow Table"):
        ga.read_reports([1, 2, 3])
    (tmp_path / "junk.parquet").write_text("not parquet")
    with pytest.raises(geofeas.GeofeasError, match="junk.parquet"):
        ga.read_reports(tmp_path / "junk.parquet")
    df = reports()
    df.loc[3, "rx"] = -2.0
    with pytest.raises(geofeas.GeofeasError, match="row 3: column rx"):
        ga.read_reports(pa.Table.from_pandas(df))
