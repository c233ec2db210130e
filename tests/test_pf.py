"""Boundary and cross-checks of the particle-filter focal-plane tracker (seed 003).

The NumPy references (``tests/pf_reference.py``) are written from the paper's equations, not
from the Rust code.
"""

from __future__ import annotations

import csv

import numpy as np
import pytest
from pf_reference import log_likelihood_ratio, render, track_method2

import geofeas
from geofeas import GeofeasError
from geofeas.cli import main
from geofeas.tracking import (
    PAPER_IC,
    pf_ellipses,
    pf_log_weights,
    pf_peaks,
    pf_render,
    pf_simulate_run,
    pf_study,
    pf_track,
)


@pytest.mark.parametrize(
    ("amplitude", "blur", "sigma", "half_box"),
    [(0.8, 3.0, 0.25, 10), (1.0, 2.0, 0.1, 10), (0.5, 0.7, 1.0, 3), (1.3, 1.5, 0.4, 0)],
)
def test_method2_weights_equal_numpy(rng, amplitude, blur, sigma, half_box):
    z = render(np.array([[20.3, 14.8], [40.0, 30.0]]), 57, 41, 1.0, 2.0, 0.3, rng)
    # particles everywhere, including off the frame and on its borders
    xy = np.column_stack([rng.uniform(-15, 72, 600), rng.uniform(-15, 56, 600)])
    xy[:5] = [[0, 0], [56, 40], [28.5, 20.5], [-10.6, 3], [70.0, 50.0]]
    got = pf_log_weights(z, xy, amplitude=amplitude, blur=blur, sigma=sigma, half_box=half_box)
    want = log_likelihood_ratio(z, xy[:, 0], xy[:, 1], amplitude, blur, sigma, half_box)
    np.testing.assert_allclose(got, want, rtol=1e-11, atol=1e-9)


def test_method2_weights_peak_at_the_target():
    z = render(np.array([[30.0, 30.0]]), 64, 64, 1.0, 2.0, 0.0, np.random.default_rng(0))
    g = np.linspace(27, 33, 61)
    xy = np.array([[x, 30.0] for x in g])
    w = pf_log_weights(z, xy, amplitude=0.8, blur=3.0, sigma=0.1)
    assert abs(g[np.argmax(w)] - 30.0) < 0.11


def test_simulator_noise_and_psf():
    sigma = 10 ** (-6 / 20)
    noise = pf_render(np.empty((0, 2)), sigma=sigma, seed=3)
    assert noise.shape == (256, 256)
    n = noise.size
    # sample sd within 4 of its standard errors (sd / sqrt(2n)), mean within 4 / sqrt(n)
    assert abs(noise.std(ddof=1) / sigma - 1) < 4 / np.sqrt(2 * n)
    assert abs(noise.mean()) < 4 * sigma / np.sqrt(n)
    # lag-1 correlation of white noise ~ N(0, 1/n)
    c = np.corrcoef(noise[:, :-1].ravel(), noise[:, 1:].ravel())[0, 1]
    assert abs(c) < 4 / np.sqrt(n)
    clean = pf_render(np.array([[100.3, 50.7]]), width=200, height=120, blur=2.0, sigma=0.0)
    jj, ii = np.mgrid[0:120, 0:200]
    want = np.exp(-((ii - 100.3) ** 2 + (jj - 50.7) ** 2) / 8.0)
    want[np.hypot(ii - 100.3, jj - 50.7) > 16] = 0.0  # truncated at 8 Sigma (< e^-32)
    np.testing.assert_allclose(clean, want, atol=1e-13)


def test_simulated_frames_have_the_claimed_sigma():
    r = pf_simulate_run(snr_db=9.0, particles=50, keep_frames=[0, 50])
    assert r["sigma_z"] == pytest.approx(10 ** (-9 / 20))
    # far from every target the frame is pure noise
    corner = r["frames"][:, :10, 120:136]
    assert abs(corner.std() / r["sigma_z"] - 1) < 0.1


