"""The `geofeas score` command on the bundled example and on malformed files."""

import argparse
import csv
import subprocess
import sys

import numpy as np
import pytest

import geofeas
from geofeas.cli import main


def test_score_example(tmp_path):
    out = tmp_path / "scored.csv"
    assert main(["score", "example", "--out", str(out)]) == 0
    rows = list(csv.DictReader(open(out)))
    assert len(rows) > 100
    assert {"glr", "glr_threshold", "overlap", "monte_carlo", "truth"} <= set(rows[0])
    same = np.array([float(r["overlap"]) for r in rows if r["truth"] == "same"])
    other = np.array([float(r["overlap"]) for r in rows if r["truth"] != "same"])
    assert np.median(same) > np.median(other)
    a = np.array([[float(r[f"a_{f}"]) for f in ("x0", "y0", "rx", "ry", "phi")] for r in rows])
    b = np.array([[float(r[f"b_{f}"]) for f in ("x0", "y0", "rx", "ry", "phi")] for r in rows])
    np.testing.assert_array_equal([float(r["glr"]) for r in rows], geofeas.glr(a, b))


def test_entry_point_runs():
    r = subprocess.run(
        [sys.executable, "-m", "geofeas.cli", "score", "example", "--score", "glr"],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0 and r.stdout.startswith("track_a,track_b")


@pytest.mark.parametrize(
    "body, message",
    [
        ("a_x0,a_y0\n1,2\n", "missing column"),
        (
            "a_x0,a_y0,a_rx,a_ry,a_phi,b_x0,b_y0,b_rx,b_ry,b_phi\n0,0,1,1,0,1,1,1,1,0\n0,0,1,x,0,1,1,1,1,0\n",
            "line 3: column a_ry",
        ),
        (
            "a_x0,a_y0,a_rx,a_ry,a_phi,b_x0,b_y0,b_rx,b_ry,b_phi\n0,0,1,1,0,1,1,-1,1,0\n",
            "line 2: column b_rx",
        ),
        (
            "a_x0,a_y0,a_rx,a_ry,a_phi,b_x0,b_y0,b_rx,b_ry,b_phi\n0,0,1,1,nan,1,1,1,1,0\n",
            "line 2: column a_phi",
        ),
        (
            "a_x0,a_y0,a_rx,a_ry,a_phi,b_x0,b_y0,b_rx,b_ry,b_phi\n0,0,1,1,0,1,1,1\n",
            "line 2: 8 fields",
        ),
        ("", "empty file"),
    ],
)
def test_malformed_files_name_the_line(tmp_path, capsys, body, message):
    src = tmp_path / "bad.csv"
    src.write_text(body)
    assert main(["score", str(src), "--out", str(tmp_path / "o.csv")]) == 2
    assert message in capsys.readouterr().err


# --------------------------------------------------------------------------- geofeas associate


def harbour(tmp_path):
    """Six ships seen by AIS (10 m) and radar (45 m, 1 sigma); ship 1 sails 20 m beside ship 0, so
    that the radar cannot tell them apart. Written as CSV with ISO times; returns the path."""
    pd = pytest.importorskip("pandas")
    rng = np.random.default_rng(11)
    frames = []
    start = rng.uniform(0, 3_000, (6, 2))
    start[1] = start[0] + [20.0, 0.0]
    velocity = rng.uniform(-5, 5, (6, 2))
    velocity[1] = velocity[0]
    for i in range(6):
        for source, step, r in (("ais", 30.0, 20.0), ("radar", 10.0, 90.0)):
            t = np.arange(0.0, 900.0, step) + rng.uniform(0, step)
            xy = start[i] + velocity[i] * t[:, None] + rng.normal(0, r / 2, (t.size, 2))
            frames.append(
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
    frame = pd.concat(frames, ignore_index=True)
    frame["time"] = (
        pd.Timestamp("2024-05-01T10:00:00Z") + pd.to_timedelta(frame["time"], unit="s")
    ).dt.strftime("%Y-%m-%dT%H:%M:%S.%fZ")
    path = tmp_path / "reports.csv"
    frame.to_csv(path, index=False)
    return path


def test_associate_writes_the_file_contract(tmp_path):
    pd = pytest.importorskip("pandas")
    src = harbour(tmp_path)
    out, objects = tmp_path / "pairs.csv", tmp_path / "objects.csv"
    assert main(["associate", str(src), "--out", str(out), "--objects", str(objects), "-q"]) == 0
    pairs = pd.read_csv(out, dtype={"track_a": str, "track_b": str})
    assert list(pairs.columns) == [
        "track_a",
        "track_b",
        "score",
        "instants",
        "class",
        "p_same",
        "review_rank",
    ]
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "objects.csv",
        "pairs.csv",
        "reports.csv",
    ]  # written through temporary files, none left behind
    api = geofeas.associate(src)
    np.testing.assert_array_equal(pairs["p_same"], api.pairs["p_same"])
    np.testing.assert_array_equal(pairs["class"], api.pairs["class"])
    assert set(pairs["class"]) == {"match", "borderline", "non-match"}
    # the classes follow p_same and the default error rates
    assert (pairs.loc[pairs["class"] == "non-match", "p_same"] <= 0.01).all()
    assert (pairs.loc[pairs["class"] == "match", "p_same"] >= 0.99).all()
    between = pairs["p_same"].between(0.01, 0.99, inclusive="neither")
    assert (pairs.loc[between, "class"] == "borderline").all()
    # review_rank: 1, 2, ... for the borderline pairs, empty for the others
    borderline = pairs["class"] == "borderline"
    assert pairs.loc[~borderline, "review_rank"].isna().all()
    ranks = sorted(pairs.loc[borderline, "review_rank"].astype(int))
    assert ranks == list(range(1, int(borderline.sum()) + 1))
    obj = pd.read_csv(objects)
    assert list(obj.columns) == ["track_id", "object", "source", "p_alone"]
    assert obj["p_alone"].between(0, 1).all()


def test_associate_decisions_flag_reads_and_never_writes(tmp_path, capsys):
    pd = pytest.importorskip("pandas")
    src = harbour(tmp_path)
    base = geofeas.associate(src)
    first = base.review_queue.iloc[0]
    decisions = tmp_path / "decisions.csv"
    decisions.write_text(
        "track_a,track_b,decision,operator,time\n"
        f"{first.track_a},{first.track_b},same,watch officer,2024-05-01T10:20:00Z\n"
    )
    before = decisions.read_bytes()
    out = tmp_path / "pairs.csv"
    assert main(["associate", str(src), "--out", str(out), "--decisions", str(decisions)]) == 0
    assert decisions.read_bytes() == before
    pairs = pd.read_csv(out).set_index(["track_a", "track_b"])
    assert pairs.loc[(first.track_a, first.track_b), "p_same"] > 1.0 - 1e-12
    assert pairs.loc[(first.track_a, first.track_b), "class"] == "match"
    want = geofeas.associate(src, decisions=decisions).pairs
    np.testing.assert_array_equal(pairs["p_same"], want["p_same"])
    capsys.readouterr()
    # contradictory decisions: refused, naming them, and nothing written
    other = next(t for t in base.objects["track_id"] if t not in (first.track_a, first.track_b))
    decisions.write_text(
        "track_a,track_b,decision\n"
        f"{first.track_a},{first.track_b},same\n"
        f"{first.track_b},{other},same\n"
        f"{first.track_a},{other},different\n"
    )
    bad_out = tmp_path / "never.csv"
    assert main(["associate", str(src), "--out", str(bad_out), "--decisions", str(decisions)]) == 2
    err = capsys.readouterr().err
    assert f"line 4 ({first.track_a} different {other})" in err and not bad_out.exists()


def test_associate_model_flags_are_the_api_options(tmp_path, capsys):
    pd = pytest.importorskip("pandas")
    src = harbour(tmp_path)
    out = tmp_path / "pairs.csv"
    flags = ["--p-match", "0.9", "--p-reject", "0.2", "--completeness", "0.7"]
    flags += ["--false-tracks", "0.3", "--details", "-q"]
    assert main(["associate", str(src), "--out", str(out), *flags]) == 0
    got = pd.read_csv(out, keep_default_na=True)
    want = geofeas.associate(src, p_match=0.9, p_reject=0.2, completeness=0.7, false_tracks=0.3)
    assert list(got.columns) == list(want.pairs.columns)  # --details: every column
    np.testing.assert_array_equal(got["p_same"], want.pairs["p_same"])
    np.testing.assert_array_equal(got["llr"], want.pairs["llr"])
    np.testing.assert_array_equal(got["class"], want.pairs["class"])
    default = geofeas.associate(src).pairs
    assert not np.array_equal(got["p_same"], default["p_same"])  # the flags were at work
    for flag, value, name in (
        ("--p-match", "0.3", "p_match"),
        ("--p-reject", "0.7", "p_reject"),
        ("--completeness", "1.5", "completeness"),
        ("--false-tracks", "1.0", "false_tracks"),
    ):
        assert main(["associate", str(src), "--out", str(out), flag, value]) == 2
        assert name in capsys.readouterr().err


def test_associate_flags_removed_with_the_rules(tmp_path, capsys):
    src = harbour(tmp_path)
    for flag in ("--lower", "--upper", "--margin"):
        with pytest.raises(SystemExit):
            main(["associate", str(src), "--out", str(tmp_path / "o.csv"), flag, "0.5"])
        assert flag in capsys.readouterr().err


def test_help_texts_are_plain_text():
    from geofeas.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for name, command in sub.choices.items():
        text = command.format_help()
        assert "``" not in text and ":func:" not in text, name
        assert "seed 00" not in text, name
