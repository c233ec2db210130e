"""Typed stub of the Rust extension module ``geofeas._core``."""

from typing import Any

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
    "association_group",
    "association_pair_stats",
    "association_score_pairs",
    "combine_instants",
    "from_gaussian",
    "mht_simulate_run",
    "mht_study",
    "mht_track",
    "mht_trilaterate",
    "polygon_error_bound",
    "score_cdist",
    "score_pairs",
    "to_gaussian",
    "validate_ellipses",
]

__version__: str

class GeofeasError(ValueError):
    """Invalid input or options for a geofeas computation (a ValueError)."""

def score_pairs(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    score: str,
    *,
    threshold: bool = False,
    method: str = "polygon",
    vertices: int = 256,
    samples: int = 500,
    seed: int = 0,
) -> NDArray[np.float64]: ...
def score_cdist(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    score: str,
    *,
    max_bytes: int,
    threshold: bool = False,
    method: str = "polygon",
    vertices: int = 256,
    samples: int = 500,
    seed: int = 0,
) -> NDArray[np.float64]: ...
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
) -> dict[str, Any]: ...
def mht_study(
    *,
    runs: int = 20,
    seed: int = 0,
    max_hypotheses: int = 50,
    ekf_iterations: int = 2,
    new_target_rate: float = 0.02,
    detection_probability: float = 1.0,
) -> dict[str, Any]: ...
def associate(
    track: NDArray[np.uint32],
    source: NDArray[np.uint32],
    time: NDArray[np.float64],
    aou: NDArray[np.float64],
    n_tracks: int,
    *,
    geographic: bool,
    score: str = "glr",
    combine: str = "chi2",
    lower: float = 0.5,
    upper: float | None = None,
    max_gap: float = 300.0,
    horizon: float = 0.0,
    process_noise: float = 2.0,
    same_source: bool = False,
    correlation_time: float = 60.0,
    window: float = 300.0,
    threshold: bool = False,
    method: str = "polygon",
    vertices: int = 256,
    samples: int = 500,
    seed: int = 0,
    inflation: float | None = None,
    margin: float | None = None,
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
def association_score_pairs(
    track: NDArray[np.uint32],
    source: NDArray[np.uint32],
    time: NDArray[np.float64],
    aou: NDArray[np.float64],
    n_tracks: int,
    a: NDArray[np.uint32],
    b: NDArray[np.uint32],
    *,
    geographic: bool,
    score: str = "glr",
    combine: str = "chi2",
    max_gap: float = 300.0,
    horizon: float = 0.0,
    process_noise: float = 2.0,
    correlation_time: float = 60.0,
    threshold: bool = False,
    method: str = "polygon",
    vertices: int = 256,
    samples: int = 500,
    seed: int = 0,
    inflation: float = 1.0,
) -> tuple[NDArray[np.float64], NDArray[np.uint32]]: ...
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
    score: str = "glr",
    combine: str = "chi2",
    max_gap: float = 300.0,
    horizon: float = 0.0,
    process_noise: float = 2.0,
    correlation_time: float = 60.0,
    threshold: bool = False,
    method: str = "polygon",
    vertices: int = 256,
    samples: int = 500,
    seed: int = 0,
    inflation: float | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.uint32], NDArray[np.float64], NDArray[np.float64]]: ...
def association_finish(
    source: NDArray[np.uint32],
    start: NDArray[np.float64],
    end: NDArray[np.float64],
    a: NDArray[np.uint32],
    b: NDArray[np.uint32],
    score: NDArray[np.float64],
    instants: NDArray[np.uint32],
    sum_m: NDArray[np.float64],
    k_eff: NDArray[np.float64],
    *,
    combine: str,
    inflation: float | None,
    lower: float,
    upper: float,
) -> dict[str, Any]: ...
def association_group(
    source: NDArray[np.uint32],
    start: NDArray[np.float64],
    end: NDArray[np.float64],
    a: NDArray[np.uint32],
    b: NDArray[np.uint32],
    score: NDArray[np.float64],
    *,
    lower: float,
    upper: float,
) -> tuple[NDArray[np.uint8], NDArray[np.uint32]]: ...
