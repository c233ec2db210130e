"""Multiple-hypothesis trilateration and tracking with distributed radars (seed 004).

Thin wrappers over the Rust core (``geofeas._core.mht_*``):

- :func:`trilaterate`: two range / range-rate detections to a Cartesian state and its covariance
  (eqs. 1-9), for sensors anywhere in the plane.
- :func:`track`: Reid's measurement-oriented MHT (or the single-hypothesis baseline) over
  detections of known sensors; returns the most likely hypothesis's tracks.
- :func:`simulate_run`: one simulated run of the paper's scenarios, tracked and scored.
- :func:`study`: the Monte-Carlo reproduction of Tables 1 and 2 (section 5).
- :func:`track_ellipses`: Cartesian track covariances as 2-sigma AOU ellipses
  ``(x0, y0, rx, ry, phi)``, ready for :func:`geofeas.glr`, :func:`geofeas.overlap` or
  :func:`geofeas.cdist` (the bridge to the geofeasibility scores).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._arrays import as_float_array
from .._atomic import save_figure
from .._core import GeofeasError

__all__ = [
    "PAPER_TABLE_1",
    "PAPER_TABLE_2",
    "STUDY_COLUMNS",
    "paper_sensors",
    "plot_run",
    "simulate_run",
    "study",
    "track",
    "track_ellipses",
    "trilaterate",
]

#: Columns of :func:`study` and of ``tables.csv``.
STUDY_COLUMNS = (
    "targets",
    "sensors",
    "tracker",
    "false_alarms",
    "t_pd",
    "t_far",
    "pos_err",
    "vel_err",
)

#: Table 1 of the paper (one target, three sensors, 50 hypotheses): false alarms per sensor per
#: scan -> (T_PD, T_FAR [tracks/s], pos err [m], vel err [m/s]).
PAPER_TABLE_1: dict[int, tuple[float, float, float, float]] = {
    0: (0.80, 0.0, 0.4, 0.8),
    1: (0.75, 0.0, 0.7, 0.8),
    2: (0.73, 0.1, 0.7, 0.9),
    4: (0.53, 0.0, 0.4, 0.6),
    6: (0.35, 0.0, 0.4, 0.7),
}

#: Table 2 of the paper (two targets, three sensors, 50 hypotheses).
PAPER_TABLE_2: dict[int, tuple[float, float, float, float]] = {
    0: (0.65, 0.0, 0.58, 0.90),
    1: (0.66, 1.6, 0.63, 0.73),
    2: (0.56, 2.6, 2.4, 28.3),
    3: (0.51, 7.0, 10.0, 50.0),
    4: (0.33, 20.0, 54.0, 18.0),
}


def _int(value: Any, name: str, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise GeofeasError(f"{name}: expected an integer, got {value!r}")
    if value < minimum:
        raise GeofeasError(f"{name}: must be >= {minimum}, got {value}")
    return int(value)


def paper_sensors(count: int = 3) -> NDArray[np.float64]:
    """Sensor rows ``[x, y, boresight, half_beam, max_range, max_range_rate]`` of the paper.

    Three sensors at x = -10, 0, 10 m on y = 0 with 180-degree beams facing +y, a 100 m range and
    +-15 m/s range-rate window; ``count=2`` keeps the outer two (x = -10 and 10 m).
    """
    xs = {3: [-10.0, 0.0, 10.0], 2: [-10.0, 10.0]}.get(count)
    if xs is None:
        raise GeofeasError(f"count: the paper's layouts have 2 or 3 sensors, got {count!r}")
    return np.array([[x, 0.0, math.pi / 2, math.pi / 2, 100.0, 15.0] for x in xs])


def trilaterate(
    pos_a: ArrayLike,
    z_a: ArrayLike,
    cov_a: ArrayLike,
    pos_b: ArrayLike,
    z_b: ArrayLike,
    cov_b: ArrayLike,
    /,
    *,
    boresight: float = math.pi / 2,
    half_beam: float = math.pi / 2,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Cartesian state of a target seen by two range / range-rate radars (eqs. 1-9).

    Parameters
    ----------
    pos_a, pos_b : array_like, shape (2,)
        Sensor positions ``(x, y)``.
    z_a, z_b : array_like, shape (2,)
        Detections ``(range, range_rate)``.
    cov_a, cov_b : array_like, shape (2, 2)
        Their covariances.
    boresight, half_beam : float
        Beam direction (radians counter-clockwise from +x) and half-width of both sensors; of the
        two mirror solutions the one inside both beams is returned.

    Returns
    -------
    state : ndarray, shape (4,)
        ``(x, y, vx, vy)``.
    cov : ndarray, shape (4, 4)
        ``J C J^T`` (eq. 8).

    Raises
    ------
    GeofeasError
        When the range circles do not intersect in front of both sensors.
    """
    args = [
        as_float_array(v, n)
        for v, n in [
            (pos_a, "pos_a"),
            (z_a, "z_a"),
            (cov_a, "cov_a"),
            (pos_b, "pos_b"),
            (z_b, "z_b"),
            (cov_b, "cov_b"),
        ]
    ]
    for arr, name, shape in zip(
        args,
        ["pos_a", "z_a", "cov_a", "pos_b", "z_b", "cov_b"],
        [(2,), (2,), (2, 2)] * 2,
        strict=True,
    ):
        if arr.shape != shape:
            raise GeofeasError(f"{name}: expected shape {shape}, got {arr.shape}")
    state, cov = _core.mht_trilaterate(
        *args, boresight=float(boresight), half_beam=float(half_beam)
    )
    return state, cov


