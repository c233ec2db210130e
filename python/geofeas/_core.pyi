"""Typed stub of the Rust extension module ``geofeas._core``."""

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "GeofeasError",
    "__version__",
    "from_gaussian",
    "intersection_area",
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
    method: str = "exact",
    vertices: int = 256,
    samples: int = 500,
    seed: int = 0,
    sampler: str = "importance",
) -> NDArray[np.float64]: ...
def score_cdist(
    a: NDArray[np.float64],
    b: NDArray[np.float64],
    score: str,
    *,
    max_bytes: int,
    threshold: bool = False,
    method: str = "exact",
    vertices: int = 256,
    samples: int = 500,
    seed: int = 0,
    sampler: str = "importance",
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
