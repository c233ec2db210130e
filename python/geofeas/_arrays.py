"""Coercion of user input to the contiguous float64 arrays the Rust core views without copying."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._core import GeofeasError

__all__ = ["as_float_array", "as_ellipses"]


def as_float_array(x: Any, name: str) -> NDArray[np.float64]:
    """``x`` as a C-contiguous float64 array (a view when it already is one).

    Raises ``GeofeasError`` (a ``ValueError``) naming ``name`` when the values cannot be
    represented as real floats (strings, complex numbers, ragged or object data).
    """
    try:
        arr = np.asarray(x)
    except (TypeError, ValueError) as exc:
        raise GeofeasError(f"{name}: cannot be read as an array of numbers ({exc})") from None
    if arr.dtype == np.float64:
        return np.ascontiguousarray(arr)
    if arr.dtype.kind in "biuf":
        return np.ascontiguousarray(arr, dtype=np.float64)
    if arr.dtype.kind == "c":
        raise GeofeasError(f"{name}: complex values cannot be used (dtype {arr.dtype})")
    try:
        return np.ascontiguousarray(arr.astype(np.float64))
    except (TypeError, ValueError) as exc:
        raise GeofeasError(f"{name}: dtype {arr.dtype} cannot be cast to float64 ({exc})") from None


def as_ellipses(x: Any, name: str) -> tuple[NDArray[np.float64], bool]:
    """``x`` as an ``(n, 5)`` float64 array; the flag says a single ``(5,)`` ellipse was given."""
    arr = as_float_array(x, name)
    if arr.ndim == 1 and arr.shape[0] == 5:
        return arr.reshape(1, 5), True
    if arr.ndim == 2 and arr.shape[1] == 5:
        return arr, False
    raise GeofeasError(
        f"{name}: expected one ellipse of shape (5,) or an array of shape (n, 5) with columns "
        f"x0, y0, rx, ry, phi; got shape {arr.shape}"
    )