def track(
    detections: ArrayLike,
    sensors: ArrayLike,
    /,
    *,
    max_hypotheses: int = 50,
    pd: float = 0.9,
    false_alarm_density: float = 1.0 / 3000.0,
    new_target_density: float = 0.02 / 3000.0,
    accel_sigma: float = 4.0 * 9.80665,
    sigma_range: float = 0.05,
    sigma_range_rate: float = 0.02,
    gate: float = 16.0,
    max_coast: float = 1.0,
    max_speed: float = 15.0,
    ekf_iterations: int = 2,
    single: bool = False,
) -> dict[str, Any]:
    """Tracks range / range-rate detections of several radars with Reid's MHT.

    Parameters
    ----------
    detections : array_like, shape (n, 4)
        Rows ``[time, sensor, range, range_rate]`` sorted by time; consecutive rows with the same
        time and sensor form one scan (a scan with no detection cannot be given and is not
        charged the missed-detection factor).
    sensors : array_like, shape (s, 6)
        Rows ``[x, y, boresight, half_beam, max_range, max_range_rate]`` (see
        :func:`paper_sensors`).
    max_hypotheses : int
        Hypotheses kept after each detection (the paper: 50).
    pd, false_alarm_density, new_target_density
        Reid's detection probability (in (0, 1)) and densities per (m x m/s) of one scan.
    accel_sigma : float
        White acceleration standard deviation of the motion models, m/s^2 (the paper: 4 g).
    sigma_range, sigma_range_rate : float
        Measurement noise.
    gate : float
        Chi-square gate (2 dof) on Kalman innovations.
    max_coast : float
        Tracks not updated for this many seconds are closed.
    max_speed : float
        Largest target speed (bounds trilaterated velocities), m/s.
    ekf_iterations : int
        Relinearisations of the Cartesian (iterated) EKF update; 0 is the paper's plain EKF.
    single : bool
        Run the single-hypothesis (global nearest neighbour) baseline instead.

    Returns
    -------
    dict
        ``tracks`` (rows ``[id, time, x, y, vx, vy]`` of every Cartesian update of the most likely
        hypothesis), ``ellipses`` (rows ``[id, x0, y0, rx, ry, phi]``: 2-sigma AOU of the open
        Cartesian tracks), ``track_of_detection`` (track id per detection, -1 for none) and
        ``probability`` (of the most likely hypothesis among those kept).
    """
    det = as_float_array(detections, "detections")
    if det.ndim != 2 or det.shape[1] != 4:
        raise GeofeasError(
            "detections: expected shape (n, 4) with columns time, sensor, range, range_rate; "
            f"got {det.shape}"
        )
    sen = as_float_array(sensors, "sensors")
    if sen.ndim != 2 or sen.shape[1] != 6:
        raise GeofeasError(
            "sensors: expected shape (s, 6) with columns x, y, boresight, half_beam, max_range, "
            f"max_range_rate; got {sen.shape}"
        )
    return dict(
        _core.mht_track(
            det,
            sen,
            max_hypotheses=_int(max_hypotheses, "max_hypotheses", 1),
            pd=float(pd),
            false_alarm_density=float(false_alarm_density),
            new_target_density=float(new_target_density),
            accel_sigma=float(accel_sigma),
            sigma_range=float(sigma_range),
            sigma_range_rate=float(sigma_range_rate),
            gate=float(gate),
            max_coast=float(max_coast),
            max_speed=float(max_speed),
            ekf_iterations=_int(ekf_iterations, "ekf_iterations", 0),
            single=bool(single),
        )
    )