def test_peaks_match_numpy_local_maxima(rng):
    z = rng.standard_normal((40, 50))
    got = pf_peaks(z, count=6, min_separation=0.0)
    pad = np.pad(z, 1, constant_values=-np.inf)
    nb = np.stack(
        [pad[1 + dj : 41 + dj, 1 + di : 51 + di] for dj in (-1, 0, 1) for di in (-1, 0, 1)]
    )
    is_max = z >= nb.max(axis=0)
    vals = np.sort(z[is_max])[::-1][:6]
    np.testing.assert_allclose(got[:, 2], vals)
    for x, y, v in got:
        assert z[int(y), int(x)] == v


def test_high_snr_tracks_all_four_targets_sub_pixel():
    r = pf_simulate_run(snr_db=15.0, method=2, particles=3000, seed=5)
    err = np.hypot(*(r["estimates"][:, :, :2] - r["truth"][:, :, :2]).transpose(2, 0, 1))
    rmse = np.sqrt((err**2).mean(axis=0))
    assert (rmse < 1.0).all(), rmse
    assert (r["pca"] > 0.9).all()
    e = pf_ellipses(r)
    assert e.shape == (4, 5)
    np.testing.assert_allclose(e[:, :2], r["estimates"][-1, :, :2])
    # a 2-sigma circle-ish AOU: rx^2 + ry^2 = 4 (Pxx + Pyy)
    cov = r["covariances"][-1]
    np.testing.assert_allclose(e[:, 2] ** 2 + e[:, 3] ** 2, 4 * (cov[:, 0, 0] + cov[:, 1, 1]))
    s = geofeas.glr(e, e)
    assert np.all(s > 0.99)


def test_two_sigma_bounds_cover_the_errors():
    # exact model (NCV truth, matched measurement model): ~95.4% of errors inside 2 sigma
    res = pf_study(
        runs=8,
        particles=1500,
        snrs=[6.0],
        ic=np.empty((0, 2)),
        truth="ncv",
        model_factors=(1.0, 1.0, 1.0),
        seed=2,
    )
    cov = res["coverage"]
    assert cov.shape == (2,)
    assert 0.90 <= cov[1] <= 0.99, cov


def test_seeded_runs_are_reproducible():
    kw = {"snr_db": 6.0, "particles": 400, "seed": 9}
    a, b = pf_simulate_run(**kw), pf_simulate_run(**kw)
    for k in ("estimates", "covariances", "peaks", "peak", "correct"):
        np.testing.assert_array_equal(a[k], b[k])
    c = pf_simulate_run(**{**kw, "seed": 10})
    assert not np.array_equal(a["estimates"], c["estimates"])
    # same truth for both methods and every SNR of a run
    d = pf_simulate_run(snr_db=0.0, method=1, particles=50, seed=9)
    np.testing.assert_array_equal(a["truth"], d["truth"])


def test_track_user_frames_matches_the_numpy_filter():
    rng = np.random.default_rng(4)
    sigma = 10 ** (-10 / 20)
    pos0 = np.array([[30.0, 30.0, 8.0, 4.0], [80.0, 60.0, -6.0, 2.0]])
    frames = np.stack(
        [
            render(pos0[:, :2] + k * 0.1 * pos0[:, 2:], 120, 100, 1.0, 2.0, sigma, rng)
            for k in range(25)
        ]
    )
    ours = pf_track(frames, pos0, sigma_z=sigma, particles=2000, seed=1)
    ref = track_method2(frames, pos0, sigma_z=sigma, particles=2000, rng=np.random.default_rng(1))
    truth = pos0[None, :, :2] + 0.1 * np.arange(25)[:, None, None] * pos0[None, :, 2:]
    e_ours = np.hypot(*(ours["estimates"][:, :, :2] - truth).transpose(2, 0, 1))
    e_ref = np.hypot(*(ref["estimates"][:, :, :2] - truth).transpose(2, 0, 1))
    assert e_ours.mean() < 0.5 and e_ref.mean() < 0.5
    # two independent implementations of one Bayes filter: same posterior up to MC noise
    np.testing.assert_allclose(
        ours["estimates"][-5:, :, :2], ref["estimates"][-5:, :, :2], atol=0.3
    )
    sd_ours = np.sqrt(ours["covariances"][-5:, :, 0, 0])
    sd_ref = np.sqrt(ref["covariances"][-5:, :, 0, 0])
    np.testing.assert_allclose(sd_ours.mean(), sd_ref.mean(), rtol=0.25)


