"""Typed stub of the Rust extension module ``geofeas._core``."""

from typing import Any, final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "GeofeasError",
    "__version__",
    "assign_one_to_one",
    "associate",
    "association_candidates",
    "association_default_upper",
    "association_finish",
    "association_pair_instants",
    "association_pair_stats",
    "association_states_at",
    "association_track_summary",
    "combine_instants",
    "from_gaussian",
    "intersection_area",
    "MhtTracker",
    "mht_metric_names",
    "mht_simulate_run",
    "mht_study",
    "mht_track",
    "mht_tracker_names",
    "mht_trilaterate",
    "pf_log_weights",
    "pf_peaks",
    "pf_render",
    "pf_simulate_run",
    "pf_study",
    "pf_track",
    "polygon_error_bound",
    "project_aeqd",
    "ScoreOptions",
    "score_cdist",
    "score_pairs",
    "to_gaussian",
    "validate_ellipses",
]

__version__: str

class GeofeasError(ValueError):
    """Invalid input or options for a geofeas computation (a ValueError)."""

    argument: str | None
    row: int | None
    field: str | None

@final
class ScoreOptions:
    def __new__(
        cls,
        *,
        threshold: bool | None = None,
        method: str | None = None,
        vertices: int | None = None,
        samples: int | None = None,
        seed: int | None = None,
        sampler: str | None = None,
    ) -> ScoreOptions: ...