def simulate_run(
    *,
    targets: int = 2,
    sensors: int = 3,
    false_alarms: int = 2,
    tracker: Literal["mht", "single"] = "mht",
    run: int = 0,
    seed: int = 0,
    max_hypotheses: int = 50,
    ekf_iterations: int = 2,
    detection_probability: float = 1.0,
) -> dict[str, Any]:
    """Simulates and tracks one run of the paper's scenario (section 5.1), with the sensors'
    ``detection_probability`` (the paper: 1).

    Returns
    -------
    dict
        ``detections`` rows ``[time, sensor, range, range_rate, target, track]`` (target -1: false
        alarm; track -1: not in a track of the final most likely hypothesis), ``tracks`` and
        ``ellipses`` as in :func:`track`, ``truth`` rows ``[target, time, x, y, vx, vy]`` every
        0.05 s, ``sensors`` positions, ``metrics`` (``t_pd``, ``t_far``, ``pos_err``,
        ``vel_err`` of this run, section 5.2) and ``duration``.
    """
    return dict(
        _core.mht_simulate_run(
            targets=_int(targets, "targets", 1),
            sensors=_int(sensors, "sensors", 1),
            false_alarms=_int(false_alarms, "false_alarms", 0),
            tracker=str(tracker),
            run=_int(run, "run", 0),
            seed=_int(seed, "seed", 0),
            max_hypotheses=_int(max_hypotheses, "max_hypotheses", 1),
            ekf_iterations=_int(ekf_iterations, "ekf_iterations", 0),
            detection_probability=float(detection_probability),
        )
    )


def study(
    *,
    runs: int = 20,
    seed: int = 0,
    max_hypotheses: int = 50,
    ekf_iterations: int = 2,
    new_target_rate: float = 0.02,
    detection_probability: float = 1.0,
) -> dict[str, Any]:
    """Monte-Carlo reproduction of Tables 1 and 2 (section 5), in parallel in Rust.

    One row per cell: one target with 0, 1, 2, 4, 6 and two targets with 0-4 false alarms per
    sensor per scan, three and two sensors, the MHT and the single-hypothesis baseline; metrics
    pooled over ``runs`` runs. Runs use streams derived from ``(seed, cell, run)``, so results do
    not depend on the thread count, and both trackers see the same data. ``ekf_iterations=0``
    uses the paper's plain EKF instead of the iterated one; ``new_target_rate`` is the expected
    number of new targets per scan in a sensor's range / range-rate window (the new-target density
    of Reid's hypothesis probabilities, which the paper does not give);
    ``detection_probability`` is the simulated sensors' (the paper: 1; the tracker assumes 0.9).

    Returns
    -------
    dict
        Columns :data:`STUDY_COLUMNS`: numeric arrays and ``tracker``, a list of ``"mht"`` /
        ``"single"``.
    """
    out = dict(
        _core.mht_study(
            runs=_int(runs, "runs", 1),
            seed=_int(seed, "seed", 0),
            max_hypotheses=_int(max_hypotheses, "max_hypotheses", 1),
            ekf_iterations=_int(ekf_iterations, "ekf_iterations", 0),
            new_target_rate=float(new_target_rate),
            detection_probability=float(detection_probability),
        )
    )
    for key in ("targets", "sensors", "false_alarms"):
        out[key] = out[key].astype(np.int64)
    return {k: out[k] for k in STUDY_COLUMNS}


