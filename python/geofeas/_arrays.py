"""Coercion of user input to the contiguous float64 arrays the Rust core views without copying."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._core import GeofeasError

__all__ = ["as_float_array", "as_ellipses"]


def as_float_array(x: Any, name: str) -> NDArray[np.float64]:
    """``x`` as an aligned, C-contiguous float64 array (a view when it already is one).

    Integers and floats of any width and byte order are converted (a copy). Anything else is
    refused with a ``GeofeasError`` (a ``ValueError``) naming ``name``, rather than coerced:
    masked arrays (their mask would be lost), complex numbers (the imaginary part would be
    dropped), booleans, strings, dates and times, ragged or object data holding non-numbers.
    Misaligned or strided buffers are copied.
    """
    if np.ma.isMaskedArray(x):
        raise _error(
            name,
            "a masked array cannot be used (its mask would be ignored); "
            "fill or drop the masked values first",
        )
    try:
        arr = np.asarray(x)
    except (TypeError, ValueError) as exc:
        raise _error(name, f"cannot be read as an array of numbers ({exc})") from None
    kind = arr.dtype.kind
    if kind == "O":
        flat = arr.ravel()
        for i, v in enumerate(flat):
            real = isinstance(v, (int, float, np.integer, np.floating))
            if isinstance(v, (bool, np.bool_)) or not real:
                raise _error(name, f"element {i} is {type(v).__name__} {v!r}, not a real number")
        arr = arr.astype(np.float64)
        kind = "f"
    if kind == "c":
        raise _error(name, f"complex values cannot be used (dtype {arr.dtype})")
    if kind not in "iuf":
        raise _error(name, f"dtype {arr.dtype} is not a real number type (int or float)")
    return np.require(arr, dtype=np.float64, requirements=["C", "A"])


def _error(name: str, message: str) -> GeofeasError:
    err = GeofeasError(f"argument '{name}': {message}")
    err.argument = name
    return err


def as_ellipses(x: Any, name: str) -> tuple[NDArray[np.float64], bool]:
    """``x`` as an ``(n, 5)`` float64 array; the flag says a single ``(5,)`` ellipse was given."""
    arr = as_float_array(x, name)
    if arr.ndim == 1 and arr.shape[0] == 5:
        return arr.reshape(1, 5), True
    if arr.ndim == 2 and arr.shape[1] == 5:
        return arr, False
    raise _error(
        name,
        f"expected one ellipse of shape (5,) or an array of shape (n, 5) with columns "
        f"x0, y0, rx, ry, phi; got shape {arr.shape}",
    )