def score_pairs(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    score: str,
    options: ScoreOptions | None = None,
) -> NDArray[np.float64]: ...
def score_cdist(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    score: str,
    options: ScoreOptions | None = None,
    *,
    max_bytes: int,
) -> NDArray[np.float64]: ...
def intersection_area(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]: ...
def to_gaussian(
    e: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def from_gaussian(mean: NDArray[np.float64], cov: NDArray[np.float64]) -> NDArray[np.float64]: ...
def validate_ellipses(e: NDArray[np.float64]) -> None: ...
def polygon_error_bound(vertices: int, ratio: float) -> float: ...
def mht_trilaterate(
    pos_a: NDArray[np.float64],
    z_a: NDArray[np.float64],
    cov_a: NDArray[np.float64],
    pos_b: NDArray[np.float64],
    z_b: NDArray[np.float64],
    cov_b: NDArray[np.float64],
    *,
    boresight: float = ...,
    half_beam: float = ...,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def mht_track(
    detections: NDArray[np.float64],
    sensors: NDArray[np.float64],
    *,
    max_hypotheses: int = 50,
    pd: float = 0.9,
    false_alarm_density: float = ...,
    new_target_density: float = ...,
    accel_sigma: float = ...,
    sigma_range: float = 0.05,
    sigma_range_rate: float = 0.02,
    gate: float = 16.0,
    max_coast: float = 1.0,
    max_speed: float = 15.0,
    ekf_iterations: int = 2,
    single: bool = False,
) -> dict[str, Any]: ...
def mht_simulate_run(
    *,
    targets: int = 2,
    sensors: int = 3,
    false_alarms: int = 2,
    tracker: str = "mht",
    run: int = 0,
    seed: int = 0,
    max_hypotheses: int = 50,
    ekf_iterations: int = 2,
    detection_probability: float = 1.0,
    new_target_rate: float = 0.02,
    confirm_probability: float = 0.0,
    accel_sigma: float = ...,
) -> dict[str, Any]: ...
def mht_study(
    *,
    runs: int = 20,
    seed: int = 0,
    max_hypotheses: int = 50,
    ekf_iterations: int = 2,
    new_target_rate: float = 0.02,
    detection_probability: float = 1.0,
    confirm_probability: float = 0.0,
    accel_sigma: float = ...,
    paper_ekf_iterations: int = 0,
    paper_new_target_rate: float = 1e-8,
    paper_confirm_probability: float = 0.0,
    paper_accel_sigma: float = ...,
    trackers: list[str] = ...,
    one_target: list[int] = ...,
    two_targets: list[int] = ...,
    resamples: int = 1000,
    level: float = 0.95,
) -> dict[str, Any]: ...
def mht_metric_names() -> list[str]: ...
def mht_tracker_names() -> list[str]: ...

@final
class MhtTracker:
    def __new__(
        cls,
        sensors: NDArray[np.float64],
        *,
        max_hypotheses: int = 50,
        pd: float = 0.9,
        false_alarm_density: float = ...,
        new_target_density: float = ...,
        accel_sigma: float = ...,
        sigma_range: float = 0.05,
        sigma_range_rate: float = 0.02,
        gate: float = 16.0,
        max_coast: float = 1.0,
        max_speed: float = 15.0,
        ekf_iterations: int = 2,
        single: bool = False,
    ) -> MhtTracker: ...
    def process_scan(self, time: float, sensor: int, detections: NDArray[np.float64]) -> int: ...
    @property
    def scans(self) -> int: ...
    @property
    def detections(self) -> int: ...
    def estimates(self, rank: int = 0) -> NDArray[np.float64]: ...
    def hypotheses(self, top: int = 5) -> list[tuple[float, NDArray[np.float64], list[int]]]: ...
    def track_of_detection(self) -> NDArray[np.float64]: ...

def pf_simulate_run(
    *,
    snr_db: float = 15.0,
    method: int = 2,
    seed: int = 0,
    run: int = 0,
    truth: str = "white",
    particles: int = 10000,
    association: str = "nearest",
    resampling: str = "systematic",
    resample_threshold: float = 1.0,
    peaks: int = 4,
    min_separation: float = 3.0,
    smoothing: float = 0.0,
    xmax: float = 3.0,
    vmax: float = 0.5,
    sigma_w: float = 0.5,
    r1: float = 1.0,
    model_factors: tuple[float, float, float] = ...,
    half_box: int = 10,
    snapshot_frames: list[int] = ...,
    snapshot_particles: int = 300,
    keep_frames: list[int] = ...,
) -> dict[str, Any]: ...
def pf_track(
    frames: NDArray[np.float64],
    init: NDArray[np.float64],
    *,
    sigma_z: float,
    method: int = 2,
    amplitude: float = 1.0,
    blur: float = 2.0,
    dt: float = 0.1,
    seed: int = 0,
    particles: int = 10000,
    association: str = "nearest",
    resampling: str = "systematic",
    resample_threshold: float = 1.0,
    peaks: int = 4,
    min_separation: float = 3.0,
    smoothing: float = 0.0,
    xmax: float = 3.0,
    vmax: float = 0.5,
    sigma_w: float = 0.5,
    r1: float = 1.0,
    model_factors: tuple[float, float, float] = ...,
    half_box: int = 10,
) -> dict[str, Any]: ...
def pf_log_weights(
    frame: NDArray[np.float64],
    xy: NDArray[np.float64],
    *,
    amplitude: float,
    blur: float,
    sigma: float,
    half_box: int = 10,
) -> NDArray[np.float64]: ...
def pf_peaks(
    frame: NDArray[np.float64],
    *,
    count: int = 4,
    min_separation: float = 3.0,
    smoothing: float = 0.0,
) -> NDArray[np.float64]: ...
def pf_render(
    positions: NDArray[np.float64],
    *,
    width: int = 256,
    height: int = 256,
    amplitude: float = 1.0,
    blur: float = 2.0,
    sigma: float = 0.1,
    seed: int = 0,
) -> NDArray[np.float64]: ...
def pf_study(
    ic: NDArray[np.float64],
    *,
    runs: int = 4,
    seed: int = 0,
    truth: str = "white",
    particles: int = 10000,
    association: str = "nearest",
    resampling: str = "systematic",
    peaks: int = 4,
    min_separation: float = 3.0,
    smoothing: float = 0.0,
    sigma_w: float = 0.5,
    model_factors: tuple[float, float, float] = ...,
    snrs: list[float] | None = None,
    ic_snr: float = 2.0,
) -> dict[str, Any]: ...
def associate(
    track: NDArray[np.uint32],
    source: NDArray[np.uint32],
    time: NDArray[np.float64],
    aou: NDArray[np.float64],
    n_tracks: int,
    decision_a: NDArray[np.uint32],
    decision_b: NDArray[np.uint32],
    decision_same: NDArray[np.bool_],
    decision_row: NDArray[np.uint64],
    *,
    geographic: bool,
    options: dict[str, Any],
) -> dict[str, Any]: ...
def association_candidates(
    track: NDArray[np.uint32],
    source: NDArray[np.uint32],
    time: NDArray[np.float64],
    aou: NDArray[np.float64],
    n_tracks: int,
    *,
    geographic: bool,
    brute_force: bool = False,
    max_gap: float = 300.0,
    horizon: float = 0.0,
    process_noise: float = 2.0,
    same_source: bool = False,
    window: float = 300.0,
) -> tuple[NDArray[np.uint32], NDArray[np.uint32]]: ...
def combine_instants(
    g: NDArray[np.float64],
    m: NDArray[np.float64],
    time: NDArray[np.float64],
    offsets: NDArray[np.uint64],
    rule: str,
    *,
    correlation_time: float = 0.0,
) -> NDArray[np.float64]: ...
def assign_one_to_one(
    a: NDArray[np.uint32],
    b: NDArray[np.uint32],
    score: NDArray[np.float64],
    *,
    min_score: float = 0.0,
) -> NDArray[np.uint64]: ...
def association_default_upper() -> float: ...
def association_pair_instants(
    track: NDArray[np.uint32],
    source: NDArray[np.uint32],
    time: NDArray[np.float64],
    aou: NDArray[np.float64],
    n_tracks: int,
    a: int,
    b: int,
    *,
    geographic: bool,
    max_gap: float = 300.0,
    horizon: float = 0.0,
    process_noise: float = 2.0,
) -> dict[str, NDArray[np.float64]]: ...
def association_states_at(
    track: NDArray[np.uint32],
    source: NDArray[np.uint32],
    time: NDArray[np.float64],
    aou: NDArray[np.float64],
    n_tracks: int,
    times: NDArray[np.float64],
    *,
    geographic: bool,
    max_gap: float = 300.0,
    horizon: float = 0.0,
    process_noise: float = 2.0,
) -> dict[str, NDArray[Any]]: ...
def project_aeqd(aou: NDArray[np.float64], origin: tuple[float, float]) -> NDArray[np.float64]: ...
def association_pair_stats(
    track: NDArray[np.uint32],
    source: NDArray[np.uint32],
    time: NDArray[np.float64],
    aou: NDArray[np.float64],
    n_tracks: int,
    a: NDArray[np.uint32],
    b: NDArray[np.uint32],
    *,
    geographic: bool,
    options: dict[str, Any],
    stream_ids: NDArray[np.uint32] | None = None,
) -> dict[str, NDArray[Any]]: ...
def association_track_summary(
    track: NDArray[np.uint32],
    source: NDArray[np.uint32],
    time: NDArray[np.float64],
    aou: NDArray[np.float64],
    n_tracks: int,
    *,
    geographic: bool,
    options: dict[str, Any],
) -> tuple[dict[str, Any], dict[str, Any]]: ...
def association_finish(
    source: NDArray[np.uint32],
    spread: NDArray[np.float64],
    cover_offsets: NDArray[np.uint32],
    cover_start: NDArray[np.float64],
    cover_end: NDArray[np.float64],
    a: NDArray[np.uint32],
    b: NDArray[np.uint32],
    stats: dict[str, NDArray[Any]],
    counts: list[dict[str, Any]],
    decision_a: NDArray[np.uint32],
    decision_b: NDArray[np.uint32],
    decision_same: NDArray[np.bool_],
    decision_row: NDArray[np.uint64],
    *,
    geographic: bool,
    options: dict[str, Any],
    candidates: int,
) -> dict[str, Any]: ...