def track_ellipses(result: dict[str, Any]) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Track ids and 2-sigma AOU ellipses ``(n, 5)`` of a :func:`track` / :func:`simulate_run`
    result, in the geofeas convention (``phi`` the bearing of ``rx``, clockwise from north, with
    x east and y north): score two radar networks' tracks with ``geofeas.cdist(a, b)``."""
    try:
        rows = np.asarray(result["ellipses"], dtype=np.float64)
    except (KeyError, TypeError) as exc:
        raise GeofeasError(f"result: no 'ellipses' array ({exc})") from None
    if rows.ndim != 2 or rows.shape[1] != 6:
        raise GeofeasError(f"result['ellipses']: expected shape (n, 6), got {rows.shape}")
    return rows[:, 0].astype(np.int64), np.ascontiguousarray(rows[:, 1:])


def plot_run(result: dict[str, Any], out_dir: str | Path, *, prefix: str = "run") -> list[Path]:
    """Figures like the paper's Figs. 4-7 for a :func:`simulate_run` result: ground truth and
    tracks in Cartesian coordinates, and each sensor's detections in range-Doppler coloured by
    the track they belong to (grey: not associated). Needs matplotlib; returns the PNG paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    det = np.asarray(result["detections"])
    tracks = np.asarray(result["tracks"])
    truth = np.asarray(result["truth"])
    sensors = np.asarray(result["sensors"])
    ids = sorted({int(t) for t in det[:, 5] if t >= 0} | {int(t) for t in tracks[:, 0]})
    cmap = plt.get_cmap("tab10")
    colour = {tid: cmap(i % 10) for i, tid in enumerate(ids)}
    paths = []

    fig, (ax0, ax1) = plt.subplots(2, 1, figsize=(6, 9), sharex=True, sharey=True)
    for k in np.unique(truth[:, 0]):
        sel = truth[truth[:, 0] == k]
        ax0.plot(sel[:, 2], sel[:, 3], "-", lw=1.5, label=f"target {int(k)}")
        ax1.plot(sel[:, 2], sel[:, 3], "-", lw=0.8, color="0.8")
    for tid in ids:
        sel = tracks[tracks[:, 0] == tid]
        if len(sel):
            ax1.plot(sel[:, 2], sel[:, 3], ".-", ms=2, lw=0.8, color=colour[tid])
    for ax in (ax0, ax1):
        ax.plot(sensors[:, 0], sensors[:, 1], "k*", ms=10)
        ax.set_aspect("equal")
        ax.set_ylabel("y [m]")
    ax0.set_title("ground truth")
    ax0.legend(loc="upper right", fontsize=8)
    ax1.set_title("tracks of the most likely hypothesis")
    ax1.set_xlabel("x [m]")
    fig.tight_layout()
    p = out / f"{prefix}_tracks.png"
    save_figure(fig, p, dpi=110)
    plt.close(fig)
    paths.append(p)

    for s in range(len(sensors)):
        sel = det[det[:, 1] == s]
        fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
        grey = sel[sel[:, 5] < 0]
        for ax, xcol in ((ax0, 3), (ax1, 0)):
            ax.plot(grey[:, xcol], grey[:, 2], ".", color="0.75", ms=3, label="not associated")
            for tid in ids:
                d = sel[sel[:, 5] == tid]
                if len(d):
                    ax.plot(d[:, xcol], d[:, 2], ".", color=colour[tid], ms=4)
        ax0.set_xlabel("range rate [m/s]")
        ax0.set_ylabel("range [m]")
        ax1.set_xlabel("time [s]")
        ax0.legend(loc="upper right", fontsize=8)
        fig.suptitle(f"detections of sensor {s + 1} (x = {sensors[s, 0]:g} m), coloured by track")
        fig.tight_layout()
        p = out / f"{prefix}_sensor{s + 1}.png"
        save_figure(fig, p, dpi=110)
        plt.close(fig)
        paths.append(p)
    return paths
