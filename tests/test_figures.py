"""`geofeas figures` in its quick form: files written, and the CSV's numbers checked against the
exact values they stand for."""

import csv
import json

import numpy as np
import pytest

import geofeas
from geofeas.cli import main

import reference as ref

pytest.importorskip("matplotlib")


def test_figures_quick(tmp_path):
    out = tmp_path / "figs"
    assert main(["figures", "--out", str(out), "--quick"]) == 0
    for k in range(2, 7):
        assert (out / f"fig{k}.png").stat().st_size > 10_000
    rows = list(csv.DictReader(open(out / "figures.csv")))
    summary = json.loads((out / "summary.json").read_text())
    by = {}
    for r in rows:
        by.setdefault((int(r["figure"]), r["series"]), []).append(
            (float(r["x"]), float(r["y"]), float(r["spread"]))
        )
    # Fig. 2: the exact series is the circle lens; every Monte-Carlo mean is within 4 standard
    # errors of it
    exact = np.array(by[(2, "exact")])
    d = np.linspace(0.0, 2.0, 21)
    lens = np.array([ref.circle_lens_area(1.0, 1.0, x) / np.pi for x in d])
    np.testing.assert_allclose(exact[:, 1], lens, atol=1e-14)
    for series in ("importance_500", "uniform_500", "sobol_64"):
        mc = np.array(by[(2, series)])
        np.testing.assert_allclose(mc[:, 0], lens, atol=1e-14)
        se = mc[:, 2] / np.sqrt(summary["trials"])
        assert np.all(np.abs(mc[:, 1] - lens) <= 4 * se + 2e-3)
    # Fig. 5 at the exact overlap 0.391; doubling N gives about -3 dB for plain Monte-Carlo
    assert summary["fig5_overlap"] == pytest.approx(0.391, abs=1e-12)
    assert -3.8 < summary["fig5_db_per_doubling"]["importance"] < -2.2
    assert summary["fig5_db_per_doubling"]["sobol"] < -3.5
    # Fig. 6: the exact series equals geofeas.overlap of the same pairs, sorted by the
    # Monte-Carlo estimate
    ex = np.array(by[(6, "exact")])[:, 1]
    mc = np.array(by[(6, "monte_carlo_1000")])[:, 1]
    assert np.all(np.diff(mc) >= 0)
    assert np.abs(mc - ex).max() < 0.1
    assert len(ex) == summary["pairs"]
    assert summary["fig2_max_abs_exact_minus_lens"] < 1e-14


def test_figures_csv_only_and_bad_option(tmp_path, capsys):
    assert main(["figures", "--out", str(tmp_path), "--csv-only", "--trials", "1"]) == 2
    assert "--trials" in capsys.readouterr().err


def test_score_cli_offers_new_scores(tmp_path):
    out = tmp_path / "s.csv"
    args = [
        "score",
        "example",
        "--out",
        str(out),
        "--score",
        "overlap",
        "--score",
        "overlap_polygon",
        "--score",
        "bhattacharyya",
        "--score",
        "monte_carlo",
        "--sampler",
        "sobol",
        "--samples",
        "64",
    ]
    assert main(args) == 0
    rows = list(csv.DictReader(open(out)))
    g = np.array([float(r["overlap"]) for r in rows])
    p = np.array([float(r["overlap_polygon"]) for r in rows])
    assert np.abs(g - p).max() < 1e-3
    a = np.array([[float(r[f"a_{f}"]) for f in ("x0", "y0", "rx", "ry", "phi")] for r in rows])
    b = np.array([[float(r[f"b_{f}"]) for f in ("x0", "y0", "rx", "ry", "phi")] for r in rows])
    np.testing.assert_array_equal(g, geofeas.overlap(a, b))
    np.testing.assert_array_equal(
        [float(r["bhattacharyya"]) for r in rows], geofeas.bhattacharyya(a, b)
    )