def test_association_variants_and_methods():
    a = pf_simulate_run(snr_db=3.0, method=1, particles=300, association="nearest")
    b = pf_simulate_run(snr_db=3.0, method=1, particles=300, association="one-to-one")
    taken = b["peak"]
    for row in taken:
        used = row[row >= 0]
        assert len(used) == len(set(used.tolist()))
    assert a["peak"].shape == taken.shape == (101, 4)


def test_bad_input_raises():
    z = np.zeros((20, 20))
    with pytest.raises(GeofeasError, match="xy row 1"):
        pf_log_weights(z, [[1.0, 1.0], [np.nan, 2.0]], amplitude=1, blur=1, sigma=1)
    with pytest.raises(GeofeasError, match="shape"):
        pf_log_weights(z, [[1.0, 1.0, 1.0]], amplitude=1, blur=1, sigma=1)
    with pytest.raises(GeofeasError, match="blur"):
        pf_log_weights(z, [[1.0, 1.0]], amplitude=1, blur=0, sigma=1)
    bad = np.zeros((3, 10, 10))
    bad[2, 4, 7] = np.inf
    with pytest.raises(GeofeasError, match="frame 2 row 4 column 7"):
        pf_track(bad, [[5, 5, 0, 0]], sigma_z=0.1)
    with pytest.raises(GeofeasError, match="init"):
        pf_track(np.zeros((3, 10, 10)), [[5, 5, 0]], sigma_z=0.1)
    with pytest.raises(GeofeasError, match="initial state row 0"):
        pf_track(np.zeros((3, 10, 10)), [[5, np.nan, 0, 0]], sigma_z=0.1)
    with pytest.raises(GeofeasError, match="sigma_z"):
        pf_track(np.zeros((3, 10, 10)), [[5, 5, 0, 0]], sigma_z=-1)
    with pytest.raises(GeofeasError, match="method"):
        pf_simulate_run(method=3)
    with pytest.raises(GeofeasError, match="association"):
        pf_simulate_run(association="greedy", particles=10)
    with pytest.raises(GeofeasError, match="resampling"):
        pf_simulate_run(resampling="none", particles=10)
    with pytest.raises(GeofeasError, match="particles"):
        pf_simulate_run(particles=0)
    with pytest.raises(GeofeasError, match="snr_db"):
        pf_simulate_run(snr_db=float("nan"))
    with pytest.raises(GeofeasError, match="keep_frames"):
        pf_simulate_run(particles=10, keep_frames=[101])
    with pytest.raises(GeofeasError, match="truth"):
        pf_simulate_run(particles=10, truth="spline")
    with pytest.raises(GeofeasError, match="runs"):
        pf_study(runs=0)
    with pytest.raises(GeofeasError, match="ic"):
        pf_study(ic=[[1.0, 2.0, 3.0]])
    with pytest.raises(GeofeasError, match="frame"):
        pf_peaks(np.zeros(5))


def test_resampling_schemes_all_track():
    for scheme in ("systematic", "stratified", "multinomial", "residual"):
        r = pf_simulate_run(snr_db=15.0, particles=800, resampling=scheme, seed=3)
        err = np.hypot(*(r["estimates"][-20:, :, :2] - r["truth"][-20:, :, :2]).transpose(2, 0, 1))
        assert err.mean() < 1.0, scheme


