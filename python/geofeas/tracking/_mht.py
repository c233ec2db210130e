"""Multiple-hypothesis trilateration and tracking with distributed radars (seed 004).

Thin wrappers over the Rust core (``geofeas._core.mht_*``):

- :func:`mht_trilaterate`: two range / range-rate detections to a Cartesian state and its covariance
  (eqs. 1-9), for sensors anywhere in the plane.
- :func:`mht_track`: Reid's measurement-oriented MHT (or the single-hypothesis baseline) over
  detections of known sensors; returns the most likely hypothesis's tracks.
- :func:`mht_simulate_run`: one simulated run of the paper's scenarios, tracked and scored.
- :func:`mht_study`: the Monte-Carlo reproduction of Tables 1 and 2 (section 5).
- :func:`mht_ellipses`: Cartesian track covariances as 2-sigma AOU ellipses
  ``(x0, y0, rx, ry, phi)``, ready for :func:`geofeas.glr`, :func:`geofeas.overlap` or
  :func:`geofeas.cdist` (the bridge to the geofeasibility scores).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._arrays import as_float_array
from .._atomic import save_figure
from .._core import GeofeasError

__all__ = [
    "OPTIONS",
    "PAPER_TABLE_1",
    "PAPER_TABLE_2",
    "ESTIMATE_COLUMNS",
    "METRICS",
    "MhtTracker",
    "STUDY_COLUMNS",
    "TRACKERS",
    "mht_track_scans",
    "paper_sensors",
    "plot_mht_run",
    "mht_simulate_run",
    "mht_study",
    "mht_track",
    "mht_ellipses",
    "mht_trilaterate",
]

#: Metrics of the study, in table order (defined once, in the Rust core).
METRICS: tuple[str, ...] = tuple(_core.mht_metric_names())

#: Trackers of the study: the MHT in the project's recommended configuration, the MHT in the
#: paper-faithful configuration, and the single-hypothesis baseline.
TRACKERS: tuple[str, ...] = tuple(_core.mht_tracker_names())

#: The option sets of the MHT as declared once in the Rust core (``geofeas._core.mht_options()``):
#: ``tracker`` (:func:`mht_track`, :class:`MhtTracker`), ``run`` (:func:`mht_simulate_run`),
#: ``study`` (:func:`mht_study`) and ``beam`` (:func:`mht_trilaterate`), each a list of
#: ``(name, kind, default, doc, choices)``. The signatures below take their defaults from it, and
#: a test checks them, the stubs, the ``mht-study`` flags and the docs table against it.
OPTIONS: dict[str, list[tuple[str, str, Any, str, tuple[str, ...]]]] = _core.mht_options()
_K, _R, _S, _B = ({o[0]: o[2] for o in OPTIONS[g]} for g in ("tracker", "run", "study", "beam"))


def _pick(group: str, arguments: dict[str, Any]) -> dict[str, Any]:
    """The arguments of a call that belong to the option set ``group``, for the core."""
    return {o[0]: arguments[o[0]] for o in OPTIONS[group]}


#: Columns of :func:`mht_study` and of ``tables.csv``: the cell, ``runs``, then every metric
#: followed by its confidence interval (``_lo``, ``_hi``).
STUDY_COLUMNS: tuple[str, ...] = (
    "targets",
    "sensors",
    "tracker",
    "false_alarms",
    "runs",
) + tuple(c for m in METRICS for c in (m, f"{m}_lo", f"{m}_hi"))

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


def mht_trilaterate(
    pos_a: ArrayLike,
    z_a: ArrayLike,
    cov_a: ArrayLike,
    pos_b: ArrayLike,
    z_b: ArrayLike,
    cov_b: ArrayLike,
    /,
    *,
    boresight: float = _B["boresight"],
    half_beam: float = _B["half_beam"],
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
    options = _pick("beam", locals())
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
    state, cov = _core.mht_trilaterate(*args, **options)
    return state, cov


def mht_track(
    detections: ArrayLike,
    sensors: ArrayLike,
    /,
    *,
    max_hypotheses: int = _K["max_hypotheses"],
    pd: float = _K["pd"],
    false_alarm_density: float = _K["false_alarm_density"],
    new_target_density: float = _K["new_target_density"],
    accel_sigma: float = _K["accel_sigma"],
    sigma_range: float = _K["sigma_range"],
    sigma_range_rate: float = _K["sigma_range_rate"],
    gate: float = _K["gate"],
    max_coast: float = _K["max_coast"],
    max_speed: float = _K["max_speed"],
    ekf_iterations: int = _K["ekf_iterations"],
    single: bool = _K["single"],
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
        White acceleration standard deviation of the motion models, m/s^2 (2 g; the paper's
        ``Q = 4 g`` read as a covariance is ``sqrt(4 g) = 6.26``).
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
    options = _pick("tracker", locals())
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
    r = _core.mht_track(det, sen, **options)
    return {
        "tracks": r.tracks,
        "ellipses": r.ellipses,
        "track_of_detection": r.track_of_detection,
        "probability": r.probability,
    }


#: Columns of :meth:`MhtTracker.estimates`.
ESTIMATE_COLUMNS: tuple[str, ...] = (
    "id",
    "time",
    "x",
    "y",
    "vx",
    "vy",
    "p_x_x",
    "p_x_y",
    "p_x_vx",
    "p_x_vy",
    "p_y_y",
    "p_y_vx",
    "p_y_vy",
    "p_vx_vx",
    "p_vx_vy",
    "p_vy_vy",
    "contacts",
    "sensors",
)


class MhtTracker:
    """Reid's multiple-hypothesis trilateration tracker (seed 004), fed one scan at a time.

    Parameters
    ----------
    sensors : array_like, shape (s, 6)
        Rows ``[x, y, boresight, half_beam, max_range, max_range_rate]`` (see
        :func:`paper_sensors`).
    **options
        Tracker options as in :func:`mht_track` (``max_hypotheses``, ``pd``,
        ``false_alarm_density``, ``new_target_density``, ``accel_sigma``, ``sigma_range``,
        ``sigma_range_rate``, ``gate``, ``max_coast``, ``max_speed``, ``ekf_iterations``,
        ``single``).

    Examples
    --------
    >>> import numpy as np
    >>> from geofeas.tracking import MhtTracker, paper_sensors
    >>> mht = MhtTracker(paper_sensors(2))
    >>> mht.process_scan(0.0, 0, np.array([[25.0, 1.0]]))
    0
    >>> mht.process_scan(0.5, 1, np.empty((0, 2)))   # an empty scan: charged 1 - P_D
    1
    >>> [round(p, 3) for p, _, _ in mht.hypotheses(top=2)]
    [0.998, 0.002]
    """

    def __init__(self, sensors: ArrayLike, /, **options: Any) -> None:
        sen = as_float_array(sensors, "sensors")
        if sen.ndim != 2 or sen.shape[1] != 6:
            raise GeofeasError(
                "sensors: expected shape (s, 6) with columns x, y, boresight, half_beam, "
                f"max_range, max_range_rate; got {sen.shape}"
            )
        known = set(_TRACK_OPTIONS)
        unknown = sorted(set(options) - known)
        if unknown:
            raise GeofeasError(f"{unknown[0]}: unknown option (expected one of {sorted(known)})")
        self._core = _core.MhtTracker(sen, **options)

    def process_scan(self, time: float, sensor: int, detections: ArrayLike) -> int:
        """Processes the scan of ``sensor`` at ``time`` (not before the previous scan).

        ``detections`` are rows ``[range, range_rate]``, possibly none (shape ``(0, 2)``): every
        track the sensor could have seen and did not is then charged Reid's ``1 - P_D``. Returns
        the stream index of the scan's first detection (detections are numbered in the order they
        are given).
        """
        det = as_float_array(detections, "detections")
        if det.size == 0:
            det = np.empty((0, 2), dtype=np.float64)
        if det.ndim != 2 or det.shape[1] != 2:
            raise GeofeasError(
                f"detections: expected shape (n, 2) with columns range, range_rate; got {det.shape}"
            )
        return int(self._core.process_scan(float(time), _int(sensor, "sensor", 0), det))

    @property
    def scans(self) -> int:
        """Scans processed."""
        return int(self._core.scans)

    def estimates(self, rank: int = 0) -> NDArray[np.float64]:
        """Cartesian tracks of the hypothesis of rank ``rank`` (0: the most likely), rows
        :data:`ESTIMATE_COLUMNS`."""
        return np.asarray(self._core.estimates(_int(rank, "rank", 0)))

    def hypotheses(self, top: int = 5) -> list[tuple[float, NDArray[np.float64], list[int]]]:
        """The ``top`` most likely hypotheses, most likely first: ``(probability, estimates,
        open track ids)``; the probabilities are normalised over the kept hypotheses."""
        return [
            (float(p), np.asarray(e), list(ids))
            for p, e, ids in self._core.hypotheses(_int(top, "top", 1))
        ]

    def track_of_detection(self) -> NDArray[np.int64]:
        """Track id of every detection so far in the most likely hypothesis (-1: false alarm)."""
        return np.asarray(self._core.track_of_detection()).astype(np.int64)


_TRACK_OPTIONS = tuple(_K)


def mht_track_scans(
    scans: Iterable[tuple[float, int, ArrayLike]],
    sensors: ArrayLike,
    /,
    *,
    top: int = 3,
    **options: Any,
) -> dict[str, Any]:
    """Tracks a stream of scans ``(time, sensor, detections)``, empty scans included.

    Parameters
    ----------
    scans : iterable of (time, sensor, detections)
        In time order; ``detections`` rows ``[range, range_rate]``, possibly none, so that
        Reid's missed-detection charge ``1 - P_D`` applies to scans that saw nothing.
    sensors : array_like, shape (s, 6)
        As for :class:`MhtTracker`.
    top : int
        Hypotheses reported after every scan.
    **options
        As for :class:`MhtTracker`.

    Returns
    -------
    dict
        ``estimates``: rows ``[scan]`` + :data:`ESTIMATE_COLUMNS` of the most likely hypothesis
        after every scan; ``top``: rows ``[scan, rank, probability]`` of the ``top`` most likely
        hypotheses after every scan; ``hypotheses``: the final ``top`` hypotheses as
        ``(probability, estimates, open track ids)``; ``track_of_detection``: track id of every
        detection in the final most likely hypothesis (-1: false alarm).
    """
    mht = MhtTracker(sensors, **options)
    k = _int(top, "top", 1)
    est: list[NDArray[np.float64]] = []
    tops: list[list[float]] = []
    for i, scan in enumerate(scans):
        try:
            time, sensor, detections = scan
        except (TypeError, ValueError):
            raise GeofeasError(
                f"scans: row {i}: expected (time, sensor, detections), got {scan!r}"
            ) from None
        mht.process_scan(time, sensor, detections)
        e = mht.estimates()
        est.append(
            np.column_stack([np.full(len(e), float(i)), e])
            if len(e)
            else e.reshape(0, 1 + len(ESTIMATE_COLUMNS))
        )
        for rank, (p, _, _) in enumerate(mht.hypotheses(k)):
            tops.append([float(i), float(rank), p])
    return {
        "estimates": np.concatenate(est) if est else np.empty((0, 1 + len(ESTIMATE_COLUMNS))),
        "top": np.array(tops, dtype=np.float64).reshape(-1, 3),
        "hypotheses": mht.hypotheses(k),
        "track_of_detection": mht.track_of_detection(),
    }


def mht_simulate_run(
    *,
    targets: int = _R["targets"],
    sensors: int = _R["sensors"],
    false_alarms: int = _R["false_alarms"],
    tracker: Literal["mht", "mht-paper", "single"] = _R["tracker"],
    run: int = _R["run"],
    seed: int = _R["seed"],
    max_hypotheses: int = _R["max_hypotheses"],
    ekf_iterations: int = _R["ekf_iterations"],
    detection_probability: float = _R["detection_probability"],
    new_target_rate: float = _R["new_target_rate"],
    confirm_probability: float = _R["confirm_probability"],
    accel_sigma: float = _R["accel_sigma"],
) -> dict[str, Any]:
    """Simulates and tracks one run of the paper's scenario (section 5.1), with the sensors'
    ``detection_probability`` (the paper: 1).

    Returns
    -------
    dict
        ``detections`` rows ``[time, sensor, range, range_rate, target, track]`` (target -1: false
        alarm; track -1: not in a track of the final most likely hypothesis), ``tracks`` and
        ``ellipses`` as in :func:`mht_track`, ``truth`` rows ``[target, time, x, y, vx, vy]`` every
        0.05 s, ``sensors`` positions, ``metrics`` (:data:`METRICS` of this run: section 5.2,
        GOSPA, identity switches, fragmentation) and ``duration``. ``tracker="mht-paper"`` runs
        the paper-faithful configuration (plain EKF, ``Q = 4 g`` read as a covariance, new-target
        rate 1e-8); the other options then apply to ``"mht"`` and ``"single"`` only.
    """
    r = _core.mht_simulate_run(**_pick("run", locals()))
    return {
        "detections": r.detections,
        "tracks": r.tracks,
        "ellipses": r.ellipses,
        "truth": r.truth,
        "sensors": r.sensors,
        "metrics": dict(zip(METRICS, r.metrics.tolist(), strict=True)),
        "duration": r.duration,
    }


def mht_study(
    *,
    runs: int = _S["runs"],
    seed: int = _S["seed"],
    max_hypotheses: int = _S["max_hypotheses"],
    ekf_iterations: int = _S["ekf_iterations"],
    new_target_rate: float = _S["new_target_rate"],
    detection_probability: float = _S["detection_probability"],
    confirm_probability: float = _S["confirm_probability"],
    accel_sigma: float = _S["accel_sigma"],
    paper_ekf_iterations: int = _S["paper_ekf_iterations"],
    paper_new_target_rate: float = _S["paper_new_target_rate"],
    paper_confirm_probability: float = _S["paper_confirm_probability"],
    paper_accel_sigma: float = _S["paper_accel_sigma"],
    trackers: Sequence[str] = _S["trackers"],
    one_target: Sequence[int] = _S["one_target"],
    two_targets: Sequence[int] = _S["two_targets"],
    resamples: int = _S["resamples"],
    level: float = _S["level"],
) -> dict[str, Any]:
    """Monte-Carlo reproduction of Tables 1 and 2 (section 5), in parallel in Rust.

    One row per cell: ``trackers`` x {3, 2 sensors} x (one target with ``one_target`` and two
    targets with ``two_targets`` false alarms per sensor per scan); metrics pooled over ``runs``
    runs, each with its percentile-bootstrap interval at ``level`` over ``resamples`` resamples
    of the runs. Runs use streams derived from ``(seed, cell, run)``, so results do not depend on
    the thread count, and all trackers see the same data.

    The recommended MHT (``"mht"``) and the baseline use ``ekf_iterations`` (0: the paper's
    plain EKF), ``new_target_rate`` (expected new targets per scan in a sensor's range /
    range-rate window: the new-target density of Reid's hypothesis probabilities, which the paper
    does not give), ``confirm_probability`` (0: no confirmation stage) and ``accel_sigma``
    (process noise: white-acceleration standard deviation, m/s^2; 2 g, the value of experiment
    E1 in ``docs/mht-study.md``, where it gives the lowest GOSPA of the values tried). The
    paper-faithful MHT (``"mht-paper"``) uses the ``paper_*`` options. ``detection_probability``
    is the simulated sensors' (the paper: 1; the trackers assume 0.9).

    Returns
    -------
    dict
        Columns :data:`STUDY_COLUMNS`: numeric arrays and ``tracker``, a list of names from
        :data:`TRACKERS`.
    """
    r = _core.mht_study(**_pick("study", locals()))
    out: dict[str, Any] = {
        "targets": r.targets,
        "sensors": r.sensors,
        "false_alarms": r.false_alarms,
        "tracker": list(r.tracker),
        "runs": np.full(len(r.tracker), int(runs), dtype=np.int64),
    }
    for table, suffix in ((r.metrics, ""), (r.metrics_lo, "_lo"), (r.metrics_hi, "_hi")):
        for j, name in enumerate(METRICS):
            out[name + suffix] = np.ascontiguousarray(table[:, j])
    return {k: out[k] for k in STUDY_COLUMNS}


def mht_ellipses(result: dict[str, Any]) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Track ids and 2-sigma AOU ellipses ``(n, 5)`` of a :func:`mht_track` /
    :func:`mht_simulate_run` result, in the geofeas convention (``phi`` the bearing of ``rx``,
    clockwise from north, with x east and y north): score two radar networks' tracks with
    ``geofeas.cdist(a, b)``."""
    try:
        rows = np.asarray(result["ellipses"], dtype=np.float64)
    except (KeyError, TypeError) as exc:
        raise GeofeasError(f"result: no 'ellipses' array ({exc})") from None
    if rows.ndim != 2 or rows.shape[1] != 6:
        raise GeofeasError(f"result['ellipses']: expected shape (n, 6), got {rows.shape}")
    return rows[:, 0].astype(np.int64), np.ascontiguousarray(rows[:, 1:])


def plot_mht_run(result: dict[str, Any], out_dir: str | Path, *, prefix: str = "run") -> list[Path]:
    """Figures like the paper's Figs. 4-7 for a :func:`mht_simulate_run` result: ground truth and
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
