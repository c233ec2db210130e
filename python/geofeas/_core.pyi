"""Typed stub of the Rust extension module ``geofeas._core``."""

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "GeofeasError",
    "__version__",
    "from_gaussian",
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