def test_cli_writes_the_contract_files(tmp_path):
    out = tmp_path / "pf"
    snrs = (2.0, 6.0, 15.0)
    args = ["pf-study", "--out", str(out), "--runs", "2", "--particles", "200", "--no-figures"]
    assert main(args + ["--snrs", "2,6,15"]) == 0
    configs = ("paper", "recommended")
    with open(out / "pca_vs_snr.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == ["config", "method", "snr_db", "pca", "pca_lo", "pca_hi"]
    # Every bootstrap interval brackets its estimate.
    assert all(
        float(r["pca_lo"]) <= float(r["pca"]) + 1e-12 <= float(r["pca_hi"]) + 2e-12 for r in rows
    )
    assert sorted((r["config"], r["method"], float(r["snr_db"])) for r in rows) == sorted(
        (c, m, s) for c in configs for m in ("1", "2") for s in snrs
    )
    assert all(0.0 <= float(r["pca"]) <= 1.0 for r in rows)
    # The recommended configuration's matched-filter peaks find the targets at 6 dB, the raw
    # intensity maxima do not (Method 2 here, the same frames).
    pca = {(r["config"], r["method"], float(r["snr_db"])): float(r["pca"]) for r in rows}
    assert pca["recommended", "2", 6.0] > pca["paper", "2", 6.0] + 0.2
    with open(out / "errors.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == ["config", "method", "snr_db", "filter", "rmse_px"]
    assert {(r["config"], r["method"], float(r["snr_db"]), r["filter"]) for r in rows} == {
        (c, m, s, f) for c in configs for m in ("1", "2") for s in snrs for f in "1234"
    }
    text = (out / "comparison.md").read_text()
    assert text.count("|") > 50
    assert "## Configuration `paper`" in text and "## Configuration `recommended`" in text
    with open(out / "summary.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0])[:6] == ["config", "method", "snr_db", "xmax", "vmax", "runs"]
    assert {"held", "held_lo", "held_hi", "rmse_px_lo", "gospa", "id_switches"} <= set(rows[0])
    # GOSPA with four targets and four filters (c = 5, p = 2): between 0 and sqrt(4 c^2) = 10.
    assert all(0.0 <= float(r["gospa"]) <= 10.0 + 1e-9 for r in rows)
    assert {r["runs"] for r in rows} == {"2"}
    with open(out / "ic_sensitivity.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [(r["config"], float(r["xmax"]), float(r["vmax"])) for r in rows] == [
        (c, x, v) for c in configs for x, v in PAPER_IC
    ]
    assert not [p for p in out.iterdir() if p.name.startswith(".")]


def test_cli_configurations(tmp_path, capsys):
    base = ["pf-study", "--runs", "2", "--particles", "100", "--snrs", "15", "--no-figures"]
    # One configuration; an explicit setting that departs from it labels the rows "custom".
    assert main(base + ["--out", str(tmp_path / "a"), "--config", "recommended"]) == 0
    custom = ["--config", "paper", "--association", "one-to-one"]
    assert main(base + ["--out", str(tmp_path / "b")] + custom) == 0
    for sub, label in (("a", "recommended"), ("b", "custom")):
        with open(tmp_path / sub / "summary.csv", newline="") as fh:
            assert {r["config"] for r in csv.DictReader(fh)} == {label}
    # A setting cannot override both configurations at once.
    assert main(base + ["--out", str(tmp_path / "c"), "--association", "one-to-one"]) == 2
    assert "--config paper or --config recommended" in capsys.readouterr().err
    assert not (tmp_path / "c").exists()
    with pytest.raises(SystemExit):
        main(base + ["--out", str(tmp_path / "d"), "--snrs", "2,x"])


def test_resampling_threshold():
    # never resampling degenerates the weights; the default resamples every frame
    never = pf_simulate_run(snr_db=15.0, particles=500, resample_threshold=0.0, seed=1)
    always = pf_simulate_run(snr_db=15.0, particles=500, seed=1)
    assert never["ess"][-10:].max() < 5.0
    assert always["ess"][-10:].min() > 20.0
    half = pf_simulate_run(snr_db=15.0, particles=500, resample_threshold=0.5, seed=1)
    assert np.isfinite(half["estimates"]).all()


def test_simulated_run_is_the_user_frame_loop_on_its_frames():
    # One frame loop in the core serves both entry points: tracking the simulated frames with
    # the run's filter seed and true initial states reproduces the simulated run bit for bit.
    kw = {"particles": 120, "association": "one-to-one", "smoothing": 2.0, "r1": 1.5}
    for method in (1, 2):
        run = pf_simulate_run(
            snr_db=6.0, method=method, seed=3, run=2, keep_frames=range(101), **kw
        )
        user = pf_track(
            run["frames"],
            run["truth"][0, :, :4],
            sigma_z=run["sigma_z"],
            method=method,
            seed=run["filter_seed"],
            **kw,
        )
        for k in ("estimates", "covariances", "peaks", "peak", "distances", "residuals", "ess"):
            np.testing.assert_array_equal(run[k], user[k], err_msg=k)
        other = pf_track(
            run["frames"],
            run["truth"][0, :, :4],
            sigma_z=run["sigma_z"],
            method=method,
            seed=run["filter_seed"] + 1,
            **kw,
        )
        assert not np.array_equal(run["estimates"], other["estimates"])
