"""Particle-filter tracking of multiple objects on a focal-plane image (seed 003).

Thin wrappers over the Rust core (``geofeas._core.pf_*``), after Ohlmeyer and Menon, *Comparison
of Two Particle Filter Methods for Image Plane Tracking of Multiple Objects*:

- :func:`pf_simulate_run`: one seeded run of the paper's four-target, 256 x 256 scenario at a
  given SNR, tracked by a bank of particle filters with Method 1 (distance to the associated
  intensity peak) or Method 2 (track-before-detect likelihood ratio).
- :func:`pf_track`: the same bank of filters on frames you provide.
- :func:`pf_study`: the Monte-Carlo reproduction of Figs. 7-20 (errors, probability of correct
  association against SNR, initial-condition sensitivity).
- :func:`pf_log_weights`, :func:`pf_peaks`, :func:`pf_render`: the Method-2 weights, the peak
  extraction and the frame simulator on their own.
- :func:`pf_ellipses`: the filters' 2-sigma position AOUs ``(x0, y0, rx, ry, phi)``, ready for
  the geofeasibility scores (:func:`geofeas.glr`, :func:`geofeas.cdist`, ...).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._arrays import as_float_array
from .._atomic import save_figure
from .._core import GeofeasError
from ..scores import from_gaussian

__all__ = [
    "OPTIONS",
    "PAPER_IC",
    "PF_CONFIGS",
    "PAPER_PCA",
    "pf_ellipses",
    "pf_log_weights",
    "pf_peaks",
    "pf_render",
    "pf_simulate_run",
    "pf_study",
    "pf_track",
    "plot_pf_run",
]

#: The paper's probability of correct association for Method 2 (section V and Fig. 19):
#: SNR [dB] -> PCA (averaged over the interval and the four filters).
PAPER_PCA: dict[float, float] = {0.0: 0.27, 2.0: 0.275, 6.0: 0.307, 9.0: 0.50, 15.0: 1.0}

#: ``(xmax, vmax)`` rows of the initial-condition study (Fig. 20; the paper finds tracking
#: acceptable up to about 7-10 pixels and 1.5-2 pixels/s at 2 dB).
PAPER_IC: tuple[tuple[float, float], ...] = (
    (3.0, 0.5),
    (5.0, 1.0),
    (7.0, 1.5),
    (10.0, 2.0),
    (15.0, 3.0),
    (20.0, 4.0),
    (30.0, 6.0),
    (40.0, 8.0),
)


#: The two configurations of the study (``geofeas pf-study --config``), as keyword arguments of
#: :func:`pf_study` / :func:`pf_simulate_run`. ``paper``: the paper's filters, its nearest-distance
#: association and peaks at the raw frame's intensity maxima. ``recommended``: the same filters and
#: association, with peaks taken after smoothing the frame by the point spread (``smoothing`` =
#: its ``Sigma`` = 2 px, the matched filter, 11 dB of SNR gain), which rescues Method 1 and the
#: association down to ~3 dB; a one-to-one association was tried and not kept (it hands a Method-1
#: filter its neighbour's peak at the crossings, 0.6 px instead of 0.3 px at 15-20 dB).
PF_CONFIGS: dict[str, dict[str, Any]] = {
    "paper": {"association": "nearest", "smoothing": 0.0},
    "recommended": {"association": "nearest", "smoothing": 2.0},
}


def _int(value: Any, name: str, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise GeofeasError(f"{name}: expected an integer, got {value!r}")
    if value < minimum:
        raise GeofeasError(f"{name}: must be >= {minimum}, got {value}")
    return int(value)


def _float(value: Any, name: str) -> float:
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise GeofeasError(f"{name}: expected a number, got {value!r}") from None
    if not np.isfinite(out):
        raise GeofeasError(f"{name}: must be finite, got {value!r}")
    return out


#: The option sets of the particle filter as declared once in the Rust core
#: (``geofeas._core.pf_options()``): ``filter`` (the bank of filters, every entry point), ``run``
#: (:func:`pf_simulate_run`), ``track`` (:func:`pf_track`) and ``study`` (:func:`pf_study`), each
#: a list of ``(name, kind, default, doc, choices)``. The signatures below take their defaults
#: from it, and a test checks them, the stubs, the ``pf-study`` flags and the docs table against it.
OPTIONS: dict[str, list[tuple[str, str, Any, str, tuple[str, ...]]]] = _core.pf_options()
_F, _R, _T, _S = ({o[0]: o[2] for o in OPTIONS[g]} for g in ("filter", "run", "track", "study"))


def _pick(groups: tuple[str, ...], arguments: dict[str, Any]) -> dict[str, Any]:
    """The arguments of a call that belong to the option sets ``groups``, for the core."""
    return {o[0]: arguments[o[0]] for g in groups for o in OPTIONS[g]}


def pf_simulate_run(
    *,
    snr_db: float = _R["snr_db"],
    method: Literal[1, 2] = _R["method"],
    seed: int = _R["seed"],
    run: int = _R["run"],
    truth: Literal["white", "jerk", "gauss-markov", "ncv"] = _R["truth"],
    particles: int = _F["particles"],
    association: Literal["nearest", "one-to-one"] = _F["association"],
    resampling: Literal["systematic", "stratified", "multinomial", "residual"] = _F["resampling"],
    resample_threshold: float = _F["resample_threshold"],
    peaks: int = _F["peaks"],
    min_separation: float = _F["min_separation"],
    smoothing: float = _F["smoothing"],
    xmax: float = _F["xmax"],
    vmax: float = _F["vmax"],
    sigma_w: float = _F["sigma_w"],
    r1: float = _F["r1"],
    model_factors: tuple[float, float, float] = _F["model_factors"],
    half_box: int = _F["half_box"],
    snapshot_frames: Sequence[int] = _R["snapshot_frames"],
    snapshot_particles: int = _R["snapshot_particles"],
    keep_frames: Sequence[int] = _R["keep_frames"],
) -> dict[str, Any]:
    """Simulates one run of the paper's scenario and tracks it with a bank of particle filters.

    Four targets cross a 256 x 256 focal plane for 10 s (101 frames at 0.1 s) with the Fig. 3
    truth model (``truth``: ``"white"`` accelerations of 1-sigma 0.5 / 1.0 pixels/s^2 drawn each
    step, the default; ``"jerk"`` random-walk accelerations driven by white jerk;
    ``"gauss-markov"``; ``"ncv"``, the filter's own model), seen through a Gaussian point
    spread (A = 1, blur 2 px) with white noise ``sigma_Z = 10^(-SNR/20)``. One filter per target
    is initialised uniformly within ``+-xmax`` pixels and ``+-vmax`` pixels/s of the truth.
    The run is a pure function of ``(seed, run)``: every SNR and both methods see the same
    truth, the same noise pattern and the same initial particles.

    Parameters
    ----------
    snr_db : float
        Signal-to-noise ratio in dB.
    method : {1, 2}
        1: weights ``exp(-(r / r1)^2)`` to the associated peak; 2: the likelihood ratio over the
        ``+-half_box`` cells about each particle, with the filter model ``model_factors`` x
        (A, blur, sigma_Z) (the paper: 0.8, 1.5, 1.5).
    particles : int
        Particles per filter (the paper: 10,000).
    association : {"nearest", "one-to-one"}
        The paper's weighted-nearest-neighbour rule (two filters may take one peak) or the
        minimum-total-distance assignment of distinct peaks.
    resampling : {"systematic", "stratified", "multinomial", "residual"}
        Scheme; ``resample_threshold`` resamples when ESS < threshold x N (1: every frame).
    peaks, min_separation, smoothing
        Peaks per frame (strongest local maxima at least ``min_separation`` px apart, after an
        optional Gaussian smoothing of that width; 0 = raw intensities as in the paper).
    sigma_w : float
        Filter process noise, pixels/s^2 (the paper: 0.5).
    snapshot_frames, snapshot_particles
        Frames at which ``snapshot_particles`` resampled particles per filter are returned.
    keep_frames
        Frames whose images are returned.

    Returns
    -------
    dict
        ``truth`` ``(F, 4, 8)`` (x, y, vx, vy, speed, heading, a_L, a_N), ``estimates``
        ``(F, 4, 4)`` and ``covariances`` ``(F, 4, 4, 4)`` (posterior mean and covariance of
        each filter), ``peaks`` ``(F, K, 3)`` (x, y, intensity; NaN rows when fewer),
        ``peak`` ``(F, 4)`` (peak taken, -1 none), ``distances`` ``(F, 4, K)`` (``R_i^j``),
        ``correct`` ``(F, 4)`` (the peak taken is nearest to the filter's own target),
        ``pca`` ``(4,)``, ``residuals`` ``(F, 4, 2)`` (Fig. 12 mean and sd), ``ess``,
        ``snapshots`` rows ``[frame, filter, x, y]``, ``frames`` ``(len(keep_frames), 256, 256)``,
        ``sigma_z``, ``dt``, ``times`` ``(F,)`` and ``filter_seed`` (the seed of the filters'
        particles: :func:`pf_track` with it on the run's frames reproduces the run exactly).
    """
    r = _core.pf_simulate_run(**_pick(("run", "filter"), locals()))
    out = _track_dict(r.track)
    out.update(
        truth=r.truth,
        correct=r.correct,
        snapshots=r.snapshots,
        frames=r.frames,
        sigma_z=r.sigma_z,
        dt=r.dt,
        filter_seed=r.filter_seed,
        pca=r.correct.mean(axis=0),
        times=np.arange(r.truth.shape[0]) * r.dt,
        method=int(method),
        snr_db=float(snr_db),
    )
    return out


def _track_dict(t: _core.PfTrack) -> dict[str, Any]:
    """The public dict of a bank's track."""
    return {
        "estimates": t.estimates,
        "covariances": t.covariances,
        "peaks": t.peaks,
        "peak": t.peak,
        "distances": t.distances,
        "residuals": t.residuals,
        "ess": t.ess,
    }


def pf_track(
    frames: ArrayLike,
    init: ArrayLike,
    /,
    *,
    sigma_z: float,
    method: Literal[1, 2] = _T["method"],
    amplitude: float = _T["amplitude"],
    blur: float = _T["blur"],
    dt: float = _T["dt"],
    seed: int = _T["seed"],
    particles: int = _F["particles"],
    association: Literal["nearest", "one-to-one"] = _F["association"],
    resampling: Literal["systematic", "stratified", "multinomial", "residual"] = _F["resampling"],
    resample_threshold: float = _F["resample_threshold"],
    peaks: int = _F["peaks"],
    min_separation: float = _F["min_separation"],
    smoothing: float = _F["smoothing"],
    xmax: float = _F["xmax"],
    vmax: float = _F["vmax"],
    sigma_w: float = _F["sigma_w"],
    r1: float = _F["r1"],
    model_factors: tuple[float, float, float] = _F["model_factors"],
    half_box: int = _F["half_box"],
) -> dict[str, Any]:
    """Tracks targets through frames with a bank of particle filters (one per row of ``init``).

    Parameters
    ----------
    frames : array_like, shape (F, H, W)
        Intensities; cell ``[k, j, i]`` is column ``i`` (x) and row ``j`` (y) of frame ``k``,
        cell centres at integer coordinates, frames ``dt`` seconds apart.
    init : array_like, shape (n, 4)
        ``x, y, vx, vy`` about which each filter's particles are drawn (``+-xmax``, ``+-vmax``).
    sigma_z, amplitude, blur : float
        The sensor's noise 1-sigma and point spread; Method 2's filter model is
        ``model_factors`` times ``(amplitude, blur, sigma_z)``.

    Other options are those of :func:`pf_simulate_run`.

    Returns
    -------
    dict
        ``estimates``, ``covariances``, ``peaks``, ``peak``, ``distances``, ``residuals`` and
        ``ess`` as in :func:`pf_simulate_run`.
    """
    options = _pick(("track", "filter"), locals())
    f = as_float_array(frames, "frames")
    if f.ndim != 3:
        raise GeofeasError(f"frames: expected shape (F, H, W), got {f.shape}")
    x0 = as_float_array(init, "init")
    if x0.ndim != 2 or x0.shape[1] != 4:
        raise GeofeasError(f"init: expected shape (n, 4) with columns x, y, vx, vy; got {x0.shape}")
    return _track_dict(_core.pf_track(f, x0, sigma_z=_float(sigma_z, "sigma_z"), **options))


def pf_log_weights(
    frame: ArrayLike,
    xy: ArrayLike,
    /,
    *,
    amplitude: float,
    blur: float,
    sigma: float,
    half_box: int = 10,
) -> NDArray[np.float64]:
    """Method 2 log weights ``sum_C -h (h - 2 z) / (2 sigma^2)`` of particles at ``xy``.

    ``C`` is the ``(2 half_box + 1)^2`` cells about each particle's cell (clipped to the
    frame) and ``h`` the point spread ``amplitude exp(-d^2 / (2 blur^2))``; computed in Rust
    with the separable point spread. ``frame`` is ``(H, W)``, ``xy`` ``(n, 2)``.
    """
    f = as_float_array(frame, "frame")
    if f.ndim != 2:
        raise GeofeasError(f"frame: expected shape (H, W), got {f.shape}")
    p = as_float_array(xy, "xy")
    if p.ndim != 2 or p.shape[1] != 2:
        raise GeofeasError(f"xy: expected shape (n, 2), got {p.shape}")
    out: NDArray[np.float64] = _core.pf_log_weights(
        f,
        p,
        amplitude=_float(amplitude, "amplitude"),
        blur=_float(blur, "blur"),
        sigma=_float(sigma, "sigma"),
        half_box=_int(half_box, "half_box", 0),
    )
    return out


def pf_peaks(
    frame: ArrayLike,
    /,
    *,
    count: int = 4,
    min_separation: float = 3.0,
    smoothing: float = 0.0,
) -> NDArray[np.float64]:
    """The ``count`` strongest 3 x 3 local maxima of ``frame`` ``(H, W)`` at least
    ``min_separation`` pixels apart, after an optional Gaussian smoothing of width
    ``smoothing``: rows ``[x, y, intensity]``, strongest first."""
    f = as_float_array(frame, "frame")
    if f.ndim != 2:
        raise GeofeasError(f"frame: expected shape (H, W), got {f.shape}")
    out: NDArray[np.float64] = _core.pf_peaks(
        f,
        count=_int(count, "count", 1),
        min_separation=_float(min_separation, "min_separation"),
        smoothing=_float(smoothing, "smoothing"),
    )
    return out


def pf_render(
    positions: ArrayLike,
    /,
    *,
    width: int = 256,
    height: int = 256,
    amplitude: float = 1.0,
    blur: float = 2.0,
    sigma: float = 0.1,
    seed: int = 0,
) -> NDArray[np.float64]:
    """A frame ``(height, width)`` of Gaussian point spreads at ``positions`` ``(n, 2)`` plus
    white noise of 1-sigma ``sigma`` (the paper: ``10^(-SNR/20)``)."""
    p = as_float_array(positions, "positions")
    if p.ndim != 2 or p.shape[1] != 2:
        raise GeofeasError(f"positions: expected shape (n, 2), got {p.shape}")
    out: NDArray[np.float64] = _core.pf_render(
        p,
        width=_int(width, "width", 1),
        height=_int(height, "height", 1),
        amplitude=_float(amplitude, "amplitude"),
        blur=_float(blur, "blur"),
        sigma=_float(sigma, "sigma"),
        seed=_int(seed, "seed", 0),
    )
    return out


def pf_study(
    *,
    runs: int = _S["runs"],
    seed: int = _S["seed"],
    ic: ArrayLike = PAPER_IC,
    ic_snr: float = _S["ic_snr"],
    snrs: Sequence[float] | None = _S["snrs"],
    truth: Literal["white", "jerk", "gauss-markov", "ncv"] = _S["truth"],
    particles: int = _S["particles"],
    association: Literal["nearest", "one-to-one"] = _S["association"],
    resampling: Literal["systematic", "stratified", "multinomial", "residual"] = _S["resampling"],
    peaks: int = _S["peaks"],
    min_separation: float = _S["min_separation"],
    smoothing: float = _S["smoothing"],
    sigma_w: float = _S["sigma_w"],
    model_factors: tuple[float, float, float] = _S["model_factors"],
) -> dict[str, Any]:
    """Monte-Carlo study of the paper, in parallel in Rust.

    Rows: Methods 1 and 2 at every SNR of ``snrs`` (default 0, 1, ..., 20 dB) with the paper's
    initialisation (3 px, 0.5 px/s), then Method 2 at ``ic_snr`` for each ``(xmax, vmax)`` row
    of ``ic``. Each row pools ``runs`` runs of the four filters; run ``r`` is the same truth and
    noise pattern for every row, so differences between rows are not sampling noise of the
    scenario.

    Returns
    -------
    dict
        Columns ``method``, ``snr_db``, ``xmax``, ``vmax``, ``pca`` (probability of correct
        association: the peak taken is nearer the filter's own target than any other), ``hit``
        (the peak taken is also within 3 px of that target), ``rmse_px`` (position RMSE),
        ``coverage`` (fraction of errors inside the filters' 2-sigma bounds, per axis),
        ``held`` (fraction of tracks whose error stays below 5 px over the last second), and
        ``filter_pca``, ``filter_rmse_px`` ``(rows, 4)``.
    """
    options = _pick(("study",), locals())
    ic_arr = as_float_array(ic, "ic")
    if ic_arr.ndim != 2 or ic_arr.shape[1] != 2:
        raise GeofeasError(f"ic: expected shape (n, 2) with columns xmax, vmax; got {ic_arr.shape}")
    r = _core.pf_study(ic_arr, **options)
    out: dict[str, Any] = {"method": r.method, "snr_db": r.snr_db, "xmax": r.xmax, "vmax": r.vmax}
    out.update(_metrics_dict(r.all, ""))
    b = r.bank
    out.update(
        gospa=b.gospa,
        gospa_loc=b.gospa_loc,
        gospa_missed=b.gospa_missed,
        gospa_false=b.gospa_false,
        id_switches=b.id_switches,
        fragmentations=b.fragmentations,
    )
    lo, hi = _metrics_dict(r.lo, "_lo"), _metrics_dict(r.hi, "_hi")
    for (k_lo, v_lo), (k_hi, v_hi) in zip(lo.items(), hi.items(), strict=True):
        out[k_lo], out[k_hi] = v_lo, v_hi
    out["filter_pca"] = r.filter_pca
    out["filter_rmse_px"] = r.filter_rmse_px
    return out


def _metrics_dict(m: _core.PfMetrics, suffix: str) -> dict[str, NDArray[np.float64]]:
    """The study's per-filter metric columns, named with ``suffix``."""
    return {
        f"pca{suffix}": m.pca,
        f"hit{suffix}": m.hit,
        f"rmse_px{suffix}": m.rmse_px,
        f"coverage{suffix}": m.coverage,
        f"held{suffix}": m.held,
    }


def pf_ellipses(result: dict[str, Any], frame: int = -1) -> NDArray[np.float64]:
    """The 2-sigma position AOUs ``(n_filters, 5)`` at ``frame`` of a :func:`pf_simulate_run` /
    :func:`pf_track` result, in the geofeas convention with the image ``x`` as east and ``y`` as
    north: score them against another sensor's reports with :func:`geofeas.cdist`."""
    try:
        est = np.asarray(result["estimates"], dtype=np.float64)
        cov = np.asarray(result["covariances"], dtype=np.float64)
    except (KeyError, TypeError) as exc:
        raise GeofeasError(f"result: no 'estimates' / 'covariances' arrays ({exc})") from None
    if est.ndim != 3 or cov.ndim != 4:
        raise GeofeasError(
            f"result: expected estimates (F, n, 4) and covariances (F, n, 4, 4), got "
            f"{est.shape} and {cov.shape}"
        )
    k = _int(frame if frame >= 0 else est.shape[0] + frame, "frame", 0)
    if k >= est.shape[0]:
        raise GeofeasError(f"frame: {frame} is not one of the {est.shape[0]} frames")
    out: NDArray[np.float64] = from_gaussian(
        np.ascontiguousarray(est[k, :, :2]), np.ascontiguousarray(cov[k, :, :2, :2])
    )
    return out


def plot_pf_run(result: dict[str, Any], out_dir: str | Path, *, prefix: str = "run") -> list[Path]:
    """Figures like the paper's for a :func:`pf_simulate_run` result: tracks with particle
    clouds over a frame (Figs. 6, 9, 13, 16), position errors with 2-sigma bounds (Figs. 7, 10,
    14, 17), correct-association flags and mean weighted distances (Figs. 8, 11, 15, 18) and
    measurement residuals (Fig. 12). Needs matplotlib; returns the PNG paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    truth = np.asarray(result["truth"])
    est = np.asarray(result["estimates"])
    cov = np.asarray(result["covariances"])
    t = np.asarray(result["times"])
    n = truth.shape[1]
    colours = [plt.get_cmap("tab10")(i) for i in range(n)]
    title = f"Method {result['method']}, SNR = {result['snr_db']:g} dB"
    paths = []

    fig, ax = plt.subplots(figsize=(6.4, 6.0))
    frames = np.asarray(result["frames"])
    if len(frames):
        ax.imshow(frames[-1], cmap="gray", origin="lower", alpha=0.6)
    snaps = np.asarray(result["snapshots"])
    for i in range(n):
        ax.plot(
            truth[:, i, 0], truth[:, i, 1], "-", color=colours[i], lw=1.2, label=f"target {i + 1}"
        )
        ax.plot(est[:, i, 0], est[:, i, 1], "--", color="k", lw=0.7)
        sel = snaps[snaps[:, 1] == i] if len(snaps) else snaps
        if len(sel):
            ax.plot(sel[:, 2], sel[:, 3], ".", ms=1.0, color=colours[i])
    ax.set_xlim(0, 255)
    ax.set_ylim(0, 255)
    ax.set_xlabel("x [pixels]")
    ax.set_ylabel("y [pixels]")
    ax.set_title(f"{title}: truth, estimates (dashed), particle clouds")
    ax.legend(loc="upper center", fontsize=7, ncol=4)
    fig.tight_layout()
    p = out / f"{prefix}_tracks.png"
    save_figure(fig, p, dpi=110)
    plt.close(fig)
    paths.append(p)

    fig, axes = plt.subplots(n, 2, figsize=(10, 2.0 * n), sharex=True)
    for i in range(n):
        for a, (col, name) in enumerate(((0, "x"), (1, "y"))):
            ax = axes[i, a]
            err = est[:, i, col] - truth[:, i, col]
            bound = 2.0 * np.sqrt(cov[:, i, col, col])
            ax.plot(t, err, color=colours[i], lw=1.0)
            ax.plot(t, bound, "k--", lw=0.7)
            ax.plot(t, -bound, "k--", lw=0.7)
            ax.set_ylabel(f"F{i + 1} {name} err [px]")
    axes[-1, 0].set_xlabel("time [s]")
    axes[-1, 1].set_xlabel("time [s]")
    fig.suptitle(f"{title}: position errors and 2-sigma bounds")
    fig.tight_layout()
    p = out / f"{prefix}_errors.png"
    save_figure(fig, p, dpi=100)
    plt.close(fig)
    paths.append(p)

    correct = np.asarray(result["correct"])
    dist = np.asarray(result["distances"])
    fig, axes = plt.subplots(n, 2, figsize=(10, 2.0 * n), sharex=True)
    for i in range(n):
        axes[i, 0].step(t, correct[:, i].astype(float), where="mid", color=colours[i])
        axes[i, 0].set_ylim(-0.1, 1.1)
        axes[i, 0].set_ylabel(f"F{i + 1}: PCA {100 * correct[:, i].mean():.0f}%", fontsize=8)
        for j in range(dist.shape[2]):
            axes[i, 1].semilogy(t, dist[:, i, j], lw=0.8, label=f"Z{j + 1}")
        axes[i, 1].set_ylabel(f"X{i + 1} R [px]")
    axes[0, 1].legend(fontsize=6, ncol=4)
    axes[0, 0].set_title("correct association (1) / incorrect (0)")
    axes[0, 1].set_title("mean weighted distance R to each peak Zj (by intensity)")
    axes[-1, 0].set_xlabel("time [s]")
    axes[-1, 1].set_xlabel("time [s]")
    fig.suptitle(title)
    fig.tight_layout()
    p = out / f"{prefix}_association.png"
    save_figure(fig, p, dpi=100)
    plt.close(fig)
    paths.append(p)

    res = np.asarray(result["residuals"])
    if np.isfinite(res).any():
        fig, axes = plt.subplots(n, 1, figsize=(7, 1.8 * n), sharex=True)
        for i in range(n):
            m, s = res[:, i, 0], res[:, i, 1]
            axes[i].plot(t, m, color=colours[i], lw=1.0)
            axes[i].plot(t, m + 2 * s, "k--", lw=0.6)
            axes[i].plot(t, m - 2 * s, "k--", lw=0.6)
            axes[i].set_ylabel(f"F{i + 1} residual")
        axes[-1].set_xlabel("time [s]")
        fig.suptitle(f"{title}: measurement residual mean and 2-sigma (Fig. 12)")
        fig.tight_layout()
        p = out / f"{prefix}_residuals.png"
        save_figure(fig, p, dpi=100)
        plt.close(fig)
        paths.append(p)
    return paths
