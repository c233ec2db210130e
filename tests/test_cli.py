"""The `geofeas score` command on the bundled example and on malformed files."""

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
